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


def test_a_case_searched_before_in_the_run_is_not_searched_again(monkeypatch):
    # agx_50's result for one case depends on that case's motions and the settings only (the
    # comparisons with n/2 are exact counts): a second search of the same motions inside
    # reusing() (as the soundness section repeats Section 8's ground search) simulates nothing
    # and returns what a search from scratch returns, bit for bit.  Searches with other
    # settings are not recalled (they run, on the outcomes the run's engines share: see the
    # next test, and may then simulate nothing either).
    import rocking.montecarlo.probability as probability
    from rocking.dynamics.body import Block
    from rocking.montecarlo.probability import agx_50
    from rocking.motions.synthesis import generate

    recalled = []
    real_recall = probability.recall

    def recall(key):
        found = real_recall(key)
        recalled.append(found is not None)
        return found

    monkeypatch.setattr(probability, "recall", recall)

    ground = generate(12, duration=6.0, dt=1 / 200, seed=21)
    floor = generate(12, duration=6.0, dt=1 / 200, seed=22)
    blocks = [Block(0.5, 3.0), Block(1.0, 4.0)]
    kw = dict(resolution=0.05, agx_max=3.0)
    fresh = agx_50(blocks, ground, **kw)
    assert fresh.attrs["chunks_computed"] > 0 and np.isfinite(fresh["agx50"].values).all()
    with reusing():
        both = agx_50(blocks, {"ground": ground, "floor": floor}, **kw)
        recalled.clear()
        again = agx_50(blocks, ground, **kw)
        assert again.attrs["chunks_computed"] == 0 and recalled == [True]
        for var in ("agx50", "probability", "probability_below"):
            np.testing.assert_array_equal(again[var].values, fresh[var].values)
            np.testing.assert_array_equal(both[var].sel(case="ground").values, fresh[var].values)
        # other settings, other motions or the outcomes of every motion: searched, not
        # recalled, with the results of searches from scratch (compared below)
        recalled.clear()
        coarse = agx_50(blocks, ground, resolution=0.1, agx_max=3.0)
        one = agx_50(blocks[:1], ground, **kw)
        members = agx_50(blocks, ground, members=True, **kw)
        assert not any(recalled)
        mixed = agx_50(
            blocks, {"floor": floor, "other": generate(12, duration=6.0, dt=1 / 200, seed=23)}, **kw
        )
        np.testing.assert_array_equal(
            mixed["agx50"].sel(case="floor").values, both["agx50"].sel(case="floor").values
        )
    np.testing.assert_array_equal(one["agx50"].values, fresh["agx50"].values[:1])
    np.testing.assert_array_equal(
        coarse["agx50"].values, agx_50(blocks, ground, resolution=0.1, agx_max=3.0)["agx50"].values
    )
    scratch = agx_50(blocks, ground, members=True, **kw)
    for var in ("agx50", "overturned"):
        np.testing.assert_array_equal(members[var].values, scratch[var].values)


def test_the_engines_of_a_run_share_their_outcomes(monkeypatch):
    # Inside reusing(), every Monte Carlo engine takes the outcomes that the run's engines
    # simulated before, keyed by the motions' contents and scaling, the impact scheme and the
    # body's constants, and simulates only the others (counted here at the batched kernel's
    # entry).  Everything that decides an outcome is in the key, so the results are those of
    # calls that simulate everything (outside reusing(), compared bit for bit below); a
    # setting that changes the outcomes (restitution, impact scheme, another body, other
    # motions) is simulated again.
    import rocking.montecarlo.engine as engine_module
    from rocking.dynamics.body import Block
    from rocking.montecarlo.probability import member_outcomes, overturning_probability
    from rocking.motions.synthesis import generate

    simulated = []
    real_run_cases = engine_module.run_cases

    def counting(table, acc, amax, dt, body, motion, scale, **kw):
        simulated.append(body.size)
        return real_run_cases(table, acc, amax, dt, body, motion, scale, **kw)

    monkeypatch.setattr(engine_module, "run_cases", counting)
    ground = generate(10, duration=5.0, dt=1 / 200, seed=31)
    other_motions = generate(10, duration=5.0, dt=1 / 200, seed=32)
    blocks = [Block(0.5, 3.0), Block(1.0, 4.0)]
    levels = [0.2, 0.35]
    calls = [
        lambda: overturning_probability(blocks, ground, levels, members=True),
        # the same outcomes asked by another kind of engine, bodies in another order
        lambda: member_outcomes(blocks[::-1], ground, [0.35, 0.2]),
        # partly known: only each body's level 0.5 is new (2 bodies x 10 motions)
        lambda: member_outcomes(blocks, ground, [[0.2, 0.5], [0.35, 0.5]]),
        lambda: overturning_probability(blocks, ground, levels, members=True, e=0.9),
        lambda: overturning_probability(blocks, ground, levels, members=True, impacts="step-end"),
        lambda: overturning_probability([Block(0.5, 3.5)], ground, levels, members=True),
        lambda: overturning_probability(blocks, other_motions, levels, members=True),
    ]
    shared, counts = [], []
    with reusing():
        for call in calls:
            simulated.clear()
            shared.append(call())
            counts.append(sum(simulated))
    assert counts == [40, 0, 20, 40, 40, 20, 40]
    for call, result in zip(calls, shared):
        alone = call()
        for var in ("overturned", "peak"):
            np.testing.assert_array_equal(result[var].values, alone[var].values)


def test_the_shared_outcomes_stop_growing_at_their_budget(monkeypatch):
    # Past rocking.montecarlo.engine._BOOK_BYTES no outcome is added (a run's memory stays
    # bounded whatever its size): with a budget below one (body, level) entry, nothing is
    # shared, and every engine simulates everything, with the same results.
    import rocking.montecarlo.engine as engine_module
    from rocking.dynamics.body import Block
    from rocking.montecarlo.probability import member_outcomes, overturning_probability
    from rocking.motions.synthesis import generate

    ground = generate(6, duration=4.0, dt=1 / 200, seed=41)
    blocks = [Block(0.5, 3.0)]
    monkeypatch.setattr(engine_module, "_BOOK_BYTES", engine_module._ENTRY_BYTES)
    with reusing():
        first = overturning_probability(blocks, ground, [0.3], members=True)
        again = member_outcomes(blocks, ground, [0.3])
    assert first.attrs["chunks_computed"] > 0 and again.attrs["chunks_computed"] > 0
    np.testing.assert_array_equal(again["peak"].values[:, 0], first["peak"].values[:, 0])
