"""Annual rate of overturning from a fragility and a hazard curve (issue 16, part 3): the closed
form of a lognormal fragility under a power-law hazard, its tails, an independent expectation,
Poisson probabilities, hazard files."""

from __future__ import annotations

import itertools
import math

import numpy as np
import pytest
from scipy import stats

import rocking
from rocking.assessment.risk import (
    HazardCurve,
    annual_rate,
    check_hazard_im,
    example_hazard_path,
    hazard_path,
)
from rocking.errors import InputError
from rocking.montecarlo.statistics import LognormalFit

K0, K = 1e-4, 2.5  # power-law hazard λ(x) = K0·x^(−K), x = PGV [m/s]
FRAG = LognormalFit(median=0.5, beta=0.4, im="pgv")


def _power_law(lo, hi, n):
    x = np.geomspace(lo, hi, n)
    return HazardCurve("pgv", x, K0 * x**-K)


def _closed_form(frag=FRAG):
    """λ_f = K0·median^(−K)·exp(K²β²/2) (Cornell et al. 2002, Eq. 11; by parts the risk
    integral is K0·E[X^(−K)] for X lognormal(ln median, β))."""
    return K0 * frag.median**-K * math.exp(K**2 * frag.beta**2 / 2)


def _tail_above(a):
    """∫_a^∞ P_f dλ for the power law, by parts in u = ln x (μ = ln median, z_a = (ln a − μ)/β):
    Φ(z_a)·K0·a^(−K) + K0·e^(−Kμ + K²β²/2)·(1 − Φ(z_a + Kβ))."""
    mu, b = math.log(FRAG.median), FRAG.beta
    z = (math.log(a) - mu) / b
    return stats.norm.cdf(z) * K0 * a**-K + _closed_form() * stats.norm.sf(z + K * b)


def test_power_law_hazard_matches_cornell_closed_form():
    # A table from 1 mm/s to 100 m/s: below it the fragility is ~1e-50, so the left-out lower
    # tail is nil; the log-log interpolation of an exact power law is exact, and quad meets a
    # relative 1e-10 per segment: 1e-8 is a margin of 100.
    res = rocking.annual_rate(FRAG, _power_law(1e-3, 100.0, 31))
    assert res.annual_rate == pytest.approx(_closed_form(), rel=1e-8)
    assert res.lower_tail < 1e-30 and res.p_first < 1e-30
    assert res.error < 1e-9 * res.annual_rate
    # the upper tail, 100 m/s and beyond, is the closed-form tail above 100 (to 1e-6 relative:
    # it is ~1e-9 of the rate, integrated to 1e-10 of itself, so absolute 1e-20 would do)
    assert res.upper_tail == pytest.approx(_tail_above(100.0), rel=1e-6)


def test_tails_of_a_short_table():
    # A table from 0.3 to 0.8 m/s only (P_f = 0.10 to 0.88): the upper tail (last power law
    # extrapolated) is included and equals the closed-form tail above 0.8 m/s; the lower tail
    # is left out of the rate, reported, and equals the closed-form part below 0.3 m/s
    # (closed form minus the tail above 0.3), so rate + lower tail is the whole closed form.
    res = annual_rate(FRAG, _power_law(0.3, 0.8, 6))
    assert res.upper_tail == pytest.approx(_tail_above(0.8), rel=1e-8)
    assert res.lower_tail == pytest.approx(_closed_form() - _tail_above(0.3), rel=1e-7)
    assert res.annual_rate == pytest.approx(res.table + res.upper_tail, rel=1e-15)
    assert res.annual_rate + res.lower_tail == pytest.approx(_closed_form(), rel=1e-8)
    lo, hi = res.upper_tail_bounds  # model-free: P_f(x_n)·λ_n ≤ tail ≤ λ_n
    assert lo == pytest.approx(FRAG.probability(0.8) * K0 * 0.8**-K, rel=1e-12)
    assert hi == pytest.approx(K0 * 0.8**-K, rel=1e-12)
    assert lo < res.upper_tail < hi
    assert res.p_first == pytest.approx(FRAG.probability(0.3), rel=1e-12)
    assert res.p_last == pytest.approx(FRAG.probability(0.8), rel=1e-12)


def test_curved_hazard_against_an_independent_expectation():
    # By parts, the whole integral (both tails extrapolated) is E[λ(X)] with X lognormal of
    # the fragility: scipy.stats.lognorm.expect of the hazard's own log-log interpolation
    # (another quadrature of another integrand). Shipped example curve (curved, 20 points).
    hazard = HazardCurve.from_csv("example")
    res = annual_rate(FRAG, hazard, im="pgv")
    dist = stats.lognorm(s=FRAG.beta, scale=FRAG.median)
    breaks = np.concatenate([[0.0], hazard.values, [np.inf]])
    expected = sum(
        dist.expect(hazard.rate, lb=a, ub=b, epsabs=0, epsrel=1e-11, limit=200)
        for a, b in itertools.pairwise(breaks)
    )
    assert res.annual_rate + res.lower_tail == pytest.approx(expected, rel=1e-7)
    # the example starts low enough for this block: nothing left out below 5 mm/s
    assert res.lower_tail < 1e-12 * res.annual_rate


def test_disaggregation_integrates_to_the_table_part():
    # trapezoid over 20,000 log-spaced points of the smooth density: relative error ~1e-8
    res = annual_rate(FRAG, example_hazard_path())
    x = np.geomspace(res.hazard.values[0], res.hazard.values[-1], 20_000)
    _, density = res.disaggregation(x)
    assert np.trapezoid(density, x) == pytest.approx(res.table, rel=1e-6)
    x, density = res.disaggregation()
    assert x.size == 200 and np.all(density >= 0)


def test_poisson_probability_in_years():
    # P(at least one in t years) = 1 − exp(−λt) = scipy.stats.poisson.sf(0, λt)
    res = annual_rate(FRAG, _power_law(1e-3, 100.0, 31))
    years = np.array([0.0, 1.0, 50.0, 1e5])
    np.testing.assert_allclose(
        res.probability_in(years), stats.poisson.sf(0, res.annual_rate * years), rtol=1e-12
    )
    assert res.return_period == pytest.approx(1 / _closed_form(), rel=1e-8)
    with pytest.raises(InputError, match="years"):
        res.probability_in(-1.0)


def test_im_of_hazard_must_match_the_fragility(tmp_path):
    path = tmp_path / "sa.csv"
    path.write_text("sa(1.0) [g],annual_rate\n0.1,1e-2\n0.5,1e-4\n")
    hazard = HazardCurve.from_csv(path)
    assert check_hazard_im(hazard, "sa(1,0.05)") == hazard.im  # same IM, other spelling
    with pytest.raises(InputError, match=r"sa\.csv.*sa\(1\) \[g\].*pgv \[m/s\]"):
        check_hazard_im(hazard, "pgv")
    with pytest.raises(InputError, match="same intensity measure"):
        annual_rate(FRAG, path, im="sa(2.0)")


@pytest.mark.parametrize(
    "text,match",
    [
        ("pgv [m/s],annual_rate\n0.1,1e-2\n0.05,1e-3\n", r"row 2 \(line 3\).*must increase"),
        ("pgv [m/s],annual_rate\n0.1,1e-2\n0.2,2e-2\n", r"row 2 \(line 3\).*must decrease"),
        ("pgv [m/s],annual_rate\n0.1,1e-2\n0.2,0\n", r"row 2 \(line 3\).*> 0"),
        ("pgv [m/s],annual_rate\n-0.1,1e-2\n0.2,1e-3\n", r"row 1 \(line 2\).*> 0"),
        ("pgv [m/s],annual_rate\n0.1,abc\n0.2,1e-3\n", r"row 1 \(line 2\).*not a number"),
        ("pgv [m/s],annual_rate\n0.1,1e-2,5\n0.2,1e-3\n", r"row 1 \(line 2\).*expected 2"),
        ("pgv,annual_rate\n0.1,1e-2\n0.2,1e-3\n", r"line 1 \(header\).*its unit"),
        ("pgv [cm/s],annual_rate\n1,1e-2\n2,1e-3\n", r"line 1.*not \[cm/s\]"),
        ("pgx [m/s],annual_rate\n0.1,1e-2\n0.2,1e-3\n", r"line 1.*unknown intensity"),
        ("pgv [m/s],probability\n0.1,1e-2\n0.2,1e-3\n", r"line 1.*annual_rate"),
        ("# only a comment\npgv [m/s],annual_rate\n0.1,1e-2\n", "at least 2 rows"),
        ("", "empty hazard file"),
    ],
)
def test_bad_hazard_files_name_file_and_row(tmp_path, text, match):
    path = tmp_path / "hazard.csv"
    path.write_text(text)
    with pytest.raises(InputError, match=rf"hazard\.csv.*{match}"):
        HazardCurve.from_csv(path)


def test_a_fragility_of_another_or_an_unknown_im_is_refused():
    # issue 48: annual_rate(LognormalFit(0.5, 0.3), "example") mixed IMs silently (a fit
    # carried no IM): the fit's IM must be the hazard's, named in the message
    with pytest.raises(InputError, match=r"not known.*pgv \[m/s\]"):
        rocking.annual_rate(LognormalFit(0.5, 0.3), "example")
    with pytest.raises(InputError, match=r"pgv \[m/s\].*sa\(1\) \[g\].*same intensity"):
        rocking.annual_rate(LognormalFit(0.5, 0.3, im="sa(1.0)"), "example")
    with pytest.raises(InputError, match="A_gx.*no site hazard curve"):
        rocking.annual_rate(LognormalFit(0.5, 0.3, im="agx"), "example")
    with pytest.raises(InputError, match="fragility is of pgv but im='pga'"):
        rocking.annual_rate(FRAG, "example", im="pga")
    # the IM given either way, or carried by a bootstrap fit, gives the same rate
    by_fit = rocking.annual_rate(FRAG, "example").annual_rate
    by_argument = annual_rate(LognormalFit(0.5, 0.4), "example", im="PGV").annual_rate
    assert by_fit == by_argument > 0.0
    x = np.geomspace(0.1, 1.5, 8)
    boot = rocking.bootstrap_fragility(x, [0, 0, 1, 0, 1, 1, 1, 1], n_boot=5, measure="pgv")
    assert annual_rate(boot, "example").fragility.im == "pgv"


def test_risk_result_and_hazard_curve_print_a_summary():
    # issue 48: the reprs dumped whole arrays; a summary holds the numbers a reader needs
    res = annual_rate(FRAG, "example")
    text = repr(res)
    assert len(text) < 400 and "\n" not in text and "array" not in text
    assert f"{res.annual_rate:.4g} /yr" in text and "pgv [m/s], 20 points" in text


def test_example_file_and_bad_arguments():
    hazard = HazardCurve.from_csv("example")
    assert hazard.im == rocking.parse_im("pgv") and hazard.values.size == 20
    assert "NOT A REAL SITE" in example_hazard_path().read_text()
    with pytest.raises(InputError, match="must decrease"):
        HazardCurve("pga", [0.1, 0.2], [1e-3, 1e-2])
    with pytest.raises(InputError, match="probability"):
        annual_rate(object(), hazard)
    with pytest.raises(InputError, match="HazardCurve or a CSV path"):
        annual_rate(FRAG, 42)
    with pytest.raises(InputError, match="cannot read"):
        annual_rate(FRAG, "no-such-hazard.csv")


def test_the_word_example_is_read_one_way_everywhere(tmp_path, monkeypatch):
    # One resolver (hazard_path) for the Python API, `rocking risk` and `rocking screen`: the word
    # in any case with blanks around it, unless a file of that name is there.
    assert hazard_path(" Example ") == example_hazard_path()
    monkeypatch.chdir(tmp_path)
    (tmp_path / "example").write_text("pga [g],annual_rate\n0.1,1e-2\n0.5,1e-4\n")
    assert hazard_path("example") == tmp_path.joinpath("example").relative_to(tmp_path)
    assert HazardCurve.from_csv("example").im == rocking.parse_im("pga")
