"""The lane machine of the batched kernel (issues 6 and 18; entry points in
:mod:`rocking.dynamics.batch`, records in :mod:`rocking.dynamics.batch_records`).

A *lane machine* integrates ``_LANES`` cases side by side, one
sample interval per round.  Each round first computes the RK4 step of every lane in loops that
the compiler turns into SIMD code (:func:`rocking.dynamics.equation._plain_step`: branch-free,
polynomial trigonometry; cut into five loops, so that the processor overlaps the lanes'
dependency chains); the lanes whose interval holds nothing else (no impact, no possible
touch of θ = 0, no overturning; about 98.5 % of rocking intervals) keep that step, and the loop
returns the others as bit masks.  Every quantity the loop changes is stored for every lane (the
state the step started from in rows of its own, which the event handling reads): a store only
where the step is plain would compile to a masked store, which AMD processors before Zen 4
execute in microcode.  The other lanes — and lanes at rest — are handled one by one by
:func:`rocking.dynamics.impacts._advance_events`, exactly as :func:`~rocking.dynamics.simulate`
handles them, except that the impact of a step that ends on the other side of θ = 0 is located
with the partial Runge–Kutta steps of its Newton iteration computed in the lane's next SIMD rounds
(:func:`_start_locating`; the same operations as :func:`rocking.dynamics.impacts._locate`: a
scalar partial step is a chain of ~100 cycles of latency), and that after an impact from which the
block rocks on the rest of the interval goes back to the SIMD loop.  Cases of the
same motion sit side by side (they read the same samples).  A lane whose case ends takes the
next case of the call's queue, which the lane machines of all threads share (each holding at
most its share of the call's cases, so that a small call keeps every thread busy); when none is
left, the last lane moves into its place, so the SIMD loop only runs over live lanes.  The
kernel's inputs are records (:class:`~rocking.dynamics.batch_records.Motions`, ``Vertical``,
``Blocks``, ``Cases``, ``Outcome``), its lanes' state :class:`Lanes`.  Work that cannot change
the answer is skipped:

* a case whose scaled motion never lifts the block (abs(scale·a_g)·cos α ≤ g·sin α at every sample;
  the ground acceleration is linear between samples, so the samples bound it; with a vertical
  acceleration, max abs(scale·a_g)·cos α ≤ (g + abs(scale)·min a_v)·sin α, a conservative bound):
  not overturned, peak 0, no integration at all;
* intervals at rest: the lane jumps to the next sample at which the block lifts, and a case
  whose remaining samples cannot lift it (their suffix maximum of abs(a_g) and, with a_v,
  suffix minimum of a_v, in the same test) ends there: at rest to the end;
* everything after overturning.

With friction (issue 45: :class:`Friction`, blocks with a finite μ_s), a lane carries the whole
state of :func:`~rocking.dynamics.modes.modes_case` (the mode, σ, the slip q and its rate, the
height and the running summaries, in rows of its own) and runs each interval where
:mod:`rocking.dynamics.batch_modes` says: rock (and rest where the block may lift, the base
cannot slip) in the rocking path above, with modes_case's contact checks at the sample that ends
the interval (in the SIMD loop, on the sin θ and cos θ it computes anyway; with margins) and after
its impacts (where they are handled); where one fails, the lane does that interval again from its
start (rows of its own) with :func:`~rocking.dynamics.modes._modes_interval`, modes_case's own
interval function (:func:`_redo`).  Slide is a step of the SIMD loop too (:func:`_slide_steps`,
modes_case's own slide step), kept where it is all that happens in the interval; every other
interval runs in the lane by that interval function (:func:`_modes_run`: slide-rock, flight,
rest where the base may slip, the transitions); rest where the base can neither slip nor lift
is skipped.  Without friction the argument is None, and all of
this compiles away (as the vertical motion's code does without it).

Every case is computed by the same operations wherever its lane, machine or thread, and writes
only its own output slot, so results do not depend on the number of threads, on which machine
takes a case or on how cases are grouped into calls; they equal :func:`~rocking.dynamics.simulate`
bit for bit.
"""

from __future__ import annotations

import math
from typing import NamedTuple

import numpy as np

from ..core.compile import (
    aligned_zeros,
    borrowing_kernel,
    fetch_add,
    highest_bit,
    kernel,
    maxnum,
    parallel_kernel,
    prange,
)
from .equation import (
    _angle_terms,
    _gv_sample,
    _gv_slope,
    _plain_terms,
    _plain_tests,
    _rk4_end,
    _rk4_middle,
    _rk4_stages,
    _sincos,
    _uplifts,
)
from .impacts import (
    _NEWTON_MAX,
    _OVERTURNED,
    _REST,
    _ROCKING,
    Body,
    Interval,
    Swing,
    _advance_events,
    _ends_across,
    _impact,
    _locate_start,
    _newton,
    _slopes,
)
from .modes import (
    REST,
    ROCK,
    SLIDE,
    _cone_holds_after_impacts,
    _contact_at,
    _contact_forces,
    _gv_or_one,
    _may_slip_at_rest,
    _modes_interval,
    _no_slip_zero,
    _sample_summaries,
    _slide_rk4,
)

#: Cases integrated side by side by one lane machine (a multiple of the SIMD width).
_LANES = 128


class Lanes(NamedTuple):
    """The state of one lane machine: ``_LANES`` cases side by side.

    ``W`` holds one row of ``_LANES`` float64 values per quantity (one array, rows at constant
    offsets ``row·_LANES``, so that the compiler can prove the SIMD loop's loads and stores
    independent); the integer arrays hold one value per lane.
    """

    W: np.ndarray
    nxt: np.ndarray  #: index in Motions.acc of that sample (one past it after a SIMD round)
    case: np.ndarray  #: the lane's case, −1 for none
    base: np.ndarray  #: index in Motions.acc of the case's first sample
    state: np.ndarray  #: _REST, _ROCKING or _OVERTURNED


class Friction(NamedTuple):
    """The contact checks of a lane machine whose cases' blocks have friction (issue 45; the
    checks and their margins: :mod:`rocking.dynamics.batch_modes`).  The kernels take None
    instead for blocks without friction, and then compile to the lane machine without checks.
    Its first fields are those of :class:`~rocking.dynamics.batch_records.Contacts`, per block
    (a record within a record does not reach a parallel kernel)."""

    R: np.ndarray
    rg2: np.ndarray
    mu_s: np.ndarray
    mu_k: np.ndarray
    e_ratio: np.ndarray
    impact_ok: np.ndarray
    cone: float  #: 1 − the friction cone's margin [-]: abs(F) ≤ μ_s·cone·N is accepted
    n_min: float  #: the least normal force per unit mass accepted [m/s²]


# Rows of the lane table W.  The SIMD loop (:func:`_lane_steps`) stores every row it changes
# unconditionally: the step's end state in the state rows (TH, OM, U0, G0, TAU) and the state
# it started from in the S rows, which the event handling of a lane whose step was not plain
# reads (a row stored only where the step is plain would compile to masked stores, slow on many
# processors).
_TH = 0  # θ [rad] at the start of the lane's interval; after a SIMD round, the RK4 step's θ
_OM = 1  # θ' [rad/s] likewise
_SG = 2  # pivot side s = ±1
_RK = 3  # 1.0 if rocking, 0.0 if at rest or locating an impact (the step cannot be plain)
_U0 = 4  # u = a_g/g at the start of the interval; after a SIMD round, u at its end
_G0 = 5  # vertical factor gv = 1 + a_v/g likewise (with a_v only)
_TAU = 6  # local time [s] from which the interval is still to be integrated (0 but after events)
_THS = 7  # the state from which the SIMD round's step started: θ, θ', u, gv, tau
_OMS = 8
_U0S = 9
_G0S = 10
_TAUS = 11
_VAL = 12  # 1.0 if the SIMD round's step is _rk4's step (fast trigonometry valid)
_PL = 13  # 1.0 if it is plain: all that happens in the interval (_plain_step)
_PK = 14  # max abs(θ) so far [rad]
_TST = 15  # _advance_events' t_start and false_side in this interval
_FS = 16
_NR = 17  # intervals of the case spent at rest throughout, so far (step counting)
_R0 = 18  # 1.0 if the lane's current interval started at rest (step counting)
_SC = 19  # the case's constants: scale factor, p² [1/s²], sin α, cos α, overturning angle [rad]
_P2 = 20
_SA = 21
_CA = 22
_OV = 23
# Rows passed from one SIMD loop of a round to the next (see _lane_steps): sin θ, cos θ, du/dt
# [1/s]; the step's length h [s], _stage_terms (θ''_1 [rad/s²], brackets Pm, Qm, Pb, Qb), the
# bound of _no_touch [rad/s²]; θ''_2, θ''_3 [rad/s²] and max(abs(δ_2), abs(δ_3)) [rad].
_ST = 24
_CT = 25
_DU = 26
_H = 27
_K1 = 28
_PM = 29
_QM = 30
_PB = 31
_QB = 32
_AM = 33
_K2 = 34
_K3 = 35
_D23 = 36
_A1 = 37  # the samples that end the lanes' intervals (_gather): a_g [m/s²], a_v [m/s²]
_AV1 = 38
# A lane locating an impact (:func:`_attend`): the partial step length of its next SIMD round
# [s] (0: none, the step to the interval's end), the bracket of _newton [s] and the Newton
# corrections made so far.
_HL = 39
_LO = 40
_HI = 41
_NI = 42
# The step's end from the fourth SIMD loop to the fifth: θ_1 [rad], θ'_1 [rad/s], max abs(δ) [rad].
_TH1 = 43
_OM1 = 44
_DMX = 45
_ROWS = 46
# With friction only (the table has _ROWS rows without): 1.0 if the checks of the interval that
# ended at the lane's sample failed (it is done again by _modes_interval); the case's
# μ_s·(1 − margin) [-] and R [m] (:class:`Friction`); 1.0 if an impact of the
# lane's interval failed the checks of impacts (which fails the interval if it ends rocking);
# 1.0 if the interval that ends at the lane's next sample is to be checked (it ends in the
# rocking path, rocking); the state the lane's interval started from (θ [rad], θ' [rad/s], s,
# 1.0 if rocking); the rest of modes_case's state (σ, q [m], q' [m/s], y [m], y' [m/s]) and
# running summaries (max abs(slip) [m], max lift [m], uplift (1.0), slip at the last sample [m]).
_FL = 46
_MU = 47
_RR = 48
_PD = 49
_CK = 50
_ITH = 51
_IOM = 52
_ISG = 53
_IRK = 54
_SIG = 55
_Q = 56
_V = 57
_Y = 58
_VY = 59
_PSL = 60
_PLF = 61
_UP = 62
_SL = 63
# 1.0 if the lane slides in the SIMD loop (:func:`_slide_steps`), the case's μ_k [-], 1.0 if the
# round's slide step is all that modes_case does in the interval.
_SLD = 64
_MK = 65
_SOK = 66
_ROWS_FRICTION = 67


@borrowing_kernel
def _lane_steps(lanes, n, motions, g, vert, fric):
    """One sample interval of lanes 0 … n−1 (SIMD loops): the RK4 step from each lane's state
    (:func:`rocking.dynamics.equation._plain_step`), kept where it is all that happens in the
    interval; every lane's ``nxt`` advances by one.

    The step is computed in five loops over the lanes, through rows of W: (1) the ground
    motion's change and sin θ, cos θ; (2) the stages' brackets and the bound of
    :func:`~rocking.dynamics.equation._no_touch` (:func:`~rocking.dynamics.equation._plain_terms`);
    (3) stages 2 and 3; (4) stage 4 and the step; (5) its tests and the lanes' masks.  With
    friction (``fric`` not None), loop (1) also checks the contact conditions of every lane that
    rocks at the state it starts from (:func:`_check_contact`), and a lane whose case failed a
    check needs attention.  The same
    operations on the same values as one loop, but the dependency chain of a lane's step, about
    110 cycles, is cut into five short ones, which the processor overlaps across lanes: one loop
    of the whole step is longer than its reorder window (Zen 3: 20 % less time per step with four
    loops than with one, 4–6 % less with five than with four; loops 1 and 2 in one: 4 % more).

    Returns the lanes that need attention (the step is not plain, or the motion has ended) as bit
    masks: lanes 0 … 63, lanes 64 … 127.
    """
    L = _LANES
    W = lanes.W
    nxt = lanes.nxt
    base = lanes.base
    dt = motions.dt
    n_t = motions.n_t
    sliding = False
    for j in range(n):  # what depends on the samples and θ only
        u0 = W[_U0 * L + j]
        sc = W[_SC * L + j]
        u1 = sc * W[_A1 * L + j] / g  # as simulate(block, scale * acc, dt)
        g0 = _vertical_row(vert, W, _G0 * L + j)
        g1 = _vertical_end(vert, W, _AV1 * L + j, sc, g)  # as simulate(..., av=abs(scale) * av)
        st, ct = _sincos(W[_TH * L + j])
        W[_ST * L + j] = st
        W[_CT * L + j] = ct
        W[_DU * L + j] = (u1 - u0) / dt
        W[_U0S * L + j] = u0
        W[_TAUS * L + j] = W[_TAU * L + j]
        at_sample = W[_TAUS * L + j] == 0.0
        _check_contact(fric, W, j, st, ct, u0, g0, at_sample, g, lanes.state[j] == _ROCKING)
        W[_U0 * L + j] = u1
        W[_TAU * L + j] = 0.0
        _store_vertical(vert, W, j, g0, g1)
        sliding |= _slides(fric, W, j)
    for j in range(n):
        u0 = W[_U0S * L + j]
        tau = W[_TAUS * L + j]
        du = W[_DU * L + j]
        hl = W[_HL * L + j]
        h = hl if hl > 0.0 else dt - tau  # hl: a partial step locating an impact
        g0 = _vertical_row(vert, W, _G0S * L + j)
        dg = _gv_slope(g0, _vertical_row(vert, W, _G0 * L + j), dt)
        k1w, Pm, Qm, Pb, Qb, amax = _plain_terms(
            W[_ST * L + j],
            W[_CT * L + j],
            W[_SG * L + j],
            u0,
            du,
            g0,
            dg,
            tau,
            h,
            W[_P2 * L + j],
            W[_SA * L + j],
            W[_CA * L + j],
        )
        W[_K1 * L + j] = k1w
        W[_PM * L + j] = Pm
        W[_QM * L + j] = Qm
        W[_PB * L + j] = Pb
        W[_QB * L + j] = Qb
        W[_AM * L + j] = amax
        W[_H * L + j] = h
    for j in range(n):
        k2w, k3w, d23 = _rk4_middle(
            W[_OM * L + j],
            W[_K1 * L + j],
            W[_PM * L + j],
            W[_QM * L + j],
            W[_H * L + j],
            W[_P2 * L + j],
        )
        W[_K2 * L + j] = k2w
        W[_K3 * L + j] = k3w
        W[_D23 * L + j] = d23
    for j in range(n):
        th1, om1, dmax = _rk4_end(
            W[_TH * L + j],
            W[_OM * L + j],
            W[_K1 * L + j],
            W[_K2 * L + j],
            W[_K3 * L + j],
            W[_D23 * L + j],
            W[_PB * L + j],
            W[_QB * L + j],
            W[_H * L + j],
            W[_P2 * L + j],
        )
        W[_TH1 * L + j] = th1
        W[_OM1 * L + j] = om1
        W[_DMX * L + j] = dmax
    if sliding:  # (never without friction)
        _slide_steps(fric, W, n, dt, g, vert)
    low = np.uint64(0)
    high = np.uint64(0)
    for j in range(n):
        theta = W[_TH * L + j]
        omega = W[_OM * L + j]
        th1 = W[_TH1 * L + j]
        valid, plain = _plain_tests(
            theta,
            omega,
            W[_SG * L + j],
            th1,
            W[_DMX * L + j],
            W[_AM * L + j],
            W[_H * L + j],
            W[_OV * L + j],
        )
        plain = plain & (W[_RK * L + j] != 0.0)
        W[_THS * L + j] = theta
        W[_OMS * L + j] = omega
        W[_TH * L + j] = _rocking_or(fric, W, j, th1, theta)
        W[_OM * L + j] = _rocking_or(fric, W, j, W[_OM1 * L + j], omega)
        W[_PK * L + j] = maxnum(W[_PK * L + j], abs(th1) if plain & (fric is None) else 0.0)
        _to_check(fric, W, j, plain)
        plain = plain | _slid(fric, W, j)
        W[_VAL * L + j] = 1.0 if valid else 0.0
        W[_PL * L + j] = 1.0 if plain else 0.0
        k1 = nxt[j] + 1
        nxt[j] = k1
        att = (not plain) | (k1 >= base[j] + n_t) | _failed(fric, W, j)  # an event, the end
        bit = np.uint64(1 if att else 0) << np.uint64(j & 63)
        low |= bit if j < 64 else np.uint64(0)
        high |= np.uint64(0) if j < 64 else bit
    return low, high


@kernel(inline="always")
def _check_contact(fric, W, j, st, ct, u, gv, at_sample, g, rocking):
    """With friction, where lane j's state is that of a sample (``at_sample``: its interval
    starts there) reached rocking (row RK) by an interval to be checked (row CK), mark that
    interval failed (row FL) if the contact conditions fail there with their margins
    (:class:`Friction`), N ≥ n_min and abs(F) ≤ μ_s·(1 − margin)·N, or an impact of that
    interval failed its checks (row PD); F and N of
    :func:`rocking.dynamics.modes._contact_forces` at θ (``st``, ``ct``: its sine and cosine),
    θ' and side s of the lane's rows, u and gv (None: 1) of the sample.  Where it holds, the
    sample is modes_case's: its summaries (max abs(θ), uplift) take it, and it is the start of
    the new interval (rows ITH, IOM, ISG, and IRK: ``rocking``, the lane's state; no impact
    yet).  Nothing without friction (``fric`` None)."""
    if fric is None:
        return
    L = _LANES
    th = W[_TH * L + j]
    S, C = _angle_terms(st, ct, W[_SG * L + j], W[_SA * L + j], W[_CA * L + j])
    om = W[_OM * L + j]
    F, N = _contact_forces(S, C, om, u, _gv_or_one(gv), W[_P2 * L + j], g, W[_RR * L + j])
    bad = (fric.n_min > N) | (abs(F) > W[_MU * L + j] * N) | (W[_PD * L + j] != 0.0)
    fail = bad & at_sample & (W[_RK * L + j] != 0.0) & (W[_CK * L + j] != 0.0)
    ok = at_sample & (not fail)
    W[_FL * L + j] = 1.0 if fail else 0.0
    W[_PD * L + j] = 0.0 if at_sample else W[_PD * L + j]
    W[_PK * L + j] = maxnum(W[_PK * L + j], abs(th) if ok else 0.0)
    W[_UP * L + j] = 1.0 if ok & (th != 0.0) else W[_UP * L + j]
    W[_ITH * L + j] = th if ok else W[_ITH * L + j]
    W[_IOM * L + j] = om if ok else W[_IOM * L + j]
    W[_ISG * L + j] = W[_SG * L + j] if ok else W[_ISG * L + j]
    W[_IRK * L + j] = (1.0 if rocking else 0.0) if ok else W[_IRK * L + j]


@kernel(inline="always")
def _slide_steps(fric, W, n, dt, g, vert):
    """With friction, the slide step of lanes 0 … n−1 (a SIMD loop; nothing without friction):
    :func:`rocking.dynamics.modes._slide_rk4` over the interval from each lane's q, q', σ (rows
    Q, V, SIG) and the round's u, gv (rows U0S, DU, G0S, G0), kept (rows Q, V and the
    summaries of slip PSL, SL; row SOK) where the lane slides (row SLD) and the step is all
    that modes_case does in the interval: no event at its end (σ·q' > 0, gv ≥ 0) and no zero of
    the slip velocity inside (:func:`rocking.dynamics.modes._no_slip_zero`, the test of
    :func:`~rocking.dynamics.modes._slip_dip`); modes_case's state is otherwise unchanged
    (θ and y at rest).  A lane only slides here where μ_k ≤ tan α (:func:`_modes_run`)."""
    if fric is None:
        return
    L = _LANES
    for j in range(n):
        tau = W[_TAUS * L + j]
        h = dt - tau
        g0 = _gv_or_one(_vertical_row(vert, W, _G0S * L + j))
        dg = (_gv_or_one(_vertical_row(vert, W, _G0 * L + j)) - g0) / dt
        q = W[_Q * L + j]
        v = W[_V * L + j]
        sig = W[_SIG * L + j]
        end, a0, a1 = _slide_rk4(
            0.0,
            0.0,
            q,
            v,
            0.0,
            0.0,
            sig,
            W[_U0S * L + j],
            W[_DU * L + j],
            g0,
            dg,
            tau,
            h,
            g,
            W[_MK * L + j],
        )
        q1 = end[2]
        v1 = end[3]
        ok = (
            (W[_SLD * L + j] != 0.0)
            & _no_slip_zero(sig * v, sig * a0 * h, sig * v1, sig * a1 * h)
            & (g0 + dg * dt >= 0.0)
        )
        W[_SOK * L + j] = 1.0 if ok else 0.0
        W[_Q * L + j] = q1 if ok else q
        W[_V * L + j] = v1 if ok else v
        W[_PSL * L + j] = maxnum(W[_PSL * L + j], abs(q1) if ok else 0.0)
        W[_SL * L + j] = q1 if ok else W[_SL * L + j]


@kernel(inline="always")
def _rocking_or(fric, W, j, x, at_rest):
    """``x`` (the rocking step's), or with friction ``at_rest`` where lane j slides."""
    if fric is None:
        return x
    return at_rest if W[_SLD * _LANES + j] != 0.0 else x


@kernel(inline="always")
def _slides(fric, W, j):
    """Whether lane j slides in the SIMD loop (row SLD; False without friction)."""
    if fric is None:
        return False
    return W[_SLD * _LANES + j] != 0.0


@kernel(inline="always")
def _slid(fric, W, j):
    """Whether lane j slides and its slide step is kept (rows SLD, SOK: the slide loop of a round
    without sliding lanes does not run; False without friction)."""
    if fric is None:
        return False
    return (W[_SLD * _LANES + j] != 0.0) & (W[_SOK * _LANES + j] != 0.0)


@kernel(inline="always")
def _to_check(fric, W, j, plain):
    """With friction, a plain step (it ends lane j's interval rocking) is to be checked at the
    sample it reaches (row CK); nothing without friction."""
    if fric is not None:
        W[_CK * _LANES + j] = 1.0 if plain else W[_CK * _LANES + j]


@kernel(inline="always")
def _check_impacts(fric, W, j, n_imp, iv, body, b, g):
    """With friction, after ``n_imp`` > 0 impacts in lane j's interval ``iv`` (block b, ``body``,
    g [m/s²]): row PD if modes_case's checks of the impacts of a rocking step fail: their
    impulse in the friction cone (``impact_ok``), and the contact right after them,
    :func:`rocking.dynamics.modes._cone_holds_after_impacts` (the same function of the same
    values: θ' at the interval's start, u and gv (None: 1) at its ends); the interval then
    fails if it ends rocking (:func:`_check_contact`), and is done again by
    :func:`~rocking.dynamics.modes._modes_interval`.  Nothing without friction (``fric``
    None)."""
    if fric is None:
        return
    if n_imp > 0:
        c = _contact_at(fric, b, g)
        g0 = _gv_or_one(iv.g0)
        g1 = _gv_or_one(iv.g1)
        om0 = W[_IOM * _LANES + j]
        if not (
            c.impact_ok and _cone_holds_after_impacts(om0, iv.u0, iv.u1, g0, g1, iv.dt, body, c)
        ):
            W[_PD * _LANES + j] = 1.0


@kernel(inline="always")
def _failed(fric, W, j):
    """Whether the interval that ended at lane j's sample failed its contact checks (False
    without friction)."""
    if fric is None:
        return False
    return W[_FL * _LANES + j] != 0.0


@kernel(inline="always")
def _rows(fric):
    """The rows of a lane machine's table W: with friction, those of the contact checks too."""
    if fric is None:
        return _ROWS
    return _ROWS_FRICTION


@kernel(inline="always")
def _vertical_row(vert, W, r):
    """W[r] with vertical motion, None without."""
    if vert is None:
        return None
    return W[r]


@kernel(inline="always")
def _vertical_end(vert, W, r, sc, g):
    """gv at the end of a lane's interval (:func:`_gv_sample` of its gathered sample W[r]), or
    None without vertical motion."""
    if vert is None:
        return None
    return _gv_sample(W, r, sc, g)


@kernel(inline="always")
def _store_vertical(vert, W, j, g0, g1):
    """The SIMD round's gv rows of lane j (nothing without vertical motion)."""
    if vert is None:
        return
    W[_G0S * _LANES + j] = g0
    W[_G0 * _LANES + j] = g1


@kernel(inline="always")
def _gather(lanes, n, motions, vert):
    """The samples that end lanes 0 … n−1's intervals into rows _A1 (acc[nxt[j]] [m/s²]) and _AV1
    (av likewise), as an unsigned index: no test for negative ones."""
    for j in range(n):
        lanes.W[_A1 * _LANES + j] = motions.acc[np.uint64(lanes.nxt[j])]
    if vert is not None:
        for j in range(n):
            lanes.W[_AV1 * _LANES + j] = vert.av[np.uint64(lanes.nxt[j])]


@kernel(inline="always")
def _row_or_none(vert, x):
    """x with vertical motion, None without."""
    if vert is None:
        return None
    return x


@borrowing_kernel
def _start_case(lanes, j, i, motions, vert, fric, blocks, cases):
    """Put case i in lane j at the first interval in which its block may lift; False (lane left
    as it was) if it never lifts: then it stays at rest throughout (its result: not overturned,
    peak 0, no steps)."""
    L = _LANES
    W = lanes.W
    b = cases.body[i]
    m = cases.motion[i]
    sc = cases.scale[i]
    g = blocks.g
    # gv ≥ 1 + abs(sc)·min a_v/g throughout the motion (conservative: it may lift only if ...)
    mu_s = _mu_of(fric, b)
    if not _may_move(motions.amax[m], _avmin(vert), m, sc, g, blocks.sa[b], blocks.ca[b], mu_s):
        return False  # no need to look at the samples
    first = m * motions.n_t
    k, u0, g0 = _rest_until_uplift(
        motions,
        vert,
        first,
        0,
        sc * motions.acc[first] / g,
        _gv_sample(_av(vert), first, sc, g),
        sc,
        g,
        blocks.sa[b],
        blocks.ca[b],
        mu_s,
    )
    if k >= motions.n_t - 1:
        return False
    lanes.base[j] = first
    lanes.nxt[j] = first + k + 1
    lanes.state[j] = _REST
    lanes.case[j] = i
    W[_TH * L + j] = 0.0
    W[_OM * L + j] = 0.0
    W[_SG * L + j] = 1.0
    W[_RK * L + j] = 0.0
    W[_HL * L + j] = 0.0
    W[_U0 * L + j] = u0
    W[_TAU * L + j] = 0.0
    W[_PK * L + j] = 0.0
    W[_TST * L + j] = -1.0
    W[_FS * L + j] = 0.0
    W[_NR * L + j] = k
    W[_SC * L + j] = sc
    W[_P2 * L + j] = blocks.p2[b]
    W[_SA * L + j] = blocks.sa[b]
    W[_CA * L + j] = blocks.ca[b]
    W[_OV * L + j] = blocks.th_ov[b]
    _set_vertical(vert, W, _G0 * L + j, g0)
    if fric is not None:  # modes_case's state at rest, its summaries
        W[_MU * L + j] = fric.mu_s[b] * fric.cone
        W[_RR * L + j] = fric.R[b]
        W[_MK * L + j] = fric.mu_k[b]
        for r in (_FL, _PD, _CK, _SIG, _Q, _V, _Y, _VY, _PSL, _PLF, _UP, _SL, _SLD, _SOK):
            W[r * L + j] = 0.0
    return True


@kernel(inline="always")
def _mu_of(fric, b):
    """Block b's μ_s [-], or None without friction."""
    if fric is None:
        return None
    return fric.mu_s[b]


@kernel(inline="always")
def _set_vertical(vert, W, r, x):
    """W[r] = x with vertical motion (nothing without)."""
    if vert is not None:
        W[r] = x


@kernel(inline="always")
def _av(vert):
    """The vertical accelerations end to end, or None."""
    if vert is None:
        return None
    return vert.av


@kernel(inline="always")
def _avmin(vert):
    """The least vertical acceleration of each motion, or None."""
    if vert is None:
        return None
    return vert.avmin


@kernel(inline="always")
def _avsuf(vert):
    """The suffix minima of the vertical accelerations, or None."""
    if vert is None:
        return None
    return vert.avsuf


@kernel(inline="always")
def _attend(lanes, j, motions, vert, fric, blocks, cases, located):
    """Lane j after a SIMD round in which it needs attention (see :func:`_lane_steps`): the
    events of its interval (:func:`rocking.dynamics.impacts._advance_events`, exactly as
    :func:`rocking.simulate` handles them), the intervals at rest that follow, or the end of its
    motion.

    With friction (``fric``), an interval whose checks failed is done again by
    :func:`~rocking.dynamics.modes._modes_interval` (:func:`_redo`), and so is every interval
    that the rocking path does not take (:func:`_modes_run`): where the base may slip at rest,
    and in slide, slide-rock and flight.

    Returns (done, overturned, k): whether the case has ended, whether by overturning, and the
    intervals integrated or skipped so far (the interval in which it ended counts).
    """
    L = _LANES
    W = lanes.W
    n_t = motions.n_t
    dt = motions.dt
    b = cases.body[lanes.case[j]]
    if _failed(fric, W, j):  # the interval before this round's, from its start
        return _redo(
            lanes, j, lanes.nxt[j] - lanes.base[j] - 3, motions, vert, fric, blocks, b, located
        )
    if W[_PL * L + j] != 0.0:  # a plain step that ended the motion
        if fric is not None:
            return _end_check(lanes, j, motions, vert, fric, blocks, b, located)
        return True, False, lanes.nxt[j] - lanes.base[j] - 1
    k = lanes.nxt[j] - lanes.base[j] - 2  # the interval: from sample k to k + 1
    if fric is not None and W[_SLD * L + j] != 0.0:  # sliding, not only the slide step
        return _modes_run(lanes, j, k, SLIDE, True, motions, vert, fric, blocks, b, located)
    state = lanes.state[j]
    if W[_TAUS * L + j] == 0.0:  # a new interval (step counting)
        W[_R0 * L + j] = 1.0 if state == _REST else 0.0
    u0 = W[_U0S * L + j]
    u1 = W[_U0 * L + j]
    g0 = _row_or_none(vert, W[_G0S * L + j])
    g1 = _row_or_none(vert, W[_G0 * L + j])
    if (
        fric is not None
        and state == _REST
        and W[_TAUS * L + j] == 0.0
        and (_may_slip_at_rest(u0, g0, fric.mu_s[b]) or _may_slip_at_rest(u1, g1, fric.mu_s[b]))
    ):  # the base may slip: modes_case's general integrator, from the round's start
        W[_TH * L + j] = W[_THS * L + j]
        W[_OM * L + j] = W[_OMS * L + j]
        return _modes_run(lanes, j, k, REST, True, motions, vert, fric, blocks, b, located)
    iv = Interval(u0, u1, g0, g1, dt)
    body = Body(
        W[_P2 * L + j],
        W[_SA * L + j],
        W[_CA * L + j],
        blocks.tan_a[b],
        blocks.e[b],
        W[_OV * L + j],
    )
    sw = Swing(
        W[_THS * L + j],
        W[_OMS * L + j],
        W[_SG * L + j],
        state,
        W[_TAUS * L + j],
        W[_TST * L + j],
        W[_FS * L + j],
    )
    if W[_HL * L + j] > 0.0:  # locating an impact: the round computed a partial step
        found, sw, deferred, n_imp = _lane_impact(W, j, sw, iv, body, located)
        if not found:  # the next partial step in the next round
            _repeat_interval(lanes, j, vert)
            return False, False, k
    elif _crosses(W, j, sw, dt, located):
        _start_locating(W, j, sw, iv)
        _repeat_interval(lanes, j, vert)
        return False, False, k
    else:
        sw, n_imp, _te, deferred = _advance_events(
            sw,
            iv,
            body,
            W[_TH * L + j],
            W[_OM * L + j],
            (state == _ROCKING) & (W[_VAL * L + j] != 0.0),
            True,
            located,
        )
    _check_impacts(fric, W, j, n_imp, iv, body, b, blocks.g)
    W[_TH * L + j] = sw.theta
    W[_OM * L + j] = sw.omega
    W[_SG * L + j] = sw.s
    lanes.state[j] = sw.state
    if deferred:  # the rest of the interval, from tau, in the next SIMD round
        W[_RK * L + j] = 1.0
        W[_TAU * L + j] = sw.tau
        W[_TST * L + j] = sw.t_start
        W[_FS * L + j] = sw.false_side
        W[_U0 * L + j] = u0
        _set_vertical(vert, W, _G0 * L + j, g0)
        lanes.nxt[j] -= 1
        return False, False, k
    W[_TST * L + j] = -1.0
    W[_FS * L + j] = 0.0
    k += 1
    if sw.state == _OVERTURNED:
        return True, True, k
    if fric is None:  # with friction: once the checks at the sample hold (_check_contact)
        W[_PK * L + j] = maxnum(W[_PK * L + j], abs(sw.theta))
    if sw.state == _REST:
        if W[_R0 * L + j] != 0.0:  # at rest throughout
            W[_NR * L + j] += 1.0
        if fric is not None:
            return _modes_run(lanes, j, k, REST, False, motions, vert, fric, blocks, b, located)
        k0 = k
        sc = W[_SC * L + j]
        k, u1, g1 = _rest_until_uplift(
            motions,
            vert,
            lanes.base[j],
            k,
            u1,
            g1,
            sc,
            blocks.g,
            W[_SA * L + j],
            W[_CA * L + j],
            None,
        )
        W[_NR * L + j] += k - k0
        W[_U0 * L + j] = u1
        _set_vertical(vert, W, _G0 * L + j, g1)
    W[_RK * L + j] = 1.0 if sw.state == _ROCKING else 0.0
    lanes.nxt[j] = lanes.base[j] + k + 1
    if fric is not None:  # rocking: the checks at the sample it ends at
        W[_CK * L + j] = 1.0
        if k >= n_t - 1:
            return _end_check(lanes, j, motions, vert, fric, blocks, b, located)
    return k >= n_t - 1, False, k


@kernel(inline="always")
def _end_check(lanes, j, motions, vert, fric, blocks, b, located):
    """Lane j's case (block b, with friction) at its motion's last sample, reached by an
    interval that ended rocking in the rocking path: its checks there (:func:`_check_contact`);
    where they fail, the interval again (:func:`_redo`).  Returns (done, overturned, k) as
    :func:`_attend`."""
    L = _LANES
    W = lanes.W
    st, ct = _sincos(W[_TH * L + j])
    gv = _row_or_none(vert, W[_G0 * L + j])
    _check_contact(fric, W, j, st, ct, W[_U0 * L + j], gv, True, blocks.g, True)
    if W[_FL * L + j] != 0.0:
        return _redo(lanes, j, motions.n_t - 2, motions, vert, fric, blocks, b, located)
    return True, False, motions.n_t - 1


@kernel(inline="always")
def _redo(lanes, j, k, motions, vert, fric, blocks, b, located):
    """Lane j's interval k (from sample k), whose checks failed, again from its start (rows
    ITH, IOM, ISG, IRK) by :func:`_modes_run`."""
    L = _LANES
    W = lanes.W
    W[_TH * L + j] = W[_ITH * L + j]
    W[_OM * L + j] = W[_IOM * L + j]
    W[_SG * L + j] = W[_ISG * L + j]
    mode = ROCK if W[_IRK * L + j] != 0.0 else REST
    return _modes_run(lanes, j, k, mode, True, motions, vert, fric, blocks, b, located)


@borrowing_kernel
def _modes_run(lanes, j, k, mode, force, motions, vert, fric, blocks, b, located):
    """Lane j's case (block b, with friction) from sample k in ``mode`` (the rest of its state
    in its rows) through :func:`~rocking.dynamics.modes._modes_interval`, modes_case's own
    interval, as long as the rocking path cannot take the interval (``force``: the first one in
    any case): in slide, slide-rock and flight, and at rest where the base may slip; intervals
    at rest where it can neither slip nor lift are skipped (:func:`_rest_until_uplift`).  The
    summaries follow each sample as in modes_case
    (:func:`~rocking.dynamics.modes._sample_summaries`).  Then the lane goes on in the rocking
    path (rock, or rest where the block may lift) from its sample.  Returns (done,
    overturned, k) as :func:`_attend`."""
    L = _LANES
    W = lanes.W
    n_t = motions.n_t
    g = blocks.g
    base = lanes.base[j]
    sc = W[_SC * L + j]
    body = Body(
        W[_P2 * L + j], W[_SA * L + j], W[_CA * L + j], blocks.tan_a[b], blocks.e[b], W[_OV * L + j]
    )
    c = _contact_at(fric, b, g)
    s = W[_SG * L + j]
    sig = W[_SIG * L + j]
    st = (
        W[_TH * L + j],
        W[_OM * L + j],
        W[_Q * L + j],
        W[_V * L + j],
        W[_Y * L + j],
        W[_VY * L + j],
    )
    peak = W[_PK * L + j]
    peak_slip = W[_PSL * L + j]
    peak_lift = W[_PLF * L + j]
    uplift = W[_UP * L + j] != 0.0
    slip = W[_SL * L + j]
    av = _av(vert)
    u0 = sc * motions.acc[base + k] / g  # as the lanes' samples (simulate(block, sc * acc, dt))
    g0 = _gv_sample(av, base + k, sc, g)
    overturned = False
    while k < n_t - 1:
        u1 = sc * motions.acc[base + k + 1] / g
        g1 = _gv_sample(av, base + k + 1, sc, g)
        if not force:
            if mode == ROCK or (mode == SLIDE and c.mu_k <= body.tan_a):
                break  # the SIMD loop's rocking step or slide step
            if mode == REST and not (
                _may_slip_at_rest(u0, g0, c.mu_s) or _may_slip_at_rest(u1, g1, c.mu_s)
            ):
                k0 = k
                k, u0, g0 = _rest_until_uplift(
                    motions, vert, base, k, u0, g0, sc, g, body.sa, body.ca, c.mu_s
                )
                W[_NR * L + j] += k - k0
                if k >= n_t - 1:
                    break
                u1 = sc * motions.acc[base + k + 1] / g
                g1 = _gv_sample(av, base + k + 1, sc, g)
                if not (_may_slip_at_rest(u0, g0, c.mu_s) or _may_slip_at_rest(u1, g1, c.mu_s)):
                    break  # it may lift: the rocking path
        force = False
        mode, s, sig, st, _n, overturned, _tev, _dem = _modes_interval(
            mode, s, sig, st, u0, u1, g0, g1, motions.dt, body, c, located
        )
        peak, peak_slip, peak_lift, uplift, slip, _lift = _sample_summaries(
            mode, st, overturned, peak, peak_slip, peak_lift, uplift, body, c
        )
        k += 1
        u0 = u1
        g0 = g1
        if overturned:
            break
    W[_TH * L + j] = st[0]
    W[_OM * L + j] = st[1]
    W[_Q * L + j] = st[2]
    W[_V * L + j] = st[3]
    W[_Y * L + j] = st[4]
    W[_VY * L + j] = st[5]
    W[_SG * L + j] = s
    W[_SIG * L + j] = sig
    W[_PK * L + j] = peak
    W[_PSL * L + j] = peak_slip
    W[_PLF * L + j] = peak_lift
    W[_UP * L + j] = 1.0 if uplift else 0.0
    W[_SL * L + j] = slip
    W[_FL * L + j] = 0.0
    if overturned:
        return True, True, k
    if k >= n_t - 1:
        return True, False, k
    # the rocking path from sample k: its SIMD round (rock), or its events (rest, may lift);
    # or the SIMD loop's slide step
    W[_RK * L + j] = 1.0 if mode == ROCK else 0.0
    W[_SLD * L + j] = 1.0 if mode == SLIDE else 0.0
    lanes.state[j] = _ROCKING if mode == ROCK else _REST
    W[_U0 * L + j] = u0
    _set_vertical(vert, W, _G0 * L + j, g0)
    W[_TAU * L + j] = 0.0
    W[_TST * L + j] = -1.0
    W[_FS * L + j] = 0.0
    W[_HL * L + j] = 0.0
    W[_CK * L + j] = 0.0  # modes_case's own sample: no check
    lanes.nxt[j] = base + k + 1
    return False, False, k


@kernel(inline="always")
def _crosses(W, j, sw, dt, located):
    """Whether lane j's SIMD step ``sw`` → (θ, θ') of its rows TH, OM is an RK4 step that ends on
    the other side of θ = 0, so that :func:`~rocking.dynamics.impacts._advance_events` would
    begin by locating that impact (:func:`~rocking.dynamics.impacts._locate` on the bracket
    (0, dt − tau)): the kernel then locates it in the lane (:func:`_start_locating`)."""
    L = _LANES
    return (
        located
        & (sw.state == _ROCKING)
        & (W[_VAL * L + j] != 0.0)
        & (dt - sw.tau > 0.0)
        & _ends_across(sw.s, W[_TH * L + j], W[_OM * L + j])
    )


@kernel(inline="always")
def _start_locating(W, j, sw, iv):
    """Lane j locates the impact of its SIMD step (:func:`_crosses`) in the next rounds: each
    computes the partial RK4 step of length W[_HL] from ``sw`` (the SIMD loop: the same
    operations as :func:`~rocking.dynamics.impacts._locate`'s scalar ones, sin θ and cos θ of
    the round in rows ST, CT), and :func:`_lane_impact` makes the Newton correction."""
    L = _LANES
    h = iv.dt - sw.tau
    du, dg = _slopes(iv)
    W[_HL * L + j] = _locate_start(
        sw.theta,
        W[_ST * L + j],
        W[_CT * L + j],
        sw.omega,
        sw.s,
        iv.u0,
        du,
        iv.g0,
        dg,
        sw.tau,
        0.0,
        h,
        sw.theta,
        W[_TH * L + j],
        0.0,
        -sw.s,
        W[_P2 * L + j],
        W[_SA * L + j],
        W[_CA * L + j],
    )
    W[_LO * L + j] = 0.0
    W[_HI * L + j] = h
    W[_NI * L + j] = 0.0
    W[_RK * L + j] = 0.0  # never plain


@kernel(inline="always")
def _lane_impact(W, j, sw, iv, body, located):
    """The Newton correction of lane j's impact location after the round's partial step
    (:func:`~rocking.dynamics.impacts._newton`, as in
    :func:`~rocking.dynamics.impacts._locate`).  Returns (found, swing, deferred, impacts): when
    found, the impact and the rest of the interval as
    :func:`~rocking.dynamics.impacts._advance_events` goes on after it (``deferred`` as it returns
    it; the impacts counted); else W[_HL] is the next length to try."""
    L = _LANES
    dt = iv.dt
    du, dg = _slopes(iv)
    s = sw.s
    h = W[_HL * L + j]
    th = W[_TH * L + j]
    om = W[_OM * L + j]
    if W[_VAL * L + j] == 0.0:  # the fast step is not valid: _rk4_sc's other branch
        th, om = _rk4_stages(
            sw.theta, sw.omega, s, iv.u0, du, iv.g0, dg, sw.tau, h, body.p2, body.sa, body.ca
        )
    ni = W[_NI * L + j]
    if ni < _NEWTON_MAX:
        found, h, lo, hi, th, om = _newton(
            th,
            om,
            h,
            W[_LO * L + j],
            W[_HI * L + j],
            0.0,
            -s,
            s,
            iv.u0,
            du,
            iv.g0,
            dg,
            sw.tau,
            body.p2,
            body.sa,
            body.ca,
        )
        W[_LO * L + j] = lo
        W[_HI * L + j] = hi
        W[_NI * L + j] = ni + 1.0
        if not found:
            W[_HL * L + j] = h
            return False, sw, False, 0
    W[_HL * L + j] = 0.0
    arrived = Swing(sw.theta, sw.omega, s, sw.state, sw.tau + h, sw.t_start, sw.false_side)
    sw, n = _impact(arrived, om, iv, du, dg, body)
    if sw.state == _ROCKING:  # what _advance_events does after it (here without a call)
        return True, sw, dt - sw.tau > 0.0, n
    sw, n2, _te, deferred = _advance_events(sw, iv, body, 0.0, 0.0, False, True, located)
    return True, sw, deferred, n + n2


@kernel(inline="always")
def _repeat_interval(lanes, j, vert):
    """Lane j back at the state its SIMD round started from, to integrate from it again."""
    L = _LANES
    W = lanes.W
    W[_TH * L + j] = W[_THS * L + j]
    W[_OM * L + j] = W[_OMS * L + j]
    W[_U0 * L + j] = W[_U0S * L + j]
    W[_TAU * L + j] = W[_TAUS * L + j]
    _set_vertical(vert, W, _G0 * L + j, _row_or_none(vert, W[_G0S * L + j]))
    lanes.nxt[j] -= 1


@kernel(inline="always")
def _no_slip(out, i):
    """Case i's slip and lift: none, with infinite friction (the block rocks on a corner that
    stays on the ground)."""
    out.peak_slip[i] = 0.0
    out.residual_slip[i] = 0.0
    out.peak_lift[i] = 0.0


@kernel(inline="always")
def _finish(lanes, j, overturned, k, motions, vert, fric, blocks, cases, out):
    """The results of lane j's case, which ended after k intervals (overturned or not); with
    friction, modes_case's summaries (rows UP, PSL, SL, PLF)."""
    L = _LANES
    i = lanes.case[j]
    W = lanes.W
    steps = k - int(W[_NR * L + j])  # k intervals, up to overturning or to the end
    out.overturned[i] = overturned
    alpha = blocks.alpha[cases.body[i]]
    out.peak_theta_ratio[i] = (W[_OV * L + j] if overturned else W[_PK * L + j]) / alpha
    if fric is None:
        out.uplift[i] = steps > 0  # an interval not at rest throughout: rocking at its end
        _no_slip(out, i)
    else:
        out.uplift[i] = overturned or W[_UP * L + j] != 0.0
        out.peak_slip[i] = W[_PSL * L + j]
        out.residual_slip[i] = abs(W[_SL * L + j])
        out.peak_lift[i] = W[_PLF * L + j]
    out.steps[i] = steps


@kernel(inline="always")
def _fill(lanes, j, queue, motions, vert, fric, blocks, cases, out):
    """Start in lane j the next case of the shared queue (positions in ``cases.order``, taken
    with :func:`~rocking.core.compile.fetch_add` on ``queue``) that lifts its block (those that
    don't get their result at once); lanes.case[j] = −1 if none is left."""
    lanes.case[j] = -1
    n = cases.order.size
    while True:
        pos = fetch_add(queue, 1)
        if pos >= n:
            return
        i = cases.order[pos]
        if _start_case(lanes, j, i, motions, vert, fric, blocks, cases):
            return
        out.overturned[i] = False
        out.peak_theta_ratio[i] = 0.0
        out.uplift[i] = False
        _no_slip(out, i)
        out.steps[i] = 0


@kernel(inline="always")
def _move_lane(lanes, src, dst, fric):
    """Lane ``src``'s case into lane ``dst``; lane ``src`` left empty."""
    L = _LANES
    for r in range(_rows(fric)):
        lanes.W[r * L + dst] = lanes.W[r * L + src]
    lanes.case[dst] = lanes.case[src]
    lanes.base[dst] = lanes.base[src]
    lanes.nxt[dst] = lanes.nxt[src]
    lanes.state[dst] = lanes.state[src]
    lanes.case[src] = -1


@kernel
def _new_lanes(vert, fric):
    """An empty lane machine (its table's rows start cache lines: :func:`aligned_zeros`)."""
    L = _LANES
    return Lanes(
        aligned_zeros(_rows(fric) * L),
        np.zeros(L, np.int64),
        np.full(L, -1, np.int64),
        np.zeros(L, np.int64),
        np.zeros(L, np.int64),
    )


@borrowing_kernel
def _lane_machine(lanes, motions, vert, fric, blocks, cases, out, located, queue, width):
    """Integrate cases taken from the shared ``queue`` (see :func:`_fill`) in the empty lane
    machine ``lanes`` (:func:`_new_lanes`; allocated by the caller: this function is compiled
    without reference counting, :func:`~rocking.core.compile.borrowing_kernel`), at most
    ``width`` (≤ ``_LANES``) at a time, until none is left, and write their results (see the
    module docstring)."""
    live = 0  # lanes 0 … live−1 hold a case
    while live < width:
        _fill(lanes, live, queue, motions, vert, fric, blocks, cases, out)
        if lanes.case[live] < 0:
            break
        live += 1
    while live > 0:
        _gather(lanes, live, motions, vert)
        low, high = _lane_steps(lanes, live, motions, blocks.g, vert, fric)
        # the lanes that need attention, from the highest down: when a case ends, its lane
        # takes the next case, or the last live lane (handled already) moves into it
        while (high | low) != 0:
            if high != 0:
                j = 64 + highest_bit(high)
                high ^= np.uint64(1) << np.uint64(j - 64)
            else:
                j = highest_bit(low)
                low ^= np.uint64(1) << np.uint64(j)
            done, overturned, k = _attend(lanes, j, motions, vert, fric, blocks, cases, located)
            if not done:
                continue
            _finish(lanes, j, overturned, k, motions, vert, fric, blocks, cases, out)
            _fill(lanes, j, queue, motions, vert, fric, blocks, cases, out)
            if lanes.case[j] < 0:  # no case left
                live -= 1
                if j < live:
                    _move_lane(lanes, live, j, fric)


@parallel_kernel
def _suffix_extremes(acc, av, used, asuf, avsuf):
    """Suffix maximum of abs(acc) ``asuf`` and suffix minimum of ``av`` ``avsuf`` (unused when
    ``av`` is None) from each sample to the end of its motion [m/s²], the motions (rows) end to
    end, filled: a block at rest that no later sample can lift is at rest to the end
    (:func:`_rest_until_uplift`).  Only the motions ``used[m]`` are computed (the others'
    values are left as they were: no case reads them)."""
    n_m, n_t = acc.shape
    for m in prange(n_m):
        if not used[m]:
            continue
        top = 0.0
        low = math.inf
        for k in range(n_t - 1, -1, -1):
            top = max(top, abs(acc[m, k]))
            asuf[m * n_t + k] = top
            if av is not None:
                low = min(low, av[m, k])
                avsuf[m * n_t + k] = low


def _suffixes_of(
    acc: np.ndarray, av: np.ndarray | None, used: np.ndarray
) -> tuple[np.ndarray, np.ndarray | None]:
    """:func:`_suffix_extremes` of the motions ``used`` into arrays allocated here by NumPy,
    which asks Linux for huge pages for large arrays (allocated by the kernel, a thousand
    motions' 64 MB took 16,000 page faults, ~0.25 s of system time on a VM, per call)."""
    asuf = np.empty(acc.size)
    avsuf = None if av is None else np.empty(av.size)
    _suffix_extremes(acc, av, used, asuf, np.empty(0) if avsuf is None else avsuf)
    return asuf, avsuf


@kernel(inline="always")
def _may_lift(amax, avmin, i, sc, g, sa, ca):
    """Whether samples whose abs(a_g) is at most ``amax`` [m/s²] and whose vertical acceleration is
    at least ``avmin[i]`` [m/s²] (``avmin`` None: no vertical motion) may lift a block at rest
    under the case's scale ``sc``: :func:`~rocking.dynamics.equation._uplifts` of the extremes.
    It is exactly the test at every such sample or weaker: abs(sc·a)/g rounds monotonically in
    abs(a), 1 + abs(sc)·a_v/g in a_v, and the test is monotone in both (conservative when the
    extremes fall on different samples)."""
    return _uplifts(abs(sc * amax) / g, _gv_sample(avmin, i, sc, g), sa, ca)


@kernel(inline="always")
def _may_move(amax, avmin, i, sc, g, sa, ca, mu_s):
    """Whether samples as in :func:`_may_lift` may lift a block at rest, or, with a friction
    coefficient μ_s (``mu_s`` None: none), make its base slip or fly
    (:func:`~rocking.dynamics.modes._may_slip_at_rest` of the extremes: as conservative, it is
    monotone in both)."""
    if _may_lift(amax, avmin, i, sc, g, sa, ca):
        return True
    return _may_slip_at_rest(abs(sc * amax) / g, _gv_sample(avmin, i, sc, g), mu_s)


@borrowing_kernel
def _rest_until_uplift(motions, vert, base, k, u, gv, sc, g, sa, ca, mu_s):
    """First interval k' ≥ k of a block at rest in which it may lift (u and gv at its start), or,
    with friction μ_s (``mu_s`` None: none), slip or fly, or (n_t − 1, u, gv) if none: the
    intervals skipped are those where _advance leaves it at rest (no uplift at either end; u and
    gv linear in between, abs(u)·cos α − gv·sin α convex), and with friction those that
    modes_case gives to _advance (:func:`~rocking.dynamics.modes._may_slip_at_rest` at neither
    end).  ``base``: index of the motion's first sample in ``motions.acc``; when no sample from k
    on can move the block (:func:`_may_move` of the suffix extremes), it is at rest to the end,
    and the samples are not looked at."""
    n_t = motions.n_t
    flat = motions.acc
    avflat = _av(vert)
    if not _may_move(motions.asuf[base + k], _avsuf(vert), base + k, sc, g, sa, ca, mu_s):
        return n_t - 1, u, gv
    while k < n_t - 1:
        u_next = sc * flat[base + k + 1] / g
        g_next = _gv_sample(avflat, base + k + 1, sc, g)
        if _uplifts(u, gv, sa, ca) or _uplifts(u_next, g_next, sa, ca):
            break
        if _may_slip_at_rest(u, gv, mu_s) or _may_slip_at_rest(u_next, g_next, mu_s):
            break
        u = u_next
        gv = g_next
        k += 1
    return k, u, gv


@parallel_kernel
def _cases_kernel(motions, vert, fric, blocks, cases, out, located, machines):
    """Integrate the cases from rest in ``machines`` lane machines (a thread each), which take
    them in the order ``cases.order`` from one shared queue, and write their :class:`Outcome`;
    the impact scheme ``located`` (bool) as in :func:`rocking.simulate`; ``fric``: the contact
    checks (:class:`Friction`) of blocks with friction, None for blocks without.

    A machine holds at most its share of the cases at a time (all its lanes when there are
    enough for every machine's): otherwise the first machine to start could take every case of
    a call of up to ``_LANES`` cases before the other threads start."""
    queue = np.zeros(1, np.int64)
    width = min(_LANES, -(-cases.order.size // machines))
    for _ in prange(machines):
        _lane_machine(
            _new_lanes(vert, fric), motions, vert, fric, blocks, cases, out, located, queue, width
        )
