"""Intensity measures of motions (issue 16, part 2): closed forms, an independent SDOF solver,
the scaling law, the parser."""

from __future__ import annotations

import math

import numpy as np
import pytest
from scipy import signal

import rocking
from rocking.defaults import G
from rocking.errors import InputError
from rocking.motions.ensemble import Ensemble
from rocking.motions.intensity import (
    IntensityMeasure,
    im_scaling_exponent,
    intensity_measures,
    parse_im,
)
from rocking.motions.records import example_record_path
from rocking.motions.response import response_spectrum

ALL_IMS = [
    "pga",
    "pgv",
    "pgd",
    "sa(0.5)",
    "sa(1.0,0.02)",
    "psv(2.0)",
    "saavg(0.2:2.0)",
    "saavg(0.1:1:4,0.1)",
    "arias",
    "cav",
    "pgv/pga",
]


def _sine_burst(amp, f, cycles, dt, pad=1.0):
    """amp·sin(2πft) for ``cycles`` whole cycles, then ``pad`` seconds of rest."""
    n = round(cycles / (f * dt))
    t = np.arange(n + 1 + round(pad / dt)) * dt
    return np.where(t <= cycles / f + 1e-12, amp * np.sin(2 * math.pi * f * t), 0.0)


@pytest.fixture(scope="module")
def el_centro():
    return Ensemble.from_records([example_record_path()])


def test_sine_burst_closed_forms():
    # a = A·sin(ωt) over N cycles of period T0 = 1/f, then rest:
    #   v = (A/ω)(1 − cos ωt) ≥ 0, so PGV = 2A/ω (at t = T0/2, a sample here) and v = 0 after;
    #   d = (A/ω)t − (A/ω²)sin ωt grows monotonically, so PGD = d(N·T0) = 2πN·A/ω²;
    #   I_A = π/(2g)·A²·N·T0/2;  CAV = A·N·T0·2/π (mean of abs(sin) is 2/π);  PGV/PGA = 2/ω.
    # The code integrates the piecewise-linear interpolant of the samples exactly; it differs
    # from the sine by O((ω·dt)²/12) = 1.3e-5 relatively (ω·dt = 0.0126), hence rel 1e-4.
    amp, f, cycles, dt = 0.3 * G, 2.0, 3, 0.001
    w = 2 * math.pi * f
    ens = Ensemble(_sine_burst(amp, f, cycles, dt), dt, ["burst"])
    got = intensity_measures(ens, ["pga", "pgv", "pgd", "arias", "cav", "pgv/pga"]).loc["burst"]
    t_burst = cycles / f
    assert got["pga [g]"] == pytest.approx(0.3, rel=1e-4)
    assert got["pgv [m/s]"] == pytest.approx(2 * amp / w, rel=1e-4)
    assert got["pgd [m]"] == pytest.approx(2 * math.pi * cycles * amp / w**2, rel=1e-4)
    assert got["arias [m/s]"] == pytest.approx(math.pi / (2 * G) * amp**2 * t_burst / 2, rel=1e-4)
    assert got["cav [m/s]"] == pytest.approx(amp * t_burst * 2 / math.pi, rel=1e-4)
    assert got["pgv/pga [s]"] == pytest.approx(2 / w, rel=1e-4)


def test_displacement_of_a_velocity_pulse_returning_to_rest():
    # One full acceleration cycle a = A·sin(ωt) then its negative: v rises to 2A/ω and returns
    # to 0 at 1 T0, then goes to −2A/ω and back to 0 at 2 T0; d peaks at d(T0) = 2πA/ω² and
    # returns to 0 at 2 T0 (the symmetric pulse leaves no residual displacement). This checks
    # that PGD is the peak of abs(d) over the record, not its final value. Tolerance as above.
    amp, f, dt = 2.0, 1.0, 0.0005
    w = 2 * math.pi * f
    one = _sine_burst(amp, f, 1, dt, pad=0.0)
    acc = np.concatenate([one, -one[1:], np.zeros(1000)])
    ens = Ensemble(acc, dt)
    row = intensity_measures(ens, ["pgd", "pgv"]).iloc[0]
    assert row["pgd [m]"] == pytest.approx(2 * math.pi * amp / w**2, rel=1e-4)
    assert row["pgv [m/s]"] == pytest.approx(2 * amp / w, rel=1e-4)


def _lsim_psa(acc, dt, period, zeta, k=40):
    """Peak ω²·abs(u) [units of acc] of u'' + 2ζωu' + ω²u = −a by scipy.signal.lsim on a grid
    k times finer than dt (linear interpolation of a, as the recurrence assumes) with five
    periods of rest after the record, so the free vibration counts too."""
    w = 2 * math.pi / period
    a = np.concatenate([acc, np.zeros(math.ceil(5 * period / dt))])
    t = np.arange(a.size) * dt
    fine_t = np.arange((a.size - 1) * k + 1) * (dt / k)
    sdof = signal.lti([-1.0], [1.0, 2 * zeta * w, w * w])
    _, u, _ = signal.lsim(sdof, np.interp(fine_t, t, a), fine_t)
    return w * w * np.abs(u).max()


def test_sa_and_psv_against_response_spectrum_and_lsim(el_centro):
    # (1) The same numbers as rocking.response_spectrum at f = 1/T (the documented source).
    # (2) An independent solver: lsim of the SDOF on a 40× finer grid; its sampled peak is at
    #     most (π·dt_fine/T)²/2 ≈ 2e-6 low at T = 0.5 s and the recurrence's is within 4e-4 of
    #     the exact one (response_spectrum's docstring): rel 1e-3 covers both.
    periods, zeta = [0.5, 1.0, 2.0], 0.02
    ims = [f"sa({t},{zeta})" for t in periods] + [f"psv({t},{zeta})" for t in periods]
    df = intensity_measures(el_centro, ims)
    sp = response_spectrum(el_centro.acc[0], el_centro.dt, 1 / np.array(periods), zeta)
    np.testing.assert_allclose(df.iloc[0, :3], sp.psa / G, rtol=1e-12)
    np.testing.assert_allclose(df.iloc[0, 3:], sp.psv, rtol=1e-12)
    for j, t in enumerate(periods):
        ref = _lsim_psa(el_centro.acc[0], el_centro.dt, t, zeta) / G
        assert df.iloc[0, j] == pytest.approx(ref, rel=1e-3)
        # PSV = PSA/ω
        assert df.iloc[0, 3 + j] == pytest.approx(ref * G * t / (2 * math.pi), rel=1e-3)


def test_saavg_is_the_geometric_mean_over_log_spaced_periods(el_centro):
    # Definition (Eads et al. 2015): exp(mean ln Sa(T_i)) with T_i log-spaced from T1 to T2
    # inclusive: here 4 periods 0.1, 0.2154, 0.4642, 1 s at 10 % damping.
    ts = np.geomspace(0.1, 1.0, 4)
    df = intensity_measures(
        el_centro, ["saavg(0.1:1:4,0.1)", *[f"sa({float(t)!r},0.1)" for t in ts]]
    )
    assert df.iloc[0, 0] == pytest.approx(np.exp(np.log(df.iloc[0, 1:]).mean()), rel=1e-12)
    assert parse_im("saavg(0.2:2)").n_periods == 10  # the documented default


def test_scaling_exponents_hold_numerically(el_centro):
    # IM(λ·a) = λ^k·IM(a): each IM's ratio at λ = 2.5 gives k = ln(ratio)/ln λ, which must be the
    # declared exponent. Every computation is homogeneous in a, so the ratio differs from λ^k
    # only by rounding: relatively at most about n·ε for sums over the record's n = 1559
    # samples (Higham's bound, ε = 2.2e-16), 3.5e-13, so k by at most 3.5e-13/ln 2.5 < 1e-12
    # (measured: 2e-15).
    lam = 2.5
    base = intensity_measures(el_centro, ALL_IMS).iloc[0]
    scaled = intensity_measures(el_centro.scaled_by(lam), ALL_IMS).iloc[0]
    for name, col in zip(ALL_IMS, base.index):
        k = math.log(scaled[col] / base[col]) / math.log(lam)
        assert k == pytest.approx(im_scaling_exponent(name), abs=1e-12), name
    assert [im_scaling_exponent(s) for s in ("arias", "pgv/pga", "sa(1)")] == [2, 0, 1]


def test_dataframe_rows_are_motions_and_columns_carry_units(el_centro):
    two = Ensemble(np.vstack([el_centro.acc[0], 2 * el_centro.acc[0]]), el_centro.dt, ["a", "b"])
    df = rocking.intensity_measures(two, "pga")  # a single name is accepted
    assert list(df.index) == ["a", "b"] and df.index.name == "motion"
    assert list(df.columns) == ["pga [g]"]
    np.testing.assert_allclose(df["pga [g]"], two.pga)
    df = intensity_measures(two, ALL_IMS)
    assert list(df.columns) == [parse_im(s).column for s in ALL_IMS]
    # El Centro 1940 NS: PGA 0.319 g in the PEER file's header (±0.001 g: rounding of the file)
    assert df.loc["a", "pga [g]"] == pytest.approx(0.319, abs=1e-3)


def test_parser_names_labels_and_equality():
    sa1 = IntensityMeasure("sa", (1.0,), 0, 0.05)
    assert parse_im(" SA( 1.0 ) ") == parse_im("sa(1,0.05)") == sa1
    assert parse_im("sa(1.0)").name == "sa(1)"
    assert parse_im("sa(0.5,0.02)").name == "sa(0.5,0.02)"
    assert parse_im("saavg(0.2:2.0:10)").name == "saavg(0.2:2)"
    assert parse_im("saavg(0.2:2.0:20)").name == "saavg(0.2:2:20)"
    assert parse_im("pgv [m/s]") == parse_im("PGV")
    assert parse_im("pgv").column == "pgv [m/s]"
    assert parse_im("sa(1)").label == "Sa(1 s, 5 %) [g]"
    assert parse_im("saavg(0.2:2)").label == "Sa_avg(0.2–2 s, 10 periods, 5 %) [g]"
    assert parse_im("pgv/pga").unit == "s"
    for s in ALL_IMS:  # the column names parse back to the same IM
        assert parse_im(parse_im(s).column) == parse_im(s)


@pytest.mark.parametrize(
    "bad,match",
    [
        ("pgx", "valid forms: pga"),
        ("sa()", "valid forms"),
        ("sa(-1)", "period must be > 0"),
        ("sa(1,5)", "fraction"),
        ("sa(x)", "not a number"),
        ("saavg(2:1)", "T1 < T2"),
        ("saavg(0.2:2:1)", "integer >= 2"),
        ("pgv [cm/s]", r"in \[m/s\], not \[cm/s\]"),
        (3.0, "must be a string"),
    ],
)
def test_bad_im_names_are_input_errors(bad, match):
    with pytest.raises(InputError, match=match):
        parse_im(bad)


def test_bad_arguments_of_intensity_measures(el_centro):
    with pytest.raises(InputError, match="rocking.Ensemble"):
        intensity_measures(el_centro.acc, ["pga"])
    with pytest.raises(InputError, match="at least one"):
        intensity_measures(el_centro, [])
    with pytest.raises(InputError, match="twice"):
        intensity_measures(el_centro, ["sa(1)", "SA(1.0, 0.05)"])


def test_dimensionless_ims_of_blocks_follow_their_similarity_law(el_centro):
    # Rocking depends on a block only through tan α and p = sqrt(3g/(4R)) (Housner 1963; the
    # similarity of Dimitrakopoulos & DeJong 2012): at γ = 4, g·tan α = g/4, so PGA/(g tan α)
    # is 4·PGA [g] for every size; a block 4 times larger has p halved, so PGV·p/(g tan α)
    # halves and Ω = 2π/(T_p·p) doubles. Only rounding differs (1e-12).
    small, large = rocking.Block(0.5, 4.0), rocking.Block(2.0, 4.0)
    ims = ["pga", "pga/gtana", "pgv*p/gtana", "omega"]
    a = intensity_measures(el_centro, ims, body=small).iloc[0]
    b = intensity_measures(el_centro, ims, body=large).iloc[0]
    assert a["pga/gtana [-]"] == pytest.approx(4.0 * a["pga [g]"], rel=1e-12)
    assert b["pga/gtana [-]"] == pytest.approx(a["pga/gtana [-]"], rel=1e-12)
    assert b["pgv*p/gtana [-]"] == pytest.approx(a["pgv*p/gtana [-]"] / 2, rel=1e-12)
    assert b["omega [-]"] == pytest.approx(2 * a["omega [-]"], rel=1e-12)
    # Ω from the record's pulse period, ω_p = 2π/T_p (Shahi & Baker 2014's T_p)
    t_p = rocking.pulse_period(el_centro.acc[0], el_centro.dt).period
    assert a["omega [-]"] == pytest.approx(2 * math.pi / (t_p * small.p), rel=1e-12)
    # scaling the motion: PGA/(g tan α), PGV·p/(g tan α) by λ, Ω not at all (its period stays);
    # to rounding, as in test_scaling_exponents_hold_numerically (< 1e-12)
    lam = 2.5
    scaled = intensity_measures(el_centro.scaled_by(lam), ims, body=small).iloc[0]
    for col, name in zip(a.index, ims):
        k = math.log(scaled[col] / a[col]) / math.log(lam)
        assert k == pytest.approx(im_scaling_exponent(name), abs=1e-12), name
    assert [parse_im(s).dimensional for s in ims] == [None, "pga", "pgv", None]
    for s in ims:  # the column names parse back to the same IM
        assert parse_im(parse_im(s).column) == parse_im(s)


def test_dimensionless_ims_are_refused_without_a_body(el_centro):
    with pytest.raises(InputError, match=r"pga/gtana, omega are per body .* give body="):
        intensity_measures(el_centro, ["pga", "pga/gtana", "omega"])
    with pytest.raises(InputError, match="body must be a rocking.Block, got str"):
        intensity_measures(el_centro, ["pga/gtana"], body="R=1")
    with pytest.raises(InputError, match="is per body.*im_efficiency"):
        rocking.fragility_analysis(
            rocking.Block(1.0, 4.0), el_centro, im="pgv*p/gtana", levels=[1.0]
        )
