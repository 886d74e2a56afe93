"""Many rocking simulations at once: overturned flags and peak rotations (issue 5, part 1).

One compiled, parallel kernel integrates independent cases (block, motion, scale factor) with the
physics of :func:`rocking.dynamics.simulate` — it calls the same one-interval step
:func:`rocking.dynamics._advance` — and keeps only what a Monte Carlo study needs: whether the
block overturned and its largest |θ|/α.  Two kinds of work are skipped because they cannot change
the answer:

* a case whose scaled motion never exceeds the uplift acceleration, |scale·a_g| ≤ g·tan α at every
  sample (the ground acceleration is linear between samples, so the samples bound it), leaves the
  block at rest: not overturned, peak 0;
* a case stops as soon as the block overturns.

Every case writes only its own output slot, so results do not depend on the number of threads or on
how cases are grouped into calls.

:func:`overturn_batch` runs the full product blocks × scales × motions;
:func:`overturn_cases` runs an explicit list of (block, motion, scale) triples, for searches that
need a different scale per block.  Both go through :func:`run_cases`, the unchecked entry used by
the Monte Carlo engine of :mod:`rocking.fragility`.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numba
import numpy as np

from ._numba import parallel_kernel, prange
from ._validate import finite_array, positive
from .body import G, Block
from .dynamics import _OVERTURNED, _REST, _advance, resolve_e, resolve_overturn_angle
from .errors import InputError

#: Cases handed to a thread at a time (dynamic scheduling: cases differ widely in cost, from
#: skipped to a full record of rocking, so static equal shares would leave threads idle).
_CHUNKSIZE = 4


@parallel_kernel
def _cases_kernel(acc, amax, dt, g, p2, sa, ca, tan_a, e, th_ov, alpha,
                  body, motion, scale, overturned, peak):
    """Integrate the cases i = (body[i], motion[i], scale[i]) from rest.

    ``acc`` (n_motions, n_t) [m/s²], ``amax`` = max|acc| per motion [m/s²], ``dt`` [s],
    ``g`` [m/s²]; per-block constants p² [1/s²], sin α, cos α, tan α, e, overturning angle [rad],
    α [rad].  Writes ``overturned[i]`` and ``peak[i]`` = max|θ|/α at the samples [-].
    """
    n_t = acc.shape[1]
    for i in prange(body.shape[0]):
        b = body[i]
        m = motion[i]
        sc = scale[i]
        # the same operations as simulate(block, sc * acc[m], dt): u = (sc·a)/g
        if abs(sc * amax[m]) / g * ca[b] <= sa[b]:  # _advance's uplift test
            overturned[i] = False  # never uplifts: stays at rest
            peak[i] = 0.0
            continue
        theta = 0.0
        omega = 0.0
        s = 1.0
        state = _REST
        pk = 0.0
        ov = False
        u0 = sc * acc[m, 0] / g
        for k in range(n_t - 1):
            u1 = sc * acc[m, k + 1] / g
            theta, omega, s, state, _ni, _tev = _advance(
                theta, omega, s, state, u0, u1, dt, p2[b], sa[b], ca[b], tan_a[b], e[b], th_ov[b])
            if state == _OVERTURNED:
                ov = True
                pk = th_ov[b]
                break  # nothing after overturning can matter
            if abs(theta) > pk:
                pk = abs(theta)
            u0 = u1
        overturned[i] = ov
        peak[i] = pk / alpha[b]


@dataclass(frozen=True, eq=False)
class BlockTable:
    """Per-block constants of Eq. (1) for the kernel, arrays of shape (n_blocks,).

    Attributes
    ----------
    p2 : ndarray
        p² = 3g/(4R) [1/s²].
    sin_a, cos_a, tan_a : ndarray
        sin α, cos α, tan α of the critical angle [-].
    e : ndarray
        Coefficient of restitution [-].
    theta_ov : ndarray
        Overturning angle [rad].
    alpha : ndarray
        Critical angle α [rad].
    g : float
        Gravity [m/s²].
    """

    p2: np.ndarray
    sin_a: np.ndarray
    cos_a: np.ndarray
    tan_a: np.ndarray
    e: np.ndarray
    theta_ov: np.ndarray
    alpha: np.ndarray
    g: float

    @classmethod
    def from_blocks(cls, blocks, *, e=0.925, overturn_angle=math.pi / 2, g=G) -> "BlockTable":
        """Constants of ``blocks`` (a sequence of :class:`~rocking.Block`).

        ``e`` and ``overturn_angle`` are one value for all blocks (number, ``"housner"`` /
        ``"alpha"``) or one per block; see :func:`rocking.simulate` [-, rad].  ``g`` [m/s²].
        """
        blocks = block_list(blocks)
        g = positive("g", g, "m/s²")
        e_vals = _per_block("e", e, blocks, resolve_e)
        ov_vals = _per_block("overturn_angle", overturn_angle, blocks, resolve_overturn_angle)
        alpha = np.array([b.alpha for b in blocks])
        # the same expressions as simulate(), so both integrate bit for bit the same equation
        return cls(p2=np.array([3.0 * g / (4.0 * b.R) for b in blocks]),
                   sin_a=np.array([math.sin(a) for a in alpha]),
                   cos_a=np.array([math.cos(a) for a in alpha]),
                   tan_a=np.array([math.tan(a) for a in alpha]),
                   e=e_vals, theta_ov=ov_vals, alpha=alpha, g=g)

    def __len__(self) -> int:
        return self.p2.size


def block_list(blocks) -> list[Block]:
    """``blocks`` as a non-empty list of :class:`~rocking.Block` (one Block is a list of one)."""
    if isinstance(blocks, Block):
        blocks = [blocks]
    blocks = list(blocks)
    if not blocks:
        raise InputError("blocks must contain at least one rocking.Block")
    for i, b in enumerate(blocks):
        if not isinstance(b, Block):
            raise InputError(f"blocks[{i}] must be a rocking.Block, got {type(b).__name__}")
    return blocks


def _per_block(name, value, blocks, resolve) -> np.ndarray:
    """One value for every block, or a sequence with one value per block, each resolved."""
    if isinstance(value, str) or np.ndim(value) == 0:
        return np.array([resolve(value, b) for b in blocks], dtype=np.float64)
    values = list(value)
    if len(values) != len(blocks):
        raise InputError(f"{name} has {len(values)} values for {len(blocks)} blocks")
    return np.array([resolve(v, b) for v, b in zip(values, blocks)], dtype=np.float64)


def motion_peaks(acc: np.ndarray) -> np.ndarray:
    """max|a| of each row of ``acc`` (n_motions, n_t) [m/s²], as the kernel's skip test needs."""
    return np.abs(acc).max(axis=1)


def run_cases(table: BlockTable, acc: np.ndarray, amax: np.ndarray, dt: float,
              body: np.ndarray, motion: np.ndarray, scale: np.ndarray):
    """Unchecked kernel call on validated, C-contiguous inputs (see :func:`overturn_cases`).

    ``amax`` is :func:`motion_peaks` of ``acc``.  Returns (overturned bool, peak float), shape
    like ``body``.
    """
    overturned = np.empty(body.shape, dtype=np.bool_)
    peak = np.empty(body.shape, dtype=np.float64)
    with numba.parallel_chunksize(_CHUNKSIZE):
        _cases_kernel(acc, amax, dt, table.g, table.p2, table.sin_a, table.cos_a, table.tan_a,
                      table.e, table.theta_ov, table.alpha, body, motion, scale, overturned, peak)
    return overturned, peak


def run_chunk(data: dict, task: tuple):
    """One chunk of a Monte Carlo run: all motions of one ensemble for each (block, scale) pair.

    Executed by a backend (:mod:`rocking.backends`), possibly in a worker process, which is why it
    lives in this light module.  ``data`` = {"table": BlockTable, "cases": [(acc, amax, dt), …]}
    (one entry per ensemble, as :func:`run_cases` takes them); ``task`` = (case index, body
    indices (n_pairs,) int64, scale factors (n_pairs,) float64).

    Returns (overturned, peak), shape (n_pairs, n_motions).
    """
    c, body, scale = task
    acc, amax, dt = data["cases"][c]
    n_m = acc.shape[0]
    overturned, peak = run_cases(data["table"], acc, amax, dt, np.repeat(body, n_m),
                                 np.tile(np.arange(n_m, dtype=np.int64), body.size),
                                 np.repeat(scale, n_m))
    return overturned.reshape(body.size, n_m), peak.reshape(body.size, n_m)


def _acc2d(acc) -> np.ndarray:
    a = finite_array("acc", acc, ndim=(1, 2), min_len=1)
    return np.ascontiguousarray(a.reshape(1, -1) if a.ndim == 1 else a)


def overturn_cases(blocks, acc, dt: float, body_index, motion_index, scales, *, e=0.925,
                   overturn_angle=math.pi / 2, g: float = G):
    """Overturning of an explicit list of cases (block, motion, scale), each from rest.

    Parameters
    ----------
    blocks : sequence of Block
        The blocks that ``body_index`` refers to.
    acc : array_like, shape (n_motions, n_t) or (n_t,)
        Ground accelerations [m/s²] sampled at ``dt``.
    dt : float
        Sample interval and Runge–Kutta step [s].
    body_index, motion_index : array_like of int, shape (n_cases,)
        Block and motion (row of ``acc``) of each case.
    scales : array_like, shape (n_cases,)
        Factor [-] multiplying the case's motion (negative: mirrored motion).
    e : float, "housner" or sequence
        Coefficient of restitution [-], one for all blocks or one per block.
    overturn_angle : float, "alpha" or sequence
        |θ| [rad] that counts as overturning, one for all blocks or one per block.
    g : float
        Gravity [m/s²].

    Returns
    -------
    overturned : ndarray of bool, shape (n_cases,)
    peak : ndarray of float, shape (n_cases,)
        max|θ|/α over the samples [-] (overturning angle/α when overturned, 0 at rest).
    """
    table = BlockTable.from_blocks(blocks, e=e, overturn_angle=overturn_angle, g=g)
    acc = _acc2d(acc)
    dt = positive("dt", dt, "s")
    body = _index("body_index", body_index, len(table))
    motion = _index("motion_index", motion_index, acc.shape[0])
    scale = finite_array("scales", scales, ndim=(1,), min_len=0)
    if not body.size == motion.size == scale.size:
        raise InputError(f"body_index, motion_index and scales must have the same length, got "
                         f"{body.size}, {motion.size} and {scale.size}")
    return run_cases(table, acc, motion_peaks(acc), dt, body, motion, scale)


def _index(name: str, values, n: int) -> np.ndarray:
    idx = np.asarray(values)
    if idx.ndim != 1 or (idx.size and idx.dtype.kind not in "iu"):
        raise InputError(f"{name} must be a 1-D array of integers")
    if idx.size and not (0 <= idx.min() and idx.max() < n):
        raise InputError(f"{name} must lie in [0, {n}), got values from {idx.min()} to {idx.max()}")
    return np.ascontiguousarray(idx, dtype=np.int64)


def overturn_batch(blocks, acc, dt: float, scales, *, e=0.925, overturn_angle=math.pi / 2,
                   g: float = G):
    """Overturning of every block under every motion at every scale factor, each from rest.

    The same answers as :func:`rocking.simulate` ``(block, scale * acc[m], dt, ...)`` case by case,
    computed in parallel.

    Parameters
    ----------
    blocks : sequence of Block
        n_blocks blocks.
    acc : array_like, shape (n_motions, n_t) or (n_t,)
        Ground accelerations [m/s²] sampled at ``dt``.
    dt : float
        Sample interval and Runge–Kutta step [s].
    scales : array_like, shape (n_scales,)
        Factors [-] multiplying the motions (negative: mirrored motion).
    e : float, "housner" or sequence
        Coefficient of restitution [-], one for all blocks or one per block.
    overturn_angle : float, "alpha" or sequence
        |θ| [rad] that counts as overturning (π/2 in the paper), one for all or one per block.
    g : float
        Gravity [m/s²].

    Returns
    -------
    overturned : ndarray of bool, shape (n_blocks, n_scales, n_motions)
    peak : ndarray of float, shape (n_blocks, n_scales, n_motions)
        max|θ|/α over the samples [-] (overturning angle/α when overturned, 0 at rest).
    """
    table = BlockTable.from_blocks(blocks, e=e, overturn_angle=overturn_angle, g=g)
    acc = _acc2d(acc)
    dt = positive("dt", dt, "s")
    scales = finite_array("scales", scales, ndim=(1,), min_len=1)
    shape = (len(table), scales.size, acc.shape[0])
    body, level, motion = (np.ascontiguousarray(i.ravel()) for i in np.indices(shape))
    overturned, peak = run_cases(table, acc, motion_peaks(acc), dt, body, motion, scales[level])
    return overturned.reshape(shape), peak.reshape(shape)
