"""Impacts, uplift, coming to rest and overturning: one sample interval of a rocking block.

Impact at θ = 0: the pivot switches (s → −s) and θ' ← e·θ' (paper Section 2).  From rest the block
starts to rock only when abs(a_g) > g·tan α, tipping to θ > 0 under a negative ground acceleration;
with a vertical ground acceleration a_v, when abs(a_g) > (g + a_v)·tan α (every "g·tan α" below is
(g + a_v)·tan α then, and the vertical factor gv = 1 + a_v/g is linear in the interval like u;
see :mod:`rocking.dynamics.equation`).

When a Runge–Kutta step (:mod:`rocking.dynamics.equation`) ends on the other side of θ = 0, or
turns round inside the step far enough to touch it, the impact instant is located by safeguarded
Newton iteration on the length of a partial Runge–Kutta step (started from the root of the cubic
Taylor polynomial of θ(t), so that one partial step usually suffices), the impact is applied and
the rest of the step is integrated from the impact.  A bounce whose free flight would last less
than ``ZENO_TIME_FRACTION·dt`` ends the chatter: the block is put at rest (the remaining flights of
the geometric series carry negligible energy), and rocking restarts only if abs(a_g) > g·tan α.  A
chatter whose next flight is shorter than ``CHATTER_FRACTION·dt`` and during which the ground
acceleration stays below g·tan α is summed in closed form instead of being integrated bounce by
bounce (such sequences are about a hundred impacts each): flights of 2·abs(θ')/abs(θ'') at θ = 0
alternating between the pivots under the ground acceleration at its start, θ' × e at every
impact; the block is at rest from the sum of the flights on, if that lies within the time step
and the ground acceleration is still below the uplift level there (u is linear in the step, so it
is below it throughout).  abs(θ) in such a chatter stays below
abs(θ'')·(CHATTER_FRACTION·dt)²/8 (1e-9 rad for the paper's bodies at dt = 1/400 s), so the
bracket of Eq. (1) is sin α ± u·cos α to that relative accuracy.

A second, selectable impact scheme (issue 17; never the default): ``impacts="step-end"``, a
straightforward reading of "fixed-step RK4": when a step ends on the other side of θ = 0, the
block is put at θ = 0 on the other pivot with θ' ← e·θ' (θ' of the step's end), at the step's end;
no impact is located inside the step and no return to θ = 0 inside a step that ends on the same
side is looked for.  Everything else is as in the default ("located"): uplift from rest and
overturning are located, a bounce shorter than the Zeno time ends at rest.

The same compiled functions serve :func:`rocking.simulate` and the batched kernel, so they agree
bit for bit.  Pure compiled functions of scalars; no state.
"""

from __future__ import annotations

import math
from typing import NamedTuple

from ..core.compile import fma, kernel
from ..defaults import IMPACT_SCHEMES
from ..errors import InputError
from .equation import (
    _accel,
    _angle_terms,
    _fast_valid,
    _gv_at,
    _gv_ends,
    _gv_fnms,
    _gv_slope,
    _gv_times,
    _no_touch,
    _plain_step,
    _rk4,
    _rk4_rotated,
    _rk4_sc,
    _sincos_any,
    _u_ends,
    _uplifts,
)

#: A bounce shorter than this fraction of the time step ends an impact sequence (block at rest).
ZENO_TIME_FRACTION = 1e-4
#: An impact sequence (chatter) whose next flight is shorter than this fraction of the time step
#: is summed in closed form (:func:`_chatter_time`) when the block cannot lift off during it.
CHATTER_FRACTION = 1.0 / 64.0
#: Partial-step probes for a return to θ = 0 inside a step that starts near θ = 0.
_N_PROBES = 8
#: Newton corrections of an impact location at most (:func:`_locate`).
_NEWTON_MAX = 100
#: Safety cap on events handled within one time step (impacts, uplifts).
_MAX_EVENTS_PER_STEP = 10_000
# Block state codes
_REST = 0
_ROCKING = 1
_OVERTURNED = 2


def resolve_impacts(impacts: str) -> bool:
    """Whether an impact scheme named by the user (:data:`rocking.defaults.IMPACT_SCHEMES`:
    "located", the default, or "step-end") locates the impacts inside the step."""
    name = impacts.strip().lower() if isinstance(impacts, str) else impacts
    if name not in IMPACT_SCHEMES:
        raise InputError(
            f"impacts must be one of {', '.join(map(repr, IMPACT_SCHEMES))}, got {impacts!r}"
        )
    return name == IMPACT_SCHEMES[0]


@kernel(inline="always")
def _locate(theta, omega, s, u0, du, g0, dg, tau, lo, hi, th_lo, th_hi, target, sgn, p2, sa, ca):
    """Partial step length h in [lo, hi] where the RK4 solution from (theta, omega) hits ``target``.

    ``th_lo``, ``th_hi``: that solution at lo and hi.  With f(h) = sgn·(θ_RK4(h) − target), the
    caller guarantees f(lo) ≤ 0 ≤ f(hi); the root kept is the first one after leaving ``lo``
    (f(lo) = 0 happens when the arc starts at θ = 0, and that trivial root is never returned).

    Newton's method on h (dθ/dh = θ') safeguarded by bisection (:func:`_newton`), from the
    first root of the cubic Taylor polynomial of θ at the start when lo = 0, else from the
    secant (:func:`_locate_start`); at most _NEWTON_MAX corrections.  Returns (h, theta_h,
    omega_h).  The batched kernel runs the same iteration with its partial steps in SIMD lanes.
    """
    st, ct = _sincos_any(theta)
    h = _locate_start(
        theta, st, ct, omega, s, u0, du, g0, dg, tau, lo, hi, th_lo, th_hi, target, sgn, p2, sa, ca
    )
    th, om = _rk4_sc(theta, st, ct, omega, s, u0, du, g0, dg, tau, h, p2, sa, ca)
    for _ in range(_NEWTON_MAX):
        done, h, lo, hi, thn, omn = _newton(
            th, om, h, lo, hi, target, sgn, s, u0, du, g0, dg, tau, p2, sa, ca
        )
        if done:
            return h, thn, omn
        th, om = _rk4_sc(theta, st, ct, omega, s, u0, du, g0, dg, tau, h, p2, sa, ca)
    return h, th, om


@kernel(inline="always")
def _locate_start(
    theta, st, ct, omega, s, u0, du, g0, dg, tau, lo, hi, th_lo, th_hi, target, sgn, p2, sa, ca
):
    """The first partial step length [s] that :func:`_locate` tries (st, ct = sin θ, cos θ):
    the first root of the Taylor cubic (:func:`_taylor_root`) when lo = 0, else (or if it
    has none) the secant of the bracket, or its middle."""
    h = -1.0
    if lo == 0.0:
        S, C = _angle_terms(st, ct, s, sa, ca)
        h = _taylor_root(
            theta, S, C, omega, fma(du, tau, u0), du, _gv_at(g0, dg, tau), dg, hi, target, p2
        )
    if h < 0.0:
        flo = sgn * (th_lo - target)
        fhi = sgn * (th_hi - target)
        h = lo - (hi - lo) * flo / (fhi - flo) if fhi > flo else 0.5 * (lo + hi)
        if not (lo < h < hi):
            h = 0.5 * (lo + hi)
    return h


@kernel(inline="always")
def _newton(th, om, h, lo, hi, target, sgn, s, u0, du, g0, dg, tau, p2, sa, ca):
    """One correction of :func:`_locate` after its RK4 partial step of length h, which gave
    (th, om): returns (done, h, lo, hi, θ, θ').  Done: (h, θ, θ') is the result.  Else h is the
    next length to try in the bracket (lo, hi), narrowed by this step.

    Done when f = sgn·(th − target) is 0, or when the Newton correction δh would leave an error
    below 1e-15 s (round-off for steps of a few ms): the state is then the RK4 state carried
    over δh by Taylor (θ → target, θ' → θ' − θ''·δh; the error, of order θ'''·δh², is at
    round-off level).  Otherwise the Newton step, or bisection where it would leave the bracket.
    """
    f = sgn * (th - target)
    if f == 0.0:
        return True, h, lo, hi, th, om
    if f < 0.0:
        lo = h
    else:
        hi = h
    hn = 0.5 * (lo + hi)
    if om != 0.0:
        step = (th - target) / om
        # the error left by this Newton correction is about θ''·step²/(2θ') [s]
        acc = _accel(th, s, fma(du, tau + h, u0), _gv_at(g0, dg, tau + h), p2, sa, ca)
        if abs(acc) * step * step <= 2e-15 * abs(om) and lo <= h - step <= hi:
            return True, h - step, lo, hi, target, fma(-acc, step, om)
        if lo < h - step < hi:
            hn = h - step
    return False, hn, lo, hi, th, om


@kernel(inline="always")
def _taylor_root(theta, S, C, omega, u, du, gv, dg, hi, target, p2):
    """First root in (0, hi) of θ + θ'·τ + θ''·τ²/2 + θ'''·τ³/6 = target, the Taylor cubic of
    Eq. (1) at the state (theta, omega) with ground acceleration u + du·τ and vertical factor
    gv + dg·τ (None: 1); −1 if none is found.

    θ'' = −p²·(gv·S + u·C) with S = sin(sα − θ), C = cos(sα − θ), hence
    θ''' = p²·((gv·C − u·S)·θ' − C·du − S·dg) (S and C given).  From the first root of the
    quadratic, one Newton step.
    """
    a = -p2 * fma(u, C, _gv_times(gv, S))
    jerk = p2 * _gv_fnms(dg, S, fma(-u, S, _gv_times(gv, C)) * omega - C * du)
    c0 = theta - target
    qa = 0.5 * a
    disc = omega * omega - 4.0 * qa * c0
    if disc < 0.0:
        return -1.0
    q = -0.5 * (omega + math.copysign(math.sqrt(disc), omega))
    h = -1.0
    for r in (q / qa if qa != 0.0 else -1.0, c0 / q if q != 0.0 else -1.0):
        if 0.0 < r < hi and (h < 0.0 or r < h):
            h = r
    if h < 0.0:
        return -1.0
    # one Newton step: the quadratic's root is off by about p²h²/6 relative, the step leaves the
    # square of that (≪ the cubic's own truncation error, which _locate's Newton step removes)
    j6 = jerk / 6.0
    f = ((j6 * h + qa) * h + omega) * h + c0
    df = (3.0 * j6 * h + a) * h + omega
    if df != 0.0:
        hn = h - f / df
        if 0.0 < hn < hi:
            h = hn
    return h


@kernel
def _hermite_min(theta, omega, th1, om1, s, h):
    """Time (> 0) of least s·θ of the Hermite cubic through the step's end states, if that cubic
    turns round inside the step (θ' changes sign towards θ = 0 and back), else −1."""
    if not (s * omega < 0.0 and s * om1 > 0.0):
        return -1.0
    # Hermite cubic θ(x) on x = τ/h ∈ [0, 1]; find where its derivative vanishes (the minimum
    # of sθ).
    a = 2.0 * theta - 2.0 * th1 + h * omega + h * om1
    b = -3.0 * theta + 3.0 * th1 - 2.0 * h * omega - h * om1
    c = h * omega
    # derivative 3a x² + 2b x + c = 0
    best = -1.0
    if abs(a) < 1e-300:
        if b != 0.0:
            best = -c / (2.0 * b)
    else:
        disc = 4.0 * b * b - 12.0 * a * c
        if disc >= 0.0:
            r = math.sqrt(disc)
            for x in ((-2.0 * b - r) / (6.0 * a), (-2.0 * b + r) / (6.0 * a)):
                if 0.0 < x < 1.0:
                    val = s * (((a * x + b) * x + c) * x + theta)
                    if best < 0.0 or val < s * (((a * best + b) * best + c) * best + theta):
                        best = x
    if best <= 0.0 or best >= 1.0:
        return -1.0
    return best * h


@kernel(inline="always")
def _interior_touch(theta, omega, th1, om1, s, u0, du, g0, dg, tau, h, p2, sa, ca):
    """Bracket (lo, hi, θ(lo), θ(hi)) of partial step lengths around the first return to θ = 0
    inside a step that ends on the same side (s·θ > 0 at lo, ≤ 0 at hi), or lo = hi = −1 if none
    is found.

    None when :func:`_no_touch` rules it out.  Otherwise two probes: the turning point of the
    Hermite cubic through the end states (a swing that turns round inside the step); and partial
    RK4 steps at h/_N_PROBES intervals (during short bounces or the chatter after an impact, where
    the cubic's error exceeds θ itself).
    """
    ua, ub = _u_ends(u0, du, tau, h)
    ga, _gm, gb = _gv_ends(g0, dg, tau, h)
    if _no_touch(theta, omega, s, ua, ub, ga, gb, h, p2, sa):
        return -1.0, -1.0, 0.0, 0.0
    st, ct = _sincos_any(theta)
    hm = _hermite_min(theta, omega, th1, om1, s, h)
    if hm > 0.0:
        tm, _w = _rk4_sc(theta, st, ct, omega, s, u0, du, g0, dg, tau, hm, p2, sa, ca)
        if s * tm <= 0.0:
            return 0.0, hm, theta, tm
    # The probes side by side (a loop the compiler turns into SIMD code: the branch-free fast
    # step of _rk4_sc, the first touch as a min-reduction; the step itself as padding, never
    # taken); where the fast step is not valid for some probe, one at a time with _rk4_sc.
    # Then the bracket of the first touch by _rk4_sc: the same values as probing one by one.
    first = _N_PROBES
    fast = True
    for j in range(1, _N_PROBES + 1):
        tj, _w, dmax = _rk4_rotated(
            theta, st, ct, omega, s, u0, du, g0, dg, tau, h * j / _N_PROBES, p2, sa, ca
        )
        inside = j < _N_PROBES
        fast &= _fast_valid(theta, dmax) | (not inside)
        first = min(first, j if (s * tj <= 0.0) & inside else _N_PROBES)
    if not fast:
        first = _N_PROBES
        for j in range(1, _N_PROBES):
            tj, _w = _rk4_sc(
                theta, st, ct, omega, s, u0, du, g0, dg, tau, h * j / _N_PROBES, p2, sa, ca
            )
            if s * tj <= 0.0:
                first = j
                break
    if first == _N_PROBES:
        return -1.0, -1.0, 0.0, 0.0
    hi = h * first / _N_PROBES
    th_hi, _w = _rk4_sc(theta, st, ct, omega, s, u0, du, g0, dg, tau, hi, p2, sa, ca)
    if first == 1:
        return 0.0, hi, theta, th_hi
    lo = h * (first - 1) / _N_PROBES
    th_lo, _w = _rk4_sc(theta, st, ct, omega, s, u0, du, g0, dg, tau, lo, p2, sa, ca)
    return lo, hi, th_lo, th_hi


@kernel(inline="always")
def _chatter_time(omega, acc_s, acc_o, e):
    """Duration [s] of the impact sequence that starts at θ = 0 with angular velocity ``omega``
    [rad/s] on a side where θ'' = ``acc_s``, the other side having θ'' = ``acc_o`` [rad/s²] (both
    pointing back to θ = 0): flights of 2·abs(θ')/abs(θ'') alternating between the sides, θ'
    multiplied by e at every impact, a geometric series of ratio e²."""
    return 2.0 * abs(omega) * (1.0 / abs(acc_s) + e / abs(acc_o)) / (1.0 - e * e)


@kernel(inline="always")
def _chatter_impacts(t0, e, dt):
    """Impacts counted for a summed chatter whose first flight lasts t0 [s]: one per flight longer
    than ZENO_TIME_FRACTION·dt (flights shrink by the factor e), as if integrated."""
    tz = ZENO_TIME_FRACTION * dt
    if t0 < tz:
        return 0
    return 1 + int(math.log(t0 / tz) / -math.log(e))


class Body(NamedTuple):
    """Constants of one block in the kernels (compiled to plain registers)."""

    p2: float  #: p² of Eq. (1) [1/s²]
    sa: float  #: sin α [-]
    ca: float  #: cos α [-]
    tan_a: float  #: tan α [-]
    e: float  #: coefficient of restitution [-]
    th_ov: float  #: overturning angle [rad]


class Interval(NamedTuple):
    """One sample interval [0, dt] of the ground motion, linear in between."""

    u0: float  #: u = a_g/g at its start [-]
    u1: float  #: u at its end [-]
    g0: float | None  #: vertical factor gv = 1 + a_v/g at its start [-], None: no a_v
    g1: float | None  #: gv at its end [-], None: no a_v
    dt: float  #: its length [s]


class Swing(NamedTuple):
    """State of a block at local time ``tau`` of an interval."""

    theta: float  #: θ [rad]
    omega: float  #: θ' [rad/s]
    s: float  #: pivot side ±1
    state: int  #: _REST, _ROCKING or _OVERTURNED
    tau: float  #: local time [s]
    t_start: float  #: local time of the last start from rest in the interval [s] (−1: none)
    false_side: float  #: sign of u of a start that landed at once (no restart on it; 0: none)


@kernel
def _advance(theta, omega, s, state, iv, body, located):
    """Advance a block over one sample interval ``iv`` (:class:`Interval`) of a block ``body``
    (:class:`Body`); impacts located inside the step, or (``located`` False) at the end of a step
    that changes side.

    Returns (theta, omega, s, state, n_impacts, t_event): ``t_event`` is the local time of
    overturning within the interval [s], or −1.
    """
    th1 = 0.0
    om1 = 0.0
    valid = False
    if state == _ROCKING:
        dg = _gv_slope(iv.g0, iv.g1, iv.dt)
        th1, om1, valid, plain = _plain_step(
            theta,
            omega,
            s,
            iv.u0,
            (iv.u1 - iv.u0) / iv.dt,
            iv.g0,
            dg,
            0.0,
            iv.dt,
            body.p2,
            body.sa,
            body.ca,
            body.th_ov,
        )
        if plain:
            return th1, om1, s, state, 0, -1.0
    sw = Swing(theta, omega, s, state, 0.0, -1.0, 0.0)
    sw, n_imp, t_event, _deferred = _advance_events(sw, iv, body, th1, om1, valid, False, located)
    return sw.theta, sw.omega, sw.s, sw.state, n_imp, t_event


@kernel(inline="always")
def _initial(theta0, omega0):
    """(pivot side s, state) of a block that starts at θ0 [rad] with θ'0 [rad/s]: rocking on
    the side of θ0 (else of θ'0), at rest when both are 0."""
    if theta0 != 0.0:
        return (1.0 if theta0 > 0.0 else -1.0), _ROCKING
    if omega0 != 0.0:
        return (1.0 if omega0 > 0.0 else -1.0), _ROCKING
    return 1.0, _REST


@kernel(inline="always")
def _uplift_time(sw, iv, du, dg, body):
    """Local time [s] at which a block at rest at ``sw.tau`` starts to rock within the interval
    (the first where abs(u) exceeds gv·tan α, on a side other than ``sw.false_side``), or −1 if
    it stays at rest through the rest of the interval."""
    ua = fma(du, sw.tau, iv.u0)
    if _uplifts(ua, _gv_at(iv.g0, dg, sw.tau), body.sa, body.ca) and ua * sw.false_side <= 0.0:
        return sw.tau
    if _uplifts(iv.u1, iv.g1, body.sa, body.ca) and iv.u1 * sw.false_side <= 0.0:
        # linear u crosses ±gv·tan α (gv linear too) inside the rest of the interval
        thr = body.tan_a if iv.u1 > 0.0 else -body.tan_a
        tstart = (_gv_times(iv.g0, thr) - iv.u0) / _gv_fnms(dg, thr, du)
        return sw.tau if tstart < sw.tau else tstart
    return -1.0


@kernel(inline="always")
def _start(sw, tau, iv, du):
    """The block starts to rock from rest at local time ``tau``: on the side opposite to the
    ground acceleration there (a negative a_g tips it to θ > 0)."""
    uc = fma(du, tau, iv.u0)
    s = -1.0 if uc > 0.0 else 1.0
    return Swing(0.0, 0.0, s, _ROCKING, tau, tau, sw.false_side)


@kernel(inline="always")
def _ends_across(s, th1, om1):
    """Whether a step on pivot side ``s`` that ends at (th1, om1) ends on the other side of θ = 0
    (or at θ = 0 moving across)."""
    return (s * th1 < 0.0) | ((th1 == 0.0) & (s * om1 < 0.0))


@kernel(inline="always")
def _slopes(iv):
    """du/dt [1/s] and the slope of gv [1/s] (or None) over the interval ``iv``: one place,
    so that the batched kernel's event handling computes exactly :func:`_advance_events`'s."""
    return (iv.u1 - iv.u0) / iv.dt, _gv_slope(iv.g0, iv.g1, iv.dt)


@kernel(inline="always")
def _find_hit(sw, th1, om1, h, iv, du, dg, body, located):
    """Bracket (lo, hit, θ(lo), θ(hit)) of partial step lengths around the block's first arrival
    at θ = 0 in the step of length h from ``sw`` that ends at (th1, om1), or hit = −1 if none
    (with ``located`` False only a step that ends on the other side counts, at its end)."""
    if _ends_across(sw.s, th1, om1):
        return 0.0, h, sw.theta, th1
    if located:
        return _interior_touch(
            sw.theta,
            sw.omega,
            th1,
            om1,
            sw.s,
            iv.u0,
            du,
            iv.g0,
            dg,
            sw.tau,
            h,
            body.p2,
            body.sa,
            body.ca,
        )
    return 0.0, -1.0, sw.theta, th1


@kernel(inline="always")
def _impact(sw, omz, iv, du, dg, body):
    """The block at θ = 0 with angular velocity ``omz`` at local time ``sw.tau`` (after an arrival
    located or taken at the step's end): a start from rest that landed at once, an impact that
    ends at rest (Zeno) or a chatter summed in closed form, or an impact after which it rocks on.

    Returns (swing, impacts counted).
    """
    dt = iv.dt
    tau = sw.tau
    p2 = body.p2
    sa = body.sa
    ca = body.ca
    e = body.e
    if sw.t_start >= 0.0 and tau - sw.t_start < ZENO_TIME_FRACTION * dt:
        # Back at θ = 0 within the Zeno time of starting: abs(a_g) fell below gv·g·tan α
        # again at once (it exceeded it by a few ulps). The block never left the
        # ground. u is linear in the interval, so abs(u) keeps falling on this side: a
        # restart on it would land again at the same instant, forever; only a
        # crossing of the threshold on the other side can start it in this interval.
        fs = 1.0 if fma(du, sw.t_start, iv.u0) > 0.0 else -1.0
        return Swing(0.0, 0.0, sw.s, _REST, tau, sw.t_start, fs), 0
    n_imp = 1
    s = -sw.s
    omega = e * omz
    # Zeno check: how long would the next free flight last?
    ua = fma(du, tau, iv.u0)  # u and gv at tau, as _u_ends and _gv_ends compute them
    ga = _gv_at(iv.g0, dg, tau)
    acc0 = -p2 * fma(ua, ca, _gv_times(ga, s * sa))  # θ'' at θ = 0 on the new side
    if omega == 0.0 or (
        acc0 * omega < 0.0 and 2.0 * abs(omega) < ZENO_TIME_FRACTION * dt * abs(acc0)
    ):
        return Swing(0.0, 0.0, s, _REST, tau, sw.t_start, sw.false_side), n_imp
    if (
        e < 1.0
        and acc0 * omega < 0.0
        and 2.0 * abs(omega) < CHATTER_FRACTION * dt * abs(acc0)
        and fma(abs(ua), ca, -_gv_times(ga, sa)) < 0.0
    ):
        # a chatter that cannot lift off (no uplift at either end; u and gv linear, so
        # abs(u)·cos α − gv·sin α is convex in between): summed
        acc_o = -p2 * fma(ua, ca, _gv_times(ga, -s * sa))
        t_end = tau + _chatter_time(omega, acc0, acc_o, e)
        sa_end = _gv_times(_gv_at(iv.g0, dg, t_end), sa)
        if t_end < dt and fma(abs(fma(du, t_end, iv.u0)), ca, -sa_end) < 0.0:
            n_imp += _chatter_impacts(2.0 * abs(omega / acc0), e, dt)
            return Swing(0.0, 0.0, s, _REST, t_end, sw.t_start, sw.false_side), n_imp
    return Swing(0.0, omega, s, _ROCKING, tau, sw.t_start, sw.false_side), n_imp


@kernel(inline="always")
def _overturn(sw, th1, h, iv, du, dg, body):
    """The block overturns within the step of length h from ``sw`` that ends at abs(th1) ≥ the
    overturning angle: (its swing at that angle, the local time [s] at which it reaches it)."""
    target = body.th_ov if th1 > 0.0 else -body.th_ov
    hz, thz, omz = _locate(
        sw.theta,
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
        th1,
        target,
        sw.s,
        body.p2,
        body.sa,
        body.ca,
    )
    return Swing(thz, omz, sw.s, _OVERTURNED, sw.tau, sw.t_start, sw.false_side), sw.tau + hz


@kernel
def _advance_events(sw, iv, body, th_step, om_step, have_step, defer, located):
    """:func:`_advance` of the part [sw.tau, dt] of an interval ``iv`` whose next step is not
    plain (see :func:`_plain_step`): impacts, uplift, coming to rest, overturning.  ``sw``: the
    block's :class:`Swing` at ``sw.tau``; ``body``: its :class:`Body`; ``located``: the impact
    scheme (False: "step-end", see the module docstring).

    ``th_step``, ``om_step``: the RK4 step from (θ, θ') at tau to dt, already computed when
    ``have_step`` (it is the same as :func:`_rk4`'s).  With ``defer``, it stops after an impact
    from which the block rocks on, so that the caller computes the rest of the interval (the
    batched kernel: in a SIMD lane) and calls again if that step is not plain.

    Returns (swing, n_impacts, t_event, deferred): ``t_event`` is the local time of overturning
    [s], or −1; ``deferred`` says that the interval goes on from swing.tau < dt (else it is done).
    """
    dt = iv.dt
    du, dg = _slopes(iv)
    n_imp = 0
    for _ in range(_MAX_EVENTS_PER_STEP):
        if sw.state == _REST:
            tstart = _uplift_time(sw, iv, du, dg, body)
            if tstart < 0.0:
                break  # at rest through the whole interval
            sw = _start(sw, tstart, iv, du)
            if tstart >= dt:
                break
            continue
        h = dt - sw.tau
        if h <= 0.0:
            break
        if have_step:  # the step from tau to dt was computed by the caller
            th1 = th_step
            om1 = om_step
            have_step = False
        else:
            th1, om1 = _rk4(
                sw.theta,
                sw.omega,
                sw.s,
                iv.u0,
                du,
                iv.g0,
                dg,
                sw.tau,
                h,
                body.p2,
                body.sa,
                body.ca,
            )
        lo, hit, th_lo, th_hi = _find_hit(sw, th1, om1, h, iv, du, dg, body, located)
        if hit > 0.0:
            if located:
                hz, _thz, omz = _locate(
                    sw.theta,
                    sw.omega,
                    sw.s,
                    iv.u0,
                    du,
                    iv.g0,
                    dg,
                    sw.tau,
                    lo,
                    hit,
                    th_lo,
                    th_hi,
                    0.0,
                    -sw.s,
                    body.p2,
                    body.sa,
                    body.ca,
                )
            else:  # "step-end": the impact is taken at the end of the step, with its θ'
                hz, omz = h, om1
            arrived = Swing(
                sw.theta, sw.omega, sw.s, sw.state, sw.tau + hz, sw.t_start, sw.false_side
            )
            sw, n = _impact(arrived, omz, iv, du, dg, body)
            n_imp += n
            if defer and sw.state == _ROCKING:  # the rest of the interval, if any, to the caller
                return sw, n_imp, -1.0, dt - sw.tau > 0.0
            continue
        if abs(th1) >= body.th_ov:
            sw, t_event = _overturn(sw, th1, h, iv, du, dg, body)
            return sw, n_imp, t_event, False
        sw = Swing(th1, om1, sw.s, sw.state, sw.tau, sw.t_start, sw.false_side)
        break
    return sw, n_imp, -1.0, False
