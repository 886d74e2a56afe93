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

**With friction** (``mu`` given; issue 45, the shared model of the response modes) the same
one-interval-at-a-time DOP853 integrates every mode: rest, slide, rock, slide-rock and flight.
It is formulated apart from the closed forms of the contact forces, as a cross-check of them:
the state is the centre of mass's position (x, y) relative to the ground, the rotation θ and
their rates, and in each mode Newton–Euler in the ground's frame (inertial force −m·a_g, gravity
g + a_v) with the mode's contact constraints (the contact corner's vertical acceleration 0, and
its horizontal one too while it sticks; Coulomb F = −σ·μ_k·N while it slips) is solved as one
small linear system for the accelerations and contact forces (``numpy.linalg.solve``).  After
each step the state is put back on the constraints.  Transitions are terminal events located
inside the interval: slip velocity 0 (stick, then the static cone decides; also where it
reaches 0 and turns back inside one step, found at the minimum of σ·slip velocity that
:func:`_segment` watches), abs(F) − μ_s·N = 0
(slip onset), N = 0 (lift-off), θ = 0 (impact), a corner's height 0 (landing), abs(θ) = the
overturning angle; the end of rest is found exactly on the linearly interpolated ground motion
(slip when abs(a_g) > μ_s·(g + a_v), tipping when abs(a_g) > (g + a_v)·tan α, flight when
g + a_v < 0; with both, tipping where μ_s ≥ tan α: Shenton 1996).  A tipping start or a stuck
corner whose friction demand leaves the cone slide-rocks instead, the corner slipping against
the friction it demands.

Impacts follow an impulse–momentum law of the kind of Shenton & Jones (1991, "Base excitation of
rigid bodies. I: Formulation", J. Eng. Mech. 117(10)), as fixed for this package in MODES.md:
rigid bodies, an instantaneous impulse P at the striking corner only (the other corner, and the
ground, exert none), no change of position during it.  (1) Stick: the corner comes to rest;
ω_L conserves the angular momentum about it (Housner's plastic law, e_H·ω⁻ after pure rocking),
ω⁺ = (e/e_H)·ω_L with at most e² of the kinetic energy (e·ω⁻ after pure rocking, today's rule,
for every body; where e_H ≤ 0, a squat body, no factor maps ω_L onto it, and after slip or flight
ω⁺ = ω_L, plastic: the only stick by an impulse at the corner alone);
accepted where P_y ≥ 0 and abs(P_x) ≤ μ_s·P_y.  (2) Otherwise a sliding impact: P_x = −σ·μ_k·P_y
with σ the sign of the corner's slip velocity before (taken not to reverse during the impact; a
corner at rest before, as after rock, slips against the friction that sticking would need, the
side a frictionless impulse drives it to: Routh) and P_y
plastic (the corner's vertical velocity 0 after); where that P_y would be negative (a
Painlevé jam) or the slip would reverse (it stops during the impact, and a reversed slip under
the same impulse would gain energy), the corner sticks, plastic: ω⁺ = ω_L, outside the cone.
(3) Both corners at once (a flat landing, or an impact after which the body would turn into the
ground): y' and θ' → 0 (plastic), tangential stick where abs(x') ≤ μ_s·P_y/m, else a Coulomb
impulse.  Kinetic energy (ground's frame) never increases with e ≤ 1.

Painlevé's paradox: where a unit normal impulse at a slipping corner, with its Coulomb partner,
would move that corner down (:meth:`_Rigid.normal_response` ≤ 0: an outward slip with large
μ_k·h), the slip has no solution, neither as a motion nor as an impact.  As in the literature
(Génot & Brogliato 1999, "New results on Painlevé paradoxes", Eur. J. Mech. A/Solids 18:653–677:
an "impact without collision"), the slip then stops at once: the same plastic impulse as a jam
above (ω_L; its friction ratio is inside the cone), after which the stuck corner's contact forces
decide.  It is a terminal event ("jam") of slide-rock and is applied where a slide tips onto
such a corner.  A stuck corner whose friction demand would need such a slip lifts off instead:
that happens only with its free vertical acceleration upward, where N = 0 solves the contact
problem (derived in :mod:`rocking.dynamics.modes`).  A bounce shorter than
:data:`REST_FLIGHT_TIME` ends in contact on both corners (rest, or slide at the centre of mass's
horizontal velocity: the tiny rotation stops without a horizontal impulse, and the kinetic energy
does not grow, as it would with the corner's slip velocity kept wherever that and θ' have
opposite signs).

Slow-but-exact: rtol 1e-10, atol 1e-12 by default; about 0.2 s per 4 s of rocking at 1/100 s,
0.4 s for 1.25 s of sliding at 1/1000 s, 0.1–2 s for 5 s of random motion through every mode at
1/100 s (one core of a shared 2-core machine); for the tests only.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np
from numpy.typing import ArrayLike
from scipy.integrate import solve_ivp

from ..core.checks import finite_array, in_range, positive
from ..defaults import DEFAULT_E, MODES, OVERTURN_ANGLE
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

    def pair(self, j: int, t: float) -> tuple[float, float]:
        """(a_g, g + a_v) at time t of interval j [m/s²]."""
        return self.at(self.a_g, j, t), self.g + self.at(self.a_v, j, t)

    def first_exceed(
        self, j: int, t: float, rows: tuple[tuple[float, float], ...]
    ) -> tuple[int, float, tuple[int, ...]] | None:
        """(interval, time, rows) of the first time from time t of interval j at which one of
        the linear functions c·a_g − k·(g + a_v) of ``rows`` = ((c, k), ...) exceeds 0, with
        the indices of the rows that exceed it first; None if none ever does."""
        now = [
            c * self.at(self.a_g, j, t) - (self.g + self.at(self.a_v, j, t)) * k for c, k in rows
        ]
        if max(now) > 0.0:
            return j, t, tuple(i for i, f in enumerate(now) if f > 0.0)
        # all linear between samples: each row that exceeds 0 at the first sample beyond is
        # linear in the interval before it and changes sign there
        over = [c * self.a_g[j + 1 :] - (self.g + self.a_v[j + 1 :]) * k for c, k in rows]
        idx = np.nonzero(np.any(np.array(over) > 0.0, axis=0))[0]
        if idx.size == 0:
            return None
        k1 = j + 1 + idx[0]
        cross = {}
        for i, (c, k) in enumerate(rows):
            f1 = c * self.a_g[k1] - (self.g + self.a_v[k1]) * k
            if f1 > 0.0:
                f0 = c * self.a_g[k1 - 1] - (self.g + self.a_v[k1 - 1]) * k
                cross[i] = (k1 - 1) * self.dt + f0 / (f0 - f1) * self.dt
        t_start = min(cross.values())
        first = tuple(i for i, tc in cross.items() if tc == t_start)
        return (k1 - 1, t_start, first) if t_start > t else (j, t, first)

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


def _segment(rhs, t_cur: float, t_next: float, y, events, watches, tol):
    """``solve_ivp`` (DOP853) of ``rhs`` from (t_cur, y) to t_next with the terminal
    ``events``; ``tol`` = (rtol, atol, max_step).

    Events are seen only as sign changes between the ends of a step, so an event function
    that crosses 0 and returns inside one step (a short flight) would go unnoticed.  Each of
    ``watches`` = ((fn, split), ...) is a non-terminal event at the extremum of such a
    function (or of its rate); where ``split(y)`` at it is true, the segment is integrated
    again in two parts, up to it and on from it, each watched alike (a crossing missed before
    an extremum is found in the first part; a function whose rate changes sign twice inside
    one step, once on each side).  Returns the solution of the last part integrated (up to a
    terminal event, or to t_next).
    """
    rtol, atol, cap = tol
    sol = solve_ivp(
        rhs,
        (t_cur, t_next),
        y,
        method="DOP853",
        rtol=rtol,
        atol=atol,
        first_step=min(t_next - t_cur, cap),
        max_step=cap,
        events=(*events, *(fn for fn, _ in watches)),
    )
    n_ev = len(events)
    margin = 1e-9 * (t_next - t_cur)  # an extremum at an end is that end's
    splits = [
        t
        for w, (_, split) in enumerate(watches)
        for t, yy in zip(sol.t_events[n_ev + w], sol.y_events[n_ev + w])
        if t_cur + margin < t < sol.t[-1] - margin and split(yy)
    ]
    if not splits:
        return sol
    t_split = min(splits)
    first = _segment(rhs, t_cur, t_split, y, events, watches, tol)
    if first.status != 0:
        return first
    return _segment(rhs, t_split, t_next, first.y[:, -1], events, watches, tol)


def _terminal(fn, direction: float):
    """Mark ``fn`` as a terminal event of ``solve_ivp`` crossing 0 in ``direction``."""
    fn.terminal = True
    fn.direction = direction
    return fn


def _flight(rhs, t_cur: float, t_next: float, y, side: float, t_seg: float, th_ov: float, tol):
    """``solve_ivp`` of a swing on pivot side ``side`` from (t_cur, y) to t_next, stopping at
    the first return to θ = 0 after ``t_seg`` (the flight's start) or at overturning (abs(θ) =
    ``th_ov``); ``tol`` = (rtol, atol, max_step)."""

    def hit_zero(t, yy):
        # At the flight's start θ = 0 exactly (impact or uplift); report the side's sign there
        # so that only the return to θ = 0 counts as a crossing, never the start itself.
        return yy[0] if t > t_seg else side

    def turn_back(t, yy):
        # minima of side·θ: where side·θ < 0 there, a return to θ = 0 was missed
        return side * yy[1]

    def bend(t, yy):
        # extrema of θ': where θ' changes sign twice inside one step (a bounce of a chatter that
        # starts and ends inside it), turn_back sees no sign change; split there
        return rhs(t, yy)[1]

    turn_back.direction = 1.0  # type: ignore[attr-defined]
    return _segment(
        rhs,
        t_cur,
        t_next,
        y,
        (_terminal(hit_zero, -side), _terminal(lambda t, yy: abs(yy[0]) - th_ov, 1.0)),
        ((turn_back, lambda yy: side * yy[0] < 0.0), (bend, lambda yy: True)),
        tol,
    )


@dataclass(frozen=True)
class Tolerances:
    """The integrator's tolerances of :func:`simulate_reference`: ``rtol`` [-] and ``atol``
    [the state's units] of ``solve_ivp``, and ``max_step`` [s], a cap on its step (None: none;
    a step never crosses a sample of the ground motion anyway)."""

    rtol: float = 1e-10
    atol: float = 1e-12
    max_step: float | None = None


def simulate_reference(
    block: Block,
    ag: ArrayLike,
    dt: float,
    *,
    e: float | str = DEFAULT_E,
    overturn_angle: float | str = OVERTURN_ANGLE,
    g: float = G,
    av: ArrayLike | None = None,
    mu: float | None = None,
    mu_k: float | None = None,
    tolerances: Tolerances | None = None,
) -> RockingResponse | ReferenceResponse:
    """Rocking response by ``solve_ivp`` (DOP853) with event location; starts from rest.

    Parameters as :func:`rocking.simulate`: ``ag`` [m/s²] sampled at ``dt`` [s], linear between
    samples; ``e`` [-]; ``overturn_angle`` [rad]; ``g`` [m/s²]; ``av`` [m/s², up positive] the
    vertical ground acceleration at the same samples, above −g (None: zero);
    ``tolerances`` those of the integrator (:class:`Tolerances`, default ``Tolerances()``).
    Events are found from the values at the ends of the integrator's steps, so a bounce much
    shorter than a step could go unseen.  Hence the extrema inside a step are looked for: of θ
    and, without friction, of θ' (a bounce of a chatter that starts and ends inside one step
    turns θ' twice), of a corner's height in flight and of the slip velocity in slide and
    slide-rock, and the step is split there.  What can still be missed is a pair of extrema of θ'
    inside one step (θ'' changing sign twice there) and, with friction, a bounce in rock or
    slide-rock that starts and ends inside one step; ``Tolerances(max_step=...)`` guards
    against those at more cost.
    """
    dt = positive("dt", dt, "s")
    g = positive("g", g, "m/s²")
    a_g = finite_array("ag", ag)
    n = a_g.size
    a_v = np.zeros(n) if av is None else finite_array("av", av)
    if a_v.size != n:
        raise InputError("av must have the samples of ag")
    if mu is None and a_v.min() <= -g:
        raise InputError("av must lie above -g without friction (mu=None); give mu for flight")
    if mu is None and mu_k is not None:
        raise InputError("mu_k needs mu (the static friction coefficient)")
    e_val = resolve_e(e, block)
    th_ov = resolve_overturn_angle(overturn_angle, block)
    alpha = block.alpha
    tan_a = math.tan(alpha)
    ground = _Ground(a_g, a_v, dt, g, np.arange(n) * dt)
    tolerances = Tolerances() if tolerances is None else tolerances
    max_step = tolerances.max_step
    tol = (
        positive("rtol", tolerances.rtol, "-"),
        positive("atol", tolerances.atol, "-"),
        math.inf if max_step is None else positive("max_step", max_step, "s"),
    )
    if mu is not None:
        mu = in_range("mu", mu, 0.0, math.inf, hi_open=True)
        mu_k = mu if mu_k is None else in_range("mu_k", mu_k, 0.0, mu)
        r_g2 = block.radius_of_gyration**2
        body = _Rigid(
            block.b, block.h_cg, r_g2, r_g2 + block.R**2, mu, mu_k, e_val, block.housner_e(), th_ov
        )
        fields = _Modes(body, ground, tan_a, tol).run(n)
        return ReferenceResponse(
            t=ground.times,
            **fields,
            block=block,
            e=e_val,
            overturn_angle=th_ov,
            mu=mu,
            mu_k=mu_k,
        )
    k_mr = block.R / (block.radius_of_gyration**2 + block.R**2)  # M·R/I_O [1/m]

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
            start = ground.first_exceed(j, t_cur, ((1.0, tan_a), (-1.0, tan_a)))
            if start is None:
                break  # at rest to the end (θ = θ' = 0 at the samples)
            j, t_cur, _ = start
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


#: The indices of :data:`rocking.MODES` (a sample's ``mode`` indexes it).
_REST, _SLIDE, _ROCK, _SLIDE_ROCK, _FLIGHT = (
    MODES.index(m) for m in ("rest", "slide", "rock", "slide-rock", "flight")
)
#: Contact kinds of a corner: stuck (friction unknown), slipping (Coulomb, μ_k·N against the
#: slip), frictionless (normal force only; the second corner of the rest mode).
_STICK, _SLIP, _FREE = range(3)
#: More than this many transitions at one instant (within 1e-12 s) is an undecided contact.
_MAX_EVENTS_AT_ONCE = 100


@dataclass(frozen=True)
class _Rigid:
    """The body per unit mass: corners at (±b, −h) from the centre of mass [m] when upright,
    I_cm/m = ``i_cm`` [m²], I_0/m = ``i_0`` [m²] about a corner; friction ``mu_s``, ``mu_k``
    [-]; restitution ``e`` and Housner's ``e_h`` [-]; overturning angle ``th_ov`` [rad]."""

    b: float
    h: float
    i_cm: float
    i_0: float
    mu_s: float
    mu_k: float
    e: float
    e_h: float
    th_ov: float

    def corner(self, c: float, th: float) -> tuple[float, float]:
        """Vector from the centre of mass to corner c (±1, at +x or −x upright) at rotation θ
        [m]; θ > 0 turns the body about its +x corner (clockwise in x right, y up)."""
        ct, st = math.cos(th), math.sin(th)
        return c * self.b * ct - self.h * st, -c * self.b * st - self.h * ct

    def normal_response(self, c: float, th: float, sigma: float) -> float:
        """The upward velocity [m/s] that a unit upward impulse [m/s] at corner c, with its
        Coulomb partner −σ·μ_k along x, gives that corner at rotation θ: 1 + r_x·(r_x +
        σ·μ_k·r_y)/(I_cm/m).  Where it is ≤ 0 (Painlevé's inconsistent case) friction pulls the
        corner down harder than the normal force lifts it: a slip to side σ has no solution,
        neither as a motion nor as an impact."""
        rx, ry = self.corner(c, th)
        return 1.0 + rx * (rx + sigma * self.mu_k * ry) / self.i_cm

    def pivot_rate(self, c: float, z) -> float:
        """ω_L [rad/s]: the angular velocity that conserves the angular momentum of state z
        about corner c (the plastic law: the corner at rest after an impulse there)."""
        rx, ry = self.corner(c, z[2])
        return (self.i_cm * z[5] + rx * z[4] - ry * z[3]) / self.i_0


@dataclass(frozen=True)
class _Phase:
    """A mode with its contact corner c (±1), the slip direction σ (±1) of a slipping
    contact, and the position x_c [m] of a stuck pivot (rock)."""

    mode: int
    c: float = 1.0
    sigma: float = 0.0
    xc: float = 0.0

    @property
    def contacts(self) -> tuple[tuple[int, float, float], ...]:
        """(kind, corner, σ) of each contact."""
        if self.mode == _REST:  # the total friction acts at one corner: the same moment
            return ((_STICK, 1.0, 0.0), (_FREE, -1.0, 0.0))
        if self.mode == _SLIDE:
            return ((_SLIP, 1.0, self.sigma), (_SLIP, -1.0, self.sigma))
        if self.mode == _ROCK:
            return ((_STICK, self.c, 0.0),)
        if self.mode == _SLIDE_ROCK:
            return ((_SLIP, self.c, self.sigma),)
        return ()


def _newton_euler(body: _Rigid, z, a_g: float, gv: float, contacts):
    """Accelerations (x'', y'', θ'') of the centre of mass and the contact forces per unit
    mass [(N, F), ...] (N up, F along +x, on the body) of state z = (x, y, θ, x', y', θ')
    under the ground accelerations a_g and g + a_v = ``gv`` [m/s²].

    Newton–Euler in the ground's frame, one linear system: x'' − ΣF = −a_g,
    y'' − ΣN = −(g + a_v), (I_cm/m)·θ'' − Σ(r_y·F − r_x·N) = 0 (r from the centre of mass to
    the contact), with per contact its vertical acceleration 0 (y'' − r_x·θ'' − r_y·θ'² = 0)
    and, if stuck, its horizontal one (x'' + r_y·θ'' − r_x·θ'² = 0); a slipping contact has
    F = −σ·μ_k·N.
    """
    th, om2 = z[2], z[5] * z[5]
    n = 3 + sum(2 if kind == _STICK else 1 for kind, _, _ in contacts)
    a = np.zeros((n, n))
    rhs = np.zeros(n)
    a[0, 0] = a[1, 1] = 1.0
    a[2, 2] = body.i_cm
    rhs[0], rhs[1] = -a_g, -gv
    col = 3
    for kind, c, sigma in contacts:
        rx, ry = body.corner(c, th)
        a[1, col] = -1.0
        a[2, col] = rx
        if kind == _SLIP:
            a[0, col] = sigma * body.mu_k
            a[2, col] = rx + sigma * body.mu_k * ry
        a[col, 1], a[col, 2], rhs[col] = 1.0, -rx, ry * om2
        if kind == _STICK:
            a[0, col + 1], a[2, col + 1] = -1.0, -ry
            a[col + 1, 0], a[col + 1, 2], rhs[col + 1] = 1.0, ry, rx * om2
        col += 2 if kind == _STICK else 1
    sol = np.linalg.solve(a, rhs)
    forces = []
    col = 3
    for kind, _, sigma in contacts:
        normal = float(sol[col])
        if kind == _STICK:
            forces.append((normal, float(sol[col + 1])))
            col += 2
        else:
            forces.append((normal, -sigma * body.mu_k * normal if kind == _SLIP else 0.0))
            col += 1
    return sol[:3], forces


def _kinetic(body: _Rigid, z) -> float:
    """Kinetic energy per unit mass in the ground's frame [J/kg]."""
    return 0.5 * (z[3] ** 2 + z[4] ** 2 + body.i_cm * z[5] ** 2)


def _lowest(body: _Rigid, z) -> tuple[float, float]:
    """(slip, lift) [m] of state z: the horizontal displacement of the lowest corner s
    (s = sign θ) from where it stood at rest, x − s·b·(1 − cos θ) − h·sin θ (the position of
    the base had the body turned back about that corner; constant while it rocks), and that
    corner's height above the ground."""
    s = -1.0 if z[2] < 0.0 else 1.0
    rx, ry = body.corner(s, z[2])
    return z[0] + rx - s * body.b, z[1] + ry


@dataclass(frozen=True, eq=False)
class ReferenceResponse:
    """Response of :func:`simulate_reference` with friction (``mu`` given).

    Attributes
    ----------
    t : ndarray
        Sample times [s].
    theta, omega : ndarray
        Rotation θ [rad] and its rate θ' [rad/s] at the samples (NaN after overturning).
    slip : ndarray
        Horizontal displacement of the block relative to the ground due to sliding [m]: that
        of its lowest corner from where it stood at rest (0 while it only rocks; NaN after
        overturning).
    lift : ndarray
        Height of the base's lowest corner above the ground [m] (NaN after overturning).
    mode : ndarray of int
        Index into :data:`rocking.MODES` of the mode at each sample (after any transition at
        that instant); after overturning, the mode it overturned in (as :func:`rocking.simulate`).
    overturned : bool
    t_overturn : float
        Time of overturning [s], NaN if none.
    n_impacts : int
        Number of impacts (a corner striking: θ crossing 0, or a landing).
    max_abs_theta : float
        Largest abs(θ) at the samples [rad] (the overturning angle if overturned).
    max_abs_slip, max_lift : float
        Largest abs(slip) and lift at the samples [m] (and at overturning).
    residual_slip : float
        Slip at the end [m] (at overturning if the block overturned).
    events : tuple
        (t [s], what, kinetic energy before, after [J/kg, ground frame]) of every transition
        and impact, in order.
    block, e, overturn_angle, mu, mu_k :
        The inputs (e [-], overturn_angle [rad], mu and mu_k [-]).
    """

    t: np.ndarray
    theta: np.ndarray
    omega: np.ndarray
    slip: np.ndarray
    lift: np.ndarray
    mode: np.ndarray
    overturned: bool
    t_overturn: float
    n_impacts: int
    max_abs_theta: float
    max_abs_slip: float
    residual_slip: float
    max_lift: float
    events: tuple
    block: Block
    e: float
    overturn_angle: float
    mu: float
    mu_k: float


def _sign(x: float) -> float:
    """+1.0 for x ≥ 0, −1.0 below."""
    return -1.0 if x < 0.0 else 1.0


class _Modes:
    """One run of the reference with friction: the body, the ground motion, the tolerances,
    and the rules that pick a mode from the contact forces and resolve the impacts."""

    def __init__(self, body: _Rigid, ground: _Ground, tan_a: float, tol):
        self.body = body
        self.ground = ground
        self.tol = tol
        # rest ends where one of these c·a_g − k·(g + a_v) exceeds 0: slip to either side,
        # tipping to either side, free fall of the ground (g + a_v < 0)
        self.rows = ((1.0, body.mu_s), (-1.0, body.mu_s), (1.0, tan_a), (-1.0, tan_a), (0.0, 1.0))
        self.tan_a = tan_a

    def forces(self, ph: _Phase, j: int, t: float, z):
        """:func:`_newton_euler` in phase ``ph`` at time t of interval j."""
        a_g, gv = self.ground.pair(j, t)
        return _newton_euler(self.body, z, a_g, gv, ph.contacts)

    def rhs(self, ph: _Phase, j: int):
        """z' = f(t, z) of phase ``ph`` in interval j."""

        def f(t, z):
            acc = self.forces(ph, j, t, z)[0]
            return [z[3], z[4], z[5], acc[0], acc[1], acc[2]]

        return f

    def project(self, ph: _Phase, z) -> np.ndarray:
        """State z put back exactly on the contact constraints of ``ph`` (removes the drift
        of integrating them at the level of accelerations)."""
        z = np.array(z, dtype=float)
        if ph.mode == _SLIDE:
            z[1], z[2], z[4], z[5] = self.body.h, 0.0, 0.0, 0.0
        elif ph.mode in (_ROCK, _SLIDE_ROCK):
            rx, ry = self.body.corner(ph.c, z[2])
            z[1], z[4] = -ry, rx * z[5]
            if ph.mode == _ROCK:
                z[0], z[3] = ph.xc - rx, -ry * z[5]
        return z

    def events(self, ph: _Phase, j: int, t_seg: float):
        """(names, terminal events, watches) of phase ``ph`` in interval j, entered at t_seg;
        each event function reports a value of its non-crossing side at t_seg itself, so that
        only a crossing after the entry counts."""
        body = self.body
        c, sigma = ph.c, ph.sigma
        names: list[str] = []
        evs: list = []
        watches: list = []

        def add(name, fn, direction):
            names.append(name)
            evs.append(_terminal(fn, direction))

        def normal(t, z):  # total normal force
            return sum(n for n, _ in self.forces(ph, j, t, z)[1]) if t > t_seg else 1.0

        if ph.mode in (_ROCK, _SLIDE_ROCK, _FLIGHT):
            add("overturn", lambda t, z: abs(z[2]) - body.th_ov, 1.0)
        if ph.mode in (_ROCK, _SLIDE_ROCK):
            add("impact", lambda t, z: z[2] if t > t_seg else c, -c)
            add("lift-off", normal, -1.0)

            def turn_back(t, z):  # minima of c·θ: where c·θ < 0, a return to θ = 0 was missed
                return c * z[5]

            turn_back.direction = 1.0  # type: ignore[attr-defined]
            watches.append((turn_back, lambda z: c * z[2] < 0.0))
        if ph.mode == _ROCK:

            def slip(t, z):  # |F| − μ_s·N
                if t <= t_seg:
                    return -1.0
                n, f = self.forces(ph, j, t, z)[1][0]
                return abs(f) - body.mu_s * n

            add("slip", slip, 1.0)
        if ph.mode in (_SLIDE, _SLIDE_ROCK):

            def slip_velocity(z):  # of the corner, x' + r_y·θ' (x' in slide: θ = θ' = 0)
                return z[3] + body.corner(c, z[2])[1] * z[5]

            def slows(t, z):  # minima of σ·(slip velocity): its rate σ·(x'' + r_y·θ'' − r_x·θ'²)
                if t <= t_seg:
                    return 1.0
                acc = self.forces(ph, j, t, z)[0]
                rx, ry = body.corner(c, z[2])
                return sigma * (acc[0] + ry * acc[2] - rx * z[5] * z[5])

            add("stick", lambda t, z: slip_velocity(z) if t > t_seg else sigma, -sigma)
            # a slip velocity that reaches 0 and turns back inside one step (in slide DOP853
            # takes whole sample intervals, the motion being polynomial in t there) leaves
            # σ·(slip velocity) < 0 at its minimum: a stop was missed before it
            slows.direction = 1.0  # type: ignore[attr-defined]
            watches.append((slows, lambda z: sigma * slip_velocity(z) < 0.0))
        if ph.mode == _SLIDE_ROCK:
            add(
                "jam",
                lambda t, z: body.normal_response(c, z[2], sigma) if t > t_seg else 1.0,
                -1.0,
            )
        if ph.mode == _SLIDE:
            add("lift-off", normal, -1.0)
        elif ph.mode == _FLIGHT:
            for corner in (1.0, -1.0):

                def height(t, z, corner=corner):
                    return z[1] + body.corner(corner, z[2])[1] if t > t_seg else 1.0

                def dip(t, z, corner=corner):  # minima of the corner's height
                    return z[4] - body.corner(corner, z[2])[0] * z[5] if t > t_seg else 1.0

                add("landing", height, -1.0)
                dip.direction = 1.0  # type: ignore[attr-defined]
                watches.append(
                    (dip, lambda z, corner=corner: z[1] + body.corner(corner, z[2])[1] < 0.0)
                )
        return names, evs, watches

    def one_corner(self, j: int, t: float, z, c: float, sigma: float = 0.0) -> _Phase:
        """Phase of a body on its corner c, stuck (``sigma`` = 0) or slipping to side σ: rock
        while the stuck corner's friction fits in the cone (|F| ≤ μ_s·N), else slide-rock with
        the corner slipping against the friction it demands; flight where N < 0."""
        if sigma == 0.0:
            rock = _Phase(_ROCK, c, 0.0, z[0] + self.body.corner(c, z[2])[0])
            n, f = self.forces(rock, j, t, z)[1][0]
            if n < 0.0:
                return _Phase(_FLIGHT)
            if abs(f) <= self.body.mu_s * n:
                return rock
            sigma = -_sign(f)
        if self.body.normal_response(c, z[2], sigma) <= 0.0:
            # a stuck corner that cannot slip to that side (Painlevé), which happens only with
            # its free vertical acceleration upward (the module docstring): it lifts off
            return _Phase(_FLIGHT)
        ph = _Phase(_SLIDE_ROCK, c, sigma)
        return ph if self.forces(ph, j, t, z)[1][0][0] >= 0.0 else _Phase(_FLIGHT)

    def both_corners(self, j: int, t: float, z, sigma: float) -> _Phase:
        """Phase of a body on both corners (θ = 0) whose base slides to side σ: slide, or
        slide-rock on the corner that keeps N > 0 where the friction's moment lifts the
        other (μ_k·h > b), flight where g + a_v < 0."""
        ph = _Phase(_SLIDE, sigma=sigma)
        (n_plus, _), (n_minus, _) = self.forces(ph, j, t, z)[1]
        if n_plus + n_minus < 0.0:
            return _Phase(_FLIGHT)
        if min(n_plus, n_minus) < 0.0:
            c = 1.0 if n_plus > n_minus else -1.0
            if self.body.normal_response(c, z[2], sigma) <= 0.0:
                return _Phase(_SLIDE_ROCK, c, sigma)  # Painlevé: it jams at once (settle)
            return self.one_corner(j, t, z, c, sigma)
        return ph

    def leave_rest(self, j: int, t: float, z, first: tuple[int, ...]) -> _Phase:
        """Mode in which the body leaves rest at time t of interval j, where the rows
        ``first`` of :attr:`rows` exceeded 0 first: flight, else tipping (rock or slide-rock,
        as the contact forces admit) where it comes first or both come at once with
        μ_s ≥ tan α, else slide (Shenton 1996)."""
        if 4 in first:
            return _Phase(_FLIGHT)
        tip = [i for i in first if i in (2, 3)]
        slide = [i for i in first if i in (0, 1)]
        if tip and (not slide or self.body.mu_s >= self.tan_a):
            # a_g > 0 (row c = +1) pushes the block to −x: it tips about its −x corner
            return self.one_corner(j, t, z, -self.rows[tip[0]][0])
        return self.both_corners(j, t, z, -self.rows[slide[0]][0])

    def settle(self, j: int, t: float, z, vx: float) -> tuple[_Phase, np.ndarray]:
        """Both corners down (θ = 0, no vertical or angular velocity) with the base sliding
        at vx [m/s]: rest if vx = 0, else slide."""
        z = np.array([z[0], self.body.h, 0.0, vx, 0.0, 0.0])
        if vx == 0.0:
            return _Phase(_REST), z
        ph = self.both_corners(j, t, z, _sign(vx))
        if ph.mode == _SLIDE_ROCK and self.body.normal_response(ph.c, 0.0, ph.sigma) <= 0.0:
            return self.jam(j, t, z, ph.c)
        return ph, z

    def jam(self, j: int, t: float, z, c: float) -> tuple[_Phase, np.ndarray]:
        """Painlevé's inconsistent case, corner c slipping where no slip can go on
        (:meth:`_Rigid.normal_response` ≤ 0): an impact without collision stops it at once,
        plastic (the corner at rest after, ω_L: the module docstring); then the stuck corner's
        contact forces decide (:meth:`one_corner`)."""
        z = np.array(z, dtype=float)
        rx, ry = self.body.corner(c, z[2])
        w = self.body.pivot_rate(c, z)
        z[3], z[4], z[5] = -ry * w, rx * w, w
        return self.one_corner(j, t, z, c), z

    def flat(self, j: int, t: float, z) -> tuple[_Phase, np.ndarray]:
        """Both corners strike at once (MODES.md rule 3): plastic in the normal direction
        (y' and θ' → 0, vertical impulse P_y = −m·y'⁻), tangential stick if abs(x') ≤
        μ_s·P_y/m, else a Coulomb impulse μ_k·P_y against the slip."""
        p_y = max(-z[4], 0.0)
        vx = z[3]
        vx = (
            0.0 if abs(vx) <= self.body.mu_s * p_y else vx - math.copysign(self.body.mu_k * p_y, vx)
        )
        return self.settle(j, t, z, vx)

    def strike(
        self, j: int, t: float, z, c: float, at_zero: bool, rocked: bool = False
    ) -> tuple[_Phase, np.ndarray, str]:
        """Corner c strikes the ground (``at_zero``: θ crossing 0 from the other corner; else a
        landing after flight; ``rocked``: from rock, the other corner stuck): the
        impulse–momentum law of the module's docstring."""
        body = self.body
        z = np.array(z, dtype=float)
        if at_zero:
            z[1], z[2] = body.h, 0.0
        ke = _kinetic(body, z)
        th, vx, vy, om = z[2], z[3], z[4], z[5]
        rx, ry = body.corner(c, th)
        # 1. stick: the corner at rest after; ω_L conserves the angular momentum about it
        w_l = body.pivot_rate(c, z)
        # e·ω⁻ after rock (= (e/e_H)·ω_L there; also where e_H ≤ 0), else plastic where e_H ≤ 0
        w = body.e * om if rocked else w_l * (body.e / body.e_h if body.e_h > 0.0 else 1.0)
        cap = body.e * math.sqrt(2.0 * ke / body.i_0)  # no more than e² of the energy
        w = max(-cap, min(cap, w))
        p_x, p_y = -ry * w - vx, rx * w - vy
        sigma = 0.0
        if p_y >= 0.0 and abs(p_x) <= body.mu_s * p_y:
            kind = "stick impact"
        else:
            # 2. sliding: P_x = −σ·μ_k·P_y, P_y such that the corner's y' is 0 after
            vcx, vcy = vx + ry * om, vy - rx * om
            # a corner at rest before (an impact from rock) has vcx = 0 up to the rounding of
            # the located θ (1e-15 relative); below 10·rtol of the velocities it is no slip,
            # and the corner slips against the friction that sticking would need
            if abs(vcx) <= 10.0 * self.tol[0] * (abs(vx) + abs(ry * om)):
                vcx = 0.0
            sigma = _sign(vcx) if vcx != 0.0 else -_sign(p_x)
            den = body.normal_response(c, th, sigma)
            q_y = -vcy / den if den > 0.0 else -1.0
            q_x = -sigma * body.mu_k * q_y
            w_s = om + (ry * q_x - rx * q_y) / body.i_cm
            vcx_after = vx + q_x + ry * w_s
            if q_y >= 0.0 and sigma * vcx_after >= 0.0:
                kind = "sliding impact"
                z[3], z[4], z[5] = vx + q_x, vy + q_y, w_s
                sigma = 0.0 if vcx_after == 0.0 else sigma
            else:
                # a jam (the Coulomb impulse would pull the corner down), or a slip that
                # stops during the impact: the corner sticks, plastic (ω_L)
                kind, w, sigma = "plastic impact", w_l, 0.0
        if sigma == 0.0 and kind != "sliding impact":
            z[3], z[4], z[5] = -ry * w, rx * w, w
        if at_zero and c * z[5] <= 0.0:  # no rotation onto corner c: both corners down
            ph, z = self.flat(j, t, z)
            return ph, z, kind
        ph = self.one_corner(j, t, z, c, sigma)
        if at_zero and ph.mode in (_ROCK, _SLIDE_ROCK):
            acc = self.forces(ph, j, t, z)[0][2]
            if acc * z[5] < 0.0 and 2.0 * abs(z[5]) / abs(acc) < REST_FLIGHT_TIME:
                # a bounce too short to follow ends the sequence, on both corners: the tiny
                # rotation stops, the centre of mass keeps its horizontal velocity if slipping
                ph, z = self.settle(j, t, z, 0.0 if sigma == 0.0 else z[3])
        return ph, z, kind

    def transition(
        self, name: str, ph: _Phase, j: int, t: float, z
    ) -> tuple[_Phase, np.ndarray, str]:
        """The phase and state after event ``name`` of phase ``ph`` at time t of interval j."""
        if name == "lift-off":
            return _Phase(_FLIGHT), z, name
        if name == "slip":  # the corner slips against the friction it would need
            f = self.forces(ph, j, t, z)[1][0][1]
            return self.one_corner(j, t, z, ph.c, -_sign(f)), z, name
        if name == "stick" and ph.mode == _SLIDE:
            return _Phase(_REST), np.array([z[0], self.body.h, 0.0, 0.0, 0.0, 0.0]), name
        if name == "stick":
            return self.one_corner(j, t, z, ph.c), z, name
        if name == "jam":
            ph, z = self.jam(j, t, z, ph.c)
            return ph, z, name
        if name == "impact":
            return self.strike(j, t, z, -ph.c, at_zero=True, rocked=ph.mode == _ROCK)
        # landing: flat (both corners at once) if the body never turned, else corner sign θ
        if z[2] == 0.0 and z[5] == 0.0:
            ph, z = self.flat(j, t, z)
            return ph, z, "flat landing"
        ph, z, kind = self.strike(j, t, z, _sign(z[2]), at_zero=False)
        return ph, z, f"landing ({kind})"

    def run(self, n: int) -> dict:
        """Integrate from rest over the n samples; the response's fields as a dict."""
        body, ground = self.body, self.ground
        out = {k: np.full(n, np.nan) for k in ("theta", "omega", "slip", "lift")}
        mode = np.full(n, -1, dtype=np.int64)
        z = np.array([0.0, body.h, 0.0, 0.0, 0.0, 0.0])
        ph = _Phase(_REST)

        def record(k: int) -> None:
            out["theta"][k], out["omega"][k] = z[2], z[5]
            out["slip"][k], out["lift"][k] = _lowest(body, z)
            mode[k] = ph.mode

        record(0)
        events: list[tuple[float, str, float, float]] = []
        j, t_cur, t_seg, t_ov, n_imp, burst = 0, 0.0, 0.0, math.nan, 0, 0
        while j < n - 1:
            if ph.mode == _REST:
                start = ground.first_exceed(j, t_cur, self.rows)
                for k in range(j + 1, n if start is None else start[0] + 1):
                    record(k)  # at rest up to the start (or to the end)
                if start is None:
                    break
                j, t_cur, first = start
                ph = self.leave_rest(j, t_cur, z, first)
                events.append((t_cur, f"onset -> {MODES[ph.mode]}", 0.0, 0.0))
                t_seg = t_cur
                continue
            t_next = ground.times[j + 1]
            if t_cur >= t_next:  # an event exactly at the sample: on to the next interval
                j += 1
                record(j)
                continue
            names, evs, watches = self.events(ph, j, t_seg)
            sol = _segment(self.rhs(ph, j), t_cur, t_next, z, evs, watches, self.tol)
            if sol.status == 1:
                t_ev, i = min(
                    (float(sol.t_events[i][0]), i) for i in range(len(evs)) if sol.t_events[i].size
                )
                z_ev = self.project(ph, sol.y_events[i][0])
                if names[i] == "overturn":
                    t_ov, z = t_ev, z_ev
                    break
                ke = _kinetic(body, z_ev)
                ph, z, what = self.transition(names[i], ph, j, t_ev, z_ev)
                n_imp += (
                    what.endswith("impact)") or what.endswith("impact") or what == "flat landing"
                )
                events.append((t_ev, f"{what} -> {MODES[ph.mode]}", ke, _kinetic(body, z)))
                burst = burst + 1 if t_ev - t_seg < 1e-12 else 0
                if burst > _MAX_EVENTS_AT_ONCE:
                    raise RuntimeError(f"contact undecided at t = {t_ev:g} s: {events[-3:]}")
                t_cur = t_seg = t_ev
                continue
            if sol.status != 0:
                raise RuntimeError(f"solve_ivp failed at t = {t_cur:g} s: {sol.message}")
            z = self.project(ph, sol.y[:, -1])
            j, t_cur = j + 1, t_next
            record(j)
        overturned = not math.isnan(t_ov)
        if overturned:
            mode[j + 1 :] = ph.mode
        slip_end, _ = _lowest(body, z)
        slip = np.append(out["slip"][np.isfinite(out["slip"])], slip_end)
        return dict(
            out,
            mode=mode,
            overturned=overturned,
            t_overturn=t_ov,
            n_impacts=n_imp,
            max_abs_theta=body.th_ov if overturned else float(np.max(np.abs(out["theta"]))),
            max_abs_slip=float(np.max(np.abs(slip))),
            residual_slip=float(slip_end),
            max_lift=float(np.nanmax(np.append(out["lift"], _lowest(body, z)[1]))),
            events=tuple(events),
        )
