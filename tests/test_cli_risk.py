"""rocking fragility --im/--method and rocking risk, end to end through the command line."""

import json
import math
import shutil

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
    assert set(fits["im"]) == {"pgv"} and set(fits["unit"]) == {"m/s"}
    assert fits["median_extrapolated"].dtype == bool
    # each body's point fit lies inside its bootstrap interval
    assert (fits["median_low"] <= fits["median"]).all()
    assert (fits["median"] <= fits["median_high"]).all()
    ranking = pd.read_csv(fragility / "im_efficiency.csv")
    # each body's rows, then those of one fit of both bodies pooled
    assert set(ranking["body"]) == {"slim", "squat", "all bodies (pooled)"}
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


def _table(output, header_start):
    """The rows of the aligned table whose header starts with ``header_start``: {first cell:
    the other cells}, split on runs of 2 or more blanks."""
    import re

    lines = output.splitlines()
    start = next(i for i, line in enumerate(lines) if line.startswith(header_start))
    rows = {}
    for line in lines[start:]:
        if line.startswith("wrote ") or line.startswith("warning: "):
            break
        cells = re.split(r"\s{2,}", line.strip())
        rows[cells[0]] = cells[1:]
    return rows


def test_fragility_and_risk_print_their_numbers_per_body(fragility, suite, tmp_path):
    # issue 48: both commands printed only "wrote ...". fragility: median [unit] with its
    # interval and beta per body; risk: annual rate and probability in --years per body, the
    # numbers of lognormal.csv and risk.csv to 3 significant digits
    bodies = tmp_path / "b.csv"
    bodies.write_text("name,R,gamma\nslim,0.5,5\nsquat,1.5,3\n")
    args = ["fragility", "--bodies", bodies, "--motions", suite, "--im", "pgv"]
    args += ["--levels", "0.05:1.5:0.05", "--n-boot", 30, "--out", tmp_path / "f", "--quiet"]
    result = _run(args)
    assert result.exit_code == 0, result.output
    printed = _table(result.output, "body")
    assert list(printed["body"][:3]) == ["median [m/s]", "95 % interval", "beta [-]"]
    fits = pd.read_csv(tmp_path / "f" / "lognormal.csv").set_index("body")
    for body in ("slim", "squat"):
        median, interval, beta = printed[body][:3]
        assert float(median) == pytest.approx(fits.loc[body, "median"], rel=5e-3)
        assert float(beta) == pytest.approx(fits.loc[body, "beta"], rel=5e-3)
        low, high = (float(v) for v in interval.split(" to "))
        assert low == pytest.approx(fits.loc[body, "median_low"], rel=5e-3)
        assert high == pytest.approx(fits.loc[body, "median_high"], rel=5e-3)
    out = tmp_path / "r"
    result = _run(
        ["risk", "--fragility", fragility, "--hazard", "example", "--years", 30, "--out", out]
    )
    assert result.exit_code == 0, result.output
    printed = _table(result.output, "body")
    assert printed["body"] == [
        "median [m/s]",
        "beta [-]",
        "annual rate [1/yr]",
        "return period [yr]",
        "P in 30 yr [-]",
    ]
    risk = pd.read_csv(out / "risk.csv").set_index("body")
    for body in ("slim", "squat"):
        rate, p = float(printed[body][2]), float(printed[body][4])
        assert rate == pytest.approx(risk.loc[body, "annual_rate"], rel=5e-3)
        assert p == pytest.approx(risk.loc[body, "p_in_30_yr"], rel=5e-3)


def test_fragility_warns_in_one_line_of_a_median_beyond_the_levels(suite, tmp_path):
    # issue 48: no word when a median lies at or beyond the highest level tested. Levels to
    # 0.75 m/s only: 1 to 3 of the 8 motions overturn the squat block (4 first at 0.85 m/s
    # in the fixture's IDA), so its fitted median lies beyond the levels, which lognormal.csv
    # records and one line says
    bodies = tmp_path / "b.csv"
    bodies.write_text("name,R,gamma\nsquat,1.5,3\n")
    args = ["fragility", "--bodies", bodies, "--motions", suite, "--im", "pgv", "--n-boot", 0]
    result = _run([*args, "--levels", "0.5:0.75:0.05", "--out", tmp_path / "f", "--quiet"])
    assert result.exit_code == 0, result.output
    fits = pd.read_csv(tmp_path / "f" / "lognormal.csv")
    counts = pd.read_csv(tmp_path / "f" / "probabilities.csv")["count"]
    assert 1 <= counts.max() < 4  # some overturn, never half of the 8
    assert fits["median"][0] > 0.75 and fits["median_extrapolated"].tolist() == [True]
    lines = [line for line in result.output.splitlines() if line.startswith("warning:")]
    assert len(lines) == 1 and "squat" in lines[0] and "0.75 m/s" in lines[0]
    assert "ExtrapolationWarning" not in result.output  # no Python warning text


@pytest.mark.parametrize(
    "text,words",
    [
        ("hello\nworld\n", "no column body, median, beta"),
        ("body,median,beta\n", "lists no bodies"),
        ("body,median,beta\nslim,abc,0.3\n", "row 1 (body 'slim'): median 'abc' is not a number"),
        ("body,median,beta\nslim,-0.5,0.3\n", "row 1 (body 'slim'): median must be"),
        ("body,median,beta\nslim,0.5,0\n", "row 1 (body 'slim'): beta must be"),
        ("body,im,median,beta\nslim,sa(1.0),0.5,0.3\n", "the curve is of sa(1), the run"),
        ("", "cannot read"),
        (b"\x89PNG\r\n\x1a\n\x00\x00\xff\xfe", "lognormal.csv"),
    ],
)
def test_risk_names_the_file_and_what_is_wrong_in_a_damaged_lognormal_csv(
    fragility, tmp_path, text, words
):
    # issue 49: garbage in lognormal.csv ended as KeyError, exit 70 (a bug): it is the
    # user's file, so one line naming the file and what is missing or wrong, exit 1
    folder = tmp_path / "frag"
    shutil.copytree(fragility, folder)
    path = folder / "lognormal.csv"
    path.write_bytes(text if isinstance(text, bytes) else text.encode())
    result = _run(["risk", "--fragility", folder, "--hazard", "example", "--out", tmp_path / "r"])
    assert result.exit_code == 1, result.output
    assert str(path) in result.output and words in result.output
    assert len(result.output.strip().splitlines()) == 1


def test_risk_reads_the_lognormal_csv_of_earlier_runs(fragility, tmp_path):
    # before the unit column, im held the IM with its unit ('pgv [m/s]'): still read, with
    # the same rates
    folder = tmp_path / "frag"
    shutil.copytree(fragility, folder)
    fits = pd.read_csv(folder / "lognormal.csv")
    fits.drop(columns=["unit", "median_extrapolated"]).assign(im="pgv [m/s]").to_csv(
        folder / "lognormal.csv", index=False
    )
    rates = []
    for source, out in ((fragility, tmp_path / "new"), (folder, tmp_path / "old")):
        result = _run(["risk", "--fragility", source, "--hazard", "example", "--out", out])
        assert result.exit_code == 0, result.output
        rates.append(pd.read_csv(out / "risk.csv")["annual_rate"].tolist())
    assert rates[0] == rates[1]


def test_a_body_without_a_fit_is_not_called_an_extrapolation(fragility, tmp_path):
    # A body that never (or always) overturned has no fitted curve: median and beta empty in
    # lognormal.csv. The risk report's check of medians outside the levels tested read its NaN
    # as "outside" and warned "The fitted median of <body> (nan m/s) ...".
    folder = tmp_path / "frag"
    shutil.copytree(fragility, folder)
    fits = pd.read_csv(folder / "lognormal.csv")
    unfitted = fits["body"].iloc[0]
    fits.loc[0, ["median", "median_low", "median_high", "beta", "beta_low", "beta_high"]] = None
    fits.to_csv(folder / "lognormal.csv", index=False)
    out = tmp_path / "risk"
    result = _run(["risk", "--fragility", folder, "--hazard", "example", "--out", out])
    assert result.exit_code == 0, result.output
    report = (out / "report.md").read_text()
    assert "(nan " not in report
    assert f"{unfitted} (" not in report.split("Warning.**")[-1].split("\n\n")[0]
