"""Results reused within a run (rocking.core.reuse): only for inputs with the same contents."""

import numpy as np
import pytest

import rocking.motions.response as response
from rocking.core.reuse import digest, reused, reusing
from rocking.motions.response import response_spectrum


@pytest.fixture
def counted(monkeypatch):
    """Counts the calls of the response spectra's compiled part."""
    calls = []
    real = response._peak_displacements

    def counting(*args):
        calls.append(1)
        return real(*args)

    monkeypatch.setattr(response, "_peak_displacements", counting)
    return calls


def test_a_spectrum_is_computed_once_per_distinct_motion_inside_reusing(counted):
    rng = np.random.default_rng(5)
    acc = rng.standard_normal((3, 400))
    freqs = np.array([0.5, 2.0, 8.0])
    with reusing():
        first = response_spectrum(acc, 0.01, freqs)
        again = response_spectrum(acc.copy(), 0.01, freqs)  # another array, the same contents
        assert len(counted) == 1
        np.testing.assert_array_equal(first.psv, again.psv)
        # a caller may change what it got without changing what the next caller gets
        first.sd[:] = 0.0
        np.testing.assert_array_equal(response_spectrum(acc, 0.01, freqs).sd, again.sd)
        assert len(counted) == 1
        # one sample, the time step, the damping or the frequencies changed: computed anew
        other = acc.copy()
        other[1, 200] += 1e-9
        changed = response_spectrum(other, 0.01, freqs)
        assert not np.array_equal(changed.sd[1], again.sd[1])
        response_spectrum(acc, 0.02, freqs)
        response_spectrum(acc, 0.01, freqs, damping=0.02)
        response_spectrum(acc, 0.01, freqs[:2])
        assert len(counted) == 5
    # outside the block nothing is kept
    response_spectrum(acc, 0.01, freqs)
    response_spectrum(acc, 0.01, freqs)
    assert len(counted) == 7


def test_nested_blocks_share_the_results_and_the_outer_one_keeps_them():
    calls = []

    def compute():
        calls.append(1)
        return np.ones(2)

    with reusing():
        with reusing():
            reused("x", (1.0,), compute)
        reused("x", (1.0,), compute)
        reused("y", (1.0,), compute)  # another kind of result
    assert len(calls) == 2


def test_the_digest_sees_every_bit_of_the_inputs():
    base = digest((np.zeros((2, 3)), 0.0, "a"))
    assert digest((np.zeros((2, 3)), 0.0, "a")) == base
    assert digest((np.zeros((3, 2)), 0.0, "a")) != base  # shape
    assert digest((np.zeros((2, 3), np.float32), 0.0, "a")) != base  # dtype
    assert digest((np.zeros((2, 3)), -0.0, "a")) != base  # the sign of a zero
    assert digest((np.zeros((2, 3)), 5e-324, "a")) != base  # the smallest float
    assert digest((np.zeros((2, 3)), 0, "a")) != base  # an int is not a float
    assert digest((np.zeros((2, 3)), 0.0, "b")) != base
    assert digest(np.zeros((2, 0))) != digest(np.zeros((0, 2)))  # no elements, other shapes
    assert digest({"a": 1, "b": 2}) == digest({"b": 2, "a": 1})
    with pytest.raises(TypeError, match="cannot key"):
        digest((object(),))
    with pytest.raises(TypeError, match="cannot key"):
        digest(np.array([object()]))  # its bytes would be addresses, not contents


def test_a_case_searched_before_in_the_run_is_not_searched_again():
    # agx_50's result for one case depends on that case's motions and the settings only (the
    # comparisons with n/2 are exact counts): a second search of the same motions inside
    # reusing() (as the soundness section repeats Section 8's ground search) simulates nothing
    # and returns what a search from scratch returns, bit for bit.
    from rocking.dynamics.body import Block
    from rocking.montecarlo.probability import agx_50
    from rocking.motions.synthesis import generate

    ground = generate(12, duration=6.0, dt=1 / 200, seed=21)
    floor = generate(12, duration=6.0, dt=1 / 200, seed=22)
    blocks = [Block(0.5, 3.0), Block(1.0, 4.0)]
    kw = dict(resolution=0.05, agx_max=3.0)
    fresh = agx_50(blocks, ground, **kw)
    assert fresh.attrs["chunks_computed"] > 0 and np.isfinite(fresh["agx50"].values).all()
    with reusing():
        both = agx_50(blocks, {"ground": ground, "floor": floor}, **kw)
        again = agx_50(blocks, ground, **kw)
        assert again.attrs["chunks_computed"] == 0
        for var in ("agx50", "probability", "probability_below"):
            np.testing.assert_array_equal(again[var].values, fresh[var].values)
            np.testing.assert_array_equal(both[var].sel(case="ground").values, fresh[var].values)
        # other settings, other motions or the outcomes of every motion: searched
        assert agx_50(blocks, ground, resolution=0.1, agx_max=3.0).attrs["chunks_computed"] > 0
        assert agx_50(blocks[:1], ground, **kw).attrs["chunks_computed"] > 0
        assert agx_50(blocks, ground, members=True, **kw).attrs["chunks_computed"] > 0
        mixed = agx_50(
            blocks, {"floor": floor, "other": generate(12, duration=6.0, dt=1 / 200, seed=23)}, **kw
        )
        np.testing.assert_array_equal(
            mixed["agx50"].sel(case="floor").values, both["agx50"].sel(case="floor").values
        )
