"""Independent reference solver for the rocking equation: SciPy ``solve_ivp`` with located events.

It shares nothing with :mod:`rocking.dynamics.equation` and :mod:`rocking.dynamics.impacts` but the
physics (Eq. 1 and the impact rule), so the
tests can check the fast fixed-step solver against it.  Adaptive DOP853 with tight tolerances, run
one sample interval of the ground motion at a time: the ground acceleration is linear between
samples and has a kink at each, so within an interval the equation is smooth and the integrator
keeps its full order (steps across a kink would be rejected again and again).  Terminal events for
the impact (θ = 0) and for overturning (abs(θ) = overturn angle); uplift from rest located
exactly on the linearly interpolated ground acceleration.  It is slow (about 0.1 s per 4 s of
motion at 1/100 s) and meant for verification, not for production runs.

Eq. (1) is written here from its physical form, I_O·θ'' = −M·R·[(g + a_v)·sin(sα − θ) +
a_g·cos(sα − θ)] with I_O = M·(r_g² + R²) (:meth:`rocking.Block.radius_of_gyration`), libm
trigonometry and no other shortcut; uplift from rest when abs(a_g) > (g + a_v)·tan α.
"""

from __future__ import annotations

import math

import numpy as np
from numpy.typing import ArrayLike
from scipy.integrate import solve_ivp

from ..core.checks import finite_array, positive
from ..defaults import DEFAULT_E
from ..errors import InputError
from .body import Block, G, resolve_e, resolve_overturn_angle
from .simulate import RockingResponse

#: A bounce whose free flight would last less than this [s] ends the impact sequence (rest).
REST_FLIGHT_TIME = 1e-7


def simulate_reference(
    block: Block,
    ag: ArrayLike,
    dt: float,
    *,
    e: float | str = DEFAULT_E,
    overturn_angle: float | str = math.pi / 2,
    g: float = G,
    av: ArrayLike | None = None,
    rtol: float = 1e-10,
    atol: float = 1e-12,
    max_step: float | None = None,
) -> RockingResponse:
    """Rocking response by ``solve_ivp`` (DOP853) with event location; starts from rest.

    Parameters as :func:`rocking.simulate`: ``ag`` [m/s²] sampled at ``dt`` [s], linear between
    samples; ``e`` [-]; ``overturn_angle`` [rad]; ``g`` [m/s²]; ``av`` [m/s², up positive] the
    vertical ground acceleration at the same samples, above −g (None: zero); ``rtol``/``atol``
    are the integrator's tolerances; ``max_step`` [s] caps its step (default: none, a step never
    crosses a sample of the ground motion anyway).  Events are found from the values at the
    ends of the integrator's steps, so a bounce much shorter than a step can go unseen (a
    minimum of θ inside a step is looked for, but a chatter of tiny bounces may still be
    missed); ``max_step = dt/2`` guards against it at twice the cost.
    """
    dt = positive("dt", dt, "s")
    g = positive("g", g, "m/s²")
    a_g = finite_array("ag", ag)
    n = a_g.size
    a_v = np.zeros(n) if av is None else finite_array("av", av)
    if a_v.size != n or a_v.min() <= -g:
        raise InputError("av must have the samples of ag, all above -g")
    e_val = resolve_e(e, block)
    th_ov = resolve_overturn_angle(overturn_angle, block)
    alpha = block.alpha
    tan_a = math.tan(alpha)
    # M·R/I_O [1/m]
    k_mr = block.R / (block.radius_of_gyration**2 + block.R**2)
    times = np.arange(n) * dt
    cap = math.inf if max_step is None else positive("max_step", max_step, "s")

    def at(x, j, t):
        """x (a_g or a_v) at time t of interval j (from sample j to sample j + 1) [m/s²]."""
        return x[j] + (x[j + 1] - x[j]) * ((t - times[j]) / dt)

    def excess(j, t):
        """abs(a_g) − (g + a_v)·tan α at time t of interval j: > 0 lifts a block at rest."""
        return abs(at(a_g, j, t)) - (g + at(a_v, j, t)) * tan_a

    def equation(side, j):
        """Right-hand side of Eq. (1) as a first-order system, (θ, θ') → (θ', θ''), on pivot
        side ``side`` in interval j (a_g and a_v linear in it)."""
        tj, gj, aj = times[j], g + a_v[j], a_g[j]
        dgj, daj = (a_v[j + 1] - a_v[j]) / dt, (a_g[j + 1] - a_g[j]) / dt

        def rhs(t, yy):
            c = side * alpha - yy[0]
            tt = t - tj
            return [yy[1], -k_mr * ((gj + dgj * tt) * math.sin(c) + (aj + daj * tt) * math.cos(c))]

        return rhs

    theta_out = np.zeros(n)
    omega_out = np.zeros(n)
    j, t_cur = 0, 0.0  # the state is known at t_cur, in the interval from sample j to j + 1
    rest = True
    s = 1.0
    y = np.zeros(2)
    t_seg = 0.0
    n_imp = 0
    overturned = False
    t_ov = math.nan

    while j < n - 1:
        if rest:
            # first time from t_cur on at which abs(a_g) exceeds (g + a_v)·tan α (both linear
            # between samples: on the side of a_g at the first sample beyond, a_g ∓ (g + a_v)·tan α
            # is linear in the interval before it and changes sign there)
            if excess(j, t_cur) <= 0.0:
                over = np.abs(a_g[j + 1 :]) - (g + a_v[j + 1 :]) * tan_a
                idx = np.nonzero(over > 0.0)[0]
                if idx.size == 0:
                    break
                k = j + 1 + idx[0]
                sgn = math.copysign(1.0, a_g[k])
                f0 = sgn * a_g[k - 1] - (g + a_v[k - 1]) * tan_a
                f1 = sgn * a_g[k] - (g + a_v[k]) * tan_a
                t_start = (k - 1) * dt + f0 / (f0 - f1) * dt
                if t_start > t_cur:
                    j, t_cur = k - 1, t_start  # the block stays at rest (θ = 0) until then
            s = -1.0 if at(a_g, j, t_cur) > 0.0 else 1.0
            y = np.zeros(2)
            t_seg = t_cur
            rest = False
        t_next = times[j + 1]
        if t_cur >= t_next:  # an event exactly at the sample: on to the next interval
            theta_out[j + 1], omega_out[j + 1] = y
            j += 1
            continue
        side = s
        rhs = equation(side, j)

        def hit_zero(t, yy):
            # At the flight's start θ = 0 exactly (impact or uplift); report the side's sign there
            # so that only the return to θ = 0 counts as a crossing, never the start itself.
            return yy[0] if t > t_seg else side

        hit_zero.terminal = True  # type: ignore[attr-defined]
        hit_zero.direction = -side  # type: ignore[attr-defined]

        def hit_overturn(t, yy):
            return abs(yy[0]) - th_ov

        hit_overturn.terminal = True  # type: ignore[attr-defined]
        hit_overturn.direction = 1.0  # type: ignore[attr-defined]

        def turn_back(t, yy):
            # Minima of side·θ. Events are seen only as sign changes between the ends of a step,
            # so a short flight inside one step (θ through 0 and back) would go unnoticed; its
            # minimum, where side·θ < 0 and side·θ' changes sign, is seen.
            return side * yy[1]

        turn_back.direction = 1.0  # type: ignore[attr-defined]

        def solve(t_stop):
            return solve_ivp(
                rhs,
                (t_cur, t_stop),
                y,
                method="DOP853",
                rtol=rtol,
                atol=atol,
                first_step=min(t_stop - t_cur, cap),
                max_step=cap,
                events=(hit_zero, hit_overturn, turn_back),
            )

        sol = solve(t_next)
        missed = [t for t, yy in zip(sol.t_events[2], sol.y_events[2]) if side * yy[0] < 0.0]
        if missed:
            # the first return to θ = 0 lies before this minimum: integrate up to it again
            sol = solve(missed[0])
            if not (sol.status == 1 and sol.t_events[0].size):
                raise RuntimeError(
                    f"no return to theta = 0 found before the minimum of side "
                    f"theta < 0 at t = {missed[0]:g} s"
                )
        if sol.status == 1 and sol.t_events[1].size:
            overturned = True
            t_ov = float(sol.t_events[1][0])
            break
        if sol.status == 1 and sol.t_events[0].size:
            t_cur = float(sol.t_events[0][0])
            w = e_val * float(sol.y_events[0][0][1])
            n_imp += 1
            s = -s
            t_seg = t_cur
            acc0 = equation(s, j)(t_cur, (0.0, 0.0))[1]
            if w == 0.0 or (acc0 * w < 0.0 and 2.0 * abs(w) / abs(acc0) < REST_FLIGHT_TIME):
                rest = True  # samples while at rest keep θ = θ' = 0
            y = np.array([0.0, w])
            continue
        if sol.status != 0:
            raise RuntimeError(f"solve_ivp failed at t = {t_cur:g} s: {sol.message}")
        y = sol.y[:, -1]
        theta_out[j + 1], omega_out[j + 1] = y
        j, t_cur = j + 1, t_next
    if overturned:
        after = times > t_ov
        theta_out[after] = np.nan
        omega_out[after] = np.nan
        peak = th_ov
    else:
        peak = float(np.max(np.abs(theta_out)))
    return RockingResponse(
        t=times,
        theta=theta_out,
        omega=omega_out,
        overturned=overturned,
        t_overturn=t_ov,
        n_impacts=n_imp,
        max_abs_theta=peak,
        block=block,
        e=e_val,
        overturn_angle=th_ov,
    )
