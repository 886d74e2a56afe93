"""Accuracy of the fast trigonometry of the RK4 kernel (issue 6) against libm.

The kernel evaluates sin θ and cos θ once per step by polynomials
(rocking.dynamics.equation._sincos) and
the stage angles θ + δ by the angle-sum identities with Taylor polynomials of δ
(rocking.dynamics.equation._rot).  References: NumPy's sin/cos (the C library's, within 1 ulp of the
exact value), and for the rotation the same expression in x87 extended precision (64-bit
mantissa, 2^11 times finer than double).  The tolerances are a few units in the last place of
double precision: they hold for every x tried, and a coefficient wrong in its 14th digit would
break them.
"""

import math

import numba
import numpy as np
import pytest

from rocking.dynamics.equation import (
    ROTATION_DMAX,
    SINCOS_TINY,
    SINCOS_XMAX,
    _rk4_fast,
    _rk4_stages,
    _rot,
    _sincos,
)

ULP1 = np.spacing(1.0)  # 2.2e-16


@numba.njit
def _sincos_array(x):
    s = np.empty_like(x)
    c = np.empty_like(x)
    for i in range(x.size):
        s[i], c[i] = _sincos(x[i])
    return s, c


@numba.njit
def _rot_array(P, Q, d):
    out = np.empty_like(P)
    for i in range(P.size):
        out[i] = _rot(P[i], Q[i], d[i])
    return out


def test_polynomial_sin_cos_match_libm_over_the_rocking_range():
    # every step starts at |θ| < overturn angle ≤ π/2 < SINCOS_XMAX
    assert math.pi / 2 < SINCOS_XMAX
    x = np.linspace(0.0, SINCOS_XMAX, 1_000_001)
    x = np.concatenate([x, -x])
    s, c = _sincos_array(x)
    # measured: 2.2e-16 and 2.0e-16 (one ulp of values near 1); libm itself may be 1 ulp off
    assert np.abs(s - np.sin(x)).max() <= 1.05 * ULP1
    assert np.abs(c - np.cos(x)).max() <= 1.05 * ULP1
    # sin is odd and cos even bit for bit (mirror symmetry of the response, reference.md §2)
    half = x.size // 2
    np.testing.assert_array_equal(s[half:], -s[:half])
    np.testing.assert_array_equal(c[half:], c[:half])
    # small angles: sin x = x and cos x = 1 to the last bit where the series says so
    # (x²/6 and x²/2 below half an ulp for |x| < SINCOS_TINY), as _sincos_any assumes when it
    # skips the polynomials there
    tiny = np.concatenate(
        [
            [np.nextafter(SINCOS_TINY, 0.0), 1e-9, 1e-12, 5e-324, 0.0],
            np.geomspace(1e-300, SINCOS_TINY, 20001)[:-1],
        ]
    )
    tiny = np.concatenate([tiny, -tiny])
    st, ct = _sincos_array(tiny)
    np.testing.assert_array_equal(st, tiny)
    np.testing.assert_array_equal(ct, 1.0)


def test_rotation_formula_matches_extended_precision():
    rng = np.random.default_rng(7)
    n = 400_000
    P = rng.uniform(-2.0, 2.0, n)
    Q = rng.uniform(-2.0, 2.0, n)
    d = rng.uniform(-ROTATION_DMAX, ROTATION_DMAX, n)
    d[:5] = [ROTATION_DMAX, -ROTATION_DMAX, 0.0, 1e-9, -1e-6]
    got = _rot_array(P, Q, d)
    ld = np.longdouble
    exact = np.cos(d.astype(ld)) * P.astype(ld) + np.sin(d.astype(ld)) * Q.astype(ld)
    err = np.abs(got.astype(ld) - exact) / (np.abs(P) + np.abs(Q))
    # measured 1.6e-16: the Taylor terms left out are below 2.3e-17 (module constants), the
    # rest is double rounding of a handful of operations
    assert float(err.max()) <= 1.5 * ULP1


@pytest.mark.parametrize("seed", range(3))
def test_fast_step_equals_the_step_with_trig_at_every_stage(seed):
    # The two evaluate the same RK4 formula; only the way sin and cos of the stage angles are
    # obtained differs, so their steps differ by round-off only (a few ulp of θ'' at each
    # stage, times h).  Random states cover both pivots, all angles up to π/2, fast swings,
    # ground accelerations above the uplift threshold and, every other state, a vertical ground
    # acceleration (gv = 1 + a_v/g from 0.3 to 1.8, linear in the step; None: without one).
    rng = np.random.default_rng(seed)
    for i in range(2000):
        R, gamma = rng.uniform(0.3, 5.0), rng.uniform(1.5, 8.0)
        alpha = math.atan(1.0 / gamma)
        p2 = 3 * 9.80665 / (4 * R)
        s = rng.choice([-1.0, 1.0])
        theta = s * rng.uniform(0.0, math.pi / 2)
        h = rng.choice([1 / 400, 1 / 200, 1 / 100]) * rng.uniform(0.01, 1.0)
        omega = rng.uniform(-1.0, 1.0) * ROTATION_DMAX / h  # all offsets within the fast range
        u0, du = rng.uniform(-2.0, 2.0), rng.uniform(-200.0, 200.0)
        g0, dg = (rng.uniform(0.5, 1.6), rng.uniform(-20.0, 20.0)) if i % 2 else (None, None)
        args = (theta, omega, s, u0, du, g0, dg, 0.0, h, p2, math.sin(alpha), math.cos(alpha))
        th, om, dmax = _rk4_fast(*args)
        th_ref, om_ref = _rk4_stages(*args)
        if dmax > ROTATION_DMAX:
            continue  # _rk4 would use _rk4_stages itself
        gmax = 1.0 if g0 is None else g0 + abs(dg) * h
        accel_scale = p2 * (gmax + abs(u0) + abs(du) * h)  # bound of |θ''| over the step
        assert abs(om - om_ref) <= 8 * ULP1 * (abs(omega) + accel_scale * h)
        assert abs(th - th_ref) <= 8 * ULP1 * (abs(theta) + abs(omega) * h + accel_scale * h * h)
