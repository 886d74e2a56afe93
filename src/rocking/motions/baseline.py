"""Quadratic baseline correction of accelerations (paper Section 4): :func:`baseline_correct`."""

from __future__ import annotations

import numpy as np
from numpy.typing import ArrayLike

from ..core import portable
from ..core.checks import finite_array, positive
from ..errors import InputError

#: Motions corrected together, one block at a time: a block's temporaries stay in the cache
#: (the result does not depend on it).
BLOCK_ROWS = 8


# The trapezoidal rules below are SciPy's (scipy.integrate.trapezoid and cumulative_trapezoid with
# a scalar step: dx·(y[1:] + y[:-1])/2 summed, the same operations in the same order, hence the
# same bits; tests/test_motions.py checks it), written out because importing scipy.integrate
# costs every ``rocking motions generate`` a quarter of a second for two one-line formulas.


def _trapezoid(y: np.ndarray, dx: float) -> np.ndarray:
    """∫ y dt over the last axis by the trapezoidal rule with step ``dx``."""
    return np.sum(dx * (y[..., 1:] + y[..., :-1]) / 2.0, axis=-1)


def _cumulative_trapezoid(y: np.ndarray, dx: float) -> np.ndarray:
    """∫_0^t y dt at every sample along the last axis (0 at the first one)."""
    out = np.zeros(y.shape)
    np.cumsum(dx * (y[..., 1:] + y[..., :-1]) / 2.0, axis=-1, out=out[..., 1:])
    return out


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
    gram = _trapezoid(basis_vel[:, None, :] * basis_vel[None, :, :], dt)
    rows = a.reshape(-1, a.shape[-1])
    out = np.empty_like(rows)

    for start in range(0, rows.shape[0], BLOCK_ROWS):
        block = rows[start : start + BLOCK_ROWS]
        vel = _cumulative_trapezoid(block, dt)
        # Normal equations ∫ψ_k ψ_j dt · c_j = ∫ψ_k v dt (reference.md §6, ψ_k = basis
        # velocities). Motion by motion, not as one matrix product, so each motion's result
        # does not depend on how many motions are corrected together (BLAS may sum in a
        # size-dependent order), and solved in a fixed order (LAPACK's depends on the CPU).
        rhs = np.stack([_trapezoid(vel * psi, dt) for psi in basis_vel], axis=-1)
        coef = portable.lstsq(gram, rhs.T).T
        baseline = sum(coef[:, j, None] * basis_acc[j] for j in range(k_max + 1))
        out[start : start + BLOCK_ROWS] = block - baseline
    return out.reshape(a.shape)
