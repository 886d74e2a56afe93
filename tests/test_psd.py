"""PSD from a target spectrum by the paper's method (Eqs. 5–8): peak factor, transfer term,
NNLS fit, and which conventions make simulated motions reproduce the target."""

from __future__ import annotations

import math

import numpy as np
import pytest
from scipy import signal
from scipy.integrate import quad

from rocking.dynamics.body import G
from rocking.errors import InputError
from rocking.motions.envelopes import make_envelope
from rocking.motions.psd import (
    DAVENPORT_CONSTANT,
    PAPER_CONSTANT,
    PowerSpectrum,
    log_frequencies,
    peak_factor,
    power_spectrum,
    transfer,
)
from rocking.motions.response import response_spectrum
from rocking.motions.synthesis import generate, spectral_fit
from rocking.motions.targets import RG160, rg160

# --------------------------------------------------------------------------- Eq. (6)


def _expected_peak(n_cycles: float) -> float:
    """E[max X]/σ of a stationary Gaussian process over n_cycles zero up-crossings, with
    up-crossings of high levels as a Poisson process: P(max < y) = exp(−N·exp(−y²/2)), y ≥ 0
    (Davenport 1964, whose formula is the asymptotic expansion of this integral)."""

    def integrand(y):  # 1 − P(max < y)
        return -math.expm1(-n_cycles * math.exp(-0.5 * y * y))

    value, _ = quad(integrand, 0.0, 20.0, points=[math.sqrt(2 * math.log(n_cycles))])
    return value


@pytest.mark.parametrize("n_cycles", [100.0, 1e3, 1e4, 1e5])
def test_davenport_constant_is_eulers_not_the_printed_one(n_cycles):
    # Against the exact expectation (quadrature): the formula with Euler's 0.5772 is within 1 %
    # for ≥ 100 cycles (its asymptotic error, measured 0.9 % at 100 cycles, 0.2 % at 1e5);
    # with the printed 5.772 it is 22–55 % too large over the same range.
    exact = _expected_peak(n_cycles)
    assert peak_factor(n_cycles, DAVENPORT_CONSTANT) == pytest.approx(exact, rel=0.01)
    assert peak_factor(n_cycles, PAPER_CONSTANT) > 1.2 * exact


@pytest.mark.parametrize("constant", [DAVENPORT_CONSTANT, PAPER_CONSTANT])
def test_peak_factor_guard_keeps_it_finite_and_monotone(constant):
    # The asymptotic formula diverges at ν·T_e = 1; the guard holds it at its minimum
    # 2·sqrt(c) below exp(c/2), so it is finite and never decreasing in ν·T_e.
    x = np.geomspace(0.01, 1e6, 2000)
    r = peak_factor(x, constant)
    assert np.all(np.isfinite(r))
    assert np.all(np.diff(r) >= -1e-12)
    assert r[0] == pytest.approx(2 * math.sqrt(constant), rel=1e-12)


def test_transfer_term_is_the_absolute_acceleration_frequency_response():
    # Eq. (6)'s second factor is |H(iω_j)| of the oscillator's absolute acceleration,
    # H(s) = (2hω_k s + ω_k²)/(s² + 2hω_k s + ω_k²): independent value from scipy.signal.
    h, wk = 0.05, 2 * math.pi * 3.0
    wj = np.geomspace(0.1, 300.0, 400)
    _, resp = signal.freqresp(([2 * h * wk, wk**2], [1.0, 2 * h * wk, wk**2]), wj)
    np.testing.assert_allclose(transfer(wk, wj, h), np.abs(resp), rtol=1e-10)
    # resonance: sqrt(1 + 4h²)/(2h)
    assert transfer(wk, wk, h) == pytest.approx(math.sqrt(1 + 4 * h * h) / (2 * h), rel=1e-14)


# --------------------------------------------------------------------------- Eqs. (5), (8)


def test_log_frequencies_and_increments_follow_the_paper():
    # 100 points from 0.15 to 50 Hz, equally spaced on a log scale; ω_j = ω_{j−1} + Δω_j.
    f = log_frequencies()
    assert f.size == 100 and f[0] == pytest.approx(0.15) and f[-1] == pytest.approx(50.0)
    ps = power_spectrum(rg160(f), f, 14.0)
    np.testing.assert_allclose(ps.omega[1:] - ps.domega[1:], ps.omega[:-1], rtol=1e-12)
    np.testing.assert_allclose(ps.S * ps.domega, ps.p, rtol=1e-12)  # Eq. (8)
    np.testing.assert_allclose(ps.amplitudes**2, 2 * ps.p, rtol=1e-12)  # one-sided S


def test_nnls_recovers_known_power_components():
    # Eq. (5) with a target built from known components p: R_t² = Σ_j p_j R_kj². The system is
    # consistent and the fit must return p (to the solver's rounding, 1e-8 relative).
    f = log_frequencies(40, 0.2, 40.0)
    te, h = 12.0, 0.05
    w = 2 * np.pi * f
    p_true = np.zeros(f.size)
    p_true[[5, 17, 30]] = [0.02, 0.1, 0.03]  # [g²]
    r2 = (peak_factor(f * te)[None, :] * transfer(w[:, None], w[None, :], h)) ** 2
    target = np.sqrt(r2 @ p_true)
    ps = power_spectrum(target, f, te, damping=h)
    np.testing.assert_allclose(ps.p / G**2, p_true, rtol=1e-8, atol=1e-12)


def test_fit_of_rg160_is_close_and_nonnegative():
    # NNLS: p ≥ 0; the fitted spectrum of Eq. (5), sqrt(Σ p R²), reproduces RG 1.60 within 3 %
    # from 0.2 to 25 Hz (measured worst 2.8 %, at 0.2 Hz). Above 25 Hz the model itself cannot
    # come down to the ZPA: every lower component passes to a stiff oscillator with transfer
    # → 1, so the fit stays 5–12 % above 1 g there (measured), as the motions do.
    f = log_frequencies()
    te = make_envelope("compound", 20.0).equivalent_duration()
    ps = power_spectrum(rg160(f), f, te)
    assert np.all(ps.p >= 0)
    r2 = (peak_factor(f * te)[None, :] * transfer(ps.omega[:, None], ps.omega[None, :], 0.05)) ** 2
    fitted = np.sqrt(r2 @ (ps.p / G**2))
    band = (f >= 0.2) & (f <= 25.0)
    np.testing.assert_allclose(fitted[band], rg160(f[band]), rtol=0.03)
    assert np.all(fitted[f > 30.0] > rg160(f[f > 30.0]))


def test_power_spectrum_rejects_bad_input():
    f = log_frequencies(10)
    with pytest.raises(InputError, match="psa_g"):
        power_spectrum(rg160(f)[:-1], f, 10.0)
    with pytest.raises(InputError, match="log scale"):
        power_spectrum(rg160(f), np.linspace(0.2, 30, 10), 10.0)
    with pytest.raises(InputError, match="convention"):
        power_spectrum(rg160(f), f, 10.0, convention="two-sided")
    with pytest.raises(InputError, match="equivalent_duration"):
        power_spectrum(rg160(f), f, 0.0)


# --------------------------------------------------------------------------- conventions


def test_synthesised_variance_equals_the_sum_of_power_components():
    # One-sided S: σ² = ∫₀^∞ S dω = Σ S_j Δω_j = Σ p_j. The time-and-ensemble mean of a² of
    # boxcar motions (I = 1) estimates σ²; the cross terms of 100 random-phase components
    # average out to a few % over 60 members × 20 s (measured 0.2 %; tolerance 5 %).
    ens = generate(60, envelope="boxcar", baseline=False)
    p = np.array(ens.meta["amplitudes"]) ** 2 / 2
    assert np.mean(ens.acc**2) == pytest.approx(p.sum(), rel=0.05)


def test_one_sided_convention_reproduces_the_target_and_the_printed_one_does_not():
    # reference.md §4: mixing one- and two-sided PSDs is a factor √2. With the paper's method
    # (no iteration), the mean PSA of 200 motions over 1–10 Hz — where the peak factor of
    # stationary theory applies (many cycles, short oscillator memory) — is 0.94 of RG 1.60 with
    # A = sqrt(2p) (one-sided) and hence 1.33 with the printed A = sqrt(4p) (the motions are
    # linear in A, so exactly √2 times). Tolerance: the one-sided ratio must lie in
    # [0.85, 1.10], where the printed one (× √2 ≥ 1.2) cannot.
    ens = generate(200)
    printed = generate(3, convention="as-printed")
    np.testing.assert_allclose(
        printed.meta["amplitudes"], math.sqrt(2) * np.array(ens.meta["amplitudes"]), rtol=1e-12
    )
    mid = spectral_fit(ens, band=(1.0, 10.0))
    ratio = mid.ratio.mean()
    assert 0.85 < ratio < 1.10
    assert math.sqrt(2) * ratio > 1.2


def test_printed_peak_constant_misses_the_target_and_the_paper_fig14():
    # Paper Section 8 / Fig. 14: 200 compound 20 s motions scaled to A_gx = 1.02 have a mean
    # PSV whose maximum over 0.04–0.6 Hz is 205.11 cm/s. Scaled to a common A_gx, the amplitude
    # convention cancels and only the spectral shape (set by the peak constant) matters:
    # Euler's constant gives 186 cm/s (−9 %), the printed 5.772 gives 146 cm/s (−29 %).
    # Tolerances: the paper's envelope parameters are unknown, so ±15 % for the default; the
    # printed constant must be further off than 20 %. The printed constant (with the printed
    # √4) also misses RG 1.60 itself: 0.40 of the target at 0.2 Hz (measured; bound 0.6).
    f_low = np.geomspace(0.04, 0.6, 30)
    max_psv = {}
    for constant in (DAVENPORT_CONSTANT, PAPER_CONSTANT):
        ens = generate(200, peak_constant=constant, convention="as-printed")
        psv = response_spectrum(ens.scaled(1.02).acc, ens.dt, f_low).mean().psv
        max_psv[constant] = 100 * psv.max()  # [cm/s]
    assert max_psv[DAVENPORT_CONSTANT] == pytest.approx(205.11, rel=0.15)
    assert abs(max_psv[PAPER_CONSTANT] / 205.11 - 1) > 0.20
    fit = spectral_fit(ens)  # the printed constant and √4, as in Eq. (6) and Eq. (3)
    assert fit.ratio[0] < 0.6


def test_target_damping_must_agree():
    with pytest.raises(InputError, match="damping"):
        generate(1, target=RG160(damping=0.02), damping=0.05)
    ens = generate(1, duration=2.0, target=RG160(damping=0.02))
    assert ens.meta["damping"] == 0.02


def test_power_spectrum_from_amplitudes_round_trip():
    f = log_frequencies(20)
    ps = PowerSpectrum.from_amplitudes(f, np.ones(20), 10.0, 0.05, "as-printed")
    np.testing.assert_allclose(ps.p, 0.25)  # A² = 4p as printed
