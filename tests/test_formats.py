"""Records of strong-motion networks (issue 47): K-NET/KiK-net, ESM/ITACA, COSMOS V1/V2, SAC and
miniSEED, recognised by their headers, with their units, steps, peaks and metadata.

The text fixtures in tests/data/formats were written by us to each published format (see the
README there); the SAC and miniSEED files are written by ObsPy itself in the tests. Values are
compared with rtol 1e-12 where the test computes them with the reader's arithmetic (floating-point
rounding apart); stated peaks to the rounding of the digits the header prints.
"""

from __future__ import annotations

import shutil
import sys
import warnings
from pathlib import Path

import numpy as np
import pytest
from click.testing import CliRunner

from rocking.cli import main
from rocking.dynamics.body import G
from rocking.errors import InputError
from rocking.motions.ensemble import Ensemble
from rocking.motions.formats import RecordHeaderWarning
from rocking.motions.records import read_record, read_records

DATA = Path(__file__).parent / "data" / "formats"
KIKNET = DATA / "XXXH011103111446.EW2"
ESM = DATA / "XX.TST1.00.HNE.D.20161030.064017.C.ACC.ASC"
COSMOS = DATA / "XXTEST1.V2c"

#: The counts of the K-NET fixture (its last 3 lines) and its scale factor 3920(gal)/6182761.
KNET_COUNTS = [12, 15, 9, -40, 220, -515, 1380, -2650, 4012, -3390, 2105, -980, 410, -120]
KNET_COUNTS += [33, 18, 11, 14, 12, 10, 13, 12, 11, 12]


def _copy(src: Path, dst: Path, old: str = "", new: str = "") -> Path:
    dst.write_text(src.read_text().replace(old, new, 1) if old else src.read_text())
    return dst


def _no_warnings(path: Path, **kw):
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        return read_record(path, **kw)


# ---------------------------------------------------------------------------------- K-NET


def test_kiknet_counts_scaled_to_gal_with_the_mean_removed():
    rec = _no_warnings(KIKNET)
    # NIED's definition: acceleration [gal] = counts × 3920/6182761, minus the record's mean.
    gal = np.array(KNET_COUNTS) * (3920.0 / 6182761.0)
    gal -= gal.mean()
    np.testing.assert_allclose(rec.acc, gal * 0.01, rtol=1e-12)  # 1 gal = 0.01 m/s²
    assert abs(rec.acc.mean()) < 1e-15
    assert rec.dt == pytest.approx(0.01)  # Sampling Freq(Hz) 100Hz
    assert rec.units == "cm/s2"
    # the header's Max. Acc. (gal) 2.527 is the peak after the mean is removed, to its rounding
    assert abs(rec.pga * G * 100.0 - 2.527) <= 0.0005
    assert rec.format == "KiK-net"
    assert rec.name == "XXXH011103111446.EW2"  # the file's stem is the same for NS2 and UD2
    assert rec.component == "EW2 (KiK-net surface)"
    assert rec.station == "XXXH01"
    assert rec.date == "2011/03/11 14:46:00 JST (UTC+9)"
    assert rec.event == "M 9.0, 38.103N 142.860E, depth 24 km"
    assert rec.header["Scale Factor"] == "3920(gal)/6182761"
    assert rec.header["Record Time"] == "2011/03/11 14:46:21"


@pytest.mark.parametrize(
    ("suffix", "direction", "component", "fmt"),
    [
        (".EW1", "E-W", "EW1 (KiK-net borehole)", "KiK-net"),
        (".EW", "E-W", "EW (K-NET surface)", "K-NET"),
        (".dat", "E-W", "EW (sensor not stated)", "K-NET/KiK-net"),  # told by its header
        (".dat", "2", "EW1 (KiK-net borehole)", "KiK-net"),  # Dir. 1-6: KiK-net's numbering
        (".dat", "6", "UD2 (KiK-net surface)", "KiK-net"),
    ],
)
def test_knet_sensor_from_extension_or_direction(tmp_path, suffix, direction, component, fmt):
    path = _copy(KIKNET, tmp_path / f"rec{suffix}", "Dir.              E-W", f"Dir.{direction:>17}")
    rec = _no_warnings(path)
    assert (rec.component, rec.format) == (component, fmt)


# ------------------------------------------------------------------------------------ ESM


#: The values of the ESM fixture [cm/s²], one per line after its 53 header lines.
ESM_VALUES = [0.012, -0.034, 0.51, -2.205, 7.812, -15.337, 23.904, -18.461, 9.12, -4.006, 1.75]
ESM_VALUES += [-0.62, 0.18, -0.05, 0.011, 0.0]


def test_esm_values_step_units_and_metadata():
    rec = _no_warnings(ESM)
    np.testing.assert_allclose(rec.acc, np.array(ESM_VALUES) * 0.01, rtol=1e-12)
    assert rec.dt == pytest.approx(0.01)
    assert rec.units == "cm/s2"
    assert rec.pga * G == pytest.approx(0.23904)  # PGA_CM/S^2: 23.904000, at TIME_PGA_S 0.06
    assert rec.format == "ESM"
    assert (rec.event, rec.date) == ("NORCIA", "2016-10-30 06:40:17 UTC")
    assert (rec.station, rec.component) == ("XX.TST1", "HNE")
    assert rec.header["EVENT_ID"] == "EMSC-20161030_0000029"


# --------------------------------------------------------------------------------- COSMOS


def test_cosmos_v2_acceleration_series():
    rec = _no_warnings(COSMOS)
    assert rec.dt == pytest.approx(0.01)  # real header #62: 10.0 ms
    assert rec.units == "cm/s2"  # unit code 04 of the data line
    assert rec.acc.size == 20  # the velocity and displacement series are skipped
    # fixed-width values that touch ("96.50000-123.45678" in 8F10.5) are read apart
    np.testing.assert_allclose(rec.acc[6:9], [0.965, -1.2345678, -2.3456789], rtol=1e-12)
    assert rec.pga * G == pytest.approx(2.3456789)  # real header #64: -234.56789 at #65 0.08 s
    assert rec.format == "COSMOS V2"
    assert rec.component == "90 deg"  # integer header #54
    assert rec.station == "XX-TEST1 Test Station, Nowhere"
    assert rec.event.startswith("Test Earthquake")
    assert rec.header["real #62"] == "10.000000"


def test_cosmos_v1_in_g_with_other_header_layouts():
    # real header in 5F15.6 on 20 lines, data in 5E16.7, "units=g(02),Format=(5E16.7)" without
    # blanks: the layout of CESMD-processed files
    rec = _no_warnings(DATA / "XXTST2.V1c")
    assert rec.format == "COSMOS V1"
    assert rec.dt == pytest.approx(0.005)  # real header #62: 5.0 ms
    assert rec.units == "g"  # unit code 02
    g_values = [0.001, -0.0025, 0.0125, -0.05, 0.1375, -0.2116, 0.1804, -0.09, 0.03, -0.008]
    np.testing.assert_allclose(rec.acc, np.array([*g_values, 0.002, 0.0]) * G, rtol=1e-12)
    assert rec.pga == pytest.approx(0.2116)  # real header #64 -0.2116 g at #65 0.025 s
    assert rec.component == "Up"  # integer header #54: 400
    assert rec.station == "XX-TST2 Second Test Station"


def test_cosmos_file_with_two_channels_refused(tmp_path):
    first = COSMOS.read_text().split("Velocity data")[0]
    two = tmp_path / "two.V2c"
    two.write_text(first + first)  # two channels' accelerations in one file
    with pytest.raises(InputError, match=r"two\.V2c: a COSMOS file with 2 acceleration series"):
        read_record(two)


# ------------------------------------------------------------- edited fixtures: errors, warnings


@pytest.mark.parametrize(
    ("fixture", "name", "old", "new", "match"),
    [
        (KIKNET, "r.NS2", "", "", r"r\.NS2: line 13: Dir\. E-W disagrees with .* extension"),
        (KIKNET, "r.EW2", "Scale Factor", "Scale", r"line 14: .*starts with 'Scale Factor'"),
        (KIKNET, "r.EW2", "(gal)", "(counts)", r"line 14: unit 'counts' is not a unit of acc"),
        (KIKNET, "r.EW2", "  -2650", "  -26x0", r"r\.EW2: line 18: not a finite number: .-26x0"),
        (ESM, "a.ASC", "NDATA: 16", "NDATA: 17", r"line 30: .*NDATA = 17 values, .* holds 16"),
        (ESM, "a.ASC", "ACCELERATION", "VELOCITY", r"line 50: DATA_TYPE VELOCITY, not an acc"),
        (ESM, "a.ASC", "UNITS: cm/s^2", "UNITS:", r"a\.ASC: an ESM/ITACA header without UNITS"),
        (ESM, "a.ASC", "UNITS: cm/s^2", "UNITS: cm/s", r"line 33: unit 'cm/s' is not a unit"),
        (COSMOS, "c.V2c", "cm/sec2 (04)", "counts (50)", r"line 45: COSMOS unit code 50 \(co"),
        (
            COSMOS,
            "c.V2c",
            "Real-header",
            "Real header",
            r"c\.V2c: line 25: expected the COSMOS real-h",
        ),
    ],
)
def test_edited_fixture_refused_naming_file_and_line(tmp_path, fixture, name, old, new, match):
    with pytest.raises(InputError, match=match):
        read_record(_copy(fixture, tmp_path / name, old, new))


def test_header_peak_judged_to_the_digits_it_prints(tmp_path):
    # the values' peak is 2.52747 gal: "2.53" is it to 2 decimals (±0.005), "2.52" is not, and
    # "2.5275E+00" (±5e-5) is it in E format
    for text in ("2.53", "2.5275E+00"):
        _no_warnings(_copy(KIKNET, tmp_path / "a.EW2", "2.527", text))
    with pytest.warns(RecordHeaderWarning, match=r"states a peak of 2\.52 cm/s2"):
        read_record(_copy(KIKNET, tmp_path / "a.EW2", "2.527", "2.52"))


@pytest.mark.parametrize(
    ("fixture", "old", "new", "match"),
    [
        (KIKNET, "2.527", "3.527", r"states a peak of 3\.527 cm/s2, the values' peak is 2\.52"),
        (ESM, "TIME_PGA_S: 0.06", "TIME_PGA_S: 0.50", r"peak at t = 0\.500000 s, the values'"),
        (COSMOS, " -234.567890", " -204.567890", r"states a peak of -204\.567890 cm/s2"),
    ],
)
def test_header_peak_disagreeing_with_the_values_warns(tmp_path, fixture, old, new, match):
    path = _copy(fixture, tmp_path / fixture.name, old, new)
    with pytest.warns(RecordHeaderWarning, match=match):
        read_record(path)


# ------------------------------------------------------------------------ file in no format


def test_unrecognised_file_lists_every_format(tmp_path):
    path = tmp_path / "odd.dat"
    path.write_text("STATION ABC\nCHANNEL 1\n1 2\n3 4 5\n")
    with pytest.raises(InputError, match=r"odd\.dat: format not recognised") as err:
        read_record(path)
    for name in ("PEER .AT2", "K-NET/KiK-net", "ESM/ITACA", "COSMOS V1/V2", "SAC", "miniSEED"):
        assert name in str(err.value)


def test_calibration_is_refused_for_text_files():
    with pytest.raises(InputError, match=r"calibration is for SAC and miniSEED files"):
        read_record(ESM, calibration=2.0)


# -------------------------------------------------------------------------- SAC, miniSEED


def _trace(obspy, counts, station="TST1", channel="HNE"):
    tr = obspy.Trace(np.asarray(counts, dtype=np.int32))
    tr.stats.update(
        {
            "network": "XX",
            "station": station,
            "location": "00",
            "channel": channel,
            "delta": 0.005,
            "starttime": obspy.UTCDateTime(2020, 1, 2, 3, 4, 5),
        }
    )
    return tr


@pytest.mark.parametrize(
    ("fmt", "suffix", "name"), [("SAC", ".sac", "SAC"), ("MSEED", ".mseed", "miniSEED")]
)
def test_obspy_formats_need_units_and_apply_the_calibration(tmp_path, fmt, suffix, name):
    obspy = pytest.importorskip("obspy")
    counts = [0, 150, -420, 980, -2500, 1200, -300, 40]
    path = tmp_path / f"rec{suffix}"
    obspy.Stream([_trace(obspy, counts)]).write(str(path), format=fmt)
    with pytest.raises(InputError, match=rf"rec\{suffix}: a {name} file holds counts"):
        read_record(path)
    # 0.01 cm/s² per count: a peak of 2500 counts is 25 gal = 0.25 m/s²
    rec = _no_warnings(path, units="cm/s2", calibration=0.01)
    np.testing.assert_allclose(rec.acc, np.array(counts) * 0.01 * 0.01, rtol=1e-12)
    assert rec.dt == pytest.approx(0.005)
    assert rec.units == "cm/s2"
    assert rec.format == name
    assert (rec.station, rec.component) == ("XX.TST1.00", "HNE")
    assert rec.date == "2020-01-02T03:04:05 UTC (first sample)"


def test_sac_velocity_refused(tmp_path):
    obspy = pytest.importorskip("obspy")
    tr = _trace(obspy, [0, 1, -2, 1])
    tr.stats.sac = obspy.core.AttribDict({"idep": 7})  # SAC's IVEL
    tr.write(str(tmp_path / "v.sac"), format="SAC")
    with pytest.raises(InputError, match=r"v\.sac: the SAC header \(IDEP\) says velocity"):
        read_record(tmp_path / "v.sac", units="cm/s2")


def test_sac_file_without_obspy_names_the_extra(tmp_path, monkeypatch):
    # a SAC header is told by its version number (NVHDR = 6, the 7th integer word after 70
    # floats: byte 304) whether or not ObsPy is installed
    head = bytearray(632)
    head[304:308] = (6).to_bytes(4, "little")
    (tmp_path / "x.sac").write_bytes(bytes(head) + bytes(16))
    monkeypatch.setitem(sys.modules, "obspy", None)  # import obspy fails
    with pytest.raises(InputError, match=r"x\.sac: a SAC file; reading it needs ObsPy: pip ins"):
        read_record(tmp_path / "x.sac", units="g")


def test_obspy_file_with_several_traces_refused(tmp_path):
    obspy = pytest.importorskip("obspy")
    path = tmp_path / "three.mseed"
    stream = obspy.Stream([_trace(obspy, [1, 2, 3, 4], channel=c) for c in ("HNE", "HNN")])
    stream.write(str(path), format="MSEED")
    with pytest.raises(InputError, match=r"three\.mseed: 2 traces \(XX\.TST1\.00\.HNE, XX"):
        read_record(path, units="cm/s2")


# --------------------------------------------------------------------------- command line


def test_folder_of_network_files_read_and_imported(tmp_path):
    folder = tmp_path / "recs"
    folder.mkdir()
    for f in (KIKNET, ESM, COSMOS):
        shutil.copy(f, folder / f.name)
    records = read_records(folder)
    assert [r.format for r in records] == ["ESM", "COSMOS V2", "KiK-net"]  # sorted by name
    out = tmp_path / "suite.nc"
    result = CliRunner().invoke(main, ["motions", "import", str(folder), "--out", str(out)])
    assert result.exit_code == 0, result.output
    meta = Ensemble.load(out).meta
    assert list(meta["stations"]) == ["XX.TST1", "XX-TEST1 Test Station, Nowhere", "XXXH01"]
    assert list(meta["components"]) == ["HNE", "90 deg", "EW2 (KiK-net surface)"]
    assert list(meta["record_units"]) == ["cm/s2"] * 3
    assert list(meta["record_formats"]) == ["ESM", "COSMOS V2", "KiK-net"]
    # the three components of a K-NET/KiK-net station share a stem: their spectra are told
    # apart by the whole file name
    ns2 = _copy(KIKNET, tmp_path / KIKNET.with_suffix(".NS2").name, "E-W", "N-S")
    result = CliRunner().invoke(main, ["spectrum", str(KIKNET), str(ns2), str(COSMOS)])
    assert result.exit_code == 0, result.output
    for name in ("XXXH011103111446.EW2:", "XXXH011103111446.NS2:", "XXTEST1:"):
        assert name in result.output


def test_cli_sac_without_units_is_one_line_error(tmp_path):
    obspy = pytest.importorskip("obspy")
    path = tmp_path / "rec.sac"
    obspy.Stream([_trace(obspy, [0, 10, -20, 5])]).write(str(path), format="SAC")
    result = CliRunner().invoke(main, ["spectrum", str(path)])
    assert result.exit_code == 1
    assert "give its units (--units" in result.output and "Traceback" not in result.output
    result = CliRunner().invoke(
        main, ["spectrum", str(path), "--units", "cm/s2", "--calibration", "1"]
    )
    assert result.exit_code == 0, result.output
