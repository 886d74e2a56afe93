"""Statistics of overturning counts: Wilson score intervals and lognormal fragility curves fitted by
maximum likelihood.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from ..core.checks import finite_array, in_range
from ..errors import InputError


def wilson_interval(count, n, confidence: float = 0.95):
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
    count, n = np.broadcast_arrays(np.asarray(count), np.asarray(n))
    if count.dtype.kind not in "iu" or n.dtype.kind not in "iu":
        raise InputError("count and n must be integers")
    if np.any(n < 1) or np.any(count < 0) or np.any(count > n):
        raise InputError("count and n must satisfy 0 <= count <= n and n >= 1")
    pairs, inverse = np.unique(
        np.stack([count.ravel(), n.ravel()], axis=1), axis=0, return_inverse=True
    )
    bounds = np.array([_wilson(int(k), int(m), confidence) for k, m in pairs]).reshape(-1, 2)
    low = bounds[inverse.ravel(), 0].reshape(count.shape)
    high = bounds[inverse.ravel(), 1].reshape(count.shape)
    return low, high


def _wilson(k: int, n: int, confidence: float) -> tuple[float, float]:
    import scipy.stats  # on first use: ~0.5 s of import that most commands do not need

    ci = scipy.stats.binomtest(k, n).proportion_ci(confidence, method="wilson")
    return ci.low, ci.high


@dataclass(frozen=True)
class LognormalFit:
    """Lognormal fragility curve P(A_gx) = Φ(ln(A_gx/median)/beta).

    Attributes
    ----------
    median : float
        A_gx of 50 % probability [g].
    beta : float
        Logarithmic standard deviation (dispersion) [-].
    """

    median: float
    beta: float

    def probability(self, agx) -> np.ndarray:
        """Probability of overturning at ``agx`` [g] (array_like, > 0) [-]."""
        import scipy.stats  # on first use (see _wilson)

        return scipy.stats.norm.cdf(np.log(np.asarray(agx, dtype=float) / self.median) / self.beta)


def fit_lognormal(agx, count, n) -> LognormalFit:
    """Maximum-likelihood lognormal fragility curve from overturning counts.

    Maximises the binomial log-likelihood Σ [k·ln P(A) + (n − k)·ln(1 − P(A))] with
    P(A) = Φ(ln(A/median)/β) over (ln median, ln β) with scipy.optimize (Nelder–Mead from a
    probit-regression start), β kept in [1e-3, 10].

    Parameters
    ----------
    agx : array_like
        Intensities A_gx [g], > 0.
    count : array_like of int
        Motions that overturned the body at each A_gx.
    n : int or array_like of int
        Motions at each A_gx (≥ 1, ≥ count).

    Returns
    -------
    LognormalFit

    Raises
    ------
    InputError
        On bad shapes or values, or if every count is 0 or every count is n (no information on
        the median).
    """
    agx = finite_array("agx", agx, ndim=(1,))
    if np.any(agx <= 0.0):
        raise InputError("agx must be > 0 [g]")
    count = np.asarray(count)
    n = np.broadcast_to(np.asarray(n), count.shape)
    if count.shape != agx.shape:
        raise InputError(f"count must have one value per agx ({agx.size}), got shape {count.shape}")
    wilson_interval(count, n)  # validates 0 <= count <= n, n >= 1 (integers)
    if np.all(count == 0) or np.all(count == n):
        raise InputError("fit_lognormal needs counts that are not all 0 and not all n")
    import scipy.stats  # on first use (see _wilson)

    x = np.log(agx)
    k = count.astype(float)
    m = n.astype(float)

    def nll(q):
        z = (x - q[0]) / math.exp(q[1])
        return -np.sum(k * scipy.stats.norm.logcdf(z) + (m - k) * scipy.stats.norm.logsf(z))

    # start: probit regression line through the empirical proportions (clipped away from 0, 1)
    p = np.clip((k + 0.5) / (m + 1.0), 1e-3, 1 - 1e-3)
    slope, icpt = np.polyfit(x, scipy.stats.norm.ppf(p), 1, w=np.sqrt(m))
    beta0 = 1.0 / slope if slope > 0.1 else 1.0
    mu0 = -icpt / slope if slope > 0.1 else float(np.average(x, weights=m))
    q0 = [mu0, math.log(min(max(beta0, 1e-3), 10.0))]
    res = scipy.optimize.minimize(
        nll,
        q0,
        method="Nelder-Mead",
        bounds=[(None, None), (math.log(1e-3), math.log(10.0))],
        options={"xatol": 1e-10, "fatol": 1e-12, "maxiter": 10_000},
    )
    return LognormalFit(median=float(math.exp(res.x[0])), beta=float(math.exp(res.x[1])))
