"""Record suites as motions: ``Ensemble.from_records`` and ``rocking motions import``.

Parsing against the files themselves, resampling against pure sines (kept below the new Nyquist
frequency, removed above it), round trips of the ensemble file with vertical components and
metadata, manifests whose errors name the row, CSV units, floor histories, and the command line
end to end into ``rocking fragility``.
"""

from __future__ import annotations

import json
import math
import re
import warnings
from pathlib import Path

import numpy as np
import pandas as pd
import pytest
from click.testing import CliRunner
from scipy import signal

from rocking.assessment.energy import assess
from rocking.cli import main
from rocking.dynamics.body import Block, G
from rocking.errors import InputError
from rocking.montecarlo.fragility import fragility_analysis
from rocking.motions.ensemble import PER_MEMBER, Ensemble, location_name
from rocking.motions.records import (
    Record,
    example_manifest_path,
    example_record_path,
    peer_title,
    read_manifest,
    read_record,
    read_records,
    resample,
    resampling_factors,
)
from rocking.motions.synthesis import generate

EL_CENTRO = example_record_path()
CHINO_HILLS = Path(__file__).parent / "data" / "RSN8883_14383980_13849360.AT2"

#: Pass-band ripple and stop-band gain of resample_poly's filter: a Kaiser window with
#: beta = 5 gives A = beta / 0.1102 + 8.7 = 54.1 dB of attenuation, i.e. a ripple
#: delta = 10^(-A/20) = 0.0020 in both bands (Kaiser's design formula, Oppenheim & Schafer,
#: Discrete-Time Signal Processing, Sec. 7.6).
DELTA = 10 ** (-(5.0 / 0.1102 + 8.7) / 20)


def _sine(f_hz: float, dt: float, duration: float = 10.0) -> np.ndarray:
    return np.sin(2 * np.pi * f_hz * np.arange(round(duration / dt) + 1) * dt)


def _interior_error(y: np.ndarray, dt: float, f_hz: float) -> float:
    """Largest deviation from the unit sine of frequency f, away from the ends (1 s each: the
    filter's half length is 10 max(up, down) input samples, well under 0.1 s here)."""
    t = np.arange(y.size) * dt
    inner = (t > 1.0) & (t < t[-1] - 1.0)
    return float(np.abs(y[inner] - np.sin(2 * np.pi * f_hz * t[inner])).max())


# ----------------------------------------------------------------------------- resampling


@pytest.mark.parametrize(
    "dt, new_dt, factors",
    [
        (0.005, 0.0025, (2, 1)),
        (0.02, 0.005, (4, 1)),
        (0.0025, 0.005, (1, 2)),
        (0.005, 0.004, (5, 4)),
    ],
)
def test_resampling_factors_are_the_exact_ratio(dt, new_dt, factors):
    assert resampling_factors(dt, new_dt) == factors


def test_resampling_by_no_fraction_is_refused():
    # dt / new_dt = pi: no p/q with p, q <= 1000 within 1e-9
    with pytest.raises(InputError, match=r"not p/q times it"):
        resampling_factors(0.01, 0.01 / math.pi)


@pytest.mark.parametrize("f_hz", [10.0, 60.0])
def test_downsampling_keeps_a_sine_below_the_new_nyquist(f_hz):
    # 400 Hz -> 200 Hz (new Nyquist 100 Hz). The filter's transition band is 100 Hz +- 16 Hz
    # (width (A - 7.95) / (2.285 M) rad/sample with M = 40 taps at 400 Hz, Oppenheim & Schafer
    # Eq. 7.63), so 10 and 60 Hz are in its pass band: kept to the ripple DELTA.
    y = resample(_sine(f_hz, 0.0025), 0.0025, 0.005)
    assert _interior_error(y, 0.005, f_hz) < DELTA


@pytest.mark.parametrize("f_hz", [130.0, 180.0])
def test_downsampling_removes_a_sine_above_the_new_nyquist(f_hz):
    # Above 116 Hz is the stop band: the sine is gone (gain < DELTA), not folded back to
    # 200 - f Hz. Taking every other sample, the aliasing this guards against, keeps it whole.
    x = _sine(f_hz, 0.0025)
    y = resample(x, 0.0025, 0.005)
    inner = slice(200, -200)
    assert np.abs(y[inner]).max() < DELTA
    assert np.abs(x[::2][inner]).max() > 0.9  # the aliased sine of plain decimation


def test_upsampling_interpolates_a_sine_to_the_ripple():
    # 50 Hz -> 200 Hz, a 5 Hz sine: band-limited interpolation is exact but for the ripple;
    # linear interpolation would be off by 1 - cos(pi f dt) ~ 5 % between samples.
    y = resample(_sine(5.0, 0.02), 0.02, 0.005)
    assert y.size == 4 * round(10.0 / 0.02) + 1  # up to the record's last time, 10 s
    assert _interior_error(y, 0.005, 5.0) < DELTA
    linear = np.interp(np.arange(y.size) * 0.005, np.arange(501) * 0.02, _sine(5.0, 0.02))
    assert _interior_error(linear, 0.005, 5.0) > 10 * DELTA


def test_from_records_resamples_with_the_filter_and_says_so():
    # A record with a 150 Hz component at 400 Hz, imported at 200 Hz: the component is removed,
    # a 10 Hz one kept; the metadata name the method, the filter and the original step.
    x = 0.1 * G * (_sine(10.0, 0.0025) + _sine(150.0, 0.0025))
    ens = Ensemble.from_records([Record(x, 0.0025, "two-sines", "memory")], dt=0.005)
    assert _interior_error(ens.acc[0] / (0.1 * G), 0.005, 10.0) < 2 * DELTA  # ripple + stop
    assert ens.meta["record_dt"] == [0.0025]
    assert "resample_poly" in ens.meta["resampling"]["method"]
    assert "Kaiser" in ens.meta["resampling"]["filter"]
    same = Ensemble.from_records([Record(x, 0.0025, "two-sines", "memory")])
    assert same.meta["resampling"] == {"method": "none"}
    np.testing.assert_array_equal(same.acc[0], x)


# ----------------------------------------------------------------------------- parsing


@pytest.mark.parametrize(
    "line, expected",
    [
        (
            "Helena Montana-01, 10/31/1935, Carroll College, 180",
            ("Helena Montana-01", "10/31/1935", "Carroll College", "180"),
        ),
        (  # NGA-West2: the event as its network number (tests/data/README.md)
            "14383980, 7/29/2008, Anaheim - Lakeview & Riverdale, 360",
            ("14383980", "7/29/2008", "Anaheim - Lakeview & Riverdale", "360"),
        ),
        (  # a comma in the event name: the date anchors the split
            "Chi-Chi, Taiwan, 9/20/1999, TCU065, E",
            ("Chi-Chi, Taiwan", "9/20/1999", "TCU065", "E"),
        ),
        (
            "Northridge-01, 1/17/1994, Arleta - Nordhoff Fire Sta, UP\r",
            ("Northridge-01", "1/17/1994", "Arleta - Nordhoff Fire Sta", "UP"),
        ),
        ("1559 points at equal spacing of 0.02 sec", ("", "", "", "")),  # El Centro: no title
        ("Helena Montana-01, 10/31/1935, 180", ("", "", "", "")),  # no station: not a title
    ],
)
def test_peer_title(line, expected):
    got = peer_title(line)
    assert (got["event"], got["date"], got["station"], got["component"]) == expected


def test_imported_records_match_their_files():
    # Counts are the NPTS of the headers and the peaks those of the files: El Centro 1559 values,
    # largest 0.31882 g (src/rocking/data/records/README.md); Chino Hills 16396 values at
    # 0.005 s, event 14383980 of 7/29/2008, Anaheim - Lakeview & Riverdale, 360 (tests/data/
    # README.md), its peak read here by a plain whitespace split of the file.
    ens = Ensemble.from_records([EL_CENTRO, CHINO_HILLS], dt=0.005)
    m = ens.meta
    assert m["record_npts"] == [1559, 16396] and m["record_dt"] == [0.02, 0.005]
    assert m["record_units"] == ["g", "g"]
    assert m["events"][1] == "14383980" and m["dates"][1] == "7/29/2008"
    assert m["stations"][1] == "Anaheim - Lakeview & Riverdale" and m["components"][1] == "360"
    assert m["events"][0] == ""  # El Centro's header has no PEER title line
    values = np.array(" ".join(CHINO_HILLS.read_text().splitlines()[4:]).split(), dtype=float)
    assert values.size == 16396
    assert ens.pga[1] == pytest.approx(np.abs(values).max(), rel=1e-12)  # not resampled
    assert read_record(EL_CENTRO).pga == pytest.approx(0.31882, rel=1e-12)


@pytest.mark.parametrize(
    "header, factor",
    [("time [s], acc [g]", G), ("time [s], acc [m/s2]", 1.0), ("time [s], acc [cm/s2]", 0.01)],
)
def test_csv_units_from_the_header(tmp_path, header, factor):
    path = tmp_path / "rec.csv"
    path.write_text(f"{header}\n0.00,0.0\n0.01,1.5\n0.02,-2.0\n0.03,0.25\n")
    ens = Ensemble.from_records([path])
    np.testing.assert_allclose(ens.acc[0], np.array([0.0, 1.5, -2.0, 0.25]) * factor, rtol=1e-15)
    assert ens.dt == pytest.approx(0.01, rel=1e-12)
    # units= gives the units of a file that states none; against the header's it is refused
    # (issue 48)
    plain = tmp_path / "plain.csv"
    plain.write_text("time,acc\n0.00,0.0\n0.01,1.5\n0.02,-2.0\n0.03,0.25\n")
    forced = Ensemble.from_records([plain], units="gal")
    np.testing.assert_allclose(forced.acc[0], [0.0, 0.015, -0.02, 0.0025], rtol=1e-15)
    assert forced.meta["record_units"] == ["cm/s2"]
    other = "mm/s2"
    with pytest.raises(InputError, match=rf"rec\.csv: units {other} given, but the file states"):
        Ensemble.from_records([path], units=other)


def test_one_column_files_take_record_dt(tmp_path):
    path = tmp_path / "one.txt"
    path.write_text("0.1\n-0.2\n0.3\n")
    with pytest.raises(InputError, match="one-column file needs the time step"):
        Ensemble.from_records([path])
    ens = Ensemble.from_records([path], record_dt=0.02)
    assert ens.dt == 0.02
    np.testing.assert_allclose(ens.acc[0], np.array([0.1, -0.2, 0.3]) * G, rtol=1e-15)


# ----------------------------------------------------------------------------- the file


def _two_component_suite(tmp_path) -> Ensemble:
    """Chino Hills with itself as vertical (scaled 0.5) and a short CSV record, at 0.005 s."""
    short = tmp_path / "short.csv"
    short.write_text("t,acc [m/s2]\n" + "".join(f"{0.005 * k:.3f},{k % 3 - 1}\n" for k in range(9)))
    return Ensemble.from_records(
        [CHINO_HILLS, short], vertical=[CHINO_HILLS, None], scale=[0.5, 1.0]
    )


def test_vertical_components_are_carried_scaled_and_padded(tmp_path):
    ens = _two_component_suite(tmp_path)
    ch = read_record(CHINO_HILLS)
    assert ens.av is not None and ens.av.shape == ens.acc.shape == (2, ch.acc.size)
    np.testing.assert_array_equal(ens.acc[0], 0.5 * ch.acc)  # both components scaled by 0.5
    np.testing.assert_array_equal(ens.av[0], 0.5 * ch.acc)
    assert np.all(ens.av[1] == 0.0)  # no vertical record: no vertical motion
    np.testing.assert_array_equal(ens.acc[1, :9], [k % 3 - 1 for k in range(9)])
    assert np.all(ens.acc[1, 9:] == 0.0)  # padded with zeros at the end
    assert ens.meta["record_scale"] == [0.5, 1.0]
    assert ens.meta["vertical_sources"] == [str(CHINO_HILLS), ""]
    # scaled and scaled_by scale both components by one factor
    doubled = ens.scaled_by(2.0)
    np.testing.assert_array_equal(doubled.av, 2.0 * ens.av)
    to_agx = ens.scaled(0.4)
    np.testing.assert_allclose(to_agx.av, to_agx.meta["scale"] * ens.av, rtol=1e-15)
    assert not ens.av.flags.writeable


def test_round_trip_keeps_av_and_metadata(tmp_path):
    ens = _two_component_suite(tmp_path)
    path = ens.save(tmp_path / "suite.nc")
    back = Ensemble.load(path)
    np.testing.assert_array_equal(back.acc, ens.acc)
    np.testing.assert_array_equal(back.av, ens.av)
    assert back.labels == ens.labels and back.dt == ens.dt and back.meta == ens.meta
    # a file without vertical components loads as before: no av
    plain = generate(2, duration=2.0).save(tmp_path / "plain.nc")
    assert Ensemble.load(plain).av is None


def test_subset_keeps_every_per_member_entry_in_step(tmp_path):
    ens = _two_component_suite(tmp_path)
    sub = ens.subset([1, 0])
    for key in PER_MEMBER:
        if key in ens.meta:
            assert sub.meta[key] == [ens.meta[key][1], ens.meta[key][0]], key
    np.testing.assert_array_equal(sub.av, ens.av[[1, 0]])
    assert sub.labels == (ens.labels[1], ens.labels[0])


def test_av_must_match_acc():
    with pytest.raises(InputError, match=r"av has shape \(1, 5\), acc \(2, 5\)"):
        Ensemble(np.zeros((2, 5)), 0.01, av=np.zeros(5))
    with pytest.raises(InputError, match="av contains a non-finite"):
        Ensemble(np.zeros((1, 5)), 0.01, av=[0, 0, math.nan, 0, 0])


def test_ensembles_and_folders_are_appended(tmp_path):
    # Generated motions merged with real records: the generated members keep their labels and
    # kind, the records theirs; a folder gives its files sorted by name; a repeated label is
    # numbered.
    gen = generate(2, duration=3.0, dt=0.005, seed=1)
    gen.save(tmp_path / "b-generated.nc")
    (tmp_path / "a.csv").write_text("t,acc [g]\n0,0.1\n0.005,0.2\n0.010,0.0\n")
    (tmp_path / "notes.md").write_text("not a motion")
    ens = Ensemble.from_records([tmp_path, tmp_path / "a.csv"])
    assert ens.labels == ("a", *gen.labels, "a-2")
    assert ens.meta["kinds"] == ["recorded", "simulated", "simulated", "recorded"]
    assert ens.meta["kind"] == "mixed" and not ens.simulated
    np.testing.assert_array_equal(ens.acc[1:3, : gen.n_t], gen.acc)
    assert ens.meta["sources"][1] == str(tmp_path / "b-generated.nc")
    # appending an imported suite keeps its per-member metadata and multiplies the scales
    suite = Ensemble.from_records([CHINO_HILLS], scale=0.5).scaled_by(2.0)
    merged = Ensemble.from_records([suite, EL_CENTRO], dt=0.005, scale=[3.0, 1.0])
    assert merged.meta["record_scale"] == [3.0, 1.0]
    assert merged.meta["events"] == ["14383980", ""] and merged.meta["record_dt"] == [0.005, 0.02]
    np.testing.assert_allclose(merged.acc[0], 3.0 * read_record(CHINO_HILLS).acc, rtol=1e-15)


def test_different_steps_are_refused_in_one_line():
    with pytest.raises(InputError) as err:
        Ensemble.from_records(["example", CHINO_HILLS])
    msg = str(err.value)
    assert "\n" not in msg
    assert "0.005 s: RSN8883_14383980_13849360" in msg and "0.02 s: ElCentro1940_NS" in msg
    assert "--dt" in msg


# ----------------------------------------------------------------------------- manifests


def test_manifest_rows_relative_to_its_folder(tmp_path):
    folder = tmp_path / "suite"
    (folder / "records").mkdir(parents=True)
    (folder / "records" / "h.csv").write_text("t,acc [cm/s2]\n0,10\n0.01,-20\n0.02,5\n")
    (folder / "records" / "v.csv").write_text("t,acc [cm/s2]\n0,1\n0.01,2\n0.02,3\n")
    manifest = folder / "manifest.csv"
    manifest.write_text(
        "# suite of two\nHorizontal,vertical,scale\nrecords/h.csv,records/v.csv,2\nexample,,\n"
    )
    rows = read_manifest(manifest)
    assert [r.row for r in rows] == [1, 2] and [r.line for r in rows] == [3, 4]
    assert rows[1].horizontal == EL_CENTRO and rows[1].vertical is None and rows[1].scale == 1.0
    ens = Ensemble.from_records(manifest=manifest, dt=0.01)
    np.testing.assert_allclose(ens.acc[0, :3], [0.2, -0.4, 0.1], rtol=1e-15)  # 2 x cm/s2
    np.testing.assert_allclose(ens.av[0, :3], [0.02, 0.04, 0.06], rtol=1e-15)
    assert ens.labels == ("h", "ElCentro1940_NS") and ens.meta["record_scale"] == [2.0, 1.0]


# Largest |value| [g] of each channel as stated in its source file's header ("Max = ... g"),
# the CSMIP V1 files of the 2019 M7.1 Ridgecrest earthquake in gmprocess 2.8.0's demo data.
RIDGECREST_HEADER_PGA = {
    "CCC_090": 0.567, "CCC_360": 0.471, "CCC_UP": 0.361,
    "CLC_090": 0.344, "CLC_360": 0.511, "CLC_UP": 0.347,
    "TOW2_090": 0.437, "TOW2_360": 0.386, "TOW2_UP": 0.360,
}  # fmt: skip


def test_shipped_records_keep_their_source_peaks_and_come_to_rest():
    # The shipped Ridgecrest files were cut to 30 s, tapered and high-passed at 0.1 Hz
    # (tools/ridgecrest_records.py). That processing leaves the peak acceleration of the source
    # within 1.5 % (the largest change, 1.0 %, is CLC 090, whose filter removes a long-period
    # offset) and the ground at rest at the end: the velocity integrated from the file returns
    # to < 0.03 m/s (the uncorrected records drift up to 0.2 m/s over the same window).
    ens = Ensemble.from_records(manifest="example", dt=0.01)
    assert ens.n == 7 and sum(map(bool, ens.meta["vertical_sources"])) == 6
    assert ens.meta["stations"][1] == "China Lake NWC Christmas Canyon Rd (CI.CCC)"
    peaks = {}
    for path in example_manifest_path().parent.glob("Ridgecrest2019_*.AT2"):
        rec = read_record(path)
        peaks[path.stem.removeprefix("Ridgecrest2019_")] = np.abs(rec.acc).max() / G
        v = np.cumsum(rec.acc) * rec.dt
        assert abs(v[-1]) < 0.03, path.name
    assert peaks.keys() == RIDGECREST_HEADER_PGA.keys()
    for name, pga in RIDGECREST_HEADER_PGA.items():
        assert peaks[name] == pytest.approx(pga, rel=0.015), name


def test_horizontal_only_leaves_the_verticals_out():
    both = Ensemble.from_records(manifest="example", dt=0.01)
    flat = Ensemble.from_records(manifest="example", dt=0.01, horizontal_only=True)
    assert flat.av is None and flat.meta["vertical_sources"] == [""] * 7
    np.testing.assert_array_equal(flat.acc, both.acc)


@pytest.mark.parametrize(
    "text, expected",
    [
        (
            "horizontal,scale\nh.csv,1\nmissing.AT2,1\n",
            r"row 2 \(line 3\): horizontal record .*missing\.AT2: no such file",
        ),
        ("horizontal,vertical\nh.csv,gone.csv\n", r"row 1 \(line 2\): vertical record .*gone\.csv"),
        ("horizontal,scale\nh.csv,-1\n", r"row 1 \(line 2\): scale must be a number > 0, got '-1'"),
        ("horizontal,scale\nh.csv,\nh.csv,x\n", r"row 2 \(line 3\): scale must be"),
        ("horizontal,scale\n,2\n", r"row 1 \(line 2\): no horizontal record"),
        ("horizontal\nh.csv,2\n", r"row 1 \(line 2\): 2 cells for 1 columns"),
        (
            "horizontal,vertcal\nh.csv,h.csv\n",
            r"line 1: the header must name .* got horizontal, vertcal",
        ),
        ("file\nh.csv\n", r"line 1: the header must name"),
        ("horizontal\n", r"names no motions"),
        ("", r"empty manifest"),
        ("horizontal\nbad.csv\n", r"row 1 \(line 2\): .*bad\.csv: line 3: not a finite number"),
        ("horizontal,dt\nh.csv,-0.01\n", r"row 1 \(line 2\): dt must be a finite number > 0"),
    ],
)
def test_manifest_errors_name_the_row(tmp_path, text, expected):
    (tmp_path / "h.csv").write_text("t,a\n0,0.1\n0.01,0.2\n")
    (tmp_path / "bad.csv").write_text("t,a\n0,0.1\n0.01,x\n")
    manifest = tmp_path / "m.csv"
    manifest.write_text(text)
    with pytest.raises(InputError, match=expected) as err:
        Ensemble.from_records(manifest=manifest)
    assert "m.csv" in str(err.value)


# ----------------------------------------------------------------------------- floors


def _floor_history(tmp_path) -> tuple[Path, Path, np.ndarray]:
    """Floor absolute accelerations of a structural model "exported from another program": a
    1-DOF oscillator (T = 0.4 s, 5 %) under El Centro solved by scipy.signal.lsim, written as a
    CSV in cm/s2 (floor 1) and a PEER file in g (floor 2, twice the motion)."""
    rec = read_record(EL_CENTRO)
    wn, zeta = 2 * np.pi / 0.4, 0.05
    # absolute acceleration of a base-excited oscillator: (2 zeta wn s + wn^2)/(s^2 + ...)
    system = signal.lti([2 * zeta * wn, wn**2], [1.0, 2 * zeta * wn, wn**2])
    _, floor, _ = signal.lsim(system, rec.acc, rec.t)
    csv_path = tmp_path / "floor1.csv"
    pd.DataFrame({"time [s]": rec.t, "acc [cm/s2]": 100 * floor}).to_csv(
        csv_path, index=False, float_format="%.9e"
    )
    values = 2 * floor / G
    at2 = tmp_path / "floor2.AT2"
    at2.write_text(
        "PEER-style export\nfloor 2 of my model\nACCELERATION IN UNITS OF G\n"
        f"NPTS= {values.size}, DT= {rec.dt:.5f} SEC\n"
        + "\n".join(
            " ".join(f"{v:.9e}" for v in values[i : i + 5]) for i in range(0, values.size, 5)
        )
        + "\n"
    )
    return csv_path, at2, floor


def test_floor_histories_import_with_their_location(tmp_path):
    csv_path, at2, floor = _floor_history(tmp_path)
    ens = Ensemble.from_records([csv_path, at2], location="floor 3")
    assert ens.meta["location"] == "floor 3" and ens.labels == ("floor1", "floor2")
    # the exported values come back in m/s2 to the 10 significant digits written
    np.testing.assert_allclose(ens.acc[0], floor, rtol=1e-9, atol=1e-12)
    np.testing.assert_allclose(ens.acc[1], 2 * floor, rtol=1e-9, atol=1e-12)
    assert ens.meta["record_units"] == ["cm/s2", "g"]
    # the floor response of a 0.4 s oscillator amplifies El Centro's PGA (resonance near its
    # 2-3 Hz content): a sanity check that these are the floor's, not the ground's, motions
    assert ens.pga[0] > read_record(EL_CENTRO).pga
    path = ens.save(tmp_path / "floor.nc")
    assert Ensemble.load(path).meta["location"] == "floor 3" and not Ensemble.load(path).simulated
    # ground motions do not mix with floor motions
    with pytest.raises(InputError, match=r"at 'ground', not at 'floor 3'"):
        Ensemble.from_records([path, generate(1, duration=2.0)], location="floor 3")
    with pytest.raises(
        InputError, match=r"floor\.nc: its motions are at 'floor 3', not at 'ground'"
    ):
        Ensemble.from_records([path])


def test_locations_are_ground_or_floors(tmp_path):
    # Issue 48: --location "roof garden" was accepted; the package knows the ground and floor N
    # (of a frame), as the floor ensembles of rocking.structures name them.
    assert location_name(" Ground ") == "ground"
    assert location_name("FLOOR  3") == "floor 3"
    assert location_name("floor 2 of paper-2.0") == "floor 2 of paper-2.0"
    for bad in ("roof garden", "floor 0", "floor", "floor -1", "basement", ""):
        with pytest.raises(InputError, match=r"location .* is not understood; give ground, floor"):
            location_name(bad)
    with pytest.raises(InputError, match=r"location 'roof garden' is not understood"):
        Ensemble.from_records([EL_CENTRO], location="roof garden")


def test_one_step_for_several_one_column_files_is_refused(tmp_path):
    # Issue 48: one --record-dt was applied to every one-column file, so a 100 Hz and a 200 Hz
    # file were both taken at 0.01 s (one silently compressed). One step serves one file;
    # several need theirs, in a manifest's dt column.
    fast, slow = tmp_path / "fast.txt", tmp_path / "slow.txt"
    fast.write_text("".join(f"{0.1 * math.sin(k / 5):.6f}\n" for k in range(400)))  # 200 Hz
    slow.write_text("".join(f"{0.1 * math.sin(k / 2.5):.6f}\n" for k in range(200)))  # 100 Hz
    with pytest.raises(InputError, match=r"one time step \(0\.01 s\) for 2 one-column files "):
        Ensemble.from_records([fast, slow], record_dt=0.01)
    with pytest.raises(InputError, match=r"one time step .* for 2 one-column files"):
        read_records([fast, slow], dt=0.01)
    manifest = tmp_path / "m.csv"
    manifest.write_text("horizontal,dt\nfast.txt,0.005\nslow.txt,0.01\n")
    ens = Ensemble.from_records(manifest=manifest, dt=0.005)
    assert ens.meta["record_dt"] == [0.005, 0.01]
    # both are the same 2 s of one sine (period 31.4 samples at 200 Hz, 15.7 at 100 Hz)
    assert ens.meta["record_npts"] == [400, 200]
    # one one-column file (with two-column ones) still takes --record-dt
    two = tmp_path / "two.csv"
    two.write_text("t,a\n0,0.1\n0.01,0.2\n0.02,-0.1\n")
    assert Ensemble.from_records([slow, two], record_dt=0.01).dt == 0.01


def test_coarse_steps_are_refused():
    # Issue 48: resampling a record to a 5 s step was accepted. The bound is 0.05 s (Nyquist
    # 10 Hz, above the 9 Hz of RG 1.60's control point B): rocking.motions.records.MAX_DT.
    with pytest.raises(InputError, match=r"dt = 5 s is coarser than 0\.05 s"):
        Ensemble.from_records([EL_CENTRO], dt=5.0)
    assert Ensemble.from_records([EL_CENTRO], dt=0.05).dt == 0.05


def test_all_zero_motions_have_no_agx(tmp_path):
    # Issue 49: an all-zero ensemble gave "+inf safe" in assess and NumPy RuntimeWarnings
    # (division by zero) in fragility before its error. It has no A_gx: an InputError names
    # the members, with no warning; its file is refused when loaded.
    zero = Ensemble(np.zeros((3, 100)), 0.01, ["a", "b", "c"])
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        with pytest.raises(InputError, match=r"every member of the ensemble is zero \(a, b, c\)"):
            print(zero.agx)
        with pytest.raises(InputError, match=r"zero \(a, b, c\): it has no A_gx"):
            zero.scaled(0.5)
        with pytest.raises(InputError, match=r"zero \(a, b, c\): it has no A_gx"):
            fragility_analysis(Block(1.0, 4.0), zero, levels=[0.1])
        # assess reads no A_gx without agx: its spectrum is zero, which cannot judge a body
        # (it reported "+inf safe")
        with pytest.raises(InputError, match=r"largest PSV in the band .* is 0 m/s"):
            assess(Block(1.0, 4.0), zero)
    path = zero.save(tmp_path / "zero.nc")
    with pytest.raises(InputError, match=r"zero\.nc: every member is zero everywhere \(a, b, c\)"):
        Ensemble.load(path)
    # a zero member among others would never move, scaled with them: refused too
    flat = tmp_path / "flat.csv"
    flat.write_text("t,a\n0,0\n0.01,0\n0.02,0\n")
    with pytest.raises(
        InputError, match=r"the records: 1 member\(s\) are zero everywhere \(flat\)"
    ):
        Ensemble.from_records([flat, EL_CENTRO], dt=0.01)


def _rewritten(path: Path, out: Path, **changes) -> Path:
    """The ensemble file ``path`` copied to ``out`` with its attribute ``dt`` or its variable
    ``acc`` changed (as another program might write it)."""
    from scipy.io import netcdf_file

    with netcdf_file(path, "r", mmap=False) as src, netcdf_file(out, "w", version=2) as dst:
        for name, size in src.dimensions.items():
            dst.createDimension(name, size)
        for name, var in src.variables.items():
            new = dst.createVariable(name, var.typecode(), var.dimensions)
            new[:] = changes.get(name, var[:])
        for key, value in src._attributes.items():
            setattr(dst, key, changes.get(key, value))
    return out


def test_inconsistent_or_absurd_ensemble_files_are_refused(tmp_path):
    ens = Ensemble.from_records([EL_CENTRO], dt=0.0025)
    path = ens.save(tmp_path / "good.nc")
    # Issue 49: attribute dt 0.01 s against a time axis of 0.0025 s was used without a word
    bad_dt = _rewritten(path, tmp_path / "dt.nc", dt=0.01)
    with pytest.raises(
        InputError,
        match=r"dt\.nc: its attribute dt = 0\.01 s disagrees with its time axis, whose step is "
        r"0\.0025 s",
    ):
        Ensemble.load(bad_dt)
    # Issue 49: a sample of 1e30 g imported as "A_gx = 1e+30 g" and was used
    acc = ens.acc.copy()
    acc[0, 100] = 1e30 * G
    huge = _rewritten(path, tmp_path / "huge.nc", acc=acc)
    with pytest.raises(InputError, match=r"huge\.nc: member ElCentro1940_NS peaks at 1e\+30 g"):
        Ensemble.load(huge)
    acc[0, 100] = math.inf
    inf = _rewritten(path, tmp_path / "inf.nc", acc=acc)
    with pytest.raises(InputError, match=r"inf\.nc: acc contains a non-finite value"):
        Ensemble.load(inf)
    assert Ensemble.load(path).dt == 0.0025


# ----------------------------------------------------------------------------- command line


def _invoke(args):
    return CliRunner().invoke(main, [str(a) for a in args])


def _fragility(tmp_path, motions: Path, n_motions: int) -> pd.DataFrame:
    """``rocking fragility`` on the file: a stocky body (B/H = 1/1.2, uplift needs a ground
    acceleration of g B/H = 0.83 g, Housner 1963) never overturns at A_gx = 0.1 g, whose
    members peak well below that; a slender one is computed alongside."""
    bodies = tmp_path / "bodies.csv"
    bodies.write_text("name,R,gamma\nstocky,1.0,1.2\nslender,0.3,8\n")
    out = tmp_path / f"frag-{motions.stem}"
    result = _invoke(
        [
            "fragility",
            "--bodies",
            bodies,
            "--motions",
            motions,
            "--agx",
            "0.1:0.5:0.4",
            "--out",
            out,
            "--quiet",
        ]
    )
    assert result.exit_code == 0, result.output
    table = pd.read_csv(out / "probabilities.csv")
    assert (table["n"] == n_motions).all()
    stocky = table[(table["body"] == "stocky") & np.isclose(table["agx"], 0.1)]
    assert stocky["count"].item() == 0
    return table


def test_cli_import_end_to_end_into_fragility(tmp_path):
    short = tmp_path / "short.csv"
    short.write_text(
        "time [s], acc [cm/s2]\n"
        + "".join(f"{0.01 * k:.2f},{50 * math.sin(k / 3):.6f}\n" for k in range(400))
    )
    manifest = tmp_path / "manifest.csv"
    manifest.write_text("horizontal,vertical,scale\nshort.csv,short.csv,0.5\n")
    out = tmp_path / "suite.nc"
    result = _invoke(
        ["motions", "import", "example", short, "--manifest", manifest, "--dt", 0.01, "--out", out]
    )
    assert result.exit_code == 0, result.output
    assert "wrote" in result.output and "3 motions" in result.output
    assert "1 with a vertical component" in result.output and "1 resampled" in result.output
    ens = Ensemble.load(out)
    assert ens.labels == ("ElCentro1940_NS", "short", "short-2") and ens.dt == 0.01
    assert ens.meta["record_dt"] == [0.02, 0.01, 0.01] and ens.av is not None
    assert ens.pga[0] == pytest.approx(0.31882, rel=3e-3)  # upsampled 2x: peak within the ripple
    _fragility(tmp_path, out, 3)


def test_cli_import_floor_histories_into_fragility(tmp_path):
    csv_path, at2, _ = _floor_history(tmp_path)
    out = tmp_path / "floors.nc"
    result = _invoke(["motions", "import", csv_path, at2, "--location", "floor 3", "--out", out])
    assert result.exit_code == 0, result.output
    assert "at floor 3" in result.output
    _fragility(tmp_path, out, 2)
    run = json.loads((tmp_path / "frag-floors" / "run.json").read_text())
    assert run["location"] == "floor 3"


@pytest.mark.parametrize(
    "args, expected",
    [
        (["example", CHINO_HILLS], r"0\.005 s: RSN8883.*0\.02 s: ElCentro.*--dt"),
        ([], r"name at least one RECORD or give --manifest"),
        (["no-such-file.AT2"], r"no-such-file\.AT2: no such file or folder"),
        (
            ["example", "--dt", 0.02 / math.pi],  # 0.02 s / dt = pi: no fraction p/q
            r"ElCentro1940_NS\.AT2: dt = 0\.00636\d* s: the record step 0\.02 s is not p/q",
        ),
        # issues 48 and 49
        (["example", "--units", "furlongs"], r"--units: unit 'furlongs' is not a unit of"),
        (["example", "--units", "cm/s2"], r"NS\.AT2: units cm/s2 given, but the file states g"),
        (["example", "--dt", 5], r"dt = 5 s is coarser than 0\.05 s"),
        (["example", "--location", "roof garden"], r"location 'roof garden' is not understood"),
        (
            ["example", "--out", "{tmp}/suite.txt"],
            r"suite\.txt: an ensemble is written as a netCDF",
        ),
        (["{tmp}/in.nc", "--out", "{tmp}/in.nc"], r"--out .*in\.nc is also an input"),
        (["{tmp}", "--out", "{tmp}/in.nc"], r"--out .*in\.nc is also an input"),
        (["{tmp}/a.txt", "{tmp}/b.txt", "--record-dt", 0.01], r"one time step \(0\.01 s\) for 2"),
        (["{tmp}/odd.txt"], r"odd\.txt: format not recognised \(line 2: .*PEER \.AT2"),
        (["--manifest", "{tmp}/binary.csv"], r"binary\.csv: the manifest is not a text file"),
    ],
)
def test_cli_import_errors_are_one_line(tmp_path, args, expected):
    Ensemble.from_records([EL_CENTRO]).save(tmp_path / "in.nc")
    for name in ("a.txt", "b.txt"):
        (tmp_path / name).write_text("0.1\n-0.2\n0.3\n")
    (tmp_path / "odd.txt").write_text("1 2\n3 4 5\n")
    (tmp_path / "binary.csv").write_bytes(b"\x89PNG\r\n\x1a\n\0\0\0\rIHDR")
    args = [str(a).replace("{tmp}", str(tmp_path)) for a in args]
    if "--out" not in args:
        args += ["--out", tmp_path / "suite.nc"]
    before = (tmp_path / "in.nc").read_bytes()
    out = tmp_path / "suite.nc"
    result = _invoke(["motions", "import", *args])
    assert (tmp_path / "in.nc").read_bytes() == before
    assert result.exit_code == 1
    lines = result.output.strip().splitlines()
    assert len(lines) == 1 and lines[0].startswith("Error: "), result.output
    assert re.search(expected, lines[0]), lines[0]
    assert not out.exists()


def test_cli_import_warns_of_an_implausible_peak_in_one_line(tmp_path):
    # Issue 48: a record in gal imported without --units became a motion of A_gx = 31.3 g
    # without a word. The warning is one line, on standard error, naming the likely units.
    gal = tmp_path / "gal.csv"
    gal.write_text(
        "t,a\n" + "".join(f"{0.01 * k:.2f},{31.3 * math.sin(k / 9):.6f}\n" for k in range(300))
    )
    result = _invoke(["motions", "import", gal, "--out", tmp_path / "g.nc"])
    assert result.exit_code == 0, result.output
    warned = [line for line in result.stderr.splitlines() if line.startswith("warning: ")]
    assert len(warned) == 1 and "likely in" in warned[0] and "cm/s2" in warned[0], result.stderr
    assert "wrote" in result.stdout
    # with the units stated, no warning
    fine = _invoke(["motions", "import", gal, "--units", "gal", "--out", tmp_path / "ok.nc"])
    assert fine.exit_code == 0 and "Warning" not in fine.output, fine.output


def test_cli_generate_out_must_be_netcdf(tmp_path):
    # Issue 48: `motions generate --out m.txt` wrote a netCDF file named .txt
    result = _invoke(["motions", "generate", "--n", 2, "--out", tmp_path / "m.txt"])
    assert result.exit_code == 1 and result.output.count("\n") == 1, result.output
    assert "m.txt: an ensemble is written as a netCDF file, named .nc" in result.output
    assert not (tmp_path / "m.txt").exists()
