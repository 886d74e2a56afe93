"""The Monte Carlo engine: (case, body, intensity level) triples simulated under all motions of a
case, in chunks on a backend, optionally kept in a resumable folder.

The work is a list of (body, level) pairs, each simulated under the motions of an ensemble (all
of them, or those that :meth:`Engine.at_least_half` needs to decide whether half of them
overturn the body), every motion scaled to the level.  A level is a value of an intensity
measure (IM): by default the paper's A_gx, the mean PGA of the ensemble [g] (one factor for all
motions); with a per-motion ``basis`` (the IM of each unscaled motion, e.g. its PGV), each
motion is scaled on its own so that its IM equals the level (incremental dynamic analysis).
The pairs are cut into chunks that a backend (:mod:`rocking.montecarlo.backends`) computes
with the batched kernel (:mod:`rocking.dynamics.batch`); finished chunks can be kept in a folder
(:mod:`rocking.montecarlo.store`) so that an interrupted run resumes where it stopped.  Every
chunk result is keyed by its (case, body, level, motion), never by position or arrival order, so
the results are bit for bit the same for every backend, worker count, chunk size and interruption
history.
"""

from __future__ import annotations

import hashlib
import math
from collections.abc import Mapping, Sequence
from contextlib import ExitStack
from typing import Any

import numpy as np

from ..core import portable
from ..core.checks import record, require_memory
from ..core.progress import resolve as resolve_progress
from ..core.reuse import array_digest, digest, shared
from ..dynamics.batch import (
    BlockTable,
    Outcome,
    block_list,
    concatenate,
    empty_outcome,
    motion_peaks,
    motion_suffixes,
    run_cases,
    take,
)
from ..dynamics.limits import OVERTURN, LimitState
from ..dynamics.physics import Physics, as_physics
from ..errors import InputError
from ..motions.ensemble import Ensemble
from .backends import Backend, Compute, LocalBackend
from .search import motions_to_decide
from .store import ChunkStore

#: Default simulations (pairs × motions) per chunk.
CHUNK_SIMULATIONS = 4096
#: Levels are keyed by integers: the level in units of LEVEL_UNIT (of the IM's unit, g for
#: A_gx; never by a float, whose last bits depend on how it was computed: 0.1 + 0.2 and 0.3 are
#: one level).
LEVEL_UNIT = 1e-9
#: Fraction of the motions simulated at least in each round of :meth:`Engine.at_least_half` after
#: the first (fewer rounds of smaller batched calls, against a few motions more).
DECIDE_STEP = 0.125
#: Bytes kept per (body, A_gx) pair beyond its 9 bytes per motion (dictionary entry, key, arrays).
_PAIR_OVERHEAD = 400
#: What the engines of one run share (:func:`rocking.core.reuse.shared`): the outcomes they
#: simulated ("levels": by :meth:`Engine._book_key` and level key) and their size ("bytes").
_BOOK = "engine outcomes"
#: Largest size of the shared outcomes [bytes], ~12 M simulations: past it no more are added
#: (a fixed figure, not the machine's memory, so that a run simulates the same on every
#: machine).  The paper run keeps 2.8 M outcomes, 62 MB.
_BOOK_BYTES = 256 * 2**20
#: Bytes of a motion's :class:`~rocking.dynamics.batch.Outcome` (every field, one case).
_CASE_BYTES = sum(field.itemsize for field in empty_outcome(1))
#: Bytes of a shared outcome (motion index and its Outcome) and of a (body, level) entry besides.
_OUTCOME_BYTES = 4 + _CASE_BYTES
_ENTRY_BYTES = 500


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
    return ratio if exponent == 1.0 else portable.power(ratio, 1.0 / exponent)


def _chunk_key(c: int, body: np.ndarray, level: np.ndarray, motion: np.ndarray) -> str:
    h = hashlib.sha256(np.int64(c).tobytes() + body.tobytes() + level.tobytes() + motion.tobytes())
    return h.hexdigest()[:24]


def _pack(units: list, size: int) -> list[list]:
    """``units`` (each with its motion indices last) in order, cut into chunks of whole units of
    at most ``size`` motions together (a larger unit alone)."""
    chunks: list[list] = []
    total = size
    for unit in units:
        if total + unit[-1].size > size:
            chunks.append([])
            total = 0
        chunks[-1].append(unit)
        total += unit[-1].size
    return chunks


def _by_triple(body, level, motion, outcome: Outcome):
    """Split the flat results of a chunk into runs of one (body, level key): yields (body, level
    key, motions, their Outcome)."""
    starts = np.flatnonzero(np.diff(body, prepend=-1) | np.diff(level, prepend=-1))
    for lo, hi in zip(starts.tolist(), [*starts[1:].tolist(), body.size]):
        yield int(body[lo]), int(level[lo]), motion[lo:hi], take(outcome, slice(lo, hi))


def _chunk_simulations(a: dict, cases: list[Ensemble]):
    """(case, body, level key, motion, Outcome), flat with one entry per simulation, of a stored
    chunk (one array per field of :class:`~rocking.dynamics.batch.Outcome`, by its name); None
    if the chunk cannot be one of this run.  Chunks without ``motion`` (written before motions
    were simulated in parts) hold every motion of each (body, level); for chunks written before
    the Outcome record or before friction, see :func:`_stored_outcome`."""
    try:
        c = int(a["case"])
        if not 0 <= c < len(cases):
            return None
        n = cases[c].n
        body, level = a["body"], a["level"]
        outcome = _stored_outcome(a)
        if "motion" not in a:  # every motion of each (body, level) pair
            if outcome.overturned.shape != (body.size, n) or level.shape != body.shape:
                return None
            body, level = np.repeat(body, n), np.repeat(level, n)
            motion = np.tile(np.arange(n, dtype=np.int64), a["body"].size)
            outcome = Outcome(*(field.ravel() for field in outcome))
        else:
            motion = a["motion"]
    except KeyError:
        return None
    shapes = {x.shape for x in (body, level, motion, *outcome)}
    if (
        len(shapes) != 1
        or body.ndim != 1
        or (motion.size and not 0 <= motion.min() <= motion.max() < n)
    ):
        return None
    return c, body, level, motion, outcome


#: The quantities of :class:`~rocking.dynamics.batch.Outcome` added with friction (issue 45).
_FRICTION_QUANTITIES = ("peak_slip", "residual_slip", "peak_lift")


def _stored_outcome(a: dict) -> Outcome:
    """The Outcome of a stored chunk (raises KeyError if it has none).

    Chunks written before the Outcome record hold ``overturned`` and ``peak`` (max abs(θ)/α)
    only: uplift is then overturned or a peak above 0 (the kernel's uplift, rocking at some
    sample, but for a block rocking at θ = 0 exactly at every sample it rocks at), steps −1
    (not recorded).  Chunks written before friction (issue 45) lack the slip and lift
    quantities, which are 0 in the frictionless runs they can only belong to (friction is in
    the run's fingerprint)."""
    fields = dict(a)
    if "peak" in a:
        fields["peak_theta_ratio"] = a["peak"]
        fields["uplift"] = a["overturned"] | (a["peak"] > 0.0)
        fields["steps"] = np.full(a["overturned"].shape, -1, np.int64)
    for name in _FRICTION_QUANTITIES:
        fields.setdefault(name, np.zeros(fields["overturned"].shape))
    return Outcome(*(fields[f] for f in Outcome._fields))


class Engine:
    """Results of (case, body, A_gx level) triples under all motions of the case, computed in
    chunks on a backend, optionally kept in a resumable folder.  A context manager: the folder
    is locked and the progress stage open while it is in use.

    Made from the bodies, the ensembles (``cases``), the name of its progress stage (``desc``),
    the :class:`~rocking.Physics` and the :class:`~rocking.montecarlo.backends.Compute` of the
    run (``e``, ``overturn_angle``, ``g``, ``impacts``: shorthands for physics's fields, one
    release; ``mu``, ``mu_k``: friction coefficients [-]; ``backend``, ``out``, ``progress``,
    ``chunk_size``: for compute's), the intensity of each motion that the levels scale
    (``basis``, default A_gx; raised to ``exponent``) and whether the cases hold the same
    motions (``same_motions``)."""

    def __init__(
        self,
        blocks,
        cases: list[Ensemble],
        *,
        desc: str,
        physics: Physics | None = None,
        compute: Compute | None = None,
        basis: list[np.ndarray] | None = None,
        exponent: float = 1.0,
        same_motions: bool = False,
        **shorthands: Any,
    ):
        self.blocks = block_list(blocks)
        compute = record(Compute, compute, shorthands, "compute")
        physics = as_physics(physics, **shorthands)
        backend, chunk_size = compute.backend, compute.chunk_size
        self.table = BlockTable.from_blocks(self.blocks, physics=physics)
        #: The physics resolved for the blocks (numbers per block).
        self.physics = self.table.physics
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
        self.impacts = self.physics.impacts
        if same_motions and len({ens.n for ens in cases}) > 1:
            raise InputError("same_motions needs ensembles with the same number of motions")
        #: The cases hold the same motions (e.g. sampled at other steps): :meth:`decision_order`
        #: reads the outcomes of the other cases at the same level.
        self.same_motions = bool(same_motions)
        self.backend = LocalBackend() if backend is None else backend
        if not isinstance(self.backend, Backend):
            raise InputError(f"backend must come from rocking.montecarlo.backends, got {backend!r}")
        chunk = CHUNK_SIMULATIONS if chunk_size is None else chunk_size
        if not (isinstance(chunk, int) and chunk >= 1):
            raise InputError(f"chunk_size must be an integer >= 1, got {chunk_size!r}")
        self.chunk_size = chunk
        #: (case, body, level key) -> the Outcome of every motion of the case.
        self.results: dict[tuple[int, int, int], Outcome] = {}
        # triples with some motions simulated: (Outcome, simulated) over the motions
        self._partial: dict[tuple[int, int, int], tuple[Outcome, np.ndarray]] = {}
        # level keys with some outcome, per (case, body): what decision_order reads
        self._levels: dict[tuple[int, int], set[int]] = {}
        self.chunks_loaded = 0
        self.chunks_computed = 0
        # inside rocking.core.reuse.reusing (``rocking reproduce``), the outcomes every engine of
        # the run simulated or loaded: a simulation made once is not made again by another
        # engine (the soundness checks ask again for outcomes that Section 8's and their own
        # searches simulated: 2.7 % of the paper run's steps)
        self._book = shared(_BOOK)
        if self._book is not None:
            self._book.setdefault("levels", {})
            self._book.setdefault("bytes", 0)
        self._book_keys: dict[tuple[int, int], tuple] = {}
        self.store = None if compute.out is None else ChunkStore(compute.out, self._params())
        self.reporter = resolve_progress(compute.progress)
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
        """What the chunks depend on (the chunk store's fingerprint): every field of the
        resolved :class:`~rocking.Physics` (:meth:`~rocking.Physics.params`, so that none can
        be left out), the bodies, the motions and their scaling."""
        return {
            **self.physics.params(),
            "bodies": [[b.R, b.gamma, b.r_g] for b in self.blocks],
            "p2": self.table.p2.tolist(),
            "level_unit_g": LEVEL_UNIT,
            "motions": [
                {
                    "dt": ens.dt,
                    "shape": list(ens.acc.shape),
                    "sha256": ens.digests[0],
                    "vertical_sha256": ens.digests[1],
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
            sims = _chunk_simulations(a, self.cases)
            if sims is None:
                continue  # not a chunk of this run: computed again if needed
            c, body, level, motion, outcome = sims
            for b, k, m, o in _by_triple(body, level, motion, outcome):
                self._record(c, b, k, m, o)
                self._enter(c, b, k, m, o)
            self.chunks_loaded += 1

    def _record(self, c: int, b: int, k: int, motion, outcome: Outcome) -> None:
        """Keep the results of motions ``motion`` of (case c, body b, level key k); a triple whose
        every motion is known moves to :attr:`results`."""
        key = (c, b, k)
        if key in self.results:
            return
        if key not in self._partial:
            self._levels.setdefault((c, b), set()).add(k)
            n = self.cases[c].n
            self._partial[key] = (empty_outcome(n), np.zeros(n, np.bool_))
        known, done = self._partial[key]
        for field, values in zip(known, outcome):
            field[motion] = values
        done[motion] = True
        if done.all():
            self.results[key] = known
            del self._partial[key]

    def _book_key(self, c: int, b: int) -> tuple:
        """What determines the outcome of a motion of case ``c`` with body ``b`` at a level (with
        the motion's index and the level key): the motions' contents, their scaling to levels,
        every field of the physics (body b's value of a per-block one) and the body's constants
        as the kernel takes them (every field of :meth:`BlockTable.arrays`, by their bits)."""
        key = self._book_keys.get((c, b))
        if key is None:
            *per_block, _g = self.table.arrays()
            body = np.array([field[b] for field in per_block])
            physics = {
                name: value[b] if isinstance(value, list) else value
                for name, value in self.physics.params().items()
            }
            scaling = digest((self.basis[c], self.exponent, sorted(physics.items())))
            key = (self.cases[c].sha256, scaling, body.tobytes())
            self._book_keys[(c, b)] = key
        return key

    def _look_up(self, c: int, b: int, k: int, missing: np.ndarray) -> np.ndarray:
        """Record the outcomes of the motions ``missing`` of (case c, body b, level key k) that
        the run's book holds; return the others."""
        if self._book is None:
            return missing
        entry = self._book["levels"].get(self._book_key(c, b), {}).get(k)
        if entry is None:
            return missing
        motions, outcome = entry
        at = np.minimum(np.searchsorted(motions, missing), motions.size - 1)
        found = motions[at] == missing
        if found.any():
            self._record(c, b, k, missing[found], take(outcome, at[found]))
        return missing[~found]

    def _enter(self, c: int, b: int, k: int, motion, outcome: Outcome) -> None:
        """Add outcomes of (case c, body b, level key k) to the run's book (if any, and while it
        is below :data:`_BOOK_BYTES`): kept by motion, in order, once each."""
        if self._book is None:
            return
        size = self._book["bytes"]
        if size + _ENTRY_BYTES + _OUTCOME_BYTES * len(motion) > _BOOK_BYTES:
            return
        levels = self._book["levels"].setdefault(self._book_key(c, b), {})
        if k in levels:
            old = levels[k]
            size -= _ENTRY_BYTES + _OUTCOME_BYTES * old[0].size
            motion = np.concatenate([old[0], motion])
            outcome = concatenate([old[1], outcome])
        motion, first = np.unique(motion, return_index=True)
        levels[k] = (motion.astype(np.int32), take(outcome, first))
        self._book["bytes"] = size + _ENTRY_BYTES + _OUTCOME_BYTES * motion.size

    def _data(self):
        if self._handle is None:
            cases = []
            for ens in self.cases:
                acc = np.ascontiguousarray(ens.acc)
                av = None if ens.av is None else np.ascontiguousarray(ens.av)
                cases.append((acc, motion_peaks(acc), ens.dt, av, motion_suffixes(acc, av)))
            data = {"table": self.table, "cases": cases, "impacts": self.impacts}
            self._handle = self.backend.scatter(data)
        return self._handle

    def outcomes(
        self, key: tuple[int, int, int], state: LimitState = OVERTURN
    ) -> tuple[np.ndarray, np.ndarray]:
        """(exceeded, simulated) masks over the motions of ``key`` = (case, body, level key):
        where the limit state ``state`` (default: overturning) is exceeded (False where not
        simulated) and which motions are simulated."""
        outcome, simulated = self._known(key)
        return state.exceeded(outcome) & simulated, simulated

    def _known(self, key: tuple[int, int, int]) -> tuple[Outcome, np.ndarray]:
        """(Outcome, simulated) over the motions of ``key`` (none simulated: zeros)."""
        if key in self.results:
            outcome = self.results[key]
            return outcome, np.ones(outcome.overturned.size, np.bool_)
        part = self._partial.get(key)
        if part is None:
            n = self.cases[key[0]].n
            return empty_outcome(n), np.zeros(n, np.bool_)
        return part

    def decision_order(self, key: tuple[int, int, int], state: LimitState = OVERTURN) -> np.ndarray:
        """The motions of ``key`` = (case, body, level key) in the order :meth:`at_least_half`
        simulates them for the limit state ``state`` (default: overturning): first those most
        likely to decide the comparison with n/2, predicted from the outcomes known at the
        body's other levels.

        A motion that exceeded the state (e.g. overturned the body) at a lower level is taken
        as likely to exceed it here, one that did not at a higher level as likely not to (the
        response is nearly monotone in the scale of one motion, not exactly); otherwise the
        peak rotation max|θ|/α of the nearest lower level where it did not exceed the state
        (over the state's threshold for a state on max|θ|/α) ranks it, and a motion exceeding
        it only at a higher level counts as slightly likely.  If the motions likely to exceed
        it make half or more, the likeliest come first (a decision "at least half" needs
        ⌈n/2⌉ exceedances, and overturning simulations stop early), else the least likely (a
        decision "below" needs ⌊n/2⌋ + 1 others).  Ties keep the ensemble's order, which
        is the whole order where nothing is known.  With :attr:`same_motions`, a motion's
        outcome at this level in another case decides its rank before all of this.  Only which
        motions are simulated depends on it, never an answer: the comparisons are exact.
        """
        c, b, k = key
        n = self.cases[c].n
        # the peak max|θ|/α in units of the state's threshold (overturning: of α)
        unit = state.threshold if state.quantity == "peak_theta_ratio" else 1.0
        over_here = np.zeros(n, np.bool_)  # exceeded at this level in another case
        safe_here = np.zeros(n, np.bool_)
        if self.same_motions:
            for other_case in range(len(self.cases)):
                if other_case != c and k in self._levels.get((other_case, b), ()):
                    ov, sim = self.outcomes((other_case, b, k), state)
                    over_here |= ov
                    safe_here |= sim & ~ov
        over_below = np.zeros(n, np.bool_)  # exceeded at some lower level
        safe_above = np.zeros(n, np.bool_)  # not exceeded at some higher level
        over_above = np.zeros(n, np.bool_)
        peak = np.full(n, np.nan)  # max|θ|/α at the nearest lower level not exceeded
        nearest = np.full(n, -1, np.int64)
        for other in self._levels.get((c, b), ()):  # any order: "nearest" compares levels
            if other == k:
                continue
            known, sim = self._known((c, b, other))
            ov, pk = state.exceeded(known), known.peak_theta_ratio
            if other < k:
                over_below |= sim & ov
                survived = sim & ~ov & (other > nearest)
                peak[survived] = pk[survived] / unit
                nearest[survived] = other
            else:
                safe_above |= sim & ~ov
                over_above |= sim & ov
        # score: 3 likely exceeded, -3 likely not, in [-1, 1) by the peak, else 0.5 or 0
        score = np.zeros(n)
        unclear = over_below == safe_above
        score[over_below & ~safe_above] = 3.0
        score[safe_above & ~over_below] = -3.0
        ranked = unclear & ~np.isnan(peak)
        score[ranked] = 2.0 * np.minimum(peak[ranked], 1.0) - 1.0
        score[unclear & np.isnan(peak) & over_above] = 0.5
        # the same motion at this level in another case (same_motions) outweighs the rest
        score[over_here & ~safe_here] = 4.0
        score[safe_here & ~over_here] = -4.0
        likely = np.clip((score + 1.0) / 2.0, 0.0, 1.0)
        if 2.0 * likely.sum() >= n:
            return np.argsort(-score, kind="stable")
        return np.argsort(score, kind="stable")

    def run(self, keys: list[tuple[int, int, int]]) -> None:
        """Make sure every (case, body, level key) in ``keys`` has a result for every motion."""
        self.run_motions(dict.fromkeys(keys))

    def run_motions(self, requests: Mapping[tuple[int, int, int], np.ndarray | None]) -> None:
        """Make sure every (case, body, level key) of ``requests`` has a result for the motions
        it maps to (indices into the case's ensemble; None: every motion).

        Each triple's motions are one unit of work; chunks hold whole units, at most
        ``chunk_size`` simulations (more only for a single larger unit) and, on a backend of
        several workers, enough of them to keep every worker busy (this process runs one chunk
        at a time on all its threads: fewer, larger kernel calls).  A unit's results do not
        depend on the chunk it is computed in.
        """
        units = []  # (case, body, level key, motion indices still missing)
        for (c, b, k), motions in requests.items():
            if (c, b, k) in self.results:
                continue
            wanted = np.arange(self.cases[c].n) if motions is None else np.asarray(motions)
            missing = self._look_up(c, b, k, wanted[~self.outcomes((c, b, k))[1][wanted]])
            if missing.size:
                units.append((c, b, k, missing.astype(np.int64)))
        if not units:
            return
        total = sum(u[3].size for u in units)
        workers = self.backend.workers
        size = (
            self.chunk_size
            if workers == 1
            else min(self.chunk_size, math.ceil(total / (4 * workers)))
        )
        tasks, levels = [], []
        for c in range(len(self.cases)):
            for chunk in _pack([u for u in units if u[0] == c], size):
                body = np.concatenate([np.full(u[3].size, u[1], np.int64) for u in chunk])
                level = np.concatenate([np.full(u[3].size, u[2], np.int64) for u in chunk])
                motion = np.concatenate([u[3] for u in chunk])
                scale = np.concatenate(
                    [
                        scale_factors(level_agx(u[2]), self.basis[c], self.exponent)[u[3]]
                        for u in chunk
                    ]
                )
                tasks.append((c, body, motion, scale))
                levels.append(level)
        self._stage.expect(total)
        for i, outcome in self.backend.map(run_chunk, self._data(), tasks):
            c, body, motion, _scale = tasks[i]
            if self.store is not None:
                self.store.save(
                    _chunk_key(c, body, levels[i], motion),
                    case=np.int64(c),
                    body=body,
                    level=levels[i],
                    motion=motion,
                    **outcome._asdict(),
                )
            for b, k, m, o in _by_triple(body, levels[i], motion, outcome):
                self._record(c, b, k, m, o)
                self._enter(c, b, k, m, o)
            self.chunks_computed += 1
            self._stage.update(motion.size)

    def at_least_half(
        self, keys: list[tuple[int, int, int]], state: LimitState = OVERTURN
    ) -> dict[tuple[int, int, int], bool]:
        """Whether at least half the motions of the case exceed the limit state ``state``
        (default: overturn the body), for every (case, body, level key) of ``keys`` (2·count ≥
        n, exactly in integers).

        The motions are simulated in the order of :meth:`decision_order` (fixed for the call),
        in rounds, each key asking for the fewest further motions that could decide it
        (:func:`rocking.montecarlo.search.motions_to_decide`; after its first round at least the
        fraction :data:`DECIDE_STEP` of the motions), until every key is decided: the answers
        are those of the full counts, without most motions that cannot change them.  Motions
        already simulated (for any limit state) count without being simulated again.  With
        :attr:`same_motions` the cases are decided one after the other, in their order, so that
        each reads the outcomes of those before it.  Which motions are simulated depends only on
        the outcomes, never on the backend or chunks.
        """
        keys = list(dict.fromkeys(keys))
        if not self.same_motions:
            return self._decide(keys, state)
        answer: dict[tuple[int, int, int], bool] = {}
        for c in sorted({key[0] for key in keys}):
            answer.update(self._decide([key for key in keys if key[0] == c], state))
        return answer

    def _decide(
        self, keys: list[tuple[int, int, int]], state: LimitState
    ) -> dict[tuple[int, int, int], bool]:
        """:meth:`at_least_half` of ``keys`` (distinct), decided together."""
        answer: dict[tuple[int, int, int], bool] = {}
        order: dict[tuple[int, int, int], np.ndarray] = {}
        while True:
            requests = {}
            for key in keys:
                exceeded, simulated = self.outcomes(key, state)
                n = exceeded.size
                count = int(np.count_nonzero(exceeded))
                m = int(np.count_nonzero(simulated))
                need = motions_to_decide(n, count, m - count)
                if need:
                    if m:
                        need = max(need, math.ceil(n * DECIDE_STEP))
                    if key not in order:
                        order[key] = self.decision_order(key, state)
                    first = order[key]
                    requests[key] = first[~simulated[first]][:need]
                else:
                    answer[key] = 2 * count >= n
            if not requests:
                return answer
            self.run_motions(requests)

    def expect(self, simulations: int) -> None:
        """Announce about ``simulations`` simulations to come (the size of the progress stage)."""
        self._stage.expect(simulations)

    def counts(self, key: tuple[int, int, int], states: Sequence[LimitState]) -> list[int]:
        """Motions of ``key`` = (case, body, level key) that exceed each of ``states``."""
        outcome = self.results[key]
        return [int(np.count_nonzero(ls.exceeded(outcome))) for ls in states]

    def require_memory(self, pairs: int, parameter: str) -> None:
        """Refuse, before any work, a run whose results for ``pairs`` (body, A_gx) pairs per
        case would not fit in the available memory."""
        per_pair = max(ens.n for ens in self.cases) * (1 + _CASE_BYTES) + _PAIR_OVERHEAD
        require_memory(
            pairs * len(self.cases) * per_pair,
            f"{parameter}: {pairs:,} (body, A_gx) pairs x "
            f"{max(ens.n for ens in self.cases):,} motions",
        )

    @property
    def stats(self) -> dict:
        return {"chunks_computed": self.chunks_computed, "chunks_loaded": self.chunks_loaded}


def run_chunk(data: dict, task: tuple) -> Outcome:
    """One chunk of a Monte Carlo run: a list of simulations (block, motion, scale).

    Executed by a backend (:mod:`rocking.montecarlo.backends`), possibly in a worker process,
    which is why it lives in this light module.  ``data`` = {"table": BlockTable, "cases":
    [(acc, amax, dt, av, suffixes), …], "impacts": str} (``av``: the vertical accelerations, or
    None; one entry per ensemble, as :func:`run_cases` takes them); ``task`` = (case index, body
    indices, motion indices (int64), scale factors (float64)), one entry per simulation.

    Returns the :class:`~rocking.dynamics.batch.Outcome`, one entry per simulation.
    """
    c, body, motion, scale = task
    acc, amax, dt, av, suffixes = data["cases"][c]
    return run_cases(
        data["table"],
        acc,
        amax,
        dt,
        body,
        motion,
        scale,
        av=av,
        impacts=data["impacts"],
        suffixes=suffixes,
    )
