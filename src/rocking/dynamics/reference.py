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
from dataclasses import dataclass

import numpy as np
from numpy.typing import ArrayLike
from scipy.integrate import solve_ivp

from ..core.checks import finite_array, positive
from ..defaults import DEFAULT_E, OVERTURN_ANGLE
from ..errors import InputError
from .body import Block, G, resolve_e, resolve_overturn_angle
from .simulate import RockingResponse

#: A bounce whose free flight would last less than this [s] ends the impact sequence (rest).
REST_FLIGHT_TIME = 1e-7


@dataclass(frozen=True, eq=False)
class _Ground:
    """The ground motion of a reference run: a_g and a_v [m/s²] linear between the samples at
    ``times`` [s] (step ``dt``), and gravity ``g`` [m/s²]."""

    a_g: np.ndarray
    a_v: np.ndarray
    dt: float
    g: float
    times: np.ndarray

    def at(self, x: np.ndarray, j: int, t: float) -> float:
        """x (a_g or a_v) at time t of interval j (from sample j to sample j + 1) [m/s²]."""
        return x[j] + (x[j + 1] - x[j]) * ((t - self.times[j]) / self.dt)

    def uplift(self, j: int, t: float, tan_a: float) -> tuple[int, float] | None:
        """(interval, time) at which a block at rest from time t of interval j starts to rock:
        the first time at which abs(a_g) exceeds (g + a_v)·tan α, or None if it never does."""
        if abs(self.at(self.a_g, j, t)) - (self.g + self.at(self.a_v, j, t)) * tan_a > 0.0:
            return j, t
        # both linear between samples: on the side of a_g at the first sample beyond,
        # a_g ∓ (g + a_v)·tan α is linear in the interval before it and changes sign there
        over = np.abs(self.a_g[j + 1 :]) - (self.g + self.a_v[j + 1 :]) * tan_a
        idx = np.nonzero(over > 0.0)[0]
        if idx.size == 0:
            return None
        k = j + 1 + idx[0]
        sgn = math.copysign(1.0, self.a_g[k])
        f0 = sgn * self.a_g[k - 1] - (self.g + self.a_v[k - 1]) * tan_a
        f1 = sgn * self.a_g[k] - (self.g + self.a_v[k]) * tan_a
        t_start = (k - 1) * self.dt + f0 / (f0 - f1) * self.dt
        return (k - 1, t_start) if t_start > t else (j, t)

    def equation(self, side: float, j: int, alpha: float, k_mr: float):
        """Right-hand side of Eq. (1) as a first-order system, (θ, θ') → (θ', θ''), on pivot
        side ``side`` in interval j (a_g and a_v linear in it), for a body of critical angle
        ``alpha`` [rad] and M·R/I_O = ``k_mr`` [1/m]."""
        tj, gj, aj = self.times[j], self.g + self.a_v[j], self.a_g[j]
        dgj = (self.a_v[j + 1] - self.a_v[j]) / self.dt
        daj = (self.a_g[j + 1] - self.a_g[j]) / self.dt

        def rhs(t, yy):
            c = side * alpha - yy[0]
            tt = t - tj
            return [yy[1], -k_mr * ((gj + dgj * tt) * math.sin(c) + (aj + daj * tt) * math.cos(c))]

        return rhs


def _flight(rhs, t_cur: float, t_next: float, y, side: float, t_seg: float, th_ov: float, tol):
    """``solve_ivp`` of a swing on pivot side ``side`` from (t_cur, y) to t_next, stopping at
    the first return to θ = 0 after ``t_seg`` (the flight's start) or at overturning (abs(θ) =
    ``th_ov``); ``tol`` = (rtol, atol, max_step)."""
    rtol, atol, cap = tol

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
    return sol


def simulate_reference(
    block: Block,
    ag: ArrayLike,
    dt: float,
    *,
    e: float | str = DEFAULT_E,
    overturn_angle: float | str = OVERTURN_ANGLE,
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
    k_mr = block.R / (block.radius_of_gyration**2 + block.R**2)  # M·R/I_O [1/m]
    ground = _Ground(a_g, a_v, dt, g, np.arange(n) * dt)
    tol = (rtol, atol, math.inf if max_step is None else positive("max_step", max_step, "s"))

    theta_out = np.zeros(n)
    omega_out = np.zeros(n)
    j, t_cur = 0, 0.0  # the state is known at t_cur, in the interval from sample j to j + 1
    rest = True
    s = 1.0
    y = np.zeros(2)
    t_seg = 0.0
    n_imp = 0
    t_ov = math.nan
    while j < n - 1:
        if rest:
            start = ground.uplift(j, t_cur, tan_a)
            if start is None:
                break  # at rest to the end (θ = θ' = 0 at the samples)
            j, t_cur = start
            s = -1.0 if ground.at(a_g, j, t_cur) > 0.0 else 1.0
            y = np.zeros(2)
            t_seg = t_cur
            rest = False
        t_next = ground.times[j + 1]
        if t_cur >= t_next:  # an event exactly at the sample: on to the next interval
            theta_out[j + 1], omega_out[j + 1] = y
            j += 1
            continue
        sol = _flight(ground.equation(s, j, alpha, k_mr), t_cur, t_next, y, s, t_seg, th_ov, tol)
        if sol.status == 1 and sol.t_events[1].size:
            t_ov = float(sol.t_events[1][0])
            break
        if sol.status == 1 and sol.t_events[0].size:  # impact: Housner's rule, the other pivot
            t_cur = float(sol.t_events[0][0])
            w = e_val * float(sol.y_events[0][0][1])
            n_imp += 1
            s = -s
            t_seg = t_cur
            acc0 = ground.equation(s, j, alpha, k_mr)(t_cur, (0.0, 0.0))[1]
            if w == 0.0 or (acc0 * w < 0.0 and 2.0 * abs(w) / abs(acc0) < REST_FLIGHT_TIME):
                rest = True  # samples while at rest keep θ = θ' = 0
            y = np.array([0.0, w])
            continue
        if sol.status != 0:
            raise RuntimeError(f"solve_ivp failed at t = {t_cur:g} s: {sol.message}")
        y = sol.y[:, -1]
        theta_out[j + 1], omega_out[j + 1] = y
        j, t_cur = j + 1, t_next
    overturned = not math.isnan(t_ov)
    if overturned:
        after = ground.times > t_ov
        theta_out[after] = np.nan
        omega_out[after] = np.nan
    return RockingResponse(
        t=ground.times,
        theta=theta_out,
        omega=omega_out,
        overturned=overturned,
        t_overturn=t_ov,
        n_impacts=n_imp,
        max_abs_theta=th_ov if overturned else float(np.max(np.abs(theta_out))),
        block=block,
        e=e_val,
        overturn_angle=th_ov,
    )
