"""General rigid bodies (issue 16, part 4): Block with a radius of gyration r_g.

Independent references: the mass properties of a composite body summed part by part with the
parallel-axis theorem (no use of I_O = M·(r_g² + R²)); the angular momentum about the new pivot
summed part by part as vectors (Housner's restitution); the energy balance of the paper's
Eq. (10) solved numerically with SciPy; the uniform block of the paper (r_g² = R²/3); and the
SciPy ``solve_ivp`` solver of :mod:`rocking.dynamics.reference`, which integrates Eq. (1) in its
physical form (I_O·θ'' = −M·R·[g·sin(sα − θ) + a_g·cos(sα − θ)], libm trigonometry, located
events) and shares no code with the fixed-step kernels.
"""

from __future__ import annotations

import math

import numpy as np
import pytest
from scipy import optimize, signal

from rocking import Block, BodyWarning, G, InputError, housner_sv, simulate
from rocking.dynamics.body import resolve_e
from rocking.dynamics.reference import simulate_reference
from rocking.motions.response import response_spectrum


def _cabinet(width, h1, rho1, h2, rho2):
    """A plane body made of two stacked homogeneous rectangles of the same width [m]: a lower
    one of height h1 and density rho1 (per unit area), an upper one of height h2 and density
    rho2.  Returns M, h_cg [m], I_cg and I_O (about a bottom corner) [kg·m²] and the parts as
    (mass, height of its centre, own moment of inertia), each summed part by part."""
    parts = []
    for h, rho, y0 in ((h1, rho1, 0.0), (h2, rho2, h1)):
        m = rho * width * h
        parts.append((m, y0 + h / 2, m * (width**2 + h**2) / 12))
    M = sum(m for m, _, _ in parts)
    h_cg = sum(m * y for m, y, _ in parts) / M
    I_cg = sum(i + m * (y - h_cg) ** 2 for m, y, i in parts)
    I_O = sum(i + m * ((width / 2) ** 2 + y**2) for m, y, i in parts)  # parallel axes, corner
    return M, h_cg, I_cg, I_O, parts


CABINETS = [
    # width, lower height, its density, upper height, its density (heavy base, light top, ...)
    (0.6, 0.3, 5.0, 1.5, 1.0),
    (0.8, 1.0, 1.0, 1.0, 3.0),
    (0.5, 0.2, 20.0, 2.0, 0.5),
]


@pytest.mark.parametrize("cabinet", CABINETS)
def test_p_squared_is_m_g_r_over_the_moment_of_inertia_about_the_pivot(cabinet):
    width = cabinet[0]
    M, h_cg, I_cg, I_O, _ = _cabinet(*cabinet)
    blk = Block.from_mass_properties(h_cg, width / 2, radius_of_gyration=math.sqrt(I_cg / M))
    size = math.hypot(h_cg, width / 2)
    r_blk = blk.R
    assert r_blk == pytest.approx(size, rel=1e-15)
    assert blk.alpha == pytest.approx(math.atan2(width / 2, h_cg), rel=1e-15)
    assert (blk.h_cg, blk.b) == pytest.approx((h_cg, width / 2), rel=1e-14)
    # Eq. (1) from the moment equation about the pivot: θ'' = −(M·g·R/I_O)·sin(α − θ) + ...;
    # I_O here from the parallel-axis theorem applied to each part, not from r_g² + R².
    # 1e-14: a few roundings of sums of products
    assert blk.p_squared(G) == pytest.approx(M * G * size / I_O, rel=1e-14)
    assert blk.p_at(3.7) ** 2 == pytest.approx(M * 3.7 * size / I_O, rel=1e-14)


@pytest.mark.parametrize("cabinet", CABINETS)
def test_housner_restitution_conserves_angular_momentum_about_the_new_pivot(cabinet):
    # Housner (1963): the impact impulse acts at the new pivot O', so the angular momentum about
    # O' is conserved. Before: each part turns at ω about O, its centre moving at ω × (r − O);
    # after: the body turns at e·ω about O'. Summed over the parts as vectors.
    width = cabinet[0]
    M, h_cg, I_cg, I_O, parts = _cabinet(*cabinet)
    blk = Block.from_mass_properties(h_cg, width / 2, radius_of_gyration=math.sqrt(I_cg / M))
    omega = -1.7  # [rad/s], any value: e is a ratio
    pivot, new_pivot = np.array([width / 2, 0.0]), np.array([-width / 2, 0.0])
    L = 0.0
    for m, y, i_own in parts:
        r = np.array([0.0, y])
        v = omega * np.array([-(r - pivot)[1], (r - pivot)[0]])  # ω ẑ × (r − O)
        d = r - new_pivot
        L += i_own * omega + m * (d[0] * v[1] - d[1] * v[0])
    e_momentum = L / (I_O * omega)  # I about O' equals I_O by symmetry
    assert blk.housner_e() == pytest.approx(e_momentum, rel=1e-13)  # roundings of the sums
    r = simulate(blk, np.zeros(3), 0.01, e="housner", theta0=0.01)
    assert r.e == blk.housner_e()


@pytest.mark.parametrize("cabinet", CABINETS)
def test_generalised_eq11_solves_the_energy_balance_of_eq10(cabinet):
    # Paper Eq. (10) with the inertia in its place: the kinetic energy ½·I_O·θ'² given by the
    # ground, θ' = (M·R·cos α/I_O)·S_v, equals the work M·g·R·(1 − cos α) that lifts the centre of
    # mass to θ = α. Solved for S_v by brentq with I_O from the parts.
    width = cabinet[0]
    M, h_cg, I_cg, I_O, _ = _cabinet(*cabinet)
    blk = Block.from_mass_properties(h_cg, width / 2, radius_of_gyration=math.sqrt(I_cg / M))
    R, ca = math.hypot(h_cg, width / 2), h_cg / math.hypot(h_cg, width / 2)

    def balance(sv):
        return 0.5 * I_O * (M * R * ca * sv / I_O) ** 2 - M * G * R * (1 - ca)

    sv = optimize.brentq(balance, 1e-6, 100.0, xtol=1e-15, rtol=1e-15)
    assert housner_sv(blk) == pytest.approx(sv, rel=1e-12)  # brentq to 1e-15, rounding


def test_uniform_composite_is_the_paper_block():
    # Equal densities: the composite is a homogeneous W × (h1 + h2) block, so the general
    # formulas must give the paper's: p² = 3g/(4R), e = 1 − 1.5·sin²α, Eq. (11).
    width, h1, h2 = 0.7, 0.5, 1.6
    M, h_cg, I_cg, _I_O, _ = _cabinet(width, h1, 2.0, h2, 2.0)
    general = Block.from_mass_properties(h_cg, width / 2, radius_of_gyration=math.sqrt(I_cg / M))
    block = Block.from_dimensions(h1 + h2, width)
    # rounding only: the same quantities by different sums and products
    assert general.p_squared() == pytest.approx(block.p_squared(), rel=1e-14)
    assert general.housner_e() == pytest.approx(block.housner_e(), rel=1e-14)
    assert housner_sv(general) == pytest.approx(housner_sv(block), rel=1e-14)


def test_general_body_with_the_uniform_inertia_rocks_as_the_block():
    # r_g² = R²/3 is the homogeneous block: p² = g·R/(R²/3 + R²) is 3g/(4R) to rounding (the two
    # are computed differently and differ by at most an ulp; for this R they are equal), and the
    # kernel then runs the same operations: the responses are equal to rounding. Measured: bit
    # for bit when p² is equal (R = 1.22 m, 0.37 m); a last bit of p² that differs (R = 1 m)
    # moves θ by ≤ 1e-16 rad over 8 s of rocking with 30 impacts.
    dt = 1 / 200
    t = np.arange(1600) * dt
    for R, gamma in ((1.0, 3.0), (1.22, 4.0), (0.37, 2.5)):
        block = Block(R, gamma)
        general = Block(R, gamma, r_g=R / math.sqrt(3.0))
        assert general != block and general.label != block.label  # told apart in tables
        assert general.p_squared() == pytest.approx(block.p_squared(), rel=2.3e-16)
        ag = -1.3 * block.uplift_acceleration * np.sin(2 * np.pi * 2.0 * t) * np.exp(-0.3 * t)
        a = simulate(block, ag, dt, e="housner")
        b = simulate(general, ag, dt, e="housner")
        assert a.n_impacts == b.n_impacts and a.n_impacts >= 20 and not a.overturned
        if general.p_squared() == block.p_squared():
            np.testing.assert_array_equal(a.theta, b.theta)
        np.testing.assert_allclose(b.theta, a.theta, rtol=0, atol=1e-13)


def test_labels_and_validation():
    blk = Block.from_mass_properties(1.0, 0.25, radius_of_gyration=0.4)
    assert blk.r_g == 0.4 and not blk.is_uniform and Block(1.0, 3.0).is_uniform
    assert blk.label == "R=1.03 m, γ=4, r_g=0.40 m"
    assert str(blk) == f"Block(R={blk.R:g} m, gamma=4, r_g=0.4 m)"
    assert Block(1.0, 3.0).radius_of_gyration == pytest.approx(1.0 / math.sqrt(3.0), rel=1e-15)
    for kwargs, word in (
        (dict(h_cg=-1.0, b=0.2, radius_of_gyration=0.3), "h_cg"),
        (dict(h_cg=1.0, b=0.0, radius_of_gyration=0.3), "b"),
        (dict(h_cg=1.0, b=0.2, radius_of_gyration=float("nan")), "radius_of_gyration"),
    ):
        with pytest.raises(InputError, match=rf"\b{word}\b"):
            Block.from_mass_properties(**kwargs)
    # unusual but physical: a warning naming r_g, not a refusal (issue 48)
    with pytest.warns(BodyWarning, match=r"\br_g = 10000 m\b"):
        Block.from_mass_properties(1.0, 0.2, radius_of_gyration=1e4)


# ---------------------------------------------------------------- against solve_ivp

DT = 1 / 100  # [s] coarse (4× the paper's step), as the 500-case test of test_dynamics.py
N_T = 400  # 4 s


def _general_case(i: int):
    """A random general body (r_g from 0.25 R to 0.9 R, so p² from 0.55 to 0.94 times the
    uniform block's), a broadband motion scaled to 1–5 times the generalised Eq. (11) in peak
    PSV, and e in turn "housner", 0.8, 0.925, 1.0."""
    rng = np.random.default_rng([777, i])
    h = rng.uniform(0.4, 2.0)
    b = h / rng.uniform(2.0, 6.0)
    blk = Block.from_mass_properties(
        h, b, radius_of_gyration=math.hypot(h, b) * rng.uniform(0.25, 0.9)
    )
    sos = signal.butter(2, [0.3, 8.0], "bandpass", fs=1 / DT, output="sos")
    x = signal.sosfilt(sos, rng.standard_normal(N_T))
    t = np.arange(N_T) * DT
    x *= np.minimum(1.0, t) * np.exp(-0.3 * np.maximum(0.0, t - 2.0))
    x /= np.abs(x).max()
    psv = response_spectrum(x, DT, np.geomspace(0.1, 2.0, 40)).psv.max()
    ag = x * housner_sv(blk) / psv * math.exp(rng.uniform(0.0, math.log(5.0)))
    return blk, ag, ["housner", 0.8, 0.925, 1.0][i % 4]


def test_general_bodies_agree_with_solve_ivp(matches_reference):
    outcomes = set()
    for i in range(16):
        blk, ag, e = _general_case(i)
        ours = simulate(blk, ag, DT, e=e)
        # the reference at its default tolerances, steps of up to a whole sample interval: it
        # watches the extrema of θ', so a bounce of a chatter that starts and ends inside one
        # of its steps is found (case 0: before it did, two impacts of a 1e-7 rad chatter went
        # unseen, after which it rocked to 0.35 rad instead of 0.48 and needed max_step = dt/2;
        # now it agrees with the capped run to 1.4e-9 rad over the 16 cases)
        ref = simulate_reference(blk, ag, DT, e=e)
        outcomes.add(ref.overturned)
        matches_reference(ours, ref, i)  # (tolerances and their reasons: tests/conftest.py)
    assert outcomes == {True, False}  # both outcomes exercised


def test_housner_restitution_of_a_body_too_squat_to_rock_is_refused():
    # e = 1 − 2b²/(r_g² + R²) ≤ 0 when b² ≥ (r_g² + h_cg² + b²)/2: a uniform block with γ < 1/√2
    # (1 − 1.5·sin²α ≤ 0 for tan α ≥ √2) has no positive Housner restitution
    squat = Block(1.0, 0.5)
    assert squat.housner_e() < 0
    with pytest.raises(InputError, match="too squat"):
        resolve_e("housner", squat)
    assert resolve_e("housner", Block(1.0, 2.0)) == pytest.approx(1 - 1.5 * 0.2)
