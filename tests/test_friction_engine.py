"""Friction through the Monte Carlo engine (issue 45): overturning_probability, fragility_analysis
and agx_50 with mu count what rocking.simulate(..., mu=...) gives case by case."""

import json

import numpy as np
import pandas as pd
import pytest
from click.testing import CliRunner

from rocking.assessment.bodies import read_bodies_table, with_body_friction
from rocking.cli import main
from rocking.dynamics.body import Block, G
from rocking.dynamics.limits import parse_limit_states
from rocking.dynamics.physics import Physics
from rocking.dynamics.simulate import simulate
from rocking.errors import InputError
from rocking.montecarlo.fragility import fragility_analysis
from rocking.montecarlo.probability import agx_50, overturning_probability
from rocking.motions.ensemble import Ensemble
from rocking.motions.synthesis import generate

# a slender block (tan α = 0.2 < μ: it rocks and slide-rocks) and a squat one (tan α = 0.5 > μ:
# it slides)
BLOCKS = [Block(0.5, 5.0), Block(1.0, 2.0)]
MU = 0.3
AGX = [0.15, 0.4, 0.8]
STATES = "uplift, slip>=0.01, residual_slip>=0.005, lift>=0.001, theta/alpha>=0.5, overturn"


@pytest.fixture(scope="module")
def ensemble():
    return generate(6, duration=4.0, dt=1 / 200, seed=7)


def _direct(block, ens, agx, mu, mu_k=None):
    """Every response quantity of every motion by rocking.simulate, each motion scaled by
    agx / A_gx of the ensemble (as the engine scales it: one factor for all motions)."""
    rows = []
    for acc in ens.acc:
        r = simulate(block, (agx / ens.agx) * acc, ens.dt, mu=mu, mu_k=mu_k)
        rows.append(
            {
                "overturned": r.overturned,
                "peak_theta_ratio": r.max_abs_theta / block.alpha,
                "uplift": r.uplift,
                "peak_slip": r.max_abs_slip,
                "residual_slip": abs(r.residual_slip),
                "peak_lift": r.max_lift,
            }
        )
    return rows


def _count(rows, state):
    return sum(float(row[state.quantity]) >= state.threshold for row in rows)


def test_every_limit_state_probability_with_friction_equals_a_direct_count(ensemble):
    # exact counts: the batched kernel equals simulate(mu=) bit for bit
    states = parse_limit_states(STATES)
    p = overturning_probability(BLOCKS, ensemble, AGX, limit_states=states, mu=MU)
    f = fragility_analysis(
        BLOCKS, ensemble, levels=AGX, limit_states=states, n_boot=0, physics=Physics(mu=MU)
    )
    seen = np.zeros(len(states), dtype=int)
    for b, block in enumerate(BLOCKS):
        for a, agx in enumerate(AGX):
            rows = _direct(block, ensemble, agx, MU)
            for s, ls in enumerate(states):
                n = _count(rows, ls)
                assert int(p["count"][b, a, s]) == n, (b, agx, ls)
                assert int(f["count"][b, a, s]) == n, (b, agx, ls)
                seen[s] += n
    # every state but lift is reached by some case, and not by all: the counts are not trivial
    # (without vertical motion the base lifts only where N < 0 during rocking: none here)
    lift = [s for s, ls in enumerate(states) if ls.quantity == "peak_lift"]
    reached = np.delete(seen, lift)
    assert np.all(reached > 0) and np.all(reached < len(BLOCKS) * len(AGX) * ensemble.n), seen


def test_per_body_friction_counts_each_body_with_its_own(ensemble):
    states = parse_limit_states("slip>=0.01, overturn")
    mu, mu_k = (0.5, 0.25), (0.4, None)
    p = overturning_probability(
        BLOCKS, ensemble, AGX, limit_states=states, physics=Physics(mu=mu, mu_k=mu_k)
    )
    for b, block in enumerate(BLOCKS):
        for a, agx in enumerate(AGX):
            rows = _direct(block, ensemble, agx, mu[b], mu_k[b])
            for s, ls in enumerate(states):
                assert int(p["count"][b, a, s]) == _count(rows, ls), (b, agx, ls)


def test_agx50_with_friction_is_an_upward_crossing_of_the_direct_counts(ensemble):
    # agx_50's definition: P(A_hi) ≥ 0.5 > P(A_hi − resolution), P the fraction of motions
    states = parse_limit_states("slip>=0.02, overturn")
    res = 0.1
    ds = agx_50(BLOCKS, ensemble, resolution=res, agx_max=3.0, limit_states=states, mu=MU)
    found = 0
    for b, block in enumerate(BLOCKS):
        for s, ls in enumerate(states):
            a50 = float(ds["agx50"][b, s])
            if np.isnan(a50):
                continue
            found += 1
            hi = _count(_direct(block, ensemble, a50, MU), ls)
            assert hi >= ensemble.n / 2 and hi / ensemble.n == float(ds["probability"][b, s])
            if a50 > res + 1e-9:
                lo = _count(_direct(block, ensemble, round(a50 - res, 12), MU), ls)
                assert lo < ensemble.n / 2, (b, ls, a50)
    assert found >= 3


def test_bodies_csv_friction_columns_reach_agx50_per_body(tmp_path, ensemble):
    # one body with its own mu and mu_k, one without (it takes --mu): the command's A_gx50
    # equals agx_50 with one friction per body
    path = tmp_path / "bodies.csv"
    path.write_text("name,R,gamma,mu,mu_k\nslim,0.5,5,0.5,0.4\nsquat,1,2,,\n")
    bodies = read_bodies_table(path)
    assert (bodies[0].mu, bodies[0].mu_k, bodies[1].mu, bodies[1].mu_k) == (0.5, 0.4, None, None)
    physics = with_body_friction(Physics(mu=0.3), bodies)
    assert (physics.mu, physics.mu_k) == ((0.5, 0.3), (0.4, None))
    # a physics with one friction per block besides the bodies' own: refused, not nested
    for per_block in (Physics(mu=(0.3, 0.4)), Physics(mu=0.6, mu_k=(0.3, 0.4))):
        name = "mu" if isinstance(per_block.mu, tuple) else "mu_k"
        with pytest.raises(InputError, match=rf"physics\.{name} must be one value for all"):
            with_body_friction(per_block, bodies)
    assert with_body_friction(Physics(mu=(0.3, 0.4)), [bodies[1]] * 2).mu == (0.3, 0.4)
    motions = tmp_path / "ens.nc"
    ensemble.save(motions)
    out = tmp_path / "out"
    args = ["agx50", "--bodies", path, "--motions", motions, "--resolution", 0.1, "--mu", 0.3]
    result = CliRunner().invoke(main, [str(a) for a in [*args, "--out", out, "--quiet"]])
    assert result.exit_code == 0, result.output
    table = pd.read_csv(out / "agx50.csv")
    expected = agx_50(BLOCKS, ensemble, resolution=0.1, physics=physics)["agx50"].values
    np.testing.assert_array_equal(table["agx50_g"].values, expected)
    run = json.loads((out / "run.json").read_text())
    assert run["mu"] == [0.5, 0.3] and run["mu_k"] == [0.4, None]


def test_simulate_command_reports_slip_lift_and_modes(tmp_path):
    # a squat block (tan α = 0.5) on μ = 0.2 under El Centro at 0.6 g: it slides (Newmark's
    # block slips when the ground exceeds μ·g) and never rocks (μ < tan α: Shenton's criteria)
    args = ["simulate", "--R", 1, "--gamma", 2, "--motion", "example", "--scale-g", 0.6]
    result = CliRunner().invoke(main, [str(a) for a in [*args, "--mu", 0.2, "--json"]])
    assert result.exit_code == 0, result.output
    r = json.loads(result.output)["response"]
    assert r["mu"] == 0.2 and r["mu_k"] == 0.2 and r["max_abs_slip_m"] > 0.0
    assert r["time_in_mode_s"]["slide"] > 0.0 and r["time_in_mode_s"]["rock"] == 0.0
    assert r["max_lift_m"] == 0.0 and r["final_mode"] in ("rest", "slide")
    text = CliRunner().invoke(main, [str(a) for a in [*args, "--mu", 0.2]]).output
    assert "max |slip| =" in text and "modes:" in text
    plain = CliRunner().invoke(main, [str(a) for a in [*args, "--json"]]).output
    assert "max_abs_slip_m" not in json.loads(plain)["response"]  # without friction: as before


# lift, slip and overturning are not nested states: their fits may cross, and are kept
@pytest.mark.filterwarnings("ignore::rocking.montecarlo.statistics.CrossingWarning")
def test_fragility_with_friction_lets_the_block_fly(ensemble):
    # vertical components at 3× another motion: scaled to A_gx = 0.8 g they fall below −g (the
    # ground drops faster than gravity). Refused without friction, pointing to mu; with mu the
    # block flies, and the counts (lift included) equal simulate(mu=, av=)'s
    ens = Ensemble(
        ensemble.acc, ensemble.dt, ensemble.labels, ensemble.meta, 3.0 * ensemble.acc[::-1]
    )
    levels = [0.3, 0.8]
    assert (levels[-1] / ens.agx) * ens.av.min() < -G
    with pytest.raises(InputError, match="mu"):
        fragility_analysis(BLOCKS, ens, levels=levels, n_boot=0)
    states = parse_limit_states("lift>=0.001, slip>=0.01, overturn")
    f = fragility_analysis(BLOCKS, ens, levels=levels, n_boot=0, limit_states=states, mu=MU)
    lifted = 0
    for b, block in enumerate(BLOCKS):
        for a, agx in enumerate(levels):
            k = agx / ens.agx
            rows = []
            for acc, av in zip(ens.acc, ens.av):
                r = simulate(block, k * acc, ens.dt, av=k * av, mu=MU)
                rows.append(
                    {
                        "peak_lift": r.max_lift,
                        "peak_slip": r.max_abs_slip,
                        "overturned": r.overturned,
                    }
                )
            for s, ls in enumerate(states):
                assert int(f["count"][b, a, s]) == _count(rows, ls), (b, agx, ls)
            lifted += _count(rows, states[0])
    assert lifted > 0
