"""Hazard curves from the engines' files (issue 47): the OpenQuake-engine hazard-curve CSV and
the USGS NSHM hazard JSON, through HazardCurve.from_csv and rocking risk. The files in
tests/data are written by hand to each format (tests/data/README.md)."""

import json
import math
from pathlib import Path

import numpy as np
import pandas as pd
import pytest
from click.testing import CliRunner

from rocking import HazardCurve, LognormalFit, annual_rate
from rocking.assessment.hazard_formats import detect_format, engine_im, poe_to_rate
from rocking.cli import main
from rocking.errors import InputError
from rocking.motions.intensity import parse_im

DATA = Path(__file__).parent / "data"
OQ = DATA / "openquake_hazard_curve-mean-PGV.csv"
USGS = DATA / "usgs_nshm_hazard.json"

# λ = −ln(1 − PoE)/T with T = 50 yr, from the natural logarithms ln 0.4 = −0.916290731874155,
# ln 0.7 = −0.356674943938732, ln 0.95 = −0.0512932943875505, ln 0.99 = −0.0100503358535014
# (tables; 15 digits), divided by hand. Tolerance 1e-13 relative: the digits given.
SITE0_RATES = [0.0183258146374831, 0.00713349887877465, 0.00102586588775101, 0.000201006717070029]


def test_openquake_poe_becomes_annual_rate_against_hand_values():
    curve = HazardCurve.from_csv(OQ, site=0)
    assert curve.im == parse_im("pgv")
    # the IMLs 5, 10, 50, 100 cm/s in m/s; the PoE of 1 at 1 cm/s (no finite rate) and the PoE
    # of 0 at 300 cm/s (no place on a log-log curve) are left out
    np.testing.assert_allclose(curve.values, [0.05, 0.1, 0.5, 1.0], rtol=1e-15)
    np.testing.assert_allclose(curve.rates, SITE0_RATES, rtol=1e-13)
    for said in ("OpenQuake", "site 0", "IMT PGV [cm/s]", "pgv [m/s]", "50 years", "PoE 1"):
        assert said in curve.origin
    # site 1, PoE 5e-4 at 300 cm/s: −ln(1 − p) = p + p²/2 + p³/3 + p⁴/4 + … = 5.0012504168229e-4
    # (the next term is 1e-14 of it), /50 = 1.00025008336458e-5; PoE 0.8: −ln 0.2/50 with
    # ln 0.2 = −1.6094379124341 (tables). Tolerance 1e-12 relative: the digits given.
    other = HazardCurve.from_csv(OQ, site=1)
    assert other.values.size == 6
    expected = [1.6094379124341 / 50, 1.00025008336458e-5]
    np.testing.assert_allclose(other.rates[[0, -1]], expected, rtol=1e-12)


def test_poe_of_one_has_no_finite_rate_and_small_poe_is_rate_times_time():
    rates = poe_to_rate(np.array([1.0, 0.0, 1e-12]), 50.0)
    assert rates[0] == math.inf and rates[1] == 0.0
    assert rates[2] == pytest.approx(1e-12 / 50, rel=1e-11)  # −ln(1 − p) = p + p²/2 + …


def test_openquake_errors_name_the_file_and_the_row(tmp_path):
    with pytest.raises(InputError, match=r"2 sites .*--site \(0 to 1\)"):
        HazardCurve.from_csv(OQ)
    with pytest.raises(InputError, match=rf"{OQ.name}: site 5 is not a site"):
        HazardCurve.from_csv(OQ, site=5)
    bad = tmp_path / "bad.csv"
    lines = OQ.read_text().splitlines()
    bad.write_text("\n".join([*lines[:3], lines[3].replace("2.000000E-01", "abc")]) + "\n")
    with pytest.raises(InputError, match=r"bad.csv: line 4, column poe-10.0000000: PoE 'abc'"):
        HazardCurve.from_csv(bad, site=1)
    plateau = tmp_path / "plateau.csv"
    plateau.write_text("\n".join([*lines[:2], lines[2].replace("3.000000E-01", "6.000000E-01")]))
    with pytest.raises(InputError, match=r"site 0 \(line 3\): the rate at poe-10.0000000"):
        HazardCurve.from_csv(plateau)
    other = tmp_path / "mmi.csv"
    other.write_text(OQ.read_text().replace("imt='PGV'", "imt='MMI'"))
    with pytest.raises(InputError, match=r"line 1: IMT 'MMI' has no intensity measure"):
        HazardCurve.from_csv(other, site=0)


def test_engine_imts_map_to_rocking_ims_in_their_units():
    assert engine_im("SA(0.3)", "") == (parse_im("sa(0.3)"), "g", 1.0)
    assert engine_im("SA0P3", "") == (parse_im("sa(0.3)"), "g", 1.0)
    assert engine_im("SA10P0", "") == (parse_im("sa(10)"), "g", 1.0)
    assert engine_im("PGA", "") == (parse_im("pga"), "g", 1.0)
    assert engine_im("PGV", "") == (parse_im("pgv"), "cm/s", 0.01)


def test_usgs_total_curve_of_the_chosen_imt():
    pga = HazardCurve.from_csv(USGS, im="pga")
    assert pga.im == parse_im("pga")
    # the Total component, not Fault; its final rate 0 (at 5 g) left out
    np.testing.assert_array_equal(pga.values, [0.005, 0.05, 0.1, 0.5, 1.0])
    np.testing.assert_array_equal(pga.rates, [0.5, 0.04, 0.012, 5.0e-4, 6.0e-5])
    assert "IMT PGA [g]" in pga.origin and "E2014" in pga.origin and "760" in pga.origin
    sa = HazardCurve.from_csv(USGS, im="sa(1.0)")
    assert sa.im == parse_im("sa(1)") and sa.rates[-1] == 5.0e-6
    with pytest.raises(InputError, match=r"curves of 2 IMTs \(PGA, SA1P0\)"):
        HazardCurve.from_csv(USGS)
    with pytest.raises(InputError, match=r"no curve of pgv; the file has PGA, SA1P0"):
        HazardCurve.from_csv(USGS, im="pgv")


def test_usgs_errors_name_the_file(tmp_path):
    doc = json.loads(USGS.read_text())
    doc["response"][1]["data"] = [{"component": "Fault", "yvalues": [1, 0.1, 0.01, 1e-3, 1e-4]}]
    bad = tmp_path / "bad.json"
    bad.write_text(json.dumps(doc))
    with pytest.raises(InputError, match=r"bad.json: response\[1\]: no data entry .*'Total'"):
        HazardCurve.from_csv(bad, im="sa(1)")
    bad.write_text('{"response": [1, 2')
    with pytest.raises(InputError, match=r"bad.json: line 1: not valid JSON"):
        HazardCurve.from_csv(bad)


def test_formats_are_told_apart_by_content(tmp_path):
    plain = tmp_path / "plain.csv"
    plain.write_text("# a comment\npga [g],annual_rate\n0.1,0.01\n0.2,0.002\n")
    assert [detect_format(p) for p in (OQ, USGS, plain)] == ["openquake", "usgs", "csv"]
    assert HazardCurve.from_csv(plain).origin == ""


def test_a_hazard_file_is_read_once(tmp_path, monkeypatch):
    # the format is told from the same text that is parsed: one read per file (before, the
    # sniff and the parse read it twice, and a file rewritten in between could be taken for one
    # format and parsed as another)
    plain = tmp_path / "plain.csv"
    plain.write_text("pga [g],annual_rate\n0.1,0.01\n0.2,0.002\n")
    reads = []
    read_bytes = Path.read_bytes

    def counted(self):
        reads.append(self.name)
        return read_bytes(self)

    monkeypatch.setattr(Path, "read_bytes", counted)
    for path, options in ((OQ, {"site": 0}), (USGS, {"im": "pga"}), (plain, {})):
        reads.clear()
        HazardCurve.from_csv(path, **options)
        assert reads == [path.name]


def _fragility_folder(folder: Path, im: str, median: float, beta: float) -> Path:
    """A completed fragility run's record and fits, as rocking risk reads them."""
    folder.mkdir()
    record = {"command": "fragility", "status": "completed", "im": im, "method": "ida"}
    (folder / "run.json").write_text(json.dumps(record))
    pd.DataFrame({"body": ["b"], "median": [median], "beta": [beta]}).to_csv(
        folder / "lognormal.csv", index=False
    )
    return folder


def test_risk_reads_an_openquake_site_and_says_what_it_found(tmp_path):
    frag = _fragility_folder(tmp_path / "frag", "pgv", 0.3, 0.5)
    run = CliRunner().invoke
    args = ["risk", "--fragility", frag, "--hazard", OQ, "--out", tmp_path / "risk", "--quiet"]
    result = run(main, [str(a) for a in args])
    assert result.exit_code != 0 and "2 sites" in result.output
    assert "Traceback" not in result.output and len(result.output.strip().splitlines()) == 1
    result = run(main, [str(a) for a in [*args, "--site", 0]])
    assert result.exit_code == 0, result.output
    assert "hazard: OpenQuake hazard curve, site 0" in result.output
    assert "IMT PGV [cm/s] read as pgv [m/s]" in result.output
    assert "IMT PGV [cm/s] read as pgv [m/s]" in (tmp_path / "risk" / "report.html").read_text()
    # the same rate as from the hand-converted curve, read by no reader of engine files
    by_hand = HazardCurve("pgv", [0.05, 0.1, 0.5, 1.0], SITE0_RATES)
    expected = annual_rate(LognormalFit(0.3, 0.5, im="pgv"), by_hand).annual_rate
    got = pd.read_csv(tmp_path / "risk" / "risk.csv")["annual_rate"].iloc[0]
    assert got == pytest.approx(expected, rel=1e-9)  # the quadrature's 1e-10, hand digits 1e-13


def test_openquake_site_columns_may_come_before_lon_and_lat(tmp_path):
    # engines that export a custom_site_id column put it before lon, lat
    lines = OQ.read_text().splitlines()
    moved = tmp_path / "ids.csv"
    moved.write_text(
        "\n".join([lines[0], "custom_site_id," + lines[1], "a," + lines[2], "b," + lines[3]])
    )
    curve = HazardCurve.from_csv(moved, site=0)
    np.testing.assert_allclose(curve.rates, SITE0_RATES, rtol=1e-13)
    assert "(lon 10.00000, lat 45.00000)" in curve.origin
