"""Rocking of a rigid rectangular block on a rigid horizontal base (paper Section 2).

Equation of motion, one form for both pivots (paper Eqs. 1–2, with the sign of Eq. 2's forcing
term corrected so that the response to −a_g is exactly −θ; reference.md §2):

    θ'' = −p²·[ sin(s·α − θ) + (a_g/g)·cos(s·α − θ) ],   s = sgn θ,   p² = 3g/(4R)      (Eq. 1)

Impact at θ = 0: the pivot switches (s → −s) and θ' ← e·θ'.  From rest the block starts to rock
only when |a_g| > g·tan α, tipping to θ > 0 under a negative ground acceleration.

Integration (the paper's scheme): classical fourth-order Runge–Kutta with a fixed step equal to the
motion's sample interval dt, the ground acceleration being linear between samples.  Within a step
the pivot is frozen; when the step ends on the other side of θ = 0, or turns round inside the step
far enough to touch it, the impact instant is located by safeguarded Newton iteration on the length
of a partial Runge–Kutta step, the impact is applied and the rest of the step is integrated from the
impact.  A bounce whose free flight would last less than ``ZENO_TIME_FRACTION·dt`` ends the
chatter: the block is put at rest (the remaining flights of the geometric series carry negligible
energy), and rocking restarts only if |a_g| > g·tan α.  A chatter whose next flight is shorter than
``CHATTER_FRACTION·dt`` and during which the ground acceleration stays below g·tan α is summed in
closed form instead of being integrated bounce by bounce (speed: such sequences are about a hundred
impacts each): flights of 2|θ'|/|θ''| at θ = 0 alternating between the pivots under the ground
acceleration at its start, θ' × e at every impact; the block is at rest from the sum of the
flights on, if that lies within the time step and the ground acceleration is still below the
uplift level there (u is linear in the step, so it is below it throughout).  |θ| in such a
chatter stays below |θ''|·(CHATTER_FRACTION·dt)²/8 (1e-9 rad for the paper's bodies at
dt = 1/400 s), so the bracket of Eq. (1) is sin α ± u·cos α to that relative accuracy.

Trigonometry (speed; see :func:`_rk4_rotated`): sin θ and cos θ once per step by polynomials
(within 2.3e-16 of libm for |θ| ≤ π/2), and at the stage angles θ + δ by the angle-sum identities
with Taylor polynomials of the small offsets δ; a step with a large offset (|θ'|·h > 1/32 rad)
evaluates sin and cos at every stage instead (:func:`_rk4_stages`).  tests/test_trig.py bounds
both against libm and against each other.  Impact location starts from the root of the cubic
Taylor polynomial of θ(t), so that one partial RK4 step usually suffices.  The same compiled
functions serve :func:`simulate` and the batched kernel of :mod:`rocking.batch` (which runs
:func:`_plain_step` in SIMD lanes and :func:`_advance_events` for the rest), so they agree bit for
bit.

The kernels here are pure functions on arrays; :func:`simulate` is the public wrapper.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field

import numpy as np

from ._numba import fma, kernel
from ._validate import finite_array, in_range, positive
from .body import G, Block, resolve_e, resolve_overturn_angle
from .errors import InputError

#: A bounce shorter than this fraction of the time step ends an impact sequence (block at rest).
ZENO_TIME_FRACTION = 1e-4
#: An impact sequence (chatter) whose next flight is shorter than this fraction of the time step
#: is summed in closed form (:func:`_chatter_time`) when the block cannot lift off during it.
CHATTER_FRACTION = 1.0 / 64.0
#: Partial-step probes for a return to θ = 0 inside a step that starts near θ = 0.
_N_PROBES = 8
#: Safety cap on events handled within one time step (impacts, uplifts).
_MAX_EVENTS_PER_STEP = 10_000

# Block state codes
_REST = 0
_ROCKING = 1
_OVERTURNED = 2

# --------------------------------------------------------------------------- sin and cos
#: |x| [rad] up to which :func:`_sincos` is accurate (a step starts at |θ| < overturn angle ≤ π/2).
SINCOS_XMAX = 1.5717963267948966
# sin x = x + x·z·R_s(z), cos x = 1 − z/2 + z²·R_c(z), z = x²: near-minimax polynomials R_s, R_c
# (Chebyshev interpolation of (sin x/x − 1)/z and (cos x − 1 + z/2)/z² on 0 ≤ z ≤ SINCOS_XMAX²,
# computed with 40-digit arithmetic, rounded to double), highest degree first.
_RS = (2.731344277439919e-15, -7.643962232442654e-13, 1.6058977059718268e-10,
       -2.5052107613095433e-08, 2.7557319219132584e-06, -0.0001984126984125486,
       0.008333333333333316, -0.16666666666666666)
_RC = (-1.5218134641974516e-16, 4.777873882841319e-14, -1.1470712146057573e-11,
       2.0876756600920194e-09, -2.75573192215542e-07, 2.4801587301579797e-05,
       -0.001388888888888888, 0.041666666666666664)
#: |x| [rad] below which sin x and cos x round to x and 1.
SINCOS_TINY = 1e-8
#: Largest stage offset |δ| [rad] for which the RK4 stages use the rotation formulas of _rot.
ROTATION_DMAX = 1.0 / 32.0
# Taylor coefficients of sin δ (to δ⁷) and cos δ (to δ⁶); the first terms left out are below
# δ⁹/9! ≤ 8e-20 and δ⁸/8! ≤ 2.3e-17 for |δ| ≤ ROTATION_DMAX.
_T1, _T2, _T3 = -1.0 / 6.0, 1.0 / 120.0, -1.0 / 5040.0
_K1, _K2 = 1.0 / 24.0, -1.0 / 720.0


@kernel(inline="always")
def _horner(c, z):
    """c[0]·z^(n−1) + c[1]·z^(n−2) + … + c[n−1] by Horner's rule, one fused multiply–add per
    coefficient (a loop of constant length: the compiler unrolls it)."""
    r = c[0]
    for k in range(1, len(c)):
        r = fma(r, z, c[k])
    return r


@kernel(inline="always")
def _sincos(x):
    """(sin x, cos x) by polynomials, for |x| ≤ SINCOS_XMAX [rad] (see tests/test_trig.py for
    the accuracy); branch-free, so that it vectorizes."""
    z = x * x
    return fma(x * z, _horner(_RS, z), x), 1.0 - fma(-(z * z), _horner(_RC, z), 0.5 * z)


@kernel(inline="always")
def _rot(P, Q, d):
    """cos δ·P + sin δ·Q for |δ| ≤ ROTATION_DMAX (Taylor polynomials of sin δ and cos δ),
    arranged as P + δ·Q + δ²·(c(δ²)·P + δ·s(δ²)·Q) with cos δ = 1 + δ²·c(δ²) and
    sin δ = δ + δ³·s(δ²): nine multiplications or fused multiply–adds."""
    z = d * d
    c = fma(fma(z, _K2, _K1), z, -0.5)
    sq = d * Q
    sn = fma(fma(z, _T3, _T2), z, _T1)
    return fma(z, fma(c, P, sq * sn), P + sq)


@kernel(inline="always")
def _signed(s, x):
    """s·x for s = ±1, exactly, as a sign flip rather than a multiplication (in SIMD loops it
    leaves the multiply units to the arithmetic)."""
    return x if s > 0.0 else -x


@kernel(inline="always")
def _angle_terms(st, ct, s, sa, ca):
    """(sin(sα − θ), cos(sα − θ)) from sin θ, cos θ."""
    ssa = _signed(s, sa)
    # sin(sα − θ) = s·sinα·cosθ − cosα·sinθ ;  cos(sα − θ) = cosα·cosθ + s·sinα·sinθ
    return fma(ssa, ct, -(ca * st)), fma(ca, ct, ssa * st)


@kernel(inline="always")
def _sincos_any(x):
    """(sin x, cos x) for any x [rad], outside SIMD loops: (x, 1) for |x| < SINCOS_TINY, which is
    exactly what :func:`_sincos` rounds to there (tests/test_trig.py) and spares the latency of
    its polynomials after every impact (θ = 0); the polynomials up to SINCOS_XMAX; else libm."""
    if abs(x) < SINCOS_TINY:
        return x, 1.0
    if abs(x) <= SINCOS_XMAX:
        return _sincos(x)
    return math.sin(x), math.cos(x)


@kernel(inline="always")
def _sin_cos_terms(theta, s, sa, ca):
    """(sin(sα − θ), cos(sα − θ)) for any θ (:func:`_sincos_any`)."""
    st, ct = _sincos_any(theta)
    return _angle_terms(st, ct, s, sa, ca)


@kernel(inline="always")
def _accel(theta, s, u, p2, sa, ca):
    """θ'' of Eq. (1) on pivot side ``s`` for ground acceleration ``u`` = a_g/g [-]."""
    S, C = _sin_cos_terms(theta, s, sa, ca)
    return -p2 * fma(u, C, S)


@kernel(inline="always")
def _rk4_fast(theta, omega, s, u0, du, tau, h, p2, sa, ca):
    """One RK4 step of length h from local time tau; u(τ) = u0 + du·τ (du per second).
    Branch-free (the batched kernel runs it in SIMD lanes): see :func:`_rk4_rotated`."""
    st, ct = _sincos(theta)
    return _rk4_rotated(theta, st, ct, omega, s, u0, du, tau, h, p2, sa, ca)


@kernel(inline="always")
def _rk4_rotated(theta, st, ct, omega, s, u0, du, tau, h, p2, sa, ca):
    """The RK4 step of :func:`_rk4_fast` given st, ct = sin θ, cos θ.

    Trigonometry: the stage angles are θ + δ with small δ (δ = h/2·θ'_1, h/2·θ'_2, h·θ'_3), so
    with S = sin(sα − θ), C = cos(sα − θ) (one :func:`_sincos` of θ per step) the bracket of
    Eq. (1) at θ + δ and ground acceleration u is

        sin(sα − θ − δ) + u·cos(sα − θ − δ) = cos δ·(S + u·C) + sin δ·(u·S − C),

    evaluated by :func:`_rot`.  Valid when |θ| ≤ SINCOS_XMAX and every |δ| ≤ ROTATION_DMAX;
    returns (θ, θ', max|δ|) so that the caller can check the second condition.
    """
    ua, ub = _u_ends(u0, du, tau, h)
    um = fma(du * 0.5, h, ua)
    S, C = _angle_terms(st, ct, s, sa, ca)
    hh = 0.5 * h
    # stage 1 at θ: −p²·(S + u·C); at θ = 0 its sign is that of s·sin α + u·cos α, exactly the
    # uplift test of _advance
    k1w = -p2 * fma(ua, C, S)
    Pm = fma(um, C, S)
    Qm = fma(um, S, -C)
    d2 = hh * omega
    k2w = -p2 * _rot(Pm, Qm, d2)
    d3 = hh * fma(hh, k1w, omega)
    k3w = -p2 * _rot(Pm, Qm, d3)
    d4 = h * fma(hh, k2w, omega)
    k4w = -p2 * _rot(fma(ub, C, S), fma(ub, S, -C), d4)
    # θ_1 = θ + h/6·(θ'_1 + 2θ'_2 + 2θ'_3 + θ'_4) = θ + h·(θ' + h/6·(θ''_1 + θ''_2 + θ''_3))
    th = fma(h, fma(h / 6.0, k1w + k2w + k3w, omega), theta)
    om = fma(h / 6.0, (k1w + k4w) + 2.0 * (k2w + k3w), omega)
    a2 = abs(d2)
    a3 = abs(d3)
    a4 = abs(d4)
    dmax = a2 if a2 > a3 else a3
    dmax = dmax if dmax > a4 else a4
    return th, om, dmax


@kernel(inline="always")
def _fast_valid(theta, dmax):
    """Whether :func:`_rk4_fast`'s result with this start angle and max|δ| is the RK4 step."""
    return (dmax <= ROTATION_DMAX) & (abs(theta) <= SINCOS_XMAX)


@kernel
def _rk4_stages(theta, omega, s, u0, du, tau, h, p2, sa, ca):
    """The RK4 step of :func:`_rk4_fast` with θ'' evaluated afresh at every stage angle
    (:func:`_accel`): valid for any step, and the reference for the fast one's accuracy."""
    ua, ub = _u_ends(u0, du, tau, h)
    um = fma(du * 0.5, h, ua)
    hh = 0.5 * h
    k1w = _accel(theta, s, ua, p2, sa, ca)
    k2w = _accel(theta + hh * omega, s, um, p2, sa, ca)
    k3w = _accel(theta + hh * fma(hh, k1w, omega), s, um, p2, sa, ca)
    k4w = _accel(theta + h * fma(hh, k2w, omega), s, ub, p2, sa, ca)
    th = fma(h, fma(h / 6.0, k1w + k2w + k3w, omega), theta)
    om = fma(h / 6.0, (k1w + k4w) + 2.0 * (k2w + k3w), omega)
    return th, om


@kernel
def _rk4(theta, omega, s, u0, du, tau, h, p2, sa, ca):
    """One RK4 step of length h from local time tau; u(τ) = u0 + du·τ (du per second).

    :func:`_rk4_fast` where it is valid (nearly always), else :func:`_rk4_stages` (a very fast
    block: |θ'|·h > ROTATION_DMAX).
    """
    st, ct = _sincos_any(theta)
    return _rk4_sc(theta, st, ct, omega, s, u0, du, tau, h, p2, sa, ca)


@kernel
def _rk4_sc(theta, st, ct, omega, s, u0, du, tau, h, p2, sa, ca):
    """:func:`_rk4` given st, ct = sin θ, cos θ (partial steps from one state share them)."""
    th, om, dmax = _rk4_rotated(theta, st, ct, omega, s, u0, du, tau, h, p2, sa, ca)
    if _fast_valid(theta, dmax):
        return th, om
    return _rk4_stages(theta, omega, s, u0, du, tau, h, p2, sa, ca)


# --------------------------------------------------------------------------- events


@kernel(inline="always")
def _locate(theta, omega, s, u0, du, tau, lo, hi, th_lo, th_hi, target, sgn, p2, sa, ca):
    """Partial step length h in [lo, hi] where the RK4 solution from (theta, omega) hits ``target``.

    ``th_lo``, ``th_hi``: that solution at lo and hi.  With f(h) = sgn·(θ_RK4(h) − target), the
    caller guarantees f(lo) ≤ 0 ≤ f(hi); the root kept is the first one after leaving ``lo``
    (f(lo) = 0 happens when the arc starts at θ = 0, and that trivial root is never returned).

    Newton's method on h (dθ/dh = θ') safeguarded by bisection, from the first root of the
    cubic Taylor polynomial of θ at the start when lo = 0 (:func:`_taylor_root`), else from the
    secant.  It ends when the next Newton correction δh would leave an error below 1e-15 s
    (round-off for steps of a few ms): the state is then the last RK4 state carried over δh by
    Taylor (θ → target, θ' → θ' − θ''·δh; the error, of order θ''' δh², is at round-off level).
    Returns (h, theta_h, omega_h).
    """
    st, ct = _sincos_any(theta)
    h = -1.0
    if lo == 0.0:
        S, C = _angle_terms(st, ct, s, sa, ca)
        h = _taylor_root(theta, S, C, omega, fma(du, tau, u0), du, hi, target, p2)
    if h < 0.0:
        flo = sgn * (th_lo - target)
        fhi = sgn * (th_hi - target)
        h = lo - (hi - lo) * flo / (fhi - flo) if fhi > flo else 0.5 * (lo + hi)
        if not (lo < h < hi):
            h = 0.5 * (lo + hi)
    th, om = _rk4_sc(theta, st, ct, omega, s, u0, du, tau, h, p2, sa, ca)
    for _ in range(100):
        f = sgn * (th - target)
        if f == 0.0:
            break
        if f < 0.0:
            lo = h
        else:
            hi = h
        hn = 0.5 * (lo + hi)
        if om != 0.0:
            step = (th - target) / om
            # the error left by this Newton correction is about θ''·step²/(2θ') [s]
            acc = _accel(th, s, fma(du, tau + h, u0), p2, sa, ca)
            if abs(acc) * step * step <= 2e-15 * abs(om) and lo <= h - step <= hi:
                return h - step, target, fma(-acc, step, om)
            if lo < h - step < hi:
                hn = h - step
        h = hn
        th, om = _rk4_sc(theta, st, ct, omega, s, u0, du, tau, h, p2, sa, ca)
    return h, th, om


@kernel(inline="always")
def _taylor_root(theta, S, C, omega, u, du, hi, target, p2):
    """First root in (0, hi) of θ + θ'·τ + θ''·τ²/2 + θ'''·τ³/6 = target, the Taylor cubic of
    Eq. (1) at the state (theta, omega) with ground acceleration u + du·τ; −1 if none is found.

    θ'' = −p²·(S + u·C) with S = sin(sα − θ), C = cos(sα − θ), hence
    θ''' = p²·((C − u·S)·θ' − C·du) (S and C given).  From the first root of the quadratic, one
    Newton step.
    """
    a = -p2 * fma(u, C, S)
    jerk = p2 * (fma(-u, S, C) * omega - C * du)
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
    # Hermite cubic θ(x) on x = τ/h ∈ [0, 1]; find where its derivative vanishes (the minimum of sθ).
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
def _no_touch(theta, omega, s, ua, ub, h, p2, sa):
    """True when the block, at s·θ ≥ 0 on side s, cannot reach θ = 0 within a step of length h.

    While 0 ≤ s·θ ≤ π/2, Eq. (1) gives −s·θ'' = p²·[sin(α − sθ) + s·u·cos(α − sθ)] ≤
    p²·(sin α + max(0, s·u)) = a⁺ (u is linear in the step: its largest s·u is at an end), so
    s·θ(τ) ≥ s·θ + s·θ'·τ − ½a⁺τ², a concave bound whose minimum over [0, h] is at an end:
    s·θ ≥ 0 at τ = 0, and the test at τ = h.  ``ua``, ``ub``: u at the ends of the step.
    """
    sua = _signed(s, ua)
    sub = _signed(s, ub)
    push = sua if sua > sub else sub  # ground acceleration towards θ = 0, if positive
    amax = p2 * (sa + (push if push > 0.0 else 0.0))
    return _signed(s, fma(omega, h, theta)) > (0.5 * h) * h * amax


@kernel(inline="always")
def _u_ends(u0, du, tau, h):
    """u at the start (tau) and end (tau + h) of a step, as :func:`_rk4_rotated` computes them."""
    ua = fma(du, tau, u0)
    return ua, fma(du, h, ua)


@kernel(inline="always")
def _interior_touch(theta, omega, th1, om1, s, u0, du, tau, h, p2, sa, ca):
    """Bracket (lo, hi, θ(lo), θ(hi)) of partial step lengths around the first return to θ = 0
    inside a step that ends on the same side (s·θ > 0 at lo, ≤ 0 at hi), or lo = hi = −1 if none
    is found.

    None when :func:`_no_touch` rules it out.  Otherwise two probes: the turning point of the
    Hermite cubic through the end states (a swing that turns round inside the step); and partial
    RK4 steps at h/_N_PROBES intervals (during short bounces or the chatter after an impact, where
    the cubic's error exceeds θ itself).
    """
    ua, ub = _u_ends(u0, du, tau, h)
    if _no_touch(theta, omega, s, ua, ub, h, p2, sa):
        return -1.0, -1.0, 0.0, 0.0
    st, ct = _sincos_any(theta)
    hm = _hermite_min(theta, omega, th1, om1, s, h)
    if hm > 0.0:
        tm, _w = _rk4_sc(theta, st, ct, omega, s, u0, du, tau, hm, p2, sa, ca)
        if s * tm <= 0.0:
            return 0.0, hm, theta, tm
    # all probes are computed (independent: the CPU overlaps them), the first touch is kept
    lo = -1.0
    hi = -1.0
    th_lo = 0.0
    th_hi = 0.0
    prev = 0.0
    th_prev = theta
    for j in range(1, _N_PROBES):
        hj = h * j / _N_PROBES
        tj, _w = _rk4_sc(theta, st, ct, omega, s, u0, du, tau, hj, p2, sa, ca)
        if hi < 0.0:
            if s * tj <= 0.0:
                lo = prev
                hi = hj
                th_lo = th_prev
                th_hi = tj
            prev = hj
            th_prev = tj
    return lo, hi, th_lo, th_hi


@kernel(inline="always")
def _uplifts(u, sa, ca):
    """Whether ground acceleration u = a_g/g [-] lifts a block at rest: |u|·cos α > sin α, rounded
    once, i.e. exactly the sign of θ'' at θ = 0 in the RK4 stages (never a start with an
    acceleration of the wrong sign)."""
    return fma(abs(u), ca, -sa) > 0.0


@kernel(inline="always")
def _plain_step(theta, omega, s, u0, du, tau, h, p2, sa, ca, th_ov):
    """The RK4 step of a rocking block from local time tau to the end of its interval (h =
    dt − tau) and whether it is all that happens in it: no impact, no touch of θ = 0, no
    overturning, and the fast trigonometry valid.  Returns (θ_1, θ'_1, fast_valid, plain); the
    step equals :func:`_rk4`'s when fast_valid.  Branch-free (SIMD lanes of the batched kernel);
    :func:`_advance` takes the same decision with it, so both paths agree bit for bit.
    """
    th1, om1, dmax = _rk4_fast(theta, omega, s, u0, du, tau, h, p2, sa, ca)
    valid = _fast_valid(theta, dmax)
    ua, ub = _u_ends(u0, du, tau, h)
    plain = (valid & (_signed(s, th1) > 0.0) & _no_touch(theta, omega, s, ua, ub, h, p2, sa)
             & (abs(th1) < th_ov))
    return th1, om1, valid, plain


@kernel(inline="always")
def _chatter_time(omega, acc_s, acc_o, e):
    """Duration [s] of the impact sequence that starts at θ = 0 with angular velocity ``omega``
    [rad/s] on a side where θ'' = ``acc_s``, the other side having θ'' = ``acc_o`` [rad/s²] (both
    pointing back to θ = 0): flights of 2|θ'|/|θ''| alternating between the sides, θ' multiplied
    by e at every impact, a geometric series of ratio e²."""
    return 2.0 * abs(omega) * (1.0 / abs(acc_s) + e / abs(acc_o)) / (1.0 - e * e)


@kernel(inline="always")
def _chatter_impacts(t0, e, dt):
    """Impacts counted for a summed chatter whose first flight lasts t0 [s]: one per flight longer
    than ZENO_TIME_FRACTION·dt (flights shrink by the factor e), as if integrated."""
    tz = ZENO_TIME_FRACTION * dt
    if t0 < tz:
        return 0
    return 1 + int(math.log(t0 / tz) / -math.log(e))


@kernel
def _advance(theta, omega, s, state, u0, u1, dt, p2, sa, ca, tan_a, e, th_ov):
    """Advance a block over one sample interval [0, dt] of linear ground acceleration u0 → u1 (in g).

    Returns (theta, omega, s, state, n_impacts, t_event): ``t_event`` is the local time of
    overturning within the interval [s], or −1.
    """
    th1 = 0.0
    om1 = 0.0
    valid = False
    if state == _ROCKING:
        th1, om1, valid, plain = _plain_step(theta, omega, s, u0, (u1 - u0) / dt, 0.0, dt, p2, sa,
                                             ca, th_ov)
        if plain:
            return th1, om1, s, state, 0, -1.0
    r = _advance_events(theta, omega, s, state, u0, u1, dt, p2, sa, ca, tan_a, e, th_ov,
                        0.0, -1.0, 0.0, th1, om1, valid, False)
    return r[0], r[1], r[2], r[3], r[4], r[5]


@kernel
def _advance_events(theta, omega, s, state, u0, u1, dt, p2, sa, ca, tan_a, e, th_ov,
                    tau, t_start, false_side, th_step, om_step, have_step, defer):
    """:func:`_advance` of the part [tau, dt] of an interval whose next step is not plain (see
    :func:`_plain_step`): impacts, uplift, coming to rest, overturning.

    ``t_start``: local time of the last start from rest in this interval (−1: none);
    ``false_side``: sign of u of a start that landed at once (no restart on that side; 0: none).
    ``th_step``, ``om_step``: the RK4 step from (theta, omega) at tau to dt, already computed when
    ``have_step`` (it is the same as :func:`_rk4`'s).  With ``defer``, it stops after an impact
    from which the block cannot come back to θ = 0 before dt (:func:`_no_touch`), so that the
    caller computes the rest of the interval (the batched kernel: in a SIMD lane) and calls again
    if that step is not plain.

    Returns (theta, omega, s, state, n_impacts, t_event, tau', t_start, false_side, deferred):
    ``t_event`` is the local time of overturning [s], or −1; ``deferred`` says that the interval
    goes on from tau' < dt (else it is done).
    """
    du = (u1 - u0) / dt
    n_imp = 0
    t_event = -1.0
    hand_over = False  # with defer: the next step is likely plain, leave it to the caller
    for _ in range(_MAX_EVENTS_PER_STEP):
        if state == _REST:
            ua = fma(du, tau, u0)
            if _uplifts(ua, sa, ca) and ua * false_side <= 0.0:
                tstart = tau
            elif _uplifts(u1, sa, ca) and u1 * false_side <= 0.0:
                # linear u crosses ±tan α inside the rest of the interval
                thr = tan_a if u1 > 0.0 else -tan_a
                tstart = (thr - u0) / du
                if tstart < tau:
                    tstart = tau
            else:
                break  # at rest through the whole interval
            tau = tstart
            t_start = tau
            hand_over = False
            uc = fma(du, tau, u0)
            s = -1.0 if uc > 0.0 else 1.0  # negative a_g tips the block to θ > 0
            theta = 0.0
            omega = 0.0
            state = _ROCKING
            if tau >= dt:
                break
            continue
        h = dt - tau
        if h <= 0.0:
            break
        if have_step:  # the step from tau to dt was computed by the caller
            th1 = th_step
            om1 = om_step
            have_step = False
        elif hand_over:
            return theta, omega, s, state, n_imp, t_event, tau, t_start, false_side, True
        else:
            th1, om1 = _rk4(theta, omega, s, u0, du, tau, h, p2, sa, ca)
        lo = 0.0
        hit = -1.0
        th_lo = theta
        th_hi = th1
        if s * th1 < 0.0 or (th1 == 0.0 and s * om1 < 0.0):
            hit = h
        else:
            lo, hit, th_lo, th_hi = _interior_touch(theta, omega, th1, om1, s, u0, du, tau, h,
                                                    p2, sa, ca)
        if hit > 0.0:
            hz, thz, omz = _locate(theta, omega, s, u0, du, tau, lo, hit, th_lo, th_hi, 0.0, -s,
                                   p2, sa, ca)
            tau += hz
            if t_start >= 0.0 and tau - t_start < ZENO_TIME_FRACTION * dt:
                # Back at θ = 0 within the Zeno time of starting: |a_g| fell below g·tan α
                # again at once (it exceeded it by a few ulps). The block never left the
                # ground. u is linear in the interval, so |u| keeps falling on this side: a
                # restart on it would land again at the same instant, forever; only a
                # crossing of the threshold on the other side can start it in this interval.
                theta = 0.0
                omega = 0.0
                state = _REST
                false_side = 1.0 if fma(du, t_start, u0) > 0.0 else -1.0
                continue
            n_imp += 1
            s = -s
            omega = e * omz
            theta = 0.0
            # Zeno check: how long would the next free flight last?
            ua, ub = _u_ends(u0, du, tau, dt - tau)
            acc0 = -p2 * fma(ua, ca, s * sa)  # θ'' at θ = 0 on the new side
            if omega == 0.0 or (acc0 * omega < 0.0 and
                                2.0 * abs(omega) < ZENO_TIME_FRACTION * dt * abs(acc0)):
                omega = 0.0
                state = _REST
            elif (e < 1.0 and acc0 * omega < 0.0
                  and 2.0 * abs(omega) < CHATTER_FRACTION * dt * abs(acc0)
                  and fma(abs(ua), ca, -sa) < 0.0):
                # a chatter that cannot lift off (no uplift at either end, u linear): summed
                t_end = tau + _chatter_time(omega, acc0, -p2 * fma(ua, ca, -s * sa), e)
                if t_end < dt and fma(abs(fma(du, t_end, u0)), ca, -sa) < 0.0:
                    n_imp += _chatter_impacts(2.0 * abs(omega / acc0), e, dt)
                    tau = t_end
                    omega = 0.0
                    state = _REST
                    continue
            # a block that cannot come back to θ = 0 before dt (not a bounce of a chatter)
            hand_over = defer and _no_touch(0.0, omega, s, ua, ub, dt - tau, p2, sa)
            continue
        if abs(th1) >= th_ov:
            target = th_ov if th1 > 0.0 else -th_ov
            hz, thz, omz = _locate(theta, omega, s, u0, du, tau, 0.0, h, theta, th1, target, s,
                                   p2, sa, ca)
            t_event = tau + hz
            theta = thz
            omega = omz
            state = _OVERTURNED
            break
        theta = th1
        omega = om1
        break
    return theta, omega, s, state, n_imp, t_event, tau, t_start, false_side, False


@kernel
def _simulate_kernel(u, dt, p2, sa, ca, tan_a, e, th_ov, theta0, omega0, theta_out, omega_out):
    """Integrate one block over the whole motion ``u`` = a_g/g [-] sampled at dt [s].

    Writes θ [rad] and θ' [rad/s] at every sample into the output arrays (NaN after overturning).
    Returns (overturned, t_overturn [s] or NaN, n_impacts, max|θ| [rad]).
    """
    n = u.shape[0]
    theta = theta0
    omega = omega0
    if theta0 != 0.0:
        s = 1.0 if theta0 > 0.0 else -1.0
        state = _ROCKING
    elif omega0 != 0.0:
        s = 1.0 if omega0 > 0.0 else -1.0
        state = _ROCKING
    else:
        s = 1.0
        state = _REST
    theta_out[0] = theta
    omega_out[0] = omega
    n_imp = 0
    peak = abs(theta)
    t_ov = math.nan
    overturned = False
    if abs(theta) >= th_ov:
        overturned = True
        t_ov = 0.0
    for k in range(n - 1):
        if overturned:
            theta_out[k + 1] = math.nan
            omega_out[k + 1] = math.nan
            continue
        theta, omega, s, state, ni, tev = _advance(
            theta, omega, s, state, u[k], u[k + 1], dt, p2, sa, ca, tan_a, e, th_ov)
        n_imp += ni
        if state == _OVERTURNED:
            overturned = True
            t_ov = k * dt + tev
            peak = th_ov
            theta_out[k + 1] = math.nan
            omega_out[k + 1] = math.nan
            continue
        theta_out[k + 1] = theta
        omega_out[k + 1] = omega
        if abs(theta) > peak:
            peak = abs(theta)
    return overturned, t_ov, n_imp, peak


@dataclass(frozen=True)
class RockingResponse:
    """Response of one block to one base motion.

    Attributes
    ----------
    t : ndarray
        Sample times [s].
    theta : ndarray
        Rotation θ [rad] at the samples (positive about corner O); NaN after overturning.
    omega : ndarray
        Angular velocity θ' [rad/s] at the samples; NaN after overturning.
    overturned : bool
        Whether |θ| reached the overturning angle.
    t_overturn : float
        Time of overturning [s], NaN if the block did not overturn.
    n_impacts : int
        Number of impacts (pivot changes at θ = 0); a chatter summed in closed form counts one
        impact per flight longer than ``ZENO_TIME_FRACTION·dt``.
    max_abs_theta : float
        Largest |θ| [rad] (the overturning angle if the block overturned).
    block, e, overturn_angle :
        The inputs that produced the response (e [-], overturn_angle [rad]).
    """

    t: np.ndarray
    theta: np.ndarray
    omega: np.ndarray
    overturned: bool
    t_overturn: float
    n_impacts: int
    max_abs_theta: float
    block: Block = field(repr=False)
    e: float = 0.925
    overturn_angle: float = math.pi / 2

    @property
    def theta_over_alpha(self) -> np.ndarray:
        """θ/α [-] at the samples."""
        return self.theta / self.block.alpha

    def summary(self) -> dict:
        """Plain-number summary (JSON-friendly)."""
        return {
            "R_m": self.block.R,
            "gamma": self.block.gamma,
            "alpha_rad": self.block.alpha,
            "e": self.e,
            "overturned": bool(self.overturned),
            "t_overturn_s": None if math.isnan(self.t_overturn) else float(self.t_overturn),
            "n_impacts": int(self.n_impacts),
            "max_abs_theta_rad": float(self.max_abs_theta),
            "max_abs_theta_over_alpha": float(self.max_abs_theta / self.block.alpha),
        }


def simulate(block: Block, ag, dt: float, *, e=0.925, overturn_angle=math.pi / 2,
             theta0: float = 0.0, omega0: float = 0.0, g: float = G) -> RockingResponse:
    """Rocking response of ``block`` to the ground acceleration history ``ag``.

    Parameters
    ----------
    block : Block
        The rigid block.
    ag : array_like, shape (n_t,)
        Horizontal ground acceleration [m/s²] at times 0, dt, 2·dt, … (linear in between).
    dt : float
        Sample interval [s]; also the Runge–Kutta step (the paper uses 1/400 s).
    e : float or "housner"
        Coefficient of restitution θ'⁺/θ'⁻ [-] in (0, 1]; the paper's 0.925 by default;
        ``"housner"`` gives 1 − 1.5·sin²α.
    overturn_angle : float or "alpha"
        |θ| [rad] at which the block counts as overturned: π/2 (the paper) or ``"alpha"``.
    theta0, omega0 : float
        Initial rotation [rad] and angular velocity [rad/s]; rest by default.
    g : float
        Gravity [m/s²].

    Returns
    -------
    RockingResponse
    """
    if not isinstance(block, Block):
        raise InputError(f"block must be a rocking.Block, got {type(block).__name__}")
    dt = positive("dt", dt, "s")
    g = positive("g", g, "m/s²")
    ag = finite_array("ag", ag, ndim=(1,), min_len=1)
    e_val = resolve_e(e, block)
    th_ov = resolve_overturn_angle(overturn_angle, block)
    theta0 = in_range("theta0", theta0, -math.pi / 2, math.pi / 2, unit="rad")
    try:
        omega0 = float(omega0)
    except (TypeError, ValueError):
        raise InputError(f"omega0 must be a number [rad/s], got {omega0!r}") from None
    if not math.isfinite(omega0):
        raise InputError(f"omega0 must be finite [rad/s], got {omega0!r}")
    alpha = block.alpha
    theta = np.empty_like(ag)
    omega = np.empty_like(ag)
    overturned, t_ov, n_imp, peak = _simulate_kernel(
        ag / g, dt, 3.0 * g / (4.0 * block.R), math.sin(alpha), math.cos(alpha), math.tan(alpha),
        e_val, th_ov, theta0, omega0, theta, omega)
    return RockingResponse(
        t=np.arange(ag.size) * dt, theta=theta, omega=omega, overturned=bool(overturned),
        t_overturn=float(t_ov), n_impacts=int(n_imp), max_abs_theta=float(peak), block=block,
        e=e_val, overturn_angle=th_ov)
