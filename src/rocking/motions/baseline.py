"""Quadratic baseline correction of accelerations (paper Section 4): :func:`baseline_correct`."""

from __future__ import annotations

import numpy as np
from numpy.typing import ArrayLike

from ..core import portable
from ..core.checks import finite_array, positive
from ..core.compile import kernel, parallel_kernel, prange
from ..errors import InputError

# The trapezoidal rules below give SciPy's bits (scipy.integrate.trapezoid and
# cumulative_trapezoid with a scalar step: the terms dx·(y[i+1] + y[i])/2, summed by np.sum or
# accumulated by np.cumsum; tests/test_motions.py checks it), in compiled code: with NumPy's
# array operations the correction of 500 motions of 12,001 samples took 0.18 s, most of it
# temporaries written and read again; importing scipy.integrate would cost every ``rocking
# motions generate`` a quarter of a second besides.


@kernel(inline="always")
def _block_sum(x, lo, n):
    """x[lo] + … + x[lo + n − 1] for n ≤ 128 as NumPy sums such a block: 8 running sums (from
    n = 8 on), combined pairwise, then the rest one by one."""
    if n < 8:
        res = 0.0
        for i in range(n):
            res += x[lo + i]
        return res
    r0, r1, r2, r3 = x[lo], x[lo + 1], x[lo + 2], x[lo + 3]
    r4, r5, r6, r7 = x[lo + 4], x[lo + 5], x[lo + 6], x[lo + 7]
    i = 8
    while i < n - n % 8:
        r0 += x[lo + i]
        r1 += x[lo + i + 1]
        r2 += x[lo + i + 2]
        r3 += x[lo + i + 3]
        r4 += x[lo + i + 4]
        r5 += x[lo + i + 5]
        r6 += x[lo + i + 6]
        r7 += x[lo + i + 7]
        i += 8
    res = ((r0 + r1) + (r2 + r3)) + ((r4 + r5) + (r6 + r7))
    while i < n:
        res += x[lo + i]
        i += 1
    return res


@kernel
def _pairwise_sum(x, n):
    """x[0] + … + x[n − 1] in the order of NumPy's pairwise summation (``np.sum`` of a
    contiguous row, numpy/_core/src/umath/loops_utils.h.src): blocks of at most 128 terms
    (:func:`_block_sum`), larger ranges cut in two at a multiple of 8 below their middle and the
    halves' sums added.  Written out so that compiled code can call it, and without recursion
    (Numba's cache does not load recursive functions safely): the ranges still to sum on one
    stack, the sums of finished halves on another; each range's depth is below 64."""
    lo_stack = np.empty(128, dtype=np.int64)
    n_stack = np.empty(128, dtype=np.int64)  # n ≥ 0: a range to sum; −1: add the last two sums
    sums = np.empty(64)
    lo_stack[0], n_stack[0] = 0, n
    tasks = 1
    done = 0
    while tasks:
        tasks -= 1
        lo = lo_stack[tasks]
        m = n_stack[tasks]
        if m < 0:
            done -= 1
            sums[done - 1] = sums[done - 1] + sums[done]
        elif m <= 128:
            sums[done] = _block_sum(x, lo, m)
            done += 1
        else:
            half = m // 2
            half -= half % 8
            # popped in the order: the first half, the second, their sum
            lo_stack[tasks], n_stack[tasks] = 0, -1
            lo_stack[tasks + 1], n_stack[tasks + 1] = lo + half, m - half
            lo_stack[tasks + 2], n_stack[tasks + 2] = lo, half
            tasks += 3
    return sums[0]


@kernel(inline="always")
def _trapezoid_term(y, i, dx):
    """dx·(y[i+1] + y[i])/2 [y·s]: the trapezoid of y over sample interval i (step dx [s]), with
    SciPy's operations in SciPy's order."""
    return dx * (y[i + 1] + y[i]) / 2.0


@kernel
def _trapezoid_1d(y, dx, terms):
    """∫ y dt [y·s] of the 1-D y by the trapezoidal rule with step dx [s] (SciPy's
    ``trapezoid``); ``terms``: scratch of y.size − 1."""
    for i in range(y.size - 1):
        terms[i] = _trapezoid_term(y, i, dx)
    return 0.0 + _pairwise_sum(terms, y.size - 1)


@kernel
def _cumulative_trapezoid_1d(y, dx, out):
    """out[i] = ∫_0^{t_i} y dt [y·s] of the 1-D y (0 at the first sample; SciPy's
    ``cumulative_trapezoid`` with ``initial=0``)."""
    out[0] = 0.0
    for i in range(y.size - 1):  # out[1] = 0 + term: a zero's sign at most differs from SciPy's
        out[i + 1] = out[i] + _trapezoid_term(y, i, dx)


def _trapezoid(y: np.ndarray, dx: float) -> np.ndarray:
    """∫ y dt over the last axis [y·s] by the trapezoidal rule with step ``dx`` [s]."""
    rows = np.ascontiguousarray(y, dtype=np.float64).reshape(-1, np.shape(y)[-1])
    terms = np.empty(rows.shape[1] - 1)
    out = np.array([_trapezoid_1d(row, dx, terms) for row in rows])
    return out.reshape(np.shape(y)[:-1])


def _cumulative_trapezoid(y: np.ndarray, dx: float) -> np.ndarray:
    """∫_0^t y dt [y·s] at every sample along the last axis (0 at the first one)."""
    rows = np.ascontiguousarray(y, dtype=np.float64).reshape(-1, np.shape(y)[-1])
    out = np.empty(rows.shape)
    for row, o in zip(rows, out):
        _cumulative_trapezoid_1d(row, dx, o)
    return out.reshape(np.shape(y))


@parallel_kernel
def _correct(rows, dx, basis_acc, basis_vel, gram, out):
    """out[m] = rows[m] − Σ_j c_mj·basis_acc[j] [m/s²] with c_m the solution of the normal
    equations gram·c_m = (∫ψ_k v_m dt)_k (v_m = ∫ rows[m] dt, ψ_k = basis_vel[k]), motion by
    motion (each motion's bits do not depend on the others or on the threads)."""
    n_k, n_t = basis_acc.shape
    for m in prange(rows.shape[0]):
        y = rows[m]
        vel = np.empty(n_t)
        product = np.empty(n_t)
        terms = np.empty(n_t - 1)
        _cumulative_trapezoid_1d(y, dx, vel)
        rhs = np.empty((n_k, 1))
        for k in range(n_k):
            for i in range(n_t):
                product[i] = vel[i] * basis_vel[k, i]
            rhs[k, 0] = _trapezoid_1d(product, dx, terms)
        coef = portable.lstsq_kernel(gram.copy(), rhs)
        for i in range(n_t):
            baseline = 0.0
            for j in range(n_k):
                baseline = baseline + coef[j, 0] * basis_acc[j, i]
            out[m, i] = y[i] - baseline


def baseline_correct(acc: ArrayLike, dt: float, order: int = 2) -> np.ndarray:
    """Subtract the polynomial baseline that minimises the mean-square velocity (paper Section 4).

    The corrected acceleration is a*(t) = a(t) − Σ_{k=0..order} (k+1)(k+2)·c_k·τ^k, τ = t/T,
    whose velocity v*(t) (trapezoidal integration from v(0) = 0) has the least mean square
    over [0, T] (Brady 1966; reference.md §6; ``order=2`` is the paper's quadratic correction).
    The normal equations of reference.md §6 are formed with the trapezoidal rule — the same
    quadrature that integrates a to v — so a polynomial of degree ≤ ``order`` is removed exactly.

    Parameters
    ----------
    acc : array_like, shape (n_t,) or (n, n_t)
        Acceleration(s) [m/s²] sampled at ``dt`` from t = 0; n_t > ``order`` + 1.
    dt : float
        Time step [s], > 0.
    order : int
        Degree of the acceleration polynomial [-], ≥ 0.

    Returns
    -------
    ndarray
        Corrected acceleration [m/s²], same shape as ``acc``.
    """
    k_max = int(order)
    if k_max != order or k_max < 0:
        raise InputError(f"order must be an integer ≥ 0, got {order!r}")
    a = finite_array("acc", acc, ndim=(1, 2), min_len=k_max + 2)
    dt = positive("dt", dt, "s")
    tau = np.linspace(0.0, 1.0, a.shape[-1])
    k = np.arange(k_max + 1)[:, None]
    # τ^k by repeated products (each rounded once, on every CPU the same; NumPy's power is not)
    tau_k = np.cumprod(np.vstack([np.ones_like(tau), np.tile(tau, (k_max, 1))]), axis=0)
    basis_acc = (k + 1) * (k + 2) * tau_k
    basis_vel = _cumulative_trapezoid(basis_acc, dt)
    # Normal equations ∫ψ_k ψ_j dt · c_j = ∫ψ_k v dt (reference.md §6, ψ_k = basis velocities),
    # solved motion by motion in a fixed order (LAPACK's depends on the CPU)
    gram = _trapezoid(basis_vel[:, None, :] * basis_vel[None, :, :], dt)
    portable.lstsq(gram, np.zeros(k_max + 1))  # raises if the basis is degenerate
    rows = np.ascontiguousarray(a.reshape(-1, a.shape[-1]))
    out = np.empty_like(rows)
    _correct(rows, dt, basis_acc, basis_vel, gram, out)
    return out.reshape(a.shape)
