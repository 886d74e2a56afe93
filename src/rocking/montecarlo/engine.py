"""The Monte Carlo engine: (case, body, intensity level) triples simulated under all motions of a
case, in chunks on a backend, optionally kept in a resumable folder.

The work is a list of (body, level) pairs, each simulated under all motions of an ensemble, every
motion scaled to the level.  A level is a value of an intensity measure (IM): by default the
paper's A_gx, the mean PGA of the ensemble [g] (one factor for all motions); with a per-motion
``basis`` (the IM of each unscaled motion, e.g. its PGV), each motion is scaled on its own so that
its IM equals the level (incremental dynamic analysis).  The pairs are cut into chunks that a
backend (:mod:`rocking.montecarlo.backends`) computes with the batched kernel
(:mod:`rocking.dynamics.batch`); finished chunks can be kept in a folder
(:mod:`rocking.montecarlo.store`) so that an interrupted run resumes where it stopped.  Every
chunk result is keyed by its (case, body, level) triples, never by position or arrival order, so
the results are bit for bit the same for every backend, worker count, chunk size and interruption
history.
"""

from __future__ import annotations

import hashlib
import math
from contextlib import ExitStack
from typing import Any

import numpy as np

from ..core.checks import require_memory
from ..core.progress import resolve as resolve_progress
from ..defaults import IMPACT_SCHEMES
from ..dynamics.batch import BlockTable, block_list, motion_peaks, run_cases
from ..errors import InputError
from ..motions.ensemble import Ensemble
from .backends import Backend, LocalBackend
from .store import ChunkStore, array_digest

#: Default simulations (pairs × motions) per chunk.
CHUNK_SIMULATIONS = 4096
#: Levels are keyed by integers: the level in units of LEVEL_UNIT (of the IM's unit, g for
#: A_gx; never by a float, whose last bits depend on how it was computed: 0.1 + 0.2 and 0.3 are
#: one level).
LEVEL_UNIT = 1e-9
#: Bytes kept per (body, A_gx) pair beyond its 9 bytes per motion (dictionary entry, key, arrays).
_PAIR_OVERHEAD = 400


def level_key(agx: float) -> int:
    """The integer key of the level ``agx`` (A_gx [g], or any IM in its unit): the level in units
    of :data:`LEVEL_UNIT`."""
    return round(agx / LEVEL_UNIT)


def level_agx(key: int) -> float:
    """The level (A_gx [g], or any IM in its unit) of a level key; for a decimal with at most 9
    decimals, exactly that decimal's float (the key divided by 1e9, rounded once)."""
    return key / round(1.0 / LEVEL_UNIT)


def scale_factors(level: float, basis: np.ndarray, exponent: float) -> np.ndarray:
    """Factors that scale motions whose IM is ``basis`` (per motion, > 0) to the IM ``level``
    when the IM grows as factor**``exponent`` (1 for amplitudes such as PGA, PGV, Sa; 2 for
    Arias intensity): (level/basis)**(1/exponent), without a power for exponent 1 (so that
    the A_gx factor is exactly that of :meth:`rocking.Ensemble.scaled`)."""
    ratio = level / basis
    return ratio if exponent == 1.0 else ratio ** (1.0 / exponent)


def _chunk_key(c: int, body: np.ndarray, level: np.ndarray) -> str:
    h = hashlib.sha256(np.int64(c).tobytes() + body.tobytes() + level.tobytes())
    return h.hexdigest()[:24]


class Engine:
    """Results of (case, body, A_gx level) triples under all motions of the case, computed in
    chunks on a backend, optionally kept in a resumable folder.  A context manager: the folder
    is locked and the progress stage open while it is in use."""

    def __init__(
        self,
        blocks,
        cases: list[Ensemble],
        *,
        e,
        overturn_angle,
        g,
        backend,
        out,
        progress,
        chunk_size,
        desc,
        basis: list[np.ndarray] | None = None,
        exponent: float = 1.0,
        impacts: str = IMPACT_SCHEMES[0],
    ):
        self.blocks = block_list(blocks)
        self.table = BlockTable.from_blocks(self.blocks, e=e, overturn_angle=overturn_angle, g=g)
        self.cases = cases
        if basis is None:  # A_gx: one factor for all motions (computed from all samples: once)
            basis = [np.full(ens.n, ens.agx) for ens in cases]
        if len(basis) != len(cases) or any(np.shape(b) != (ens.n,) for b, ens in zip(basis, cases)):
            raise InputError("basis must give one intensity per motion of every case")
        if not all(np.all(np.isfinite(b) & (b > 0.0)) for b in basis):
            raise InputError(
                "every motion needs an intensity > 0 to be scaled to a level "
                "(a motion of zero intensity cannot be scaled)"
            )
        self.basis = [np.asarray(b, dtype=float) for b in basis]
        self.exponent = float(exponent)
        if impacts not in IMPACT_SCHEMES:
            raise InputError(f"impacts must be one of {', '.join(IMPACT_SCHEMES)}, got {impacts!r}")
        self.impacts = impacts
        self.backend = LocalBackend() if backend is None else backend
        if not isinstance(self.backend, Backend):
            raise InputError(f"backend must come from rocking.montecarlo.backends, got {backend!r}")
        chunk = CHUNK_SIMULATIONS if chunk_size is None else chunk_size
        if not (isinstance(chunk, int) and chunk >= 1):
            raise InputError(f"chunk_size must be an integer >= 1, got {chunk_size!r}")
        self.chunk_size = chunk
        self.results: dict[tuple[int, int, int], tuple[np.ndarray, np.ndarray]] = {}
        self.chunks_loaded = 0
        self.chunks_computed = 0
        self.store = None if out is None else ChunkStore(out, self._params())
        self.reporter = resolve_progress(progress)
        self.desc = desc
        self._handle: Any = None  # the scattered data, on first use
        self._stage: Any = None  # the progress stage, while open
        self._exit: Any = None  # the ExitStack that __exit__ closes

    def __enter__(self) -> Engine:
        with ExitStack() as stack:
            if self.store is not None:
                stack.enter_context(self.store)
                self._load()
            self._stage = stack.enter_context(self.reporter.stage(self.desc, total=None))
            self._exit = stack.pop_all()
        return self

    def __exit__(self, *exc) -> None:
        self._exit.__exit__(*exc)

    def _params(self) -> dict:
        t = self.table
        return {
            "bodies": [[b.R, b.gamma, b.r_g] for b in self.blocks],
            "p2": t.p2.tolist(),
            "e": t.e.tolist(),
            "overturn_angle": t.theta_ov.tolist(),
            "g": t.g,
            "level_unit_g": LEVEL_UNIT,
            "impacts": self.impacts,
            "motions": [
                {
                    "dt": ens.dt,
                    "shape": list(ens.acc.shape),
                    "sha256": array_digest(ens.acc),
                    "vertical_sha256": None if ens.av is None else array_digest(ens.av),
                }
                for ens in self.cases
            ],
            "scaling": {
                "exponent": self.exponent,
                "basis_sha256": [array_digest(b) for b in self.basis],
            },
        }

    def _load(self) -> None:
        if self.store is None:
            return
        for _key, a in self.store.load_all():
            try:
                c = int(a["case"])
                ok = (
                    0 <= c < len(self.cases)
                    and a["overturned"].shape == (a["body"].size, self.cases[c].n)
                    and a["level"].shape == a["body"].shape
                )
            except KeyError:
                ok = False
            if not ok:
                continue  # not a chunk of this run: computed again if needed
            for j, (b, k) in enumerate(zip(a["body"].tolist(), a["level"].tolist())):
                self.results[(c, b, k)] = (a["overturned"][j], a["peak"][j])
            self.chunks_loaded += 1

    def _data(self):
        if self._handle is None:
            cases = [
                (
                    np.ascontiguousarray(ens.acc),
                    motion_peaks(ens.acc),
                    ens.dt,
                    None if ens.av is None else np.ascontiguousarray(ens.av),
                )
                for ens in self.cases
            ]
            data = {"table": self.table, "cases": cases, "impacts": self.impacts}
            self._handle = self.backend.scatter(data)
        return self._handle

    def run(self, keys: list[tuple[int, int, int]]) -> None:
        """Make sure every (case, body, level key) in ``keys`` has a result."""
        missing = list(dict.fromkeys(k for k in keys if k not in self.results))
        if not missing:
            return
        # chunks of at most chunk_size simulations, and enough of them to keep every worker busy
        total = sum(self.cases[c].n for c, _, _ in missing)
        size = min(self.chunk_size, math.ceil(total / (4 * self.backend.workers)))
        tasks, levels = [], []
        for c in range(len(self.cases)):
            mine = [(b, k) for cc, b, k in missing if cc == c]
            per = max(1, size // self.cases[c].n)
            for i in range(0, len(mine), per):
                body = np.array([b for b, _ in mine[i : i + per]], dtype=np.int64)
                level = np.array([k for _, k in mine[i : i + per]], dtype=np.int64)
                scale = np.array(
                    [
                        scale_factors(level_agx(k), self.basis[c], self.exponent)
                        for k in level.tolist()
                    ]
                )
                tasks.append((c, body, scale))
                levels.append(level)
        self._stage.expect(sum(t[1].size * self.cases[t[0]].n for t in tasks))
        for i, (overturned, peak) in self.backend.map(run_chunk, self._data(), tasks):
            c, body, _scale = tasks[i]
            if self.store is not None:
                self.store.save(
                    _chunk_key(c, body, levels[i]),
                    case=np.int64(c),
                    body=body,
                    level=levels[i],
                    overturned=overturned,
                    peak=peak,
                )
            for j, (b, k) in enumerate(zip(body.tolist(), levels[i].tolist())):
                self.results[(c, b, k)] = (overturned[j], peak[j])
            self.chunks_computed += 1
            self._stage.update(body.size * self.cases[c].n)

    def expect(self, simulations: int) -> None:
        """Announce about ``simulations`` simulations to come (the size of the progress stage)."""
        self._stage.expect(simulations)

    def count(self, c: int, b: int, k: int) -> int:
        """Motions of case ``c`` that overturn body ``b`` at level key ``k``."""
        return int(np.count_nonzero(self.results[(c, b, k)][0]))

    def require_memory(self, pairs: int, parameter: str) -> None:
        """Refuse, before any work, a run whose results for ``pairs`` (body, A_gx) pairs per
        case would not fit in the available memory."""
        per_pair = max(ens.n for ens in self.cases) * 9 + _PAIR_OVERHEAD
        require_memory(
            pairs * len(self.cases) * per_pair,
            f"{parameter}: {pairs:,} (body, A_gx) pairs x "
            f"{max(ens.n for ens in self.cases):,} motions",
        )

    @property
    def stats(self) -> dict:
        return {"chunks_computed": self.chunks_computed, "chunks_loaded": self.chunks_loaded}


def run_chunk(data: dict, task: tuple):
    """One chunk of a Monte Carlo run: all motions of one ensemble for each (block, scale) pair.

    Executed by a backend (:mod:`rocking.montecarlo.backends`), possibly in a worker process, which
    is why it
    lives in this light module.  ``data`` = {"table": BlockTable, "cases": [(acc, amax, dt, av),
    …]} (``av``: the vertical accelerations, or None)
    (one entry per ensemble, as :func:`run_cases` takes them); ``task`` = (case index, body
    indices (n_pairs,) int64, scale factors of every motion (n_pairs, n_motions) float64).

    Returns (overturned, peak), shape (n_pairs, n_motions).
    """
    c, body, scale = task
    acc, amax, dt, av = data["cases"][c]
    n_m = acc.shape[0]
    overturned, peak = run_cases(
        data["table"],
        acc,
        amax,
        dt,
        np.repeat(body, n_m),
        np.tile(np.arange(n_m, dtype=np.int64), body.size),
        scale.ravel(),
        av=av,
        impacts=data["impacts"],
    )
    return overturned.reshape(body.size, n_m), peak.reshape(body.size, n_m)
