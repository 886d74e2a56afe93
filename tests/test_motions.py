"""Simulated ground motions (paper Section 3, Eq. 9), baseline correction (Section 4),
ensembles and the ``rocking motions`` command."""

from __future__ import annotations

import json
import math
from pathlib import Path

import numba
import numpy as np
import pytest
import scipy.fft
from click.testing import CliRunner
from scipy.integrate import cumulative_trapezoid, quad

import rocking.motions.baseline as baseline_module
import rocking.motions.ensemble as ensemble_module
import rocking.motions.synthesis as synthesis
from rocking.cli import main
from rocking.core import portable
from rocking.dynamics.body import G
from rocking.errors import InputError
from rocking.motions.baseline import baseline_correct
from rocking.motions.ensemble import Ensemble
from rocking.motions.envelopes import make_envelope
from rocking.motions.psd import PowerSpectrum
from rocking.motions.records import example_record_path, read_record
from rocking.motions.response import response_spectrum
from rocking.motions.synthesis import (
    generate,
    limit_peaks,
    member_phases,
    regenerate,
    spectral_fit,
    synthesize,
)
from rocking.motions.targets import rg160

#: Shipped with the package (1559 points at 0.02 s) and with the tests (16396 points at 0.005 s).
EL_CENTRO = str(example_record_path())
CHINO_HILLS = str(Path(__file__).parent / "data" / "RSN8883_14383980_13849360.AT2")


@pytest.fixture(scope="module")
def paper_ensemble():
    """200 motions with the paper's settings (compound, 20 s, 1/400 s, 100 frequencies from
    0.15 to 50 Hz, RG 1.60 at 5 %), by the paper's method alone (no iteration)."""
    return generate(200)


# --------------------------------------------------------------------------- reproducibility


def test_member_k_does_not_depend_on_ensemble_size():
    # Bit for bit, with baseline correction, and with the iterative correction (fixed pilot).
    np.testing.assert_array_equal(generate(5).acc, generate(10).acc[:5])
    small = generate(3, iterations=1, pilot=20)
    np.testing.assert_array_equal(small.acc, generate(6, iterations=1, pilot=20).acc[:3])


def test_result_does_not_depend_on_chunking_or_threads(monkeypatch):
    ref = generate(8)
    corrected = generate(5, iterations=1, pilot=5)  # peak limiting has its own kernel
    monkeypatch.setattr(synthesis, "CHUNK", 3)
    # tiles of the synthesis that split the members and samples unevenly (8 motions of 8001
    # samples)
    monkeypatch.setattr(synthesis, "TILE_SAMPLES", 1000)
    monkeypatch.setattr(synthesis, "TILE_MEMBERS", 3)
    np.testing.assert_array_equal(generate(8).acc, ref.acc)
    np.testing.assert_array_equal(generate(5, iterations=1, pilot=5).acc, corrected.acc)
    threads = numba.get_num_threads()
    try:
        numba.set_num_threads(1)
        np.testing.assert_array_equal(generate(8).acc, ref.acc)
        np.testing.assert_array_equal(generate(5, iterations=1, pilot=5).acc, corrected.acc)
    finally:
        numba.set_num_threads(threads)


def test_member_streams_are_the_spawned_children_of_the_seed():
    # reference.md §4: member k uses the k-th child of SeedSequence(seed).
    children = np.random.SeedSequence(7).spawn(4)
    expected = [np.random.default_rng(c).uniform(0, 2 * math.pi, 50) for c in children]
    np.testing.assert_array_equal(member_phases(7, range(4), 50), expected)
    assert np.all(
        (member_phases(0, range(20), 100) >= 0) & (member_phases(0, range(20), 100) < 2 * math.pi)
    )


def test_synthesis_is_eq9_evaluated_directly():
    # Eq. (9) at a few times with np.sin of the full argument, independent of the kernel's
    # sin/cos tables and angle-sum expansion: agreement to rounding (1e-9 of the PGA).
    ens = generate(2, duration=10.0, baseline=False, envelope="trapezoidal")
    m = ens.meta
    env = make_envelope("trapezoidal", 10.0)
    phases = member_phases(0, [1], m["n_freq"])[0]
    omega = 2 * np.pi * np.array(m["freqs_hz"])
    for i in (0, 1, 137, 2000, 3999, 4000):
        t = i * ens.dt
        direct = env(t) * np.sum(np.array(m["amplitudes"]) * np.sin(omega * t + phases))
        assert ens.acc[1, i] == pytest.approx(direct, abs=1e-9 * np.abs(ens.acc[1]).max())


@pytest.mark.parametrize("period", [1000, 2048])  # shorter than the record (periodic), longer
def test_fft_synthesis_on_a_uniform_grid_is_eq9_to_rounding(monkeypatch, period):
    # Frequencies f_j = q_j/(N·dt) take the inverse-FFT path (the direct kernel is disabled);
    # Eq. (9) written here independently with NumPy: I(t)·Σ_j A_j sin(2π f_j t + φ_kj).
    # Tolerance: the sum cannot exceed Σ A_j; the arguments 2π f_j t ≤ 2π·50 Hz·12 s ≈ 4e3 rad
    # carry an absolute rounding of ~4e3·1.1e-16 ≈ 5e-13 rad, and the 99-term sum and the FFT
    # (error ~ε·log2 N) add a few 1e-15 of Σ A_j: 1e-11·Σ A_j bounds them, while a wrong bin,
    # scale or phase would be off by order Σ A_j.
    def direct_kernel_called(*args):
        raise AssertionError("the direct sum was used on a uniform grid")

    monkeypatch.setattr(synthesis, "_superpose", direct_kernel_called)
    dt, env = 0.01, make_envelope("compound", 12.0)
    freqs = np.arange(5, 500, 5) / (period * dt)
    amps = np.random.default_rng(2).uniform(0.1, 2.0, freqs.size)
    spec = PowerSpectrum.from_amplitudes(freqs, amps, 8.0, 0.05)
    phases = member_phases(4, range(3), freqs.size)
    acc = synthesize(spec, env, dt, phases)
    t = np.arange(acc.shape[1]) * dt
    assert t[-1] == pytest.approx(12.0)
    for k in range(3):
        arg = 2 * np.pi * freqs[:, None] * t + phases[k][:, None]
        direct = env(t) * np.sum(amps[:, None] * np.sin(arg), axis=0)
        np.testing.assert_allclose(acc[k], direct, rtol=0, atol=1e-11 * amps.sum())


def test_log_spaced_frequencies_take_the_direct_sum(monkeypatch):
    # generate's log-spaced grid is not a uniform one: the FFT must not be used for it.
    monkeypatch.setattr(scipy.fft, "irfft", None)
    assert np.isfinite(generate(2, duration=2.0).acc).all()


def test_baseline_flag_only_applies_the_correction():
    # The pilot of the iterations is uncorrected, so the motion before correction is the same.
    raw = generate(4, baseline=False, iterations=1, pilot=10)
    cor = generate(4, baseline=True, iterations=1, pilot=10)
    np.testing.assert_array_equal(baseline_correct(raw.acc, raw.dt), cor.acc)
    np.testing.assert_array_equal(regenerate(cor, baseline=False).acc, raw.acc)


# --------------------------------------------------------------------------- baseline correction


def _velocity(acc, dt):
    return cumulative_trapezoid(acc, dx=dt, initial=0.0, axis=-1)


def test_baseline_correction_lowers_velocity_and_drift(paper_ensemble):
    # Minimum mean-square velocity: lower than before for every member (the uncorrected motion
    # is one of the candidates). The end velocity and the drift of displacement shrink on
    # average (measured: mean |v(T)| 0.23 → 0.08 m/s, mean |d(T)| 4.1 → 0.11 m for 200
    # motions at 1 g); bounds: factor 2 and 10.
    ens = paper_ensemble
    raw = regenerate(ens, baseline=False).acc
    v_raw, v_cor = _velocity(raw, ens.dt), _velocity(ens.acc, ens.dt)
    assert np.all((v_cor**2).mean(axis=1) < (v_raw**2).mean(axis=1))
    assert np.abs(v_cor[:, -1]).mean() < 0.5 * np.abs(v_raw[:, -1]).mean()
    d_raw, d_cor = _velocity(v_raw, ens.dt), _velocity(v_cor, ens.dt)
    assert np.abs(d_cor[:, -1]).mean() < 0.1 * np.abs(d_raw[:, -1]).mean()


def test_baseline_correction_is_imperceptible_on_acceleration(paper_ensemble):
    # Paper Section 4: "imperceptibly small" on the acceleration. Measured RMS(Δa)/RMS(a):
    # mean 1.0 %, worst 3.6 % of 200 motions; max |Δa| ≤ 2.6 % of the PGA. Bounds 2 % / 5 %.
    ens = paper_ensemble
    raw = regenerate(ens, baseline=False).acc
    rel = np.sqrt(((raw - ens.acc) ** 2).mean(axis=1) / (raw**2).mean(axis=1))
    assert rel.mean() < 0.02 and rel.max() < 0.05


def test_quadratic_acceleration_is_removed_completely():
    dt = 0.01
    t = np.arange(1501) * dt
    quadratic = 0.3 - 0.02 * t + 0.004 * t**2
    np.testing.assert_allclose(baseline_correct(quadratic, dt), 0.0, atol=1e-12)
    # a linear baseline on top of a motion is removed by order 1 and 2 alike
    motion = np.sin(2 * np.pi * 1.3 * t) * np.exp(-0.2 * t)
    for order in (1, 2):
        np.testing.assert_allclose(
            baseline_correct(motion + 0.05 - 0.01 * t, dt, order),
            baseline_correct(motion, dt, order),
            atol=1e-12,
        )


def _closed_form_baseline(omega, T, t):
    """reference.md §6 for a(t) = sin(ωt), v(t) = (1 − cos ωt)/ω: solve
    Σ_j (j+2)·T^(k+j+3)/(k+j+3)·C_j = ∫₀^T t^(k+1)·v dt (k = 0, 1, 2; quadrature of the exact
    v) and return the baseline Σ (k+1)(k+2)·C_k·t^k."""
    mat = np.array([[(j + 2) * T ** (k + j + 3) / (k + j + 3) for j in range(3)] for k in range(3)])
    rhs = [
        quad(lambda s, k=k: s ** (k + 1) * (1 - math.cos(omega * s)) / omega, 0, T, limit=200)[0]
        for k in range(3)
    ]
    c = np.linalg.solve(mat, rhs)
    return sum((k + 1) * (k + 2) * c[k] * t**k for k in range(3))


def test_baseline_matches_the_continuous_normal_equations_to_second_order():
    # The discrete (trapezoidal) normal equations converge to the continuous ones of
    # reference.md §6 with error O(dt²): < 1e-4 of the baseline at dt = 0.01 s, and halving dt
    # divides the error by 4 (3.5–4.5 allowed).
    omega, T = 2 * math.pi * 0.37, 10.0
    errors = []
    for n in (1000, 2000):
        t = np.linspace(0.0, T, n + 1)
        exact = _closed_form_baseline(omega, T, t)
        got = np.sin(omega * t) - baseline_correct(np.sin(omega * t), T / n)
        errors.append(np.abs(got - exact).max() / np.abs(exact).max())
    assert errors[0] < 1e-4
    assert 3.5 < errors[0] / errors[1] < 4.5


@pytest.mark.parametrize(
    "shape", [(2,), (7,), (9,), (3, 130), (3, 1001), (2, 3, 50), (2, 8194), (1, 12001)]
)
def test_trapezoidal_rules_are_scipys_bit_for_bit(shape):
    # The baseline correction integrates with its own compiled trapezoidal rules (importing
    # scipy.integrate is slow, NumPy's temporaries were most of the correction's time): they
    # must be SciPy's, the same operations in the same order, so exact equality (the correction
    # of a motion then has the bits it had with SciPy). The lengths cover every branch of
    # NumPy's pairwise summation that SciPy's sum goes through: fewer than 8 terms, one block of
    # at most 128, and ranges cut in halves once or many times (8193 terms: halves that are not
    # multiples of 8; 12,000: the correction's motions of 30 s at 400 Hz).
    from scipy.integrate import trapezoid

    y = np.random.default_rng(len(shape)).normal(size=shape) * 37.0
    for dx in (0.0025, 1 / 3):
        assert np.array_equal(baseline_module._trapezoid(y, dx), trapezoid(y, dx=dx))
        assert np.array_equal(
            baseline_module._cumulative_trapezoid(y, dx),
            cumulative_trapezoid(y, dx=dx, initial=0.0),
        )


@pytest.mark.parametrize("order", [0, 1, 2, 3])
def test_baseline_correct_is_the_scipy_normal_equations_bit_for_bit(order):
    # The correction of reference.md §6 formed with SciPy's trapezoidal rules and solved by
    # portable.lstsq, written out here with NumPy arrays: the compiled correction must give
    # these bits exactly (it does the same operations in the same order, motion by motion).
    from scipy.integrate import trapezoid

    rng = np.random.default_rng(order)
    dt = 0.0025
    for n_t in (order + 2, 9, 130, 12001):
        acc = rng.normal(size=(3, n_t)) * np.exp(rng.normal(size=(3, 1)))
        tau = np.linspace(0.0, 1.0, n_t)
        tau_k = np.cumprod(np.vstack([np.ones_like(tau), np.tile(tau, (order, 1))]), axis=0)
        basis_acc = (np.arange(order + 1)[:, None] + 1) * (np.arange(order + 1)[:, None] + 2)
        basis_acc = basis_acc * tau_k
        psi = cumulative_trapezoid(basis_acc, dx=dt, initial=0.0)
        gram = trapezoid(psi[:, None, :] * psi[None, :, :], dx=dt)
        vel = cumulative_trapezoid(acc, dx=dt, initial=0.0)
        rhs = np.stack([trapezoid(vel * p, dx=dt) for p in psi], axis=-1)
        coef = portable.lstsq(gram, rhs.T).T
        expected = acc - sum(coef[:, j, None] * basis_acc[j] for j in range(order + 1))
        assert np.array_equal(baseline_correct(acc, dt, order), expected)


def test_baseline_correct_input_checks_and_shapes():
    a = np.random.default_rng(1).normal(size=(3, 500))
    np.testing.assert_array_equal(baseline_correct(a, 0.01)[1], baseline_correct(a[1], 0.01))
    with pytest.raises(InputError, match="order"):
        baseline_correct(a, 0.01, order=-1)
    with pytest.raises(InputError, match="dt"):
        baseline_correct(a, 0.0)
    with pytest.raises(InputError, match="acc"):
        baseline_correct([1.0, np.nan, 2.0, 3.0], 0.01)


# --------------------------------------------------------------------------- fit to RG 1.60


def test_paper_method_alone_fits_rg160_loosely(paper_ensemble):
    # The paper's method (iterations=0) over 0.2–33 Hz, measured for 200 motions: mean PSA
    # 0.71 (0.2 Hz) to 1.20 (31 Hz) of RG 1.60, mean |deviation| 10.8 %. Below ~1 Hz an
    # oscillator completes too few cycles in T_e ≈ 14 s to reach the stationary response that
    # Eq. (6) assumes, so the fit is low there; near 33 Hz the mean PSA tends to the mean PGA
    # (1.19 g), above the 1 g ZPA. Bounds: [0.65, 1.30] and mean deviation < 15 %.
    fit = spectral_fit(paper_ensemble)
    assert fit.freqs_hz[0] >= 0.2 and fit.freqs_hz[-1] <= 33.0 and fit.freqs_hz.size > 80
    assert fit.ratio.min() > 0.65 and fit.ratio.max() < 1.30
    assert fit.mean_deviation < 0.15


def test_stiff_oscillators_follow_the_ground_so_the_zpa_is_the_mean_pga(paper_ensemble):
    # Why the PSD iteration alone cannot fit RG 1.60 (see generate's docstring): at 33 Hz the
    # 5 %-damped oscillator follows the ground, so the ensemble-mean PSA there is the mean PGA
    # whatever the 20–50 Hz components. Measured ratio 1.04 for 200 motions (the 15–26 Hz
    # content is slightly amplified); bound ±8 %, while the PGA itself is 19 % above the ZPA.
    psa_33 = response_spectrum(paper_ensemble.acc, paper_ensemble.dt, [33.0]).psa[:, 0] / G
    assert psa_33.mean() == pytest.approx(paper_ensemble.agx, rel=0.08)
    assert paper_ensemble.agx > 1.1


def test_iterative_correction_fits_rg160_within_10_percent():
    # Issue 3's criterion: 200 motions with the paper's settings (compound, 20 s, dt = 1/400 s,
    # 100 frequencies 0.15–50 Hz, RG 1.60 at 5 %), iterative correction on (2 PSD iterations on
    # a 200-member pilot, with peak limiting): the mean PSA is within ±10 % of RG 1.60 from 0.2
    # to 33 Hz, checked at 100 frequencies per decade with both ends (US SRP 3.7.1's density,
    # 223 frequencies: also between the fitted ones and at 33 Hz itself, which the fitted grid
    # skips). Measured 0.971–1.068, worst at 33 Hz, where the mean PSA is 1.05 × the mean PGA
    # (1.015 g); on the fitted frequencies alone ±3.6 %. n = 200 as in the issue. The pilot is
    # members 0–199 of the same seed, i.e. this ensemble; members 200–399, which the pilot
    # never saw, measured 0.957–1.070, and seed 1 0.971–1.071 (`rocking motions fit` prints
    # this check and plots it, with the paper's method alone: 0.701–1.238).
    ens = generate(200, iterations=2)
    fit = spectral_fit(ens, rg160, per_decade=100)
    assert fit.freqs_hz[0] == pytest.approx(0.2) and fit.freqs_hz[-1] == pytest.approx(33.0)
    assert fit.freqs_hz.size >= 220
    assert np.all(np.abs(fit.ratio - 1.0) < 0.10)
    # The peak limiting keeps the amplitudes of the PSD and lowers the PGA towards the ZPA.
    assert ens.agx == pytest.approx(1.0, abs=0.05)


def test_peak_limiting_keeps_the_power_and_lowers_the_peak():
    # limit_peaks changes phases only: the component amplitudes, hence the PSD and the energy
    # (mean square acceleration, equal to Σ A_j²/2 up to cross terms of a few %) are kept,
    # while the mean PGA of 20 motions whose untouched PGA is ~1.4 g falls to near the 1 g
    # limit (measured 1.37 → 1.02 g with 200 motions; bounds 1.05 g mean, 1.10 g each).
    # Phases of components with less than one beat against their neighbour over the record
    # (below 0.88 Hz for 20 s) are not touched; the others are.
    env = make_envelope("compound", 20.0)
    ens = generate(1, baseline=False)
    f = np.array(ens.meta["freqs_hz"])
    spec = PowerSpectrum.from_amplitudes(f, 1.15 * np.array(ens.meta["amplitudes"]), 14.0, 0.05)
    phases = member_phases(3, range(20), f.size)
    new = limit_peaks(spec, env, ens.dt, phases, G)
    before, after = (synthesize(spec, env, ens.dt, p) for p in (phases, new))
    assert np.abs(before).max(axis=1).mean() > 1.25 * G
    assert np.abs(after).max(axis=1).mean() < 1.05 * G
    assert np.abs(after).max() < 1.10 * G
    assert np.mean(after**2) == pytest.approx(np.mean(before**2), rel=0.03)
    locked = spec.domega / (2 * math.pi) * 20.0 < 1.0
    assert f[locked].max() < 0.88 < f[~locked].min()
    np.testing.assert_array_equal(new[:, locked], phases[:, locked])
    free = ~locked & (spec.amplitudes > 0)  # components with A_j = 0 are left out
    assert np.mean(np.abs(np.sin(new[:, free] - phases[:, free])) > 1e-6) > 0.9


# --------------------------------------------------------------------------- ensembles


def test_scaling_uses_one_factor_and_hits_agx(paper_ensemble):
    ens = paper_ensemble.scaled(0.6)
    assert ens.agx == pytest.approx(0.6, rel=1e-12)
    factor = ens.acc / paper_ensemble.acc
    np.testing.assert_allclose(factor[np.isfinite(factor)], 0.6 / paper_ensemble.agx, rtol=1e-12)
    assert ens.pga.shape == (200,) and np.std(ens.pga) > 0  # members keep their own PGA


def test_save_load_and_regenerate_are_identical(tmp_path, paper_ensemble):
    ens = paper_ensemble.subset([7, 3, 150]).scaled(0.45)
    path = ens.save(tmp_path / "ens.nc")
    back = Ensemble.load(path)
    np.testing.assert_array_equal(back.acc, ens.acc)
    assert back.dt == ens.dt and back.labels == ("sim-0007", "sim-0003", "sim-0150")
    assert back.meta == ens.meta and back.meta["seed"] == 0
    np.testing.assert_array_equal(regenerate(back).acc, ens.acc)


def test_generation_parameters_are_stored(tmp_path):
    import xarray as xr

    ens = generate(2, duration=12.0, envelope="trapezoidal", seed=11, iterations=0)
    with xr.open_dataset(ens.save(tmp_path / "e.nc"), engine=ensemble_module.NETCDF_ENGINE) as ds:
        attrs = dict(ds.attrs)
        assert ds["acc"].attrs["units"] == "m s-2" and ds["time"].attrs["units"] == "s"
    assert attrs["seed"] == 11 and attrs["envelope"] == "trapezoidal"
    assert attrs["duration"] == 12.0 and attrs["envelope_shape_rise"] == pytest.approx(1.2)
    assert attrs["kind"] == "simulated" and attrs["location"] == "ground"
    assert attrs["baseline"] == 1 and attrs["n_freq"] == 100


def test_ensemble_files_have_the_layout_xarray_gives_the_dataset(tmp_path):
    # Ensemble.save writes with scipy.io.netcdf_file (no xarray import); its file must be the
    # one xarray writes for the same Dataset, both ways: xarray reads it as that Dataset
    # (identical: values, dimensions, coordinates, attributes), and a file xarray wrote (as
    # the package did before) loads as the same ensemble. Labels with non-ASCII characters and
    # a vertical component included.
    import xarray as xr

    ens = generate(2, duration=4.0, seed=3)
    ens = Ensemble(ens.acc, ens.dt, ["Ridgecrest – CCC 000", "sim-1"], ens.meta, ens.acc / 3)
    attrs = {
        **ensemble_module._flat_attrs(ens.meta),
        "dt": ens.dt,
        "meta_json": json.dumps(ens.meta),
    }
    units = {"units": "m s-2"}
    expected = xr.Dataset(
        {
            "acc": (("member", "time"), ens.acc, {**units, "long_name": "ground acceleration"}),
            "av": (
                ("member", "time"),
                ens.av,
                {**units, "long_name": "vertical ground acceleration, up positive"},
            ),
        },
        coords={"member": list(ens.labels), "time": ("time", ens.t, {"units": "s"})},
        attrs=attrs,
    )
    with xr.open_dataset(ens.save(tmp_path / "new.nc"), engine="scipy") as ds:
        assert ds.identical(expected)
    (tmp_path / "old.nc").write_bytes(bytes(expected.to_netcdf(engine="scipy")))
    back = Ensemble.load(tmp_path / "old.nc")
    assert back.labels == ens.labels and back.meta == ens.meta and back.dt == ens.dt
    np.testing.assert_array_equal(back.acc, ens.acc)
    np.testing.assert_array_equal(back.av, ens.av)


def test_floor_ensembles_keep_their_location_and_cannot_regenerate():
    ground = generate(2, duration=4.0)
    floor = Ensemble(
        ground.acc * 2,
        ground.dt,
        ground.labels,
        {**ground.meta, "location": "floor 3 of paper-2.0"},
    )
    assert floor.meta["location"] == "floor 3 of paper-2.0" and not floor.simulated
    with pytest.raises(InputError, match="regenerate"):
        regenerate(floor)
    assert Ensemble(np.ones((2, 5)), 0.1).meta["location"] == "ground"


def test_from_records_resamples_and_pads():
    # El Centro (0.02 s) and Chino Hills (0.005 s) have different steps: without dt they are
    # refused with both steps named (the step, and the cost of the runs, is the user's choice).
    # With dt = 0.005 s El Centro is upsampled 4x by resample_poly: band-limited interpolation
    # keeps the original samples (every 4th) to within the pass-band ripple of its Kaiser
    # filter (beta = 5: about 0.2 %, Oppenheim & Schafer 7.6) of the PGA; it is shorter (31.16 s
    # against 81.97 s) and padded with zeros. Chino Hills, already at 0.005 s, is unchanged.
    ec, ch = read_record(EL_CENTRO), read_record(CHINO_HILLS)
    with pytest.raises(InputError, match=r"0\.005 s: RSN8883.*; 0\.02 s: ElCentro.*--dt"):
        Ensemble.from_records([EL_CENTRO, ch])
    ens = Ensemble.from_records([EL_CENTRO, ch], dt=0.005)
    assert ens.dt == 0.005 and ens.n_t == ch.acc.size
    assert ens.labels == (ec.name, ch.name)
    n_ec = 4 * (ec.acc.size - 1) + 1
    np.testing.assert_allclose(ens.acc[0, :n_ec:4], ec.acc, rtol=0, atol=2e-3 * ec.pga * G)
    assert np.all(ens.acc[0, n_ec:] == 0.0)
    np.testing.assert_array_equal(ens.acc[1], ch.acc)
    assert ens.meta["kind"] == "recorded" and ens.meta["record_dt"] == [0.02, 0.005]
    assert "resample_poly" in ens.meta["resampling"]["method"]
    assert ens.subset([1]).meta["sources"] == [str(ch.source)]
    assert Ensemble.from_records([EL_CENTRO], dt=0.01).n_t == 2 * (ec.acc.size - 1) + 1
    with pytest.raises(InputError, match="regenerate"):
        regenerate(ens)


def test_ensemble_input_checks():
    with pytest.raises(InputError, match="labels"):
        Ensemble(np.zeros((2, 10)), 0.01, ["a"])
    with pytest.raises(InputError, match="dt"):
        Ensemble(np.zeros((2, 10)), -0.01)
    with pytest.raises(InputError, match="indices"):
        Ensemble(np.zeros((2, 10)), 0.01).subset([5])
    with pytest.raises(InputError, match="seed"):
        generate(2, seed=-1)
    with pytest.raises(InputError, match="n must"):
        generate(0)
    with pytest.raises(InputError, match="envelope"):
        generate(2, envelope="sawtooth")
    ens = Ensemble(np.arange(10.0), 0.5)
    assert ens.n == 1 and not ens.acc.flags.writeable


def test_synthesize_checks_phase_columns():
    env = make_envelope("boxcar", 1.0)
    spec = PowerSpectrum.from_amplitudes(np.geomspace(1, 10, 5), np.ones(5), 1.0, 0.05)
    with pytest.raises(InputError, match="phases"):
        synthesize(spec, env, 0.01, np.zeros((2, 4)))


# --------------------------------------------------------------------------- command line


def test_cli_generate_and_show(tmp_path):
    runner = CliRunner()
    out = tmp_path / "ens.nc"
    res = runner.invoke(
        main,
        [
            "motions",
            "generate",
            "--n",
            "4",
            "--duration",
            "6",
            "--envelope",
            "boxcar",
            "--seed",
            "3",
            "--out",
            str(out),
        ],
    )
    assert res.exit_code == 0, res.output
    ens = Ensemble.load(out)
    assert ens.n == 4 and ens.meta["seed"] == 3 and ens.duration == pytest.approx(6.0)
    res = runner.invoke(
        main, ["motions", "show", str(out), "--agx", "0.6", "--out", str(tmp_path / "figs")]
    )
    assert res.exit_code == 0, res.output
    assert "max deviation" in res.output and "A_gx = 0.6 g" in res.output
    for name in ("baseline.png", "spectrum.png", "envelope.png"):
        assert (tmp_path / "figs" / name).stat().st_size > 10_000


def test_cli_fit_writes_figure_table_and_both_fits(tmp_path):
    # The one command of issue 3 (run with defaults for the 200-motion check; small here).
    res = CliRunner().invoke(
        main,
        [
            "motions",
            "fit",
            "--n",
            "6",
            "--duration",
            "8",
            "--iterations",
            "1",
            "--per-decade",
            "10",
            "--out",
            str(tmp_path),
        ],
    )
    assert res.exit_code == 0, res.output
    assert "paper's method alone" in res.output and "iterative correction" in res.output
    table = np.loadtxt(tmp_path / "fit.csv", delimiter=",", skiprows=1)
    assert table.shape == (24, 4)  # ceil(10·log10(33/0.2)) + 1 frequencies, 4 columns
    assert table[0, 0] == pytest.approx(0.2) and table[-1, 0] == pytest.approx(33.0)
    np.testing.assert_allclose(table[:, 1], rg160(table[:, 0]), rtol=1e-5)  # 6 digits in CSV
    assert (tmp_path / "fit.png").stat().st_size > 10_000


def test_cli_bad_input_is_one_line(tmp_path):
    runner = CliRunner()
    res = runner.invoke(main, ["motions", "generate", "--n", "0", "--out", str(tmp_path / "e")])
    assert res.exit_code != 0 and "Traceback" not in res.output
    res = runner.invoke(main, ["motions", "show", EL_CENTRO, "--out", str(tmp_path)])
    assert res.exit_code == 1 and "not a netCDF ensemble file" in res.output
    assert res.output.count("\n") == 1
