"""Statistics of overturning counts: Wilson score intervals, lognormal fragility curves fitted by
maximum likelihood (:func:`fit_lognormal`) and their bootstrap confidence intervals
(:func:`bootstrap_fragility`).

The fragility curves are functions of any intensity measure (IM): the paper's A_gx [g] or one of
:func:`rocking.intensity_measures` (PGV [m/s], Sa(T) [g], …); the median is in the IM's unit.
The fit is Baker's (2015, "Efficient analytical fragility function fitting using dynamic
structural analysis data", Earthquake Spectra 31(1)): the binomial likelihood of the outcomes,
which serves incremental dynamic analysis (IDA: every motion at every level), multiple-stripe
analysis (MSA: a set of motions per level) and the cloud (each motion at its own IM, one trial
each) alike.
"""

from __future__ import annotations

import itertools
import math
from collections.abc import Iterator
from dataclasses import dataclass, replace
from typing import NamedTuple

import numpy as np
from numpy.typing import ArrayLike

from ..core import portable
from ..core.checks import finite_array, in_range, positive
from ..defaults import AGX, N_BOOT
from ..errors import InputError


def wilson_interval(
    count: ArrayLike, n: ArrayLike, confidence: float = 0.95
) -> tuple[np.ndarray, np.ndarray]:
    """Wilson score interval of a binomial proportion count/n (no continuity correction).

    Parameters
    ----------
    count, n : array_like of int
        Successes (here: motions that overturn the body) and trials, 0 ≤ count ≤ n, n ≥ 1.
    confidence : float
        Confidence level in (0, 1) [-].

    Returns
    -------
    low, high : ndarray
        Interval bounds [-], shaped like ``count``.
    """
    confidence = in_range("confidence", confidence, 0.0, 1.0, lo_open=True, hi_open=True)
    count, n = _counts(count, n)
    import scipy.special  # here and below on first use: 0.2-0.8 s that most commands skip

    # Newcombe (1998, Statistics in Medicine 17: 857-872, method 3) in the operations of SciPy's
    # binomtest(k, n).proportion_ci(method="wilson"), which gives the same bits
    # (tests/test_fragility.py) but costs ~6 ms per call (it computes an exact binomial test
    # too) and 1.3 s to import scipy.stats
    z = scipy.special.ndtri(0.5 + 0.5 * confidence)
    p = count / n
    denom = 2 * (n + z**2)
    center = (2 * n * p + z**2) / denom
    delta = z / denom * np.sqrt(4 * n * p * (1 - p) + z**2)
    low = np.where(count == 0, 0.0, center - delta)
    high = np.where(count == n, 1.0, center + delta)
    return low, high


def _counts(count: ArrayLike, n: ArrayLike) -> tuple[np.ndarray, np.ndarray]:
    """``count`` and ``n`` broadcast together, checked: integers, 0 ≤ count ≤ n, n ≥ 1."""
    count, n = np.broadcast_arrays(np.asarray(count), np.asarray(n))
    if count.dtype.kind not in "iu" or n.dtype.kind not in "iu":
        raise InputError("count and n must be integers")
    if np.any(n < 1) or np.any(count < 0) or np.any(count > n):
        raise InputError("count and n must satisfy 0 <= count <= n and n >= 1")
    return count, n


class ExtrapolationWarning(UserWarning):
    """A fitted median lies at or outside the intensities tested
    (:attr:`LognormalFit.extrapolated`): the data do not bracket it, so it is an extrapolation
    of the lognormal model."""


@dataclass(frozen=True)
class LognormalFit:
    """Lognormal fragility curve P(IM) = Φ(ln(IM/median)/beta) of one intensity measure.

    Attributes
    ----------
    median : float
        Intensity of 50 % probability, > 0, in the IM's unit (A_gx [g] for the paper's curves).
    beta : float
        Logarithmic standard deviation (dispersion) [-], > 0.
    im : str or None
        The intensity measure: ``"agx"`` (the paper's A_gx, the mean PGA of an ensemble) or any
        form of :func:`rocking.parse_im` (stored by its canonical name, e.g. ``"pgv"``,
        ``"sa(1)"``); None (the default) when it is not known, which
        :func:`rocking.annual_rate` then asks for.
    unit : str or None
        Unit of the median: the IM's own (``"g"``, ``"m/s"``, …; derived from ``im`` when not
        given, and refused when it differs: convert the median instead); None when neither is
        known.
    im_range : (float, float) or None
        Lowest and highest intensity of the data the curve was fitted to [the IM's unit]
        (:func:`fit_lognormal`, :func:`bootstrap_fragility`); None when not known.

    Raises
    ------
    InputError
        When ``median`` or ``beta`` is not a finite number > 0, or ``im`` or ``unit`` is not
        one the package knows.
    """

    median: float
    beta: float
    im: str | None = None
    unit: str | None = None
    im_range: tuple[float, float] | None = None

    def __post_init__(self) -> None:
        unit = "" if self.unit is None or self.im is None else f" {self.unit}"
        object.__setattr__(self, "median", positive("median", self.median, unit.strip()))
        object.__setattr__(self, "beta", positive("beta", self.beta))
        if self.im is not None:
            name, own = _im_name_unit(self.im)
            if self.unit is not None and str(self.unit).strip() != own:
                raise InputError(
                    f"unit {self.unit!r} is not the unit of {name}, [{own}]: give the median "
                    f"in {own}"
                )
            object.__setattr__(self, "im", name)
            object.__setattr__(self, "unit", own)
        elif self.unit is not None:
            object.__setattr__(self, "unit", str(self.unit).strip())
        if self.im_range is not None:
            lo, hi = (positive("im_range", v) for v in self.im_range)
            if lo > hi:
                raise InputError(f"im_range must be (lowest, highest), got {self.im_range!r}")
            object.__setattr__(self, "im_range", (lo, hi))

    @property
    def extrapolated(self) -> bool:
        """True when the median lies at or beyond the highest intensity of :attr:`im_range`
        (or at or below the lowest): the data do not bracket it. False when the range is not
        known."""
        if self.im_range is None:
            return False
        lo, hi = self.im_range
        return not lo < self.median < hi

    def probability(self, x: ArrayLike) -> np.ndarray:
        """Probability of overturning at intensities ``x`` (array_like, > 0, in the unit of the
        median, e.g. A_gx [g] or PGV [m/s]) [-]."""
        import scipy.special  # on first use (see wilson_interval)

        z = portable.log(np.asarray(x, dtype=float) / self.median) / self.beta
        return scipy.special.ndtr(z)  # Φ(z), as scipy.stats.norm.cdf (1.3 s lighter to import)


def _im_name_unit(im) -> tuple[str, str]:
    """Canonical name and unit of an intensity measure: ``"agx"`` (the paper's A_gx [g]) or
    any form of :func:`rocking.parse_im`."""
    if isinstance(im, str) and im.strip().lower() == AGX:
        return AGX, "g"
    from ..motions.intensity import parse_im  # on first use: pandas and SciPy

    measure = parse_im(im)
    return measure.name, measure.unit


def fit_lognormal(
    agx: ArrayLike,
    count: ArrayLike,
    n: ArrayLike,
    *,
    measure: str | None = None,
    unit: str | None = None,
) -> LognormalFit:
    """Maximum-likelihood lognormal fragility curve from overturning counts (Baker 2015).

    Maximises the binomial log-likelihood Σ [k·ln P(x) + (n − k)·ln(1 − P(x))] with
    P(x) = Φ(ln(x/median)/β) by Newton's method on the probit coefficients (1/β and
    −ln(median)/β, where the log-likelihood is concave), from a probit-regression start, β kept
    in [1e-3, 10] (:data:`BETA_BOUNDS`). Outcomes that the intensity separates completely (every
    level below some intensity has count 0, every level above it count n, none in between) have
    no finite maximum (the likelihood grows as β → 0): the fit is then β = 1e-3 with the median
    at the geometric middle of the gap. So do quasi-separated outcomes (one intensity with
    0 < count < n, count 0 below it and n above): the fit is then β = 1e-3 with the median that
    gives that intensity its observed proportion.

    Parameters
    ----------
    agx : array_like
        Intensities x, > 0: the paper's A_gx [g] or any other intensity measure, in its unit
        (the median comes out in the same unit). Repeated values are allowed (a cloud analysis
        gives each motion its own x with n = 1).
    count : array_like of int
        Motions that overturned the body at each intensity.
    n : int or array_like of int
        Motions at each intensity (≥ 1, ≥ count).
    measure, unit : str, optional
        The intensity measure of ``agx`` and its unit (:class:`LognormalFit` ``im`` and
        ``unit``; default: not known).

    Returns
    -------
    LognormalFit
        With ``im_range`` the lowest and highest of ``agx``.

    Raises
    ------
    InputError
        On bad shapes or values, or if every count is 0 or every count is n (no information on
        the median).
    """
    agx = finite_array("agx", agx, ndim=(1,))
    if np.any(agx <= 0.0):
        raise InputError("agx (the intensities) must be > 0")
    count = np.asarray(count)
    n = np.broadcast_to(np.asarray(n), count.shape)
    if count.shape != agx.shape:
        raise InputError(f"count must have one value per agx ({agx.size}), got shape {count.shape}")
    count, n = _counts(count, n)
    if np.all(count == 0) or np.all(count == n):
        raise InputError("fit_lognormal needs counts that are not all 0 and not all n")
    fit = _mle(portable.log(agx), count.astype(float), n.astype(float))
    return replace(fit, im=measure, unit=unit, im_range=(float(agx.min()), float(agx.max())))


#: Bounds of the dispersion β of a fit [-].
BETA_BOUNDS = (1e-3, 10.0)


def _separation(
    x: np.ndarray, k: np.ndarray, m: np.ndarray
) -> tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray]:
    """Per row of (ln x, k of m trials), shape (B, n): whether the outcomes are completely
    separated by x (no x has both outcomes: every survivor below every overturn), whether they
    are quasi-completely separated (one x has both, every lower one only survivors, every higher
    one only overturns), the largest x with a survivor and the smallest with an overturn."""
    hi_survive = np.max(np.where(k < m, x, -np.inf), axis=1)
    lo_overturn = np.min(np.where(k > 0, x, np.inf), axis=1)
    return hi_survive < lo_overturn, hi_survive == lo_overturn, hi_survive, lo_overturn


#: Newton iterations of a fit at most: from the probit-regression start a fit takes 3-8 (the
#: likelihood is concave in the probit coefficients); the bound only guards against a loop.
_NEWTON_MAX = 100


def _probit_loglik(
    x: np.ndarray, k: np.ndarray, m: np.ndarray, c: np.ndarray, s: np.ndarray
) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Binomial probit log-likelihoods ℓ = Σ k·ln Φ(z) + (m − k)·ln Φ(−z) with z = c + s·x,
    one per row of x, k, m (shape (B, n); c, s of shape (B,)), and the first and second
    derivatives of ℓ with respect to each z.

    With the inverse Mills ratios a = φ(z)/Φ(z) and b = φ(z)/Φ(−z):
    dℓ/dz = k·a − (m − k)·b and d²ℓ/dz² = −k·a·(z + a) − (m − k)·b·(b − z) < 0.
    """
    import scipy.special  # on first use (see wilson_interval)

    z = c[:, None] + s[:, None] * x
    lp, lq = scipy.special.log_ndtr(z), scipy.special.log_ndtr(-z)
    log_phi = -0.5 * math.log(2.0 * math.pi) - 0.5 * z * z
    a, b = portable.exp(log_phi - lp), portable.exp(log_phi - lq)
    g = k * a - (m - k) * b
    h = -k * a * (z + a) - (m - k) * b * (b - z)
    return np.sum(k * lp + (m - k) * lq, axis=1), g, h


#: Elements (rows × points) at most that the callers of :func:`_fit_rows` give it at once:
#: it holds ~15 temporaries of this many float64 (~120 MB in all); more resamples are fitted
#: block by block (:func:`_bootstrap_resamples` draws them).
_FIT_BLOCK_ELEMENTS = 1 << 20

#: Bounds of s = 1/β, the probit slope of a fit (:data:`BETA_BOUNDS`) [-].
_S_LO, _S_HI = 1.0 / BETA_BOUNDS[1], 1.0 / BETA_BOUNDS[0]


def _betas(s: np.ndarray) -> np.ndarray:
    """β = 1/s, exactly at a bound of :data:`BETA_BOUNDS` where s is at one of its bounds."""
    return np.where(s >= _S_HI, BETA_BOUNDS[0], np.where(s <= _S_LO, BETA_BOUNDS[1], 1.0 / s))


def _bootstrap_resamples(seed: int, n_boot: int, n: int) -> np.ndarray:
    """``n_boot`` resamples with replacement of ``n`` motions, drawn from NumPy's default
    generator seeded with ``seed``: their indices, shape (n_boot, n)."""
    rng = np.random.default_rng(int(seed))
    draws = [rng.integers(0, n, n) for _ in range(n_boot)]
    return np.array(draws, dtype=np.int64).reshape(n_boot, n)


def _resampled_counts(
    log_x: np.ndarray, outcomes: np.ndarray, n_boot: int, seed: int
) -> Iterator[tuple[np.ndarray, np.ndarray, np.ndarray]]:
    """The ``n_boot`` bootstrap resamples of the motions of :func:`_bootstrap_resamples`
    (``seed``) as trials to fit, block by block (at most :data:`_FIT_BLOCK_ELEMENTS` counts
    each): (x, k, m) of shapes (B, n), (B, K, n), (B, n), k of m trials at x = ln(IM).

    ``outcomes`` (bool) of K rows (e.g. limit states): shape (K, n_levels, n_motions) for an
    IDA or MSA at intensities ``log_x`` (whole motions resampled, so that a motion's outcomes
    at all levels stay together: the counts of each level over the resampled motions), or
    (K, n_motions) for a cloud, ``log_x`` each motion's (one trial per resampled motion)."""
    n_motions = outcomes.shape[-1]
    resamples = _bootstrap_resamples(seed, n_boot, n_motions)
    step = max(1, _FIT_BLOCK_ELEMENTS // (outcomes.shape[0] * max(log_x.size, n_motions)))
    for idx in (resamples[i : i + step] for i in range(0, n_boot, step)):
        if outcomes.ndim == 3:
            k = np.transpose(np.sum(outcomes[:, :, idx], axis=3), (2, 0, 1)).astype(float)
            x = np.broadcast_to(log_x, (idx.shape[0], log_x.size))
            m = np.full(x.shape, float(n_motions))
        else:
            k = np.transpose(outcomes[:, idx], (1, 0, 2)).astype(float)
            x, m = log_x[idx], np.ones(idx.shape)
        yield x, k, m


def _fit_rows(
    x: np.ndarray, k: np.ndarray, m: np.ndarray
) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Maximum-likelihood fits of :func:`fit_lognormal`, one per row of x = ln(IM), k of m
    trials (shape (B, n); checked: no row all 0 or all m; at most :data:`_FIT_BLOCK_ELEMENTS`
    elements): (medians, βs, separated), shape (B,), separated saying which rows are
    completely or quasi-completely separated. A row's fit does not depend on the other rows
    (the same operations on its values whatever B is).

    Newton's method on the probit coefficients (c, s), z = c + s·x (median = exp(−c/s),
    β = 1/s), where the log-likelihood is concave (second derivatives of
    :func:`_probit_loglik` negative). From the probit-regression line through the empirical
    proportions, each step solves the 2×2 Newton system; a step that would take β beyond a
    bound of :data:`BETA_BOUNDS` moves c alone (β stays at the bound), or is shortened to reach
    it; a step is halved until the likelihood does not decrease (to its rounding). A fit ends
    when the gain its step predicts (half the Newton decrement) is below the rounding of ℓ,
    after that step: the convergence is quadratic, so what is left is rounding.

    Complete separation: no finite maximum, the likelihood grows as β → 0; the fit is β at its
    lower bound with the median at the geometric middle of the gap. Quasi-complete separation
    has no finite maximum either (the likelihood grows as β → 0 with the probability at the
    mixed intensity fixed): β at its lower bound, c by Newton.

    Written here rather than with ``scipy.optimize.minimize``: its L-BFGS-B on
    (ln median, ln β) took 300-700 evaluations of this ill-conditioned likelihood (90 ms per
    fit, 90 s for a bootstrap of 1000 resamples) and stopped on flat ridges wherever the
    rounding of ℓ stopped it; its bounded second-order method (trust-constr) costs more per
    iteration than these few iterations in all, and neither fits a thousand resamples at once.
    """
    import scipy.special  # on first use (see wilson_interval)

    s_lo, s_hi = _S_LO, _S_HI
    median, beta = np.empty(x.shape[0]), np.empty(x.shape[0])
    complete, quasi, mixed_x, gap_end = _separation(x, k, m)  # mixed_x: where quasi mixes
    separated = complete | quasi
    median[complete] = portable.exp(0.5 * (mixed_x + gap_end))[complete]
    beta[complete] = BETA_BOUNDS[0]
    rows = np.flatnonzero(~complete)
    x, k, m, quasi, mixed_x = x[rows], k[rows], m[rows], quasi[rows], mixed_x[rows]
    with np.errstate(divide="ignore", invalid="ignore"):
        # start: the weighted least-squares line of Φ⁻¹ of the empirical proportions (clipped
        # away from 0 and 1) on x, weights m; a slope outside the bounds is clipped, keeping
        # the line's median; no rising line: s = 1 at the weighted mean of x
        v = scipy.special.ndtri(np.clip((k + 0.5) / (m + 1.0), 1e-3, 1 - 1e-3))
        sw = np.sum(m, axis=1)
        xm, vm = np.sum(m * x, axis=1) / sw, np.sum(m * v, axis=1) / sw
        dx = x - xm[:, None]
        slope = np.sum(m * dx * (v - vm[:, None]), axis=1) / np.sum(m * dx * dx, axis=1)
        rising = slope > 0.1
        s = np.where(rising, np.clip(slope, s_lo, s_hi), 1.0)
        c = np.where(rising, (vm / slope - xm) * s, -xm)
        # quasi-complete separation: β at its bound, Φ(z) = k/m where the outcomes mix
        at = x == mixed_x[:, None]
        p_mixed = np.sum(np.where(at, k, 0.0), axis=1) / np.sum(np.where(at, m, 0.0), axis=1)
        s = np.where(quasi, s_hi, s)
        c = np.where(quasi, scipy.special.ndtri(p_mixed) - s_hi * mixed_x, c)
    ll, g, h = _probit_loglik(x, k, m, c, s)
    on = np.arange(rows.size)  # rows still iterating, into x, k, m, c, s
    for _ in range(_NEWTON_MAX):
        if on.size == 0:
            break
        xo, co, so = x[on], c[on], s[on]
        gc, gs = np.sum(g, axis=1), np.sum(g * xo, axis=1)
        hcc, hcs, hss = np.sum(h, axis=1), np.sum(h * xo, axis=1), np.sum(h * xo * xo, axis=1)
        with np.errstate(divide="ignore", invalid="ignore"):
            det = hcc * hss - hcs * hcs
            ds = (hcs * gc - hcc * gs) / det
            inward = ((so > s_lo) | (ds > 0.0)) & ((so < s_hi) | (ds < 0.0))
            both = (det > 1e-12 * hcc * hss) & inward  # else c alone: β at a bound, or one x
            dc = np.where(both, (hcs * gs - hss * gc) / det, -gc / hcc)
            ds = np.where(both, ds, 0.0)
            # a step that would cross a bound of s is shortened to end on it (_s_after)
            bound = np.where(so + ds > s_hi, s_hi, np.where(so + ds < s_lo, s_lo, np.nan))
            t_bound = np.where(np.isnan(bound), 1.0, (bound - so) / ds)
        t = t_bound.copy()
        rounding = 8.0 * np.finfo(float).eps * np.maximum(1.0, np.abs(ll))
        last = 0.5 * t * (gc * dc + gs * ds) <= rounding  # the gain left is rounding
        c[on[last]] = (co + t * dc)[last]
        s[on[last]] = _s_after(so, ds, t, t_bound, bound, np.flatnonzero(last))
        # the others: halve the step until the likelihood does not decrease
        step = ~last
        trial = np.flatnonzero(step)
        ll_new, g_new, h_new = np.empty(on.size), np.empty_like(g), np.empty_like(h)
        while trial.size:
            ct = co[trial] + t[trial] * dc[trial]
            ll_new[trial], g_new[trial], h_new[trial] = _probit_loglik(
                xo[trial],
                k[on[trial]],
                m[on[trial]],
                ct,
                _s_after(so, ds, t, t_bound, bound, trial),
            )
            worse = ll_new[trial] < ll[trial] - rounding[trial]
            t[trial[worse]] *= 0.5
            trial = trial[worse & (t[trial] >= 1e-12)]
        gain = step & (ll_new >= ll - rounding)  # no gain along the Newton direction: done
        moved = on[gain]
        c[moved] = co[gain] + t[gain] * dc[gain]
        s[moved] = _s_after(so, ds, t, t_bound, bound, np.flatnonzero(gain))
        on, ll, g, h = moved, ll_new[gain], g_new[gain], h_new[gain]
    median[rows] = portable.exp(-c / s)
    beta[rows] = _betas(s)
    return median, beta, separated


def _s_after(so, ds, t, t_bound, bound, i) -> np.ndarray:
    """s of the rows ``i`` after steps ``t`` along ``ds`` from ``so``: exactly the ``bound``
    (NaN: none) where the step is the one cut to end on it (so + t·ds would miss it by a
    rounding, and the next step be cut to that), else so + t·ds within the bounds of s."""
    on_bound = (t[i] == t_bound[i]) & ~np.isnan(bound[i])
    return np.where(on_bound, bound[i], np.clip(so[i] + t[i] * ds[i], _S_LO, _S_HI))


def _mle(x: np.ndarray, k: np.ndarray, m: np.ndarray) -> LognormalFit:
    """The maximum-likelihood fit of :func:`fit_lognormal` on x = ln(IM), k of m trials (1-D,
    checked, not all 0, not all m): :func:`_fit_rows` of one row."""
    median, beta, _ = _fit_rows(x[None, :], k[None, :], m[None, :])
    return LognormalFit(median=float(median[0]), beta=float(beta[0]))


class Interval(NamedTuple):
    """A confidence interval (low, high)."""

    low: float
    high: float


@dataclass(frozen=True)
class FragilityFit:
    """A lognormal fragility curve with bootstrap confidence intervals
    (:func:`bootstrap_fragility`).

    Attributes
    ----------
    fit : LognormalFit
        The maximum-likelihood fit to all motions (with its IM, unit and range of
        intensities).
    median_ci : Interval
        Percentile bootstrap interval of the median, in the IM's unit.
    beta_ci : Interval
        Percentile bootstrap interval of β [-].
    confidence : float
        Confidence level of the intervals [-].
    n_boot : int
        Bootstrap resamples drawn.
    seed : int
        Seed of the resampling (the same seed gives the same intervals).
    n_unfitted : int
        Resamples in which no motion or every motion overturned at every intensity: they hold
        no information on the median and are left out of the intervals (many of them mean that
        the data barely bracket the median and the intervals are too narrow).
    n_separated : int
        Resamples completely or quasi-completely separated by the intensity (fitted with
        β = 1e-3, see :func:`fit_lognormal`); they are kept.
    """

    fit: LognormalFit
    median_ci: Interval
    beta_ci: Interval
    confidence: float
    n_boot: int
    seed: int
    n_unfitted: int
    n_separated: int

    @property
    def median(self) -> float:
        """Median of the point fit, in the IM's unit."""
        return self.fit.median

    @property
    def beta(self) -> float:
        """Dispersion β of the point fit [-]."""
        return self.fit.beta

    @property
    def im(self) -> str | None:
        """The intensity measure of the curve (None: not known)."""
        return self.fit.im

    @property
    def unit(self) -> str | None:
        """Unit of the median (None: not known)."""
        return self.fit.unit

    @property
    def extrapolated(self) -> bool:
        """Whether the median of the point fit lies at or outside the intensities of the data
        (:attr:`LognormalFit.extrapolated`)."""
        return self.fit.extrapolated

    def probability(self, im: ArrayLike) -> np.ndarray:
        """Probability of overturning of the point fit at intensities ``im`` (> 0) [-]."""
        return self.fit.probability(im)


def bootstrap_fragility(
    im: ArrayLike,
    outcomes: ArrayLike,
    *,
    n_boot: int = N_BOOT,
    confidence: float = 0.95,
    seed: int = 0,
    measure: str | None = None,
    unit: str | None = None,
) -> FragilityFit:
    """Lognormal fragility curve by maximum likelihood with bootstrap confidence intervals.

    Two layouts of the outcomes (True = the body overturned):

    * IDA or multiple-stripe analysis: ``outcomes`` of shape (n_levels, n_motions), motion j at
      intensity ``im[i]`` (the stripes of an MSA share the motions, or hold as many);
    * cloud: ``im`` and ``outcomes`` of shape (n_motions,), each motion at its own intensity.

    The point fit is :func:`fit_lognormal` on the counts (cloud: one trial per motion). The
    bootstrap draws ``n_boot`` resamples of the motions with replacement (whole columns of an
    IDA, so that a motion's outcomes at all levels stay together), refits each, and takes the
    percentile intervals of median and β ((1 − confidence)/2 and (1 + confidence)/2 quantiles of
    the fitted resamples). Resamples in which nothing or everything overturned cannot be fitted:
    they are counted (:attr:`FragilityFit.n_unfitted`) and left out.

    Parameters
    ----------
    im : array_like, shape (n_levels,) or (n_motions,)
        Intensities, > 0, in the IM's unit (e.g. PGV [m/s]).
    outcomes : array_like of bool, shape (n_levels, n_motions) or (n_motions,)
        Overturned (True) or not; 0/1 integers are accepted.
    n_boot : int
        Bootstrap resamples, ≥ 1.
    confidence : float
        Confidence level of the intervals, in (0, 1) [-].
    seed : int
        Seed of NumPy's default generator, ≥ 0.
    measure, unit : str, optional
        The intensity measure of ``im`` and its unit (:class:`LognormalFit` ``im`` and
        ``unit``; default: not known).

    Returns
    -------
    FragilityFit

    Raises
    ------
    InputError
        On bad shapes or values, fewer than 2 distinct intensities, or when no motion or every
        motion overturned (nothing to fit).
    """
    x = finite_array("im", im, ndim=(1,))
    if np.any(x <= 0.0):
        raise InputError("im (the intensities) must be > 0")
    if np.unique(x).size < 2:
        raise InputError("im must hold at least 2 distinct intensities")
    y = _outcomes(outcomes, x.size)
    if isinstance(n_boot, bool) or not isinstance(n_boot, (int, np.integer)) or n_boot < 1:
        raise InputError(f"n_boot must be an integer >= 1, got {n_boot!r}")
    confidence = in_range("confidence", confidence, 0.0, 1.0, lo_open=True, hi_open=True)
    if isinstance(seed, bool) or not isinstance(seed, (int, np.integer)) or seed < 0:
        raise InputError(f"seed must be an integer >= 0, got {seed!r}")
    if not y.any() or y.all():
        state = "overturned in every case" if y.any() else "never overturned"
        raise InputError(f"outcomes: the body {state}; there is no fragility curve to fit")
    log_x = portable.log(x)
    n_motions = y.shape[-1]
    if y.ndim == 2:
        point = _mle(log_x, y.sum(axis=1).astype(float), np.full(x.size, float(n_motions)))
    else:
        point = _mle(log_x, y.astype(float), np.ones(x.size))
    point = replace(point, im=measure, unit=unit, im_range=(float(x.min()), float(x.max())))
    median_parts, beta_parts, separated = [np.empty(0)], [np.empty(0)], 0
    for xb, k_rows, mb in _resampled_counts(log_x, y[None], n_boot, seed):
        kb = k_rows[:, 0]
        fitted = np.any(kb > 0, axis=1) & np.any(kb < mb, axis=1)
        xb, kb, mb = np.ascontiguousarray(xb[fitted]), kb[fitted], mb[fitted]
        fit = _fit_rows(xb, kb, mb)
        median_parts.append(fit[0])
        beta_parts.append(fit[1])
        separated += int(np.sum(fit[2]))
    medians, betas = np.concatenate(median_parts), np.concatenate(beta_parts)
    q = [(1.0 - confidence) / 2.0, (1.0 + confidence) / 2.0]
    if medians.size:
        med, beta = np.quantile(medians, q), np.quantile(betas, q)
    else:
        med = beta = np.full(2, np.nan)
    return FragilityFit(
        fit=point,
        median_ci=Interval(float(med[0]), float(med[1])),
        beta_ci=Interval(float(beta[0]), float(beta[1])),
        confidence=confidence,
        n_boot=int(n_boot),
        seed=int(seed),
        n_unfitted=int(n_boot - medians.size),
        n_separated=separated,
    )


def severity_order(flags: np.ndarray) -> tuple[list[int], list[tuple[int, int]]]:
    """Limit states in order of severity, and where they are not nested.

    ``flags`` (bool, state first): each limit state's exceedances over the same cases.  Returns
    the states' indices from the most often exceeded (the mildest) to the least (in the order
    given where counts tie), and the neighbouring pairs (milder, severer) of that order where
    a case exceeds the severer state but not the milder (none: the states are nested, each
    exceeded in every case a severer one is)."""
    flat = np.asarray(flags, dtype=bool).reshape(len(flags), -1)
    order = [int(i) for i in np.argsort(-flat.sum(axis=1), kind="stable")]
    loose = [(m, s) for m, s in itertools.pairwise(order) if np.any(flat[s] & ~flat[m])]
    return order, loose


class CrossingWarning(UserWarning):
    """The maximum-likelihood curves of two nested limit states, each fitted alone, cross inside
    the intensities tested (the severer state the likelier at some of them, which no data of
    nested states can be): the states were refitted together under the constraint that their
    curves do not cross there (:func:`bootstrap_limit_states`; the flag ``fit_constrained`` of
    :func:`rocking.fragility_analysis`), or, where the severer is the likelier by no more than
    :data:`CROSSING_TOLERANCE`, kept as fitted (the warning says which)."""


class Crossing(NamedTuple):
    """Where the curves of two nested limit states, each fitted alone, cross inside the
    intensities tested (:func:`bootstrap_limit_states`)."""

    milder: int
    severer: int
    #: The intensity where they cross [the IM's unit].
    at: float
    #: The largest excess of the severer state's probability over the milder's there [-].
    excess: float


class LimitStateFits(NamedTuple):
    """The fits of :func:`bootstrap_limit_states`, one per limit state as given."""

    #: The curve of each state, None for a state never or always exceeded (nothing to fit).
    fits: list[FragilityFit | None]
    #: Whether a state's point fit is the constrained one, not its own maximum likelihood (its
    #: curve touches a neighbour's at an end of the intensities tested).
    constrained: list[bool]
    #: The crossings of the states' own fits that the constraint removed.
    crossings: list[Crossing]


def _own_rows(x: np.ndarray, k: np.ndarray, m: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Probit coefficients (c, s) of each limit state fitted alone (:func:`_fit_rows`), z = c +
    s·ln(IM), s = 1/β: x = ln(IM), m of shape (B, n), k of shape (B, K, n); NaN for a state
    never or always exceeded in its row (nothing to fit). Shapes (B, K)."""
    B, K, n = k.shape
    mm = np.broadcast_to(m[:, None, :], k.shape).reshape(B * K, n)
    kk = k.reshape(B * K, n)
    rows = np.flatnonzero(np.any(kk > 0, axis=1) & np.any(kk < mm, axis=1))
    xk = np.broadcast_to(x[:, None, :], k.shape).reshape(B * K, n)
    c, s = np.full(B * K, np.nan), np.full(B * K, np.nan)
    if rows.size:
        median, beta, _ = _fit_rows(np.ascontiguousarray(xk[rows]), kk[rows], mm[rows])
        s[rows] = 1.0 / beta
        c[rows] = -s[rows] * portable.log(median)
    return c.reshape(B, K), s.reshape(B, K)


#: The largest excess of a severer limit state's curve over a milder one's [-] that a crossing
#: of their own fits may have and be kept (reported, not refitted): below the resolution of
#: any probability here (the Wilson 95 % interval of a proportion from up to 1000 motions
#: is wider than 3.8e-3 at any count), where refitting to remove it would move the curves
#: where the data are (curves of different β cross once, often far in their tails).
CROSSING_TOLERANCE = 1e-3


def _constrained_fit(
    x: np.ndarray,
    k: np.ndarray,
    m: np.ndarray,
    c0: np.ndarray,
    s0: np.ndarray,
    pairs: list[tuple[int, int]],
) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Maximum likelihood of nested limit states (x = ln(IM), m of shape (n,), k of shape
    (K, n); c0, s0: their own fits, z = c + s·x, NaN for a state without a fit) under the
    constraint that in each of ``pairs`` (milder, severer) the severer curve lies nowhere above
    the milder inside the intensities tested. z_milder − z_severer is linear in x, so the
    constraint is that it is ≥ 0 at the two ends of the range: linear in (c, s); the
    log-likelihood (the sum of the states' binomial probit likelihoods) is concave in (c, s):
    one maximum, found by SciPy's SLSQP from the own fits (coefficients centred on the middle
    of the range, s within :data:`BETA_BOUNDS`). States in no pair keep their own fits (the
    likelihood is a sum over the states). Returns (c, s, touching), touching saying which
    states meet a neighbour's curve at an end of the range (an active constraint)."""
    from scipy.optimize import LinearConstraint, minimize  # on first use (see wilson_interval)

    free = sorted({i for pair in pairs for i in pair})
    at = {state: p for p, state in enumerate(free)}
    K = len(free)
    ends = np.array([x.min(), x.max()])
    mid = 0.5 * (ends[0] + ends[1])
    xx = np.broadcast_to(x - mid, (K, x.size))
    kk, mm = k[free], np.broadcast_to(m, (K, x.size))

    def loss(p: np.ndarray) -> tuple[float, np.ndarray]:
        ll, g, _h = _probit_loglik(xx, kk, mm, p[:K], p[K:])
        return -float(ll.sum()), -np.concatenate([g.sum(axis=1), np.sum(g * xx, axis=1)])

    rows = np.zeros((2 * len(pairs), 2 * K))
    for r, ((i, j), end) in enumerate(itertools.product(pairs, ends - mid)):
        rows[r, [at[i], at[j], K + at[i], K + at[j]]] = 1.0, -1.0, end, -end
    s_start = s0[free]
    result = minimize(
        loss,
        np.concatenate([c0[free] + s_start * mid, s_start]),
        jac=True,
        method="SLSQP",
        bounds=[(None, None)] * K + [(_S_LO, _S_HI)] * K,
        constraints=[LinearConstraint(rows, 0.0, np.inf)],
        options={"ftol": 1e-12, "maxiter": 500},
    )
    a, s = result.x[:K], np.clip(result.x[K:], _S_LO, _S_HI)
    c, slope = c0.copy(), s0.copy()
    c[free], slope[free] = a - s * mid, s
    p = np.concatenate([a, s])
    gap = rows @ p
    active = (gap <= 1e-6 * np.maximum(1.0, np.abs(rows) @ np.abs(p))).reshape(len(pairs), 2)
    touching = np.zeros(c0.shape, dtype=bool)
    for (i, j), on in zip(pairs, active):
        if on.any():
            touching[[i, j]] = True
    return c, slope, touching


def _without_crossing(
    x: np.ndarray, k: np.ndarray, m: np.ndarray, order: list[int]
) -> tuple[np.ndarray, np.ndarray, np.ndarray, list[list[Crossing]]]:
    """Fits of nested limit states, one set per row (x = ln(IM), m of shape (B, n), k of shape
    (B, K, n); ``order``: mildest first): each state's own (:func:`_own_rows`), and where two
    neighbours' own curves cross inside the intensities tested by more than
    :data:`CROSSING_TOLERANCE`, the constrained fit of :func:`_constrained_fit` of those pairs
    (and of any pair that its refit makes cross so). Returns c, s (B, K; NaN: no fit),
    touching (B, K), and the crossings of the own fits of each row (:func:`_crossings`)."""
    c_own, s_own = _own_rows(x, k, m)
    c, s = c_own.copy(), s_own.copy()
    touching = np.zeros(c.shape, dtype=bool)
    own_crossings = []
    for b in range(x.shape[0]):
        found = _crossings(c[b], s[b], order, x[b])
        own_crossings.append(found)
        pairs: list[tuple[int, int]] = []
        while True:
            more = [
                (cross.milder, cross.severer)
                for cross in found
                if cross.excess > CROSSING_TOLERANCE and (cross.milder, cross.severer) not in pairs
            ]
            if not more:
                break
            pairs += more
            c[b], s[b], touching[b] = _constrained_fit(
                x[b], k[b], m[b], c_own[b], s_own[b], sorted(pairs)
            )
            found = _crossings(c[b], s[b], order, x[b])
    return c, s, touching, own_crossings


def _crossings(c: np.ndarray, s: np.ndarray, order: list[int], log_x: np.ndarray) -> list[Crossing]:
    """The neighbouring pairs whose curves (c, s: shape (K,)) cross inside the intensities
    ``log_x`` (ln(IM)): where, and by how much the severer curve exceeds the milder at most
    (on 1025 points of the range). ``at`` is NaN where the severer curve lies above the milder
    across the whole range (reversed medians, not a crossing inside it)."""
    import scipy.special  # on first use (see wilson_interval)

    lo, hi = float(log_x.min()), float(log_x.max())
    grid = np.linspace(lo, hi, 1025)
    found = []
    fitted = [i for i in order if np.isfinite(c[i])]
    for i, j in itertools.pairwise(fitted):
        # z_milder − z_severer at both ends, differences first: exactly 0 for equal curves
        gap_lo, gap_hi = ((c[i] - c[j]) + (s[i] - s[j]) * e for e in (lo, hi))
        if gap_lo >= 0.0 and gap_hi >= 0.0:
            continue
        inside = (gap_lo < 0.0) != (gap_hi < 0.0)
        at = math.exp((c[j] - c[i]) / (s[i] - s[j])) if inside else math.nan
        excess = scipy.special.ndtr(c[j] + s[j] * grid) - scipy.special.ndtr(c[i] + s[i] * grid)
        found.append(Crossing(i, j, at, float(np.max(excess))))
    return found


def bootstrap_limit_states(
    im: np.ndarray,
    outcomes: np.ndarray,
    *,
    n_boot: int,
    confidence: float,
    seed: int,
    measure: str | None = None,
    unit: str | None = None,
) -> LimitStateFits:
    """Lognormal curves of nested limit states that do not cross inside the intensities tested,
    with bootstrap intervals over the motions as :func:`bootstrap_fragility` draws them (the
    same resamples for the same seed).

    Each limit state is fitted alone, by the maximum likelihood of :func:`fit_lognormal`: its
    own median and β.  Curves of different β cross once; where two nested states' curves cross
    inside the intensities tested, the severer state is the likelier at some of them, which
    their data cannot be (every case that exceeds it exceeds the milder).  Where it is the
    likelier by more than :data:`CROSSING_TOLERANCE`, the pair is refitted together: the
    maximum of the sum of their likelihoods under the constraint that the severer curve lies
    nowhere above the milder inside the range (:func:`_constrained_fit`: linear constraints
    on the probit coefficients, a concave likelihood, so one maximum); a state whose refitted
    curve touches its neighbour's at an end of the range is flagged
    (:attr:`LimitStateFits.constrained`).  A smaller crossing, below the resolution of the
    data (typically far in the tails, at probabilities of 1e-5 and less), is kept: removing it
    would bend the curves where the data are.  Every crossing of the own fits is reported
    (:attr:`LimitStateFits.crossings`); every other state keeps its own maximum.

    Not one β for all states (an ordinal probit model, e.g. Nguyen & Lallemant 2022, Risk
    Analysis 42(5)): a state that the intensity separates (uplift, nearly a step: never, then
    always exceeded) has no finite maximum, β → 0 (:func:`fit_lognormal`), and a common β
    collapses with it, turning the curves of the other states into steps that contradict their
    data.  Here such a state's β stays at its bound, or grows only as much as a material
    crossing requires, and the others keep their own β.  Each bootstrap resample is fitted
    the same way, so that the intervals are those of the curves reported.

    ``im`` [the IM's unit, > 0] and ``outcomes`` (bool) of limit state i in ``outcomes[i]``,
    laid out as for :func:`bootstrap_fragility` (levels × motions, or one per motion for a
    cloud, where im holds each motion's IM); nested (every exceedance of a state is one of
    the states exceeded more often: :func:`severity_order`, checked by the caller).  A state
    without information (never or always exceeded) has the fit None.  ``n_boot`` 0: the point
    fits only, intervals NaN."""
    log_x = portable.log(im)
    K, n_motions = outcomes.shape[0], outcomes.shape[-1]
    order = severity_order(outcomes)[0]
    if outcomes.ndim == 3:
        k = outcomes.sum(axis=2).astype(float)[None]
        m = np.full((1, im.size), float(n_motions))
    else:
        k, m = outcomes.astype(float)[None], np.ones((1, im.size))
    c, s, touching, crossings = _without_crossing(log_x[None], k, m, order)
    parts_c, parts_s = [np.empty((0, K))], [np.empty((0, K))]
    for xb, kb, mb in _resampled_counts(log_x, outcomes, n_boot, seed):
        cb, sb, _, _ = _without_crossing(np.ascontiguousarray(xb), kb, mb, order)
        parts_c.append(cb)
        parts_s.append(sb)
    boot_s = np.concatenate(parts_s)
    with np.errstate(invalid="ignore"):
        boot_m = portable.exp(-np.concatenate(parts_c) / boot_s)
    q = [(1.0 - confidence) / 2.0, (1.0 + confidence) / 2.0]
    fits: list[FragilityFit | None] = []
    for i in range(K):
        if not np.isfinite(c[0, i]):
            fits.append(None)
            continue
        point = LognormalFit(
            float(portable.exp(-c[0, i] / s[0, i])),
            float(_betas(s[0, i])),
            im=measure,
            unit=unit,
            im_range=(float(im.min()), float(im.max())),
        )
        ok = np.isfinite(boot_m[:, i])
        nan = Interval(math.nan, math.nan)
        fits.append(
            FragilityFit(
                fit=point,
                median_ci=Interval(*map(float, np.quantile(boot_m[ok, i], q))) if ok.any() else nan,
                beta_ci=Interval(*map(float, np.quantile(_betas(boot_s[ok, i]), q)))
                if ok.any()
                else nan,
                confidence=confidence,
                n_boot=int(n_boot),
                seed=int(seed),
                n_unfitted=int(n_boot - ok.sum()),
                n_separated=int(np.sum(boot_s[ok, i] >= _S_HI)),
            )
        )
    return LimitStateFits(fits, [bool(t) for t in touching[0]], crossings[0])


def _outcomes(outcomes, n_im: int) -> np.ndarray:
    """``outcomes`` as a bool array of shape (n_im, n_motions) or (n_im,), checked."""
    y = np.asarray(outcomes)
    if y.dtype != bool:
        if y.dtype.kind not in "iuf" or not np.isin(y, (0, 1)).all():
            raise InputError("outcomes must be booleans (True = overturned) or 0/1")
        y = y.astype(bool)
    if y.ndim not in (1, 2) or y.shape[0] != n_im:
        raise InputError(
            f"outcomes must have shape (n_levels, n_motions) = ({n_im}, …) for IDA/MSA or "
            f"({n_im},) for a cloud (one per im), got {y.shape}"
        )
    if y.ndim == 2 and y.shape[1] < 2:
        raise InputError(f"outcomes must hold at least 2 motions, got {y.shape[1]}")
    return y
