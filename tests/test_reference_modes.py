"""The SciPy reference with friction (issue 45): every response mode against closed forms.

``simulate_reference(..., mu=...)`` integrates Newton–Euler in the centre of mass's coordinates
with the contact forces solved per mode; these tests hold it to values derived apart from it
(Newmark's sliding block, Shenton's onset criteria, ballistic flight, the frictionless
slide-rock's free centre of mass, today's pure rocking) and to the symmetries and the energy
law of the model.  The whole file runs in about 15 s on one core.
"""

import math
from collections import Counter

import numpy as np
import pytest

import rocking
from rocking.dynamics.reference import _Ground, _Modes, _Phase, _Rigid, simulate_reference
from rocking.errors import InputError

G = 9.80665
MODES = ("rest", "slide", "rock", "slide-rock", "flight")


def _mode_names(r, k):
    return MODES[r.mode[k]]


def _smooth_noise(rng, n, scale):
    """A smooth random acceleration history [m/s²]: white noise averaged over 8 samples."""
    return np.convolve(rng.standard_normal(n), np.ones(8) / 8, "same") * scale


def test_newmark_rigid_sliding_block_under_a_rectangular_pulse():
    # Newmark (1965), "Effects of earthquakes on dams and embankments", Géotechnique 15(2):
    # a rigid block on a plane with friction μ under a rectangular pulse A for t_d slides by
    # d = A·(A − μg)·t_d²/(2μg): 0.919 m for A = 0.5 g, t_d = 0.5 s, μ = 0.2.  B/H = 0.5 > μ,
    # so the block slides without tipping (μ_k·h < b).
    block = rocking.Block.from_dimensions(1.0, 0.5)
    a, mu, t_d, dt = 0.5 * G, 0.2, 0.5, 1e-3
    ag = np.zeros(1600)
    ag[: round(t_d / dt) + 1] = a  # ag > 0 drives the block to −x relative to the ground
    r = simulate_reference(block, ag, dt, mu=mu)
    newmark = a * (a - mu * G) * t_d**2 / (2 * mu * G)
    assert newmark == pytest.approx(0.9194, abs=1e-4)
    # The sampled pulse falls to 0 linearly over one more step: the same sliding equation
    # integrated by hand over the pulse, the ramp and the deceleration at μg gives the exact
    # slip of the motion the solver sees (rtol 1e-10 of the integrator: 1e-8 relative).
    v_d = (a - mu * G) * t_d
    v_1 = v_d + a * dt / 2 - mu * G * dt
    exact = (a - mu * G) * t_d**2 / 2 + v_d * dt + a * dt**2 / 3 - mu * G * dt**2 / 2
    exact += v_1**2 / (2 * mu * G)
    assert -r.residual_slip == pytest.approx(exact, rel=1e-8)
    assert r.max_abs_slip == pytest.approx(exact, rel=1e-8)
    # the ramp's extra impulse a·dt/2 moves Newmark's value by about dt/t_d (measured 0.2 %)
    assert -r.residual_slip == pytest.approx(newmark, rel=4e-3)
    t_stick = t_d + dt + v_1 / (mu * G)  # the slip velocity's zero
    stick = [t for t, what, _, _ in r.events if what.startswith("stick")]
    assert stick == [pytest.approx(t_stick, abs=1e-9)]
    assert set(r.mode.tolist()) == {0, 1}  # rest and slide only
    assert np.all(r.theta == 0.0) and np.all(r.lift == 0.0)


def _mu_cr(a, beta):
    """Friction needed to rock a uniform rectangle from rest under a sustained a = |a_g|/g
    (issue 45, from the contact forces at the pivot at onset)."""
    return (a * (1 + 4 * beta**2) + 3 * beta) / (4 + beta**2 + 3 * a * beta)


def _shenton(a, mu, beta):
    """Shenton (1996), "Criteria for initiation of slide, rock, and slide-rock rigid-body
    modes", J. Eng. Mech. 122(7): the mode a uniform rectangle leaves rest in."""
    if a <= min(mu, beta):
        return "rest"
    if mu < beta:
        return "slide"
    return "rock" if mu >= _mu_cr(a, beta) else "slide-rock"


def _onset(beta, a, mu):
    """Mode in which a uniform rectangle of B/H = ``beta`` leaves rest when a sustained
    a_g = −a·g is applied at t = 0 (the mode of the sample after, where it stays rest)."""
    block = rocking.Block.from_dimensions(1.0, beta)
    r = simulate_reference(block, np.full(3, -a * G), 1e-3, mu=mu)
    if not r.events:
        return _mode_names(r, 1)
    t, what, _, _ = r.events[0]
    assert t == 0.0 and what.startswith("onset -> ")
    return what.removeprefix("onset -> ")


@pytest.mark.parametrize("beta", [0.2, 0.35, 0.5])
def test_shenton_onset_classification_on_a_grid(beta):
    # Every cell against Shenton's closed-form criteria (exact: a classification).
    got = Counter()
    for a in (0.15, 0.3, 0.45, 0.6, 1.0, 1.5):
        for mu in (0.1, 0.25, 0.4, 0.7, 1.0):
            expected = _shenton(a, mu, beta)
            assert _onset(beta, a, mu) == expected, (beta, a, mu)
            got[expected] += 1
    assert len(got) >= 3  # the grid reaches at least three of the four modes at each β


@pytest.mark.parametrize(("beta", "a"), [(0.25, 1.0), (0.2, 0.6), (0.4, 0.9)])
def test_rock_or_slide_rock_switches_at_mu_cr(beta, a):
    # The reference's friction demand |F|/N at onset is solved from Newton–Euler; the issue's
    # μ_cr(a) is a closed form of it: the switch lies within 1e-6 of it (float rounding of the
    # linear system is ~1e-15).  The example: B/H = 0.25, μ = 0.35 slide-rocks at 1 g.
    # (Just below μ_cr the corner slips only briefly: as the block turns, the demand falls
    # back inside the cone and it sticks, 0.6 ms later here.)
    mu_cr = _mu_cr(a, beta)
    assert mu_cr > beta
    assert _onset(beta, a, mu_cr * (1 + 1e-6)) == "rock"
    assert _onset(beta, a, mu_cr * (1 - 1e-6)) == "slide-rock"
    if (beta, a) == (0.25, 1.0):
        assert _onset(beta, a, 0.35) == "slide-rock"


def test_flight_under_vertical_acceleration_below_minus_g_is_ballistic():
    # a_v = −1.5 g lifts the block off at once; after 0.3 s a_v returns to 0 (linearly over one
    # sample).  In flight the centre of mass moves under −a_g and −(g + a_v) alone: the lift
    # is the exact double integral of the piecewise-linear −(g + a_v) (cubic in each step),
    # the slip −a_g·t²/2, and it lands where that cubic returns to 0.  Tolerance 1e-9 m/s:
    # the integrator's (polynomials are integrated to rounding by DOP853).
    block = rocking.Block.from_dimensions(2.0, 0.5)
    dt, n = 0.01, 101
    av = np.full(n, -1.5 * G)
    av[31:] = 0.0
    ag = np.full(n, 0.2 * G)
    r = simulate_reference(block, ag, dt, mu=0.5, av=av)
    acc = -(G + av)
    v, y = np.zeros(n), np.zeros(n)
    for k in range(n - 1):
        v[k + 1] = v[k] + dt * (acc[k] + acc[k + 1]) / 2
        y[k + 1] = y[k] + v[k] * dt + dt**2 * (2 * acc[k] + acc[k + 1]) / 6
    t = r.t
    flying = r.mode == 4
    assert flying[1:60].all()
    np.testing.assert_allclose(r.lift[flying], y[flying], rtol=0, atol=1e-9)
    np.testing.assert_allclose(r.slip[flying], -0.1 * G * t[flying] ** 2, rtol=0, atol=1e-9)
    assert r.max_lift == pytest.approx(y.max(), abs=1e-9)
    k = int(np.nonzero((y[:-1] > 0) & (y[1:] <= 0))[0][0])  # the landing interval
    da = (acc[k + 1] - acc[k]) / dt
    roots = np.roots([da / 6, acc[k] / 2, v[k], y[k]])
    tau = min(x.real for x in roots if abs(x.imag) < 1e-12 and 0 < x.real <= dt)
    landing = [t_ev for t_ev, what, _, _ in r.events if "landing" in what]
    assert landing[0] == pytest.approx(t[k] + tau, abs=1e-9)
    assert np.all(r.lift[t > landing[0]] == 0.0)


@pytest.mark.parametrize(("mu", "after"), [(0.2, "slide"), (0.5, "slide-rock")])
def test_sliding_tips_onto_its_leading_corner_when_mu_k_h_exceeds_b(mu, after):
    # After the flat landing of the flight above the block slides at 1.4 m/s (more than μ_s
    # times the vertical impulse).  MODES.md: both corners stay down while μ_k·h ≤ b, i.e.
    # μ_k ≤ tan α = B/H = 0.25; above, the friction's moment lifts the trailing corner and
    # the block slide-rocks on the leading one (here −x: it slides to −x, θ < 0).
    block = rocking.Block.from_dimensions(2.0, 0.5)
    av = np.full(101, -1.5 * G)
    av[31:] = 0.0
    r = simulate_reference(block, np.full(101, 0.2 * G), 0.01, mu=mu, av=av)
    t_land, what, _, _ = next(e for e in r.events if "landing" in e[1])
    assert what == f"flat landing -> {after}"
    k = int(np.searchsorted(r.t, t_land))
    assert r.slip[k + 1] < r.slip[k] < 0.0
    assert (r.theta[k] < 0.0) if after == "slide-rock" else (r.theta[k] == 0.0)


def test_rotating_body_in_flight_keeps_its_angular_velocity():
    # No contact, no moment: θ' is constant in flight and θ linear (to the integrator's 1e-9).
    rng = np.random.default_rng(5)
    block = rocking.Block(0.6, 3.0)
    n = 300
    r = simulate_reference(
        block,
        _smooth_noise(rng, n, 1.2 * G),
        0.01,
        mu=0.38,
        av=_smooth_noise(rng, n, 2.0 * G),
    )
    runs = [k for k in range(1, n - 1) if np.all(r.mode[k - 1 : k + 2] == 4)]
    assert len(runs) >= 10
    for k in runs:
        assert r.omega[k + 1] == pytest.approx(r.omega[k], abs=1e-9)
        assert r.theta[k + 1] - 2 * r.theta[k] + r.theta[k - 1] == pytest.approx(0, abs=1e-9)


def test_large_friction_is_todays_rocking():
    # μ = 1e6 never slips: the reference with friction must give the frictionless-contact
    # reference's rocking (a separate formulation: Eq. (1) in θ alone) and rocking.simulate's.
    block = rocking.Block(1.0, 4.0)
    dt = 0.01
    t = np.arange(0, 4, dt)
    for amp in (0.3, 0.35):
        ag = amp * G * np.sin(2 * np.pi * 1.5 * t) * (t < 2)
        ours = simulate_reference(block, ag, dt, mu=1e6)
        ref = simulate_reference(block, ag, dt)
        assert ours.n_impacts == ref.n_impacts > 5
        # both at rtol 1e-10: measured 2e-15 apart
        np.testing.assert_allclose(ours.theta, ref.theta, rtol=0, atol=1e-10)
        np.testing.assert_allclose(ours.omega, ref.omega, rtol=0, atol=1e-9)
        assert set(ours.mode.tolist()) == {0, 2}  # rest and rock
        assert np.max(np.abs(ours.slip)) < 1e-12 and np.all(ours.lift == 0.0)
    # a general body (issue 16) too: Eq. (1) with I_0 = m·(r_g² + R²)
    body = rocking.Block.from_mass_properties(0.8, 0.2, radius_of_gyration=0.35)
    ag = 0.3 * G * np.sin(2 * np.pi * 1.5 * t) * (t < 2)
    ours = simulate_reference(body, ag, dt, mu=1e6)
    ref = simulate_reference(body, ag, dt)
    assert ours.n_impacts == ref.n_impacts > 5
    np.testing.assert_allclose(ours.theta, ref.theta, rtol=0, atol=1e-10)
    # rocking.simulate is RK4 at dt with located impacts: its error falls as dt⁴; at dt =
    # 1/500 s it is 9e-11 rad here (5.6e-8 at 1/100 s), so 1e-8 rad holds with margin.
    dt = 0.002
    t = np.arange(0, 3, dt)
    ag = 0.3 * G * np.sin(2 * np.pi * 1.5 * t) * (t < 2)
    ours = simulate_reference(block, ag, dt, mu=1e6)
    fast = rocking.simulate(block, ag, dt)
    assert ours.n_impacts == fast.n_impacts == 7
    np.testing.assert_allclose(ours.theta, fast.theta, rtol=0, atol=1e-8)
    assert ours.max_abs_theta == pytest.approx(fast.max_abs_theta, abs=1e-8)


@pytest.mark.parametrize(
    "block",
    [rocking.Block(0.6, 3.0), rocking.Block.from_mass_properties(0.5, 0.2, radius_of_gyration=0.3)],
)
def test_mirror_symmetry(block):
    # −a_g is the mirror image: θ, θ' and slip change sign, lift and mode do not.  Every
    # operation is odd or even in x, so the two runs agree to rounding (1e-12).
    rng = np.random.default_rng(1)
    n = 300
    ag = _smooth_noise(rng, n, 1.2 * G)
    av = _smooth_noise(rng, n, 2.0 * G)
    p = simulate_reference(block, ag, 0.01, mu=0.38, av=av)
    m = simulate_reference(block, -ag, 0.01, mu=0.38, av=av)
    assert len(set(p.mode.tolist()) - {-1}) >= 3  # several modes, not a trivial case
    assert p.overturned == m.overturned
    np.testing.assert_array_equal(p.mode, m.mode)
    for a, b, sign in ((p.theta, m.theta, -1), (p.omega, m.omega, -1), (p.slip, m.slip, -1)):
        np.testing.assert_allclose(a, sign * b, rtol=0, atol=1e-12)
    np.testing.assert_allclose(p.lift, m.lift, rtol=0, atol=1e-12)


def test_energy_never_increases_across_impacts():
    # MODES.md: the stick law keeps at most e² of the kinetic energy, the sliding and flat
    # impacts are dissipative (plastic normal, Coulomb against the slip).  Relative 1e-12:
    # rounding of the impulses.  The cases are drawn until every kind of impact has occurred.
    rng = np.random.default_rng(1)
    kinds: Counter = Counter()
    n = 400
    for case in range(8):
        block = rocking.Block(0.6, 3.0) if case % 2 else rocking.Block(1.0, 4.0)
        ag = _smooth_noise(rng, n, rng.uniform(0.5, 1.5) * G)
        av = _smooth_noise(rng, n, rng.uniform(0.0, 2.5) * G)
        e = (0.9, 1.0, "housner")[case % 3]
        r = simulate_reference(block, ag, 0.01, mu=rng.uniform(0.3, 0.6), e=e, av=av)
        for t, what, before, after in r.events:
            if "impact" in what or "landing" in what:
                assert after <= before * (1 + 1e-12), (case, t, what, before, after)
                kinds[what.split(" -> ")[0]] += 1
    # Two landings whose Coulomb impulse would reverse the slip (it gained 0.6 % of the energy
    # before such an impact was made to stick): drawn as in a sweep of random cases.
    for seed in (23, 42):
        rng = np.random.default_rng(seed)
        n = 300
        block = rocking.Block(rng.uniform(0.3, 2.0), rng.uniform(1.5, 6))
        ag = np.convolve(rng.standard_normal(n), np.ones(6) / 6, "same") * rng.uniform(0.2, 2) * G
        av = np.convolve(rng.standard_normal(n), np.ones(6) / 6, "same") * rng.uniform(0, 3) * G
        mu = rng.uniform(0.05, 1.0)
        r = simulate_reference(
            block, ag, 0.01, mu=mu, mu_k=mu * rng.uniform(0.5, 1.0), e=0.9, av=av
        )
        for t, what, before, after in r.events:
            if "impact" in what or "landing" in what:
                assert after <= before * (1 + 1e-12), (seed, t, what, before, after)
                kinds[what.split(" -> ")[0]] += 1
    assert kinds["landing (plastic impact)"] > 0
    assert kinds["stick impact"] > 10
    assert kinds["sliding impact"] + kinds["landing (sliding impact)"] > 3
    assert kinds["landing (stick impact)"] > 0


@pytest.mark.parametrize("c", [1.0, -1.0])
def test_sliding_impact_from_rock_does_not_hang_on_the_rounding_of_theta(c):
    # An impact from rock: the new corner c is at rest before (θ = 0), so the slip direction
    # is where a frictionless impulse drives it (side c; Routh), whatever side of 0 the
    # located θ lies on by rounding (±3e-15 rad here, as SciPy's root finder leaves it).
    # Uniform block b = 0.15 m, h = 0.6 m, i = r_g² = (b² + h²)/3; e = 0.5 asks
    # abs(P_x)/P_y = 1.33 > μ_s = 0.5, so a sliding impact, P_x = −c·μ_k·P_y with the plastic
    # P_y = 2·c·b·ω/(1 + b·(b − μ_k·h)/i), θ'⁺ = ω + c·P_y·(μ_k·h − b)/i (μ_k = 0.1 keeps the
    # slip: μ_k < b·h/(i + h²)).  Before the fix, θ on the far side of 0 gave vcx ≈ −c·6e-16
    # m/s, a slip to −c, which reverses: a plastic stick impact instead.  1e-9: rtol 1e-10.
    block = rocking.Block.from_dimensions(1.2, 0.3)
    b, h, i = block.b, block.h_cg, block.radius_of_gyration**2
    body = _Rigid(b, h, i, i + block.R**2, 0.5, 0.1, 0.5, block.housner_e(), block.alpha)
    ground = _Ground(np.zeros(2), np.zeros(2), 0.01, G, np.array([0.0, 0.01]))
    modes = _Modes(body, ground, math.tan(block.alpha), (1e-10, 1e-12, math.inf))
    om = c * 1.3  # rocking about corner −c towards c
    p_y = 2.0 * c * b * om / (1.0 + b * (b - 0.1 * h) / i)
    for th in (3e-15, -3e-15):
        rx, ry = body.corner(-c, th)
        z = modes.project(_Phase(2, -c), [-rx, -ry, th, -ry * om, rx * om, om])
        ph, after, kind = modes.strike(0, 0.0, z, c, at_zero=True)
        assert kind == "sliding impact" and MODES[ph.mode] == "slide-rock" and ph.sigma == c
        assert after[5] == pytest.approx(om + c * p_y * (0.1 * h - b) / i, rel=1e-9)


def test_frictionless_slide_rock_frees_the_centre_of_mass():
    # With μ_k = 0 a slipping corner exerts no horizontal force: in slide-rock the centre of
    # mass's horizontal motion is x'' = −a_g exactly, so its second difference over two steps
    # equals −dt²·(a_{k−1} + 4·a_k + a_{k+1})/6 for a_g linear between samples; and the
    # motion in (y, θ) conserves ½·y'² + ½·r_g²·θ'² + g·y (N does no work: the corner moves
    # horizontally).  Checked on every stretch of slide-rock without an event inside, to
    # 1e-12 m and 1e-9 relative (the integrator's tolerances).
    block = rocking.Block.from_dimensions(2.0, 0.5)
    dt = 0.005
    t = np.arange(0, 3, dt)
    ag = 0.6 * G * np.sin(2 * np.pi * t) * (t < 1.5)
    r = simulate_reference(block, ag, dt, mu=0.3, mu_k=0.0)
    h, b, r_g2 = block.h_cg, block.b, block.radius_of_gyration**2
    th = r.theta
    s = np.where(th < 0, -1.0, 1.0)
    x = r.slip + s * b * (1 - np.cos(th)) + h * np.sin(th)  # the centre of mass
    r_x = s * b * np.cos(th) - h * np.sin(th)  # from it to the contact corner
    y = s * b * np.sin(th) + h * np.cos(th)
    energy = 0.5 * (r_x * r.omega) ** 2 + 0.5 * r_g2 * r.omega**2 + G * y
    events = np.array([e[0] for e in r.events])
    quiet = [
        k
        for k in range(1, t.size - 1)
        if np.all(r.mode[k - 1 : k + 2] == 3)
        and not np.any((events >= t[k - 1]) & (events <= t[k + 1]))
    ]
    assert len(quiet) >= 50
    for k in quiet:
        d2 = x[k + 1] - 2 * x[k] + x[k - 1]
        assert d2 == pytest.approx(-(dt**2) * (ag[k - 1] + 4 * ag[k] + ag[k + 1]) / 6, abs=1e-12)
        assert energy[k + 1] == pytest.approx(energy[k], rel=1e-9)


def test_friction_inputs_are_checked():
    block = rocking.Block(1.0, 4.0)
    ag = np.zeros(10)
    with pytest.raises(InputError, match="mu_k needs mu"):
        simulate_reference(block, ag, 0.01, mu_k=0.3)
    with pytest.raises(InputError, match="mu_k"):
        simulate_reference(block, ag, 0.01, mu=0.3, mu_k=0.5)
    with pytest.raises(InputError, match="mu"):
        simulate_reference(block, ag, 0.01, mu=-0.1)
    with pytest.raises(InputError, match="give mu"):
        simulate_reference(block, ag, 0.01, av=np.full(10, -1.1 * G))
    r = simulate_reference(block, ag, 0.01, mu=0.5, av=np.full(10, -1.1 * G))
    assert r.mode[1] == 4 and math.isclose(r.max_lift, 0.5 * 0.1 * G * 0.09**2, rel_tol=1e-9)
