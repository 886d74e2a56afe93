"""Many rocking simulations at once: the response quantities of each case (issue 5, part 1).

One compiled, parallel kernel integrates independent cases (block, motion, scale factor) with the
physics of :func:`rocking.dynamics.simulate` — the same compiled one-interval functions of
:mod:`rocking.dynamics` — and keeps only what a Monte Carlo study needs, the
:class:`~rocking.dynamics.batch_records.Outcome` of each case: whether the block overturned, its
largest abs(θ)/α and whether it left rest at all.  Split along its seams (issue 44): the records
in :mod:`rocking.dynamics.batch_records`, the lane machine (how it is fast, issues 6 and 18) in
:mod:`rocking.dynamics.batch_lanes`, the entry points here.  With friction (issue 45: a finite
μ_s of the :class:`~rocking.Physics`), the lanes carry every response mode
(:mod:`rocking.dynamics.batch_modes`); the Outcome gains their slip and lift.

Every case is computed by the same operations wherever its lane, machine or thread, and writes
only its own output slot, so results do not depend on the number of threads, on which machine
takes a case or on how cases are grouped into calls; they equal :func:`~rocking.dynamics.simulate`
bit for bit.

:func:`overturn_batch` runs the full product blocks × scales × motions;
:func:`overturn_cases` runs an explicit list of (block, motion, scale) triples, for searches that
need a different scale per block.  Both go through :func:`run_cases`, the unchecked entry used by
the Monte Carlo engine of :mod:`rocking.montecarlo.probability`.

The records are re-exported here (``from rocking.dynamics.batch import BlockTable, Outcome``).
"""

from __future__ import annotations

from collections.abc import Iterable
from typing import Any

import numba
import numpy as np
from numpy.typing import ArrayLike

from ..core.checks import finite_array, positive
from ..core.compile import readonly
from ..errors import InputError
from .batch_lanes import _cases_kernel, _suffixes_of
from .batch_modes import lane_friction
from .batch_records import (
    QUANTITIES,
    Blocks,
    BlockTable,
    Cases,
    Motions,
    Outcome,
    PerBlock,
    Vertical,
    block_list,
    concatenate,
    empty_outcome,
    motion_peaks,
    take,
)
from .body import Block
from .impacts import resolve_impacts
from .physics import Physics, as_physics

__all__ = [
    "QUANTITIES",
    "BlockTable",
    "Blocks",
    "Cases",
    "Motions",
    "Outcome",
    "PerBlock",
    "Vertical",
    "block_list",
    "concatenate",
    "empty_outcome",
    "motion_peaks",
    "motion_suffixes",
    "overturn_batch",
    "overturn_cases",
    "run_cases",
    "take",
]


def motion_suffixes(
    acc: np.ndarray, av: np.ndarray | None = None
) -> tuple[np.ndarray, np.ndarray | None]:
    """The rest test's suffix extremes of every motion of ``acc`` (n_motions, n_t) and of its
    vertical accelerations ``av`` (or None) [m/s²], flat (see
    :func:`rocking.dynamics.batch_lanes._suffix_extremes`), for
    :func:`run_cases` calls on the same motions: computed once for them instead of in every
    call (with a thousand motions, as long as the simulations of a call)."""
    acc = readonly(np.ascontiguousarray(acc))
    av = None if av is None else readonly(np.ascontiguousarray(av))
    return _suffixes_of(acc, av, np.ones(acc.shape[0], dtype=np.bool_))


def run_cases(
    table: BlockTable,
    acc: np.ndarray,
    amax: np.ndarray,
    dt: float,
    body: np.ndarray,
    motion: np.ndarray,
    scale: np.ndarray,
    av: np.ndarray | None = None,
    impacts: str | None = None,
    *,
    suffixes: tuple[np.ndarray, np.ndarray | None] | None = None,
) -> Outcome:
    """Kernel call on validated, C-contiguous inputs (see :func:`overturn_cases`).

    ``amax`` is :func:`motion_peaks` of ``acc``; ``suffixes``, if given, :func:`motion_suffixes`
    of ``acc`` and ``av`` (else computed here for the motions this call uses).  ``av``: vertical
    ground accelerations [m/s², up positive], finite, shape and samples as ``acc``, or None (no
    vertical motion: exactly the results without it); case i scales it by abs(scale[i]) (a
    negative scale mirrors the horizontal motion only).  ``impacts``: "located" or "step-end",
    as in :func:`rocking.simulate` (None: the table's physics).  The checks made here: a
    scaled ``av`` that reaches −g for a block without friction (with friction it may fly), and
    an unknown ``impacts``, raise :class:`~rocking.errors.InputError`.

    Cases of blocks with friction (the table's μ_s finite, issue 45) run in the lane machines
    with the modes model's state and checks (:mod:`rocking.dynamics.batch_modes`): rock in
    SIMD, every other interval by modes_case's own interval function; they give
    :func:`rocking.simulate` ``(..., mu=...)``'s results bit for bit.
    Returns the :class:`Outcome` of every case, shape like ``body``; its ``steps`` are the
    integrated steps of each case: the sample intervals that are not skipped at rest (in
    which the block is not at rest throughout, or with friction may slip), up to and including
    the one in which it overturns.
    """
    acc = readonly(acc)
    av = None if av is None else readonly(av)
    located = resolve_impacts(table.physics.impacts if impacts is None else impacts)
    avmin = None if av is None else av.min(axis=1)
    frictionless = table.contacts.mu_s == np.inf
    if avmin is not None:
        low = np.abs(scale) * avmin[motion]
        low[~frictionless[body]] = np.inf  # with friction the block may fly: allowed
        if low.size and low.min() <= -table.g:
            i = int(np.argmin(low))
            raise InputError(
                f"av scaled by {abs(scale[i]):g} (case {i}, motion {motion[i]}) reaches "
                f"{low[i]:g} m/s², at or below -g = {-table.g:g} m/s²: the block would leave "
                "the ground, which the rocking-only model does not model; give a friction "
                "coefficient mu for the model with sliding and flight"
            )
    if frictionless.all():
        return _lanes(
            table, acc, amax, dt, (body, motion, scale), (av, avmin), located, suffixes, None
        )
    if suffixes is None:  # once for the motions of both lane calls below
        used = np.zeros(acc.shape[0], dtype=np.bool_)
        used[motion] = True
        suffixes = _suffixes_of(acc, av, used)
    out = empty_outcome(body.size, alloc=np.empty)  # every case is written
    # the blocks without friction in lanes without checks, those with in lanes with checks
    for checked in (False, True):
        sel = np.flatnonzero(frictionless[body] != checked)
        if not sel.size:
            continue
        fric = lane_friction(table.contacts, table.g) if checked else None
        lanes = _lanes(
            table,
            acc,
            amax,
            dt,
            (body[sel], motion[sel], scale[sel]),
            (av, avmin),
            located,
            suffixes,
            fric,
        )
        for field, values in zip(out, lanes):
            field[sel] = values
    return out


def _lanes(table, acc, amax, dt, cases, vertical, located, suffixes, fric) -> Outcome:
    """The lane machines of :mod:`rocking.dynamics.batch_lanes` on ``cases`` (body, motion,
    scale arrays), with ``vertical`` = (av, its min per motion) or (None, None) and the contact
    checks ``fric`` (:class:`~rocking.dynamics.batch_lanes.Friction`, or None: none)."""
    body, motion, scale = cases
    av, avmin = vertical
    if suffixes is None:
        used = np.zeros(acc.shape[0], dtype=np.bool_)
        used[motion] = True  # the suffix extremes of these motions only (a call may use few)
        asuf, avsuf = _suffixes_of(acc, av, used)
    else:
        asuf, avsuf = suffixes
    vert = None
    if av is not None:
        assert avsuf is not None  # computed with av
        vert = Vertical(av.reshape(-1), avmin, avsuf)
    out = empty_outcome(body.size, alloc=np.empty)  # every case is written by the kernel
    # one lane machine per thread, all taking cases from one queue: the threads finish
    # together, and each machine's lanes empty only once per call, at its end (a lane machine
    # per group of cases instead, four per thread, spent ~20 % more time per step in the
    # Monte Carlo engine's chunks of ~4,000 cases, in their groups' partly filled ends);
    # cases of the same motion side by side, so that the lanes read the same samples (cache)
    machines = max(1, min(numba.get_num_threads(), body.size))
    order = np.argsort(motion, kind="stable")
    motions = Motions(acc.reshape(-1), acc.shape[1], float(dt), amax, asuf)
    with numba.parallel_chunksize(1):
        _cases_kernel(
            motions,
            vert,
            fric,
            table.arrays(),
            Cases(body, motion, scale, order),
            out,
            located,
            machines,
        )
    return out


def _acc2d(acc, name: str = "acc") -> np.ndarray:
    a = finite_array(name, acc, ndim=(1, 2), min_len=1)
    return np.ascontiguousarray(a.reshape(1, -1) if a.ndim == 1 else a)


def _av2d(av, acc: np.ndarray) -> np.ndarray | None:
    """``av`` as a C-contiguous array shaped like ``acc`` (None stays None)."""
    if av is None:
        return None
    a = _acc2d(av, "av")
    if a.shape != acc.shape:
        raise InputError(
            f"av must have the shape of acc, {acc.shape}, got {a.shape} (one vertical "
            "acceleration per horizontal one, at the same samples)"
        )
    return a


def overturn_cases(
    blocks: Block | Iterable[Block],
    acc: ArrayLike,
    dt: float,
    body_index: ArrayLike,
    motion_index: ArrayLike,
    scales: ArrayLike,
    *,
    physics: Physics | None = None,
    av: ArrayLike | None = None,
    **shorthands: Any,
) -> tuple[np.ndarray, np.ndarray]:
    """Overturning of an explicit list of cases (block, motion, scale), each from rest.

    Parameters
    ----------
    blocks : Block or sequence of Block
        The blocks that ``body_index`` refers to.
    acc : array_like, shape (n_motions, n_t) or (n_t,)
        Ground accelerations [m/s²] sampled at ``dt``.
    dt : float
        Sample interval and Runge–Kutta step [s].
    body_index, motion_index : array_like of int, shape (n_cases,)
        Block and motion (row of ``acc``) of each case.
    scales : array_like, shape (n_cases,)
        Factor [-] multiplying the case's motion (negative: mirrored motion).
    physics : Physics, optional
        The physics (:class:`~rocking.Physics`; default ``Physics()``): restitution [-],
        overturning angle [rad] and friction coefficients [-] one for all blocks or one per
        block, g [m/s²], impact scheme.
    av : array_like, shape like ``acc``, optional
        Vertical ground accelerations [m/s², up positive] at the samples of ``acc``, scaled by
        abs(scale) for each case; above −g after scaling for a block without friction (with
        ``mu`` it may fly).  None: no vertical motion.
    **shorthands
        ``e``, ``overturn_angle``, ``g``, ``impacts``: shorthands for physics's fields, one
        release; ``mu``, ``mu_k``: friction coefficients [-] (one value or one per block;
        issue 45).  Any other keyword is an InputError.

    Returns
    -------
    overturned : ndarray of bool, shape (n_cases,)
    peak : ndarray of float, shape (n_cases,)
        max abs(θ)/α over the samples [-] (overturning angle/α when overturned, 0 at rest).
    """
    physics = as_physics(physics, **shorthands)
    table = BlockTable.from_blocks(blocks, physics=physics)
    acc = _acc2d(acc)
    av = _av2d(av, acc)
    dt = positive("dt", dt, "s")
    body = _index("body_index", body_index, len(table))
    motion = _index("motion_index", motion_index, acc.shape[0])
    scale = finite_array("scales", scales, ndim=(1,), min_len=0)
    if not body.size == motion.size == scale.size:
        raise InputError(
            f"body_index, motion_index and scales must have the same length, got "
            f"{body.size}, {motion.size} and {scale.size}"
        )
    out = run_cases(table, acc, motion_peaks(acc), dt, body, motion, scale, av)
    return out.overturned, out.peak_theta_ratio


def _index(name: str, values, n: int) -> np.ndarray:
    idx = np.asarray(values)
    if idx.ndim != 1 or (idx.size and idx.dtype.kind not in "iu"):
        raise InputError(f"{name} must be a 1-D array of integers")
    if idx.size and not (idx.min() >= 0 and idx.max() < n):
        raise InputError(f"{name} must lie in [0, {n}), got values from {idx.min()} to {idx.max()}")
    return np.ascontiguousarray(idx, dtype=np.int64)


def overturn_batch(
    blocks: Block | Iterable[Block],
    acc: ArrayLike,
    dt: float,
    scales: ArrayLike,
    *,
    physics: Physics | None = None,
    av: ArrayLike | None = None,
    **shorthands: Any,
) -> tuple[np.ndarray, np.ndarray]:
    """Overturning of every block under every motion at every scale factor, each from rest.

    The same answers as :func:`rocking.simulate` ``(block, scale * acc[m], dt, ...)`` case by case
    (with ``av=abs(scale) * av[m]``), computed in parallel.

    Parameters
    ----------
    blocks : Block or sequence of Block
        n_blocks blocks.
    acc : array_like, shape (n_motions, n_t) or (n_t,)
        Ground accelerations [m/s²] sampled at ``dt``.
    dt : float
        Sample interval and Runge–Kutta step [s].
    scales : array_like, shape (n_scales,)
        Factors [-] multiplying the motions (negative: mirrored motion).
    physics : Physics, optional
        The physics (:class:`~rocking.Physics`; default ``Physics()``): restitution [-],
        overturning angle [rad] and friction coefficients [-] one for all blocks or one per
        block, g [m/s²], impact scheme.
    av : array_like, shape like ``acc``, optional
        Vertical ground accelerations [m/s², up positive] at the samples of ``acc``, scaled by
        abs(scale); above −g after scaling for a block without friction (with ``mu`` it may
        fly).  None: no vertical motion.
    **shorthands
        ``e``, ``overturn_angle``, ``g``, ``impacts``: shorthands for physics's fields, one
        release; ``mu``, ``mu_k``: friction coefficients [-] (one value or one per block;
        issue 45).  Any other keyword is an InputError.

    Returns
    -------
    overturned : ndarray of bool, shape (n_blocks, n_scales, n_motions)
    peak : ndarray of float, shape (n_blocks, n_scales, n_motions)
        max abs(θ)/α over the samples [-] (overturning angle/α when overturned, 0 at rest).
    """
    physics = as_physics(physics, **shorthands)
    table = BlockTable.from_blocks(blocks, physics=physics)
    acc = _acc2d(acc)
    av = _av2d(av, acc)
    dt = positive("dt", dt, "s")
    scales = finite_array("scales", scales, ndim=(1,), min_len=1)
    shape = (len(table), scales.size, acc.shape[0])
    body, level, motion = (np.ascontiguousarray(i.ravel()) for i in np.indices(shape))
    out = run_cases(table, acc, motion_peaks(acc), dt, body, motion, scales[level], av)
    return out.overturned.reshape(shape), out.peak_theta_ratio.reshape(shape)
