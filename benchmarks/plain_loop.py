"""The baseline of issue 6: a plain, straightforward compiled rocking loop.

What a user would write with Numba after reading the paper: one simulation at a time, Eq. (1)
with ``math.sin``/``math.cos`` of (s·α − θ) at every Runge–Kutta stage, fixed-step RK4 at the
motion's dt with the ground acceleration linear between samples, and simple impact handling: when
a step ends on the other side of θ = 0, the block is put at θ = 0 on the other pivot with
θ' ← e·θ' (no location of the impact inside the step).  It starts from rest, stays at rest while
|a_g| ≤ g·tan α, comes to rest again when an impact leaves it slower than a tiny threshold under
a ground acceleration below the uplift level, and stops at overturning (|θ| ≥ the overturning
angle).  It counts its own integrated steps.  Not part of the package: benchmarks only.
"""

from __future__ import annotations

import math

import numba
import numpy as np


@numba.njit(cache=True)
def _theta2(theta, s, u, p2, alpha):
    return -p2 * (math.sin(s * alpha - theta) + u * math.cos(s * alpha - theta))


@numba.njit(cache=True)
def simulate_plain(acc, scale, g, dt, p2, alpha, e, th_ov):
    """One simulation under u = scale·acc/g [-] (acc [m/s²] sampled at dt [s]); returns
    (overturned, max|θ| [rad], RK4 steps integrated)."""
    tan_a = math.tan(alpha)
    theta = 0.0
    omega = 0.0
    s = 1.0
    rocking = False
    peak = 0.0
    steps = 0
    for k in range(acc.shape[0] - 1):
        u0 = scale * acc[k] / g
        u1 = scale * acc[k + 1] / g
        if not rocking:
            if abs(u1) <= tan_a:
                continue
            rocking = True
            s = -1.0 if u1 > 0.0 else 1.0
        um = 0.5 * (u0 + u1)
        h = dt
        k1t = omega
        k1w = _theta2(theta, s, u0, p2, alpha)
        k2t = omega + 0.5 * h * k1w
        k2w = _theta2(theta + 0.5 * h * k1t, s, um, p2, alpha)
        k3t = omega + 0.5 * h * k2w
        k3w = _theta2(theta + 0.5 * h * k2t, s, um, p2, alpha)
        k4t = omega + h * k3w
        k4w = _theta2(theta + h * k3t, s, u1, p2, alpha)
        theta_new = theta + h / 6.0 * (k1t + 2.0 * k2t + 2.0 * k3t + k4t)
        omega = omega + h / 6.0 * (k1w + 2.0 * k2w + 2.0 * k3w + k4w)
        steps += 1
        if s * theta_new < 0.0:  # impact: switch pivot at θ = 0
            theta = 0.0
            s = -s
            omega = e * omega
            if abs(omega) < 1e-6 and abs(u1) <= tan_a:
                omega = 0.0
                rocking = False
        else:
            theta = theta_new
        if abs(theta) >= th_ov:
            return True, th_ov, steps
        peak = max(peak, abs(theta))
    return False, peak, steps


@numba.njit(cache=True)
def run_serial(acc, motion, scale, g, dt, p2, alpha, e, th_ov, overturned, peak, steps):
    """Case i (motion[i] scaled by scale[i], block constants [i]) one after the other."""
    for i in range(motion.shape[0]):
        overturned[i], peak[i], steps[i] = simulate_plain(
            acc[motion[i]], scale[i], g, dt, p2[i], alpha[i], e[i], th_ov[i]
        )


@numba.njit(cache=True, parallel=True)
def run_parallel(acc, motion, scale, g, dt, p2, alpha, e, th_ov, overturned, peak, steps):
    """The same with the cases spread over all cores (``prange``), one simulation per thread
    at a time."""
    for i in numba.prange(motion.shape[0]):
        overturned[i], peak[i], steps[i] = simulate_plain(
            acc[motion[i]], scale[i], g, dt, p2[i], alpha[i], e[i], th_ov[i]
        )


def run(kind: str, acc: np.ndarray, motion, scale, g, dt, p2, alpha, e, th_ov):
    """Run the cases with ``kind`` "serial" or "parallel"; per-case arrays; returns
    (overturned, peak, steps)."""
    n = motion.size
    overturned = np.empty(n, np.bool_)
    peak = np.empty(n)
    steps = np.empty(n, np.int64)
    func = run_serial if kind == "serial" else run_parallel
    func(acc, motion, scale, g, dt, p2, alpha, e, th_ov, overturned, peak, steps)
    return overturned, peak, steps
