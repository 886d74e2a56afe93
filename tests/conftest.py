"""Shared checks of the tests."""

import numpy as np
import pytest


def _matches_reference(ours, ref, case) -> None:
    """``rocking.simulate``'s result ``ours`` against the SciPy reference ``ref`` (DOP853 at
    rtol 1e-10 with located events) on the same case: the same outcome; a located overturning
    within 1e-3 s (RK4 at dt = 1/100 s; measured at most 3e-5 s); otherwise issue 2's bounds,
    max abs(θ) within 1 % and the whole history within 2 % of it (measured at most 3e-4 and
    0.4 %, in chatters whose impact times shift slightly)."""
    assert ours.overturned == ref.overturned, case
    if ours.overturned:
        assert ours.t_overturn == pytest.approx(ref.t_overturn, abs=1e-3), case
        return
    assert ours.max_abs_theta == pytest.approx(ref.max_abs_theta, rel=0.01), case
    np.testing.assert_allclose(ours.theta, ref.theta, rtol=0, atol=0.02 * ref.max_abs_theta)


@pytest.fixture
def matches_reference():
    """The check :func:`_matches_reference`."""
    return _matches_reference


@pytest.fixture
def simulations(monkeypatch):
    """Counts the simulations handed to the batched kernel (by the Monte Carlo engine)."""
    import rocking.montecarlo.engine as engine_module

    count = [0]
    run_cases = engine_module.run_cases

    def counting(table, acc, amax, dt, body, *args, **kwargs):
        count[0] += body.size
        return run_cases(table, acc, amax, dt, body, *args, **kwargs)

    monkeypatch.setattr(engine_module, "run_cases", counting)
    return count
