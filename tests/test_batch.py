"""Batched overturning kernel: the same answers as rocking.simulate, case by case."""

import numba
import numpy as np
import pytest

from rocking.dynamics.batch import overturn_batch, overturn_cases
from rocking.dynamics.body import Block
from rocking.dynamics.simulate import simulate
from rocking.errors import InputError
from rocking.motions.synthesis import generate


@pytest.fixture(scope="module")
def ensemble():
    return generate(8, duration=6.0, dt=1 / 200, seed=3)


def _random_blocks(rng, n):
    return [Block(float(rng.uniform(0.3, 3.0)), float(rng.uniform(1.5, 6.0))) for _ in range(n)]


def _check_against_simulate(blocks, acc, dt, body, motion, scale, overturned, peak, av=None, **kw):
    """Every case equals simulate(); returns the kinds of cases seen (to prove coverage).
    ``av``: vertical motions like ``acc``, scaled by abs(scale) (a mirror flips only a_g)."""
    kinds = set()
    for i in range(len(body)):
        blk = blocks[body[i]]
        vert = None if av is None else abs(scale[i]) * av[motion[i]]
        r = simulate(blk, scale[i] * acc[motion[i]], dt, av=vert, **kw)
        assert overturned[i] == r.overturned, i
        # the kernel runs the same floating-point operations as simulate, so the values are
        # expected to be equal; 1e-12 relative only allows for compiler reordering
        assert peak[i] == pytest.approx(r.max_abs_theta / blk.alpha, rel=1e-12, abs=0.0), i
        kinds.add("overturned" if r.overturned else "rest" if r.max_abs_theta == 0 else "rocked")
    return kinds


def test_batch_equals_simulate_on_random_cases(ensemble):
    rng = np.random.default_rng(11)
    blocks = _random_blocks(rng, 5)
    # A_gx from 0.05 g (most blocks stay at rest) to 1.5 g (most overturn); negative = mirrored
    scales = rng.uniform(0.05, 1.5, 6) / ensemble.agx * rng.choice([-1.0, 1.0], 6)
    overturned, peak = overturn_batch(blocks, ensemble.acc, ensemble.dt, scales)
    assert overturned.shape == peak.shape == (5, 6, ensemble.n)
    b, j, m = (i.ravel() for i in np.indices(overturned.shape))
    kinds = _check_against_simulate(
        blocks, ensemble.acc, ensemble.dt, b, m, scales[j], overturned.ravel(), peak.ravel()
    )
    assert kinds == {"overturned", "rest", "rocked"}


def test_per_case_entry_with_housner_e_and_alpha_angle(ensemble):
    rng = np.random.default_rng(12)
    blocks = _random_blocks(rng, 4)
    n = 60
    body = rng.integers(0, 4, n)
    motion = rng.integers(0, ensemble.n, n)
    scale = rng.uniform(-1.2, 1.2, n) / ensemble.agx
    kw = dict(e="housner", overturn_angle="alpha")
    overturned, peak = overturn_cases(blocks, ensemble.acc, ensemble.dt, body, motion, scale, **kw)
    kinds = _check_against_simulate(
        blocks, ensemble.acc, ensemble.dt, body, motion, scale, overturned, peak, **kw
    )
    assert "overturned" in kinds and "rest" in kinds


def test_batch_with_vertical_motion_and_general_bodies_equals_simulate(ensemble):
    # the vertical component: another motion of the ensemble at 0.2–0.5 of its size (down to
    # about −0.8 g with the largest scale: above −g, as it must be)
    rng = np.random.default_rng(13)
    av = ensemble.acc[::-1] * rng.uniform(0.2, 0.5, (ensemble.n, 1))
    blocks = [
        *_random_blocks(rng, 2),
        Block.from_mass_properties(0.8, 0.2, radius_of_gyration=0.35),
        Block(1.5, 4.0, r_g=1.2),
    ]
    n = 80
    body = rng.integers(0, len(blocks), n)
    motion = rng.integers(0, ensemble.n, n)
    scale = rng.uniform(-1.5, 1.5, n) / ensemble.agx
    for kw in ({}, dict(e="housner", overturn_angle="alpha")):
        overturned, peak = overturn_cases(
            blocks, ensemble.acc, ensemble.dt, body, motion, scale, av=av, **kw
        )
        kinds = _check_against_simulate(
            blocks, ensemble.acc, ensemble.dt, body, motion, scale, overturned, peak, av=av, **kw
        )
        assert kinds == {"overturned", "rest", "rocked"}


def test_mirrored_motion_gives_the_same_flags_and_peaks(ensemble):
    # reference.md §2: a block responds to −a_g(t) with exactly −θ(t); the kernel's arithmetic is
    # sign-symmetric, so |θ| and the flags agree bit for bit
    blocks = [Block(0.5, 3.0), Block(1.22, 4.0), Block(2.5, 2.5)]
    s = np.array([0.4, 0.8, 1.2]) / ensemble.agx
    overturned, peak = overturn_batch(blocks, ensemble.acc, ensemble.dt, np.concatenate([s, -s]))
    assert 0 < overturned.mean() < 1
    np.testing.assert_array_equal(overturned[:, :3], overturned[:, 3:])
    np.testing.assert_array_equal(peak[:, :3], peak[:, 3:])


def test_per_block_restitution(ensemble):
    blocks = [Block(1.0, 3.0), Block(1.0, 3.0)]
    scales = np.array([0.5, 0.8]) / ensemble.agx
    _ov, pk = overturn_batch(blocks, ensemble.acc, ensemble.dt, scales, e=[0.7, 1.0])
    _ov7, pk7 = overturn_batch(blocks[:1], ensemble.acc, ensemble.dt, scales, e=0.7)
    _ov1, pk1 = overturn_batch(blocks[:1], ensemble.acc, ensemble.dt, scales, e=1.0)
    np.testing.assert_array_equal(pk[0], pk7[0])
    np.testing.assert_array_equal(pk[1], pk1[0])
    # less energy lost at impacts: the elastic block rocks at least as far (physics, not code)
    assert pk1.sum() > pk7.sum()


def test_results_do_not_depend_on_thread_count(ensemble):
    blocks = [Block(0.6, 3.0), Block(2.0, 5.0)]
    scales = np.linspace(0.1, 1.2, 5) / ensemble.agx
    before = numba.get_num_threads()
    try:
        numba.set_num_threads(1)
        one = overturn_batch(blocks, ensemble.acc, ensemble.dt, scales)
        numba.set_num_threads(numba.config.NUMBA_NUM_THREADS)
        many = overturn_batch(blocks, ensemble.acc, ensemble.dt, scales)
    finally:
        numba.set_num_threads(before)
    np.testing.assert_array_equal(one[0], many[0])
    np.testing.assert_array_equal(one[1], many[1])


def test_lanes_take_new_cases_from_the_shared_queue_as_simulate_computes_them(ensemble):
    # More cases than the lane machines hold (128 lanes each, one machine per thread), so that
    # lanes whose case ended take the next from the queue the machines share, on one thread and
    # on all: every case still equals simulate().
    rng = np.random.default_rng(14)
    blocks = _random_blocks(rng, 6)
    n = 2 * 128 * numba.config.NUMBA_NUM_THREADS + 37
    body = rng.integers(0, len(blocks), n)
    motion = rng.integers(0, ensemble.n, n)
    scale = rng.uniform(0.05, 1.5, n) / ensemble.agx
    before = numba.get_num_threads()
    try:
        for threads in (1, numba.config.NUMBA_NUM_THREADS):
            numba.set_num_threads(threads)
            overturned, peak = overturn_cases(
                blocks, ensemble.acc, ensemble.dt, body, motion, scale
            )
            kinds = _check_against_simulate(
                blocks, ensemble.acc, ensemble.dt, body, motion, scale, overturned, peak
            )
            assert kinds == {"overturned", "rest", "rocked"}
    finally:
        numba.set_num_threads(before)


def test_bad_input_is_named(ensemble):
    blk = [Block(1.0, 3.0)]
    with pytest.raises(InputError, match="blocks"):
        overturn_batch([], ensemble.acc, ensemble.dt, [1.0])
    with pytest.raises(InputError, match="e has 2 values"):
        overturn_batch(blk, ensemble.acc, ensemble.dt, [1.0], e=[0.9, 0.8])
    with pytest.raises(InputError, match="scales"):
        overturn_batch(blk, ensemble.acc, ensemble.dt, [np.nan])
    with pytest.raises(InputError, match="motion_index"):
        overturn_cases(blk, ensemble.acc, ensemble.dt, [0], [ensemble.n], [1.0])
    with pytest.raises(InputError, match="same length"):
        overturn_cases(blk, ensemble.acc, ensemble.dt, [0, 0], [0], [1.0])
