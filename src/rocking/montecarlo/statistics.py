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


def _bootstrap_resamples(seed: int, n_boot: int, n: int) -> np.ndarray:
    """``n_boot`` resamples with replacement of ``n`` motions, drawn from NumPy's default
    generator seeded with ``seed``: their indices, shape (n_boot, n)."""
    rng = np.random.default_rng(int(seed))
    draws = [rng.integers(0, n, n) for _ in range(n_boot)]
    return np.array(draws, dtype=np.int64).reshape(n_boot, n)


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
    beta[rows] = np.where(s >= s_hi, BETA_BOUNDS[0], np.where(s <= s_lo, BETA_BOUNDS[1], 1.0 / s))
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


def _ordinal_rows(x: np.ndarray, k: np.ndarray, m: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Joint maximum-likelihood fits of nested limit states, one per row: K lognormal curves
    with one β and a median each (an ordinal probit model: z_i = c_i + s·x, s = 1/β), so that
    the curves never cross.  x = ln(IM) and m trials of shape (B, n), k of shape (B, K, n)
    (k[:, i] the exceedances of limit state i).  Returns (medians (B, K), βs (B,)); a limit
    state all 0 or all m in a row has no information on its median (NaN), and a row with no
    such state is NaN throughout.

    Newton's method on (c_1 … c_K, s), whose Hessian is an arrowhead (c_i meets only s), solved
    through its Schur complement; from the one-by-one fits (:func:`_fit_rows`), s at the mean
    of their slopes.  A step that would take s beyond its bounds (:data:`BETA_BOUNDS`) is
    shortened to end on the bound (or, from the bound outward, moves the c alone); a step is
    halved until the likelihood does not decrease; a fit ends when the gain its step predicts
    is below the rounding of ℓ (the likelihood is concave: a probit model)."""
    B, K, n = k.shape
    mm = np.broadcast_to(m[:, None, :], k.shape)
    informed = np.any(k > 0, axis=2) & np.any(k < mm, axis=2)  # (B, K)
    flat = informed.ravel()
    rows = np.flatnonzero(flat)
    xk = np.broadcast_to(x[:, None, :], k.shape).reshape(B * K, n)
    med1, _beta1, _sep = _fit_rows(
        np.ascontiguousarray(xk[rows]), k.reshape(B * K, n)[rows], mm.reshape(B * K, n)[rows]
    )
    slope = np.zeros(B * K)
    slope[rows] = 1.0 / _beta1
    lnmed = np.zeros(B * K)
    lnmed[rows] = portable.log(med1)
    used = informed.sum(axis=1)
    s = np.clip(slope.reshape(B, K).sum(axis=1) / np.maximum(used, 1), _S_LO, _S_HI)
    c = -s[:, None] * lnmed.reshape(B, K)
    w = informed.astype(float)[:, :, None]  # states without information weigh nothing
    kw, mw = k * w, mm * w

    def loglik(c, s, on):
        ll, g, h = _probit_loglik(
            xk.reshape(B, K, n)[on].reshape(-1, n),
            kw[on].reshape(-1, n),
            mw[on].reshape(-1, n),
            c[on].ravel(),
            np.repeat(s[on], K),
        )
        shape = (on.size, K, n)
        return ll.reshape(on.size, K).sum(axis=1), g.reshape(shape), h.reshape(shape)

    on = np.flatnonzero(used > 0)
    ll, g, h = loglik(c, s, on)
    for _ in range(_NEWTON_MAX):
        if on.size == 0:
            break
        xo, co, so, inf = x[on][:, None, :], c[on], s[on], informed[on]
        gc, gs = g.sum(axis=2), np.sum(g * xo, axis=(1, 2))
        d = np.where(inf, h.sum(axis=2), -1.0)  # -1: a state without information stays put
        b = np.sum(h * xo, axis=2)
        a = np.sum(h * xo * xo, axis=(1, 2))
        with np.errstate(divide="ignore", invalid="ignore"):
            schur = a - np.sum(b * b / d, axis=1)
            ds = (-gs + np.sum(b * gc / d, axis=1)) / schur
            ds = np.where(np.isfinite(ds), ds, 0.0)
            outward = ((so >= _S_HI) & (ds > 0.0)) | ((so <= _S_LO) & (ds < 0.0))
            ds = np.where(outward, 0.0, ds)
            dc = (-gc - b * ds[:, None]) / d
            bound = np.where(so + ds > _S_HI, _S_HI, np.where(so + ds < _S_LO, _S_LO, np.nan))
            t = np.where(np.isnan(bound), 1.0, (bound - so) / ds)
        rounding = 8.0 * np.finfo(float).eps * np.maximum(1.0, np.abs(ll))
        gain = 0.5 * t * (np.sum(gc * dc, axis=1) + gs * ds)
        last = gain <= rounding
        trial = np.flatnonzero(~last)
        ll_new, g_new, h_new = ll.copy(), g.copy(), h.copy()
        while trial.size:
            c_try, s_try = c.copy(), s.copy()
            c_try[on[trial]] = co[trial] + t[trial, None] * dc[trial]
            s_try[on[trial]] = np.clip(so[trial] + t[trial] * ds[trial], _S_LO, _S_HI)
            ll_t, g_t, h_t = loglik(c_try, s_try, on[trial])
            ok = ll_t >= ll[trial] - rounding[trial]
            ll_new[trial[ok]], g_new[trial[ok]], h_new[trial[ok]] = ll_t[ok], g_t[ok], h_t[ok]
            c[on[trial[ok]]] = c_try[on[trial[ok]]]
            s[on[trial[ok]]] = s_try[on[trial[ok]]]
            t[trial[~ok]] *= 0.5
            trial = trial[~ok & (t[trial] >= 1e-12)]
        moved = ~last & (ll_new > ll + rounding)  # still gaining: another step
        on, ll, g, h = on[moved], ll_new[moved], g_new[moved], h_new[moved]
    with np.errstate(divide="ignore", invalid="ignore", over="ignore"):
        medians = np.where(informed, portable.exp(-c / s[:, None]), np.nan)
    beta = np.where(used > 0, 1.0 / s, np.nan)
    return medians, beta


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
    resamples = _bootstrap_resamples(seed, n_boot, n_motions)
    median_parts, beta_parts, separated = [np.empty(0)], [np.empty(0)], 0
    step = max(1, _FIT_BLOCK_ELEMENTS // max(x.size, n_motions))  # resamples at a time
    for idx in (resamples[i : i + step] for i in range(0, n_boot, step)):
        if y.ndim == 2:  # whole motions: the count of each level over the resampled motions
            kb = np.sum(y[:, idx], axis=2).T.astype(float)
            xb, mb = np.broadcast_to(log_x, kb.shape), np.full(kb.shape, float(n_motions))
        else:
            xb, kb, mb = log_x[idx], y[idx].astype(float), np.ones(idx.shape)
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


def bootstrap_limit_states(
    im: np.ndarray,
    outcomes: np.ndarray,
    *,
    n_boot: int,
    confidence: float,
    seed: int,
    measure: str | None = None,
    unit: str | None = None,
) -> list[FragilityFit | None]:
    """Lognormal curves of nested limit states fitted jointly, with one β (:func:`_ordinal_rows`:
    an ordinal probit model, so that the curves never cross; e.g. Nguyen & Lallemant 2022,
    "Order matters: the benefits of ordinal fragility curves for damage and loss estimation",
    Risk Analysis 42(5)), with bootstrap intervals over the motions as
    :func:`bootstrap_fragility` draws them (the same resamples for the same seed).

    ``im`` [the IM's unit, > 0] and ``outcomes`` (bool) of limit state i in ``outcomes[i]``,
    laid out as for :func:`bootstrap_fragility` (levels × motions, or one per motion for a
    cloud, where im holds each motion's IM); every exceedance of a state is one of the states
    before it or after it (nested: :func:`severity_order`, checked by the caller).  Returns one
    :class:`FragilityFit` per limit state (its β and β interval those of all), None for a
    state without information (never or always exceeded).  ``n_boot`` 0: the point fit only,
    intervals NaN."""
    log_x = portable.log(im)
    K, n_motions = outcomes.shape[0], outcomes.shape[-1]
    if outcomes.ndim == 3:
        k = outcomes.sum(axis=2).astype(float)[None]
        m = np.full((1, im.size), float(n_motions))
    else:
        k, m = outcomes.astype(float)[None], np.ones((1, im.size))
    medians, beta = _ordinal_rows(log_x[None], k, m)
    parts_m, parts_b = [np.empty((0, K))], [np.empty(0)]
    resamples = _bootstrap_resamples(seed, n_boot, n_motions)
    step = max(1, _FIT_BLOCK_ELEMENTS // (K * max(im.size, n_motions)))
    for idx in (resamples[i : i + step] for i in range(0, n_boot, step)):
        if outcomes.ndim == 3:
            kb = np.transpose(np.sum(outcomes[:, :, idx], axis=3), (2, 0, 1)).astype(float)
            xb = np.broadcast_to(log_x, (idx.shape[0], im.size))
            mb = np.full(xb.shape, float(n_motions))
        else:
            kb = np.transpose(outcomes[:, idx], (1, 0, 2)).astype(float)
            xb, mb = log_x[idx], np.ones(idx.shape)
        med_b, beta_b = _ordinal_rows(np.ascontiguousarray(xb), kb, mb)
        parts_m.append(med_b)
        parts_b.append(beta_b)
    boot_m, boot_b = np.concatenate(parts_m), np.concatenate(parts_b)
    q = [(1.0 - confidence) / 2.0, (1.0 + confidence) / 2.0]
    ok_b = boot_b[np.isfinite(boot_b)]
    beta_ci = (
        Interval(*map(float, np.quantile(ok_b, q))) if ok_b.size else Interval(math.nan, math.nan)
    )
    fits: list[FragilityFit | None] = []
    for i in range(K):
        if not np.isfinite(medians[0, i]):
            fits.append(None)
            continue
        point = LognormalFit(
            float(medians[0, i]),
            float(beta[0]),
            im=measure,
            unit=unit,
            im_range=(float(im.min()), float(im.max())),
        )
        ok = boot_m[np.isfinite(boot_m[:, i]), i]
        med_ci = (
            Interval(*map(float, np.quantile(ok, q))) if ok.size else Interval(math.nan, math.nan)
        )
        fits.append(
            FragilityFit(
                fit=point,
                median_ci=med_ci,
                beta_ci=beta_ci if n_boot else Interval(math.nan, math.nan),
                confidence=confidence,
                n_boot=int(n_boot),
                seed=int(seed),
                n_unfitted=int(n_boot - ok.size),
                n_separated=int(np.sum(boot_b == BETA_BOUNDS[0])),
            )
        )
    return fits


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
