"""Independent reference solver for the rocking equation: SciPy ``solve_ivp`` with located events.

It shares nothing with :mod:`rocking.dynamics` but the physics (Eq. 1 and the impact rule), so the
tests can check the fast fixed-step solver against it.  Adaptive DOP853 with tight tolerances,
steps no longer than the motion's sample interval (the ground acceleration has a kink at every
sample), terminal events for the impact (θ = 0) and for overturning (|θ| = overturn angle), and
uplift from rest located exactly on the linearly interpolated ground acceleration.  It is slow
(about a second per 10 s of motion) and meant for verification, not for production runs.
"""

from __future__ import annotations

import math

import numpy as np
from scipy.integrate import solve_ivp

from .body import G, Block
from .body import resolve_e, resolve_overturn_angle
from .dynamics import RockingResponse
from ._validate import finite_array, positive

#: A bounce whose free flight would last less than this [s] ends the impact sequence (rest).
REST_FLIGHT_TIME = 1e-7


def simulate_reference(block: Block, ag, dt: float, *, e=0.925, overturn_angle=math.pi / 2,
                       g: float = G, rtol: float = 1e-10, atol: float = 1e-12,
                       max_step: float | None = None) -> RockingResponse:
    """Rocking response by ``solve_ivp`` (DOP853) with event location; starts from rest.

    Parameters as :func:`rocking.simulate`: ``ag`` [m/s²] sampled at ``dt`` [s], linear between
    samples; ``e`` [-]; ``overturn_angle`` [rad]; ``g`` [m/s²]; ``rtol``/``atol`` are the
    integrator's tolerances;
    ``max_step`` [s] caps its step (default: ``dt``, one kink of the ground motion per step).
    """
    dt = positive("dt", dt, "s")
    u = finite_array("ag", ag) / positive("g", g, "m/s²")
    e_val = resolve_e(e, block)
    th_ov = resolve_overturn_angle(overturn_angle, block)
    alpha = block.alpha
    sa, ca, tan_a = math.sin(alpha), math.cos(alpha), math.tan(alpha)
    p2 = 3.0 * g / (4.0 * block.R)
    n = u.size
    t_end = (n - 1) * dt
    times = np.arange(n) * dt

    def u_at(t):
        k = min(max(int(t / dt), 0), n - 2)
        x = t / dt - k
        return u[k] + (u[k + 1] - u[k]) * x

    theta_out = np.zeros(n)
    omega_out = np.zeros(n)
    t_cur = 0.0
    rest = True
    s = 1.0
    y = np.zeros(2)
    n_imp = 0
    overturned = False
    t_ov = math.nan

    while t_cur < t_end and not overturned:
        if rest:
            # first time after t_cur at which |u| exceeds tan α (u linear between samples)
            k0 = int(t_cur / dt)
            if abs(u_at(t_cur)) > tan_a:
                t_start = t_cur
            else:
                idx = np.nonzero(np.abs(u[k0 + 1:]) > tan_a)[0]
                if idx.size == 0:
                    break
                k = k0 + 1 + idx[0]
                thr = math.copysign(tan_a, u[k])
                t_start = max(t_cur, (k - 1) * dt + (thr - u[k - 1]) / (u[k] - u[k - 1]) * dt)
            # the block stays at rest (θ = 0) until t_start
            t_cur = t_start
            s = -1.0 if u_at(t_cur) > 0.0 else 1.0
            y = np.zeros(2)
            rest = False
            continue

        side = s

        def rhs(t, yy):
            th = yy[0]
            uu = u_at(t)
            return [yy[1], -p2 * (math.sin(side * alpha - th) + uu * math.cos(side * alpha - th))]

        t_seg = t_cur

        def hit_zero(t, yy):
            # At the segment's start θ = 0 exactly (impact or uplift); report the side's sign there
            # so that only the return to θ = 0 counts as a crossing, never the start itself.
            return yy[0] if t > t_seg else side

        hit_zero.terminal = True
        hit_zero.direction = -side

        def hit_overturn(t, yy):
            return abs(yy[0]) - th_ov

        hit_overturn.terminal = True
        hit_overturn.direction = 1.0

        t_eval = times[(times > t_cur) & (times <= t_end)]
        sol = solve_ivp(rhs, (t_cur, t_end), y, method="DOP853", rtol=rtol, atol=atol,
                        max_step=dt if max_step is None else max_step, events=(hit_zero, hit_overturn), t_eval=t_eval)
        t_sol = np.asarray(sol.t)
        if t_sol.size:
            k_written = np.searchsorted(times, t_sol)
            theta_out[k_written] = sol.y[0]
            omega_out[k_written] = sol.y[1]
        if sol.status == 1 and sol.t_events[1].size:
            overturned = True
            t_ov = float(sol.t_events[1][0])
            break
        if sol.status == 1 and sol.t_events[0].size:
            t_cur = float(sol.t_events[0][0])
            w = e_val * float(sol.y_events[0][0][1])
            n_imp += 1
            s = -s
            acc0 = -p2 * (s * sa + u_at(t_cur) * ca)
            if w == 0.0 or (acc0 * w < 0.0 and 2.0 * abs(w) / abs(acc0) < REST_FLIGHT_TIME):
                rest = True  # samples while at rest keep θ = θ' = 0
            y = np.array([0.0, w])
            continue
        break
    if overturned:
        after = times > t_ov
        theta_out[after] = np.nan
        omega_out[after] = np.nan
        peak = th_ov
    else:
        peak = float(np.max(np.abs(theta_out)))
    return RockingResponse(t=times, theta=theta_out, omega=omega_out, overturned=overturned,
                           t_overturn=t_ov, n_impacts=n_imp, max_abs_theta=peak, block=block,
                           e=e_val, overturn_angle=th_ov)
