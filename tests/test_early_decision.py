"""agx_50 decides each level's comparison with n/2 from as few motions as can decide it (issue 18):
the rule checked against brute force, the search's result against the exhaustive search, and the
chunk store with (body, level) pairs of which only some motions were simulated."""

import numpy as np
import pytest
import xarray as xr

from rocking.defaults import DEFAULT_E, G
from rocking.dynamics.batch import Outcome
from rocking.dynamics.body import Block
from rocking.errors import InputError
from rocking.montecarlo.engine import Engine, level_key
from rocking.montecarlo.probability import agx_50, overturning_probability
from rocking.montecarlo.search import motions_to_decide
from rocking.motions.synthesis import generate
from rocking.studies.soundness import refine

RUN_STATS = ("chunks_computed", "chunks_loaded")
BLOCKS = [Block(0.8, 3.0), Block(1.22, 4.0), Block(2.0, 2.5)]


@pytest.fixture(scope="module")
def ensemble():
    # 24 motions: enough for a level to be decided before its last motions
    return generate(24, duration=5.0, dt=1 / 200, seed=11)


def _science(ds):
    out = ds.copy()
    out.attrs = {k: v for k, v in ds.attrs.items() if k not in RUN_STATS}
    return out


def _bytes_equal(a, b):
    xr.testing.assert_identical(_science(a), _science(b))
    for name in a.data_vars:
        assert a[name].values.tobytes() == b[name].values.tobytes(), name


def _decided(n, overturned, safe):
    """Brute force: every way the other motions can turn out gives the same answer."""
    rest = n - overturned - safe
    return (2 * overturned >= n) == (2 * (overturned + rest) >= n)


@pytest.mark.parametrize("n", range(1, 12))
def test_motions_to_decide_is_the_fewest_outcomes_that_can_decide(n):
    # brute force over every state (overturned, safe) and every outcome of j more motions: the
    # rule returns the smallest j after which some outcome decides the comparison (0: decided)
    for overturned in range(n + 1):
        for safe in range(n + 1 - overturned):
            rest = n - overturned - safe
            fewest = next(
                j
                for j in range(rest + 1)
                if any(_decided(n, overturned + i, safe + j - i) for i in range(j + 1))
            )
            assert motions_to_decide(n, overturned, safe) == fewest, (overturned, safe)
    with pytest.raises(InputError, match="overturned"):
        motions_to_decide(n, n, 1)


def test_early_decision_gives_the_exhaustive_result_with_fewer_simulations(ensemble, simulations):
    # the exhaustive search counts every motion at every level it visits (the search before
    # issue 18); deciding from fewer motions must give the same bytes, including the returned
    # probabilities, and must simulate fewer cases (here about a fifth fewer)
    full = agx_50(BLOCKS, ensemble, resolution=0.05, exhaustive=True)
    exhaustive = simulations[0]
    simulations[0] = 0
    early = agx_50(BLOCKS, ensemble, resolution=0.05)
    assert np.all(np.isfinite(early["agx50"].values))
    _bytes_equal(full, early)
    assert simulations[0] < 0.9 * exhaustive


def _engine(ensemble, out=None):
    return Engine(
        BLOCKS[:1],
        [ensemble],
        e=DEFAULT_E,
        overturn_angle=np.pi / 2,
        g=G,
        backend=None,
        out=out,
        progress=False,
        chunk_size=None,
        desc="one body",
    )


def _outcome(overturned, peak):
    """The engine's record of motions that overturned or reached ``peak`` = max|θ|/α."""
    zero = np.zeros(peak.size)  # no slip, no lift: infinite friction
    return Outcome(overturned, peak, peak > 0.0, zero, zero, zero, np.zeros(peak.size, np.int64))


def test_decision_order_puts_the_motions_likeliest_to_decide_first(ensemble):
    # outcomes known at the body's other levels (recorded by hand, nothing simulated) rank the
    # motions of level 500: a motion that overturned at a lower level is likely to overturn,
    # one survived at a higher level likely not to, the others rank by their peak at the
    # nearest lower level survived (or overturning above); the likely side comes first
    n, motions = ensemble.n, np.arange(ensemble.n)
    assert n == 24
    assert _engine(ensemble).decision_order((0, 0, 500)).tolist() == list(range(n))  # unknown
    # 0-15 overturned at 400, 16-23 survived with peaks 0.67-0.96: likely >= half, likeliest
    # first (the overturned in their order, then the survivors by falling peak)
    eng = _engine(ensemble)
    eng._record(
        0, 0, 400, motions, _outcome(motions < 16, np.where(motions < 16, 2.0, motions / n))
    )
    assert eng.decision_order((0, 0, 500)).tolist() == [*range(16), *range(23, 15, -1)]
    # 0-3 overturned at 400, 4-23 survived with peaks 0.04-0.23: fewer than half likely, the
    # least likely first (the survivors by rising peak, the overturned last)
    eng = _engine(ensemble)
    eng._record(
        0, 0, 400, motions, _outcome(motions < 4, np.where(motions < 4, 2.0, motions / 100))
    )
    assert eng.decision_order((0, 0, 500)).tolist() == [*range(4, 24), *range(4)]
    # only a higher level known: 0-4 survived there (likely safe), 5-23 overturned there
    # (slightly likely): likely >= half, 5-23 first
    eng = _engine(ensemble)
    eng._record(0, 0, 600, motions, _outcome(motions >= 5, np.where(motions >= 5, 2.0, 0.5)))
    assert eng.decision_order((0, 0, 500)).tolist() == [*range(5, 24), *range(5)]
    # the order is only the order: the answer of at_least_half is that of the full count
    full = overturning_probability(BLOCKS[:1], ensemble, [0.5], members=True)
    eng = _engine(ensemble)
    with eng:
        key = (0, 0, level_key(0.5))
        eng._record(0, 0, level_key(0.4), motions, _outcome(motions < 16, np.full(n, 0.5)))
        answer = eng.at_least_half([key])[key]
    assert answer == (2 * int(full["count"].values[0, 0]) >= n)


def test_same_motions_give_the_same_search_with_fewer_simulations(ensemble, simulations):
    # the ensemble and its refinement to half the step (the same piecewise-linear motions, as
    # in the soundness section): searched as the same motions, the finer one simulates first
    # the motions whose outcome at a level the coarser one found; the results must be those of
    # the two searches made apart, bit for bit, from fewer simulations
    cases = {"coarse": ensemble, "fine": refine(ensemble, 2)}
    apart = agx_50(BLOCKS, cases, resolution=0.05)
    n_apart = simulations[0]
    simulations[0] = 0
    together = agx_50(BLOCKS, cases, resolution=0.05, same_motions=True)
    _bytes_equal(apart, together)
    assert simulations[0] < n_apart
    with pytest.raises(InputError, match="same number of motions"):
        agx_50(BLOCKS, {"a": ensemble, "b": ensemble.subset(range(10))}, same_motions=True)


def test_partial_chunks_resume_and_complete(ensemble, tmp_path, simulations):
    early = agx_50(BLOCKS, ensemble, resolution=0.05, out=tmp_path)
    computed = simulations[0]
    # the same search again: every partial (body, level) is loaded, nothing simulated
    again = agx_50(BLOCKS, ensemble, resolution=0.05, out=tmp_path)
    assert simulations[0] == computed and again.attrs["chunks_computed"] == 0
    _bytes_equal(early, again)
    # the exhaustive search in the same folder simulates only the motions the chunks lack: every
    # motion of the visited levels (those of a fresh exhaustive search) but the early ones
    full = agx_50(BLOCKS, ensemble, resolution=0.05, out=tmp_path, exhaustive=True)
    _bytes_equal(early, full)
    added = simulations[0] - computed
    simulations[0] = 0
    agx_50(BLOCKS, ensemble, resolution=0.05, exhaustive=True)
    assert added == simulations[0] - computed > 0


def test_chunks_with_every_motion_of_a_pair_still_load(ensemble, tmp_path):
    # chunks written before motions were simulated in parts hold (pairs, motions) arrays and no
    # motion indices; a folder holding one is resumed from it
    agx = 0.6
    ref = overturning_probability(BLOCKS[:1], ensemble, [agx], members=True)
    old = _engine(ensemble, out=tmp_path)
    with old:
        old.store.save(
            "old-format",
            case=np.int64(0),
            body=np.array([0]),
            level=np.array([level_key(agx)]),
            overturned=ref["overturned"].values[0],
            peak=ref["peak"].values[0],
        )
    resumed = overturning_probability(BLOCKS[:1], ensemble, [agx], members=True, out=tmp_path)
    assert resumed.attrs["chunks_loaded"] == 1 and resumed.attrs["chunks_computed"] == 0
    _bytes_equal(ref, resumed)


def test_chunks_written_before_friction_still_load(ensemble, tmp_path):
    # chunks written before issue 45 hold the Outcome record without the slip and lift
    # quantities: a frictionless run (the only kind they can belong to, friction being in the
    # fingerprint) resumes from them, with no slip and no lift, and simulates nothing
    agx = 0.6
    ref = overturning_probability(
        BLOCKS[:1], ensemble, [agx], members=True, limit_states="uplift, slip>=0.001, overturn"
    )
    engine = _engine(ensemble)
    with engine:
        engine.run([(0, 0, level_key(agx))])
    outcome = engine.results[(0, 0, level_key(agx))]
    old = _engine(ensemble, out=tmp_path)
    with old:
        old.store.save(
            "before-friction",
            case=np.int64(0),
            body=np.zeros(ensemble.n, np.int64),
            level=np.full(ensemble.n, level_key(agx)),
            motion=np.arange(ensemble.n, dtype=np.int64),
            overturned=outcome.overturned,
            peak_theta_ratio=outcome.peak_theta_ratio,
            uplift=outcome.uplift,
            steps=outcome.steps,
        )
    resumed = overturning_probability(
        BLOCKS[:1],
        ensemble,
        [agx],
        members=True,
        limit_states="uplift, slip>=0.001, overturn",
        out=tmp_path,
    )
    assert resumed.attrs["chunks_loaded"] == 1 and resumed.attrs["chunks_computed"] == 0
    _bytes_equal(ref, resumed)
    # no slip without friction: the slip limit state is never exceeded, uplift sometimes is
    counts = resumed["count"].sel(limit_state="slip>=0.001").values
    assert counts.sum() == 0 and resumed["count"].sel(limit_state="uplift").values.sum() > 0
