"""Every response mode of a free-standing block (issue 45): rocking.simulate with friction, each
check against an independent reference (closed forms, Shenton's criteria, SciPy's solve_ivp, the
rocking-only kernel)."""

from __future__ import annotations

import itertools
import math

import numpy as np
import pytest
from scipy.integrate import solve_ivp

import rocking
from rocking import Block, InputError, Physics, simulate
from rocking.defaults import G
from rocking.dynamics.impacts import Body
from rocking.dynamics.modes import (
    _LOCATE_TOL,
    _NONE,
    Contact,
    _event,
    _locate,
    _rk4,
    _rock_forces,
    _slide_rock,
    _strike,
    modes_case,
)

DT = 1.0 / 400.0
REST, SLIDE, ROCK, SLIDE_ROCK, FLIGHT = range(5)


def newmark_slip(A: float, t_d: float, mu: float, g: float = G) -> float:
    """Newmark (1965)'s rigid sliding block under a rectangular pulse A [m/s²] lasting t_d [s]:
    the residual slip A·(A − μg)·t_d²/(2μg) [m] (the pulse drives it to (A − μg)·t_d, friction
    μg stops it)."""
    return A * (A - mu * g) * t_d**2 / (2.0 * mu * g)


def test_modes_are_public_and_named_as_the_issue():
    assert rocking.MODES == ("rest", "slide", "rock", "slide-rock", "flight")


@pytest.mark.parametrize("g_eff", [1.0, 0.7])
def test_newmark_rectangular_pulse(g_eff):
    # Reference: Newmark's closed form (the issue's example: A = 0.5 g, t_d = 0.5 s, μ = 0.2
    # gives 0.919 m), with g + a_v for a constant vertical acceleration (g_eff = 0.7: a_v =
    # −0.3 g).  A square block (B/H = 1 > μ) slides and never rocks.  The sampled pulse is A up
    # to t_d and falls to 0 linearly over the next sample interval, so its slip lies between
    # the closed form at t_d and at t_d + dt (the bracket is the tolerance; the slide is
    # integrated exactly, a_g being linear between samples).
    A, t_d, mu, dt = 0.5 * G, 0.5, 0.2, 1.0 / 4000.0
    if g_eff == 1.0:
        assert newmark_slip(A, t_d, mu) == pytest.approx(0.919, abs=5e-4)
    t = np.arange(0.0, 3.0, dt)
    ag = np.where(t <= t_d + 1e-12, A, 0.0)
    av = None if g_eff == 1.0 else np.full(t.size, (g_eff - 1.0) * G)
    r = simulate(Block.from_dimensions(H=1.0, B=1.0), ag, dt, mu=mu, av=av)
    lo = newmark_slip(A, t_d, mu, g_eff * G)
    hi = newmark_slip(A, t_d + dt, mu, g_eff * G)
    assert lo < -r.residual_slip < hi  # a positive a_g slides the block to −x
    assert r.max_abs_slip == pytest.approx(-r.residual_slip, rel=1e-12)
    assert set(np.unique(r.mode)) == {REST, SLIDE}
    assert r.mode[-1] == REST and r.max_abs_theta == 0.0 and r.max_lift == 0.0
    assert not r.uplift


def _sliding_reference(t_s, ag_s, mu_s, mu_k, g=G):
    """Slip [m] at the samples t_s of a rigid block on a base with friction (μ_s, μ_k) under
    a_g linear between the samples ag_s [m/s²], by solve_ivp with events: at rest while
    abs(a_g) ≤ μ_s·g, sliding with x'' = −a_g − sign(x')·μ_k·g, stick at x' = 0 if the friction
    can hold it.  Written here, independently of the kernel."""

    def ag(t):
        return np.interp(t, t_s, ag_s)

    x = np.zeros(t_s.size)
    t0, x0 = 0.0, 0.0
    end = t_s[-1]
    while t0 < end:
        # at rest from t0 to the first sample interval where abs(a_g) > μ_s·g (then the exact
        # crossing, a_g being linear between samples)
        k = np.searchsorted(t_s, t0, side="right")
        above = np.nonzero(np.abs(ag_s[k:]) > mu_s * g)[0]
        x[t_s >= t0] = x0
        if above.size == 0:
            break
        j = k + above[0]
        a0, a1 = ag_s[j - 1], ag_s[j]
        thr = math.copysign(mu_s * g, a1)
        t_start = max(t0, t_s[j - 1] + (thr - a0) / (a1 - a0) * (t_s[j] - t_s[j - 1]))
        sign = -math.copysign(1.0, a1)  # the slip's direction

        def rhs(t, y, sign=sign):
            return [y[1], -ag(t) - sign * mu_k * g]

        def stick(t, y, sign=sign, t_start=t_start):
            return y[1] if t > t_start else sign

        stick.terminal = True  # type: ignore[attr-defined]
        sol = solve_ivp(
            rhs,
            (t_start, end),
            [x0, 0.0],
            events=stick,
            dense_output=True,
            rtol=1e-12,
            atol=1e-14,
            max_step=(t_s[1] - t_s[0]) / 4.0,
        )
        t1 = sol.t[-1]
        inside = (t_s >= t_start) & (t_s <= t1)
        x[inside] = sol.sol(t_s[inside])[0]
        t0, x0 = t1, float(sol.y[0, -1])
        x[t_s > t1] = x0
        if abs(ag(t1)) > mu_s * g:  # it cannot stick: slides on, reversed
            raise AssertionError("reference: reversal not needed for these pulses")
    return x


def test_half_sine_pulse_against_solve_ivp():
    # Reference: the sliding equation integrated by solve_ivp (rtol 1e-12) with the same input
    # (a_g linear between samples), events at stick.  Tolerance 1e-8 m: the kernel integrates
    # the slide exactly (RK4 of a cubic) and locates start (exactly) and stick (to 1e-13·dt),
    # so what is left is solve_ivp's error.
    t = np.arange(0.0, 2.0, DT)
    A, t_d = 0.6 * G, 0.4
    ag = np.where(t < t_d, A * np.sin(np.pi * t / t_d), 0.0)
    r = simulate(Block.from_dimensions(H=1.0, B=1.0), ag, DT, mu=0.3, mu_k=0.25)
    ref = _sliding_reference(t, ag, 0.3, 0.25)
    assert abs(ref[-1]) > 0.05  # it slides, by centimetres
    np.testing.assert_allclose(r.slip, ref, rtol=0, atol=1e-8)
    assert r.residual_slip == pytest.approx(ref[-1], abs=1e-8)


def mu_cr(a: float, beta: float) -> float:
    """The friction that rocking from rest needs at onset, for a uniform rectangle under a
    sustained a_g = a·g (the issue's formula; Shenton 1996)."""
    return (a * (1 + 4 * beta**2) + 3 * beta) / (4 + beta**2 + 3 * a * beta)


def shenton(a: float, mu: float, beta: float) -> int:
    """Shenton (1996)'s onset classification from rest (MODES.md)."""
    if a <= min(mu, beta):
        return REST
    if mu < beta:
        return SLIDE
    return ROCK if mu >= mu_cr(a, beta) else SLIDE_ROCK


def test_onset_follows_shenton_on_a_grid():
    # Reference: Shenton, H.W. (1996), J. Eng. Mech. 122(7):690-693 (MODES.md).  A sustained
    # a_g = −a·g from rest; the mode at the first sample after the start (1 ms later: too
    # early for a rock to become a slide-rock, so points within 0.02 of the μ_cr boundary or
    # 1e-3 of a threshold are left out) is the classification, exactly.
    seen = set()
    for beta in (0.2, 0.35, 0.6):
        for mu in (0.1, 0.25, 0.4, 0.7, 1.0):
            for a in (0.15, 0.3, 0.5, 0.8, 1.0, 1.5):
                if min(abs(a - mu), abs(a - beta)) < 1e-3 or abs(mu - mu_cr(a, beta)) < 0.02:
                    continue
                block = Block.from_dimensions(H=1.0, B=beta)
                r = simulate(block, np.full(4, -a * G), 1e-3, mu=mu)
                want = shenton(a, mu, beta)
                assert r.mode[1] == want, (a, mu, beta)
                seen.add(want)
    assert seen == {REST, SLIDE, ROCK, SLIDE_ROCK}
    # the issue's cabinet: B/H = 0.25 and μ = 0.35 slide-rocks at 1 g
    r = simulate(Block.from_dimensions(H=1.0, B=0.25), np.full(4, -G), 1e-3, mu=0.35)
    assert r.mode[1] == SLIDE_ROCK


def _noise(seed: int, n: int, peak: float) -> np.ndarray:
    w = np.random.default_rng(seed).standard_normal(n)
    f = np.convolve(w, np.hanning(60), mode="same")
    return f * (peak * G / np.abs(f).max())


CASES = [
    (Block.from_dimensions(H=2.0, B=0.5), 0, 0.35, None, 0.925),
    (Block.from_dimensions(H=10.0, B=2.0), 1, 0.4, 0.3, "housner"),
    (Block.from_mass_properties(1.0, 0.3, radius_of_gyration=0.5), 2, 0.4, None, 0.9),
]


@pytest.mark.parametrize(("block", "seed", "peak", "vertical", "e"), CASES)
def test_infinite_friction_is_todays_rocking_bit_for_bit(block, seed, peak, vertical, e):
    # Reference: today's rocking kernel (mu=None).  With μ = 1e6 the contact never slips while
    # rocking and every impact stays in the friction cone, so the modes kernel takes the
    # rocking kernel's own steps: the same bits.  (A block falling over may not: close to
    # overturning N → 0, and the rocking model then asks the ground to pull; these cases do not
    # overturn.)
    ag = _noise(seed, 6000, peak)
    av = None if vertical is None else _noise(seed + 10, 6000, vertical)
    r0 = simulate(block, ag, DT, av=av, e=e)
    r1 = simulate(block, ag, DT, av=av, e=e, mu=1e6)
    assert not r0.overturned and r0.n_impacts > 5 and r0.max_abs_theta > 0.01
    assert np.array_equal(r0.theta, r1.theta) and np.array_equal(r0.omega, r1.omega)
    assert (r0.n_impacts, r0.max_abs_theta) == (r1.n_impacts, r1.max_abs_theta)
    assert not r1.slip.any() and not r1.lift.any()
    np.testing.assert_array_equal(r0.mode, r1.mode)
    assert set(np.unique(r1.mode)) == {REST, ROCK}


@pytest.mark.parametrize("mu", [0.15, 0.3])
def test_mirror_symmetry(mu):
    # Reference: the mirror image of the motion gives the mirror image of the response (the
    # model has no preferred side); the kernel's arithmetic is symmetric up to round-off.
    block = Block.from_dimensions(H=1.5, B=0.45)
    ag = _noise(5, 3000, 0.6)
    r = simulate(block, ag, DT, mu=mu)
    m = simulate(block, -ag, DT, mu=mu)
    assert r.max_abs_slip > 1e-3 and set(np.unique(r.mode)) - {REST, ROCK}
    np.testing.assert_allclose(m.theta, -r.theta, rtol=0, atol=1e-12)
    np.testing.assert_allclose(m.slip, -r.slip, rtol=0, atol=1e-12)
    np.testing.assert_array_equal(m.mode, r.mode)


def test_contact_equations_against_newton_euler_solved_numerically():
    # Reference: Newton-Euler for the body on one corner written here in another form (the
    # centre of mass as the corner plus the rotated vector (−s·b, h), the unknowns solved as a
    # 3x3 linear system by NumPy): stick (θ'', F, N) and slip with F = −σ·μ·N (θ'', the
    # corner's x'', N), against the closed forms of rocking.dynamics.modes, at random states.
    # Tolerance 1e-12 relative: round-off of either.
    rng = np.random.default_rng(0)
    block = Block.from_mass_properties(0.8, 0.3, radius_of_gyration=0.4)
    a, rg2, b, h = block.alpha, block.radius_of_gyration**2, block.b, block.h_cg
    body = Body(block.p_squared(), math.sin(a), math.cos(a), math.tan(a), 0.9, math.pi / 2)
    for _ in range(100):
        mu = float(rng.uniform(0.1, 0.8))
        c = Contact.of(block, 0.9, mu, None, G)
        th, om, u = float(rng.uniform(-1, 1)), float(rng.normal()), float(rng.normal())
        gv, sig = 1 + 0.3 * float(rng.normal()), float(rng.choice([-1.0, 1.0]))
        s = 1.0 if th > 0 else -1.0
        dx = -s * b * math.cos(th) + h * math.sin(th)  # centre of mass from the corner
        dy = s * b * math.sin(th) + h * math.cos(th)
        # X'' = x_c'' + θ''·dy − θ'²·dx = F − a_g;  Y'' = −θ''·dx − θ'²·dy = N − G;
        # −r_g²·θ'' = −dx·N + dy·F (moment about the centre of mass, counter-clockwise)
        rhs = [om**2 * dx - G * u, om**2 * dy - G * gv, 0.0]
        slip = np.linalg.solve(
            [[1, dy, sig * mu], [0, -dx, -1], [0, -rg2, dx + dy * sig * mu]], rhs
        )
        stick = np.linalg.solve([[dy, -1, 0], [-dx, 0, -1], [-rg2, -dy, dx]], rhs)
        acc, qdd, N = _slide_rock(th, om, s, sig, u, gv, body, c)
        np.testing.assert_allclose([qdd, acc, N], slip, rtol=1e-12, atol=1e-12)
        F, N = _rock_forces(th, om, s, u, gv, body, c)
        np.testing.assert_allclose([F, N], stick[1:], rtol=1e-12, atol=1e-12)


def test_energy_never_increases_in_free_response():
    # Reference: with e ≤ 1 neither the impacts (capped at e² of the kinetic energy) nor
    # Coulomb friction add energy.  The motion stops at 2 s; from then on the total mechanical
    # energy in the ground frame, ½·I_0·θ'² + g·(height of the centre of mass), at the samples
    # where the block rests or rocks (where θ' gives the whole kinetic energy) never grows by
    # more than the Runge–Kutta step's error (1e-9 relative).
    block = Block.from_dimensions(H=1.5, B=0.45)
    ag = _noise(7, 2400, 0.7)
    ag[800:] = 0.0
    for e in (0.925, 1.0):
        r = simulate(block, ag, DT, mu=0.3, e=e)
        assert not r.overturned and set(np.unique(r.mode[:800])) - {REST, ROCK}
        R, a = block.R, block.alpha
        i0 = block.radius_of_gyration**2 + R**2
        s = np.where(r.theta >= 0.0, 1.0, -1.0)
        energy = 0.5 * i0 * r.omega**2 + G * (R * np.cos(s * a - r.theta) - R * np.cos(a))
        free = np.nonzero((np.arange(ag.size) >= 800) & np.isin(r.mode, (REST, ROCK)))[0]
        assert free.size > 100
        E = energy[free]
        assert np.all(np.diff(E) <= 1e-9 * E[0])


def test_energy_never_increases_across_an_impact():
    # Reference: the kinetic energy after the impact law (stick or sliding impact, rules 1-2 of
    # rocking.dynamics.modes), computed here from the state it returns, is at most the energy
    # before, for random states before the impact and friction coefficients.
    rng = np.random.default_rng(3)
    modes = set()
    block = Block.from_dimensions(H=1.2, B=0.5)
    R, a, rg2 = block.R, block.alpha, block.radius_of_gyration**2
    body = Body(block.p_squared(), math.sin(a), math.cos(a), math.tan(a), 0.9, math.pi / 2)
    n_cases = 0
    for _ in range(600):
        mu = float(rng.uniform(0.05, 1.0))
        c = Contact(G, R, rg2, mu, mu * float(rng.uniform(0.3, 1.0)), 0.9 / block.housner_e(), True)
        th = float(rng.uniform(-0.3, 0.3))
        sc = 1.0 if th > 0 else -1.0
        om, vx, vy = rng.normal(size=3)
        S, C = math.sin(sc * a - th), math.cos(sc * a - th)
        if vy - om * R * S >= 0.0:  # the corner moves up: no impact
            continue
        mode, om2, v2, _sig = _strike(th, sc, om, vx, vy, False, False, body, c)
        before = 0.5 * (vx**2 + vy**2 + rg2 * om**2)
        n_cases += 1
        after = 0.5 * ((v2 + R * C * om2) ** 2 + (R * S * om2) ** 2 + rg2 * om2**2)
        assert after <= before * (1 + 1e-12), (mode, th, om, vx, vy, mu)
        modes.add(mode)
    assert n_cases > 200 and {ROCK, SLIDE_ROCK} <= modes


@pytest.mark.parametrize("c", [1.0, -1.0])
def test_sliding_impact_from_rock_slips_against_friction(c):
    # Hand check of rule 2 for an impact from pure rocking (the new corner c at rest before,
    # θ = 0): uniform block b = 0.15 m, h = 0.6 m, r_g² = i = (b² + h²)/3, rocking about corner
    # −c at θ' = ω (c·ω > 0), so V = (h·ω, −c·b·ω) and the new corner moves at (0, −2·c·b·ω).
    # e = 0.5 asks abs(P_x)/P_y = (1 − e)/((1 + e)·tan α) = 1.33 > μ_s = 0.5: no stick impact.
    # The corner slips where a frictionless impulse drives it (side c, Routh), so
    # P_x = −c·μ_k·P_y; the plastic normal impulse P_y = 2·c·b·ω/(1 + b·(b − μ_k·h)/i);
    # θ'⁺ = ω + c·P_y·(μ_k·h − b)/i and the corner's slip velocity
    # c·P_y·(b·h/i − μ_k·(1 + h²/i)), which keeps the side c while μ_k < b·h/(i + h²) = 0.185.
    # Beyond, the slip stops during the impact: the corner sticks, plastic, θ'⁺ = e_H·ω; so
    # too where 1 + b·(b − μ_k·h)/i ≤ 0 (μ_k ≥ 1.67): the Coulomb impulse would need P_y < 0, a
    # jam (e = 0.1 then asks 3.3 > μ_s = 1.8 of a stick impact).  (Before the fix the corner
    # at rest got no friction at all.)  1e-12: rounding.
    block = Block.from_dimensions(H=1.2, B=0.3)
    b, h, i = 0.15, 0.6, (0.15**2 + 0.6**2) / 3.0
    a = block.alpha
    om = c * 1.3
    for e, mu_s, mu_k in ((0.5, 0.5, 0.1), (0.5, 0.5, 0.19), (0.1, 1.8, 1.8)):
        assert (1.0 - e) / ((1.0 + e) * math.tan(a)) > mu_s  # no stick impact
        body = Body(block.p_squared(), math.sin(a), math.cos(a), math.tan(a), e, math.pi / 2)
        con = Contact(G, block.R, i, mu_s, mu_k, e / block.housner_e(), False)
        mode, om2, v, sig = _strike(0.0, c, om, h * om, -c * b * om, True, True, body, con)
        if mu_k < b * h / (i + h * h):
            p_y = 2.0 * c * b * om / (1.0 + b * (b - mu_k * h) / i)
            assert mode == SLIDE_ROCK and sig == c
            assert om2 == pytest.approx(om + c * p_y * (mu_k * h - b) / i, rel=1e-12)
            slip_v = c * p_y * (b * h / i - mu_k * (1.0 + h * h / i))
            assert v == pytest.approx(slip_v, rel=1e-12) and c * v > 0.0
        else:
            assert mode == ROCK and v == 0.0
            assert om2 == pytest.approx(block.housner_e() * om, rel=1e-12)


def test_sliding_impact_that_turns_into_the_ground_lands_flat():
    # Hand check of rule 2 then 3: a squat uniform block (b = 1 m, h = 0.5 m, i = r_g² =
    # (b² + h²)/3; e_H < 0, so no stick impact: it would stop the centre of mass, which needs
    # abs(P_x)/P_y = 1.5 > μ_s) slide-rocks on its −x corner at θ' = ω = 1 rad/s, the corner
    # slipping at v0 = −2 m/s; the +x corner strikes at θ = 0.  Coulomb impulse against the
    # slip (σ = −1): P_y = 2·b·ω/(1 + b·(b + μ_k·h)/i), P_x = μ_k·P_y, after which
    # θ'⁺ = ω − P_y·(b + μ_k·h)/i < 0 would turn the body into the ground about the +x corner:
    # the −x corner strikes too, a flat impact on the centre of mass's velocity after the
    # first, V = (v0 + h·ω + P_x, −b·ω + P_y): plastic P_y2 = −V_y, and since
    # abs(V_x) > μ_s·P_y2 it slides at V_x + μ_k·P_y2.  (Before the fix the slide went on at
    # the first impact's corner velocity, a horizontal change of the centre of mass's velocity
    # by h·θ'⁺ that no impulse within the friction cone makes.)  1e-12: rounding.
    with pytest.warns(UserWarning, match="squat"):
        block = Block.from_dimensions(H=1.0, B=2.0)
    b, h, i = 1.0, 0.5, (1.0 + 0.25) / 3.0
    a = block.alpha
    assert block.housner_e() < 0.0
    body = Body(block.p_squared(), math.sin(a), math.cos(a), math.tan(a), 0.9, math.pi / 2)
    mu_s, mu_k, om, v0 = 0.5, 0.4, 1.0, -2.0
    con = Contact(G, block.R, i, mu_s, mu_k, 0.0, False)
    mode, om2, v, sig = _strike(0.0, 1.0, om, v0 + h * om, -b * om, True, False, body, con)
    p_y = 2.0 * b * om / (1.0 + b * (b + mu_k * h) / i)
    assert om - p_y * (b + mu_k * h) / i < 0.0  # it turns into the ground
    vx, vy = v0 + h * om + mu_k * p_y, -b * om + p_y
    assert vy < 0.0 and abs(vx) > mu_s * -vy  # the flat impact slips
    assert mode == SLIDE and om2 == 0.0 and sig == -1.0
    assert v == pytest.approx(vx + mu_k * -vy, rel=1e-12)


def test_stick_impact_that_turns_into_the_ground_lands_flat():
    # Hand check of rule 1 then 3: a uniform block (b = 0.15 m, h = 0.6 m, i = r_g² =
    # (b² + h²)/3, I_0/m = i + b² + h²) slide-rocks on its −x corner at θ' = ω = 1 rad/s, the
    # corner slipping at v0 = −1 m/s (V = (v0 + h·ω, −b·ω)); the +x corner strikes at θ = 0.
    # e = 0.8·e_H: θ'⁺ = 0.8·ω_L, ω_L = (ω·(i − b² + h²) + h·v0)/I_0 < 0, a rotation back into
    # the ground; its impulse V⁺ − V, V⁺ = (h·θ'⁺, b·θ'⁺), asks abs(P_x)/P_y = 2.31 ≤ μ_s = 2.4:
    # a stick impact, after which the −x corner strikes too,
    # a flat impact on V⁺: P_y2 = −b·θ'⁺, and abs(h·θ'⁺) > μ_s·P_y2, so it slides at
    # h·θ'⁺ + μ_k·P_y2.  (Before the fix the stick impact was asked to stop the body at once,
    # abs(P_x)/P_y = 2.67 > μ_s, and went on as a sliding impact that stuck, plastic, at ω_L.)
    # 1e-12: rounding.
    block = Block.from_dimensions(H=1.2, B=0.3)
    b, h, i = 0.15, 0.6, (0.15**2 + 0.6**2) / 3.0
    a, e_h = block.alpha, block.housner_e()
    body = Body(block.p_squared(), math.sin(a), math.cos(a), math.tan(a), 0.8 * e_h, math.pi / 2)
    mu, om, v0 = 2.4, 1.0, -1.0
    con = Contact(G, block.R, i, mu, mu, 0.8, False)
    mode, om2, v, sig = _strike(0.0, 1.0, om, v0 + h * om, -b * om, True, False, body, con)
    w = 0.8 * (om * (i - b * b + h * h) + h * v0) / (i + b * b + h * h)
    assert w < 0.0
    assert abs(h * w - v0 - h * om) / (b * w + b * om) == pytest.approx(2.309, abs=1e-3)
    assert mode == SLIDE and om2 == 0.0 and sig == -1.0
    assert v == pytest.approx(h * w + mu * -b * w, rel=1e-12)


def test_flight_under_a_falling_ground_is_ballistic():
    # Reference: from rest under a constant a_v < −g and no a_g both corners leave together and
    # the block moves freely: lift(t) = ½·(−g − a_v)·t² relative to the ground, θ = 0, no slip
    # (exact: the flight's equations are polynomial in t, which RK4 integrates exactly).
    t = np.arange(0.0, 0.3, DT)
    av = np.full(t.size, -1.5 * G)
    r = simulate(Block.from_dimensions(H=1.0, B=0.3), np.zeros(t.size), DT, mu=0.5, av=av)
    np.testing.assert_allclose(r.lift, 0.5 * 0.5 * G * t**2, rtol=1e-12, atol=1e-15)
    assert np.all(r.mode[1:] == FLIGHT) and not r.theta.any() and not r.slip.any()
    assert r.max_lift == pytest.approx(0.25 * G * t[-1] ** 2, rel=1e-12)
    # the ground stops falling at 0.1 s: the block lands flat (plastic, nothing slides) and rests.
    # Reference: the lift integrated exactly in the test (a_v linear between samples: per
    # interval y += v·h + h²·(2a₀ + a₁)/6, v += h·(a₀ + a₁)/2 with a = −g − a_v).
    av[t >= 0.1] = 0.0
    r = simulate(Block.from_dimensions(H=1.0, B=0.3), np.zeros(t.size), DT, mu=0.5, av=av)
    acc = -G - av
    y, v, ref = 0.0, 0.0, [0.0]
    for a0, a1 in itertools.pairwise(acc):
        y, v = y + v * DT + DT**2 * (2 * a0 + a1) / 6, v + DT * (a0 + a1) / 2
        ref.append(y)
    landed = int(np.argmax(np.array(ref[1:]) < 0.0)) + 1
    assert 40 < landed < t.size - 10
    np.testing.assert_allclose(r.lift[:landed], ref[:landed], rtol=1e-12, atol=1e-15)
    assert not r.lift[landed:].any() and np.all(r.mode[landed:] == REST)
    assert np.all(r.mode[1:landed] == FLIGHT) and not r.slip.any() and not r.theta.any()
    # rocking-only refuses it, and says what to give instead
    with pytest.raises(InputError, match=r"av.*\bmu\b"):
        simulate(Block.from_dimensions(H=1.0, B=0.3), np.zeros(t.size), DT, av=av)


def test_one_case_entry_point_gives_the_summaries_of_simulate():
    # Reference: rocking.simulate's response of the same case (the entry point for batched
    # loops runs the same kernel without the time history: the same numbers).
    block = Block.from_dimensions(H=1.5, B=0.45)
    ag = _noise(11, 3000, 0.7)
    av = _noise(12, 3000, 1.2)
    r = simulate(block, ag, DT, mu=0.3, av=av)
    body = Body(
        block.p_squared(),
        math.sin(block.alpha),
        math.cos(block.alpha),
        1 / block.gamma,
        0.925,
        math.pi / 2,
    )
    got = modes_case(
        ag / G, 1 + av / G, DT, body, Contact.of(block, 0.925, 0.3, None, G), True, 0.0, 0.0, None
    )
    overturned, t_ov, n_imp, peak, uplift, peak_slip, residual, peak_lift, demand = got
    assert r.max_lift > 0.0 and r.max_abs_slip > 0.0
    np.testing.assert_array_equal(t_ov, r.t_overturn)  # NaN equals NaN here
    assert (overturned, n_imp, peak, uplift) == (
        r.overturned,
        r.n_impacts,
        r.max_abs_theta,
        r.uplift,
    )
    assert (peak_slip, residual, peak_lift) == (r.max_abs_slip, r.residual_slip, r.max_lift)
    assert 0.0 < demand <= 0.3


def test_fourth_order_convergence_through_every_transition():
    # Reference: the exact solution, approached by refining the step (the same input: a_g and
    # a_v linear between the coarse samples).  Classical RK4 with every transition located
    # (to 1e-13·dt) converges as dt⁴: the difference between dt and dt/4 shrinks about 256-fold
    # between dt/4 and dt/16 (50-fold asserted: a located event costs a little order), through
    # rock, slide-rock and flight.
    rng = np.random.default_rng(2)
    w = rng.standard_normal(1200)
    ag = np.convolve(w, np.hanning(60), mode="same")
    ag *= 0.6 * G / np.abs(ag).max()
    av = 2.2 * ag[::-1]
    t = np.arange(ag.size) * DT
    block = Block.from_dimensions(H=2.0, B=0.5)
    runs = []
    for k in (1, 4, 16):
        tk = np.arange((ag.size - 1) * k + 1) * DT / k
        r = simulate(block, np.interp(tk, t, ag), DT / k, mu=0.4, av=np.interp(tk, t, av))
        runs.append(np.r_[r.theta[::k], r.slip[::k], r.lift[::k]])
    assert {ROCK, SLIDE_ROCK, FLIGHT} <= set(np.unique(r.mode))
    coarse = np.abs(runs[0] - runs[1]).max()
    fine = np.abs(runs[1] - runs[2]).max()
    assert 0.0 < fine < coarse / 50 and coarse < 1e-7


def test_friction_settings_are_checked_and_part_of_the_physics():
    assert Physics().mu is None and Physics().mu_k is None
    p = Physics(mu=0.4, mu_k=0.3)
    assert p.params()["mu"] == 0.4 and p.params()["mu_k"] == 0.3
    assert p.fingerprint != Physics(mu=0.4).fingerprint != Physics().fingerprint
    for kw, words in (
        ({"mu_k": 0.3}, "mu_k needs mu"),
        ({"mu": 0.3, "mu_k": 0.4}, "mu_k = 0.4 exceeds mu"),
        ({"mu": 0.0}, "mu must be"),
        ({"mu": math.inf}, "mu must be"),
        ({"mu": 0.5, "mu_k": -1.0}, "mu_k must be"),
    ):
        with pytest.raises(InputError, match=words):
            Physics(**kw)
    block = Block.from_dimensions(H=1.0, B=0.3)
    # mu=None is "not given": the physics' field decides
    r = simulate(block, np.full(50, 0.5 * G), DT, physics=Physics(mu=0.2))
    assert r.mu == 0.2 and r.max_abs_slip > 0.0
    summary = r.summary()
    assert (summary["mu"], summary["mu_k"]) == (0.2, 0.2)
    assert summary["residual_slip_m"] == r.residual_slip < 0.0  # a_g > 0 slides it to −x
    # without friction the summary is today's (the command line's JSON unchanged)
    assert "mu" not in simulate(block, np.full(50, 0.5 * G), DT).summary()


def test_slip_velocity_that_reaches_zero_inside_a_step_stops_there():
    # A square block (B/H = 1 > μ = 0.2: it only slides) at the package's dt.  The ground
    # pushes it to +x over the first interval (a_g from 0 to −10 m/s²), brakes it over the
    # second (to +11.9 m/s²), leaving q' = 0.81 mm/s at t = 2·dt; over the third a_g falls from
    # +11.9 to −40 m/s², so with the slip kept in +x, q'' = −a_g − μg goes from −13.9 to
    # +38.0 m/s²: q' would dip to −3.8 mm/s near t = 2.27·dt and end at +31.0 mm/s, positive at
    # both ends of the step.  Newmark's block stops at t = 2.024·dt instead (q' = 0 with
    # a_g = 10.6 m/s² > μg: the slip reverses), stops again at 2.359·dt and slides to +x.
    # Before the kernel looked inside the step it missed both (slip 6.6e-6 m low at 3·dt,
    # 1.4e-4 m low at the end).  Reference: the SciPy solver at its default tolerances, which
    # takes one step per interval here (q' is a polynomial in t) and finds the dip as a minimum
    # of σ·q' inside the step (before it watched for that: no stop at all), then locates the
    # zeros of q' with an event function.  In slide q' is quadratic in t on each interval,
    # which RK4 integrates exactly, so the two agree to rounding and the event location
    # (1e-13·dt): tolerance 1e-12 m.
    from rocking.dynamics.reference import simulate_reference

    ag = np.zeros(20)
    ag[1:4] = (-10.0, 11.9, -40.0)
    block = Block(1.0, 1.0)
    fast = simulate(block, ag, DT, mu=0.2)
    ref = simulate_reference(block, ag, DT, mu=0.2)
    stops = [t / DT for t, what, _, _ in ref.events if what == "stick -> rest"]
    assert stops[:2] == pytest.approx([2.024, 2.359], abs=1e-3)
    np.testing.assert_array_equal(fast.mode, ref.mode)
    np.testing.assert_allclose(fast.slip, ref.slip, rtol=0, atol=1e-12)
    assert fast.residual_slip == pytest.approx(ref.residual_slip, abs=1e-12)


def test_slip_velocity_of_slide_rock_that_reaches_zero_inside_a_step_stops_there():
    # A block of B/H = 1/2.77 (tan α = 0.36 < μ = 0.42: it rocks, and slide-rocks where the
    # friction it needs exceeds the cone) under 0.72 g at 2.7 Hz plus 1.27 g at 83 Hz (4.8
    # samples a period at the package's dt), for 1 s: the corner's slip velocity reaches 0
    # inside many steps.  Reference: the SciPy solver at its default tolerances, which watches
    # for a minimum of σ·(slip velocity) inside each step (before it did, it missed the same
    # zeros unless its steps were capped at dt/32).  Measured: the slip at the samples within
    # 5e-10 m of it (RK4's error); before the kernel looked inside the step, 3.1e-5 m off.
    # Tolerance 1e-7 m.
    from rocking.dynamics.reference import simulate_reference

    t = np.arange(400) * DT
    ag = G * (0.72 * np.sin(2 * np.pi * 2.7 * t) + 1.27 * np.sin(2 * np.pi * 83.0 * t + 0.32))
    block = Block(1.0, 2.77)
    fast = simulate(block, ag, DT, mu=0.42)
    ref = simulate_reference(block, ag, DT, mu=0.42)
    assert any(what == "stick -> rock" for _, what, _, _ in ref.events)
    np.testing.assert_array_equal(fast.mode, ref.mode)
    np.testing.assert_allclose(fast.slip, ref.slip, rtol=0, atol=1e-7)


def _painleve_motion(which: str):
    """A body whose mass sits near its centre (h = 1 m, b = 0.5 m, r_g = 0.2 m: Painlevé's
    f(α) = (r_g² + b²)/(b·h) = 0.58 < μ = 0.7) and a motion that drives it into Painlevé's
    region (the module docstring of rocking.dynamics.modes), at DT: (block, ag, av)."""
    t = np.arange(401) * DT
    fall = np.sin(np.pi * t / 0.3) * (t < 0.3)
    if which == "lift":  # a_v down to −1.5 g: G < 0 while it rocks
        return (
            Block.from_mass_properties(1.0, 0.5, radius_of_gyration=0.2),
            -1.5 * G * fall,
            (-1.5 * G * fall),
        )
    push = np.sin(np.pi * (t - 0.08) / 0.14) * ((t > 0.08) & (t < 0.22))
    return (
        Block.from_mass_properties(1.0, 0.5, radius_of_gyration=0.2),
        -3 * G * push,
        -2 * G * fall,
    )


@pytest.mark.parametrize(
    ("which", "events"),
    [
        # it flies while the ground falls at 2 g, is pushed at up to 3 g meanwhile, lands flat
        # and slides (μ_k > tan α: it tips over its leading corner, which slips outward with
        # μ_k > f(α): no slide-rock exists) — the corner jams at once
        ("tip", ["onset -> flight", "flat landing -> rock"]),
        # it rocks while the ground falls at up to 1.5 g; its stuck corner needs more than μ_s·N
        # to the outward side, where a slip has no solution — it lifts off
        ("lift", ["onset -> rock", "slip -> flight", "landing (stick impact) -> rock"]),
    ],
)
def test_painleve_paradox_is_resolved_alike_by_kernel_and_reference(which, events):
    # Painlevé's inconsistent case of slide-rock (den = r_g² + R²·k·sin φ ≤ 0), reached by an
    # ordinary μ = 0.7.  Before it was resolved, the kernel went on with a negative den ("tip":
    # 149000 impacts, θ never off 0; "lift": the corner kept on the ground, slide-rocking, peak
    # θ 0.37 rad instead of 1.55) and the reference never ended ("tip") or stopped with
    # "contact undecided" ("lift").  Now both
    # apply the literature's resolution (an impact without collision that stops the slip, the
    # plastic jam; or lift-off where the corner's free vertical acceleration is upward),
    # written apart.  Checked: that the body goes through that transition (the reference's
    # events), that the jam dissipates energy, and that kernel and reference agree: the same
    # mode at every sample, the same impact count, θ and slip within 1e-8 (measured 3e-10 rad
    # and 1e-10 m at this dt: RK4's error and the event location; the agreement tests' 1e-5
    # would hide a wrong impulse of 1e-5 relative, this would not).
    from rocking.dynamics.reference import simulate_reference

    block, ag, av = _painleve_motion(which)
    fast = simulate(block, ag, DT, mu=0.7, e=0.9, av=av)
    assert fast.n_impacts == 1
    ref = simulate_reference(block, ag, DT, mu=0.7, e=0.9, av=av)
    assert [what for _, what, _, _ in ref.events][: len(events)] == events
    if which == "tip":
        _t, _what, before, after = ref.events[1]
        assert after < 0.1 * before  # the flat landing and the jam take most of the energy
    np.testing.assert_array_equal(fast.mode, ref.mode)
    assert fast.n_impacts == ref.n_impacts
    np.testing.assert_allclose(fast.theta, ref.theta, rtol=0, atol=1e-8)
    np.testing.assert_allclose(fast.slip, ref.slip, rtol=0, atol=1e-8)
    np.testing.assert_allclose(fast.lift, ref.lift, rtol=0, atol=1e-8)


@pytest.mark.parametrize(
    ("A", "V", "events"),
    [
        # a corner switch from rock after the landing: e·θ'⁻ (the reference stopped it)
        (3.0, 2.0, ["landing (stick impact) -> rock", "stick impact -> rock"]),
        # a landing on a corner after flight: plastic θ'_L (the kernel stopped it)
        (4.0, 1.5, ["landing (stick impact) -> rock", "slip -> slide-rock"]),
    ],
)
def test_squat_body_with_a_number_e_impacts_alike_in_kernel_and_reference(A, V, events):
    # A uniform block of B/H = 2 (e_H = 1 − 1.5·sin²α = −0.2 ≤ 0: Housner's law turns it back)
    # with e = 0.9 and μ = 3 (it rocks), under a_g = −A·g (half-sine, 0.4 s) and a_v down to
    # −V·g (0.1–0.4 s): it rocks, lifts off (flight), lands on a corner and rocks on.  The
    # convention (rocking.dynamics.modes, rule 1): e·θ'⁻ after rock, as today's rule without
    # friction, and the plastic θ'_L after flight or slip.  Before, the kernel used the factor
    # 0 on θ'_L (a landing stopped dead: θ 0.032 rad off at the samples for A = 4) and the
    # reference Housner's law after rock (rest after the second impact for A = 3: peak θ 0.39
    # against 0.22 rad).  Checked: the events, and kernel and reference alike: mode, impacts,
    # θ and slip within 1e-7 (measured 4e-9 rad, 9e-10 m: RK4's error at this dt).
    from rocking.dynamics.reference import simulate_reference

    t = np.arange(601) * DT
    ag = -A * G * np.sin(np.pi * t / 0.4) * (t < 0.4)
    av = -V * G * np.sin(np.pi * (t - 0.1) / 0.3) * ((t > 0.1) & (t < 0.4))
    block = Block(1.0, 0.5)
    assert block.housner_e() < 0.0
    fast = simulate(block, ag, DT, mu=3.0, e=0.9, av=av)
    ref = simulate_reference(block, ag, DT, mu=3.0, e=0.9, av=av)
    assert [what for _, what, _, _ in ref.events][2 : 2 + len(events)] == events
    np.testing.assert_array_equal(fast.mode, ref.mode)
    assert fast.n_impacts == ref.n_impacts
    np.testing.assert_allclose(fast.theta, ref.theta, rtol=0, atol=1e-7)
    np.testing.assert_allclose(fast.slip, ref.slip, rtol=0, atol=1e-7)


@pytest.mark.parametrize(
    ("v0", "g0", "dg", "t_true"),
    [
        # the slip velocity reaches 0 (stick): q' = v0 − g·(u + μ_k·gv)·t, RK4 exact in slide
        (0.01, 1.0, 0.0, 0.01 / (G * (0.1 + 0.3))),
        # the effective gravity reaches 0 (lift-off: gv = g0 + dg·t, linear) before any stick
        (1.0, 1.0, -1.0 / 0.0013, 0.0013),
        # at the very start: gv = 0 there (no event yet), < 0 right after
        (1.0, 0.0, -100.0, 0.0),
    ],
)
def test_an_event_is_located_to_the_tolerance_after_its_true_instant(v0, g0, dg, t_true):
    # Reference: the closed-form instants above (slide on a block with tan α > μ_k: u = 0.1,
    # μ_k = 0.3, σ = +1).  _locate's guarantee: the returned step length shows the event, one
    # _LOCATE_TOL·dt shorter does not (the predicate is monotonic here), so the located
    # instant lies within _LOCATE_TOL·dt after the true one (plus the rounding of t_true and
    # of the state, ~1e-18 s: tolerance 2·_LOCATE_TOL·dt on the far side, 1e-17 s before).
    dt = 0.005
    block = Block.from_mass_properties(0.8, 0.3, radius_of_gyration=0.4)
    a = block.alpha
    body = Body(block.p_squared(), math.sin(a), math.cos(a), math.tan(a), 0.9, math.pi / 2)
    c = Contact.of(block, 0.9, 0.3, None, G)
    st = (0.0, 0.0, 0.0, v0, 0.0, 0.0)
    u0, du = 0.1, 0.0
    end = _rk4(SLIDE, 1.0, 1.0, st, u0, du, g0, dg, 0.0, dt, body, c)[0]
    assert _event(SLIDE, 1.0, 1.0, end, u0, g0 + dg * dt, body, c) != _NONE
    hi, at = _locate(SLIDE, 1.0, 1.0, st, 0.0, dt, end, u0, du, g0, dg, dt, body, c)
    lo = hi - _LOCATE_TOL * dt
    before = _rk4(SLIDE, 1.0, 1.0, st, u0, du, g0, dg, 0.0, lo, body, c)[0]
    assert _event(SLIDE, 1.0, 1.0, at, u0, g0 + dg * hi, body, c) != _NONE
    assert lo <= 0.0 or _event(SLIDE, 1.0, 1.0, before, u0, g0 + dg * lo, body, c) == _NONE
    assert t_true - 1e-17 <= hi <= t_true + 2 * _LOCATE_TOL * dt
