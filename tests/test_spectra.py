"""Target spectra (RG 1.60, tables), response spectra and the ``rocking spectrum`` command."""

from __future__ import annotations

import csv
import json
import math
from pathlib import Path

import numba
import numpy as np
import pytest
from click.testing import CliRunner
from scipy import signal

from rocking.cli import main
from rocking.dynamics.body import G
from rocking.errors import InputError
from rocking.motions.ensemble import Ensemble
from rocking.motions.records import example_record_path
from rocking.motions.response import (
    _free_vibration_extremum,
    _hermite_extremum,
    foh_coefficients,
    response_spectrum,
)
from rocking.motions.targets import RG160, TabulatedSpectrum, rg160
from rocking.plots.spectra import plot_mean_vs_target, plot_spectra

EL_CENTRO = str(example_record_path())  # shipped with the package

# US AEC Regulatory Guide 1.60 (1973), Table 1 (as in reference.md §3): damping, B, C, D.
RG160_TABLE = [
    (0.005, 4.96, 5.95, 3.20),
    (0.02, 3.54, 4.25, 2.50),
    (0.05, 2.61, 3.13, 2.05),
    (0.07, 2.27, 2.72, 1.88),
    (0.10, 1.90, 2.28, 1.70),
]
PGD_PER_G = 36 * 0.0254  # 36 in of peak ground displacement per g [m] (RG 1.60)


# --------------------------------------------------------------------------- RG 1.60


@pytest.mark.parametrize("zeta,b,c,d", RG160_TABLE)
@pytest.mark.parametrize("pga", [1.0, 0.35])
def test_rg160_control_points_exact(zeta, b, c, d, pga):
    # Control points of RG 1.60: A 33 Hz = ZPA, B 9 Hz = b·ZPA, C 2.5 Hz = c·ZPA and at
    # D 0.25 Hz SD = d·PGD. Exact up to rounding (1e-12).
    psa_d = d * PGD_PER_G * pga * (2 * math.pi * 0.25) ** 2 / G
    expected = [pga, b * pga, c * pga, psa_d]
    got = rg160([33.0, 9.0, 2.5, 0.25], damping=zeta, pga=pga)
    np.testing.assert_allclose(got, expected, rtol=1e-12)
    np.testing.assert_allclose(RG160(zeta, pga).sd(0.25), d * PGD_PER_G * pga, rtol=1e-12)


def test_rg160_published_value_at_d():
    # reference.md §3: at 5 % and 1 g, SD(0.25 Hz) = 2.05·36 in = 73.8 in and PSA ≈ 0.4716 g
    # (4 significant digits given, hence the 5e-5 tolerance).
    assert RG160().sd(0.25) / 0.0254 == pytest.approx(73.8, rel=1e-12)
    assert rg160(0.25) == pytest.approx(0.4716, abs=5e-5)


@pytest.mark.parametrize("zeta", [row[0] for row in RG160_TABLE] + [0.03])
def test_rg160_straight_on_log_log_axes_between_control_points(zeta):
    # A straight line in (ln f, ln PSA) means PSA at the geometric mean of two frequencies of a
    # segment is the geometric mean of their PSA (rounding only: 1e-12).
    spec = RG160(zeta, 0.6)
    for lo, hi in [(0.25, 2.5), (2.5, 9.0), (9.0, 33.0)]:
        f1, f2 = lo * 1.07, hi / 1.13
        mid = math.sqrt(f1 * f2)
        assert spec.psa(mid) == pytest.approx(math.sqrt(spec.psa(f1) * spec.psa(f2)), rel=1e-12)
    # The break points are real: slopes differ on the two sides of C and of B.
    slope = [
        math.log(spec.psa(hi) / spec.psa(lo)) / math.log(hi / lo)
        for lo, hi in [(0.25, 2.5), (2.5, 9.0), (9.0, 33.0)]
    ]
    assert slope[0] > slope[1] and slope[2] < 0.0


def test_rg160_outside_control_points():
    spec = RG160(0.05, 0.4)
    # Above 33 Hz PSA equals the ZPA.
    np.testing.assert_allclose(spec.psa([33.0, 40.0, 100.0, 1e4]), 0.4, rtol=1e-12)
    # Below 0.25 Hz the spectral displacement is constant.
    np.testing.assert_allclose(spec.sd([0.01, 0.1, 0.2]), spec.sd(0.25), rtol=1e-12)


def test_rg160_damping_interpolation_rule():
    # Documented rule: amplification factors linear in ln(damping) between tabulated values.
    w = math.log(0.03 / 0.02) / math.log(0.05 / 0.02)
    b3 = 3.54 + w * (2.61 - 3.54)
    assert rg160(9.0, damping=0.03) == pytest.approx(b3, rel=1e-12)
    # More damping, less response, at every frequency below 33 Hz (above it PSA = ZPA).
    f = np.geomspace(0.05, 32, 60)
    assert np.all(
        np.diff([rg160(f, damping=z) for z in (0.005, 0.01, 0.03, 0.06, 0.1)], axis=0) < 0
    )


def test_rg160_scaling_and_shape():
    f = np.geomspace(0.1, 50, 7).reshape(7, 1)
    assert RG160().psa(f).shape == (7, 1)
    np.testing.assert_allclose(RG160().scaled(0.3).psa(f), 0.3 * rg160(f), rtol=1e-12)
    assert RG160().scaled(0.3).pga == pytest.approx(0.3)
    # PSV = PSA·g/ω [m/s] (definition), checked at the 2.5 Hz control point: 3.13 g.
    assert RG160().psv(2.5) == pytest.approx(3.13 * G / (2 * math.pi * 2.5), rel=1e-12)


@pytest.mark.parametrize(
    "kw",
    [
        dict(damping=0.004),
        dict(damping=0.11),
        dict(damping=math.nan),
        dict(pga=0.0),
        dict(pga=-1.0),
    ],
)
def test_rg160_bad_parameters(kw):
    with pytest.raises(InputError, match=next(iter(kw))):
        RG160(**kw)


@pytest.mark.parametrize("f", [0.0, -1.0, math.nan, [1.0, math.inf]])
def test_rg160_bad_frequencies(f):
    with pytest.raises(InputError, match="freqs_hz"):
        rg160(f)


# --------------------------------------------------------------------------- tabulated spectra


def test_tabulated_reproduces_rg160_from_its_control_points():
    # Both use the same documented extrapolation (constant SD below, constant PSA above) and
    # log-log lines between points, so a table of the 4 control points is the RG 1.60 spectrum.
    spec = RG160(0.05, 0.6)
    ctrl = [0.25, 2.5, 9.0, 33.0]
    table = TabulatedSpectrum(ctrl[::-1], spec.psa(ctrl[::-1]), name="rg")  # unsorted on purpose
    f = np.geomspace(0.01, 300, 200)
    np.testing.assert_allclose(table.psa(f), spec.psa(f), rtol=1e-12)
    np.testing.assert_allclose(table.scaled(2.0).psa(f), 2.0 * spec.psa(f), rtol=1e-12)


def test_tabulated_from_csv_frequency_and_period(tmp_path):
    freq_file = tmp_path / "freq.csv"
    freq_file.write_text("# a comment\nFrequency (Hz),PSA (g)\n0.5,0.2\n2,0.8\n\n10,0.5\n")
    period_file = tmp_path / "period.csv"
    period_file.write_text("Period (s),PSA (g)\n0.1,0.5\n0.5,0.8\n2.0,0.2\n")
    a = TabulatedSpectrum.from_csv(freq_file, damping=0.05)
    b = TabulatedSpectrum.from_csv(period_file)
    f = np.geomspace(0.05, 100, 50)
    np.testing.assert_allclose(a.psa(f), b.psa(f), rtol=1e-12)
    assert a.name == "freq" and a.damping == 0.05
    np.testing.assert_allclose(a.psa([0.5, 2.0, 10.0]), [0.2, 0.8, 0.5], rtol=1e-12)
    # Documented extrapolation: constant SD below 0.5 Hz, constant PSA above 10 Hz.
    np.testing.assert_allclose(a.sd([0.05, 0.2]), a.sd(0.5), rtol=1e-12)
    np.testing.assert_allclose(a.psa([20.0, 100.0]), 0.5, rtol=1e-12)
    # Log-log line between rows: geometric mean of 2 and 10 Hz gets the geometric mean PSA.
    assert a.psa(math.sqrt(20.0)) == pytest.approx(math.sqrt(0.8 * 0.5), rel=1e-12)


@pytest.mark.parametrize(
    "text,match",
    [
        ("freq,psa\n1,0.5\n2,abc\n", r"line 3: not a number: 'abc'"),
        ("freq,psa\n1,0.5\n-2,0.3\n", r"line 3: frequency must be a finite number > 0"),
        ("freq,psa\n1,0.5\n2,0\n", r"line 3: PSA must be a finite number > 0"),
        ("freq,psa\n1,0.5\n2,0.6\n1.0,0.7\n", r"line 4: frequency 1 Hz repeats that of .*line 2"),
        ("T (s),psa\n1,0.5\n0.5,0.6\n1,0.7\n", r"line 4: period 1 s repeats that of .*line 2"),
        ("freq,psa\n1,0.5\n", r"at least 2 rows, got 1"),
        ("damping,psa\n1,0.5\n2,0.6\n", r"line 1: first column header 'damping'"),
        ("freq,psa\n1,0.5\n2\n", r"line 3: need 2 values, got 1"),
        ("", r"empty spectrum file"),
    ],
)
def test_tabulated_csv_errors_name_file_and_line(tmp_path, text, match):
    path = tmp_path / "bad.csv"
    path.write_text(text)
    with pytest.raises(InputError, match=match) as err:
        TabulatedSpectrum.from_csv(path)
    assert "bad.csv" in str(err.value)


@pytest.mark.parametrize(
    "text,match",
    [
        ("freq,psv\n1,50\n2,60\n", r"line 1: column 'psv': state the unit of PSV, cm/s or m/s"),
        # issue 49: a unit that is not understood was taken as a location name and PSA read as g
        (
            "freq,PSA [furlongs]\n1,5\n2,6\n",
            r"line 1: column 'PSA \[furlongs\]': unit 'furlongs' is not a unit of acceleration",
        ),
        ("freq,psv (in/hr)\n1,5\n2,6\n", r"column 'psv \(in/hr\)': unit 'in/hr' of PSV is not"),
        ("freq,psa_m_s2\n1,5\n2,6\n", r"column 'psa_m_s2': state the unit of PSA"),
        ("freq,sd_cm\n1,5\n2,6\n", r"line 1: need a column of PSA \[g\] or PSV"),
        (
            "freq,psv [m/s]\n1,0.5\n2,0\n",
            r"line 3: PSV must be a finite number > 0 \[psv \[m/s\]\]",
        ),
    ],
)
def test_tabulated_csv_column_errors(tmp_path, text, match):
    path = tmp_path / "bad.csv"
    path.write_text(text)
    with pytest.raises(InputError, match=match):
        TabulatedSpectrum.from_csv(path)


def test_tabulated_csv_psv_in_m_s_and_cm_s_and_column_order(tmp_path):
    # PSA [g] = ω·PSV/g: the same spectrum given as PSA, as PSV in m/s (period first) and as PSV
    # in cm/s after a notes column reads the same.
    f = [0.2, 1.0, 5.0]
    psa = [0.1, 0.6, 0.4]
    psv = [a * G / (2 * math.pi * x) for x, a in zip(f, psa)]  # [m/s]
    files = {
        "a.csv": "freq_hz,psa_g\n" + "".join(f"{x!r},{y!r}\n" for x, y in zip(f, psa)),
        "b.csv": "T (s),PSV (m/s)\n" + "".join(f"{1 / x!r},{y!r}\n" for x, y in zip(f, psv)),
        "c.csv": "notes,Frequency [Hz],psv [cm/s]\n"
        + "".join(f"x,{x!r},{100 * y!r}\n" for x, y in zip(f, psv)),
        # PSA in any unit of acceleration of rocking.motions.units (issue 49): m/s², gal
        "d.csv": "freq,PSA [m/s^2]\n" + "".join(f"{x!r},{y * G!r}\n" for x, y in zip(f, psa)),
        "e.csv": "freq,Sa (gal)\n" + "".join(f"{x!r},{y * G * 100!r}\n" for x, y in zip(f, psa)),
    }
    for name, text in files.items():
        (tmp_path / name).write_text(text)
        np.testing.assert_allclose(
            TabulatedSpectrum.from_csv(tmp_path / name).psa(f), psa, rtol=1e-13
        )


# --------------------------------------------------------------------------- response spectra


@pytest.mark.parametrize("zeta", [0.0, 0.02, 0.05, 0.10])
def test_step_response_peak(zeta):
    # A step of ground acceleration a0 from rest: u peaks at t = π/ωd with
    # |u|·ω²/a0 = 1 + exp(−ζπ/sqrt(1−ζ²)) (= 1.854468 at 5 %, reference.md §7). The record
    # (2 s) holds the peak of every oscillator (≥ 0.5 Hz); after the record the ground stops and
    # the free vibration from u ≈ −a0/ω² cannot exceed it. The peak between sub-steps is found by
    # cubic Hermite interpolation, error ≤ (ωh)⁴/384 ≈ 4e-4 at 10 steps per period.
    a0 = 0.3 * G
    freqs = np.geomspace(0.5, 45.0, 25)
    sp = response_spectrum(np.full(201, a0), 0.01, freqs, zeta)
    exact = 1.0 + math.exp(-zeta * math.pi / math.sqrt(1.0 - zeta * zeta))
    np.testing.assert_allclose(sp.psa / a0, exact, rtol=5e-4)
    if zeta == 0.05:
        assert exact == pytest.approx(1.854468, abs=1e-6)
    # With many steps per period the same peak comes out to ~1e-9 (Hermite error ∝ h⁴).
    fine = response_spectrum(np.full(201, a0), 0.01, freqs, zeta, steps_per_period=200)
    np.testing.assert_allclose(fine.psa / a0, exact, rtol=1e-8)


@pytest.mark.parametrize("ratio", [0.1, 0.25, 0.4])
def test_rectangular_pulse_peak_in_free_vibration(ratio):
    # Undamped oscillator, rectangular pulse of duration td ≤ T/2 (the record), then ground at
    # rest: the peak comes after the pulse, |u|max·ω²/a0 = 2·sin(π·td/T) (Chopra, Dynamics of
    # Structures, §4.8). The tail is evaluated in closed form, so only rounding remains.
    f, n = 1.0, 400
    td = ratio / f
    sp = response_spectrum(np.ones(n + 1), td / n, [f], damping=0.0)
    assert sp.psa[0] == pytest.approx(2.0 * math.sin(math.pi * ratio), rel=1e-9)


@pytest.mark.parametrize("zeta", [0.02, 0.05, 0.10])
def test_harmonic_at_resonance(zeta):
    # a(t) = A·sin(ωt) at the oscillator frequency: steady-state PSA = A/(2ζ) (reference.md §7).
    # The recurrence sees the piecewise-linear interpolant of the samples, whose component at f
    # has amplitude A·sinc²(f·dt) (linear interpolation is a convolution with a triangle of
    # width 2·dt). The record (150 cycles at 2 %, fewer at more damping) leaves a transient
    # of exp(−2πζ·n_cycles) ≤ 1e-8.
    f, amp, per_cycle = 2.0, 0.2 * G, 100
    cycles = math.ceil(18.5 / (2 * math.pi * zeta))
    dt = 1.0 / (per_cycle * f)
    t = np.arange(cycles * per_cycle + 1) * dt
    sp = response_spectrum(amp * np.sin(2 * math.pi * f * t), dt, [f], zeta)
    x = math.pi * f * dt
    expected = amp / (2 * zeta) * (math.sin(x) / x) ** 2
    assert sp.psa[0] == pytest.approx(expected, rel=1e-6)


def _lsim_peak(acc, dt, f, zeta, steps_per_period=400):
    """max |u| by scipy.signal.lsim on a fine grid of the same piecewise-linear input, with zeros
    after the record (acc[-1] must be 0), refined by a parabola through the 3 largest samples."""
    w = 2 * math.pi * f
    k = max(20, math.ceil(steps_per_period * dt * f))
    a = np.concatenate([acc, np.zeros(math.ceil(1.5 / (f * dt)) + 2)])
    fine_t = np.arange((a.size - 1) * k + 1) * (dt / k)
    sdof = signal.StateSpace([[0, 1], [-w * w, -2 * zeta * w]], [[0], [-1]], [[1, 0]], [[0]])
    _, y, _ = signal.lsim(sdof, np.interp(fine_t, np.arange(a.size) * dt, a), fine_t)
    y = np.abs(y)
    i = int(np.argmax(y))
    y0, y1, y2 = y[i - 1 : i + 2]
    return y1 - 0.125 * (y0 - y2) ** 2 / (y0 - 2 * y1 + y2)


@pytest.fixture(scope="module")
def random_motion():
    acc = np.random.default_rng(7).standard_normal(250)  # white noise [m/s²], dt = 0.01 s
    acc[-1] = 0.0  # so that "ground at rest after the record" is the same as zero padding
    return acc


FREQS_LSIM = np.array([0.3, 1.7, 6.0, 9.7, 23.0])


@pytest.fixture(scope="module")
def lsim_reference(random_motion):
    # Reference accuracy: parabola on 400 points per period, error ~(2π/400)⁴ ≈ 6e-8.
    return np.array([_lsim_peak(random_motion, 0.01, f, 0.05) for f in FREQS_LSIM])


def test_matches_lsim_on_random_motion(random_motion, lsim_reference):
    # Default (≥ 10 steps per period): cubic Hermite peak error ≤ (2π/10)⁴/384 ≈ 4e-4.
    sp = response_spectrum(random_motion, 0.01, FREQS_LSIM, 0.05)
    np.testing.assert_allclose(sp.sd, lsim_reference, rtol=5e-4)
    # 200 steps per period: Hermite error ≈ 3e-9, so agreement to the reference's accuracy.
    fine = response_spectrum(random_motion, 0.01, FREQS_LSIM, 0.05, steps_per_period=200)
    np.testing.assert_allclose(fine.sd, lsim_reference, rtol=1e-6)
    np.testing.assert_allclose(fine.psv, 2 * math.pi * FREQS_LSIM * lsim_reference, rtol=1e-6)


def test_rigid_oscillator_psa_tends_to_pga():
    # A very stiff oscillator follows the ground: PSA → PGA. The leading deviation is the damping
    # term 2ζ·ȧ/ω, so it shrinks like 1/f.
    # The record's 0.02 s step holds nothing above 25 Hz (response_spectrum refuses it), so the
    # record is given as its piecewise-linear interpolant sampled at 0.2 ms (the ground motion the
    # recurrence integrates exactly either way), whose Nyquist frequency is 2500 Hz.
    acc = np.loadtxt(EL_CENTRO, skiprows=4, usecols=range(8), max_rows=190).ravel() * G
    t = 0.02 * np.arange(acc.size)
    fine = np.interp(np.arange(100 * (acc.size - 1) + 1) * 0.0002, t, acc)
    sp = response_spectrum(fine, 0.0002, [100.0, 1000.0], 0.05)
    dev = sp.psa / np.abs(acc).max() - 1.0
    assert dev[1] < 1e-3 and dev[1] < dev[0] / 5


def test_shapes_linearity_and_thread_independence(random_motion):
    freqs = np.geomspace(0.2, 40, 9)
    stack = np.stack([random_motion, -2.0 * random_motion, np.roll(random_motion, 17)])
    sp = response_spectrum(stack, 0.01, freqs)
    assert sp.sd.shape == sp.psv.shape == sp.psa.shape == (3, 9)
    one = response_spectrum(random_motion, 0.01, freqs)
    assert one.psa.shape == (9,)
    np.testing.assert_array_equal(sp.psa[0], one.psa)
    # The system is linear and symmetric: acc → −2·acc doubles every ordinate (rounding only).
    np.testing.assert_allclose(sp.psa[1], 2.0 * one.psa, rtol=1e-12)
    # PSA = ω²·SD (definition)
    np.testing.assert_allclose(sp.psa, (2 * np.pi * freqs) ** 2 * sp.sd, rtol=1e-14)
    np.testing.assert_allclose(sp.mean().psa, sp.psa.mean(axis=0), rtol=1e-14)
    assert one.mean() is one
    threads = numba.get_num_threads()
    try:
        numba.set_num_threads(1)
        serial = response_spectrum(stack, 0.01, freqs)
    finally:
        numba.set_num_threads(threads)
    np.testing.assert_array_equal(serial.sd, sp.sd)


def _lone_oscillator_peak(a, dt, f, zeta, steps_per_period):
    """max |u| of one oscillator by the plain scalar recurrence, one sub-step after the other (the
    method of response_spectrum, reference.md §7), in Python floats: IEEE double arithmetic
    in the same order, without fused multiply-adds, as each SIMD lane of the kernel computes."""
    nsub = max(1, math.ceil(steps_per_period * dt * f - 1e-9))
    h = dt / nsub
    omega = 2 * math.pi * f
    c = foh_coefficients(np.array([omega]), zeta, np.array([h]))[0].tolist()
    u = v = peak = 0.0
    for a0, a1 in zip(a[:-1].tolist(), a[1:].tolist()):
        da = (a1 - a0) / nsub
        for k in range(nsub):
            g0, g1 = a0 + k * da, a0 + (k + 1) * da
            u1 = c[0] * u + c[1] * v + c[2] * g0 + c[3] * g1
            v1 = c[4] * u + c[5] * v + c[6] * g0 + c[7] * g1
            if v * v1 < 0.0:
                peak = max(peak, abs(_hermite_extremum.py_func(u, v, u1, v1, h)))
            peak = max(peak, abs(u1))
            u, v = u1, v1
    return max(peak, abs(_free_vibration_extremum.py_func(u, v, omega, zeta)))


@pytest.mark.parametrize("zeta,steps_per_period", [(0.05, 10), (0.0, 1), (0.3, 20)])
def test_simd_lanes_compute_what_a_lone_oscillator_does(zeta, steps_per_period):
    # The kernel integrates 16 oscillators side by side (16 motions at one frequency, or one
    # motion at 16 frequencies of one sub-step count) and evaluates the Hermite peak only where
    # it can raise the peak. Each lane does the same operations in the same order as a lone
    # oscillator (no fastmath: no reassociation, no fused multiply-add), so every result is the
    # same to the bit, whatever the grouping: 37 motions (3 blocks, the last padded), one motion
    # at a time, the motions in another order, and a plain scalar evaluation.
    rng = np.random.default_rng(11)
    dt = 0.01
    acc = rng.standard_normal((37, 300)) * np.geomspace(0.01, 10.0, 37)[:, None]
    acc[:, :40] = 0.0  # a quiet start: v = 0 exactly, no sign change
    acc[::2, :40] = -0.0  # in half the motions with zeros of the other sign (see _lane_steps)
    freqs = np.array([0.05, 0.7, 3.0, 9.5, 31.0, 48.0])  # 1 to 5 sub-steps at 10 per period
    batch = response_spectrum(acc, dt, freqs, zeta, steps_per_period=steps_per_period)
    for i in (0, 5, 36):
        one = response_spectrum(acc[i], dt, freqs, zeta, steps_per_period=steps_per_period)
        np.testing.assert_array_equal(one.sd, batch.sd[i])
        for j in (0, 3, 5):
            lone = _lone_oscillator_peak(acc[i], dt, freqs[j], zeta, steps_per_period)
            assert batch.sd[i, j] == lone
    perm = rng.permutation(37)
    shuffled = response_spectrum(
        acc[perm], dt, freqs[::-1], zeta, steps_per_period=steps_per_period
    )
    np.testing.assert_array_equal(shuffled.sd, batch.sd[perm][:, ::-1])
    np.testing.assert_array_equal(shuffled.psa, batch.psa[perm][:, ::-1])
    # the blocks of lanes are read from a read-only or a column-major ensemble the same way
    readonly = acc.copy()
    readonly.flags.writeable = False
    for other in (readonly, np.asfortranarray(acc)):
        again = response_spectrum(other, dt, freqs, zeta, steps_per_period=steps_per_period)
        np.testing.assert_array_equal(again.sd, batch.sd)


def test_lanes_of_long_periods_evaluate_every_extremum_to_the_same_peaks():
    # Where every lane's period spans _SPARSE_STEPS sub-steps or more, the SIMD loop tests only
    # the sign of v and evaluates the Hermite extremum at every change of sign (as the lone
    # oscillator below does) instead of only where the bound says it may raise the peak: the
    # same peaks, to the bit.  Here 500 sub-steps per period or more (steps_per_period=500):
    # dozens of changes of sign in 3 s at 5 Hz, a few at 0.45 Hz.
    rng = np.random.default_rng(5)
    dt = 0.01
    acc = rng.standard_normal((20, 300))
    freqs = np.array([0.2, 0.45, 1.0, 5.0])
    batch = response_spectrum(acc, dt, freqs, 0.05, steps_per_period=500)
    one = response_spectrum(acc[7], dt, freqs, 0.05, steps_per_period=500)
    np.testing.assert_array_equal(one.sd, batch.sd[7])
    for j in range(freqs.size):
        assert batch.sd[7, j] == _lone_oscillator_peak(acc[7], dt, freqs[j], 0.05, 500)


@pytest.mark.parametrize(
    "args,kw,match",
    [
        ((np.ones(10), 0.0, [1.0]), {}, "dt"),
        ((np.ones(10), -0.01, [1.0]), {}, "dt"),
        ((np.array([0.0, np.nan, 1.0]), 0.01, [1.0]), {}, r"acc contains a non-finite value .* 1"),
        ((np.ones(10), 0.01, [1.0, 0.0]), {}, "freqs_hz must be > 0"),
        ((np.ones(10), 0.01, [1.0, -2.0]), {}, "freqs_hz must be > 0"),
        ((np.ones(10), 0.01, [1.0]), dict(damping=1.0), "damping"),
        ((np.ones(10), 0.01, [1.0]), dict(steps_per_period=0), "steps_per_period"),
        ((np.ones((2, 2, 5)), 0.01, [1.0]), {}, "acc must have 1 or 2 dimension"),
        ((np.ones(1), 0.01, [1.0]), {}, "at least 2 sample"),
    ],
)
def test_response_spectrum_bad_input(args, kw, match):
    with pytest.raises(InputError, match=match):
        response_spectrum(*args, **kw)


# --------------------------------------------------------------------------- figures and CLI


def test_plots_have_log_axes_and_units():
    f = np.geomspace(0.1, 50, 30)
    fig = plot_spectra(f, [rg160(f), rg160(f, 0.02)], ["5 %", "2 %"], damping=0.05)
    ax = fig.axes[0]
    assert ax.get_xscale() == ax.get_yscale() == "log"
    assert "[Hz]" in ax.get_xlabel() and "[g]" in ax.get_ylabel()
    assert len(ax.get_lines()) == 2
    members = np.stack([rg160(f) * s for s in (0.9, 1.0, 1.1)])
    fig = plot_mean_vs_target(f, members, RG160())
    lines = fig.axes[0].get_lines()
    np.testing.assert_allclose(lines[0].get_ydata(), members.mean(axis=0))
    np.testing.assert_allclose(lines[1].get_ydata(), rg160(f))


def test_cli_spectrum(tmp_path):
    out_csv, out_png = tmp_path / "s.csv", tmp_path / "s.png"
    result = CliRunner().invoke(
        main, ["spectrum", EL_CENTRO, "--n", "20", "--csv", str(out_csv), "--plot", str(out_png)]
    )
    assert result.exit_code == 0, result.output
    assert "ElCentro1940_NS" in result.output and "PSA [g]" in result.output
    # Default fmax: 50 Hz, lowered to the record's Nyquist frequency 1/(2·0.02 s) = 25 Hz.
    assert result.output.startswith("fmax = 25 Hz: the Nyquist frequency")
    with open(out_csv, newline="") as fh:
        rows = list(csv.DictReader(fh))
    assert len(rows) == 20
    f, psa, psv, sd = (
        np.array([float(r[k]) for r in rows]) for k in ("freq_hz", "psa_g", "psv_cm_s", "sd_cm")
    )
    assert f[0] == pytest.approx(0.1) and f[-1] == pytest.approx(25.0)
    # Units of the columns: PSV = ω·SD and PSA = ω²·SD (definitions), SD in cm, PSV in cm/s,
    # PSA in g; 6 significant digits in the file, so each value is rounded by up to 5e-6 (the
    # frequency too).
    omega = 2 * np.pi * f
    np.testing.assert_allclose(psv, omega * sd, rtol=1.6e-5)
    np.testing.assert_allclose(psa, omega**2 * sd / 100 / G, rtol=2.1e-5)
    # Near the Nyquist frequency the oscillator is stiff: PSA approaches the PGA, 0.31882 g
    # (the largest |value| in the file), from above by the damping term (see the rigid-oscillator
    # test: 2ζ·ȧ/ω, a few % at 25 Hz for this record).
    assert 1.0 < psa[-1] / 0.31882 < 1.05
    assert out_png.stat().st_size > 0


def test_cli_spectrum_fmax_above_nyquist_is_an_error():
    # El Centro is sampled at 0.02 s: nothing above 25 Hz is in the record.
    result = CliRunner().invoke(main, ["spectrum", "example", "--fmax", "30"])
    assert result.exit_code == 1 and result.output.count("\n") == 1
    assert "--fmax 30 Hz is above the Nyquist frequency 1/(2 dt) = 25 Hz" in result.output
    result = CliRunner().invoke(main, ["spectrum", "example", "--fmax", "25", "--n", "5"])
    assert result.exit_code == 0 and "fmax =" not in result.output


def test_cli_spectrum_of_a_netcdf_ensemble_says_what_it_is(tmp_path):
    path = tmp_path / "motions.nc"
    Ensemble(np.zeros((2, 50)), 0.01).save(path)
    result = CliRunner().invoke(main, ["spectrum", str(path)])
    assert result.exit_code == 1 and result.output.count("\n") == 1
    assert "motions.nc: a netCDF (binary) file, not a ground-motion record" in result.output
    assert "--motions" in result.output and "not a finite number" not in result.output


def test_cli_spectrum_example_is_el_centro():
    # The word 'example' selects the shipped El Centro 1940 NS record (1559 points at 0.02 s,
    # largest |value| 0.31882 g: src/rocking/data/records/README.md).
    result = CliRunner().invoke(main, ["spectrum", "example", "--n", "5", "--fmax", "20"])
    assert result.exit_code == 0, result.output
    assert result.output.startswith("ElCentro1940_NS: 1559 samples at 0.02 s, PGA 0.3188 g")


def test_cli_spectrum_bad_input_is_one_line(tmp_path):
    bad = tmp_path / "bad.AT2"
    bad.write_text("header\nNPTS=  3, DT= .01 SEC\n0.1 0.2\n")
    result = CliRunner().invoke(main, ["spectrum", str(bad)])
    assert result.exit_code == 1
    assert result.output.count("\n") == 1 and "NPTS = 3" in result.output
    assert "Traceback" not in result.output
    result = CliRunner().invoke(main, ["spectrum", EL_CENTRO, "--fmin", "5", "--fmax", "1"])
    assert result.exit_code == 1 and "--fmin" in result.output


# ----------------------------------------------------------------------- spectrum files of ours

CHINO_HILLS = str(Path(__file__).parent / "data" / "RSN8883_14383980_13849360.AT2")


def _csv_columns(path):
    with open(path, newline="") as fh:
        rows = list(csv.DictReader(fh))
    return {k: [r[k] for r in rows] for k in rows[0]}


def test_spectrum_csv_of_several_records_is_read_one_record_at_a_time(tmp_path):
    # rocking spectrum --csv writes record,freq_hz,psa_g,psv_cm_s,sd_cm, one record after the
    # other: the reader takes PSA [g] against frequency of the record it is asked for.
    path = tmp_path / "two.csv"
    result = CliRunner().invoke(
        main, ["spectrum", "example", CHINO_HILLS, "--n", "30", "--csv", str(path)]
    )
    assert result.exit_code == 0, result.output
    cols = _csv_columns(path)
    with pytest.raises(
        InputError,
        match=r"holds 2 spectra \('ElCentro1940_NS', "
        r"'RSN8883_14383980_13849360'\): choose one",
    ):
        TabulatedSpectrum.from_csv(path)
    with pytest.raises(InputError, match=r"no single spectrum named 'Kobe'; the file holds"):
        TabulatedSpectrum.from_csv(path, select="Kobe")
    for record in ("ElCentro1940_NS", "RSN8883_14383980_13849360"):
        mine = [i for i, r in enumerate(cols["record"]) if r == record]
        f = np.array(cols["freq_hz"], float)[mine]
        table = TabulatedSpectrum.from_csv(path, select=record.lower())
        assert table.name == f"two:{record}"
        np.testing.assert_array_equal(table.freqs_hz, f)
        # at the knots the log-log interpolation returns the values (exp(log(x)) to round-off)
        np.testing.assert_allclose(table.psa(f), np.array(cols["psa_g"], float)[mine], rtol=1e-14)


def test_floor_spectra_csv_gives_psa_from_psv_of_the_chosen_floor(tmp_path):
    # rocking frame spectra --csv writes freq_hz and PSV [cm/s] of the ground and each floor.
    # PSA = ω·PSV/g (definition), so the table's PSV at its own frequencies is the file's.
    path = tmp_path / "floors.csv"
    result = CliRunner().invoke(
        main, ["frame", "spectra", "paper-0.5", "--n", "2", "--csv", str(path)]
    )
    assert result.exit_code == 0, result.output
    cols = _csv_columns(path)
    f = np.array(cols["freq_hz"], float)
    with pytest.raises(
        InputError,
        match=r"holds 6 spectra \('ground', 'floor 1', 'floor 2', "
        r"'floor 3', 'floor 4', 'floor 5'\)",
    ):
        TabulatedSpectrum.from_csv(path)
    for name, column in (
        ("floor 1", "psv_floor_1_cm_s"),
        ("FLOOR_5", "psv_floor_5_cm_s"),
        ("ground", "psv_ground_cm_s"),
    ):
        table = TabulatedSpectrum.from_csv(path, select=name)
        psv_cm_s = np.array(cols[column], float)
        np.testing.assert_allclose(100 * table.psv(f), psv_cm_s, rtol=1e-12)
        np.testing.assert_allclose(table.psa(f), psv_cm_s / 100 * 2 * np.pi * f / G, rtol=1e-12)


def test_assess_and_screen_take_the_spectra_our_commands_write(tmp_path):
    floors, records = tmp_path / "floors.csv", tmp_path / "rec.csv"
    runner = CliRunner()
    assert (
        runner.invoke(
            main, ["frame", "spectra", "paper-0.5", "--n", "2", "--csv", str(floors)]
        ).exit_code
        == 0
    )
    assert runner.invoke(main, ["spectrum", "example", "--csv", str(records)]).exit_code == 0
    cols = _csv_columns(floors)
    f = np.array(cols["freq_hz"], float)
    band = (f >= 0.04) & (f <= 0.6)
    # Available S_v is the largest PSV in 0.04–0.6 Hz; PSV is monotonic between the knots of a
    # log-log table, so it is the largest tabulated value in the band (energy.available_sv).
    rec = _csv_columns(records)
    rf = np.array(rec["freq_hz"], float)
    cases = (
        (f"{floors}:floor_2", np.array(cols["psv_floor_2_cm_s"], float)[band], 1e-9),
        # this file has PSA and PSV, each to 6 digits; the reader takes PSA, so the PSV it
        # gives back agrees with the file's to the rounding of the two columns
        (str(records), np.array(rec["psv_cm_s"], float)[(rf >= 0.04) & (rf <= 0.6)], 2e-5),
    )
    for spec, psv_cm_s, rtol in cases:
        result = runner.invoke(
            main, ["assess", "--bodies", "example", "--spectrum", spec, "--json"]
        )
        assert result.exit_code == 0, result.output
        available = json.loads(result.stdout)["sv_available_cm_s"]  # progress goes to stderr
        assert available == pytest.approx(psv_cm_s.max(), rel=rtol)
    result = runner.invoke(main, ["assess", "--bodies", "example", "--spectrum", str(floors)])
    assert result.exit_code == 1 and "choose one, e.g." in result.output
    result = runner.invoke(
        main,
        [
            "screen",
            "example",
            "--spectrum",
            f"{floors}:ground",
            "--frame",
            "paper-0.5",
            "--n",
            "4",
            "--out",
            str(tmp_path / "screen"),
        ],
    )
    assert result.exit_code == 0, result.output
    assert (tmp_path / "screen" / "report.html").is_file()


def test_cli_spectrum_step_is_record_dt_and_dt_still_works_for_now(tmp_path):
    # Issue 48: the step of a one-column file was --record-dt in motions import and --dt in
    # spectrum. It is --record-dt in both; --dt stays one release, with a warning. The record
    # is a 2 Hz cosine of 0.3 g at 0.01 s (50 samples per period, the first at its peak): PGA
    # 0.3 g; in gal 0.3 / 980.665 g.
    one = tmp_path / "one.txt"
    wave = (0.3 * math.cos(2 * math.pi * 2 * 0.01 * k) for k in range(400))
    one.write_text("".join(f"{a:.9f}\n" for a in wave))
    new = CliRunner().invoke(main, ["spectrum", str(one), "--record-dt", "0.01", "--n", "5"])
    assert new.exit_code == 0, new.output
    assert new.stdout.startswith("one: 400 samples at 0.01 s, PGA 0.3 g") and not new.stderr
    old = CliRunner().invoke(main, ["spectrum", str(one), "--dt", "0.01", "--n", "5"])
    assert old.exit_code == 0 and old.stdout == new.stdout, old.output
    assert old.stderr.startswith("warning: --dt of 'rocking spectrum' is renamed --record-dt")
    both = CliRunner().invoke(main, ["spectrum", str(one), "--dt", "0.01", "--record-dt", "0.01"])
    assert both.exit_code == 1 and "give --record-dt only" in both.output
    assert "--dt" not in CliRunner().invoke(main, ["spectrum", "--help"]).output
    # units in any usual spelling; others refused in one line
    gal = CliRunner().invoke(main, ["spectrum", str(one), "--record-dt", "0.01", "--units", "GAL"])
    assert gal.exit_code == 0 and "PGA 0.0003059 g" in gal.stdout, gal.output
    bad = CliRunner().invoke(main, ["spectrum", str(one), "--record-dt", "0.01", "--units", "ft"])
    assert bad.exit_code == 1 and bad.output.count("\n") == 1
    assert "--units: unit 'ft' is not a unit of acceleration" in bad.output
