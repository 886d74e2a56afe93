"""Overturning spectra under pulses (issue 46) against the closed forms of the literature, the
similarity of rocking blocks and the independent SciPy reference solver."""

from __future__ import annotations

import math

import numpy as np
import pytest
from scipy.optimize import brentq

from rocking import Block, simulate
from rocking.defaults import G
from rocking.dynamics.reference import simulate_reference
from rocking.errors import InputError
from rocking.montecarlo.pulse_spectrum import overturning_spectrum
from rocking.motions.pulses import pulse

#: A slender block, α = atan(1/100) = 0.0100 rad: the closed forms below linearise Eq. (1) in
#: θ and α, whose neglected terms are relatively of order α²/6 ≈ 2e-5.
SLENDER = Block(1.0, 100.0)
#: Relative tolerance on κ against a closed form: the reported amplitude lies up to rtol = 1e-4
#: above the computed threshold, plus the linearisation (2e-5) and the RK4 error at 200 samples
#: per period (7e-5 between 200 and 400 samples for a one-sine spectrum of R = 1 m, γ = 4).
KAPPA_RTOL = 3e-4


def _makris_roussos_eq27(omega: float) -> float:
    """κ of the first mode (no impact) under a half-sine pulse, Makris & Roussos (2000), Eq. (27):
    √(κ² − 1) + κ·exp(−(π − arcsin(1/κ))/Ω) = Ω."""

    def f(k):
        return math.sqrt(k * k - 1) + k * math.exp(-(math.pi - math.asin(1 / k)) / omega) - omega

    return brentq(f, 1.0 + 1e-12, 100.0, xtol=1e-14)


def test_half_sine_slender_limit_is_makris_roussos_eq27():
    omegas = np.array([1.0, 2.0, 4.0, 0.2])
    # the values printed in the issue (3 decimals) check our solution of Eq. (27)
    printed = [1.322, 1.801, 2.791]
    closed = [_makris_roussos_eq27(o) for o in omegas]
    np.testing.assert_allclose(closed[:3], printed, atol=5e-4)
    periods = 2 * np.pi / (omegas * SLENDER.p)
    ds = overturning_spectrum(SLENDER, "half-sine", periods, e=0.9, kappa_max=5.0)
    np.testing.assert_allclose(ds["omega_ratio"], omegas, rtol=1e-12)
    np.testing.assert_allclose(ds["kappa"], closed, rtol=KAPPA_RTOL)
    # the long pulse (Ω = 0.2, p·T_p = 31) is sampled finer than T_p/200: p·dt ≤ 0.05
    assert float(ds["dt"][3]) * SLENDER.p <= 0.05 < float(ds["period"][3]) / 200 * SLENDER.p
    # first mode: overturning without impact, and a half-sine has no other switch
    assert (ds["impacts_before_overturning"].sel(switch=0) == 0).all()
    assert ds.sizes["switch"] == 1


def test_rectangular_pulse_slender_limit_is_housner_1963():
    # Housner (1963): a rectangular pulse of duration t_d overturns a slender block from
    # κ = 1/(1 − exp(−p·t_d))
    p_td = np.array([0.2, 0.5, 1.0, 2.0])
    ds = overturning_spectrum(SLENDER, "rectangular", p_td / SLENDER.p, e=0.9, kappa_max=8.0)
    np.testing.assert_allclose(ds["kappa"], 1 / (1 - np.exp(-p_td)), rtol=KAPPA_RTOL)
    np.testing.assert_allclose(ds["overturning_amplitude"], ds["kappa"] * G / 100.0, rtol=1e-12)


def _zhang_makris_block() -> Block:
    # Zhang & Makris (2001): p = 2.14 rad/s, i.e. R = 3g/(4p²); α = 0.25 rad
    return Block(3 * G / (4 * 2.14**2), 1 / math.tan(0.25))


def test_one_sine_pulse_overturns_first_at_zhang_makris_2_22_g():
    # Zhang & Makris (2001): ω_p = 15.7 rad/s, restitution 0.9: first overturns at 2.22 g
    # (printed to 0.01 g: tolerance half of that); the block overturns after one impact, 8.2 s
    # after the pulse, within the default tail (21.2/p = 9.9 s)
    block = _zhang_makris_block()
    ds = overturning_spectrum(block, "one-sine", [2 * math.pi / 15.7], e=0.9, kappa_max=15.0)
    assert float(ds["overturning_amplitude"][0]) / G == pytest.approx(2.22, abs=0.005)
    assert ds["overturning_time"].values[0, 0] < ds["duration"].values[0] - 1.0
    assert float(ds["omega_ratio"][0]) == pytest.approx(15.7 / 2.14, rel=2e-3)  # p rounded
    # above the minimum the outcome switches back (a safe band) and again: alternating branches
    amps = ds["switch_amplitude"].values[0]
    over = ds["overturns"].values[0]
    n = int(np.isfinite(amps).sum())
    assert n >= 3 and np.all(np.diff(amps[:n]) > 0)
    assert list(over[:n]) == [k % 2 == 0 for k in range(n)]


def test_the_reference_solver_brackets_the_reported_minimum():
    # solve_ivp with located events (dynamics/reference.py) on the same sampled pulse: safe
    # just below the reported minimum, overturned just above it; margins: the bracket's width
    # rtol (1e-4) and the difference of the two integrators (RK4 at T_p/200 against DOP853 at
    # rtol 1e-10), 5e-4 in all (here both sides hold 2e-5 beyond the bracket)
    block = _zhang_makris_block()
    period = 2 * math.pi / 15.7
    ds = overturning_spectrum(block, "one-sine", [period], e=0.9, kappa_max=15.0)
    a_min = float(ds["overturning_amplitude"][0])
    dt = float(ds["dt"][0])
    assert dt == period / 200  # p·dt = 0.0043
    unit = pulse("one-sine", 1.0, period, dt, tail=ds.attrs["tail"])
    below = simulate_reference(block, a_min * (1 - 5e-4) * unit, dt, e=0.9)
    above = simulate_reference(block, a_min * (1 + 5e-4) * unit, dt, e=0.9)
    assert not below.overturned and above.overturned


def test_similar_blocks_rock_alike_against_p_t():
    # at fixed α, Ω and κ, θ/α against p·t is the same for every size R (Eq. 1 in τ = p·t
    # depends on α, Ω, κ and e only): with dt = T_p/200 each, sample k is the same p·t
    omega, kappa = 6.0, 2.0
    curves = []
    for R in (0.2, 2.0, 20.0):
        block = Block(R, 5.0)
        period = 2 * math.pi / (omega * block.p)
        dt = period / 200
        a = pulse("one-sine", kappa * G / 5.0, period, dt, tail=10 / block.p)
        r = simulate(block, a, dt, e=0.9)
        curves.append(r.theta_over_alpha)
        assert not r.overturned and r.n_impacts >= 5  # it rocks, with impacts
    for c in curves[1:]:
        # rounding only: p²·dt² is the same number up to a few ulps
        np.testing.assert_allclose(c, curves[0], rtol=0, atol=1e-9)
    # and so does the spectrum: κ(Ω) of a 10 times larger block is the same
    small, large = Block(0.5, 5.0), Block(5.0, 5.0)
    omegas = np.array([2.0, 6.0])
    k_small = overturning_spectrum(small, "one-sine", 2 * np.pi / (omegas * small.p), e=0.9)
    k_large = overturning_spectrum(large, "one-sine", 2 * np.pi / (omegas * large.p), e=0.9)
    np.testing.assert_allclose(k_small["kappa"], k_large["kappa"], rtol=1e-9)


def test_refusals_name_the_parameter():
    for kwargs, word in [
        ({"kappa_max": 1.0}, "kappa_max"),
        ({"samples_per_period": 201}, "samples_per_period"),
        ({"n_scan": 1}, "n_scan"),
        ({"n_scan": 2.5}, "n_scan must be an integer"),
        # the sizes' limits (rocking.core.checks.LIMITS), before any work
        ({"n_scan": 10**6}, "n_scan 1,000,000 is above the limit of 10,000 levels"),
        ({"samples_per_period": 10**6}, "samples_per_period 1,000,000 is above the limit"),
        ({"rtol": 0.5}, "rtol"),
        ({"nu": 0.3}, "gamma and nu"),
    ]:
        with pytest.raises(InputError, match=word):
            overturning_spectrum(SLENDER, "one-sine", [1.0], **kwargs)
    with pytest.raises(InputError, match="periods"):
        overturning_spectrum(SLENDER, "one-sine", [1.0, -1.0])


def test_with_friction_below_b_over_h_no_pulse_overturns_and_the_result_says_mu():
    # μ = 0.2 < B/H = 0.25: the base slips before the block can tip, and sliding with μ < tan α
    # cannot tip it (Shenton 1996): no amplitude of the scan overturns it, where the rigid-base
    # block overturns; the result records the friction it was computed with (issue 45)
    block = Block(1.0, 4.0)
    rigid = overturning_spectrum(block, "one-sine", [1.0], n_scan=20)
    sliding = overturning_spectrum(block, "one-sine", [1.0], n_scan=20, mu=0.2)
    assert np.isfinite(rigid["overturning_amplitude"]).all()
    assert np.isnan(sliding["overturning_amplitude"]).all()
    assert (sliding.attrs["mu"], sliding.attrs["mu_k"]) == (0.2, 0.2)
    assert "mu" not in rigid.attrs
