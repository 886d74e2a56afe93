"""Every response mode of a free-standing block (issue 45): rest, slide, rock, slide-rock, flight.

The model (the shared specification of issue 45): a planar rigid body (:class:`rocking.Block`,
general bodies included: centre of mass at h = R·cos α above the base, base corners at b = R·sin α
either side, radius of gyration r_g) on a rigid horizontal base that moves with a_g(t) and a_v(t)
(linear between samples), with Coulomb friction of static coefficient μ_s and kinetic μ_k ≤ μ_s.
Everything is written in the ground's frame (effective gravity G = g + a_v, inertial force −a_g),
per unit mass.  Signs as :func:`rocking.simulate`: θ > 0 leans the body to +x about its corner
at +x, φ = s·α − θ for the corner of side s = ±1 (the corner lies at (R·sin φ, −R·cos φ) from the
centre of mass, for either sign of θ).

Modes (:data:`MODES`, their index is the kernels' ``mode``) and their equations:

* rest: nothing moves while abs(a_g) ≤ μ_s·G and abs(a_g) ≤ G·tan α.  It is left when
  abs(a_g) first exceeds min(μ_s, tan α)·G (linear in the interval: the instant is exact); then
  Shenton (1996)'s classification: flight if G ≤ 0, slide if μ_s < tan α, else rock, or
  slide-rock where the friction that rocking needs at onset exceeds μ_s·N (Shenton, H.W. 1996,
  "Criteria for initiation of slide, rock, and slide-rock rigid-body modes", J. Eng. Mech.
  122(7):690–693).
* slide (θ = 0, both corners down): q'' = −a_g − σ·μ_k·G, σ the sign of the slip velocity
  (Newmark 1965's rigid sliding block); → rest when the slip velocity reaches 0 (rest then
  restarts at once if the ground still asks for more than μ_s·G); → flight when G < 0; → slide-rock
  when μ_k > tan α (the friction's moment tips the body over the leading corner).
* rock (one corner, sticking): Eq. (1) of :mod:`rocking.dynamics.equation`,
  θ'' = −(R/(r_g² + R²))·(G·sin φ + a_g·cos φ), with the contact forces from Newton's law for the
  centre of mass (X = x_c − R·sin φ, Y = R·cos φ):
  F = a_g + R·cos φ·θ'' + R·sin φ·θ'²,  N = G + R·sin φ·θ'' − R·cos φ·θ'²   (:func:`_rock_forces`);
  → slide-rock when abs(F) > μ_s·N (the corner slips opposite to F), → flight when N < 0.
* slide-rock (one corner, slipping at q'): F = −σ·μ_k·N, N from the corner staying on the ground;
  the moment about the centre of mass, −r_g²·θ'' = R·(sin φ·N + cos φ·F), gives with
  k = sin φ − σ·μ_k·cos φ
  θ'' = −R·k·(G − R·cos φ·θ'²)/(r_g² + R²·k·sin φ),  N = G + R·sin φ·θ'' − R·cos φ·θ'²,
  q'' = −σ·μ_k·N − a_g − R·cos φ·θ'' − R·sin φ·θ'²   (:func:`_rates`);
  → rock when the slip velocity reaches 0 and the rock mode's abs(F) ≤ μ_s·N (else the slip
  reverses), → flight when N < 0.
* Painlevé's paradox.  N = r_g²·(G − R·cos φ·θ'²)/den with den = r_g² + R²·k·sin φ, and den ≤ 0
  (no slide-rock at all: friction pulls the corner down harder than N pushes it up) for a
  corner that slips outward (σ = s) where μ_k ≥ f(φ) = (r_g² + R²·sin²φ)/(R²·sin φ·cos φ).
  With ρ = r_g²/R², f is smallest, 2·sqrt(ρ·(1 + ρ)), at tan φ = sqrt(ρ/(1 + ρ)), else at φ = α:
  f(α) = 1.93 for a uniform block of B/H = 0.2 (4/3 at best for any uniform block), but 0.58
  for a body whose mass sits near its centre (h = 1 m, b = 0.5 m, r_g = 0.2 m).  So ordinary
  μ reach it, and it is resolved, not refused, as in the literature (Génot, F. and Brogliato,
  B. 1999, "New results on Painlevé paradoxes", Eur. J. Mech. A/Solids 18:653–677; Champneys,
  A.R. and Várkonyi, P.L. 2016, "The Painlevé paradox in contact mechanics", IMA J. Appl.
  Math. 81:538–588): where the slip cannot go on, an impulsive tangential impact ("impact
  without collision", a "dynamic jam") stops it at once.  Here it is rule 2's jam: the plastic
  impulse that stops the corner, whose abs(P_x)/P_y = f(φ) ≤ μ_k lies inside the cone (at
  den = 0 it is the Coulomb impulse itself); then the stuck corner's contact forces decide, as
  after any transition (:func:`_plastic`, event ``_JAM``).  den ≤ 0 is entered by a transition
  (a slide that tips over its leading corner, μ_k > tan α, with μ_k ≥ f(α)); a slide-rock with
  G − R·cos φ·θ'² > 0 does not cross den = 0 by itself (θ'' and N grow like 1/den and turn θ
  back: an unbounded force of bounded impulse, Génot & Brogliato), but a fixed step can step
  over that turn, and the event catches it there.  A stuck corner never needs such a slip
  unless it would lift: its outward demand is −s·F = f(φ)·N − r_g²·(G − R·cos φ·θ'²)/
  (R²·sin φ·cos φ) (from the rock forces above), which exceeds μ_s·N ≥ f(φ)·N only where
  G − R·cos φ·θ'² < 0, i.e. where the corner's free vertical acceleration is upward: then
  N = 0 solves the contact problem, and the corner lifts off (:func:`_unstuck`).
* flight: X'' = −a_g, Y'' = −G, θ'' = 0, until a corner lands.
* overturning: abs(θ) ≥ the overturning angle, in any mode.

Impacts (a corner striking during rock or slide-rock, a landing after flight), an
impulse–momentum law of the Shenton & Jones (1991) type (Shenton, H.W. and Jones, N.P. 1991,
"Base excitation of rigid bodies. I: Formulation", J. Eng. Mech. 117(10):2286–2306; the same
distinction as Pompei, Scalia & Sumbatyan 1998 and Taniguchi 2002) with the impulse P at the
striking corner c and r_c from the centre of mass to c, m·ΔV = P, m·r_g²·ΔΩ = (r_c × P)_z:

1. stick impact: the striking corner becomes the pivot, at rest after the impact, and turns at
   θ'⁺ = (e/e_H)·θ'_L, θ'_L the angular velocity that conserves the angular momentum about c
   (Housner's e_H·θ'⁻ when nothing slipped before), with no more than e² of the kinetic energy
   before; without slip before it is :mod:`rocking.dynamics.impacts`' rule θ'⁺ = e·θ'⁻ itself.
   A squat body (e_H ≤ 0, Housner's law would turn it back) with a number e: θ'⁺ = e·θ'⁻ after
   rock all the same (today's rule, which a user's e describes), and after slip or flight the
   plastic θ'_L (factor 1): the only stick at the corner alone (the angular momentum about it
   kept), where no positive factor maps θ'_L onto e·θ'⁻ (a factor 0, a stop, would need
   impulses elsewhere; e/e_H < 0 would turn a body that lands on a corner up over it).
   Accepted when its impulse lies in the friction cone, P_y ≥ 0 and abs(P_x) ≤ μ_s·P_y (where
   θ'⁺ turns the body back into the ground, as after slide-rock, the other corner strikes too:
   rule 3 on the velocity that this impulse left);
2. otherwise a sliding (Coulomb) impact: P_x = −μ_k·P_y·sign(v_cx⁻) (a corner at rest before,
   as after rock, slips where a frictionless impulse would drive it: Routh), plastic in the normal
   direction (the corner's vertical velocity 0 after it); the body goes on in slide-rock (where it
   would turn back into the ground, the other corner strikes too: rule 3 on the velocity that
   the first impulse left).  Where that impulse would reverse the slip, the slip
   stops during the impact instead, and where its normal impulse would be negative (a jam,
   large μ_k·h) the corner jams: plastic in both directions (the corner at rest after it);
3. a flat landing (both corners at once): plastic normal impulse, stick if abs(V_x) ≤ μ_s·P_y,
   else Coulomb.

Assumptions: rigid body and base, point contacts at the corners, instantaneous impacts with one
impulse at the striking corner (the other corner's reaction during the impact is neglected, as in
Housner's rule), the tangential slip does not reverse during a sliding impact, and the restitution
e is empirical (e < e_H dissipates what the impulse at one corner cannot).  A bounce whose next
flight would last less than ``ZENO_TIME_FRACTION·dt`` ends at rest (or sliding), as the chatter
rule of :mod:`rocking.dynamics.impacts` does.

Integration, designed for bit-identity: an interval that starts at rest or in rock, and at rest
cannot slip (abs(a_g) ≤ μ_s·G, G > 0 at both ends; linear in between), is advanced by the rocking
kernel's own step (:func:`rocking.dynamics.impacts._advance`, the same arithmetic), and the contact
conditions (N ≥ 0, abs(F) ≤ μ_s·N at the step's end; the friction cone of its impacts; on a step
with an impact, the contact right after it: a bound over the step, else the general integrator below
keeping the corner stuck) are checked; only where one fails is the interval done again from its
start by the general integrator below.  A case that never leaves stick-rock thus gives
:func:`rocking.simulate`'s results bit for bit.  The general integrator takes one classical
Runge–Kutta step over the rest of the interval (the paper's scheme) in the current mode; where the
step ends with an event (the conditions of the mode above) the first instant is located on the
length of a partial Runge–Kutta step from the same start, to 1e-13·dt, by a safeguarded secant on
the event's continuous gap (:func:`_locate`; every trial classified by the event test itself, so
the bracket is a bisection's, in about 6–9 partial steps instead of its 43), the transition is
applied there and the interval goes on.  Events are looked for at the step's ends, right after
each transition (a corner that an impact leaves stuck slips, or lifts, at once where its contact
forces say so), and, for the slip velocity q' in slide and slide-rock, inside the step too: q'
may reach 0 and turn back between the ends.  The cubic Hermite interpolant of q' over the step
(q' at its ends, q'' of the first and the last Runge–Kutta stage; exact in slide, where q' is
quadratic in t) gives the instant of its lowest σ·q' (:func:`_slip_dip`); where that is ≤ 0 and
the partial step to it has σ·q' < 0, the first event is located by the same search up to that
instant, and the stick test applied there as at a step's end (stick where the friction needed
fits the cone, else the slip reverses).

Pure compiled functions on scalars and arrays; no I/O, no state.
"""

from __future__ import annotations

import math
from typing import TYPE_CHECKING, NamedTuple

from ..core.compile import kernel
from ..defaults import MODES
from .equation import _sin_cos_terms
from .impacts import (
    _OVERTURNED,
    _REST,
    _ROCKING,
    ZENO_TIME_FRACTION,
    Interval,
    _advance,
    _initial,
)

if TYPE_CHECKING:
    from .body import Block

__all__ = ["MODES", "Contact", "modes_case", "stick_impact_demand"]


# Mode codes: the index in MODES.
REST, SLIDE, ROCK, SLIDE_ROCK, FLIGHT = 0, 1, 2, 3, 4
# Event codes of the general integrator (:func:`_event`).
_NONE, _CROSS, _STICK, _LIFT, _SLIP, _LAND, _OVER, _JAM = 0, 1, 2, 3, 4, 5, 6, 7
#: Events handled in one sample interval at most (a safety cap; a Zeno sequence ends sooner).
_MAX_EVENTS = 1000
#: A located event lies within this fraction of the time step after its true instant.
_LOCATE_TOL = 1e-13


class Contact(NamedTuple):
    """Constants of one body's contact with its base, per unit mass (compiled to registers)."""

    g: float  #: gravity [m/s²]
    R: float  #: distance centre of mass–corner [m]
    rg2: float  #: r_g² [m²]
    mu_s: float  #: static friction coefficient [-]
    mu_k: float  #: kinetic friction coefficient [-]
    e_ratio: float  #: e/e_H (1 where e_H ≤ 0): the stick impact's factor on ω_L [-]
    impact_ok: bool  #: θ'⁺ = e·θ'⁻ from rock is in the friction cone (stick_impact_demand)

    @classmethod
    def of(cls, block: Block, e: float, mu: float, mu_k: float | None, g: float) -> Contact:
        """The contact of ``block`` with restitution e [-] (a number), friction μ_s = ``mu`` and
        μ_k = ``mu_k`` (None: μ_s) [-] under gravity g [m/s²]."""
        # e_H ≤ 0 for a squat body: no factor turns ω_L into e·θ'⁻ (that rule applies after
        # rock by itself), and after slip or flight the impact is plastic, ω_L: the only stick
        # impulse at the corner alone (the module docstring, rule 1)
        e_h = block.housner_e()
        return cls(
            g,
            block.R,
            block.radius_of_gyration**2,
            mu,
            mu if mu_k is None else mu_k,
            e / e_h if e_h > 0.0 else 1.0,
            stick_impact_demand(e, math.tan(block.alpha)) <= mu,
        )


@kernel(inline="always")
def _contact_at(x, b, g):
    """The :class:`Contact` of block b from per-block arrays ``x`` (the fields R, rg2, mu_s,
    mu_k, e_ratio, impact_ok of :class:`~rocking.dynamics.batch_records.Contacts`, which the
    lanes' ``Friction`` begins with) under gravity g [m/s²]."""
    return Contact(g, x.R[b], x.rg2[b], x.mu_s[b], x.mu_k[b], x.e_ratio[b], x.impact_ok[b])


def stick_impact_demand(e: float, tan_a: float) -> float:
    """abs(P_x)/P_y [-] of the impulse of the rule θ'⁺ = e·θ'⁻ at an impact from rock without
    slip (the same for every θ'⁻): (1 − e)/((1 + e)·tan α).

    Just before, the centre of mass moves at θ'⁻·(h, s·b) about the old corner; just after, at
    e·θ'⁻·(h, −s·b) about the new one; P/m is the difference, (h·θ'⁻·(e − 1), −s·b·θ'⁻·(1 + e)).
    """
    return (1.0 - e) / ((1.0 + e) * tan_a)


@kernel(inline="always")
def _sign(x):
    return 1.0 if x > 0.0 else (-1.0 if x < 0.0 else 0.0)


@kernel(inline="always")
def _rock_forces(th, om, s, u, gv, body, c):
    """(F, N) [m/s²] of the sticking corner s during rock (the module docstring), with
    u = a_g/g and gv = 1 + a_v/g."""
    S, C = _sin_cos_terms(th, s, body.sa, body.ca)
    return _contact_forces(S, C, om, u, gv, body.p2, c.g, c.R)


@kernel(inline="always")
def _contact_forces(S, C, om, u, gv, p2, g, R):
    """(F, N) [m/s²] of :func:`_rock_forces` from S = sin φ, C = cos φ, θ' = ``om`` [rad/s], p²
    [1/s²], g [m/s²] and R [m] (branch-free: the lane machine's checks use it too)."""
    acc = -p2 * (gv * S + u * C)  # Eq. (1)
    w2 = om * om
    F = g * u + R * (C * acc + S * w2)
    N = g * gv + R * (S * acc - C * w2)
    return F, N


@kernel(inline="always")
def _slide_rock(th, om, s, sig, u, gv, body, c):
    """(θ'' [rad/s²], q'' [m/s²], N [m/s²]) of slide-rock on corner s slipping in direction sig."""
    S, C = _sin_cos_terms(th, s, body.sa, body.ca)
    G = c.g * gv
    R = c.R
    w2 = om * om
    k = S - sig * c.mu_k * C
    acc = -R * k * (G - R * C * w2) / _slip_den(S, C, sig, c)
    N = G + R * (S * acc - C * w2)
    qdd = -sig * c.mu_k * N - c.g * u - R * (C * acc + S * w2)
    return acc, qdd, N


@kernel(inline="always")
def _slip_den(S, C, sig, c):
    """The denominator r_g² + R²·k·sin φ [m²] of slide-rock (k = sin φ − σ·μ_k·cos φ) on the
    corner at S = sin φ, C = cos φ slipping to side σ: ≤ 0 is Painlevé's inconsistent case
    (the module docstring)."""
    return c.rg2 + c.R * c.R * (S - sig * c.mu_k * C) * S


@kernel(inline="always")
def _painleve(th, s, sig, body, c):
    """Whether slide-rock on corner s slipping to side σ at rotation θ has no solution
    (:func:`_slip_den` ≤ 0)."""
    S, C = _sin_cos_terms(th, s, body.sa, body.ca)
    return _slip_den(S, C, sig, c) <= 0.0


@kernel(inline="always")
def _unstuck(th, s, F, body, c):
    """(mode, σ) of a stuck corner s whose friction demand F [m/s²] leaves the cone: slide-rock
    against F, or flight where that slide-rock has no solution (Painlevé; the module
    docstring: then the corner's free vertical acceleration is upward)."""
    sg = -_sign(F)
    if _painleve(th, s, sg, body, c):
        return FLIGHT, 0.0
    return SLIDE_ROCK, sg


@kernel(inline="always")
def _lowest(th, body, c):
    """(side, height below the centre of mass [m]) of the lower base corner at rotation θ."""
    s = 1.0 if th >= 0.0 else -1.0
    _S, C = _sin_cos_terms(th, s, body.sa, body.ca)
    return s, c.R * C


@kernel
def _rates(mode, s, sig, th, om, q, v, y, vy, u, gv, body, c):
    """Time derivatives of the state (θ, θ', q, q', y, y') in ``mode``: q is the slip (the corner
    of side s less s·b) in contact, the centre of mass's X in flight; y, y' its height (flight).
    Not for slide (its Runge–Kutta step: :func:`_slide_rk4`)."""
    if mode == ROCK:
        S, C = _sin_cos_terms(th, s, body.sa, body.ca)
        return om, -body.p2 * (gv * S + u * C), 0.0, 0.0, 0.0, 0.0
    if mode == SLIDE_ROCK:
        acc, qdd, _N = _slide_rock(th, om, s, sig, u, gv, body, c)
        return om, acc, v, qdd, 0.0, 0.0
    if mode == FLIGHT:
        return om, 0.0, v, -c.g * u, vy, -c.g * gv
    return 0.0, 0.0, 0.0, 0.0, 0.0, 0.0


@kernel(inline="always")
def _stage_inputs(u0, du, g0, dg, tau, h):
    """u and gv at a Runge–Kutta step's start, middle and end (u = u0 + du·τ, gv = g0 + dg·τ):
    (u_a, u_m, u_b, gv_a, gv_m, gv_b)."""
    ua = u0 + du * tau
    um = u0 + du * (tau + 0.5 * h)
    ub = u0 + du * (tau + h)
    ga = g0 + dg * tau
    gm = g0 + dg * (tau + 0.5 * h)
    gb = g0 + dg * (tau + h)
    return ua, um, ub, ga, gm, gb


@kernel(inline="always")
def _slide_rk4(th, om, q, v, y, vy, sig, u0, du, g0, dg, tau, h, g, mu_k):
    """:func:`_rk4` in slide (q'' = −g·(u + σ·μ_k·gv), g [m/s²], the rest of the state at rest):
    the same operations on the same values (the lanes of :mod:`rocking.dynamics.batch_lanes`
    run it in SIMD)."""
    ua, um, ub, ga, gm, gb = _stage_inputs(u0, du, g0, dg, tau, h)
    k1 = -g * (ua + sig * mu_k * ga)
    v2 = v + 0.5 * h * k1
    k2 = -g * (um + sig * mu_k * gm)
    v3 = v + 0.5 * h * k2
    k3 = -g * (um + sig * mu_k * gm)
    v4 = v + h * k3
    k4 = -g * (ub + sig * mu_k * gb)
    h6 = h / 6.0
    end = (
        th + h6 * 0.0,
        om + h6 * 0.0,
        q + h6 * (v + 2.0 * v2 + 2.0 * v3 + v4),
        v + h6 * (k1 + 2.0 * k2 + 2.0 * k3 + k4),
        y + h6 * 0.0,
        vy + h6 * 0.0,
    )
    return end, k1, k4


@kernel
def _rk4(mode, s, sig, st, u0, du, g0, dg, tau, h, body, c):
    """One classical Runge–Kutta step of length h from local time tau of the state tuple ``st``
    (θ, θ', q, q', y, y'), with u = u0 + du·τ and gv = g0 + dg·τ: (the state at tau + h, q'' of
    the first stage and of the last, the slopes of the slip velocity at the step's ends)."""
    th, om, q, v, y, vy = st
    if mode == SLIDE:
        return _slide_rk4(th, om, q, v, y, vy, sig, u0, du, g0, dg, tau, h, c.g, c.mu_k)
    ua, um, ub, ga, gm, gb = _stage_inputs(u0, du, g0, dg, tau, h)
    a1 = _rates(mode, s, sig, th, om, q, v, y, vy, ua, ga, body, c)
    x2 = (th + 0.5 * h * a1[0], om + 0.5 * h * a1[1], q + 0.5 * h * a1[2])
    y2 = (v + 0.5 * h * a1[3], y + 0.5 * h * a1[4], vy + 0.5 * h * a1[5])
    a2 = _rates(mode, s, sig, x2[0], x2[1], x2[2], y2[0], y2[1], y2[2], um, gm, body, c)
    x3 = (th + 0.5 * h * a2[0], om + 0.5 * h * a2[1], q + 0.5 * h * a2[2])
    y3 = (v + 0.5 * h * a2[3], y + 0.5 * h * a2[4], vy + 0.5 * h * a2[5])
    a3 = _rates(mode, s, sig, x3[0], x3[1], x3[2], y3[0], y3[1], y3[2], um, gm, body, c)
    x4 = (th + h * a3[0], om + h * a3[1], q + h * a3[2])
    y4 = (v + h * a3[3], y + h * a3[4], vy + h * a3[5])
    a4 = _rates(mode, s, sig, x4[0], x4[1], x4[2], y4[0], y4[1], y4[2], ub, gb, body, c)
    h6 = h / 6.0
    end = (
        th + h6 * (a1[0] + 2.0 * a2[0] + 2.0 * a3[0] + a4[0]),
        om + h6 * (a1[1] + 2.0 * a2[1] + 2.0 * a3[1] + a4[1]),
        q + h6 * (a1[2] + 2.0 * a2[2] + 2.0 * a3[2] + a4[2]),
        v + h6 * (a1[3] + 2.0 * a2[3] + 2.0 * a3[3] + a4[3]),
        y + h6 * (a1[4] + 2.0 * a2[4] + 2.0 * a3[4] + a4[4]),
        vy + h6 * (a1[5] + 2.0 * a2[5] + 2.0 * a3[5] + a4[5]),
    )
    return end, a1[3], a4[3]


@kernel(inline="always")
def _no_slip_zero(w0, e0, w1, e1):
    """Whether the cubic of :func:`_slip_dip` (w0, e0, w1, e1 as there) has no zero on [0, 1]
    by the quick test: it lies above its Bernstein control points w0, w0 + e0/3, w1 − e1/3,
    w1, and where all are positive (nearly every step) it has none.  Branch-free (the lanes'
    SIMD loop uses it too)."""
    return (w0 > 0.0) & (3.0 * w0 + e0 > 0.0) & (3.0 * w1 - e1 > 0.0) & (w1 > 0.0)


@kernel(inline="always")
def _slip_dip(sig, v0, a0, v1, a1, h):
    """Local time [s] in (0, h) of the lowest σ·q' on the cubic Hermite interpolant of the slip
    velocity over a step (q' = v0, v1 [m/s] and q'' = a0, a1 [m/s²] at its ends), where that
    lowest value is ≤ 0 (the slip velocity reaches 0 inside the step), or −1.  With
    w(x) = σ·q' at x = τ/h ∈ [0, 1], w = w0 + e0·x + B·x² + C·x³, e0 = σ·a0·h,
    B = 3·(w1 − w0) − 2·e0 − e1, C = 2·(w0 − w1) + e0 + e1 (e1 = σ·a1·h); its minimum is the
    root of w' = e0 + 2·B·x + 3·C·x² where w'' > 0, x = −e0/(B + sqrt(B² − 3·C·e0)) (the
    conjugate form, also right for C = 0).  In slide (q'' depends on time only, linearly) the
    interpolant is the slip velocity itself."""
    w0 = sig * v0
    w1 = sig * v1
    e0 = sig * a0 * h
    e1 = sig * a1 * h
    if _no_slip_zero(w0, e0, w1, e1):
        return -1.0
    B = 3.0 * (w1 - w0) - 2.0 * e0 - e1
    C = 2.0 * (w0 - w1) + e0 + e1
    disc = B * B - 3.0 * C * e0
    if disc < 0.0:
        return -1.0
    den = B + math.sqrt(disc)
    if den <= 0.0:
        return -1.0
    x = -e0 / den
    if not 0.0 < x < 1.0 or w0 + x * (e0 + x * (B + x * C)) > 0.0:
        return -1.0
    return x * h


@kernel
def _event(mode, s, sig, st, u, gv, body, c):
    """The event that the state tuple ``st`` shows in ``mode`` (the module docstring), or
    _NONE: the first of overturning, a corner through the ground, the slip velocity through 0,
    lift-off, slip of the sticking corner, landing."""
    th, om, _q, v, y, _vy = st
    if mode != SLIDE and abs(th) >= body.th_ov:
        return _OVER
    if mode == SLIDE:
        if sig * v < 0.0:
            return _STICK
        if gv < 0.0:
            return _LIFT
        return _NONE
    if mode in (ROCK, SLIDE_ROCK):
        if s * th < 0.0 or (th == 0.0 and s * om < 0.0):
            return _CROSS
        if mode == SLIDE_ROCK:
            if sig * v < 0.0:
                return _STICK
            if _painleve(th, s, sig, body, c):
                return _JAM
            _acc, _qdd, N = _slide_rock(th, om, s, sig, u, gv, body, c)
            return _LIFT if N < 0.0 else _NONE
        F, N = _rock_forces(th, om, s, u, gv, body, c)
        if N < 0.0:
            return _LIFT
        if abs(F) > c.mu_s * N:
            return _SLIP
        return _NONE
    if mode == FLIGHT:
        _sl, low = _lowest(th, body, c)
        if y - low < 0.0:
            return _LAND
    return _NONE


@kernel
def _gap(code, mode, s, sig, st, u, gv, body, c):
    """How far the state tuple ``st`` in ``mode`` (u = a_g/g, gv = 1 + a_v/g) is from the event
    ``code`` of :func:`_event`, continuous in the state: > 0 where that code's condition does
    not hold, ≤ 0 where it does (up to its ties at 0).  In the code's own units: θ_ov − abs(θ)
    and s·θ [rad] (_OVER, _CROSS), σ·q' [m/s] (_STICK), N [m/s²] (_LIFT; gv [-] in slide),
    μ_s·N − abs(F) [m/s²] (_SLIP), y minus the lower corner's depth [m] (_LAND), the slide-rock
    denominator [m²] (_JAM).  Only to interpolate (:func:`_locate`), never to classify."""
    th, om, _q, v, y, _vy = st
    if code == _OVER:
        return body.th_ov - abs(th)
    if code == _CROSS:
        return s * th
    if code == _STICK:
        return sig * v
    if code == _LIFT:
        if mode == SLIDE:
            return gv
        if mode == SLIDE_ROCK:
            return _slide_rock(th, om, s, sig, u, gv, body, c)[2]
        return _rock_forces(th, om, s, u, gv, body, c)[1]
    if code == _SLIP:
        F, N = _rock_forces(th, om, s, u, gv, body, c)
        return c.mu_s * N - abs(F)
    if code == _LAND:
        return y - _lowest(th, body, c)[1]
    S, C = _sin_cos_terms(th, s, body.sa, body.ca)
    return _slip_den(S, C, sig, c)  # _JAM


@kernel
def _locate(mode, s, sig, st, tau, hi, end, u0, du, g0, dg, dt, body, c):
    """The first event of the partial Runge–Kutta steps from local time tau [s] of the state
    tuple ``st`` in ``mode`` (the module docstring), given a step length ``hi`` [s] whose state
    ``end`` shows an event (by :func:`_event`, u and gv at tau + hi).  Returns (hi, end): the
    partial step of length hi (end, its state) shows an event, one of length lo ≥ 0 shows
    none (lo = 0: the start, taken as showing none, as every event is located after a state
    without one), and hi − lo ≤ _LOCATE_TOL·dt: the guarantee of a bisection on the same
    predicate.

    Every trial point is classified by :func:`_event` itself and moves lo or hi as a bisection
    would; only the choice of the trial differs: the secant of the last two trials on the
    event's :func:`_gap` (of the code shown at hi; where a new hi shows another code, of that
    one, from the bracket's ends), kept inside the bracket by at least _LOCATE_TOL·dt/2, so
    that an estimate within that of an end closes the bracket with one more trial; a bisection
    where the secant leaves the bracket or would move at least half as far as the trial before
    the last (Brent's safeguard: the moves shrink at least geometrically).  Every trial shrinks
    the bracket, by at least _LOCATE_TOL·dt/2: the loop ends."""
    w = _LOCATE_TOL * dt
    m = 0.5 * w
    lo = 0.0
    slo = st
    code = _event(mode, s, sig, end, u0 + du * (tau + hi), g0 + dg * (tau + hi), body, c)
    a = lo  # the trial before the last, and the last: (time, gap)
    ga = _gap(code, mode, s, sig, st, u0 + du * tau, g0 + dg * tau, body, c)
    b = hi
    gb = _gap(code, mode, s, sig, end, u0 + du * (tau + hi), g0 + dg * (tau + hi), body, c)
    d = e = math.inf  # the last move and the one before
    while hi - lo > w:
        x = -1.0
        if gb != ga:
            x = b - gb * ((b - a) / (gb - ga))
        if lo <= x <= hi and abs(x - b) < 0.5 * e:
            e = d
        else:
            x = 0.5 * (lo + hi)
            e = abs(x - b)
        x = min(max(x, lo + m), hi - m)
        d = abs(x - b)
        sx = _rk4(mode, s, sig, st, u0, du, g0, dg, tau, x, body, c)[0]
        ux = u0 + du * (tau + x)
        gx = g0 + dg * (tau + x)
        cx = _event(mode, s, sig, sx, ux, gx, body, c)
        a, ga = b, gb
        if cx != _NONE:
            hi = x
            end = sx
            if cx != code:  # from the bracket's ends, in the new code's gap
                code = cx
                a = lo
                ga = _gap(
                    code, mode, s, sig, slo, u0 + du * (tau + lo), g0 + dg * (tau + lo), body, c
                )
        else:
            lo = x
            slo = sx
        b = x
        gb = _gap(code, mode, s, sig, sx, ux, gx, body, c)
    return hi, end


@kernel
def _leave_rest(tau, u0, du, g0, dg, dt, tan_a, mu_s):
    """Local time [s] in [tau, dt] at which a body at rest starts to move (abs(u) first exceeds
    min(μ_s, tan α)·gv; u and gv linear), or −1 if it stays at rest."""
    thr = min(mu_s, tan_a)
    best = -1.0
    for sg in (1.0, -1.0):
        a = sg * u0 - thr * g0  # f(τ) = a + b·τ
        b = sg * du - thr * dg
        if a + b * tau > 0.0:
            return tau
        if a + b * dt > 0.0:
            t = -a / b
            t = tau if t < tau else t
            if best < 0.0 or t < best:
                best = t
    return best


@kernel
def _start(u, gv, body, c):
    """The mode in which a body at rest starts to move (Shenton 1996's classification): returns
    (mode, s, σ)."""
    if gv <= 0.0:
        return FLIGHT, 1.0, 0.0
    if c.mu_s < body.tan_a:
        return SLIDE, 1.0, -_sign(u)
    s = -1.0 if u > 0.0 else 1.0
    F, N = _rock_forces(0.0, 0.0, s, u, gv, body, c)
    if abs(F) <= c.mu_s * N:
        return ROCK, s, 0.0
    mode, sg = _unstuck(0.0, s, F, body, c)
    return mode, s, sg


@kernel
def _strike(th, sc, om, VX, VY, switch, rocked, body, c):
    """Impact of the corner of side ``sc`` at rotation θ, the centre of mass moving at
    (VX, VY) [m/s] and the body turning at θ' = ``om`` [rad/s] (rules 1 and 2 of the module
    docstring; ``switch``: a pivot change at θ = 0, where a body that would turn back into the
    ground comes down on both corners; ``rocked``: nothing slipped before, the body rocked on
    its other corner, and the stick impact is θ'⁺ = e·θ'⁻).  Returns (mode, θ', corner's slip
    velocity [m/s], σ)."""
    S, C = _sin_cos_terms(th, sc, body.sa, body.ca)
    R = c.R
    rcx = R * S  # centre of mass → striking corner
    rcy = -R * C
    Om = -om  # counter-clockwise angular velocity
    i0 = c.rg2 + R * R
    # 1. stick: angular momentum about the corner conserved, times e/e_H, capped at e²·KE; e·θ'⁻
    # after rock (the same where e_H > 0)
    OmL = (c.rg2 * Om - rcx * VY + rcy * VX) / i0
    Omp = body.e * Om if rocked else c.e_ratio * OmL
    cap = body.e * math.sqrt((VX * VX + VY * VY + c.rg2 * om * om) / i0)
    if abs(Omp) > cap:
        Omp = math.copysign(cap, Omp)
    Px = Omp * rcy - VX
    Py = -Omp * rcx - VY
    if Py >= 0.0 and abs(Px) <= c.mu_s * Py:
        if switch and sc * -Omp <= 0.0:  # the other corner comes down too: rule 3 after this
            mode, v = _flat(VX + Px, VY + Py, c)
            return mode, 0.0, v, _sign(v)
        return (ROCK if Omp != 0.0 else REST), -Omp, 0.0, 0.0
    # 2. sliding impact: Coulomb tangential impulse, plastic normal
    vcx = VX - Om * rcy
    vcy = VY + Om * rcx
    # the direction of the slip: the corner's, or for a corner at rest (an impact from rock at
    # θ = 0) where a frictionless impulse would drive it (Routh's rule; −rcx·rcy·Py/rg² with
    # Py > 0), which is also the side opposite to the friction that sticking would need
    sg = _sign(vcx) if vcx != 0.0 else _sign(-rcx * rcy)
    lam = -c.mu_k * sg
    den = 1.0 + rcx * (rcx - lam * rcy) / c.rg2
    Py = -vcy / den if den > 0.0 else -1.0
    Px = lam * Py
    Om2 = Om + (rcx * Py - rcy * Px) / c.rg2
    v = VX + Px - Om2 * rcy
    # the slip would reverse (it stops during the impact), or the Coulomb impulse would pull the
    # corner down (den ≤ 0: a jam, Painlevé): plastic, stuck
    if Py < 0.0 or v * sg < 0.0:
        Px, Py, Om2 = _plastic(rcx, rcy, vcx, vcy, Om, c)
        v = 0.0
    if switch and sc * -Om2 <= 0.0:  # the other corner comes down too: rule 3 after this
        mode, v = _flat(VX + Px, VY + Py, c)
        return mode, 0.0, v, _sign(v)
    return (SLIDE_ROCK if v != 0.0 else ROCK), -Om2, v, _sign(v)


@kernel(inline="always")
def _plastic(rcx, rcy, vcx, vcy, Om, c):
    """The impulse (P_x, P_y) [m/s] that stops a corner at (rcx, rcy) [m] from the centre of
    mass moving at (vcx, vcy) [m/s] in both directions, and the counter-clockwise angular
    velocity after it [rad/s] (Om before): P = −K⁻¹·v_c, K the corner's inverse mass matrix
    per unit mass (the jam of rule 2 and of Painlevé's case)."""
    kxx = 1.0 + rcy * rcy / c.rg2
    kyy = 1.0 + rcx * rcx / c.rg2
    kxy = -rcx * rcy / c.rg2
    det = kxx * kyy - kxy * kxy
    Px = -(kyy * vcx - kxy * vcy) / det
    Py = -(kxx * vcy - kxy * vcx) / det
    return Px, Py, Om + (rcx * Py - rcy * Px) / c.rg2


@kernel(inline="always")
def _flat(VX, VY, c):
    """Rule 3, both corners striking at once with the centre of mass at (VX, VY) [m/s] and no
    rotation after: plastic normal impulse P_y = −VY, stick if abs(VX) ≤ μ_s·P_y, else a Coulomb
    impulse μ_k·P_y against the slip.  Returns (mode, slip velocity after [m/s])."""
    Py = max(-VY, 0.0)
    if abs(VX) <= c.mu_s * Py:
        return REST, 0.0
    return SLIDE, VX - _sign(VX) * c.mu_k * Py


@kernel
def _settle(mode, s, sig, st, u, gv, dt, body, c):
    """After an impact at θ = 0: a next flight shorter than ZENO_TIME_FRACTION·dt ends the
    sequence, on both corners: rest, or, if the corner slips, slide at the centre of mass's
    horizontal velocity q' + h·θ' (q': the corner's): the tiny rotation stops without a
    horizontal impulse, as the bounces it stands for are neglected, and the kinetic energy,
    ½·(q' + h·θ')² + ½·(r_g² + b²)·θ'² before, does not grow; keeping the corner's q' instead
    would raise it by about h·abs(q'·θ') wherever q'·θ' < 0.  Returns (mode, θ', slip
    velocity [m/s])."""
    th, om, q, v, y, vy = st
    if mode != ROCK and mode != SLIDE_ROCK:
        return mode, om, v
    acc = _rates(mode, s, sig, th, om, q, v, y, vy, u, gv, body, c)[1]
    if om == 0.0 or (acc * om < 0.0 and 2.0 * abs(om) < ZENO_TIME_FRACTION * dt * abs(acc)):
        vx = v + c.R * body.ca * om if mode == SLIDE_ROCK else 0.0
        return (SLIDE if vx != 0.0 else REST), 0.0, vx
    return mode, om, v


@kernel
def _to_flight(mode, s, st, body, c):
    """The state tuple in flight (X, V_X, Y, V_Y of the centre of mass) from contact on corner s."""
    th, om, q, v, _y, _vy = st
    if mode == SLIDE:
        return (0.0, 0.0, q, v, c.R * body.ca, 0.0)
    S, C = _sin_cos_terms(th, s, body.sa, body.ca)
    xc = q + s * c.R * body.sa  # the corner's position
    return (th, om, xc - c.R * S, v + c.R * C * om, c.R * C, c.R * S * om)


@kernel
def _transition(code, mode, s, sig, st, u, gv, dt, body, c):
    """Apply the event ``code`` located at the state tuple ``st``: returns (mode, s, σ, state,
    impacts counted)."""
    th, om, q, v, _y, vy = st
    if code == _STICK and mode == SLIDE:  # rest, which restarts at once if it cannot hold
        return REST, s, 0.0, (0.0, 0.0, q, 0.0, 0.0, 0.0), 0
    if code in (_STICK, _SLIP):
        if code == _STICK:
            st = (th, om, q, 0.0, 0.0, 0.0)
        F, N = _rock_forces(th, om, s, u, gv, body, c)
        if code == _STICK and abs(F) <= c.mu_s * N:
            return ROCK, s, 0.0, st, 0
        m2, sg = _unstuck(th, s, F, body, c)
        if m2 == FLIGHT:
            return FLIGHT, s, 0.0, _to_flight(ROCK, s, st, body, c), 0
        return SLIDE_ROCK, s, sg, st, 0
    if code == _JAM:  # Painlevé: the slip stops at once, plastic (the module docstring)
        S, C = _sin_cos_terms(th, s, body.sa, body.ca)
        _Px, _Py, Om2 = _plastic(c.R * S, -c.R * C, v, 0.0, -om, c)
        return ROCK, s, 0.0, (th, -Om2, q, 0.0, 0.0, 0.0), 0
    if code == _LIFT:
        return FLIGHT, s, 0.0, _to_flight(mode, s, st, body, c), 0
    if code == _CROSS:
        if mode == ROCK and c.impact_ok:  # rule 1 without slip: θ'⁺ = e·θ'⁻
            new = (0.0, body.e * om, q, 0.0, 0.0, 0.0)
            m2, om2, _v = _settle(ROCK, -s, 0.0, new, u, gv, dt, body, c)
            return m2, -s, 0.0, (0.0, om2, q, 0.0, 0.0, 0.0), 1
        fl = _to_flight(mode, s, (0.0, om, q, v, 0.0, 0.0), body, c)
        m2, om2, v2, sg2 = _strike(0.0, -s, om, fl[3], fl[5], True, mode == ROCK, body, c)
        m2, om2, v2 = _settle(m2, -s, sg2, (0.0, om2, q, v2, 0.0, 0.0), u, gv, dt, body, c)
        return m2, -s, _sign(v2), (0.0, om2, q, v2, 0.0, 0.0), 1
    if code == _LAND:
        X = q
        sl, _low = _lowest(th, body, c)
        if th == 0.0 and om == 0.0:  # 3. flat landing: plastic normal, then stick or Coulomb
            m2, v2 = _flat(v, vy, c)
            return m2, s, _sign(v2), (0.0, 0.0, X, v2, 0.0, 0.0), 1
        S, _C = _sin_cos_terms(th, sl, body.sa, body.ca)
        qc = X + c.R * S - sl * c.R * body.sa  # the slip of the landing corner
        m2, om2, v2, sg2 = _strike(th, sl, om, v, vy, False, False, body, c)
        return m2, sl, sg2, (th, om2, qc, v2 if m2 != REST else 0.0, 0.0, 0.0), 1
    return mode, s, sig, st, 0


@kernel
def _then(code, mode, s, sig, st, u, gv, dt, body, c):
    """:func:`_transition` of ``code``, then the contact right after it: a corner that an impact
    (or a jam) leaves stuck may have to slip (or lift) at once; the contact forces decide there,
    not only at the step's end.  Returns (mode, s, σ, state, impacts counted)."""
    mode, s, sig, st, n = _transition(code, mode, s, sig, st, u, gv, dt, body, c)
    code = _event(mode, s, sig, st, u, gv, body, c)
    if code in (_SLIP, _LIFT):
        mode, s, sig, st, n2 = _transition(code, mode, s, sig, st, u, gv, dt, body, c)
        n += n2
    return mode, s, sig, st, n


@kernel
def _general(mode, s, sig, st, tau, u0, du, g0, dg, dt, body, c):
    """The general integrator over the local times [tau, dt] of a sample interval (the module
    docstring).  Returns (mode, s, σ, state, impacts counted, local time of overturning [s] or
    −1)."""
    n_imp = 0
    for _ in range(_MAX_EVENTS):
        if tau >= dt:
            break
        if mode == REST:
            t = _leave_rest(tau, u0, du, g0, dg, dt, body.tan_a, c.mu_s)
            if t < 0.0:
                break
            tau = t
            mode, s, sig = _start(u0 + du * t, g0 + dg * t, body, c)
            q = st[2]
            if mode == FLIGHT:
                st = (0.0, 0.0, q, 0.0, c.R * body.ca, 0.0)
            continue
        if mode == SLIDE and c.mu_k > body.tan_a:  # the friction's moment tips the body
            mode = SLIDE_ROCK
            s = sig
            if _painleve(0.0, s, sig, body, c):  # onto a corner that jams at once
                ut = u0 + du * tau
                gt = g0 + dg * tau
                mode, s, sig, st, _n = _then(_JAM, mode, s, sig, st, ut, gt, dt, body, c)
        h = dt - tau
        end, a0, a1 = _rk4(mode, s, sig, st, u0, du, g0, dg, tau, h, body, c)
        code = _event(mode, s, sig, end, u0 + du * dt, g0 + dg * dt, body, c)
        hi = h
        if mode in (SLIDE, SLIDE_ROCK):
            # a slip velocity that reaches 0 and turns back inside the step: its ends do not
            # show it; the partial step to the interpolant's lowest point brackets it
            tz = _slip_dip(sig, st[3], a0, end[3], a1, h)
            if tz > 0.0:
                sz = _rk4(mode, s, sig, st, u0, du, g0, dg, tau, tz, body, c)[0]
                if sig * sz[3] < 0.0:
                    hi = tz
                    end = sz
                    code = _STICK
        if code == _NONE:
            st = end
            break
        hi, end = _locate(mode, s, sig, st, tau, hi, end, u0, du, g0, dg, dt, body, c)
        tau += hi
        ut = u0 + du * tau
        gt = g0 + dg * tau
        code = _event(mode, s, sig, end, ut, gt, body, c)
        if code == _OVER:
            th = body.th_ov if end[0] > 0.0 else -body.th_ov
            return mode, s, sig, (th, end[1], end[2], end[3], end[4], end[5]), n_imp, tau
        mode, s, sig, st, n = _then(code, mode, s, sig, end, ut, gt, dt, body, c)
        n_imp += n
    return mode, s, sig, st, n_imp, -1.0


@kernel
def _cone_holds_after_impacts(om0, u0, u1, g0, g1, dt, body, c):
    """Whether every state right after an impact inside a rocking step (θ = 0 on either corner,
    abs(θ') ≤ W, u and gv anywhere between their values at the step's ends) meets the rock
    mode's contact conditions N ≥ 0 and abs(F) ≤ μ_s·N: a cheap sufficient condition.  At
    θ = 0, F and N are affine in u, gv and θ'², so their vertices decide; W = abs(θ'0) +
    dt·p²·(max abs(gv) + max abs(u)) bounds abs(θ') over the step (abs(θ'') ≤ p²·(abs(gv) +
    abs(u)), and an impact only slows the body)."""
    W = abs(om0) + dt * body.p2 * (max(abs(g0), abs(g1)) + max(abs(u0), abs(u1)))
    for sd in (1.0, -1.0):
        for uu, gg in ((u0, g0), (u1, g1)):
            for w in (0.0, W):
                F, N = _rock_forces(0.0, w, sd, uu, gg, body, c)
                if N < 0.0 or abs(F) > c.mu_s * N:
                    return False
    return True


@kernel
def _stays_stuck(mode, s, st, u0, du, g0, dg, dt, body, c):
    """Whether the general integrator keeps the corner stuck (no slip, no flight, no
    overturning) over the interval from the state tuple ``st`` in ``mode`` (rest or rock): the
    check of the contact right after an impact inside a rocking step, which that step only
    looks at the step's end."""
    m2, _s, _sig, st2, _n, tev = _general(mode, s, 0.0, st, 0.0, u0, du, g0, dg, dt, body, c)
    return tev < 0.0 and m2 in (ROCK, REST) and st2[2] == st[2]


@kernel(inline="always")
def _slip_lift(mode, st, body, c):
    """(slip [m], lift [m]) of the state tuple ``st`` in ``mode`` (module docstring)."""
    if mode != FLIGHT:
        return st[2], 0.0
    sl, low = _lowest(st[0], body, c)
    S, _C = _sin_cos_terms(st[0], sl, body.sa, body.ca)
    return st[2] + c.R * S - sl * c.R * body.sa, st[4] - low


@kernel(inline="always")
def _gv_or_one(gv):
    """gv [-], or 1.0 for None (no vertical motion)."""
    if gv is None:
        return 1.0
    return gv


@kernel(inline="always")
def _may_slip_at_rest(u, gv, mu_s):
    """Whether a base at rest under u = a_g/g [-] and gv = 1 + a_v/g [-] (None: 1) may slip or
    fly (G ≤ 0 or abs(u) > μ_s·gv): where it holds at either end of an interval,
    :func:`modes_case` does that interval with the general integrator; ``mu_s`` None: never
    (no friction)."""
    if mu_s is None:
        return False
    gf = _gv_or_one(gv)
    return not (gf > 0.0 and abs(u) <= mu_s * gf)


@kernel
def _modes_interval(mode, s, sig, st, u0, u1, g0, g1, dt, body, c, located):
    """One sample interval of :func:`modes_case` from (``mode``, side s, σ, state tuple ``st``
    (θ, θ', q, q', y, y')) under u = a_g/g [-] from u0 to u1 and gv = 1 + a_v/g [-] from g0 to
    g1 (None: no vertical motion), dt [s]: the rocking kernel's step with the contact checks
    where the interval starts in rock, or at rest where the base cannot slip, else (or where a
    check fails) the general integrator from the interval's start (the module docstring).
    Returns (mode, s, σ, state, impacts counted, overturned, local time of overturning [s],
    friction demand at the end [-] (0 where none is defined))."""
    gf0 = _gv_or_one(g0)
    gf1 = _gv_or_one(g1)
    dem = 0.0
    if mode == ROCK or (
        mode == REST
        and not _may_slip_at_rest(u0, g0, c.mu_s)
        and not _may_slip_at_rest(u1, g1, c.mu_s)
    ):
        state = _ROCKING if mode == ROCK else _REST
        th1, om1, s1, st1, ni, tev = _advance(
            st[0], st[1], s, state, Interval(u0, u1, g0, g1, dt), body, located
        )
        done = False
        if st1 == _OVERTURNED:
            done = True
        elif st1 == _REST:
            done = True
            dem = abs(u1) / gf1
        else:
            F, N = _rock_forces(th1, om1, s1, u1, gf1, body, c)
            if N >= 0.0 and abs(F) <= c.mu_s * N and (ni == 0 or c.impact_ok):
                du = (u1 - u0) / dt
                dg = (gf1 - gf0) / dt
                done = (
                    ni == 0
                    or _cone_holds_after_impacts(st[1], u0, u1, gf0, gf1, dt, body, c)
                    or _stays_stuck(mode, s, st, u0, du, gf0, dg, dt, body, c)
                )
                if N > 0.0:
                    dem = abs(F) / N
        if done:
            m2 = ROCK if st1 != _REST else REST
            return m2, s1, sig, (th1, om1, st[2], 0.0, 0.0, 0.0), ni, st1 == _OVERTURNED, tev, dem
    du = (u1 - u0) / dt
    dg = (gf1 - gf0) / dt
    mode, s, sig, st, ni, tev = _general(mode, s, sig, st, 0.0, u0, du, gf0, dg, dt, body, c)
    overturned = tev >= 0.0
    if mode == REST:
        dem = max(dem, abs(u1) / gf1)
    elif mode == ROCK and not overturned:
        F, N = _rock_forces(st[0], st[1], s, u1, gf1, body, c)
        if N > 0.0:
            dem = max(dem, abs(F) / N)
    return mode, s, sig, st, ni, overturned, tev, dem


@kernel(inline="always")
def _sample_summaries(mode, st, overturned, peak, peak_slip, peak_lift, uplift, body, c):
    """:func:`modes_case`'s running summaries after a sample reached in ``mode`` at the state
    tuple ``st`` (or overturning): (max abs(θ) [rad], max abs(slip) [m], max lift [m], uplift,
    slip [m], lift [m])."""
    slip, lift = _slip_lift(mode, st, body, c)
    peak_slip = max(peak_slip, abs(slip))
    peak_lift = max(peak_lift, lift)
    if overturned:
        return body.th_ov, peak_slip, peak_lift, True, slip, lift
    th = st[0]
    return max(peak, abs(th)), peak_slip, peak_lift, uplift or th != 0.0 or lift > 0.0, slip, lift


@kernel
def modes_case(u, gv, dt, body, c, located, theta0, omega0, out):
    """One body (``body``: :class:`~rocking.dynamics.impacts.Body`, ``c``: :class:`Contact`) under
    one motion, every response mode: ``u`` = a_g/g [-] and ``gv`` = 1 + a_v/g [-] (None: no
    vertical motion; it may be ≤ 0 here, flight) at samples dt [s] apart; ``located``: the impact
    scheme of the rocking steps (:func:`rocking.dynamics.impacts.resolve_impacts`); θ0 [rad], θ'0
    [rad/s] the initial state (rest when both are 0).

    ``out``: None, or an array (5, n) that receives θ [rad], θ' [rad/s], slip [m], lift [m] and
    the mode (index into :data:`MODES`) at every sample (NaN after overturning, the mode there
    kept).  Returns the summaries (overturned, t_overturn [s] or NaN, n_impacts, max abs(θ) [rad]
    (the overturning angle if overturned), uplift (the body rocked or lifted at a sample, or
    overturned), max abs(slip) [m] and max lift [m] (at the samples and at overturning, so that
    the peak slip bounds the residual), residual slip [m] (at the end, or at overturning),
    friction demand [-] (the largest abs(F)/N at the samples where the base sticks)).
    """
    n = u.shape[0]
    th = theta0
    om = omega0
    s, state0 = _initial(theta0, omega0)
    mode = ROCK if state0 == _ROCKING else REST
    sig = 0.0
    st = (th, om, 0.0, 0.0, 0.0, 0.0)
    overturned = abs(th) >= body.th_ov
    t_ov = 0.0 if overturned else math.nan
    peak = body.th_ov if overturned else abs(th)
    n_imp = 0
    uplift = overturned
    peak_slip = 0.0
    peak_lift = 0.0
    demand = 0.0
    slip = 0.0
    if out is not None:
        out[0, 0] = th
        out[1, 0] = om
        out[2, 0] = 0.0
        out[3, 0] = 0.0
        out[4, 0] = mode
    for k in range(n - 1):
        if overturned:
            if out is not None:
                for r in range(4):
                    out[r, k + 1] = math.nan
                out[4, k + 1] = mode
            continue
        g0 = None if gv is None else gv[k]
        g1 = None if gv is None else gv[k + 1]
        mode, s, sig, st, ni, overturned, tev, dem = _modes_interval(
            mode, s, sig, st, u[k], u[k + 1], g0, g1, dt, body, c, located
        )
        n_imp += ni
        demand = max(demand, dem)
        peak, peak_slip, peak_lift, uplift, slip, lift = _sample_summaries(
            mode, st, overturned, peak, peak_slip, peak_lift, uplift, body, c
        )
        if overturned:
            t_ov = k * dt + tev
            if out is not None:
                for r in range(4):
                    out[r, k + 1] = math.nan
                out[4, k + 1] = mode
            continue
        if out is not None:
            out[0, k + 1] = st[0]
            out[1, k + 1] = st[1]
            out[2, k + 1] = slip
            out[3, k + 1] = lift
            out[4, k + 1] = mode
    return overturned, t_ov, n_imp, peak, uplift, peak_slip, slip, peak_lift, demand
