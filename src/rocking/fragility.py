"""Overturning probability, the A_gx of 50 % probability and lognormal fragility (paper §§6–8).

For a body and an ensemble of motions scaled so that its mean PGA is A_gx (``ensemble.scaled``),
the probability of overturning is the fraction of the motions that overturn it (paper Figs. 9–11,
13).  :func:`overturning_probability` computes it on a grid of A_gx with a Wilson score interval,
:func:`agx_50` searches the A_gx of 50 % probability adaptively (paper Section 8, Figs. 15–16) and
:func:`fit_lognormal` fits a lognormal fragility curve by maximum likelihood.

The work is a list of (body, A_gx) pairs, each simulated under all motions of an ensemble.  The
pairs are cut into chunks that a backend (:mod:`rocking.backends`) computes with the batched kernel
(:mod:`rocking.batch`); finished chunks can be kept in a folder (:mod:`rocking.store`) so that an
interrupted run resumes where it stopped.  Every chunk result is keyed by its (case, body, scale
factor) triples, never by position or arrival order, so the results are bit for bit the same for
every backend, worker count, chunk size and interruption history.
"""

from __future__ import annotations

import hashlib
import math
from contextlib import ExitStack
from dataclasses import dataclass

import numpy as np
import scipy.optimize
import xarray as xr
from ._validate import finite_array, in_range, positive, require_memory
from .backends import LocalBackend
from .batch import BlockTable, block_list, motion_peaks, run_chunk
from .body import G
from .errors import InputError
from .motions import Ensemble
from .progress import resolve as resolve_progress
from .store import ChunkStore, array_digest

#: Default simulations (pairs × motions) per chunk.
CHUNK_SIMULATIONS = 4096


# --------------------------------------------------------------------------- statistics


def wilson_interval(count, n, confidence: float = 0.95):
    """Wilson score interval of a binomial proportion count/n (no continuity correction).

    Parameters
    ----------
    count, n : array_like of int
        Successes (here: motions that overturn the body) and trials, 0 ≤ count ≤ n, n ≥ 1.
    confidence : float
        Confidence level in (0, 1) [-].

    Returns
    -------
    low, high : ndarray
        Interval bounds [-], shaped like ``count``.
    """
    confidence = in_range("confidence", confidence, 0.0, 1.0, lo_open=True, hi_open=True)
    count, n = np.broadcast_arrays(np.asarray(count), np.asarray(n))
    if count.dtype.kind not in "iu" or n.dtype.kind not in "iu":
        raise InputError("count and n must be integers")
    if np.any(n < 1) or np.any(count < 0) or np.any(count > n):
        raise InputError("count and n must satisfy 0 <= count <= n and n >= 1")
    pairs, inverse = np.unique(np.stack([count.ravel(), n.ravel()], axis=1), axis=0,
                               return_inverse=True)
    bounds = np.array([_wilson(int(k), int(m), confidence) for k, m in pairs]).reshape(-1, 2)
    low = bounds[inverse.ravel(), 0].reshape(count.shape)
    high = bounds[inverse.ravel(), 1].reshape(count.shape)
    return low, high


def _wilson(k: int, n: int, confidence: float) -> tuple[float, float]:
    import scipy.stats  # on first use: ~0.5 s of import that most commands do not need

    ci = scipy.stats.binomtest(k, n).proportion_ci(confidence, method="wilson")
    return ci.low, ci.high


@dataclass(frozen=True)
class LognormalFit:
    """Lognormal fragility curve P(A_gx) = Φ(ln(A_gx/median)/beta).

    Attributes
    ----------
    median : float
        A_gx of 50 % probability [g].
    beta : float
        Logarithmic standard deviation (dispersion) [-].
    """

    median: float
    beta: float

    def probability(self, agx) -> np.ndarray:
        """Probability of overturning at ``agx`` [g] (array_like, > 0) [-]."""
        import scipy.stats  # on first use (see _wilson)

        return scipy.stats.norm.cdf(np.log(np.asarray(agx, dtype=float) / self.median) / self.beta)


def fit_lognormal(agx, count, n) -> LognormalFit:
    """Maximum-likelihood lognormal fragility curve from overturning counts.

    Maximises the binomial log-likelihood Σ [k·ln P(A) + (n − k)·ln(1 − P(A))] with
    P(A) = Φ(ln(A/median)/β) over (ln median, ln β) with scipy.optimize (Nelder–Mead from a
    probit-regression start), β kept in [1e-3, 10].

    Parameters
    ----------
    agx : array_like
        Intensities A_gx [g], > 0.
    count : array_like of int
        Motions that overturned the body at each A_gx.
    n : int or array_like of int
        Motions at each A_gx (≥ 1, ≥ count).

    Returns
    -------
    LognormalFit

    Raises
    ------
    InputError
        On bad shapes or values, or if every count is 0 or every count is n (no information on
        the median).
    """
    agx = finite_array("agx", agx, ndim=(1,))
    if np.any(agx <= 0.0):
        raise InputError("agx must be > 0 [g]")
    count = np.asarray(count)
    n = np.broadcast_to(np.asarray(n), count.shape)
    if count.shape != agx.shape:
        raise InputError(f"count must have one value per agx ({agx.size}), got shape {count.shape}")
    wilson_interval(count, n)  # validates 0 <= count <= n, n >= 1 (integers)
    if np.all(count == 0) or np.all(count == n):
        raise InputError("fit_lognormal needs counts that are not all 0 and not all n")
    import scipy.stats  # on first use (see _wilson)

    x = np.log(agx)
    k = count.astype(float)
    m = n.astype(float)

    def nll(q):
        z = (x - q[0]) / math.exp(q[1])
        return -np.sum(k * scipy.stats.norm.logcdf(z) + (m - k) * scipy.stats.norm.logsf(z))

    # start: probit regression line through the empirical proportions (clipped away from 0, 1)
    p = np.clip((k + 0.5) / (m + 1.0), 1e-3, 1 - 1e-3)
    slope, icpt = np.polyfit(x, scipy.stats.norm.ppf(p), 1, w=np.sqrt(m))
    beta0 = 1.0 / slope if slope > 0.1 else 1.0
    mu0 = -icpt / slope if slope > 0.1 else float(np.average(x, weights=m))
    q0 = [mu0, math.log(min(max(beta0, 1e-3), 10.0))]
    res = scipy.optimize.minimize(nll, q0, method="Nelder-Mead",
                                  bounds=[(None, None), (math.log(1e-3), math.log(10.0))],
                                  options={"xatol": 1e-10, "fatol": 1e-12, "maxiter": 10_000})
    return LognormalFit(median=float(math.exp(res.x[0])), beta=float(math.exp(res.x[1])))


# --------------------------------------------------------------------------- engine

#: A_gx levels are keyed by integers: A_gx in units of LEVEL_UNIT [g] (never by a float, whose
#: last bits depend on how it was computed: 0.1 + 0.2 and 0.3 are one level).
LEVEL_UNIT = 1e-9
#: Bytes kept per (body, A_gx) pair beyond its 9 bytes per motion (dictionary entry, key, arrays).
_PAIR_OVERHEAD = 400


def level_key(agx: float) -> int:
    """The integer key of the A_gx level ``agx`` [g] (A_gx in units of :data:`LEVEL_UNIT`)."""
    return round(agx / LEVEL_UNIT)


def level_agx(key: int) -> float:
    """A_gx [g] of a level key; for a decimal A_gx with at most 9 decimals, exactly that decimal's
    float (the key divided by 1e9, rounded once)."""
    return key / round(1.0 / LEVEL_UNIT)


def _chunk_key(c: int, body: np.ndarray, level: np.ndarray) -> str:
    h = hashlib.sha256(np.int64(c).tobytes() + body.tobytes() + level.tobytes())
    return h.hexdigest()[:24]


class _Engine:
    """Results of (case, body, A_gx level) triples under all motions of the case, computed in
    chunks on a backend, optionally kept in a resumable folder.  A context manager: the folder
    is locked and the progress stage open while it is in use."""

    def __init__(self, blocks, cases: list[Ensemble], *, e, overturn_angle, g, backend, out,
                 progress, chunk_size, desc):
        self.blocks = block_list(blocks)
        self.table = BlockTable.from_blocks(self.blocks, e=e, overturn_angle=overturn_angle,
                                            g=g)
        self.cases = cases
        self.agx0 = [ens.agx for ens in cases]  # (computed from all samples: once)
        self.backend = LocalBackend() if backend is None else backend
        if not all(hasattr(self.backend, a) for a in ("map", "scatter", "workers")):
            raise InputError(f"backend must come from rocking.backends, got {backend!r}")
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
        self._handle = None
        self._stage = None
        self._exit = None

    def __enter__(self) -> "_Engine":
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
            "bodies": [[b.R, b.gamma] for b in self.blocks],
            "e": t.e.tolist(), "overturn_angle": t.theta_ov.tolist(), "g": t.g,
            "level_unit_g": LEVEL_UNIT,
            "motions": [{"dt": ens.dt, "shape": list(ens.acc.shape),
                         "sha256": array_digest(ens.acc)} for ens in self.cases],
        }

    def _load(self) -> None:
        for _key, a in self.store.load_all():
            try:
                c = int(a["case"])
                ok = 0 <= c < len(self.cases) and a["overturned"].shape == (
                    a["body"].size, self.cases[c].n) and a["level"].shape == a["body"].shape
            except KeyError:
                ok = False
            if not ok:
                continue  # not a chunk of this run: computed again if needed
            for j, (b, k) in enumerate(zip(a["body"].tolist(), a["level"].tolist())):
                self.results[(c, b, k)] = (a["overturned"][j], a["peak"][j])
            self.chunks_loaded += 1

    def _data(self):
        if self._handle is None:
            cases = [(np.ascontiguousarray(ens.acc), motion_peaks(ens.acc), ens.dt)
                     for ens in self.cases]
            self._handle = self.backend.scatter({"table": self.table, "cases": cases})
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
                body = np.array([b for b, _ in mine[i:i + per]], dtype=np.int64)
                level = np.array([k for _, k in mine[i:i + per]], dtype=np.int64)
                # the factor of Ensemble.scaled: A_gx / A_gx of the ensemble
                scale = np.array([level_agx(k) / self.agx0[c] for k in level.tolist()])
                tasks.append((c, body, scale))
                levels.append(level)
        self._stage.expect(sum(t[1].size * self.cases[t[0]].n for t in tasks))
        for i, (overturned, peak) in self.backend.map(run_chunk, self._data(), tasks):
            c, body, _scale = tasks[i]
            if self.store is not None:
                self.store.save(_chunk_key(c, body, levels[i]), case=np.int64(c), body=body,
                                level=levels[i], overturned=overturned, peak=peak)
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
        require_memory(pairs * len(self.cases) * per_pair,
                       f"{parameter}: {pairs:,} (body, A_gx) pairs x "
                       f"{max(ens.n for ens in self.cases):,} motions")

    @property
    def stats(self) -> dict:
        return {"chunks_computed": self.chunks_computed, "chunks_loaded": self.chunks_loaded}


# --------------------------------------------------------------------------- public functions


def _cases(ensemble) -> tuple[list[str] | None, list[Ensemble]]:
    """(case labels or None, ensembles) from an Ensemble or a dict label -> Ensemble."""
    if isinstance(ensemble, Ensemble):
        items = [(None, ensemble)]
    elif isinstance(ensemble, dict) and ensemble:
        items = [(str(k), v) for k, v in ensemble.items()]
    else:
        raise InputError("ensemble must be a rocking Ensemble or a non-empty dict label -> "
                         f"Ensemble, got {type(ensemble).__name__}")
    for label, ens in items:
        where = "ensemble" if label is None else f"ensemble[{label!r}]"
        if not isinstance(ens, Ensemble):
            raise InputError(f"{where} must be a rocking Ensemble, got {type(ens).__name__}")
        if ens.agx == 0.0:
            raise InputError(f"{where} has only zero motions: it cannot be scaled to an agx")
    labels = None if items[0][0] is None else [label for label, _ in items]
    return labels, [ens for _, ens in items]


def _dataset(blocks, table: BlockTable, labels, data_vars: dict, coords: dict,
             attrs: dict) -> xr.Dataset:
    """Labelled result; ``data_vars`` values have a leading case axis, dropped for one ensemble."""
    lead = () if labels is None else ("case",)
    dvars = {}
    for name, (dims, values, vattrs) in data_vars.items():
        values = values[0] if labels is None else values
        dvars[name] = (lead + dims, values, vattrs)
    all_coords = {
        "body": ("body", [b.label for b in blocks]),
        "R": ("body", [b.R for b in blocks], {"units": "m", "long_name": "size parameter R"}),
        "gamma": ("body", [b.gamma for b in blocks], {"units": "1", "long_name": "H/B"}),
        "e": ("body", table.e, {"units": "1", "long_name": "coefficient of restitution"}),
        "overturn_angle": ("body", table.theta_ov, {"units": "rad"}),
        **coords,
    }
    if labels is not None:
        all_coords["case"] = ("case", labels)
    return xr.Dataset(dvars, coords=all_coords, attrs={"g": table.g, **attrs})


def overturning_probability(blocks, ensemble, agx, *, e=0.925, overturn_angle=math.pi / 2,
                            g: float = G, backend=None, out=None, progress=None,
                            confidence: float = 0.95, chunk_size: int | None = None,
                            members: bool = False) -> xr.Dataset:
    """Probability that each body overturns, as a function of the ensemble intensity A_gx.

    At each A_gx the ensemble is scaled so that its mean PGA equals A_gx
    (``ensemble.scaled(agx)``) and every body is simulated under every motion.

    Parameters
    ----------
    blocks : sequence of Block
        The bodies.
    ensemble : Ensemble or dict of str -> Ensemble
        The motions [m/s²] (ground or floor); a dict gives a leading ``case`` dimension
        (e.g. floors, durations, intensity functions).
    agx : array_like
        Intensities A_gx [g], > 0.
    e : float, "housner" or sequence
        Coefficient of restitution [-], one for all bodies or one per body.
    overturn_angle : float, "alpha" or sequence
        |θ| [rad] that counts as overturning (π/2 in the paper).
    g : float
        Gravity [m/s²].
    backend : LocalBackend or DaskBackend, optional
        Where to compute (default: this process, all cores).
    out : str or Path, optional
        Folder for finished chunks (:class:`rocking.store.ChunkStore`).  A later call with the
        same bodies, motions, e, overturning angle and g computes only what the folder lacks
        (after a kill, or for new A_gx levels); a folder of another run is refused.
    progress : bool, optional
        Show a progress bar (default: only if stderr is a terminal).
    confidence : float
        Level of the Wilson interval, in (0, 1) [-].
    chunk_size : int, optional
        Largest number of simulations per chunk (default :data:`CHUNK_SIMULATIONS`; chunks are
        smaller when needed to give each worker of the backend about four); chunks hold whole
        (body, A_gx) pairs.  Does not change the results.
    members : bool
        Also return ``overturned`` and ``peak`` of every motion (dimension ``member``; for a
        dict, all ensembles must have the same number of motions).

    Returns
    -------
    xarray.Dataset
        Dimensions ([case,] body, agx[, member]); ``probability`` [-], ``count`` (motions that
        overturned the body), ``n`` (motions), ``ci_low``/``ci_high`` (Wilson) [-], and with
        ``members``: ``overturned`` (bool) and ``peak`` = max|θ|/α [-].  Coordinates ``body``
        (labels), ``R`` [m], ``gamma`` [-], ``e`` [-], ``overturn_angle`` [rad] on body,
        ``agx`` [g].  Attributes: ``g`` [m/s²], ``confidence``, and how many chunks were
        computed / loaded from ``out`` (``chunks_computed``, ``chunks_loaded``).
    """
    labels, cases = _cases(ensemble)
    agx = finite_array("agx", np.atleast_1d(agx), ndim=(1,))
    if np.any(agx < LEVEL_UNIT):
        raise InputError(f"agx must be >= {LEVEL_UNIT:g} g, got {agx[agx < LEVEL_UNIT][0]}")
    confidence = in_range("confidence", confidence, 0.0, 1.0, lo_open=True, hi_open=True)
    if members and len({ens.n for ens in cases}) > 1:
        raise InputError("members=True needs ensembles with the same number of motions")
    nb = len(block_list(blocks))
    engine = _Engine(blocks, cases, e=e, overturn_angle=overturn_angle, g=g, backend=backend,
                     out=out, progress=progress, chunk_size=chunk_size, desc="P(overturn)")
    engine.require_memory(nb * agx.size * (2 if members else 1), "agx")
    levels = [level_key(a) for a in agx.tolist()]
    agx = np.array([level_agx(k) for k in levels])
    keys = [[[(c, b, k) for k in levels] for b in range(nb)] for c in range(len(cases))]
    with engine:
        engine.run([k for per_case in keys for per_body in per_case for k in per_body])
    count = np.array([[[engine.count(*k) for k in per_body] for per_body in per_case]
                      for per_case in keys], dtype=np.int64)
    n = np.broadcast_to(np.array([ens.n for ens in cases])[:, None, None], count.shape).copy()
    low, high = wilson_interval(count, n, confidence)
    dims = ("body", "agx")
    data_vars = {
        "probability": (dims, count / n, {"units": "1", "long_name": "overturning probability"}),
        "count": (dims, count, {"long_name": "motions that overturn the body"}),
        "n": (dims, n, {"long_name": "motions"}),
        "ci_low": (dims, low, {"units": "1", "long_name": f"Wilson {confidence:g} lower bound"}),
        "ci_high": (dims, high, {"units": "1", "long_name": f"Wilson {confidence:g} upper bound"}),
    }
    coords = {"agx": ("agx", agx, {"units": "g", "long_name": "mean PGA of the ensemble"})}
    if members:
        flags, peaks = (np.array([[[engine.results[k][i] for k in pb] for pb in pc] for pc in keys])
                        for i in (0, 1))
        data_vars["overturned"] = (dims + ("member",), flags, {})
        data_vars["peak"] = (dims + ("member",), peaks,
                             {"units": "1", "long_name": "max |theta| / alpha"})
        coords["member"] = ("member", list(cases[0].labels) if labels is None
                            else np.arange(cases[0].n))
    return _dataset(blocks, engine.table, labels, data_vars, coords,
                    {"confidence": confidence, **engine.stats})


def agx_50(blocks, ensemble, *, resolution: float = 0.01, agx_max: float = 5.0, e=0.925,
           overturn_angle=math.pi / 2, g: float = G, backend=None, out=None, progress=None,
           coarse: int = 10, chunk_size: int | None = None) -> xr.Dataset:
    """A_gx at which each body overturns with 50 % probability, by an adaptive grid search.

    The search runs on the grid A_k = k·resolution (k = 1 … K, K = ⌊agx_max/resolution⌋, values
    rounded to 12 decimals) with P(A_0 = 0) = 0.  With the counts of a finite ensemble, P(A) need
    not be monotone, so the result is defined by the search itself:

    1. bracket: P is computed at ``coarse`` evenly spread levels (the last is K) in increasing
       order until P ≥ 0.5; the bracket is (previous coarse level or 0, that level).  If
       P < 0.5 at all of them, the result is NaN (not reached by ``agx_max``, or only between
       coarse levels);
    2. bisection on the integer levels inside the bracket, keeping P(lo) < 0.5 ≤ P(hi), until
       hi = lo + 1.

    The result A_hi is thus an upward crossing of 50 % on the grid: P(A_hi) ≥ 0.5 and
    P(A_hi − resolution) < 0.5 (``probability`` and ``probability_below``).  Where P is monotone
    on the grid it is the smallest grid A_gx with P ≥ 0.5.  P ≥ 0.5 means count ≥ n/2.  Each
    round evaluates one level for every body (and case) still searching, in one batched call.

    Parameters
    ----------
    blocks : sequence of Block
        The bodies.
    ensemble : Ensemble or dict of str -> Ensemble
        The motions [m/s²]; a dict gives a leading ``case`` dimension.
    resolution : float
        Grid step of A_gx [g] (the paper reads A_gx to 0.01 g).
    agx_max : float
        Largest A_gx searched [g], ≥ resolution.
    e, overturn_angle, g, backend, out, progress, chunk_size :
        As for :func:`overturning_probability`.
    coarse : int
        Levels of the bracketing round (≥ 1).

    Returns
    -------
    xarray.Dataset
        Dimension ([case,] body): ``agx50`` [g] (NaN if not reached), ``probability`` at agx50
        and ``probability_below`` at agx50 − resolution [-]; coordinates as for
        :func:`overturning_probability`; attributes ``resolution``, ``agx_max`` [g].
    """
    labels, cases = _cases(ensemble)
    resolution = in_range("resolution", resolution, 1e-6, math.inf, unit="g")
    agx_max = positive("agx_max", agx_max, "g")
    K = int(math.floor(agx_max / resolution * (1.0 + 1e-12)))
    if K < 1:
        raise InputError(f"agx_max ({agx_max:g} g) must be at least resolution ({resolution:g} g)")
    if not (isinstance(coarse, int) and coarse >= 1):
        raise InputError(f"coarse must be an integer >= 1, got {coarse!r}")
    nb = len(block_list(blocks))
    engine = _Engine(blocks, cases, e=e, overturn_angle=overturn_angle, g=g, backend=backend,
                     out=out, progress=progress, chunk_size=chunk_size, desc="A_gx(50%)")

    def key(c, b, k):  # the level key of grid level k (A_gx = k·resolution)
        return (c, b, level_key(round(k * resolution, 12)))

    def above(c, b, k):  # P(A_k) >= 0.5, exactly in integers
        return 2 * engine.count(*key(c, b, k)) >= cases[c].n

    bodies = [(c, b) for c in range(len(cases)) for b in range(nb)]
    grid = sorted({math.ceil(K * i / coarse) for i in range(1, coarse + 1)})
    scan = {cb: 0 for cb in bodies}  # bracketing: index in grid of the next coarse level
    lo, hi = {}, {}  # bisection: P(lo) < 0.5 <= P(hi)
    step = max(b - a for a, b in zip([0] + grid, grid))
    rounds = len(grid) // 2 + math.ceil(math.log2(step))  # a guess, for the progress display
    engine.require_memory(nb * (len(grid) + math.ceil(math.log2(step)) + 1), "resolution")
    with engine:
        engine.expect(rounds * nb * sum(ens.n for ens in cases))
        while True:
            level = {cb: grid[i] for cb, i in scan.items()}
            level.update({cb: (lo[cb] + hi[cb]) // 2 for cb in hi if hi[cb] - lo[cb] > 1})
            if not level:
                break
            engine.run([key(c, b, k) for (c, b), k in level.items()])  # one batch per round
            for cb, k in level.items():
                if cb in scan:
                    if above(*cb, k):
                        i = scan.pop(cb)
                        lo[cb], hi[cb] = (grid[i - 1] if i else 0), k
                    elif scan[cb] + 1 < len(grid):
                        scan[cb] += 1
                    else:
                        del scan[cb]  # P < 0.5 at every coarse level: NaN
                elif above(*cb, k):
                    hi[cb] = k
                else:
                    lo[cb] = k
    shape = (len(cases), nb)
    agx50 = np.full(shape, np.nan)
    p_at = np.full(shape, np.nan)
    p_below = np.full(shape, np.nan)
    for (c, b), k in hi.items():
        agx50[c, b] = level_agx(key(c, b, k)[2])
        p_at[c, b] = engine.count(*key(c, b, k)) / cases[c].n
        p_below[c, b] = engine.count(*key(c, b, k - 1)) / cases[c].n if k > 1 else 0.0
    dims = ("body",)
    data_vars = {
        "agx50": (dims, agx50, {"units": "g", "long_name": "A_gx of 50 % overturning probability"}),
        "probability": (dims, p_at, {"units": "1", "long_name": "probability at agx50"}),
        "probability_below": (dims, p_below,
                              {"units": "1", "long_name": "probability at agx50 - resolution"}),
    }
    return _dataset(blocks, engine.table, labels, data_vars, {},
                    {"resolution": resolution, "agx_max": agx_max, **engine.stats})
