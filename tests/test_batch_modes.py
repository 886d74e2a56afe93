"""The batched kernel with friction (issue 45): every case equals rocking.simulate(..., mu=...)."""

import numba
import numpy as np
import pytest

from rocking import Physics
from rocking.defaults import MODES
from rocking.dynamics import batch
from rocking.dynamics.batch import BlockTable, motion_peaks, overturn_cases, run_cases
from rocking.dynamics.batch_modes import modes_needed
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
    same compiled modes_case on the same scaled samples, or the lanes the same steps); returns
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
        table = BlockTable.from_blocks(blocks, physics=physics)
        need = modes_needed(
            motion_peaks(ensemble.acc),
            None,
            table.g,
            table.arrays(),
            table.contacts,
            body,
            motion,
            scale,
        )
        # the lanes take the cases at rest, and with their checks those whose base cannot slip
        assert (~need).sum() >= 10
        out = _run(blocks, ensemble, body, motion, scale, physics)
        seen = _check(blocks, ensemble, body, motion, scale, out, mu, mu_k)
        assert {"overturned", "standing", ROCK} <= seen, mu
        if mu < 0.5:
            assert {SLIDE, SLIDE_ROCK} <= seen


def _run_spied(monkeypatch, blocks, ens, body, motion, scale, physics, av=None):
    """run_cases, and the cases that the lanes with contact checks kept and those they sent to
    the modes kernel (every block has friction here)."""
    made = []
    real = batch.lane_friction

    def spy(*args):
        made.append(real(*args))
        return made[-1]

    monkeypatch.setattr(batch, "lane_friction", spy)
    out = _run(blocks, ens, body, motion, scale, physics, av)
    table = BlockTable.from_blocks(blocks, physics=physics)
    avmin = None if av is None else av.min(axis=1)
    need = modes_needed(
        motion_peaks(ens.acc), avmin, table.g, table.arrays(), table.contacts, body, motion, scale
    )
    checked = np.flatnonzero(~need)
    assert len(made) == (1 if checked.size else 0)
    failed = made[0].failed if made else np.zeros(0, dtype=bool)
    return out, checked[~failed], checked[failed]


@pytest.fixture(scope="module")
def slender():
    """Slender blocks (tan α 0.17 to 0.25, R 0.1 to 0.5 m) and a general body, which rock, and
    overturn, at peak accelerations below μ_s·g for μ_s = 0.3: cases that the lanes keep and
    cases that fail their checks, at every μ_s."""
    rng = np.random.default_rng(31)
    blocks = [Block(float(rng.uniform(0.1, 0.5)), float(rng.uniform(4.0, 8.0))) for _ in range(4)]
    blocks.append(Block.from_mass_properties(0.8, 0.2, radius_of_gyration=0.35))
    return blocks, rng


def test_lanes_keep_rocking_cases_with_friction_bit_for_bit(ensemble, slender, monkeypatch):
    blocks, rng = slender
    n = 150
    body, motion = _cases(rng, len(blocks), ensemble, n)
    # peaks from 0.1 g to 1.2 g, log-uniform, either sign
    scale = rng.choice([-1.0, 1.0], n) * np.exp(rng.uniform(np.log(0.1), np.log(1.2), n))
    scale /= ensemble.agx
    for mu, e in ((1e6, None), (0.6, None), (0.3, None), (0.45, "housner")):
        physics = Physics(mu=mu) if e is None else Physics(mu=mu, e=e)
        out, kept, rerun = _run_spied(monkeypatch, blocks, ensemble, body, motion, scale, physics)
        # bit for bit simulate(mu=...): whether the lanes kept a case or the modes kernel re-ran it
        seen = _check(blocks, ensemble, body, motion, scale, out, mu, e=e)
        assert kept.size and rerun.size, mu  # both kinds
        assert out.uplift[kept].any(), mu  # the lanes keep rocking cases, not only rest
        assert {"overturned", "standing", ROCK} <= seen, mu
        if mu == 1e6:
            assert out.overturned[kept].any()
            # with ample friction the lanes keep every case that does not overturn (only
            # overturning ones fly off their corner first, N < 0: measured, all 150 cases)
            assert np.isin(np.flatnonzero(~out.overturned), kept).all()


def test_lanes_with_friction_and_vertical_motion_bit_for_bit(ensemble, slender, monkeypatch):
    blocks, rng = slender
    n = 80
    body, motion, scale = _cases(rng, len(blocks), ensemble, n, (-0.8, 0.8))
    av = 0.5 * ensemble.acc[::-1]  # above −g at these scales: the lanes may take the cases
    for mu in (1e6, 0.4):
        physics = Physics(mu=mu)
        out, kept, rerun = _run_spied(
            monkeypatch, blocks, ensemble, body, motion, scale, physics, av
        )
        _check(blocks, ensemble, body, motion, scale, out, mu, av=av)
        assert out.uplift[kept].any() and rerun.size, mu


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
