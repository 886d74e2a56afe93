"""Many rocking simulations at once: overturned flags and peak rotations (issue 5, part 1).

One compiled, parallel kernel integrates independent cases (block, motion, scale factor) with the
physics of :func:`rocking.dynamics.simulate` — the same compiled one-interval functions of
:mod:`rocking.dynamics` — and keeps only what a Monte Carlo study needs: whether the block
overturned and its largest abs(θ)/α.

How it is fast (issue 6).  A *lane machine* integrates ``_LANES`` cases side by side, one sample
interval per round.  Each round first computes the RK4 step of every lane in one loop that the
compiler turns into SIMD code (:func:`rocking.dynamics.equation._plain_step`: branch-free,
polynomial
trigonometry); the lanes whose interval holds nothing else (no impact, no possible touch of θ = 0,
no overturning; about 98.5 % of rocking intervals) keep that step, and the loop returns the
others as bit masks.  Those — and lanes at rest — are handled one by one by
:func:`rocking.dynamics.impacts._advance_events`, exactly as :func:`~rocking.dynamics.simulate`
handles
them, except that after an impact from which the block swings clear of θ = 0 the rest of the
interval goes back to the SIMD loop.  Cases of the same
motion sit side by side (they read the same samples).  A lane whose case ends takes the next case
of its group; when none is left, the last lane moves into its place, so the SIMD loop only runs
over live lanes.  Work that cannot change the answer is skipped:

* a case whose scaled motion never lifts the block (abs(scale·a_g)·cos α ≤ g·sin α at every sample;
  the ground acceleration is linear between samples, so the samples bound it; with a vertical
  acceleration, max abs(scale·a_g)·cos α ≤ (g + abs(scale)·min a_v)·sin α, a conservative bound):
  not overturned, peak 0, no integration at all;
* intervals at rest: the lane jumps to the next sample at which the block lifts, and a case
  whose remaining samples cannot lift it (their suffix maximum of abs(a_g) and, with a_v,
  suffix minimum of a_v, in the same test) ends there: at rest to the end;
* everything after overturning.

Every case is computed by the same operations wherever its lane, group or thread, and writes only
its own output slot, so results do not depend on the number of threads or on how cases are grouped
into calls; they equal :func:`~rocking.dynamics.simulate` bit for bit.

:func:`overturn_batch` runs the full product blocks × scales × motions;
:func:`overturn_cases` runs an explicit list of (block, motion, scale) triples, for searches that
need a different scale per block.  Both go through :func:`run_cases`, the unchecked entry used by
the Monte Carlo engine of :mod:`rocking.montecarlo.probability`.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numba
import numpy as np

from ..core.checks import finite_array, positive
from ..core.compile import highest_bit, kernel, parallel_kernel, prange
from ..defaults import DEFAULT_E, IMPACT_SCHEMES
from ..errors import InputError
from .body import Block, G, resolve_e, resolve_overturn_angle
from .equation import _gv_sample, _gv_slope, _plain_step, _uplifts
from .impacts import (
    _OVERTURNED,
    _REST,
    _ROCKING,
    Body,
    Interval,
    Swing,
    _advance_events,
    resolve_impacts,
)

#: Cases integrated side by side by one lane machine (a multiple of the SIMD width).
_LANES = 128
#: Cases per lane machine, at most (a group is run by one thread; results do not depend on it).
_GROUP_MAX = 1024

# Rows of the lane table W (float64, _LANES values per row; one array, rows at constant offsets,
# so that the compiler can prove the SIMD loop's loads and stores independent)
_TH = 0  # θ [rad] at the start of the lane's current interval
_OM = 1  # θ' [rad/s]
_SG = 2  # pivot side s = ±1
_RK = 3  # 1.0 if rocking, 0.0 if at rest
_U0 = 4  # u = a_g/g at the start of the interval
_U1 = 5  # u at its end
_SC = 6  # scale factor of the case
_P2 = 7  # p² [1/s²]
_SA = 8  # sin α
_CA = 9  # cos α
_OV = 10  # overturning angle [rad]
_PK = 11  # max abs(θ) so far [rad]
_TH1 = 12  # RK4 step over the interval ...
_OM1 = 13
_VAL = 14  # ... and whether it is _rk4's step (1.0) or not (0.0)
_TAU = 15  # local time [s] from which the interval is still to be integrated (0 but after an event)
_H = 16  # dt − tau [s]
_TST = 17  # _advance_events' t_start and false_side in this interval
_FS = 18
_G0 = 19  # vertical factor gv = 1 + a_v/g at the start of the interval (with a_v only)
_G1 = 20  # gv at its end
_NR = 21  # intervals of the case spent at rest throughout, so far (step counting)
_R0 = 22  # 1.0 if the lane's current interval started at rest (step counting)
_ROWS = 23


@kernel
def _lane_steps(W, acc1, av1, nxt, base, n, dt, g, n_t):
    """One sample interval of lanes 0 … n−1 (a SIMD loop): the RK4 step, kept where it is all
    that happens in the interval (:func:`rocking.dynamics.equation._plain_step`).

    ``acc1``: each lane's ground acceleration at the end of the interval [m/s²], ``av1``: the
    vertical one [m/s²] or None, ``nxt``: index of that sample in the motions end to end
    (advanced where the interval is done), ``base``: index of the lane's motion there, ``n_t``:
    samples per motion.  Returns the lanes that need attention (an event, or the end of the
    motion) as bit masks: lanes 0 … 63, lanes 64 … 127.
    """
    L = _LANES
    low = np.uint64(0)
    high = np.uint64(0)
    for j in range(n):
        u0 = W[_U0 * L + j]
        sc = W[_SC * L + j]
        u1 = sc * acc1[j] / g  # as simulate(block, scale * acc, dt)
        g0 = None if av1 is None else W[_G0 * L + j]
        g1 = _gv_sample(av1, j, sc, g)  # as simulate(..., av=abs(scale) * av)
        theta = W[_TH * L + j]
        omega = W[_OM * L + j]
        th1, om1, valid, plain = _plain_step(
            theta,
            omega,
            W[_SG * L + j],
            u0,
            (u1 - u0) / dt,
            g0,
            _gv_slope(g0, g1, dt),
            W[_TAU * L + j],
            W[_H * L + j],
            W[_P2 * L + j],
            W[_SA * L + j],
            W[_CA * L + j],
            W[_OV * L + j],
        )
        plain = plain & (W[_RK * L + j] != 0.0)
        pk = W[_PK * L + j]
        a1 = abs(th1)
        W[_TH * L + j] = th1 if plain else theta
        W[_OM * L + j] = om1 if plain else omega
        W[_U0 * L + j] = u1 if plain else u0
        W[_PK * L + j] = a1 if (plain & (a1 > pk)) else pk
        nxt[j] += 1 if plain else 0
        W[_TAU * L + j] = 0.0 if plain else W[_TAU * L + j]
        W[_H * L + j] = dt if plain else W[_H * L + j]
        W[_U1 * L + j] = u1
        if av1 is not None:
            W[_G0 * L + j] = g1 if plain else g0
            W[_G1 * L + j] = g1
        W[_TH1 * L + j] = th1
        W[_OM1 * L + j] = om1
        W[_VAL * L + j] = 1.0 if valid else 0.0
        att = (not plain) | (nxt[j] >= base[j] + n_t)  # an event, or the motion ended
        bit = np.uint64(1 if att else 0) << np.uint64(j & 63)
        low |= bit if j < 64 else np.uint64(0)
        high |= np.uint64(0) if j < 64 else bit
    return low, high


@kernel
def _gather_acc(acc1, nxt, n, flat):
    """acc1[j] = flat[nxt[j]], the ground acceleration sample that ends lane j's interval [m/s²]
    (as an unsigned index: no test for negative ones)."""
    for j in range(n):
        acc1[j] = flat[np.uint64(nxt[j])]


@kernel
def _start_case(
    W,
    j,
    i,
    base,
    nxt_sample,
    state,
    acc,
    av,
    amax,
    avmin,
    asuf,
    avsuf,
    dt,
    g,
    p2,
    sa,
    ca,
    th_ov,
    body,
    motion,
    scale,
):
    """Put case i in lane j at the first interval in which its block may lift; False (lane left
    as it was) if it never lifts: then it stays at rest throughout (its result: not overturned,
    peak 0).  ``av`` (like ``acc``) and ``avmin`` (its least value per motion) [m/s²], or
    None."""
    L = _LANES
    n_t = acc.shape[1]
    b = body[i]
    m = motion[i]
    sc = scale[i]
    # gv ≥ 1 + abs(sc)·min a_v/g throughout the motion (conservative: it may lift only if ...)
    if not _may_lift(amax[m], avmin, m, sc, g, sa[b], ca[b]):
        return False  # no need to look at the samples
    flat = acc.reshape(-1)
    avflat = None if av is None else av.reshape(-1)
    k, u0, g0 = _rest_until_uplift(
        flat,
        avflat,
        asuf,
        avsuf,
        m * n_t,
        0,
        n_t,
        sc * flat[m * n_t] / g,
        _gv_sample(avflat, m * n_t, sc, g),
        sc,
        g,
        sa[b],
        ca[b],
    )
    if k >= n_t - 1:
        return False
    if av is not None:
        W[_G0 * L + j] = g0
    base[j] = m * n_t
    nxt_sample[j] = m * n_t + k + 1
    state[j] = _REST
    W[_TH * L + j] = 0.0
    W[_OM * L + j] = 0.0
    W[_SG * L + j] = 1.0
    W[_RK * L + j] = 0.0
    W[_U0 * L + j] = u0
    W[_SC * L + j] = sc
    W[_P2 * L + j] = p2[b]
    W[_SA * L + j] = sa[b]
    W[_CA * L + j] = ca[b]
    W[_OV * L + j] = th_ov[b]
    W[_PK * L + j] = 0.0
    W[_TAU * L + j] = 0.0
    W[_H * L + j] = dt
    W[_TST * L + j] = -1.0
    W[_FS * L + j] = 0.0
    W[_NR * L + j] = k
    return True


@kernel
def _lane_machine(
    acc,
    av,
    amax,
    avmin,
    asuf,
    avsuf,
    dt,
    g,
    p2,
    sa,
    ca,
    tan_a,
    e,
    th_ov,
    located,
    alpha,
    body,
    motion,
    scale,
    order,
    overturned,
    peak,
    steps,
    c0,
    c1,
):
    """Integrate cases order[c0] … order[c1 − 1] (see the module docstring); writes their
    results, and their integrated steps into ``steps`` unless it is None."""
    L = _LANES
    n_t = acc.shape[1]
    flat = acc.reshape(-1)
    avflat = None if av is None else av.reshape(-1)
    W = np.zeros(_ROWS * L)
    acc1 = np.zeros(L)  # ground acceleration at the end of each lane's interval [m/s²]
    av1 = None if av is None else np.zeros(L)  # vertical one [m/s²]
    nxt_sample = np.zeros(L, np.int64)  # index in flat of that sample
    case = np.full(L, -1, np.int64)
    base = np.zeros(L, np.int64)  # offset of the case's motion in flat
    state = np.zeros(L, np.int64)
    nxt = c0  # next case to start
    live = 0  # lanes 0 … live−1 hold a case
    while live < L and nxt < c1:
        i = order[nxt]
        nxt += 1
        if _start_case(
            W,
            live,
            i,
            base,
            nxt_sample,
            state,
            acc,
            av,
            amax,
            avmin,
            asuf,
            avsuf,
            dt,
            g,
            p2,
            sa,
            ca,
            th_ov,
            body,
            motion,
            scale,
        ):
            case[live] = i
            live += 1
        else:
            overturned[i] = False
            peak[i] = 0.0
            if steps is not None:
                steps[i] = 0
    while live > 0:
        _gather_acc(acc1, nxt_sample, live, flat)
        if av is not None:
            _gather_acc(av1, nxt_sample, live, avflat)
        low, high = _lane_steps(W, acc1, av1, nxt_sample, base, live, dt, g, n_t)
        # the lanes that need attention, from the highest down: an event, or the end of a case
        # (then the lane takes the next case, or the last live lane, handled already, moves
        # into it)
        while (high | low) != 0:
            if high != 0:
                j = 64 + highest_bit(high)
                high ^= np.uint64(1) << np.uint64(j - 64)
            else:
                j = highest_bit(low)
                low ^= np.uint64(1) << np.uint64(j)
            i = case[j]
            b = body[i]
            k = nxt_sample[j] - base[j] - 1  # the interval: from sample k to k + 1
            done = k >= n_t - 1  # the motion has ended
            ov = False
            if not done:
                u1 = W[_U1 * L + j]
                g1 = None if av is None else W[_G1 * L + j]
                if steps is not None and W[_TAU * L + j] == 0.0:  # a new interval
                    W[_R0 * L + j] = 1.0 if state[j] == _REST else 0.0
                sw, _ni, _te, deferred = _advance_events(
                    Swing(
                        W[_TH * L + j],
                        W[_OM * L + j],
                        W[_SG * L + j],
                        state[j],
                        W[_TAU * L + j],
                        W[_TST * L + j],
                        W[_FS * L + j],
                    ),
                    Interval(W[_U0 * L + j], u1, None if av is None else W[_G0 * L + j], g1, dt),
                    Body(
                        W[_P2 * L + j],
                        W[_SA * L + j],
                        W[_CA * L + j],
                        tan_a[b],
                        e[b],
                        W[_OV * L + j],
                    ),
                    W[_TH1 * L + j],
                    W[_OM1 * L + j],
                    (state[j] == _ROCKING) & (W[_VAL * L + j] != 0.0),
                    True,
                    located,
                )
                th, om, sg, st, tau, tst, fs = (
                    sw.theta,
                    sw.omega,
                    sw.s,
                    sw.state,
                    sw.tau,
                    sw.t_start,
                    sw.false_side,
                )
                if deferred:  # the rest of the interval, from tau, in the next SIMD round
                    W[_TH * L + j] = th
                    W[_OM * L + j] = om
                    W[_SG * L + j] = sg
                    W[_RK * L + j] = 1.0
                    W[_TAU * L + j] = tau
                    W[_H * L + j] = dt - tau
                    W[_TST * L + j] = tst
                    W[_FS * L + j] = fs
                    state[j] = st
                    continue
                W[_TAU * L + j] = 0.0
                W[_H * L + j] = dt
                W[_TST * L + j] = -1.0
                W[_FS * L + j] = 0.0
                k += 1
                if st == _OVERTURNED:
                    ov = True
                    done = True
                else:
                    if abs(th) > W[_PK * L + j]:
                        W[_PK * L + j] = abs(th)
                    if st == _REST:
                        k0 = k
                        if steps is not None and W[_R0 * L + j] != 0.0:  # at rest throughout
                            W[_NR * L + j] += 1.0
                        k, u1, g1 = _rest_until_uplift(
                            flat,
                            avflat,
                            asuf,
                            avsuf,
                            base[j],
                            k,
                            n_t,
                            u1,
                            g1,
                            W[_SC * L + j],
                            g,
                            W[_SA * L + j],
                            W[_CA * L + j],
                        )
                        if steps is not None:
                            W[_NR * L + j] += k - k0
                    W[_TH * L + j] = th
                    W[_OM * L + j] = om
                    W[_SG * L + j] = sg
                    W[_U0 * L + j] = u1
                    if av is not None:
                        W[_G0 * L + j] = g1
                    W[_RK * L + j] = 1.0 if st == _ROCKING else 0.0
                    nxt_sample[j] = base[j] + k + 1
                    state[j] = st
                    done = k >= n_t - 1
            if done:
                overturned[i] = ov
                peak[i] = (W[_OV * L + j] if ov else W[_PK * L + j]) / alpha[b]
                if steps is not None:  # k intervals, up to overturning or to the end
                    steps[i] = k - int(W[_NR * L + j])
                case[j] = -1
                while nxt < c1 and case[j] < 0:
                    i = order[nxt]
                    nxt += 1
                    if _start_case(
                        W,
                        j,
                        i,
                        base,
                        nxt_sample,
                        state,
                        acc,
                        av,
                        amax,
                        avmin,
                        asuf,
                        avsuf,
                        dt,
                        g,
                        p2,
                        sa,
                        ca,
                        th_ov,
                        body,
                        motion,
                        scale,
                    ):
                        case[j] = i
                    else:
                        overturned[i] = False
                        peak[i] = 0.0
                        if steps is not None:
                            steps[i] = 0
                if case[j] < 0:  # no case left: the last live lane (handled already) moves here
                    live -= 1
                    if j < live:
                        for r in range(_ROWS):
                            W[r * L + j] = W[r * L + live]
                        case[j] = case[live]
                        base[j] = base[live]
                        nxt_sample[j] = nxt_sample[live]
                        state[j] = state[live]
                        case[live] = -1


@kernel
def _suffix_extremes(acc, av):
    """Suffix maximum of abs(acc) and suffix minimum of ``av`` (None: None) from each sample to
    the end of its motion [m/s²], the motions (rows) end to end: a block at rest that no later
    sample can lift is at rest to the end (:func:`_rest_until_uplift`)."""
    n_m, n_t = acc.shape
    asuf = np.empty(n_m * n_t)
    avsuf = np.empty(0 if av is None else n_m * n_t)
    for m in range(n_m):
        top = 0.0
        low = math.inf
        for k in range(n_t - 1, -1, -1):
            top = max(top, abs(acc[m, k]))
            asuf[m * n_t + k] = top
            if av is not None:
                low = min(low, av[m, k])
                avsuf[m * n_t + k] = low
    return asuf, None if av is None else avsuf


@kernel(inline="always")
def _may_lift(amax, avmin, i, sc, g, sa, ca):
    """Whether samples whose abs(a_g) is at most ``amax`` [m/s²] and whose vertical acceleration is
    at least ``avmin[i]`` [m/s²] (``avmin`` None: no vertical motion) may lift a block at rest
    under the case's scale ``sc``: :func:`~rocking.dynamics.equation._uplifts` of the extremes.
    It is exactly the test at every such sample or weaker: abs(sc·a)/g rounds monotonically in
    abs(a), 1 + abs(sc)·a_v/g in a_v, and the test is monotone in both (conservative when the
    extremes fall on different samples)."""
    return _uplifts(abs(sc * amax) / g, _gv_sample(avmin, i, sc, g), sa, ca)


@kernel
def _rest_until_uplift(flat, avflat, asuf, avsuf, base, k, n_t, u, gv, sc, g, sa, ca):
    """First interval k' ≥ k of a block at rest in which it may lift (u and gv at its start), or
    (n_t − 1, u, gv) if none: the intervals skipped are those where _advance leaves it at rest
    (no uplift at either end; u and gv linear in between, abs(u)·cos α − gv·sin α convex).
    ``avflat``: the vertical accelerations end to end [m/s²], or None (then gv is None);
    ``asuf``, ``avsuf``: suffix maximum of abs(acc) and suffix minimum of av at each sample,
    end to end like them (None without av): when no sample from k on can lift the block
    (:func:`_may_lift`), it is at rest to the end, and the samples are not looked at."""
    if not _may_lift(asuf[base + k], avsuf, base + k, sc, g, sa, ca):
        return n_t - 1, u, gv
    while k < n_t - 1:
        u_next = sc * flat[base + k + 1] / g
        g_next = _gv_sample(avflat, base + k + 1, sc, g)
        if _uplifts(u, gv, sa, ca) or _uplifts(u_next, g_next, sa, ca):
            break
        u = u_next
        gv = g_next
        k += 1
    return k, u, gv


@parallel_kernel
def _cases_kernel(
    acc,
    av,
    amax,
    avmin,
    asuf,
    avsuf,
    dt,
    g,
    p2,
    sa,
    ca,
    tan_a,
    e,
    th_ov,
    located,
    alpha,
    body,
    motion,
    scale,
    order,
    group,
    overturned,
    peak,
    steps,
):
    """Integrate the cases i = (body[i], motion[i], scale[i]) from rest, in the order ``order``
    (a permutation of the cases), ``group`` consecutive ones per lane machine.

    ``acc`` (n_motions, n_t) [m/s²], ``av`` the vertical accelerations like it or None,
    ``amax`` = max abs(acc) per motion [m/s²], ``avmin`` = min ``av`` per motion or None,
    ``asuf``, ``avsuf`` their suffix versions at every sample (see :func:`_rest_until_uplift`),
    ``dt`` [s], ``g`` [m/s²]; per-block constants p² [1/s²], sin α, cos α, tan α, e, overturning
    angle [rad], the impact scheme (``located``: bool), α [rad].  Writes ``overturned[i]`` and
    ``peak[i]`` = max abs(θ)/α at the samples [-], and the integrated steps ``steps[i]`` unless
    ``steps`` is None.
    """
    n = body.shape[0]
    for q in prange((n + group - 1) // group):
        _lane_machine(
            acc,
            av,
            amax,
            avmin,
            asuf,
            avsuf,
            dt,
            g,
            p2,
            sa,
            ca,
            tan_a,
            e,
            th_ov,
            located,
            alpha,
            body,
            motion,
            scale,
            order,
            overturned,
            peak,
            steps,
            q * group,
            min(n, (q + 1) * group),
        )


@dataclass(frozen=True, eq=False)
class BlockTable:
    """Per-block constants of Eq. (1) for the kernel, arrays of shape (n_blocks,).

    Attributes
    ----------
    p2 : ndarray
        p² = g·R/(r_g² + R²) [1/s²] (3g/(4R) for a uniform block; :meth:`Block.p_squared`).
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
    def from_blocks(cls, blocks, *, e=DEFAULT_E, overturn_angle=math.pi / 2, g=G) -> BlockTable:
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
        return cls(
            p2=np.array([b.p_squared(g) for b in blocks]),
            sin_a=np.array([math.sin(a) for a in alpha]),
            cos_a=np.array([math.cos(a) for a in alpha]),
            tan_a=np.array([math.tan(a) for a in alpha]),
            e=e_vals,
            theta_ov=ov_vals,
            alpha=alpha,
            g=g,
        )

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
    """max abs(a) of each row of ``acc`` (n_motions, n_t) [m/s²], as the kernel's skip test
    needs."""
    return np.abs(acc).max(axis=1)


def run_cases(
    table: BlockTable,
    acc: np.ndarray,
    amax: np.ndarray,
    dt: float,
    body: np.ndarray,
    motion: np.ndarray,
    scale: np.ndarray,
    av: np.ndarray | None = None,
    impacts: str = IMPACT_SCHEMES[0],
    *,
    count_steps: bool = False,
):
    """Kernel call on validated, C-contiguous inputs (see :func:`overturn_cases`).

    ``amax`` is :func:`motion_peaks` of ``acc``.  ``av``: vertical ground accelerations [m/s², up
    positive], finite, shape and samples as ``acc``, or None (no vertical motion: exactly the
    results without it); case i scales it by abs(scale[i]) (a negative scale mirrors the
    horizontal motion only).  ``impacts``: "located" (default) or "step-end", as in
    :func:`rocking.simulate`.  The checks made here: a scaled ``av`` that reaches −g, and an
    unknown ``impacts``, raise :class:`~rocking.errors.InputError`.  Returns (overturned bool,
    peak float), shape like ``body``; with ``count_steps``, also the integrated steps of each
    case (int64): the sample intervals in which the block is not at rest throughout (it rocks at
    the start or at the end of the interval), up to and including the one in which it
    overturns.
    """
    asuf, avsuf = _suffix_extremes(acc, av)
    avmin = None
    if av is not None:
        avmin = av.min(axis=1)
        low = np.abs(scale) * avmin[motion]
        if low.size and low.min() <= -table.g:
            i = int(np.argmin(low))
            raise InputError(
                f"av scaled by {abs(scale[i]):g} (case {i}, motion {motion[i]}) reaches "
                f"{low[i]:g} m/s², at or below -g = {-table.g:g} m/s²: the block would leave "
                "the ground, which is not modelled"
            )
    overturned = np.empty(body.shape, dtype=np.bool_)
    peak = np.empty(body.shape, dtype=np.float64)
    steps = np.empty(body.shape, dtype=np.int64) if count_steps else None
    # about four groups per thread (dynamic scheduling), of at least _LANES cases so that the
    # lanes are filled
    group = max(_LANES, min(_GROUP_MAX, -(-body.size // (4 * numba.get_num_threads()))))
    # cases of the same motion side by side, so that their lanes read the same samples (cache);
    # every ng-th of them in a group, so that the groups have about the same mix of motions and
    # cost (the threads finish together)
    order = np.argsort(motion, kind="stable")
    ng = max(1, -(-body.size // group))
    order = np.concatenate([order[q::ng] for q in range(ng)])
    with numba.parallel_chunksize(1):
        _cases_kernel(
            acc,
            av,
            amax,
            avmin,
            asuf,
            avsuf,
            dt,
            table.g,
            table.p2,
            table.sin_a,
            table.cos_a,
            table.tan_a,
            table.e,
            table.theta_ov,
            resolve_impacts(impacts),
            table.alpha,
            body,
            motion,
            scale,
            order,
            group,
            overturned,
            peak,
            steps,
        )
    if steps is not None:
        return overturned, peak, steps
    return overturned, peak


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
    blocks,
    acc,
    dt: float,
    body_index,
    motion_index,
    scales,
    *,
    e=DEFAULT_E,
    overturn_angle=math.pi / 2,
    g: float = G,
    av=None,
    impacts: str = IMPACT_SCHEMES[0],
):
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
        abs(θ) [rad] that counts as overturning, one for all blocks or one per block.
    g : float
        Gravity [m/s²].
    av : array_like, shape like ``acc``, optional
        Vertical ground accelerations [m/s², up positive] at the samples of ``acc``, scaled by
        abs(scale) for each case; above −g after scaling.  None: no vertical motion.
    impacts : {"located", "step-end"}
        Impact handling, as in :func:`rocking.simulate` ("located" by default).

    Returns
    -------
    overturned : ndarray of bool, shape (n_cases,)
    peak : ndarray of float, shape (n_cases,)
        max abs(θ)/α over the samples [-] (overturning angle/α when overturned, 0 at rest).
    """
    table = BlockTable.from_blocks(blocks, e=e, overturn_angle=overturn_angle, g=g)
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
    return run_cases(table, acc, motion_peaks(acc), dt, body, motion, scale, av, impacts)


def _index(name: str, values, n: int) -> np.ndarray:
    idx = np.asarray(values)
    if idx.ndim != 1 or (idx.size and idx.dtype.kind not in "iu"):
        raise InputError(f"{name} must be a 1-D array of integers")
    if idx.size and not (idx.min() >= 0 and idx.max() < n):
        raise InputError(f"{name} must lie in [0, {n}), got values from {idx.min()} to {idx.max()}")
    return np.ascontiguousarray(idx, dtype=np.int64)


def overturn_batch(
    blocks,
    acc,
    dt: float,
    scales,
    *,
    e=DEFAULT_E,
    overturn_angle=math.pi / 2,
    g: float = G,
    av=None,
    impacts: str = IMPACT_SCHEMES[0],
):
    """Overturning of every block under every motion at every scale factor, each from rest.

    The same answers as :func:`rocking.simulate` ``(block, scale * acc[m], dt, ...)`` case by case
    (with ``av=abs(scale) * av[m]``), computed in parallel.

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
        abs(θ) [rad] that counts as overturning (π/2 in the paper), one for all or one per block.
    g : float
        Gravity [m/s²].
    av : array_like, shape like ``acc``, optional
        Vertical ground accelerations [m/s², up positive] at the samples of ``acc``, scaled by
        abs(scale); above −g after scaling.  None: no vertical motion.
    impacts : {"located", "step-end"}
        Impact handling, as in :func:`rocking.simulate` ("located" by default).

    Returns
    -------
    overturned : ndarray of bool, shape (n_blocks, n_scales, n_motions)
    peak : ndarray of float, shape (n_blocks, n_scales, n_motions)
        max abs(θ)/α over the samples [-] (overturning angle/α when overturned, 0 at rest).
    """
    table = BlockTable.from_blocks(blocks, e=e, overturn_angle=overturn_angle, g=g)
    acc = _acc2d(acc)
    av = _av2d(av, acc)
    dt = positive("dt", dt, "s")
    scales = finite_array("scales", scales, ndim=(1,), min_len=1)
    shape = (len(table), scales.size, acc.shape[0])
    body, level, motion = (np.ascontiguousarray(i.ravel()) for i in np.indices(shape))
    overturned, peak = run_cases(
        table, acc, motion_peaks(acc), dt, body, motion, scales[level], av, impacts
    )
    return overturned.reshape(shape), peak.reshape(shape)
