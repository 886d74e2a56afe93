"""Fragility curves written for loss tools (issue 47): export_fragility and rocking fragility
--export. The pelicun file is loaded by pelicun itself where pelicun is installed (it is not in
the test extra: pelicun 3.10 pins scipy < 1.16 and pandas < 3, older than this package's test
environment; `.ci/run` runs that test in an environment of its own, the `pelicun` extra); the
NRML file is checked against the facts of the OpenQuake engine's manual (Risk → Fragility
Models, NRML 0.5) with the standard library's XML parser."""

import csv
import json
import math
import os
import re
import xml.etree.ElementTree as ET

import numpy as np
import pytest
import scipy.stats
from click.testing import CliRunner

from rocking import LognormalFit, export_fragility, generate
from rocking.cli import main
from rocking.errors import InputError

NS = {"n": "http://openquake.org/xmlns/nrml/0.5"}
FITS = {"cabinet A": LognormalFit(0.4, 0.5), "tank": LognormalFit(0.25, 0.3)}


def _nrml(path):
    root = ET.parse(path).getroot()
    assert root.tag == "{http://openquake.org/xmlns/nrml/0.5}nrml"
    return root.find("n:fragilityModel", NS)


def test_openquake_nrml_holds_mean_and_stddev_of_the_iml(tmp_path):
    path = export_fragility(FITS, tmp_path / "frag.xml", "openquake", im="pga")
    model = _nrml(path)
    # the manual's schema: id (letters, digits, - and _, at most 100), lossCategory among four,
    # a description, the limit states separated by blanks, one continuous logncdf function per
    # taxonomy with imls (imt, minIML, maxIML) and one params (ls, mean, stddev) per limit state
    assert re.fullmatch(r"[A-Za-z0-9_-]{1,100}", model.get("id"))
    assert model.get("lossCategory") in ("structural", "nonstructural", "contents")
    assert model.find("n:description", NS).text.strip()
    states = model.find("n:limitStates", NS).text.split()
    assert states == ["overturning"]
    functions = model.findall("n:fragilityFunction", NS)
    assert [f.get("id") for f in functions] == ["cabinet_A", "tank"]
    for function, fit in zip(functions, FITS.values()):
        assert (function.get("format"), function.get("shape")) == ("continuous", "logncdf")
        imls = function.find("n:imls", NS)
        assert imls.get("imt") == "PGA"
        assert float(imls.get("minIML")) < fit.median < float(imls.get("maxIML"))
        (params,) = function.findall("n:params", NS)
        assert params.get("ls") == "overturning"
        # mean and standard deviation of the IML itself: those of scipy's lognormal of median
        # θ and shape β (an independent formula), to rounding (1e-13)
        dist = scipy.stats.lognorm(s=fit.beta, scale=fit.median)
        assert float(params.get("mean")) == pytest.approx(dist.mean(), rel=1e-13)
        assert float(params.get("stddev")) == pytest.approx(dist.std(), rel=1e-13)
        # and back, as the engine turns them into the parameters of ln(IML):
        # σ² = ln(1 + sd²/mean²), median = mean/√(1 + sd²/mean²)
        mean, sd = float(params.get("mean")), float(params.get("stddev"))
        ratio = 1.0 + (sd / mean) ** 2
        assert math.sqrt(math.log(ratio)) == pytest.approx(fit.beta, rel=1e-12)
        assert mean / math.sqrt(ratio) == pytest.approx(fit.median, rel=1e-12)


def test_openquake_pgv_is_in_cm_per_s_and_sa_names_its_period(tmp_path):
    fit = LognormalFit(0.3, 0.4)  # m/s
    model = _nrml(export_fragility(fit, tmp_path / "pgv.xml", "openquake", im="pgv"))
    function = model.find("n:fragilityFunction", NS)
    assert function.find("n:imls", NS).get("imt") == "PGV"
    # 30 cm/s: mean = 30·exp(0.08) = 32.4986...; exp(0.08) = 1.0832870676749586 (tables)
    mean = float(function.find("n:params", NS).get("mean"))
    assert mean == pytest.approx(30.0 * 1.0832870676749586, rel=1e-13)
    model = _nrml(export_fragility(fit, tmp_path / "sa.xml", "openquake", im="sa(1.0)"))
    assert model.find("n:fragilityFunction/n:imls", NS).get("imt") == "SA(1.0)"


def test_pelicun_csv_has_pelicuns_columns_and_demand_types(tmp_path):
    path = export_fragility(FITS, tmp_path / "dmg.csv", "pelicun", im="pga")
    rows = list(csv.DictReader(path.open()))
    assert list(rows[0]) == [
        "ID",
        "Demand-Directional",
        "Demand-Offset",
        "Demand-Type",
        "Demand-Unit",
        "LS1-Family",
        "LS1-Theta_0",
        "LS1-Theta_1",
    ]
    assert [r["ID"] for r in rows] == ["cabinet_A", "tank"]
    for row, fit in zip(rows, FITS.values()):
        assert (row["Demand-Type"], row["Demand-Unit"]) == ("Peak Ground Acceleration", "g")
        assert row["LS1-Family"] == "lognormal"
        assert float(row["LS1-Theta_0"]) == fit.median and float(row["LS1-Theta_1"]) == fit.beta
    for im, demand, unit in [
        ("pgv", "Peak Ground Velocity", "mps"),
        ("sa(1.0)", "Peak Spectral Acceleration|1.0", "g"),
        ("psv(0.5)", "Peak Spectral Velocity|0.5", "mps"),
    ]:
        path = export_fragility(FITS["tank"], tmp_path / "one.csv", "pelicun", im=im)
        (row,) = csv.DictReader(path.open())
        assert (row["ID"], row["Demand-Type"], row["Demand-Unit"]) == ("body", demand, unit)


def test_what_cannot_be_exported_is_refused(tmp_path):
    fit = LognormalFit(0.4, 0.5)
    cases = [
        (dict(format="pelicun", im="agx"), r"A_gx is the mean PGA of an ensemble"),
        (dict(format="pelicun", im="arias"), r"pelicun has no demand type"),
        (dict(format="pelicun", im="sa(1.0,0.02)"), r"pelicun has no demand type"),
        (dict(format="openquake", im="cav"), r"OpenQuake engine has no IMT"),
        (dict(format="hazus", im="pga"), r"format must be one of pelicun, openquake"),
        (dict(format="pelicun"), r"give im"),
    ]
    for kwargs, message in cases:
        with pytest.raises(InputError, match=message):
            export_fragility(fit, tmp_path / "x", **kwargs)
    with pytest.raises(InputError, match=r"no body has a fitted curve"):
        export_fragility({"a": None}, tmp_path / "x", im="pga")
    with pytest.warns(RuntimeWarning, match=r"not exported, no finite fit: a"):
        fits = {"a": None, "b": fit}
        path = export_fragility(fits, tmp_path / "y.csv", im="pga")
    assert [r["ID"] for r in csv.DictReader(path.open())] == ["b"]
    assert not (tmp_path / "x").exists()


def test_pelicun_damage_probabilities_equal_the_lognormal_cdf(tmp_path):
    # .ci/run runs this test in an environment with pelicun and ROCKING_REQUIRE_PELICUN=1, where
    # a missing pelicun fails instead of skipping
    if os.environ.get("ROCKING_REQUIRE_PELICUN"):
        import pelicun
    else:
        pelicun = pytest.importorskip("pelicun")
    from pelicun import assessment, file_io

    path = export_fragility(FITS, tmp_path / "dmg.csv", "pelicun", im="pga")
    n = 20_000  # realizations per demand value
    x = np.array([0.1, 0.25, 0.4, 0.8])  # PGA [g]
    asmnt = assessment.Assessment({"PrintLog": False, "Seed": 7})
    demand = tmp_path / "demand.csv"  # pelicun's sample format: labels, a row of units
    values = np.repeat(x, n)
    demand.write_text(
        ",PGA-0-1\nUnits,g\n" + "".join(f"{i},{v!r}\n" for i, v in enumerate(values.tolist()))
    )
    asmnt.demand.load_sample(str(demand))
    asmnt.stories = 1
    ids = ["cabinet_A", "tank"]
    marginals = pelicun.base.pd.DataFrame(
        {"Units": "ea", "Location": "0", "Direction": "1", "Theta_0": 1.0}, index=ids
    )
    asmnt.asset.load_cmp_model({"marginals": marginals})
    asmnt.asset.generate_cmp_sample()
    db = file_io.load_data(
        str(path), reindex=False, unit_conversion_factors=asmnt.unit_conversion_factors
    )
    asmnt.damage.load_model_parameters([db], set(ids))
    # pelicun reads our median in g and turns it into m/s² (g = 9.80665 m/s²), β as it is
    params = asmnt.damage.ds_model.damage_params
    for name, fit in zip(ids, FITS.values()):
        assert params.loc[name, ("LS1", "Theta_0")] == pytest.approx(fit.median * 9.80665, 1e-15)
        assert params.loc[name, ("LS1", "Theta_1")] == fit.beta
    asmnt.damage.calculate()
    sample = asmnt.damage.ds_model.sample
    for name, fit in zip(ids, FITS.values()):
        # the sample holds the quantity of the component in each damage state (columns
        # component, location, direction, uid, damage state): here 1 in state 1 (overturned)
        part = sample.xs(name, axis=1, level=0)
        in_ds1 = part.loc[:, part.columns.get_level_values(-1) == "1"].to_numpy()[:, 0]
        overturned = in_ds1.reshape(x.size, n).mean(axis=1)
        expected = fit.probability(x)
        # pelicun draws a capacity per realization: the fraction is binomial, its standard
        # deviation sqrt(p(1 - p)/n) <= 0.0036; 5 of them (seeded, so the test is repeatable)
        np.testing.assert_array_less(
            np.abs(overturned - expected), 5 * np.sqrt(expected * (1 - expected) / n) + 1e-12
        )


def test_fragility_export_option(tmp_path):
    motions = tmp_path / "motions.nc"
    generate(4, duration=6.0, dt=1 / 200, seed=3).save(motions)
    out = tmp_path / "frag"
    args = ["fragility", "--bodies", "example", "--motions", motions, "--im", "pga"]
    args += ["--levels", "0.1:1.5:0.2", "--n-boot", 0, "--out", out, "--quiet"]
    run = CliRunner().invoke
    refused = run(
        main,
        [str(a) for a in ["fragility", "--bodies", "example", "--motions"]]
        + [
            str(motions),
            "--agx",
            "0.1:0.5:0.2",
            "--out",
            str(tmp_path / "agx"),
            "--export",
            "pelicun",
        ],
    )
    assert refused.exit_code != 0 and "A_gx is the mean PGA" in refused.output
    assert not (tmp_path / "agx").exists()  # refused before any work
    result = run(main, [str(a) for a in [*args, "--export", "pelicun", "--export", "openquake"]])
    assert result.exit_code == 0, result.output
    outputs = json.loads((out / "run.json").read_text())["outputs"]
    assert {"fragility_pelicun.csv", "fragility_openquake.xml"} <= set(outputs)
    fits = {r["body"]: r for r in csv.DictReader((out / "lognormal.csv").open())}
    rows = list(csv.DictReader((out / "fragility_pelicun.csv").open()))
    assert rows and all(r["Demand-Type"] == "Peak Ground Acceleration" for r in rows)
    for row in rows:  # one row per body with a fit, its median and β as in lognormal.csv
        fit = next(f for b, f in fits.items() if re.sub(r"[^A-Za-z0-9_-]", "_", b) == row["ID"])
        assert float(row["LS1-Theta_0"]) == pytest.approx(float(fit["median"]), rel=1e-9)
        assert float(row["LS1-Theta_1"]) == pytest.approx(float(fit["beta"]), rel=1e-9)
    assert len(_nrml(out / "fragility_openquake.xml").findall("n:fragilityFunction", NS)) == len(
        rows
    )
