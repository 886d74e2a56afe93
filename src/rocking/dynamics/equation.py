"""The rocking equation of motion (paper Eq. 1) and its Runge–Kutta step.

One form for both pivots (paper Eqs. 1–2, with the sign of Eq. 2's forcing term corrected so that
the response to −a_g is exactly −θ; reference.md §2):

    θ'' = −p²·[ sin(s·α − θ) + (a_g/g)·cos(s·α − θ) ],   s = sgn θ,   p² = 3g/(4R)      (Eq. 1)

General bodies and vertical ground motion (issue 16).  For a body with I_O = M·(r_g² + R²)
(:class:`rocking.Block` with ``r_g``) and a vertical ground acceleration a_v [m/s², up positive],
which adds to gravity in the frame of the ground (I_O·θ'' = −M·(g + a_v)·R·sin(sα − θ) −
M·a_g·R·cos(sα − θ)):

    θ'' = −(R/(r_g² + R²))·[ (g + a_v)·sin(s·α − θ) + a_g·cos(s·α − θ) ]
        = −p²·[ (1 + a_v/g)·sin(s·α − θ) + (a_g/g)·cos(s·α − θ) ],   p² = g·R/(r_g² + R²)  (Eq. 1)

so the kernels integrate u = a_g/g and the vertical factor gv = 1 + a_v/g, both linear between
samples; a block at rest lifts when abs(a_g) > (g + a_v)·tan α.  Without vertical motion gv is
``None`` rather than 1.0: the ``_gv_*`` helpers below are compiled per type and, given ``None``,
leave the horizontal-only arithmetic untouched, so such a run executes exactly the operations
(and gives exactly the bits) of Eq. (1) without a_v, at its speed.  With a_v the same source is
compiled a second time, with the factor.

Integration (the paper's scheme): classical fourth-order Runge–Kutta with a fixed step equal to the
motion's sample interval dt, the ground acceleration being linear between samples; within a step
the pivot is frozen (impacts: :mod:`rocking.dynamics.impacts`).

Trigonometry (speed; see :func:`_rk4_rotated`): sin θ and cos θ once per step by polynomials
(within 2.3e-16 of libm for abs(θ) ≤ π/2), and at the stage angles θ + δ by the angle-sum identities
with Taylor polynomials of the small offsets δ; a step with a large offset (abs(θ')·h > 1/32 rad)
evaluates sin and cos at every stage instead (:func:`_rk4_stages`).  tests/test_trig.py bounds
both against libm and against each other.  :func:`_plain_step` is branch-free: the batched kernel
(:mod:`rocking.dynamics.batch`) runs it in SIMD lanes, and :func:`rocking.simulate` takes the same
decision with it, so both agree bit for bit.

Pure compiled functions of scalars; no state.
"""

from __future__ import annotations

import math

from ..core.compile import fma, kernel

#: abs(x) [rad] up to which :func:`_sincos` is accurate (a step starts at abs(θ) < overturn
#: angle ≤ π/2).
SINCOS_XMAX = 1.5717963267948966
# sin x = x + x·z·R_s(z), cos x = 1 − z/2 + z²·R_c(z), z = x²: near-minimax polynomials R_s, R_c
# (Chebyshev interpolation of (sin x/x − 1)/z and (cos x − 1 + z/2)/z² on 0 ≤ z ≤ SINCOS_XMAX²,
# computed with 40-digit arithmetic, rounded to double), highest degree first.
_RS = (
    2.731344277439919e-15,
    -7.643962232442654e-13,
    1.6058977059718268e-10,
    -2.5052107613095433e-08,
    2.7557319219132584e-06,
    -0.0001984126984125486,
    0.008333333333333316,
    -0.16666666666666666,
)
_RC = (
    -1.5218134641974516e-16,
    4.777873882841319e-14,
    -1.1470712146057573e-11,
    2.0876756600920194e-09,
    -2.75573192215542e-07,
    2.4801587301579797e-05,
    -0.001388888888888888,
    0.041666666666666664,
)
#: abs(x) [rad] below which sin x and cos x round to x and 1.
SINCOS_TINY = 1e-8
#: Largest stage offset abs(δ) [rad] for which the RK4 stages use the rotation formulas of _rot.
ROTATION_DMAX = 1.0 / 32.0
# Taylor coefficients of sin δ (to δ⁷) and cos δ (to δ⁶); the first terms left out are below
# δ⁹/9! ≤ 8e-20 and δ⁸/8! ≤ 2.3e-17 for abs(δ) ≤ ROTATION_DMAX.
_T1, _T2, _T3 = -1.0 / 6.0, 1.0 / 120.0, -1.0 / 5040.0
_K1, _K2 = 1.0 / 24.0, -1.0 / 720.0


# --------------------------------------------------------------- the vertical factor gv = 1 + a_v/g
# Each takes gv (or its slope) as a float, or None for no vertical motion.  They are not
# inline="always": Numba settles their `is None` by the argument's type only in a function
# compiled on its own (LLVM inlines them afterwards).


@kernel
def _gv_times(gv, x):
    """gv·x, or x without vertical motion (gv None)."""
    if gv is None:
        return x
    return gv * x


@kernel
def _gv_fnms(dg, x, y):
    """y − dg·x (one fused multiply–add), or y without vertical motion (dg None)."""
    if dg is None:
        return y
    return fma(-dg, x, y)


@kernel
def _gv_at(g0, dg, tau):
    """gv at local time tau of a step, g0 + dg·tau (as u), or None."""
    if g0 is None:
        return None
    return fma(dg, tau, g0)


@kernel
def _gv_ends(g0, dg, tau, h):
    """gv at the start, middle and end of a step from tau to tau + h (as :func:`_u_ends` and
    :func:`_rk4_rotated` compute u there), or Nones."""
    if g0 is None:
        return None, None, None
    ga = fma(dg, tau, g0)
    return ga, fma(dg * 0.5, h, ga), fma(dg, h, ga)


@kernel
def _gv_slope(g0, g1, dt):
    """Slope (g1 − g0)/dt [1/s] of gv over a sample interval, or None."""
    if g0 is None:
        return None
    return (g1 - g0) / dt


@kernel
def _gv_max(ga, gb):
    """The larger of gv at the two ends of a step, or None."""
    if ga is None:
        return None
    return ga if ga > gb else gb


@kernel
def _gv_sample(av, k, sc, g):
    """gv = 1 + abs(sc)·a_v/g at sample k of ``av`` [m/s²] scaled by abs(sc) (a negative scale
    mirrors the horizontal motion only), or None when ``av`` is None."""
    if av is None:
        return None
    return 1.0 + abs(sc) * av[k] / g


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
    """(sin x, cos x) by polynomials, for abs(x) ≤ SINCOS_XMAX [rad] (see tests/test_trig.py for
    the accuracy); branch-free, so that it vectorizes."""
    z = x * x
    return fma(x * z, _horner(_RS, z), x), 1.0 - fma(-(z * z), _horner(_RC, z), 0.5 * z)


@kernel(inline="always")
def _rot(P, Q, d):
    """cos δ·P + sin δ·Q for abs(δ) ≤ ROTATION_DMAX (Taylor polynomials of sin δ and cos δ),
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
    """(sin x, cos x) for any x [rad], outside SIMD loops: (x, 1) for abs(x) < SINCOS_TINY, which is
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
def _accel(theta, s, u, gv, p2, sa, ca):
    """θ'' of Eq. (1) on pivot side ``s`` for ground acceleration ``u`` = a_g/g [-] and vertical
    factor ``gv`` = 1 + a_v/g [-] (or None)."""
    S, C = _sin_cos_terms(theta, s, sa, ca)
    return -p2 * fma(u, C, _gv_times(gv, S))


@kernel(inline="always")
def _rk4_fast(theta, omega, s, u0, du, g0, dg, tau, h, p2, sa, ca):
    """One RK4 step of length h from local time tau; u(τ) = u0 + du·τ (du per second), and
    gv(τ) = g0 + dg·τ (or None: no vertical motion).
    Branch-free (the batched kernel runs it in SIMD lanes): see :func:`_rk4_rotated`."""
    st, ct = _sincos(theta)
    return _rk4_rotated(theta, st, ct, omega, s, u0, du, g0, dg, tau, h, p2, sa, ca)


@kernel(inline="always")
def _rk4_rotated(theta, st, ct, omega, s, u0, du, g0, dg, tau, h, p2, sa, ca):
    """The RK4 step of :func:`_rk4_fast` given st, ct = sin θ, cos θ.

    Trigonometry: the stage angles are θ + δ with small δ (δ = h/2·θ'_1, h/2·θ'_2, h·θ'_3), so
    with S = sin(sα − θ), C = cos(sα − θ) (one :func:`_sincos` of θ per step) the bracket of
    Eq. (1) at θ + δ, ground acceleration u and vertical factor gv is

        gv·sin(sα − θ − δ) + u·cos(sα − θ − δ) = cos δ·(gv·S + u·C) + sin δ·(u·S − gv·C),

    evaluated by :func:`_rot` (gv·S is S when gv is None).  Valid when abs(θ) ≤ SINCOS_XMAX
    and every abs(δ) ≤ ROTATION_DMAX; returns (θ, θ', max abs(δ)) so that the caller can check
    the second condition.
    """
    k1w, Pm, Qm, Pb, Qb = _stage_terms(st, ct, s, u0, du, g0, dg, tau, h, p2, sa, ca)
    k2w, k3w, d23 = _rk4_middle(omega, k1w, Pm, Qm, h, p2)
    return _rk4_end(theta, omega, k1w, k2w, k3w, d23, Pb, Qb, h, p2)


@kernel(inline="always")
def _stage_terms(st, ct, s, u0, du, g0, dg, tau, h, p2, sa, ca):
    """What the stages of :func:`_rk4_rotated` take from θ and the ground motion (not from θ'):
    θ''_1 and the brackets P = gv·S + u·C, Q = u·S − gv·C at the middle (Pm, Qm) and the end
    (Pb, Qb) of the step."""
    ua, ub = _u_ends(u0, du, tau, h)
    um = fma(du * 0.5, h, ua)
    ga, gm, gb = _gv_ends(g0, dg, tau, h)
    S, C = _angle_terms(st, ct, s, sa, ca)
    # stage 1 at θ: −p²·(gv·S + u·C); at θ = 0 its sign is that of gv·s·sin α + u·cos α,
    # exactly the uplift test of _advance
    k1w = -p2 * fma(ua, C, _gv_times(ga, S))
    Pm = fma(um, C, _gv_times(gm, S))
    Qm = fma(um, S, -_gv_times(gm, C))
    Pb = fma(ub, C, _gv_times(gb, S))
    Qb = fma(ub, S, -_gv_times(gb, C))
    return k1w, Pm, Qm, Pb, Qb


@kernel(inline="always")
def _rk4_middle(omega, k1w, Pm, Qm, h, p2):
    """Stages 2 and 3 of :func:`_rk4_rotated`: θ''_2, θ''_3 and max(abs(δ_2), abs(δ_3))."""
    hh = 0.5 * h
    d2 = hh * omega
    k2w = -p2 * _rot(Pm, Qm, d2)
    d3 = hh * fma(hh, k1w, omega)
    k3w = -p2 * _rot(Pm, Qm, d3)
    a2 = abs(d2)
    a3 = abs(d3)
    return k2w, k3w, a2 if a2 > a3 else a3


@kernel(inline="always")
def _rk4_end(theta, omega, k1w, k2w, k3w, d23, Pb, Qb, h, p2):
    """Stage 4 of :func:`_rk4_rotated` and the step: (θ, θ', max abs(δ))."""
    d4 = h * fma(0.5 * h, k2w, omega)
    k4w = -p2 * _rot(Pb, Qb, d4)
    # θ_1 = θ + h/6·(θ'_1 + 2θ'_2 + 2θ'_3 + θ'_4) = θ + h·(θ' + h/6·(θ''_1 + θ''_2 + θ''_3))
    th = fma(h, fma(h / 6.0, k1w + k2w + k3w, omega), theta)
    om = fma(h / 6.0, (k1w + k4w) + 2.0 * (k2w + k3w), omega)
    a4 = abs(d4)
    return th, om, d23 if d23 > a4 else a4


@kernel(inline="always")
def _fast_valid(theta, dmax):
    """Whether :func:`_rk4_fast`'s result with this start angle and max abs(δ) is the RK4 step."""
    return (dmax <= ROTATION_DMAX) & (abs(theta) <= SINCOS_XMAX)


@kernel
def _rk4_stages(theta, omega, s, u0, du, g0, dg, tau, h, p2, sa, ca):
    """The RK4 step of :func:`_rk4_fast` with θ'' evaluated afresh at every stage angle
    (:func:`_accel`): valid for any step, and the reference for the fast one's accuracy."""
    ua, ub = _u_ends(u0, du, tau, h)
    um = fma(du * 0.5, h, ua)
    ga, gm, gb = _gv_ends(g0, dg, tau, h)
    hh = 0.5 * h
    k1w = _accel(theta, s, ua, ga, p2, sa, ca)
    k2w = _accel(theta + hh * omega, s, um, gm, p2, sa, ca)
    k3w = _accel(theta + hh * fma(hh, k1w, omega), s, um, gm, p2, sa, ca)
    k4w = _accel(theta + h * fma(hh, k2w, omega), s, ub, gb, p2, sa, ca)
    th = fma(h, fma(h / 6.0, k1w + k2w + k3w, omega), theta)
    om = fma(h / 6.0, (k1w + k4w) + 2.0 * (k2w + k3w), omega)
    return th, om


@kernel
def _rk4(theta, omega, s, u0, du, g0, dg, tau, h, p2, sa, ca):
    """One RK4 step of length h from local time tau; u(τ) = u0 + du·τ (du per second), gv(τ) =
    g0 + dg·τ (or None).

    :func:`_rk4_fast` where it is valid (nearly always), else :func:`_rk4_stages` (a very fast
    block: abs(θ')·h > ROTATION_DMAX).
    """
    st, ct = _sincos_any(theta)
    return _rk4_sc(theta, st, ct, omega, s, u0, du, g0, dg, tau, h, p2, sa, ca)


@kernel
def _rk4_sc(theta, st, ct, omega, s, u0, du, g0, dg, tau, h, p2, sa, ca):
    """:func:`_rk4` given st, ct = sin θ, cos θ (partial steps from one state share them)."""
    th, om, dmax = _rk4_rotated(theta, st, ct, omega, s, u0, du, g0, dg, tau, h, p2, sa, ca)
    if _fast_valid(theta, dmax):
        return th, om
    return _rk4_stages(theta, omega, s, u0, du, g0, dg, tau, h, p2, sa, ca)


@kernel(inline="always")
def _no_touch(theta, omega, s, ua, ub, ga, gb, h, p2, sa):
    """True when the block, at s·θ ≥ 0 on side s, cannot reach θ = 0 within a step of length h.

    While 0 ≤ s·θ ≤ π/2, Eq. (1) gives −s·θ'' = p²·[gv·sin(α − sθ) + s·u·cos(α − sθ)] ≤
    p²·(max gv·sin α + max(0, s·u)) = a⁺ (gv > 0; u and gv are linear in the step: their largest
    values are at an end), so s·θ(τ) ≥ s·θ + s·θ'·τ − ½a⁺τ², a concave bound whose minimum over
    [0, h] is at an end: s·θ ≥ 0 at τ = 0, and the test at τ = h.  ``ua``, ``ub``: u at the
    ends of the step; ``ga``, ``gb``: gv there (or None: gv = 1).
    """
    return _clear_of_zero(theta, omega, s, h, _pull_bound(s, ua, ub, ga, gb, p2, sa))


@kernel(inline="always")
def _pull_bound(s, ua, ub, ga, gb, p2, sa):
    """The bound a⁺ [rad/s²] of :func:`_no_touch`."""
    sua = _signed(s, ua)
    sub = _signed(s, ub)
    push = sua if sua > sub else sub  # ground acceleration towards θ = 0, if positive
    return p2 * (_gv_times(_gv_max(ga, gb), sa) + (push if push > 0.0 else 0.0))


@kernel(inline="always")
def _clear_of_zero(theta, omega, s, h, amax):
    """:func:`_no_touch` given its bound a⁺ = ``amax`` [rad/s²]."""
    return _signed(s, fma(omega, h, theta)) > (0.5 * h) * h * amax


@kernel(inline="always")
def _u_ends(u0, du, tau, h):
    """u at the start (tau) and end (tau + h) of a step, as :func:`_rk4_rotated` computes them."""
    ua = fma(du, tau, u0)
    return ua, fma(du, h, ua)


@kernel(inline="always")
def _uplifts(u, gv, sa, ca):
    """Whether ground acceleration u = a_g/g [-] lifts a block at rest under the vertical factor
    gv = 1 + a_v/g (None: 1): abs(u)·cos α > gv·sin α, rounded once, i.e. exactly the sign of θ''
    at θ = 0 in the RK4 stages (never a start with an acceleration of the wrong sign)."""
    return fma(abs(u), ca, -_gv_times(gv, sa)) > 0.0


@kernel(inline="always")
def _plain_step(theta, omega, s, u0, du, g0, dg, tau, h, p2, sa, ca, th_ov):
    """The RK4 step of a rocking block from local time tau to the end of its interval (h =
    dt − tau) and whether it is all that happens in it: no impact, no touch of θ = 0, no
    overturning, and the fast trigonometry valid.  Returns (θ_1, θ'_1, fast_valid, plain); the
    step equals :func:`_rk4`'s when fast_valid.  Branch-free (SIMD lanes of the batched kernel);
    :func:`_advance` takes the same decision with it, so both paths agree bit for bit.
    """
    st, ct = _sincos(theta)
    k1w, Pm, Qm, Pb, Qb, amax = _plain_terms(st, ct, s, u0, du, g0, dg, tau, h, p2, sa, ca)
    k2w, k3w, d23 = _rk4_middle(omega, k1w, Pm, Qm, h, p2)
    return _plain_step_end(theta, omega, s, k1w, k2w, k3w, d23, Pb, Qb, amax, h, p2, th_ov)


@kernel(inline="always")
def _plain_terms(st, ct, s, u0, du, g0, dg, tau, h, p2, sa, ca):
    """What :func:`_plain_step` takes from θ and the ground motion: the :func:`_stage_terms` and
    the bound a⁺ [rad/s²] of :func:`_no_touch` (:func:`_pull_bound`)."""
    ua, ub = _u_ends(u0, du, tau, h)
    ga, _gm, gb = _gv_ends(g0, dg, tau, h)
    k1w, Pm, Qm, Pb, Qb = _stage_terms(st, ct, s, u0, du, g0, dg, tau, h, p2, sa, ca)
    return k1w, Pm, Qm, Pb, Qb, _pull_bound(s, ua, ub, ga, gb, p2, sa)


@kernel(inline="always")
def _plain_step_end(theta, omega, s, k1w, k2w, k3w, d23, Pb, Qb, amax, h, p2, th_ov):
    """The end of :func:`_plain_step`: stage 4 and the step (:func:`_rk4_end`), and its tests
    (:func:`_plain_tests`), given what comes before them (:func:`_plain_terms`, and stages 2 and
    3 from :func:`_rk4_middle`).  The batched kernel computes each of these parts in a SIMD loop
    of its own."""
    th1, om1, dmax = _rk4_end(theta, omega, k1w, k2w, k3w, d23, Pb, Qb, h, p2)
    valid, plain = _plain_tests(theta, omega, s, th1, dmax, amax, h, th_ov)
    return th1, om1, valid, plain


@kernel(inline="always")
def _plain_tests(theta, omega, s, th1, dmax, amax, h, th_ov):
    """Whether the step from (θ, θ') on side s to θ_1 with max abs(δ) ``dmax`` (:func:`_rk4_end`)
    is :func:`_rk4`'s step (fast trigonometry valid) and whether it is plain: valid, θ_1 on the
    same side, no touch of θ = 0 within it (:func:`_no_touch` with its bound a⁺ = ``amax``), and
    abs(θ_1) below the overturning angle ``th_ov``."""
    valid = _fast_valid(theta, dmax)
    plain = (
        valid
        & (_signed(s, th1) > 0.0)
        & _clear_of_zero(theta, omega, s, h, amax)
        & (abs(th1) < th_ov)
    )
    return valid, plain
