"""The batched kernel with friction (issue 45): every case equals rocking.simulate(..., mu=...)."""

import numba
import numpy as np
import pytest

from rocking import Physics
from rocking.defaults import MODES
from rocking.dynamics.batch import BlockTable, motion_peaks, overturn_cases, run_cases
from rocking.dynamics.body import Block
from rocking.dynamics.simulate import simulate
from rocking.errors import InputError
from rocking.motions.synthesis import generate

SLIDE, ROCK, SLIDE_ROCK, FLIGHT = (
    MODES.index(m) for m in ("slide", "rock", "slide-rock", "flight")
)


@pytest.fixture(scope="module")
def ensemble():
    return generate(6, duration=4.0, dt=1 / 200, seed=5)


def _run(blocks, ens, body, motion, scale, physics, av=None):
    table = BlockTable.from_blocks(blocks, physics=physics)
    return run_cases(table, ens.acc, motion_peaks(ens.acc), ens.dt, body, motion, scale, av)


def _check(blocks, ens, body, motion, scale, out, mu, mu_k=None, av=None, e=None):
    """Every case's Outcome equals simulate()'s summaries bit for bit (the kernel calls the
    same compiled interval function of modes_case on the same scaled samples, or the same
    rocking steps); returns
    the modes seen.  ``e``: the restitution (None: simulate's default)."""
    restitution = {} if e is None else {"e": e}
    seen = set()
    for i in range(body.size):
        b = body[i]
        blk = blocks[b]
        vert = None if av is None else abs(scale[i]) * av[motion[i]]
        m, mk = (mu[b], None if mu_k is None else mu_k[b]) if isinstance(mu, list) else (mu, mu_k)
        r = simulate(
            blk, scale[i] * ens.acc[motion[i]], ens.dt, av=vert, mu=m, mu_k=mk, **restitution
        )
        assert out.overturned[i] == r.overturned, i
        assert out.peak_theta_ratio[i] == r.max_abs_theta / blk.alpha, i
        assert out.uplift[i] == r.uplift, i
        assert out.peak_slip[i] == r.max_abs_slip, i
        assert out.residual_slip[i] == abs(r.residual_slip), i
        assert out.peak_lift[i] == r.max_lift, i
        seen.update(int(x) for x in np.unique(r.mode))
        seen.add("overturned" if r.overturned else "standing")
    return seen


def _cases(rng, n_blocks, ensemble, n, peaks_g=None):
    """``n`` random cases: block and motion indices and, with ``peaks_g`` = (lo, hi), scale
    factors giving the ensemble's A_gx uniform in [lo, hi] g (negative: mirrored)."""
    body = rng.integers(0, n_blocks, n)
    motion = rng.integers(0, ensemble.n, n)
    if peaks_g is None:
        return body, motion
    return body, motion, rng.uniform(*peaks_g, n) / ensemble.agx


def test_batch_with_friction_equals_simulate(ensemble):
    rng = np.random.default_rng(21)
    blocks = [
        Block(float(rng.uniform(0.3, 2.0)), float(rng.uniform(1.5, 5.0))) for _ in range(3)
    ] + [Block.from_mass_properties(0.8, 0.2, radius_of_gyration=0.35)]
    n = 120
    # from 0.02 g (rest, in the lanes) to 1.5 g; negative: mirrored
    body, motion, scale = _cases(rng, len(blocks), ensemble, n, (-1.5, 1.5))
    scale[:10] = 0.02 / ensemble.agx
    for mu, mu_k in ((0.3, 0.25), (0.6, None), (1e6, None)):
        physics = Physics(mu=mu, mu_k=mu_k)
        out = _run(blocks, ensemble, body, motion, scale, physics)
        seen = _check(blocks, ensemble, body, motion, scale, out, mu, mu_k)
        assert {"overturned", "standing", ROCK} <= seen, mu
        if mu < 0.5:
            assert {SLIDE, SLIDE_ROCK} <= seen


@pytest.fixture(scope="module")
def slender():
    """Slender blocks (tan α 0.17 to 0.25, R 0.1 to 0.5 m) and a general body, which rock, and
    overturn, at peak accelerations below μ_s·g for μ_s = 0.3: cases that rock in the lanes'
    SIMD path and cases whose checks fail there (their intervals done again by modes_case's
    own interval function), at every μ_s."""
    rng = np.random.default_rng(31)
    blocks = [Block(float(rng.uniform(0.1, 0.5)), float(rng.uniform(4.0, 8.0))) for _ in range(4)]
    blocks.append(Block.from_mass_properties(0.8, 0.2, radius_of_gyration=0.35))
    return blocks, rng


def test_lanes_keep_rocking_cases_with_friction_bit_for_bit(ensemble, slender):
    blocks, rng = slender
    n = 150
    body, motion = _cases(rng, len(blocks), ensemble, n)
    # peaks from 0.1 g to 1.2 g, log-uniform, either sign
    scale = rng.choice([-1.0, 1.0], n) * np.exp(rng.uniform(np.log(0.1), np.log(1.2), n))
    scale /= ensemble.agx
    for mu, e in ((1e6, None), (0.6, None), (0.3, None), (0.45, "housner")):
        physics = Physics(mu=mu) if e is None else Physics(mu=mu, e=e)
        out = _run(blocks, ensemble, body, motion, scale, physics)
        # bit for bit simulate(mu=...), whichever path each interval took in the lanes
        seen = _check(blocks, ensemble, body, motion, scale, out, mu, e=e)
        assert out.uplift.any(), mu
        assert {"overturned", "standing", ROCK} <= seen, mu
        if mu == 1e6:
            assert out.overturned.any()


def test_lanes_with_friction_and_vertical_motion_bit_for_bit(ensemble, slender):
    blocks, rng = slender
    n = 80
    body, motion, scale = _cases(rng, len(blocks), ensemble, n, (-0.8, 0.8))
    av = 0.5 * ensemble.acc[::-1]  # above −g at these scales: the lanes may take the cases
    for mu in (1e6, 0.4):
        physics = Physics(mu=mu)
        out = _run(blocks, ensemble, body, motion, scale, physics, av)
        _check(blocks, ensemble, body, motion, scale, out, mu, av=av)
        assert out.uplift.any(), mu


def test_flight_and_per_block_friction_equal_simulate(ensemble):
    # the vertical component: another motion at 1–2 times its size, scaled by up to 1.5/agx:
    # below −g at the larger scales (flight, allowed with friction)
    rng = np.random.default_rng(22)
    av = ensemble.acc[::-1] * rng.uniform(1.0, 2.0, (ensemble.n, 1))
    blocks = [Block(0.4, 3.0), Block(1.0, 2.0), Block(0.6, 4.0)]
    n = 60
    body, motion, scale = _cases(rng, 3, ensemble, n, (-1.5, 1.5))
    mu, mu_k = [0.3, 0.7, None], [0.2, None, None]
    physics = Physics(mu=mu, mu_k=mu_k)
    out = _run(blocks, ensemble, body[body < 2], motion[body < 2], scale[body < 2], physics, av)
    seen = _check(
        blocks, ensemble, body[body < 2], motion[body < 2], scale[body < 2], out, mu, mu_k, av
    )
    assert FLIGHT in seen
    # the frictionless block under a vertical motion below −g: refused, pointing to mu
    with pytest.raises(InputError, match="mu"):
        _run(blocks, ensemble, body, motion, scale, physics, av)
    small = 0.3 * av  # above −g: the frictionless block rocks in the lanes beside the others
    out = _run(blocks, ensemble, body, motion, scale, physics, small)
    _check(blocks, ensemble, body, motion, scale, out, mu, mu_k, small)


def test_friction_results_do_not_depend_on_threads_or_grouping(ensemble):
    rng = np.random.default_rng(23)
    blocks = [Block(0.5, 3.0), Block(1.5, 2.5)]
    n = 40
    body, motion, scale = _cases(rng, 2, ensemble, n, (0.02, 1.2))
    physics = Physics(mu=0.35)
    before = numba.get_num_threads()
    try:
        numba.set_num_threads(1)
        one = _run(blocks, ensemble, body, motion, scale, physics)
        numba.set_num_threads(numba.config.NUMBA_NUM_THREADS)
        many = _run(blocks, ensemble, body, motion, scale, physics)
    finally:
        numba.set_num_threads(before)
    half = [
        _run(blocks, ensemble, body[s], motion[s], scale[s], physics)
        for s in (np.s_[:17], np.s_[17:])
    ]
    for a, b, *parts in zip(one, many, *half):
        np.testing.assert_array_equal(a, b)
        np.testing.assert_array_equal(a, np.concatenate(parts))


def test_overturn_cases_take_mu(ensemble):
    blocks = [Block(0.5, 3.0)]
    scale = np.array([0.3, 0.9]) / ensemble.agx
    ov, pk = overturn_cases(blocks, ensemble.acc, ensemble.dt, [0, 0], [0, 1], scale, mu=0.25)
    for i in range(2):
        r = simulate(blocks[0], scale[i] * ensemble.acc[i], ensemble.dt, mu=0.25)
        assert ov[i] == r.overturned and pk[i] == r.max_abs_theta / blocks[0].alpha


def test_per_block_friction_is_checked_block_by_block():
    physics = Physics(mu=[0.3, None, 0.5], mu_k=[0.2, None, None])
    assert physics.friction(0) == (0.3, 0.2) and physics.friction(1) == (None, None)
    assert physics.friction(2) == (0.5, 0.5)
    with pytest.raises(InputError, match=r"mu_k = 0.6 exceeds mu = 0.5 \(block 1\)"):
        Physics(mu=[0.3, 0.5], mu_k=[0.2, 0.6])
    with pytest.raises(InputError, match=r"mu_k needs mu \(block 1\)"):
        Physics(mu=[0.3, None], mu_k=[0.2, 0.1])
    with pytest.raises(InputError, match="mu_k has 1 values but mu has 2"):
        Physics(mu=[0.3, 0.4], mu_k=[0.2])
    with pytest.raises(InputError, match="mu has 3 values for 2 blocks"):
        BlockTable.from_blocks([Block(1.0, 3.0), Block(1.0, 4.0)], physics=physics)
    with pytest.raises(InputError, match="mu"):
        Physics(mu=[0.3, -1.0])
    # the fingerprint of the chunk store follows per-block friction
    assert Physics(mu=[0.3, 0.4]).fingerprint != Physics(mu=[0.4, 0.3]).fingerprint


def test_friction_with_housner_e_alpha_angle_and_step_end_impacts_equals_simulate(ensemble):
    rng = np.random.default_rng(24)
    blocks = [Block(0.5, 4.0), Block(1.2, 3.0)]
    n = 30
    body, motion, scale = _cases(rng, 2, ensemble, n, (-1.2, 1.2))
    kw = dict(e="housner", overturn_angle="alpha", impacts="step-end")
    out = _run(blocks, ensemble, body, motion, scale, Physics(mu=0.45, **kw))
    for i in range(n):
        blk = blocks[body[i]]
        r = simulate(blk, scale[i] * ensemble.acc[motion[i]], ensemble.dt, mu=0.45, **kw)
        assert out.overturned[i] == r.overturned, i
        assert out.peak_theta_ratio[i] == r.max_abs_theta / blk.alpha, i
        assert out.peak_slip[i] == r.max_abs_slip, i
    assert out.overturned.any() and (out.peak_slip > 0).any()


def test_every_mode_within_one_case_in_the_lanes_bit_for_bit(ensemble):
    # cases that rock, slide, slide-rock and fly within one motion (a vertical motion twice
    # the size of the horizontal one, reversed: below −g at the larger scales; μ_k well below
    # μ_s, so that impacts and landings leave the base sliding): the lanes carry the modes
    # state from their SIMD rocking path to modes_case's interval function and back, within
    # one case; bit for bit simulate(mu=...), on one thread and on all, in one call and in two
    rng = np.random.default_rng(45)
    blocks = [
        Block(0.3, 3.0),
        Block(0.6, 2.5),
        Block(0.4, 4.0),
        Block.from_mass_properties(0.8, 0.2, radius_of_gyration=0.35),
        Block(0.5, 1.5),
    ]
    n = 40
    body, motion, scale = _cases(rng, len(blocks), ensemble, n, (-1.6, 1.6))
    av = 2.0 * ensemble.acc[::-1]
    physics = Physics(mu=0.7, mu_k=0.2)
    before = numba.get_num_threads()
    try:
        numba.set_num_threads(1)
        one = _run(blocks, ensemble, body, motion, scale, physics, av)
        numba.set_num_threads(numba.config.NUMBA_NUM_THREADS)
        many = _run(blocks, ensemble, body, motion, scale, physics, av)
    finally:
        numba.set_num_threads(before)
    half = [
        _run(blocks, ensemble, body[s], motion[s], scale[s], physics, av)
        for s in (np.s_[:23], np.s_[23:])
    ]
    for a, b, *parts in zip(one, many, *half):
        np.testing.assert_array_equal(a, b)
        np.testing.assert_array_equal(a, np.concatenate(parts))
    _check(blocks, ensemble, body, motion, scale, one, 0.7, 0.2, av)
    every = 0
    for i in range(n):
        r = simulate(
            blocks[body[i]],
            scale[i] * ensemble.acc[motion[i]],
            ensemble.dt,
            av=abs(scale[i]) * av[motion[i]],
            mu=0.7,
            mu_k=0.2,
        )
        every += {SLIDE, ROCK, SLIDE_ROCK, FLIGHT} <= set(r.mode.tolist())
    assert every >= 3  # measured: 6 of the 40 cases


def test_lanes_check_the_contact_right_after_an_impact(ensemble):
    # found by a search over random blocks, scales and μ_s (random.default_rng(7), trial 252):
    # in this case's interval 88, modes_case's rocking step has an impact whose impulse lies
    # in the friction cone (impact_ok) and ends rocking within the cone (N ≥ 0, abs(F) ≤ μ_s·N),
    # but the bound on the contact right after the impact fails and the general integrator does
    # not keep the corner stuck (_stays_stuck): modes_case does the interval again with it.  The
    # lanes must see it too (their check after impacts, _check_impacts): without that check they
    # keep the rocking step, and the case's results differ from simulate(mu=...)
    block = Block(0.46818163742279684, 4.084210225660907)
    mu = 0.2452037663931383
    scale = np.array([1.467012383254617 / ensemble.agx])
    out = _run([block], ensemble, np.array([0]), np.array([1]), scale, Physics(mu=mu))
    seen = _check([block], ensemble, np.array([0]), np.array([1]), scale, out, mu)
    assert SLIDE_ROCK in seen  # the corner slips after the impact
