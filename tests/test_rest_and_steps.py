"""The batched kernel's early end of a case at rest (issue 18) and its count of integrated steps.

A block at rest that no remaining sample can lift is at rest to the end: the kernel finishes such
a case at once from suffix extremes of the motion.  The tests here put the only strong sample
late (and at the very last sample) so that an exit taken too early changes the answer, and they
check it against the uplift condition of Housner's rule, abs(a_g) > g·tan α (paper Section 2),
and against :func:`rocking.simulate`, which integrates every interval and has no such exit.
"""

import math

import numpy as np
import pytest

from rocking.dynamics.batch import BlockTable, motion_peaks, motion_suffixes, run_cases
from rocking.dynamics.body import Block, G
from rocking.dynamics.simulate import simulate
from rocking.motions.synthesis import generate

DT = 1 / 200  # [s]


def _late_pulse_motions(block: Block, n_t: int) -> np.ndarray:
    """Motions [m/s²] of a block of critical angle α: (0) a strong early pulse, quiet ground
    (a fifth of the uplift level) and one strong late pulse; (1) quiet ground but the last sample,
    above the uplift level; (2) quiet ground throughout, for comparison."""
    t = np.arange(n_t) * DT
    lift = G * math.tan(block.alpha)  # uplift level of a block at rest [m/s²]
    quiet = 0.2 * lift * np.sin(2 * np.pi * 1.3 * t)
    early = quiet + 3.0 * lift * np.exp(-(((t - 0.5) / 0.1) ** 2)) * np.sin(2 * np.pi * 2 * t)
    late_t = t[-1] - 0.6
    late = early + 6.0 * lift * np.exp(-(((t - late_t) / 0.1) ** 2)) * np.sin(
        2 * np.pi * 2 * (t - late_t)
    )
    last = quiet.copy()
    last[-1] = 1.5 * lift
    return np.ascontiguousarray(np.vstack([late, last, quiet]))


def _run(blocks, acc, body, motion, scale, count_steps=False, **kw):
    table = BlockTable.from_blocks(blocks)
    out = run_cases(table, acc, motion_peaks(acc), DT, body, motion, scale, **kw)
    if count_steps:
        return out.overturned, out.peak_theta_ratio, out.steps
    return out.overturned, out.peak_theta_ratio


@pytest.mark.parametrize("given", [False, True], ids=["suffixes computed", "suffixes given"])
def test_a_late_pulse_after_rest_is_not_skipped(given):
    # also with the suffix extremes computed once for the motions (motion_suffixes, as the
    # Monte Carlo engine passes them) instead of in the call: the same answers, bit for bit
    block = Block(0.5, 4.0)
    acc = _late_pulse_motions(block, 2000)  # 10 s, the late pulse at 9.4 s
    body = np.zeros(6, np.int64)
    motion = np.array([0, 1, 2, 0, 1, 2])
    scale = np.array([1.0, 1.0, 1.0, -1.0, -1.0, -1.0])
    kw = {"suffixes": motion_suffixes(acc)} if given else {}
    overturned, peak = _run([block], acc, body, motion, scale, **kw)
    for i in range(body.size):
        r = simulate(block, scale[i] * acc[motion[i]], DT)
        # the same floating-point operations as simulate (no tolerance: bit for bit)
        assert overturned[i] == r.overturned, i
        assert peak[i] == r.max_abs_theta / block.alpha, i
    # motion 0: the early pulse rocks the block and it comes to rest during the quiet part
    # (simulate: at rest from 4.7 s on); the late pulse (six times the uplift level) must overturn
    # it or at least rock it further than the early one did
    r_early = simulate(block, acc[0, :1400], DT)
    assert r_early.theta[-1] == 0.0 and r_early.omega[-1] == 0.0
    assert overturned[0] or peak[0] > r_early.max_abs_theta / block.alpha
    # motion 1: only its last sample exceeds g·tan α, so the block lifts in the last interval
    # (Housner's uplift condition): a small but nonzero peak, never an early "at rest"
    assert not overturned[1] and 0.0 < peak[1] < 1e-3
    # motion 2 never reaches g·tan α: at rest throughout, peak exactly 0
    assert not overturned[2] and peak[2] == 0.0


@pytest.mark.parametrize("given", [False, True], ids=["suffixes computed", "suffixes given"])
def test_a_late_pulse_with_vertical_motion_is_not_skipped(given):
    # with a_v the uplift level is (g + a_v)·tan α: a late downward a_v lowers it, so a late
    # sample below g·tan α may lift the block; the suffix minimum of a_v must keep the case
    block = Block.from_mass_properties(0.6, 0.15, radius_of_gyration=0.45)
    n_t = 1200
    acc = _late_pulse_motions(block, n_t)[[2]]  # quiet: a fifth of g·tan α
    acc[0, -20:] = 0.8 * G * math.tan(block.alpha)  # below g·tan α, above (g + a_v)·tan α
    av = np.zeros_like(acc)
    av[0, -20:] = -0.4 * G  # (g + a_v)·tan α = 0.6·g·tan α at the end
    body = np.zeros(1, np.int64)
    motion = np.zeros(1, np.int64)
    scale = np.ones(1)
    kw = {"suffixes": motion_suffixes(acc, av)} if given else {}
    overturned, peak = _run([block], acc, body, motion, scale, av=av, **kw)
    r = simulate(block, acc[0], DT, av=av[0])
    assert overturned[0] == r.overturned and peak[0] == r.max_abs_theta / block.alpha
    assert peak[0] > 0.0  # it lifts (0.8 > 0.6), which a test without a_v would not see


def _steps_of(r) -> int:
    """Intervals of simulate's response in which the block is not at rest at both ends (θ = θ'
    = 0), up to and including the one in which it overturns (NaN afterwards)."""
    nan = np.isnan(r.theta)
    n_int = int(np.argmax(nan)) if nan.any() else r.theta.size - 1
    still = (r.theta == 0.0) & (r.omega == 0.0)
    return int(n_int - np.count_nonzero(still[:n_int] & still[1 : n_int + 1]))


@pytest.mark.parametrize("impacts", ["located", "step-end"])
def test_step_count_equals_the_intervals_simulate_integrates(impacts):
    ens = generate(4, duration=6.0, dt=DT, seed=5)
    acc = np.ascontiguousarray(ens.acc)
    av = 0.2 * np.roll(acc, 1, axis=0)
    blocks = [
        Block(0.6, 4.0),
        Block(1.5, 6.0),
        Block.from_mass_properties(0.7, 0.2, radius_of_gyration=0.4),
    ]
    rng = np.random.default_rng(2)
    n = 36
    body = rng.integers(0, len(blocks), n)
    motion = rng.integers(0, acc.shape[0], n)
    scale = rng.uniform(-1.5, 1.5, n) / ens.agx
    for vert in (None, av):
        o, p, steps = _run(
            blocks, acc, body, motion, scale, av=vert, impacts=impacts, count_steps=True
        )
        o2, p2 = _run(blocks, acc, body, motion, scale, av=vert, impacts=impacts)
        assert np.array_equal(o, o2) and np.array_equal(p, p2)  # counting changes nothing
        kinds = set()
        for i in range(n):
            v = None if vert is None else abs(scale[i]) * vert[motion[i]]
            r = simulate(blocks[body[i]], scale[i] * acc[motion[i]], DT, av=v, impacts=impacts)
            assert steps[i] == _steps_of(r), i
            kinds.add("overturned" if r.overturned else "rest" if steps[i] == 0 else "rocked")
        # the cases cover blocks that overturn, rock and stay at rest (so the count is tested on
        # each way a case ends)
        assert kinds == {"overturned", "rocked", "rest"}, kinds
