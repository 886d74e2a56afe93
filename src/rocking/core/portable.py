"""Numerics whose bits do not depend on the CPU they run on.

NumPy picks its float64 ``sin``, ``cos``, ``exp``, ``log`` and ``arctan2`` loops at run time
from the CPU's instruction sets (on AVX-512 machines vectorised approximations, elsewhere the C
library's functions), and OpenBLAS picks its BLAS and LAPACK kernels, and with them the order
of their sums, by CPU model (``OPENBLAS_CORETYPE`` shows it on one machine).  Motions generated
from one seed then differed in their last bits between machines, and so did every Monte Carlo
outcome that turns on them.  The functions here compute what the motions, response spectra and
floor motions need through the C library's scalar functions (compiled calls: Numba without
SVML) and through small linear algebra written out with its sums in one fixed order, so that
they give the same bits on every x86-64 CPU with the same C library.  On machines without
AVX-512 the elementary functions give exactly NumPy's results (tests/test_portable.py).

The linear algebra is hand-written only because the libraries made for it (LAPACK through
NumPy and SciPy) cannot promise this; it is for the small, well-conditioned systems of this
package (at most a few hundred unknowns), not a general replacement.
"""

from __future__ import annotations

import math

import numpy as np
from numpy.typing import ArrayLike

from .compile import kernel, parallel_kernel, prange

_SIN, _COS, _EXP, _EXPM1, _LOG, _LOG10, _ATAN2, _POW = range(8)


@kernel(inline="always")
def _value(op, x, y):
    """f(x) (or f(x, y)) through the C library's function f of ``op``."""
    if op == _SIN:
        return math.sin(x)
    if op == _COS:
        return math.cos(x)
    if op == _EXP:
        return math.exp(x)
    if op == _EXPM1:
        return math.expm1(x)
    if op == _LOG:
        return math.log(x) if x >= 0.0 else math.nan
    if op == _LOG10:
        return math.log10(x) if x >= 0.0 else math.nan
    if op == _ATAN2:
        return math.atan2(x, y)
    if y == 2.0:  # NumPy's shortcuts for a constant exponent, exact on every CPU
        return x * x
    if y == 0.5:
        return math.sqrt(x)
    if y == -1.0:
        return 1.0 / x
    return x**y


@kernel
def _serial(op, x, y, y_step, out):
    """out[i] = f(x[i], y[i·y_step]): y_step 0 for the one-argument functions (y = [0])."""
    for i in range(out.size):
        out[i] = _value(op, x[i], y[i * y_step])


@parallel_kernel
def _threads(op, x, y, y_step, out):
    """:func:`_serial` on all threads."""
    for i in prange(out.size):
        out[i] = _value(op, x[i], y[i * y_step])


#: Elements from which an elementwise function runs on all threads (below it, starting the
#: threads costs more than they save).
_THREADS_FROM = 1 << 16


_NO_Y = np.zeros(1)


def _apply(op: int, x: ArrayLike, y: ArrayLike | None = None) -> np.ndarray:
    a = np.asarray(x, dtype=np.float64)
    if y is None:
        b, y_step = _NO_Y, 0
    else:
        a, b = np.broadcast_arrays(a, np.asarray(y, dtype=np.float64))
        b, y_step = np.ascontiguousarray(b).reshape(-1), 1
    out = np.empty(a.shape)  # the (broadcast) input's shape, 0-d included
    run = _threads if a.size >= _THREADS_FROM else _serial
    run(op, np.ascontiguousarray(a).reshape(-1), b, y_step, out.reshape(-1))
    return out


def sin(x: ArrayLike) -> np.ndarray:
    """sin x (x in radians), elementwise, as a float64 array."""
    return _apply(_SIN, x)


def cos(x: ArrayLike) -> np.ndarray:
    """cos x (x in radians), elementwise, as a float64 array."""
    return _apply(_COS, x)


def exp(x: ArrayLike) -> np.ndarray:
    """eˣ, elementwise, as a float64 array."""
    return _apply(_EXP, x)


def expm1(x: ArrayLike) -> np.ndarray:
    """eˣ − 1 (accurate for small x), elementwise, as a float64 array."""
    return _apply(_EXPM1, x)


def log(x: ArrayLike) -> np.ndarray:
    """Natural logarithm, elementwise, as a float64 array (−inf at 0, NaN below 0)."""
    return _apply(_LOG, x)


def log10(x: ArrayLike) -> np.ndarray:
    """Decimal logarithm, elementwise, as a float64 array (−inf at 0, NaN below 0)."""
    return _apply(_LOG10, x)


def power(x: ArrayLike, y: ArrayLike) -> np.ndarray:
    """xʸ, elementwise with broadcasting, as a float64 array: the C library's ``pow``, except
    x·x, √x and 1/x for the exponents 2, 0.5 and −1 (as NumPy computes ``x ** c`` for these
    constants)."""
    return _apply(_POW, x, y)


def geomspace(start: float, stop: float, num: int) -> np.ndarray:
    """``num`` numbers from ``start`` to ``stop`` (both > 0), evenly spaced on a log scale:
    NumPy's ``geomspace`` (10 to the powers of an even spacing of the decimal logarithms, the
    ends set exactly) through :func:`log10` and :func:`power`."""
    if not (start > 0.0 and stop > 0.0):
        raise ValueError(f"geomspace needs start and stop > 0, got {start!r}, {stop!r}")
    ends = log10(np.array([start, stop], dtype=np.float64))
    out = power(10.0, np.linspace(ends[0], ends[1], num))
    if num > 0:
        out[0] = start
    if num > 1:
        out[-1] = stop
    return out


def arctan2(y: ArrayLike, x: ArrayLike) -> np.ndarray:
    """Angle of the point (x, y) [rad] in [−π, π], elementwise with broadcasting."""
    return _apply(_ATAN2, y, x)


#: Terms of the Taylor series of :func:`expm` and the largest 1-norm it is applied to (after
#: scaling by a power of 2): the truncation error is below 0.5¹⁹/19! ≈ 2e-23 of the norm.
_EXPM_TERMS = 18
_EXPM_NORM = 0.5


@kernel
def _matmul_kernel(a, b, out):
    for i in range(a.shape[0]):
        for j in range(b.shape[1]):
            s = 0.0
            for q in range(a.shape[1]):
                s += a[i, q] * b[q, j]
            out[i, j] = s


@kernel
def _expm_kernel(m, out, terms, limit):
    # explicit loops throughout: Numba takes seconds to compile a 2-D slice assignment
    n = m.shape[1]
    a = np.empty((n, n))
    e = np.empty((n, n))
    t = np.empty((n, n))
    for k in range(m.shape[0]):
        norm = 0.0  # 1-norm: largest column sum of magnitudes
        for j in range(n):
            col = 0.0
            for i in range(n):
                col += abs(m[k, i, j])
            norm = max(norm, col)
        scale = 1.0
        squarings = 0
        while norm > limit:  # scale by 2^-s (exact)
            norm *= 0.5
            scale *= 0.5
            squarings += 1
        for i in range(n):
            for j in range(n):
                a[i, j] = m[k, i, j] * scale
                e[i, j] = 1.0 if i == j else 0.0
        for term in range(terms, 0, -1):  # Horner: e = I + a·e/term
            _matmul_kernel(a, e, t)
            for i in range(n):
                for j in range(n):
                    e[i, j] = t[i, j] / term + (1.0 if i == j else 0.0)
        for _ in range(squarings):
            _matmul_kernel(e, e, t)
            e, t = t, e
        for i in range(n):
            for j in range(n):
                out[k, i, j] = e[i, j]


def expm(m: ArrayLike) -> np.ndarray:
    """Matrix exponential of each (n, n) matrix of ``m`` (shape (..., n, n)), by scaling and
    squaring of a Taylor series: for the small matrices of this package (a few rows), accurate
    to a few units of round-off like ``scipy.linalg.expm``."""
    a = np.asarray(m, dtype=np.float64)
    if a.ndim < 2 or a.shape[-1] != a.shape[-2]:
        raise ValueError(f"expm needs square matrices, got shape {a.shape}")
    flat = np.ascontiguousarray(a.reshape(-1, *a.shape[-2:]))
    out = np.empty_like(flat)
    _expm_kernel(flat, out, _EXPM_TERMS, _EXPM_NORM)
    return out.reshape(a.shape)


@kernel
def _reflect(v, vv, j, x, first):
    """Columns ``first``… of x (rows j…) reflected by the Householder vector v (‖v‖² = vv)."""
    for c in range(first, x.shape[1]):
        s = 0.0
        for i in range(j, x.shape[0]):
            s += v[i] * x[i, c]
        s = 2.0 * s / vv
        for i in range(j, x.shape[0]):
            x[i, c] -= s * v[i]


@kernel
def lstsq_kernel(a, b):
    """Householder QR of a (m, n), m ≥ n, applied to b (m, k); both overwritten. Returns x (n, k)
    of least ‖a·x − b‖ (units of b over those of a), or an empty array if a column is dependent
    on the earlier ones.  Compiled: :func:`lstsq` for Python callers, this for kernels (e.g. the
    baseline correction's solve per motion); each column of b is solved as if alone."""
    m, n = a.shape
    k = b.shape[1]
    v = np.empty(m)
    diag = np.empty(n)
    for j in range(n):
        norm = 0.0
        for i in range(j, m):
            norm += a[i, j] * a[i, j]
        norm = math.sqrt(norm)
        if norm == 0.0:
            return np.empty((0, k))
        alpha = -math.copysign(norm, a[j, j])
        for i in range(j, m):
            v[i] = a[i, j]
        v[j] -= alpha
        vv = 0.0
        for i in range(j, m):
            vv += v[i] * v[i]
        diag[j] = alpha
        _reflect(v, vv, j, a, j + 1)  # the remaining columns of a
        _reflect(v, vv, j, b, 0)  # and every right-hand side
    x = np.empty((n, k))
    for c in range(k):  # back substitution with R (diag on the diagonal, a above it)
        for j in range(n - 1, -1, -1):
            s = b[j, c]
            for q in range(j + 1, n):
                s -= a[j, q] * x[q, c]
            x[j, c] = s / diag[j]
    return x


def lstsq(a: ArrayLike, b: ArrayLike) -> np.ndarray:
    """Least-squares solution x of a·x ≈ b (a: (m, n) of full column rank, m ≥ n; b: (m,) or
    (m, k)) by Householder QR; a square a gives the solution of a·x = b."""
    am = np.array(a, dtype=np.float64, order="C")
    bm = np.array(b, dtype=np.float64, order="C")
    vector = bm.ndim == 1
    if vector:
        bm = bm[:, None]
    if am.ndim != 2 or am.shape[0] < am.shape[1] or bm.ndim != 2 or bm.shape[0] != am.shape[0]:
        raise ValueError(
            f"lstsq needs a (m, n), m >= n, and b (m[, k]); got {am.shape}, {bm.shape}"
        )
    x = lstsq_kernel(am, bm)
    if x.shape[0] != am.shape[1]:
        raise np.linalg.LinAlgError("lstsq: the columns of a are linearly dependent")
    return x[:, 0] if vector else x


#: Sweeps of :func:`eigh` before it gives up (cyclic Jacobi converges quadratically: about ten
#: sweeps reach round-off for a few hundred unknowns).
_JACOBI_SWEEPS = 60


@kernel
def _jacobi_kernel(a, v):
    """Cyclic Jacobi rotations on the symmetric a (n, n), accumulated in v; returns the sweeps
    used (−1 if not converged)."""
    n = a.shape[0]
    total = 0.0
    for i in range(n):
        for j in range(n):
            total += a[i, j] * a[i, j]
    eps = np.finfo(np.float64).eps
    for sweep in range(_JACOBI_SWEEPS):
        off = 0.0
        for p in range(n - 1):
            for q in range(p + 1, n):
                off += a[p, q] * a[p, q]
        if off <= (eps * eps) * total * 1e-4:
            return sweep
        for p in range(n - 1):
            for q in range(p + 1, n):
                apq = a[p, q]
                if apq == 0.0:
                    continue
                theta = (a[q, q] - a[p, p]) / (2.0 * apq)
                if abs(theta) > 1e150:
                    t = 0.5 / theta
                else:
                    t = math.copysign(1.0, theta) / (abs(theta) + math.sqrt(theta * theta + 1.0))
                c = 1.0 / math.sqrt(t * t + 1.0)
                s = t * c
                for r in range(n):  # columns p and q
                    arp, arq = a[r, p], a[r, q]
                    a[r, p] = c * arp - s * arq
                    a[r, q] = s * arp + c * arq
                for r in range(n):  # rows p and q
                    apr, aqr = a[p, r], a[q, r]
                    a[p, r] = c * apr - s * aqr
                    a[q, r] = s * apr + c * aqr
                a[p, q] = 0.0
                a[q, p] = 0.0
                for r in range(n):
                    vrp, vrq = v[r, p], v[r, q]
                    v[r, p] = c * vrp - s * vrq
                    v[r, q] = s * vrp + c * vrq
    return -1


def eigh(a: ArrayLike) -> tuple[np.ndarray, np.ndarray]:
    """Eigenvalues (ascending) and orthonormal eigenvectors (columns) of the symmetric matrix
    ``a`` (n, n), by cyclic Jacobi rotations.  Each eigenvector's sign makes its last nonzero
    entry positive (LAPACK leaves the sign free)."""
    am = np.array(a, dtype=np.float64, order="C")
    if am.ndim != 2 or am.shape[0] != am.shape[1]:
        raise ValueError(f"eigh needs a square matrix, got shape {am.shape}")
    if not np.array_equal(am, am.T):
        raise ValueError("eigh needs a symmetric matrix")
    v = np.eye(am.shape[0])
    if _jacobi_kernel(am, v) < 0:
        raise np.linalg.LinAlgError("eigh: Jacobi rotations did not converge")
    w = np.diag(am).copy()
    order = np.argsort(w, kind="stable")
    w, v = w[order], v[:, order]
    for j in range(v.shape[1]):
        nonzero = np.flatnonzero(v[:, j])
        if nonzero.size and v[nonzero[-1], j] < 0.0:
            v[:, j] = -v[:, j]
    return w, v


def pinv_symmetric(a: ArrayLike) -> np.ndarray:
    """Pseudo-inverse of the symmetric positive semi-definite matrix ``a`` (n, n): eigenvalues
    below n·eps times the largest are taken as zero (NumPy's default cut-off for ``pinv``)."""
    w, v = eigh(a)
    cut = w.size * np.finfo(np.float64).eps * max(abs(w[0]), abs(w[-1]))
    inv = np.where(np.abs(w) > cut, 1.0 / np.where(w == 0.0, 1.0, w), 0.0)
    return matmul(v * inv, v.T)


def matmul(a: ArrayLike, b: ArrayLike) -> np.ndarray:
    """a (m, n) · b (n, p), every sum over q in increasing order."""
    am = np.ascontiguousarray(a, dtype=np.float64)
    bm = np.ascontiguousarray(b, dtype=np.float64)
    if am.ndim != 2 or bm.ndim != 2 or am.shape[1] != bm.shape[0]:
        raise ValueError(f"matmul needs (m, n) and (n, p), got {am.shape} and {bm.shape}")
    out = np.empty((am.shape[0], bm.shape[1]))
    _matmul_kernel(am, bm, out)
    return out
