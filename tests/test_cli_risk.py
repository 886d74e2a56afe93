"""rocking fragility --im/--method and rocking risk, end to end through the command line."""

import json
import math

import numpy as np
import pandas as pd
import pytest
from click.testing import CliRunner

from rocking import Ensemble, generate
from rocking.cli import main
from rocking.motions.records import example_record_path


def _run(args):
    return CliRunner().invoke(main, [str(a) for a in args])


@pytest.fixture(scope="module")
def suite(tmp_path_factory):
    """A suite of one real record (El Centro 1940 NS, 0.02 s) and 7 generated motions,
    imported at 0.01 s as a user would."""
    folder = tmp_path_factory.mktemp("suite")
    generate(7, duration=8.0, dt=1 / 200, seed=4).save(folder / "gen.nc")
    out = folder / "suite.nc"
    result = _run(["motions", "import", example_record_path(), folder / "gen.nc", "--dt", 0.01])
    assert result.exit_code != 0  # --out is required
    result = _run(
        ["motions", "import", example_record_path(), folder / "gen.nc", "--dt", 0.01, "--out", out]
    )
    assert result.exit_code == 0, result.output
    return out


@pytest.fixture(scope="module")
def fragility(suite, tmp_path_factory):
    folder = tmp_path_factory.mktemp("frag")
    bodies = folder / "bodies.csv"
    bodies.write_text("name,R,gamma\nslim,0.5,5\nsquat,1.5,3\n")
    out = folder / "frag"
    args = ["fragility", "--bodies", bodies, "--motions", suite, "--im", "pgv"]
    args += ["--levels", "0.05:1.5:0.05", "--n-boot", 30, "--out", out, "--quiet"]
    result = _run([*args, "--im-efficiency", "pga,pgv,sa(1.0, 0.05)"])
    assert result.exit_code == 0, result.output
    return out


def test_fragility_against_pgv_writes_curves_fits_and_im_ranking(fragility, suite):
    table = pd.read_csv(fragility / "probabilities.csv")
    assert "pgv [m/s]" in table.columns
    assert (table["n"] == Ensemble.load(suite).n).all()
    fits = pd.read_csv(fragility / "lognormal.csv")
    assert set(fits["im"]) == {"pgv [m/s]"}
    # each body's point fit lies inside its bootstrap interval
    assert (fits["median_low"] <= fits["median"]).all()
    assert (fits["median"] <= fits["median_high"]).all()
    ranking = pd.read_csv(fragility / "im_efficiency.csv")
    assert set(ranking["body"]) == {"slim", "squat"}
    assert set(ranking["im"]) == {"pga", "pgv", "sa(1)"}
    record = json.loads((fragility / "run.json").read_text())
    assert record["status"] == "completed" and record["im"] == "pgv"
    assert "report.html" in record["outputs"]


def test_risk_equals_the_closed_form_for_a_power_law_hazard(fragility, tmp_path):
    # λ(x) = k0·x^-k, tabulated far beyond the fragility on both sides: the rate of a lognormal
    # fragility is k0·median^-k·exp(k²β²/2) (Cornell et al. 2002, Eq. 11); the table's ends
    # contribute below 1e-9 of it (P_f(1e-3) ~ 1e-50, the upper tail is extrapolated exactly
    # for a power law), so the CLI must give the closed form to the quadrature's 1e-8.
    k0, k = 1e-4, 2.5
    x = np.geomspace(1e-3, 1e2, 41)
    hazard = tmp_path / "hazard.csv"
    pd.DataFrame({"pgv [m/s]": x, "annual_rate": k0 * x**-k}).to_csv(hazard, index=False)
    out = tmp_path / "risk"
    result = _run(["risk", "--fragility", fragility, "--hazard", hazard, "--out", out, "--quiet"])
    assert result.exit_code == 0, result.output
    risk = pd.read_csv(out / "risk.csv")
    fits = pd.read_csv(fragility / "lognormal.csv").set_index("body")
    for _, row in risk.iterrows():
        median, beta = fits.loc[row["body"], "median"], fits.loc[row["body"], "beta"]
        exact = k0 * median**-k * math.exp(k**2 * beta**2 / 2)
        assert row["annual_rate"] == pytest.approx(exact, rel=1e-6)
        assert row["p_in_50_yr"] == pytest.approx(-math.expm1(-50 * exact), rel=1e-6)
    assert (out / "report.html").stat().st_size > 0


def test_risk_refuses_what_does_not_match(fragility, suite, tmp_path):
    wrong = tmp_path / "pga.csv"
    wrong.write_text("pga [g],annual_rate\n0.1,0.01\n0.5,0.001\n")
    result = _run(["risk", "--fragility", fragility, "--hazard", wrong, "--out", tmp_path / "a"])
    assert result.exit_code == 1 and "same intensity measure" in result.output
    assert len(result.output.strip().splitlines()) == 1
    agx = tmp_path / "agx"
    bodies = tmp_path / "b.csv"
    bodies.write_text("R,gamma\n0.5,5\n")
    made = _run(
        ["fragility", "--bodies", bodies, "--motions", suite, "--agx", 0.5, "--out", agx, "--quiet"]
    )
    assert made.exit_code == 0, made.output
    result = _run(["risk", "--fragility", agx, "--hazard", "example", "--out", tmp_path / "b"])
    assert result.exit_code == 1 and "A_gx" in result.output


def test_fragility_option_mistakes_are_one_line(suite, tmp_path):
    bodies = tmp_path / "b.csv"
    bodies.write_text("R,gamma\n0.5,5\n")
    base = ["fragility", "--bodies", bodies, "--motions", suite, "--out", tmp_path / "o"]
    for extra, words in (
        (["--im", "pgv"], "needs --levels"),
        (["--im", "pgv", "--agx", "0.1:0.5:0.1"], "--agx gives A_gx levels"),
        (["--method", "msa"], "--stripes"),
        (["--im", "bogus"], "unknown intensity measure"),
        (["--method", "cloud", "--im-efficiency", "pga"], "--method ida"),
    ):
        result = _run(base + extra)
        assert result.exit_code in (1, 2) and words in result.output, (extra, result.output)


def test_fragility_on_a_floor_of_the_users_own_building(suite, tmp_path):
    # A two-story frame from a TOML file (masses, stiffnesses, damping): the counts on floor 2
    # are those of the library's floor motions of that frame, scaled to each A_gx
    building = tmp_path / "building.toml"
    building.write_text(
        "masses_kg = [2.0e5, 1.5e5]\nstiffnesses_N_per_m = [8.0e7, 6.0e7]\ndamping = 0.03\n"
    )
    bodies = tmp_path / "b.csv"
    bodies.write_text("R,gamma\n0.5,5\n")
    out = tmp_path / "frag"
    args = ["fragility", "--bodies", bodies, "--motions", suite, "--agx", "0.2:0.6:0.2"]
    result = _run([*args, "--frame", building, "--floor", 2, "--out", out, "--quiet"])
    assert result.exit_code == 0, result.output
    from rocking import Block, ShearFrame, overturning_probability

    floor = ShearFrame.from_toml(building).floor_ensemble(Ensemble.load(suite), 2)
    ref = overturning_probability([Block(0.5, 5.0)], floor, [0.2, 0.4, 0.6], progress=False)
    table = pd.read_csv(out / "probabilities.csv")
    np.testing.assert_array_equal(table["count"].to_numpy(), ref["count"].values.ravel())
    assert json.loads((out / "run.json").read_text())["location"] == "floor 2 of building"
