"""Lognormal fragility fits by maximum likelihood (Baker 2015) and their bootstrap intervals
(issue 16, part 2): recovery of known parameters within the sampling error, agreement with an
independent maximisation, the separation convention, the bootstrap's width and reproducibility."""

from __future__ import annotations

import math

import numpy as np
import pytest
from scipy import optimize, stats

import rocking
from rocking.errors import InputError
from rocking.montecarlo.statistics import (
    BETA_BOUNDS,
    FragilityFit,
    LognormalFit,
    bootstrap_fragility,
    fit_lognormal,
)

TRUE = LognormalFit(median=0.45, beta=0.4)  # e.g. PGV [m/s]


def _standard_errors(x, m, fit):
    """Standard errors of (ln median, beta) from the Fisher information of the binomial probit
    model: I = Σ m·φ(z)²/(P(1 − P))·∇z∇zᵀ with z = (ln x − ln median)/β,
    ∇z = (−1/β, −z/β) (Baker 2015, Eq. 11's likelihood; standard GLM theory)."""
    z = (np.log(x) - math.log(fit.median)) / fit.beta
    p = stats.norm.cdf(z)
    w = m * stats.norm.pdf(z) ** 2 / (p * (1 - p))
    grad = np.stack([-np.ones_like(z), -z]) / fit.beta
    info = (w * grad) @ grad.T
    return np.sqrt(np.diag(np.linalg.inv(info)))


def _cloud(n, seed):
    """A cloud analysis: n motions with lognormal IMs around the median (log-sd 0.6), each
    overturning with the true probability."""
    rng = np.random.default_rng(seed)
    im = np.exp(rng.normal(math.log(TRUE.median), 0.6, n))
    return im, rng.random(n) < TRUE.probability(im)


def _independent_mle(x, k, n):
    """Maximise Σ ln Binom(k; n, Φ(a + b·ln x)) over the probit coefficients (a, b) with
    Nelder–Mead on scipy.stats.binom.logpmf: another parametrisation, optimiser and
    expression of the same likelihood; median = exp(−a/b), β = 1/b."""

    def nll(q):
        return -stats.binom.logpmf(k, n, stats.norm.cdf(q[0] + q[1] * np.log(x))).sum()

    opts = {"xatol": 1e-12, "fatol": 1e-13, "maxiter": 40_000, "maxfev": 80_000}
    res = optimize.minimize(nll, [0.0, 1.0], method="Nelder-Mead", options=opts)
    res = optimize.minimize(nll, res.x, method="Nelder-Mead", options=opts)  # restart
    a, b = res.x
    return math.exp(-a / b), 1.0 / b


def test_fit_recovers_known_parameters_of_a_cloud():
    im, y = _cloud(3000, seed=11)
    fit = fit_lognormal(im, y.astype(int), 1)
    se_mu, se_beta = _standard_errors(im, 1, TRUE)
    # within 4 standard errors (Fisher information at the truth; se ≈ 0.011 on ln median and
    # 0.017 on β here): a false failure has probability < 1e-4
    assert abs(math.log(fit.median / TRUE.median)) < 4 * se_mu
    assert abs(fit.beta - TRUE.beta) < 4 * se_beta


@pytest.mark.parametrize("layout", ["stripes", "cloud", "three levels"])
def test_fit_equals_an_independent_maximisation_of_the_likelihood(layout):
    rng = np.random.default_rng(3)
    if layout == "stripes":  # multiple-stripe analysis: 12 levels of 15 motions each
        x = np.geomspace(0.1, 1.5, 12)
        n = np.full(x.size, 15)
        k = rng.binomial(n, TRUE.probability(x))
    elif layout == "three levels":  # a small IDA with a flat likelihood (β ≈ 0.1)
        x, n, k = np.array([0.2, 0.5, 0.8]), np.full(3, 8), np.array([1, 5, 8])
    else:
        x, y = _cloud(60, seed=4)
        n, k = np.ones(x.size, int), y.astype(int)
    fit = fit_lognormal(x, k, n)
    median, beta = _independent_mle(x, k, n)
    # both optimisers stop far below 1e-6 of the optimum of a smooth, log-concave problem
    assert fit.median == pytest.approx(median, rel=1e-6)
    assert fit.beta == pytest.approx(beta, rel=1e-6)


def test_separated_outcomes_follow_the_documented_convention():
    # No motion below 0.4 overturns, every one above 0.5 does: the likelihood rises to its
    # supremum 0 (log) as β → 0, so the fit is β at its lower bound with the median at the
    # geometric middle of the gap sqrt(0.4·0.5), where the log-likelihood is within 1e-9 of 0.
    x = np.array([0.1, 0.2, 0.3, 0.4, 0.5, 0.6, 0.8])
    k = np.array([0, 0, 0, 0, 1, 1, 1])
    fit = fit_lognormal(x, k, 1)
    assert fit.beta == BETA_BOUNDS[0]
    assert fit.median == pytest.approx(math.sqrt(0.4 * 0.5), rel=1e-12)
    p = fit.probability(x)
    assert np.sum(stats.binom.logpmf(k, 1, p)) > -1e-9


def _loglik(x, k, n, fit):
    return np.sum(stats.binom.logpmf(k, n, fit.probability(x)))


def test_quasi_separated_outcomes_take_the_lower_bound_of_beta():
    # Only survivors below 0.5, only overturns above, 5 of 8 at 0.5: ℓ < its supremum, the
    # binomial log-probability of 5 of 8 at p = 5/8 (the others' terms → 0), for every β > 0 and
    # reaches it as β → 0 with P(0.5) = 5/8. So the fit is β at its lower bound with P(0.5) = 5/8;
    # at β = 1e-3 the other levels are ≥ 470 standard deviations away, so both hold to rounding.
    x, n, k = np.array([0.2, 0.5, 0.8]), np.full(3, 8), np.array([0, 5, 8])
    fit = fit_lognormal(x, k, n)
    assert fit.beta == BETA_BOUNDS[0]
    assert fit.probability(0.5) == pytest.approx(5 / 8, rel=1e-12)
    sup = stats.binom.logpmf(5, 8, 5 / 8)
    assert _loglik(x, k, n, fit) == pytest.approx(sup, abs=1e-12)
    # and an unconstrained optimiser, which stops somewhere on the ridge towards β → 0, does
    # not find a higher likelihood
    median, beta = _independent_mle(x, k, n)
    assert beta > BETA_BOUNDS[0]
    assert _loglik(x, k, n, LognormalFit(median, beta)) <= _loglik(x, k, n, fit)


@pytest.mark.parametrize(
    "x, n, k",
    [
        ([0.2, 0.5, 0.8], 8, [3, 4, 3]),
        # reached in two steps, the first cut to end on the bound (it once stopped a rounding
        # short of it, and the next step was cut to that rounding: median 0.61 instead of 5.1)
        ([0.114, 0.508, 1.447, 1.877], 3, [1, 3, 1, 0]),
    ],
)
def test_a_falling_proportion_holds_beta_at_its_upper_bound_with_the_best_median(x, n, k):
    # Proportions that do not rise with the intensity: the unconstrained maximum has a
    # negative slope (a falling curve), so the fit is β at its upper bound, 10, with the median
    # that maximises the likelihood at that β (checked with SciPy's bounded scalar minimiser;
    # the likelihood is smooth and unimodal in ln median, both stop within 1e-7 of it).
    x, n, k = np.array(x), np.full(len(x), n), np.array(k)
    fit = fit_lognormal(x, k, n)
    assert fit.beta == BETA_BOUNDS[1]
    best = optimize.minimize_scalar(
        lambda mu: -_loglik(x, k, n, LognormalFit(math.exp(mu), BETA_BOUNDS[1])),
        bounds=(-20.0, 20.0),
        method="bounded",
        options={"xatol": 1e-10},
    )
    assert math.log(fit.median) == pytest.approx(best.x, abs=1e-6)


def test_bootstrap_interval_width_matches_the_sampling_error():
    # A large cloud: the 95 % percentile intervals hold the point fit and their half-widths are
    # 1.96 standard errors of the Fisher information, to within 25 % (300 resamples estimate a
    # 2.5 % quantile to about ±10 % of the width; the information is an asymptotic value).
    im, y = _cloud(800, seed=21)
    res = bootstrap_fragility(im, y, n_boot=300, seed=5)
    assert isinstance(res, FragilityFit) and res.n_boot == 300 and res.n_unfitted == 0
    assert res.fit == fit_lognormal(im, y.astype(int), 1)
    assert res.median_ci.low < res.median < res.median_ci.high
    assert res.beta_ci.low < res.beta < res.beta_ci.high
    se_mu, se_beta = _standard_errors(im, 1, res.fit)
    half_mu = math.log(res.median_ci.high / res.median_ci.low) / 2
    half_beta = (res.beta_ci.high - res.beta_ci.low) / 2
    assert half_mu == pytest.approx(1.96 * se_mu, rel=0.25)
    assert half_beta == pytest.approx(1.96 * se_beta, rel=0.25)


def test_bootstrap_intervals_cover_the_truth():
    # Coverage: 20 independent clouds of 100 motions, 95 % intervals of 100 resamples each. The
    # count holding the true median is Binomial(20, ~0.95); at least 16 fails with probability
    # 0.003 at 95 % coverage and 0.016 at 93 % (100 resamples make the percentiles a little
    # narrow), while intervals of the wrong width (e.g. resampling nothing) would cover far less.
    covered = 0
    for seed in range(20):
        im, y = _cloud(100, seed=100 + seed)
        res = bootstrap_fragility(im, y, n_boot=100, seed=seed)
        covered += res.median_ci.low < TRUE.median < res.median_ci.high
    assert covered >= 16


def test_bootstrap_of_an_ida_resamples_whole_motions():
    # IDA: motion j overturns at every level at or above its capacity c_j, c_j lognormal. On a
    # fine grid of levels the fit estimates ln median by about the mean of ln c_j, whose
    # standard error is β/sqrt(n) (the motions, not the 120 × 150 cells, are the sample): the
    # half-width of the 90 % interval must be 1.645·β/sqrt(n) to within 25 %.
    rng = np.random.default_rng(8)
    n = 150
    capacity = np.exp(rng.normal(math.log(TRUE.median), TRUE.beta, n))
    levels = np.geomspace(0.1, 2.0, 120)
    outcomes = levels[:, None] >= capacity[None, :]
    res = bootstrap_fragility(levels, outcomes, n_boot=200, confidence=0.9, seed=1)
    half = math.log(res.median_ci.high / res.median_ci.low) / 2
    assert half == pytest.approx(1.645 * TRUE.beta / math.sqrt(n), rel=0.25)
    assert res.median_ci.low < TRUE.median < res.median_ci.high
    assert res.beta_ci.low < TRUE.beta < res.beta_ci.high


@pytest.mark.parametrize("layout", ["cloud", "ida"])
def test_bootstrap_fits_every_resample_as_fit_lognormal_fits_it_alone(layout):
    # The resamples are fitted all at once; each must be fitted exactly as fit_lognormal fits
    # it alone (same draws of NumPy's generator, motions resampled whole), so the intervals
    # are the quantiles of those single fits, to the bit.
    im, y = _cloud(60, seed=9)
    if layout == "ida":  # motion j overturns from level y-independent capacity im_j upwards
        levels = np.geomspace(0.1, 2.0, 12)
        y = levels[:, None] >= im[None, :] * np.exp(np.random.default_rng(1).normal(0, 0.3, 60))
        im = levels
    res = bootstrap_fragility(im, y, n_boot=40, seed=4)
    rng = np.random.default_rng(4)
    fits = []
    for _ in range(40):
        idx = rng.integers(0, 60, 60)
        if layout == "ida":
            k, n, x = y[:, idx].sum(axis=1), 60, im
        else:
            k, n, x = y[idx].astype(int), 1, im[idx]
        if np.any(k > 0) and np.any(k < n):
            fits.append(fit_lognormal(x, k, n))
    q = [(1 - 0.95) / 2, (1 + 0.95) / 2]  # as computed from the default confidence
    assert res.n_unfitted == 40 - len(fits)
    assert res.median_ci == tuple(np.quantile([f.median for f in fits], q))
    assert res.beta_ci == tuple(np.quantile([f.beta for f in fits], q))


def test_same_seed_same_numbers_and_other_seed_other_numbers():
    im, y = _cloud(80, seed=2)
    a = bootstrap_fragility(im, y, n_boot=60, seed=7)
    assert a == bootstrap_fragility(im, y, n_boot=60, seed=7)
    b = bootstrap_fragility(im, y, n_boot=60, seed=8)
    assert b.fit == a.fit and b.median_ci != a.median_ci and b.seed == 8


def test_unfittable_resamples_are_counted_and_left_out():
    # 6 motions of which one overturned: a resample misses it with probability (5/6)^6 = 0.335,
    # so of 300 resamples 100.5 ± 8.2 (binomial sd) cannot be fitted; 5 sd either side. The
    # others are separated (one overturn above all survivors) and counted as such.
    im = np.array([0.1, 0.2, 0.3, 0.4, 0.5, 0.6])
    y = np.array([False, False, False, False, False, True])
    res = bootstrap_fragility(im, y, n_boot=300, seed=3)
    assert 60 <= res.n_unfitted <= 141
    assert res.n_separated == 300 - res.n_unfitted
    assert res.beta_ci.high == BETA_BOUNDS[0]


def test_top_level_names_and_bad_input():
    assert rocking.bootstrap_fragility is bootstrap_fragility
    assert rocking.FragilityFit is FragilityFit
    im = np.array([0.1, 0.2, 0.3])
    with pytest.raises(InputError, match="never overturned"):
        bootstrap_fragility(im, np.zeros((3, 4), bool))
    with pytest.raises(InputError, match="every case"):
        bootstrap_fragility(im, np.ones(3, bool))
    with pytest.raises(InputError, match=r"shape \(n_levels, n_motions\)"):
        bootstrap_fragility(im, np.zeros((4, 3), bool))
    with pytest.raises(InputError, match="booleans"):
        bootstrap_fragility(im, np.array([0, 2, 1]))
    with pytest.raises(InputError, match="n_boot"):
        bootstrap_fragility(im, np.array([0, 1, 1]), n_boot=0)
    with pytest.raises(InputError, match="im"):
        bootstrap_fragility([0.1, -0.2, 0.3], np.array([0, 1, 1]))
    with pytest.raises(InputError, match="2 distinct"):
        bootstrap_fragility([0.2, 0.2], np.array([0, 1]))


def test_fits_in_blocks_are_the_fits_of_all_rows_at_once(monkeypatch):
    # Many resamples are fitted in blocks of rows (memory); a block's rows must be fitted as
    # all rows at once would fit them: the same intervals to the bit with blocks of 7 rows.
    from rocking.montecarlo import statistics

    im, y = _cloud(80, seed=12)
    whole = bootstrap_fragility(im, y, n_boot=50, seed=2)
    monkeypatch.setattr(statistics, "_FIT_BLOCK_ELEMENTS", 7 * 80)
    assert bootstrap_fragility(im, y, n_boot=50, seed=2) == whole


@pytest.mark.parametrize(
    "args,match",
    [
        ((-1.0, 0.5), "median must be a finite number > 0, got -1"),
        ((0.5, 0.0), "beta must be a finite number > 0, got 0"),
        ((math.nan, 0.5), "median must be a finite number > 0, got nan"),
        ((0.5, math.inf), "beta must be a finite number > 0"),
        ((0.5, 0.3, "pgv", "cm/s"), r"unit 'cm/s' is not the unit of pgv, \[m/s\]"),
        ((0.5, 0.3, "pgx"), "unknown intensity measure 'pgx'"),
    ],
)
def test_a_lognormal_fit_refuses_parameters_that_are_no_curve(args, match):
    # issue 49: LognormalFit(-1, 0.5), (0.5, 0) and (nan, 0.5) were accepted, and annual_rate
    # then returned NaN with integration warnings
    with pytest.raises(InputError, match=match):
        LognormalFit(*args)


def test_a_lognormal_fit_carries_its_im_and_unit():
    # issue 48: a fit carried no IM, and its probability's argument was named agx whatever
    # the IM; the IM is stored by its canonical name, the unit is the IM's own
    fit = LognormalFit(0.5, 0.3, im="Sa(1.0, 0.05)")
    assert (fit.im, fit.unit) == ("sa(1)", "g")
    assert LognormalFit(0.5, 0.3, im="agx").unit == "g"
    assert LognormalFit(0.5, 0.3).im is None  # not known: annual_rate asks for it
    # Φ(ln(x/median)/β) at x = median·e^β is Φ(1) (scipy.stats.norm.cdf, to rounding)
    x = 0.5 * math.exp(0.3)
    assert LognormalFit(0.5, 0.3, im="pgv").probability(x=x) == pytest.approx(
        stats.norm.cdf(1.0), rel=1e-14
    )
    im, y = _cloud(200, seed=3)
    fit = bootstrap_fragility(im, y, n_boot=10, measure="pgv", unit="m/s")
    assert (fit.im, fit.unit, fit.fit.im_range) == ("pgv", "m/s", (im.min(), im.max()))
    k = fit_lognormal(im, y.astype(int), 1, measure="pgv")
    assert (k.im, k.unit) == ("pgv", "m/s")


def test_a_median_beyond_the_intensities_fitted_is_flagged_as_an_extrapolation():
    # issue 48: the transformer's median 1.52 m/s against a top level of 1.5 m/s was reported
    # without a word. Levels 0.1-1.5 with at most 2 of 10 overturning: the fitted median lies
    # above 1.5 (below 50 % everywhere, the ML curve reaches 50 % beyond the data).
    levels = np.array([0.5, 1.0, 1.5])
    low = fit_lognormal(levels, [0, 1, 2], 10)
    assert low.median > 1.5 and low.extrapolated
    # a median inside the levels tested is not; one at the top level is ("at or beyond")
    assert not fit_lognormal(levels, [0, 5, 10], 10).extrapolated
    assert LognormalFit(1.5, 0.3, im_range=(0.5, 1.5)).extrapolated
    assert not LognormalFit(1.5, 0.3).extrapolated  # range not known
    assert bootstrap_fragility(levels, np.arange(10)[None, :] < [[0], [1], [2]]).extrapolated
