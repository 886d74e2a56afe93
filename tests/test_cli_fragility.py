"""``rocking fragility``, ``rocking agx50`` and ``rocking assess``: bad input stops before any work
with one line and no traceback; small runs write their files and agree with the library."""

import json
import math
import re

import numpy as np
import pandas as pd
import pytest
import xarray as xr
from click.testing import CliRunner

from rocking.cli import main
from rocking.cli._options import parse_range
from rocking.dynamics.body import FOOT, Block, G
from rocking.errors import InputError
from rocking.motions.ensemble import NETCDF_ENGINE
from rocking.motions.synthesis import generate
from rocking.structures.frames import ShearFrame


@pytest.fixture(scope="module")
def motions(tmp_path_factory):
    """A tiny simulated ensemble (6 motions of 5 s at 200 Hz) saved as netCDF."""
    path = tmp_path_factory.mktemp("motions") / "ens.nc"
    generate(6, duration=5.0, dt=1 / 200, seed=3).save(path)
    return path


@pytest.fixture
def bodies(tmp_path):
    """Two slender bodies of one size (a 1 × 2 R × γ grid) that overturn at moderate A_gx."""
    path = tmp_path / "bodies.csv"
    path.write_text("name,R,gamma\nslim,0.5,5\nslimmer,0.5,6\n")
    return path


def _one_line_error(result):
    """The CLI failed with a one-line message and no traceback."""
    assert result.exit_code != 0
    assert "Traceback" not in result.output
    assert result.exception is None or isinstance(result.exception, SystemExit)
    lines = result.output.strip().splitlines()
    assert len(lines) == 1 and lines[0].startswith("Error: "), result.output
    return lines[0]


def _run(args):
    return CliRunner().invoke(main, [str(a) for a in args])


# ----------------------------------------------------------------------------- bad input


@pytest.mark.parametrize(
    "csv_text, command, expected",
    [
        ("R\n1.0\n", "fragility", "missing column"),
        (
            "R,gamma\n1.0,4\n-0.5,3\n",
            "fragility",
            r"row 2 \(line 3\): R must be a finite number > 0",
        ),
        ("H,B\n1.0,0.2\n1.0,-0.2\n", "agx50", r"row 2 \(line 3\): B must be"),
        ("", "agx50", "empty bodies file"),
    ],
)
def test_bad_bodies_file_stops_before_work(tmp_path, motions, csv_text, command, expected):
    bad = tmp_path / "bad.csv"
    bad.write_text(csv_text)
    out = tmp_path / "out"
    line = _one_line_error(_run([command, "--bodies", bad, "--motions", motions, "--out", out]))
    assert "bad.csv" in line and re.search(expected, line), line
    assert not out.exists()  # no work started, nothing written


@pytest.mark.parametrize(
    "extra, expected",
    [
        (["--frame", "paper-9.9", "--floor", "1"], "unknown frame preset 'paper-9.9'"),
        (["--frame", "paper-2.0", "--floor", "6"], "--floor must be from 0"),
        (["--floor", "2"], "--floor and --frame go together"),
        (["--agx", "1.5:0.1:0.05"], "empty range"),
        (["--agx", "0.1:1.5:0"], "step must be > 0"),
        (["--agx", "0.1:x:0.1"], "start:stop:step"),
        (["--agx", "-0.1:0.5:0.1"], "values must be > 0"),
        (["--e", "1.5"], "--e must be"),
        (["--scheduler", "bogus"], "scheduler"),
    ],
)
def test_bad_options_stop_before_work(tmp_path, motions, bodies, extra, expected):
    out = tmp_path / "out"
    line = _one_line_error(
        _run(["fragility", "--bodies", bodies, "--motions", motions, "--out", out, *extra])
    )
    assert expected in line
    assert not out.exists()


def test_missing_or_bad_motions_file(tmp_path, bodies):
    out = tmp_path / "out"
    line = _one_line_error(
        _run(["agx50", "--bodies", bodies, "--motions", tmp_path / "none.nc", "--out", out])
    )
    assert "none.nc" in line
    not_nc = tmp_path / "text.nc"
    not_nc.write_text("hello")
    line = _one_line_error(_run(["agx50", "--bodies", bodies, "--motions", not_nc, "--out", out]))
    assert "text.nc" in line
    assert not out.exists()


def test_agx_range_includes_stop_within_tolerance():
    # 0.1 + 14·0.1 is 1.5000000000000002 in binary: the stop still counts, values read as written.
    np.testing.assert_array_equal(parse_range("0.1:1.5:0.1"), np.round(np.arange(1, 16) / 10, 12))
    assert parse_range("0.3:0.8:0.05")[-1] == 0.8
    assert parse_range("0.6").tolist() == [0.6]
    with pytest.raises(InputError, match="empty range"):
        parse_range("0.5:0.4:0.1")


# ----------------------------------------------------------------------------- assess


@pytest.fixture
def flat_spectrum(tmp_path):
    """CSV spectrum with PSV = 114.30 cm/s at every frequency (PSA ∝ f), the paper's first floor."""
    path = tmp_path / "floor1.csv"
    rows = "\n".join(f"{fi!r},{1.1430 * 2 * math.pi * fi / G!r}" for fi in (0.01, 10.0))
    path.write_text("freq_hz,psa_g\n" + rows + "\n")
    return path


def test_assess_paper_examples_sorted_most_at_risk_first(tmp_path, flat_spectrum):
    # Paper Section 8: R = 1.22 m, γ = 2 (205.11 cm/s needed) is safe, γ = 4 (100.56 cm/s)
    # overturns with more than 50 % probability on a floor offering 114.30 cm/s.
    path = tmp_path / "b.csv"
    path.write_text(f"name,R,gamma\nstocky,{4 * FOOT!r},2\nslender,{4 * FOOT!r},4\n")
    result = _run(["assess", "--bodies", path, "--spectrum", flat_spectrum])
    assert result.exit_code == 0, result.output
    lines = result.output.strip().splitlines()
    assert "114.30 cm/s" in lines[0]
    assert lines[2].split()[0] == "slender" and lines[2].endswith("overturn>50%")
    assert lines[3].split()[0] == "stocky" and lines[3].endswith("safe")
    assert "205.12" in lines[3] and "100.57" in lines[2]  # Eq. (11) for 4 ft (paper: .11, .56)

    data = json.loads(
        _run(["assess", "--bodies", path, "--spectrum", flat_spectrum, "--json"]).output
    )
    assert [b["verdict"] for b in data["bodies"]] == ["overturn>50%", "safe"]
    assert data["sv_available_cm_s"] == pytest.approx(114.30, rel=1e-12)
    first = data["bodies"][0]
    assert first["margin"] == pytest.approx(first["sv_required_cm_s"] / 114.30 - 1, rel=1e-12)


def test_example_bodies_are_shipped_and_hold_the_paper_section_8_pair(flat_spectrum):
    # --bodies example: the shipped file (src/rocking/data/example_bodies.csv), whose first two
    # rows are the paper's R = 4 ft blocks given by H and B to 0.1 mm: Eq. (11) gives the same
    # 205.12 and 100.57 cm/s as the test above to 1e-4 (the rounding of H and B).
    data = json.loads(
        _run(["assess", "--bodies", "example", "--spectrum", flat_spectrum, "--json"]).stdout
    )
    need = {b["name"]: b["sv_required_cm_s"] for b in data["bodies"]}
    assert len(need) == 7
    assert need["paper stocky (R = 4 ft; gamma = 2)"] == pytest.approx(205.12, rel=1e-4)
    assert need["paper slender (R = 4 ft; gamma = 4)"] == pytest.approx(100.57, rel=1e-4)


def test_assess_paper_bodies_and_ensemble_source(motions, flat_spectrum):
    result = _run(["assess", "--bodies", "paper", "--spectrum", flat_spectrum, "--json"])
    assert len(json.loads(result.stdout)["bodies"]) == 72
    # An ensemble on floor 1 of the 2.0 s frame, scaled to 0.6 g, agrees with the library.
    from rocking.assessment.energy import available_sv
    from rocking.motions.ensemble import Ensemble

    floor = ShearFrame.preset("paper-2.0").floor_ensemble(Ensemble.load(motions), 1)
    data = json.loads(
        _run(
            [
                "assess",
                "--bodies",
                "paper",
                "--spectrum",
                motions,
                "--agx",
                0.6,
                "--frame",
                "paper-2.0",
                "--floor",
                1,
                "--json",
            ]
        ).stdout
    )
    assert data["sv_available_cm_s"] == pytest.approx(100 * available_sv(floor, agx=0.6), rel=1e-12)


def test_assess_takes_a_design_spectrum_specification():
    # ASCE 7 with S_D1 = 0.6 g: the band 0.04–0.6 Hz lies on the constant-velocity plateau
    # (T_s = S_D1/S_DS = 0.6 s to T_L = 8 s), so S_v = S_D1·g/(2π) = 93.65 cm/s exactly.
    data = json.loads(
        _run(
            ["assess", "--bodies", "paper", "--spectrum", "asce7:SDS=1.0,SD1=0.6,TL=8", "--json"]
        ).stdout
    )
    assert data["sv_available_cm_s"] == pytest.approx(100 * 0.6 * G / (2 * math.pi), rel=1e-9)
    line = _one_line_error(_run(["assess", "--bodies", "paper", "--spectrum", "asce7:SDS=1"]))
    assert "missing SD1, TL" in line


@pytest.mark.parametrize(
    "extra, expected",
    [
        (["--band", "0.6:0.04"], "0 < LOW < HIGH"),
        (["--band", "x"], "LOW:HIGH"),
        (["--agx", "0.6"], "apply to an ensemble"),
    ],
)
def test_assess_bad_input(flat_spectrum, extra, expected):
    line = _one_line_error(
        _run(["assess", "--bodies", "paper", "--spectrum", flat_spectrum, *extra])
    )
    assert expected in line


# ----------------------------------------------------------------------------- end to end


def test_fragility_run_writes_its_files_and_matches_the_library(tmp_path, motions, bodies):
    from rocking.montecarlo.probability import overturning_probability
    from rocking.motions.ensemble import Ensemble

    out = tmp_path / "out"
    args = [
        "fragility",
        "--bodies",
        bodies,
        "--motions",
        motions,
        "--agx",
        "0.2:0.6:0.2",
        "--frame",
        "paper-2.0",
        "--floor",
        1,
        "--out",
        out,
        "--quiet",
    ]
    result = _run(args)
    assert result.exit_code == 0, result.output
    for name in ("probabilities.csv", "probabilities.nc", "lognormal.csv", "fragility.png"):
        assert (out / name).stat().st_size > 0
    table = pd.read_csv(out / "probabilities.csv")
    assert list(table.columns) == [
        "body",
        "R",
        "gamma",
        "agx",
        "probability",
        "count",
        "n",
        "ci_low",
        "ci_high",
    ]
    assert len(table) == 2 * 3 and set(table["body"]) == {"slim", "slimmer"}
    assert (table["n"] == 6).all()
    np.testing.assert_allclose(table["probability"], table["count"] / table["n"])
    # The floor motions, scaled to each A_gx, give what the library gives.
    floor = ShearFrame.preset("paper-2.0").floor_ensemble(Ensemble.load(motions), 1)
    ref = overturning_probability([Block(0.5, 5.0), Block(0.5, 6.0)], floor, [0.2, 0.4, 0.6])
    np.testing.assert_array_equal(table["count"].to_numpy(), ref["count"].values.ravel())
    with xr.open_dataset(out / "probabilities.nc", engine=NETCDF_ENGINE) as ds:
        assert ds["probability"].dims == ("body", "agx")
        np.testing.assert_array_equal(ds["count"].values, ref["count"].values)
    # Run again: every finished chunk is loaded from --out, none computed, the same bytes (the
    # counts of chunks, which differ, are kept in run.json, not in the results: issue 49).
    first = (out / "probabilities.nc").read_bytes()
    again = _run(args)
    assert again.exit_code == 0, again.output
    pd.testing.assert_frame_equal(pd.read_csv(out / "probabilities.csv"), table)
    assert (out / "probabilities.nc").read_bytes() == first
    counts = json.loads((out / "run.json").read_text())["bookkeeping"]["probabilities.nc"]
    assert counts["chunks_computed"] == 0 and counts["chunks_loaded"] > 0


def test_agx50_run_writes_tables_and_plot(tmp_path, motions, bodies):
    out = tmp_path / "out"
    result = _run(
        [
            "agx50",
            "--bodies",
            bodies,
            "--motions",
            motions,
            "--resolution",
            0.05,
            "--out",
            out,
            "--quiet",
        ]
    )
    assert result.exit_code == 0, result.output
    for name in (
        "agx50.csv",
        "agx50.nc",
        "table1_sv_required_cm_s.csv",
        "table2_sv1_cm_s.csv",
        "table3_ratio.csv",
        "sv_agx.png",
    ):
        assert (out / name).stat().st_size > 0
    table = pd.read_csv(out / "agx50.csv")
    assert list(table["body"]) == ["slim", "slimmer"]
    ok = np.isfinite(table["agx50_g"])
    np.testing.assert_allclose(
        table["ratio"][ok], (table["sv1_cm_s"] / table["sv_required_cm_s"])[ok], rtol=1e-5
    )
    grid = pd.read_csv(out / "table1_sv_required_cm_s.csv", index_col=0)
    assert grid.shape == (1, 2)


@pytest.fixture(scope="module")
def paper_run(tmp_path_factory, motions):
    """``rocking fragility --bodies paper`` on the tiny ensemble at three A_gx levels."""
    out = tmp_path_factory.mktemp("paper") / "out"
    result = _run(
        [
            "fragility",
            "--bodies",
            "paper",
            "--motions",
            motions,
            "--agx",
            "0.3:0.9:0.3",
            "--out",
            out,
            "--quiet",
        ]
    )
    assert result.exit_code == 0, result.output
    return out


def test_fragility_csv_has_no_float_noise(paper_run):
    # R = 6 ft = 6 * 0.3048 m is 1.8288000000000002 in binary and was written so; the CSV keeps
    # 12 significant digits, which give back every R in feet and P = count/n to half a unit in
    # the 12th digit.
    text = (paper_run / "probabilities.csv").read_text()
    assert "1.8288000000000002" not in text and ",1.8288," in text
    assert not re.search(r"\d\.\d*(0{6}|9{6})\d", text), "float noise in probabilities.csv"
    table = pd.read_csv(paper_run / "probabilities.csv")
    feet = np.unique(table["R"]) / FOOT
    np.testing.assert_allclose(feet, np.arange(4, 12), rtol=5e-12)
    np.testing.assert_allclose(table["probability"], table["count"] / table["n"], rtol=5e-12)


def test_paper_body_names_write_gamma_as_gamma(paper_run):
    # Body names are Block labels: "R=1.22 m, γ=4", not "R=1.22m g=4" (γ read as "g").
    for name in ("probabilities.csv", "lognormal.csv"):
        table = pd.read_csv(paper_run / name)
        assert "R=1.22 m, γ=4" in set(table["body"]), name
        assert not table["body"].str.contains(r"\bg=").any(), name
        assert "gamma" in table.columns
    with xr.open_dataset(paper_run / "probabilities.nc", engine=NETCDF_ENGINE) as ds:
        assert "R=3.35 m, γ=6" in ds["body"].values  # the netCDF-3 file keeps the name


def test_im_efficiency_report_says_whether_the_dimensionless_ims_predict_better(tmp_path, motions):
    # Two blocks of one slenderness, R = 0.3 and 1.5 m: pooled, PGV·p/(g tan α) removes their
    # size (similarity: Makris & Konstantinidis 2003; Dimitrakopoulos & DeJong 2012), so the
    # report compares its pooled β with PGV's in one sentence, with the numbers of the table.
    bodies = tmp_path / "sizes.csv"
    bodies.write_text("name,R,gamma\nsmall,0.3,4\nlarge,1.5,4\n")
    out = tmp_path / "out"
    args = ["fragility", "--bodies", bodies, "--motions", motions, "--im", "pga"]
    args += ["--levels", "0.1:1.5:0.1", "--n-boot", 0, "--out", out, "--quiet"]
    result = _run([*args, "--im-efficiency", "pga,pgv,pga/gtana,pgv*p/gtana"])
    assert result.exit_code == 0, result.output
    table = pd.read_csv(out / "im_efficiency.csv", keep_default_na=False)
    pooled = table[table["body"] == "all bodies (pooled)"].set_index("im")["beta"]
    assert sorted(pooled.index) == ["pga", "pga/gtana", "pgv", "pgv*p/gtana"]
    html = (out / "report.html").read_text()
    word = "better than" if pooled["pgv*p/gtana"] < pooled["pgv"] else "worse than"
    sentence = (
        f"PGV·p/(g tan α) predicts overturning {word} PGV "
        f"(β {pooled['pgv*p/gtana']:.2f} against {pooled['pgv']:.2f})"
    )
    assert "Pooled over the 2 bodies" in html and sentence in html
    assert word == "better than"  # the physics of the comparison, with these 6 motions


def test_im_efficiency_reads_the_fragilitys_own_runs(tmp_path, motions, bodies):
    # scaled by the fragility's IM to its levels, the comparison's IDA is the fragility's own:
    # its simulations are taken from that run, none made (and stored) again
    out = tmp_path / "out"
    args = ["fragility", "--bodies", bodies, "--motions", motions, "--im", "pga"]
    args += ["--levels", "0.2:1.0:0.4", "--n-boot", 0, "--out", out, "--quiet"]
    result = _run([*args, "--im-efficiency", "pga,pgv"])
    assert result.exit_code == 0, result.output
    assert any((out / "chunks" / "fragility").iterdir())  # the fragility's runs
    again = out / "chunks" / "im-efficiency"
    assert not again.exists() or not any(p.suffix == ".npz" for p in again.rglob("*"))


@pytest.mark.parametrize(
    "extra, expected",
    [
        (["--im", "pga/gtana"], "im pga/gtana is per body"),
        (["--im", "pga", "--im-efficiency", "pgv,omega"], "omega does not change when"),
    ],
)
def test_im_efficiency_refuses_what_it_cannot_compare_before_work(
    tmp_path, motions, bodies, extra, expected
):
    out = tmp_path / "out"
    args = ["fragility", "--bodies", bodies, "--motions", motions, "--levels", "0.1:1:0.1"]
    line = _one_line_error(_run([*args, "--out", out, *extra]))
    assert expected in line
    assert not out.exists()
