"""Intensity functions (paper Fig. 2) and their equivalent duration (Eq. 7)."""

from __future__ import annotations

import math

import numpy as np
import pytest
from scipy.integrate import quad

from rocking.errors import InputError
from rocking.motions.envelopes import Boxcar, Compound, Trapezoidal, make_envelope

ENVELOPES = [
    Boxcar(20.0),
    Trapezoidal(20.0, rise=2.0, decay=6.0),
    Trapezoidal(13.0, rise=0.0, decay=0.0),
    Compound(20.0, t1=2.0, t2=12.0, c=0.25),
    Compound(30.0, t1=0.0, t2=5.0, c=0.0),
    Compound(10.0, t1=1.5, t2=10.0, c=3.0),
]


@pytest.mark.parametrize("env", ENVELOPES, ids=repr)
def test_equivalent_duration_closed_form_matches_quadrature(env):
    # Eq. (7): T_e = ∫₀ᵀ I dτ / max I. Independent value by adaptive quadrature (scipy quad) with
    # the kinks given as break points, max I from dense sampling; quad's error here is < 1e-10.
    T = env.duration
    points = [p for p in env.params().values() if 0.0 < p < T]
    points += [T - env.params()["decay"]] if isinstance(env, Trapezoidal) else []
    integral, _ = quad(lambda t: float(env(t)), 0.0, T, points=points or None, limit=200)
    peak = env(np.linspace(0.0, T, 200_001)).max()
    assert peak == pytest.approx(1.0, abs=1e-12)
    assert env.equivalent_duration() == pytest.approx(integral / peak, rel=1e-9)


@pytest.mark.parametrize("env", ENVELOPES, ids=repr)
def test_zero_outside_the_motion_and_between_zero_and_one(env):
    t = np.linspace(-5.0, env.duration + 5.0, 20_001)
    i = env(t)
    assert np.all((i >= 0.0) & (i <= 1.0))
    assert np.all(i[(t < 0.0) | (t > env.duration)] == 0.0)


def test_compound_shape_jennings_housner_tsai():
    # I = (t/t1)² rising, 1 on [t1, t2], exp(−c(t − t2)) after: continuous at t1 and t2.
    env = Compound(20.0, t1=2.0, t2=12.0, c=0.25)
    np.testing.assert_allclose(
        env([0.0, 1.0, 2.0, 7.0, 12.0, 16.0]),
        [0.0, 0.25, 1.0, 1.0, 1.0, math.exp(-1.0)],
        rtol=1e-15,
    )
    eps = 1e-9
    assert env(2.0 - eps) == pytest.approx(1.0, abs=1e-8)
    assert env(12.0 + eps) == pytest.approx(1.0, abs=1e-8)


def test_trapezoid_shape():
    env = Trapezoidal(20.0, rise=2.0, decay=6.0)
    np.testing.assert_allclose(
        env([0.0, 1.0, 2.0, 10.0, 14.0, 17.0, 20.0]),
        [0.0, 0.5, 1.0, 1.0, 1.0, 0.5, 0.0],
        atol=1e-15,
    )


def test_duration_rule_gives_the_common_20_s_compound_default():
    # reference.md §5: a common compound default for a 20 s motion is t1 = 2 s, t2 = 12 s,
    # c = 0.25 /s; the rule t1 = 0.1T, t2 = 0.6T, I(T) = exp(−2) reproduces it.
    env = make_envelope("compound", 20.0)
    assert (env.t1, env.t2, env.c) == pytest.approx((2.0, 12.0, 0.25), rel=1e-15)
    for T in (10.0, 15.0, 25.0, 30.0):
        env = make_envelope("compound", T)
        assert env(T) == pytest.approx(math.exp(-2.0), rel=1e-12)
        assert (env.t1 / T, env.t2 / T) == pytest.approx((0.1, 0.6), rel=1e-15)
    trap = make_envelope("trapezoidal", 30.0)
    assert (trap.rise, trap.decay) == pytest.approx((3.0, 9.0), rel=1e-15)
    assert make_envelope("Boxcar", 12.0) == Boxcar(12.0)


def test_equivalent_durations_of_the_rule_scale_with_duration():
    # With shapes proportional to T, T_e/T is a constant: 1 (boxcar), 0.8 (trapezoid),
    # 0.1/3 + 0.5 + (1 − e⁻²)/5 (compound).
    expected = {
        "boxcar": 1.0,
        "trapezoidal": 0.8,
        "compound": 0.1 / 3 + 0.5 + (1 - math.exp(-2.0)) / 5,
    }
    for name, ratio in expected.items():
        for T in (10.0, 20.0, 30.0):
            assert make_envelope(name, T).equivalent_duration() == pytest.approx(
                ratio * T, rel=1e-12
            )


def test_explicit_parameters_override_the_rule():
    env = make_envelope("compound", 20.0, c=0.5)
    assert (env.t1, env.t2, env.c) == pytest.approx((2.0, 12.0, 0.5))
    assert make_envelope("trapezoidal", 20.0, rise=1.0).decay == pytest.approx(6.0)


@pytest.mark.parametrize(
    "call, words",
    [
        (lambda: make_envelope("gaussian", 20.0), "envelope"),
        (lambda: make_envelope("compound", 20.0, rise=1.0), "rise"),
        (lambda: make_envelope("boxcar", 20.0, t1=1.0), "t1"),
        (lambda: make_envelope("compound", -1.0), "duration"),
        (lambda: Compound(20.0, t1=5.0, t2=4.0, c=0.2), "t1"),
        (lambda: Compound(20.0, t1=1.0, t2=21.0, c=0.2), "t2"),
        (lambda: Compound(20.0, t1=1.0, t2=2.0, c=-0.2), "c"),
        (lambda: Trapezoidal(10.0, rise=6.0, decay=5.0), "decay"),
    ],
)
def test_bad_parameters_are_named(call, words):
    with pytest.raises(InputError, match=words):
        call()
