"""Idealised pulses (issue 46): each shape against its defining formula or an independent
property of it (its velocity, its impulse, the frequency at which its Fourier amplitude peaks)."""

from __future__ import annotations

import math

import numpy as np
import pytest
from scipy.integrate import cumulative_trapezoid

import rocking
from rocking.defaults import PULSE_SHAPES
from rocking.errors import InputError
from rocking.motions.pulses import pulse, pulse_duration


def test_sines_and_cosine_follow_their_formulas_and_end_with_the_tail():
    a_p, T, dt = 3.0, 0.8, 0.004
    w = 2 * math.pi / T
    for shape, end in [("half-sine", T / 2), ("one-sine", T), ("one-cosine", T)]:
        a = pulse(shape, a_p, T, dt, tail=1.0)
        t = np.arange(a.size) * dt
        on = t < end - 1e-12
        f = np.sin if shape != "one-cosine" else np.cos
        # the formulas of the module docstring (rounding only)
        np.testing.assert_allclose(a[on], a_p * f(w * t[on]), rtol=0, atol=1e-12)
        assert np.all(a[t > end + 1e-12] == 0.0)
        assert a.size == round((end + 1.0) / dt) + 1


def test_rectangle_and_cosine_carry_their_exact_impulse():
    # half the end's jump at its sample: the linear interpolant's integral (trapezoid) is the
    # pulse's velocity change a_p·t_d exactly, and 0 for the one-cosine (a whole cycle)
    a_p, T, dt = 2.0, 0.5, 0.01
    for shape, impulse in [("rectangular", a_p * T), ("one-cosine", 0.0)]:
        a = pulse(shape, a_p, T, dt, tail=0.2)
        assert np.trapezoid(a, dx=dt) == pytest.approx(impulse, abs=1e-12)


@pytest.mark.parametrize("shape", ["ricker", "ricker-antisymmetric"])
def test_ricker_wavelets_peak_at_a_p_and_at_the_frequency_one_over_t_p(shape):
    a_p, T, dt = 1.5, 0.5, 0.0005
    a = pulse(shape, a_p, T, dt, tail=50.0)  # the tail refines the Fourier grid (0.02 Hz)
    # the largest abs(a) is a_p (β normalises the antisymmetric one); 1e-5: a sample at most
    # half a step Δx = 2π·dt/(√3·T_p) off the peak drops by ½·abs(f''/f)·(Δx/2)² = 6.5e-6 for
    # the antisymmetric one (f''/f = −4 there), less for the symmetric one
    assert np.abs(a).max() == pytest.approx(a_p, rel=1e-5)
    # a second and a third derivative of a Gaussian: no net velocity change
    assert abs(np.trapezoid(a, dx=dt)) < 1e-9
    # their Fourier amplitude peaks at 1/T_p (Vassiliou & Makris 2011), within the grid step
    spec = np.abs(np.fft.rfft(a))
    f = np.fft.rfftfreq(a.size, dt)
    assert f[np.argmax(spec)] == pytest.approx(1 / T, abs=f[1])


def test_mavroeidis_papageorgiou_integrates_to_its_velocity_pulse():
    # Mavroeidis & Papageorgiou (2003), Eq. (2): v(t) = (A/2)(1 + cos(2πf_p τ/γ)) cos(2πf_p τ + ν)
    # on abs(τ) ≤ γ/(2f_p); our acceleration, integrated, must be it (A from the peak)
    T, dt, gam, nu = 1.2, 0.0005, 2.5, 0.7
    a = pulse("mavroeidis-papageorgiou", 4.0, T, dt, gamma=gam, nu=nu)
    # the sampled peak: at most half a step off the true one, ½·(2π/T_p)²·(1 + 1/γ²)·(dt/2)² ≈
    # 1.1e-6 below it
    assert np.abs(a).max() == pytest.approx(4.0, rel=3e-6)
    assert pulse_duration("mavroeidis-papageorgiou", T, gamma=gam) == pytest.approx(gam * T)
    v = cumulative_trapezoid(a, dx=dt, initial=0.0)
    tau = np.arange(a.size) * dt - gam * T / 2
    shape = 0.5 * (1 + np.cos(2 * np.pi * tau / (gam * T))) * np.cos(2 * np.pi * tau / T + nu)
    amp = np.dot(v, shape) / np.dot(shape, shape)
    # trapezoid error (dt/T)² ~ 2e-7 of the amplitude
    np.testing.assert_allclose(v, amp * shape, atol=1e-6 * abs(amp))
    # the same pulse from the specification string
    b = pulse("mavroeidis-papageorgiou:gamma=2.5,nu=0.7", 4.0, T, dt)
    np.testing.assert_array_equal(a, b)


def test_public_names_and_refusals():
    assert rocking.pulse is pulse and rocking.motions.pulse is pulse
    assert len(PULSE_SHAPES) == 7
    with pytest.raises(InputError, match="shape"):
        pulse("triangle", 1.0, 1.0, 0.01)
    with pytest.raises(InputError, match="gamma"):
        pulse("mavroeidis-papageorgiou", 1.0, 1.0, 0.01, gamma=0.9)
    with pytest.raises(InputError, match="gamma and nu"):
        pulse("one-sine", 1.0, 1.0, 0.01, nu=0.3)
    with pytest.raises(InputError, match="period"):
        pulse("one-sine", 1.0, -1.0, 0.01)
    with pytest.raises(InputError, match="tail"):
        pulse("one-sine", 1.0, 1.0, 0.01, tail=-1.0)
