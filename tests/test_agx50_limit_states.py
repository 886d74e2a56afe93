"""The A_gx of 50 % probability of each limit state (issue 44): ``agx_50(..., limit_states=...)``
and ``rocking agx50 --limit-states``, checked against brute-force counts on the whole grid."""

import math

import numpy as np
import pandas as pd
import pytest
import xarray as xr
from click.testing import CliRunner

from rocking.cli import main
from rocking.defaults import G
from rocking.dynamics.body import Block
from rocking.montecarlo.engine import Engine
from rocking.montecarlo.probability import agx_50, overturning_probability
from rocking.motions.synthesis import generate

BLOCKS = [Block(0.5, 5.0), Block(1.0, 4.0), Block(0.8, 3.0)]
STATES = "uplift, theta/alpha>=0.5, overturn"
#: Nested states, from the least severe: uplift ⊇ θ/α ≥ x ⊇ overturning, case by case.
NESTED = "uplift, theta/alpha>=0.2, theta/alpha>=0.5, theta/alpha>=1, overturn"
RESOLUTION, K, COARSE = 0.05, 20, 5  # the grid A_k = 0.05·k g, k = 1 … 20 (to 1 g)


@pytest.fixture(scope="module")
def ensemble():
    """9 motions of 6 s at 200 Hz (an odd n: "at least half" is 5): the bodies uplift, rock
    and overturn below 1 g."""
    return generate(9, duration=6.0, dt=1 / 200, seed=5)


@pytest.fixture(scope="module")
def brute(ensemble):
    """Counts of every nested limit state at every grid level, every motion simulated:
    (body, level 1 … K, state), with the level 0 (P = 0) in front."""
    grid = [round(k * RESOLUTION, 12) for k in range(1, K + 1)]
    p = overturning_probability(BLOCKS, ensemble, grid, limit_states=NESTED)
    count = p["count"].values
    return np.concatenate([np.zeros_like(count[:, :1]), count], axis=1)


def _search(above: np.ndarray) -> tuple[int | None, set[int]]:
    """agx_50's docstring on the full counts: ``above[k]`` (2·count ≥ n at level k, k = 0 … K)
    bracketed at the COARSE levels ⌈K·i/COARSE⌉, then bisected; (the crossing level or None,
    the levels visited)."""
    grid = sorted({math.ceil(K * i / COARSE) for i in range(1, COARSE + 1)})
    visited, lo = set(), 0
    for level in grid:
        visited.add(level)
        if above[level]:
            hi = level
            break
        lo = level
    else:
        return None, visited
    while hi - lo > 1:
        mid = (lo + hi) // 2
        visited.add(mid)
        lo, hi = (lo, mid) if above[mid] else (mid, hi)
    return hi, visited


def _on_grid(ensemble, **options):
    """agx_50 of BLOCKS on the grid of :func:`brute` (K levels of RESOLUTION, COARSE)."""
    return agx_50(
        BLOCKS, ensemble, resolution=RESOLUTION, agx_max=K * RESOLUTION, coarse=COARSE, **options
    )


@pytest.mark.parametrize("exhaustive", [False, True])
def test_every_state_agx50_is_the_crossing_of_the_brute_force_counts(ensemble, brute, exhaustive):
    # the adaptive search, with early decisions and simulations shared among the states,
    # against the docstring's definition applied to the full counts of overturning_probability
    # on the same grid (exact: integer counts of the same simulations, no tolerance)
    ds = _on_grid(ensemble, limit_states=NESTED, exhaustive=exhaustive)
    assert ds["agx50"].dims == ("body", "limit_state")
    assert list(ds["quantity"].values) == ["uplift", *["peak_theta_ratio"] * 3, "overturned"]
    n = ensemble.n
    found = 0
    for b in range(len(BLOCKS)):
        for s in range(brute.shape[2]):
            count = brute[b, :, s]
            above = 2 * count >= n
            hi, _ = _search(above)
            got = float(ds["agx50"][b, s])
            if hi is None:
                assert math.isnan(got), (b, s)
                continue
            found += 1
            assert got == round(hi * RESOLUTION, 12), (b, s)
            # an upward crossing: P ≥ 0.5 there, < 0.5 one step below
            assert above[hi] and not above[hi - 1]
            if np.all(np.diff(above.astype(int)) >= 0):  # monotone: the first level at 50 %
                assert hi == int(np.argmax(above)), (b, s)
            assert float(ds["probability"][b, s]) == count[hi] / n
            assert float(ds["probability_below"][b, s]) == count[hi - 1] / n
    # the test sees crossings of every state, at different levels
    assert found >= 2 * brute.shape[2]
    assert len(np.unique(ds["agx50"].values[np.isfinite(ds["agx50"].values)])) >= 4


def test_nested_states_have_ordered_agx50(ensemble):
    # P(a less severe state) ≥ P(a severer one) at every level on the same motions, so the
    # search of the less severe brackets and bisects no later: agx50 grows with severity, and
    # a state not reached by agx_max leaves every severer one unreached (more bodies and a
    # finer grid than above, so that the order is tested where the states differ by one step)
    blocks = [Block(r, g) for r in (0.4, 0.8, 1.5) for g in (2.5, 4.0, 6.0)]
    ds = agx_50(blocks, ensemble, resolution=0.02, agx_max=1.2, limit_states=NESTED)
    a50 = ds["agx50"].values
    reached = np.isfinite(a50)
    assert np.all(reached[:, :-1] >= reached[:, 1:])  # unreached: the severer too
    both = reached[:, :-1] & reached[:, 1:]
    assert np.all(a50[:, :-1][both] <= a50[:, 1:][both])
    assert np.any(a50[:, :-1][both] < a50[:, 1:][both])  # the states do differ
    assert reached[:, -1].sum() >= 3  # and some bodies overturn


def test_uplift_agx50_is_where_half_the_scaled_pgas_pass_g_tan_alpha(ensemble):
    # physics: a block at rest uplifts once the ground acceleration exceeds g·tan α (Housner
    # 1963), so a motion of PGA p (at the ensemble's scale, A_gx0) uplifts the block at A_gx = A
    # iff p·A/A_gx0 > g·tan α: P(uplift) is monotone in A, and its A_gx50 is the first grid level
    # where half the motions pass.  Exact: the kernel compares the same scaled samples (a tie
    # within rounding of the threshold would need a PGA within 1e-16 of it)
    blocks = [Block(r, g) for r in (0.5, 1.5) for g in (1.5, 2.5, 4.0, 7.0)]
    ds = agx_50(blocks, ensemble, resolution=0.01, agx_max=2.0, limit_states="uplift")
    pga = np.abs(ensemble.acc).max(axis=1)  # [m/s²]
    grid = np.round(np.arange(1, 201) * 0.01, 12)
    for b, block in enumerate(blocks):
        passing = (pga[None, :] * (grid[:, None] / ensemble.agx) > G * math.tan(block.alpha)).sum(1)
        assert np.any(2 * passing >= ensemble.n)  # reached below agx_max
        expected = grid[np.argmax(2 * passing >= ensemble.n)]
        assert float(ds["agx50"][b, 0]) == expected, block
    # the slenderest at about g tan α (the median motion's PGA is near the mean): 1/7 g
    assert abs(float(ds["agx50"][-1, 0]) - 1 / 7) < 0.05


def test_the_states_share_their_simulations(ensemble, brute, simulations):
    # exhaustive: every motion at every level that some state's search visits (and at the
    # crossing and the level below it), each (body, level, motion) simulated once
    levels = [set() for _ in BLOCKS]
    for b in range(len(BLOCKS)):
        for s in range(brute.shape[2]):
            hi, visited = _search(2 * brute[b, :, s] >= ensemble.n)
            levels[b] |= visited | ({hi, hi - 1} - {0} if hi else set())
    _on_grid(ensemble, limit_states=NESTED, exhaustive=True)
    assert simulations[0] == ensemble.n * sum(len(v) for v in levels)
    # with early decisions, fewer than the states searched one by one
    simulations[0] = 0
    _on_grid(ensemble, limit_states=NESTED)
    together = simulations[0]
    simulations[0] = 0
    for state in NESTED.split(","):
        _on_grid(ensemble, limit_states=state)
    assert together < simulations[0]


def test_overturn_alone_is_the_default_search(ensemble):
    # the limit state "overturn" gives the default's numbers, which keep their shape (no
    # limit_state dimension); members: "exceeded" per limit state, as fragility_analysis
    plain = _on_grid(ensemble, members=True)
    assert "limit_state" not in plain.dims and plain["overturned"].dims == ("body", "member")
    one = _on_grid(ensemble, members=True, limit_states="overturn")
    for name in ("agx50", "probability", "probability_below"):
        np.testing.assert_array_equal(one[name].values[:, 0], plain[name].values)
    np.testing.assert_array_equal(one["exceeded"].values[..., 0], plain["overturned"].values)


def test_the_command_writes_a_row_per_body_and_limit_state(ensemble, tmp_path):
    motions = tmp_path / "m.nc"
    ensemble.save(motions)
    bodies = tmp_path / "bodies.csv"
    bodies.write_text("name,R,gamma\nslim,0.5,5\nstocky,0.5,3\n")  # a 1 x 2 grid
    out = tmp_path / "out"
    args = ["agx50", "--bodies", bodies, "--motions", motions, "--resolution", RESOLUTION]
    args += ["--agx-max", 1.0, "--limit-states", STATES, "--quiet", "--out", out]
    result = CliRunner().invoke(main, [str(a) for a in args])
    assert result.exit_code == 0, result.output
    table = pd.read_csv(out / "agx50.csv")
    assert list(table["body"]) == ["slim"] * 3 + ["stocky"] * 3
    assert list(table["limit_state"]) == ["uplift", "theta/alpha>=0.5", "overturn"] * 2
    # the A_gx50 of the API on the same motions (the CSV keeps 6 significant digits)
    blocks = [Block(0.5, 5.0), Block(0.5, 3.0)]
    api = agx_50(blocks, ensemble, resolution=RESOLUTION, agx_max=1.0, limit_states=STATES)
    np.testing.assert_allclose(table["agx50_g"], api["agx50"].values.ravel(), rtol=1e-6)
    # S_v1 at each limit state's A_gx50, the required S_v the body's
    ok = np.isfinite(table["agx50_g"])
    np.testing.assert_allclose(
        table["ratio"][ok], (table["sv1_cm_s"] / table["sv_required_cm_s"])[ok], rtol=1e-5
    )
    assert np.all(table.groupby("body")["sv_required_cm_s"].nunique() == 1)
    with xr.open_dataset(out / "agx50.nc") as ds:
        assert ds["agx50"].dims == ("body", "limit_state")
        assert ds["sv_required"].dims == ("body",)
        assert list(ds["threshold"].values) == [1.0, 0.5, 1.0]
    # the paper's Tables 2-3 once per limit state (Table 1, the required S_v, once)
    sv1 = pd.read_csv(out / "table2_sv1_cm_s-theta_alpha_0.5.csv", index_col=0)
    mine = table[table["limit_state"] == "theta/alpha>=0.5"].set_index("gamma")["sv1_cm_s"]
    np.testing.assert_allclose(sv1.loc[0.5, ["3", "5"]], mine[[3.0, 5.0]], rtol=1e-3)
    for name in ("table1_sv_required_cm_s", "table3_ratio-uplift", "table3_ratio-overturn"):
        assert (out / f"{name}.csv").stat().st_size > 0
    assert (out / "sv_agx.png").stat().st_size > 0
    assert "(uplift)" in result.output and "(overturn)" in result.output


def test_progress_total_counts_every_limit_states_search(ensemble, monkeypatch):
    # each limit state is searched on its own (its own brackets and bisection), so the progress
    # bar must expect the simulations of each search: three states announce three times the
    # work of one (before the fix every number of states announced one search's)
    announced: list[int] = []
    monkeypatch.setattr(Engine, "expect", lambda self, n: announced.append(n))
    for states in ("overturn", "uplift, theta/alpha>=0.5, overturn"):
        agx_50([Block(1.0, 3.0)], ensemble, resolution=0.1, agx_max=1.0, limit_states=states)
    assert len(announced) == 2 and announced[1] == 3 * announced[0] > 0
