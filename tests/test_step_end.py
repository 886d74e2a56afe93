"""The fixed-step impact scheme ``impacts="step-end"`` (issue 17), against RK4 worked by hand.

The scheme: a classical RK4 step of the motion's dt; when the step ends on the other side of
θ = 0 the block is put at θ = 0 on the other pivot with θ' ← e·θ' (θ' of the step's end), and no
impact is located inside the step.  The test computes two steps from the RK4 formulas with libm
sine (Eq. 1 for a free block, a_g = 0) and checks :func:`rocking.simulate` and the batched
kernel against them; it also checks that the default ("located") is a different scheme.
"""

from __future__ import annotations

import math

import numpy as np
import pytest

from rocking import Block, G, InputError, simulate
from rocking.dynamics.batch import overturn_cases
from rocking.motions.synthesis import generate


def _rk4_by_hand(theta, omega, s, h, p2, alpha):
    """One classical RK4 step of θ'' = −p²·sin(sα − θ) (Eq. 1, a_g = 0) from (θ, θ')."""

    def f(th):
        return -p2 * math.sin(s * alpha - th)

    k1t, k1w = omega, f(theta)
    k2t, k2w = omega + h / 2 * k1w, f(theta + h / 2 * k1t)
    k3t, k3w = omega + h / 2 * k2w, f(theta + h / 2 * k2t)
    k4t, k4w = omega + h * k3w, f(theta + h * k3t)
    return (
        theta + h / 6 * (k1t + 2 * k2t + 2 * k3t + k4t),
        omega + h / 6 * (k1w + 2 * k2w + 2 * k3w + k4w),
    )


def test_step_end_impacts_follow_rk4_worked_by_hand():
    block = Block(1.0, 4.0)
    p2, alpha = block.p_squared(G), block.alpha
    dt, e = 0.02, 0.8
    theta0, omega0 = 0.004, -0.5  # on pivot O (θ > 0), falling back: θ = 0 within the step
    # step 1 on side s = +1 ends at θ < 0: the impact is taken there
    th1, om1 = _rk4_by_hand(theta0, omega0, 1.0, dt, p2, alpha)
    assert th1 < 0.0
    theta1, omega1 = 0.0, e * om1  # now on pivot O' (s = −1)
    # step 2 on side s = −1 from θ = 0
    th2, om2 = _rk4_by_hand(theta1, omega1, -1.0, dt, p2, alpha)
    assert th2 < 0.0  # still on O'
    r = simulate(block, np.zeros(3), dt, e=e, theta0=theta0, omega0=omega0, impacts="step-end")
    # the kernel evaluates the same RK4 formulas with polynomial sine/cosine and fused
    # multiply–adds: agreement to a few ulp of the terms (1e-13 relative)
    assert r.theta[1] == 0.0 and r.n_impacts == 1
    assert r.omega[1] == pytest.approx(omega1, rel=1e-13)
    assert r.theta[2] == pytest.approx(th2, rel=1e-13)
    assert r.omega[2] == pytest.approx(om2, rel=1e-13)
    # the default locates the impact inside step 1 and integrates the rest of it from there:
    # another state (by about θ''·δt·dt, here ~1e-4 rad/s)
    located = simulate(block, np.zeros(3), dt, e=e, theta0=theta0, omega0=omega0)
    assert located.n_impacts == 1 and located.theta[1] != 0.0
    assert abs(located.omega[2] - r.omega[2]) > 1e-5


def test_step_end_in_the_batched_kernel_equals_simulate():
    ens = generate(4, duration=6.0, dt=1 / 200, seed=3)
    rng = np.random.default_rng(21)
    blocks = [Block(0.6, 3.0), Block(1.5, 5.0), Block(1.0, 4.0, r_g=0.45)]
    n = 48
    body = rng.integers(0, len(blocks), n)
    motion = rng.integers(0, ens.n, n)
    scale = rng.uniform(-1.5, 1.5, n) / ens.agx
    ov, pk = overturn_cases(blocks, ens.acc, ens.dt, body, motion, scale, impacts="step-end")
    differ = 0
    for i in range(n):
        blk = blocks[body[i]]
        r = simulate(blk, scale[i] * ens.acc[motion[i]], ens.dt, impacts="step-end")
        # the same compiled operations (bit for bit, as for the default scheme)
        assert ov[i] == r.overturned and pk[i] == r.max_abs_theta / blk.alpha, i
        d = simulate(blk, scale[i] * ens.acc[motion[i]], ens.dt)
        differ += d.overturned != r.overturned or d.max_abs_theta != r.max_abs_theta
    assert 0 < ov.mean() < 1
    assert differ > n // 4  # the two schemes are different schemes


def test_unknown_impact_scheme_is_refused():
    with pytest.raises(InputError, match=r"\bimpacts\b"):
        simulate(Block(1.0, 3.0), np.zeros(4), 0.01, impacts="fixed")
    with pytest.raises(InputError, match=r"\bimpacts\b"):
        overturn_cases([Block(1.0, 3.0)], np.ones((1, 4)), 0.01, [0], [0], [1.0], impacts=None)
