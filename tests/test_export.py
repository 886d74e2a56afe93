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

from rocking import LognormalFit, export_fragility, fragility_analysis, generate
from rocking.cli import main
from rocking.dynamics.body import Block
from rocking.errors import InputError

NS = {"n": "http://openquake.org/xmlns/nrml/0.5"}
FITS = {"cabinet A": LognormalFit(0.4, 0.5), "tank": LognormalFit(0.25, 0.3)}
STATES = "uplift, theta/alpha>=0.5, overturn"
ORDER = ["uplift", "theta/alpha>=0.5", "overturn"]  # by increasing severity
FAMILY_COLUMNS = ("Family", "Theta_0", "Theta_1")
PGV = [0.05, 0.1, 0.15, 0.2, 0.3, 0.45, 0.7, 1.0]  # m/s


@pytest.fixture(scope="module")
def limit_states():
    """The three limit states of two bodies against PGV by IDA, 8 motions of 6 s at 200 Hz:
    the levels span uplift to overturning of both, so that every state has a finite fit
    (a few seconds once the kernels are compiled)."""
    ensemble = generate(8, duration=6.0, dt=1 / 200, seed=5)
    blocks = [Block(0.5, 5.0), Block(1.0, 4.0)]
    return fragility_analysis(blocks, ensemble, im="pgv", levels=PGV, limit_states=STATES, n_boot=0)


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


def test_every_limit_state_is_exported_by_increasing_severity(limit_states, tmp_path):
    ds = limit_states
    assert ds.attrs["fits"].startswith("each limit state alone; nested")
    ids = [re.sub(r"[^A-Za-z0-9_-]", "_", str(b)) for b in ds["body"].values]
    rows = list(csv.DictReader(export_fragility(ds, tmp_path / "ls.csv", "pelicun").open()))
    assert list(rows[0])[5:] == [f"LS{n}-{c}" for n in (1, 2, 3) for c in FAMILY_COLUMNS]
    assert [r["ID"] for r in rows] == ids
    for b, row in enumerate(rows):
        medians = [float(row[f"LS{n}-Theta_0"]) for n in (1, 2, 3)]
        # LS1..LS3 are uplift, θ/α ≥ 0.5, overturn with their fitted medians [m/s] and each
        # state's own β (exact: the file holds repr of the float)
        assert medians == [float(ds["median"].sel(limit_state=s)[b]) for s in ORDER]
        assert medians[0] < medians[1] < medians[2]
        betas = [float(row[f"LS{n}-Theta_1"]) for n in (1, 2, 3)]
        assert betas == [float(ds["beta"].sel(limit_state=s)[b]) for s in ORDER]
        assert all(0.0 < beta < 1.0 for beta in betas)
        assert {row[f"LS{n}-Family"] for n in (1, 2, 3)} == {"lognormal"}
    # the order given does not matter: the states are written by increasing severity
    shuffled = ds.isel(limit_state=[2, 0, 1])
    again = export_fragility(shuffled, tmp_path / "again.csv", "pelicun")
    assert again.read_bytes() == (tmp_path / "ls.csv").read_bytes()

    model = _nrml(export_fragility(ds, tmp_path / "ls.xml", "openquake"))
    # the manual: limit-state names of letters, digits, - and _, one params per limit state in
    # each function, in the order of limitStates
    states = model.find("n:limitStates", NS).text.split()
    assert states == ["uplift", "theta_alpha__0_5", "overturn"]
    assert all(s in model.find("n:description", NS).text for s in ORDER)
    functions = model.findall("n:fragilityFunction", NS)
    assert [f.get("id") for f in functions] == ids
    for b, function in enumerate(functions):
        assert function.find("n:imls", NS).get("imt") == "PGV"
        params = function.findall("n:params", NS)
        assert [p.get("ls") for p in params] == states
        for p, state in zip(params, ORDER):
            # the engine's own conversion back (σ² = ln(1 + sd²/mean²), median = mean/√(…)),
            # in cm/s: PGV's unit in the engine; to rounding (1e-12)
            mean, sd = float(p.get("mean")), float(p.get("stddev"))
            ratio = 1.0 + (sd / mean) ** 2
            median = 100.0 * float(ds["median"].sel(limit_state=state)[b])
            assert mean / math.sqrt(ratio) == pytest.approx(median, rel=1e-12)
            beta = float(ds["beta"].sel(limit_state=state)[b])
            assert math.sqrt(math.log(ratio)) == pytest.approx(beta, rel=1e-12)


def test_limit_states_a_loss_tool_cannot_take_in_sequence_are_refused(limit_states, tmp_path):
    ds = limit_states
    # not nested: a case where θ/α ≥ 0.5 is exceeded but uplift is not (made up by clearing
    # an uplift flag where the block rocked that far); fitted one by one they could cross
    flags = ds["exceeded"].copy()
    where = np.argwhere(flags.sel(limit_state="theta/alpha>=0.5").values)[0]
    flags.values[(*where, 0)] = False
    loose = ds.assign(exceeded=flags)
    with pytest.raises(InputError, match=r"not nested \('theta/alpha>=0.5' is exceeded where "):
        export_fragility(loose, tmp_path / "x.csv", "pelicun")
    # equal medians (two states exceeded in the same cases): a damage state that never occurs
    same = ds.copy(deep=True)
    same["median"][0, 1] = same["median"][0, 0]
    with pytest.raises(InputError, match=r"'theta/alpha>=0.5' .* is not above that of the milder"):
        export_fragility(same, tmp_path / "x.xml", "openquake")
    assert not (tmp_path / "x.csv").exists() and not (tmp_path / "x.xml").exists()
    # one state alone still exports
    alone = export_fragility(loose.sel(limit_state=["overturn"]), tmp_path / "y.csv", "pelicun")
    assert list(next(csv.DictReader(alone.open())))[-1] == "LS1-Theta_1"


def _pelicun_damage(path, ids, demand, unit, x, n, tmp_path):
    """pelicun's own damage calculation of the components ``ids`` of the damage-model CSV
    ``path``, n realizations at each demand value x (demand label, e.g. "PGA", in ``unit``):
    P(DS ≥ k) [x, k - 1] per component, and pelicun's fragility parameters."""
    # .ci/run runs these tests in an environment with pelicun and ROCKING_REQUIRE_PELICUN=1,
    # where a missing pelicun fails instead of skipping
    if os.environ.get("ROCKING_REQUIRE_PELICUN"):
        import pelicun
    else:
        pelicun = pytest.importorskip("pelicun")
    from pelicun import assessment, file_io

    asmnt = assessment.Assessment({"PrintLog": False, "Seed": 7})
    sample = tmp_path / "demand.csv"  # pelicun's sample format: labels, a row of units
    values = np.repeat(x, n)
    sample.write_text(
        f",{demand}-0-1\nUnits,{unit}\n"
        + "".join(f"{i},{v!r}\n" for i, v in enumerate(values.tolist()))
    )
    asmnt.demand.load_sample(str(sample))
    asmnt.stories = 1
    marginals = pelicun.base.pd.DataFrame(
        {"Units": "ea", "Location": "0", "Direction": "1", "Theta_0": 1.0}, index=ids
    )
    asmnt.asset.load_cmp_model({"marginals": marginals})
    asmnt.asset.generate_cmp_sample()
    db = file_io.load_data(
        str(path), reindex=False, unit_conversion_factors=asmnt.unit_conversion_factors
    )
    asmnt.damage.load_model_parameters([db], set(ids))
    asmnt.damage.calculate()
    damaged = {}
    for name in ids:
        # the sample holds the quantity of the component in each damage state (columns
        # component, location, direction, uid, damage state): 1 in the state it is in
        part = asmnt.damage.ds_model.sample.xs(name, axis=1, level=0)
        state = part.columns.get_level_values(-1).astype(int).to_numpy()
        in_state = part.to_numpy()
        states = range(1, max(state.max(), 1) + 1)
        at_least = np.stack([in_state[:, state >= k].sum(axis=1) for k in states], axis=1)
        damaged[name] = at_least.reshape(x.size, n, -1).mean(axis=1)
    return damaged, asmnt.damage.ds_model.damage_params


def _assert_binomial(fraction, expected, n):
    # pelicun draws a capacity per realization: the fraction is binomial, its standard
    # deviation sqrt(p(1 - p)/n) <= 0.0036 for n = 20 000; 5 of them (seeded, so the test is
    # repeatable)
    np.testing.assert_array_less(
        np.abs(fraction - expected), 5 * np.sqrt(expected * (1 - expected) / n) + 1e-12
    )


def test_pelicun_damage_probabilities_equal_the_lognormal_cdf(tmp_path):
    path = export_fragility(FITS, tmp_path / "dmg.csv", "pelicun", im="pga")
    n = 20_000  # realizations per demand value
    x = np.array([0.1, 0.25, 0.4, 0.8])  # PGA [g]
    ids = ["cabinet_A", "tank"]
    damaged, params = _pelicun_damage(path, ids, "PGA", "g", x, n, tmp_path)
    for name, fit in zip(ids, FITS.values()):
        # pelicun reads our median in g and turns it into m/s² (g = 9.80665 m/s²), β as it is
        assert params.loc[name, ("LS1", "Theta_0")] == pytest.approx(fit.median * 9.80665, 1e-15)
        assert params.loc[name, ("LS1", "Theta_1")] == fit.beta
        # state 1: overturned
        _assert_binomial(damaged[name][:, 0], fit.probability(x), n)


def test_pelicun_damage_states_of_several_limit_states_equal_ours(limit_states, tmp_path):
    # P(DS ≥ k) in pelicun, whose limit states share one drawn capacity per realization and
    # whose damage state is the highest limit state exceeded, equals our curve of the k-th
    # limit state by severity, Φ(ln(x/θ_k)/β), at demands across all three curves
    ds = limit_states
    path = export_fragility(ds, tmp_path / "ls.csv", "pelicun")
    ids = [r["ID"] for r in csv.DictReader(path.open())]
    n = 20_000
    x = np.array([0.15, 0.2, 0.25, 0.3, 0.35, 0.45, 0.55, 0.65, 0.8])  # PGV [m/s]
    damaged, params = _pelicun_damage(path, ids, "PGV", "mps", x, n, tmp_path)
    for b, name in enumerate(ids):
        assert damaged[name].shape == (x.size, 3)
        for k, state in enumerate(ORDER):
            fit = ds[["median", "beta"]].sel(limit_state=state).isel(body=b)
            median, beta = float(fit["median"]), float(fit["beta"])  # the state's own β
            # pelicun holds our median in m/s (its unit: mps) and our β, to pandas' parsing
            # of the file's repr (1 ulp off at times: 2e-16)
            assert params.loc[name, (f"LS{k + 1}", "Theta_0")] == pytest.approx(median, 1e-15)
            assert params.loc[name, (f"LS{k + 1}", "Theta_1")] == pytest.approx(beta, 1e-15)
            expected = LognormalFit(median, beta).probability(x)
            _assert_binomial(damaged[name][:, k], expected, n)
        # the demands tell the states apart: each is neither certain nor impossible somewhere
        assert np.any((damaged[name] > 0.05) & (damaged[name] < 0.95), axis=0).all()


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


def test_fragility_exports_every_limit_state(tmp_path):
    motions = tmp_path / "motions.nc"
    generate(8, duration=6.0, dt=1 / 200, seed=5).save(motions)
    bodies = tmp_path / "bodies.csv"
    bodies.write_text("name,R,gamma\nslim,0.5,5\nstocky,1.0,4\n")
    out = tmp_path / "frag"
    args = ["fragility", "--bodies", bodies, "--motions", motions, "--im", "pgv"]
    args += ["--levels", "0.05:1.0:0.05", "--limit-states", STATES, "--n-boot", 0]
    args += ["--out", out, "--quiet", "--export", "pelicun", "--export", "openquake"]
    result = CliRunner().invoke(main, [str(a) for a in args])
    assert result.exit_code == 0, result.output
    fits = {
        (r["body"], r["limit_state"]): r for r in csv.DictReader((out / "lognormal.csv").open())
    }
    rows = {r["ID"]: r for r in csv.DictReader((out / "fragility_pelicun.csv").open())}
    assert sorted(rows) == ["slim", "stocky"]
    for body, row in rows.items():
        # LS1..LS3: uplift, θ/α ≥ 0.5, overturn, each with the median and β of lognormal.csv
        # (lognormal.csv holds 12 significant digits, CSV_FLOAT_FORMAT, the pelicun file every
        # digit: rel 1e-9 is well above that rounding)
        for n, state in enumerate(ORDER, start=1):
            fit = fits[(body, state)]
            assert float(row[f"LS{n}-Theta_0"]) == pytest.approx(float(fit["median"]), rel=1e-9)
            assert float(row[f"LS{n}-Theta_1"]) == pytest.approx(float(fit["beta"]), rel=1e-9)
    model = _nrml(out / "fragility_openquake.xml")
    assert model.find("n:limitStates", NS).text.split() == [
        "uplift",
        "theta_alpha__0_5",
        "overturn",
    ]
    assert len(model.findall("n:fragilityFunction/n:params", NS)) == 2 * 3
