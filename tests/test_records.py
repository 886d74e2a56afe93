"""Reading ground-motion records: PEER .AT2 (real files and header variants) and plain text."""

from __future__ import annotations

import warnings
from pathlib import Path

import numpy as np
import pytest

from rocking.dynamics.body import G
from rocking.errors import InputError
from rocking.motions.records import example_record_path, read_record, read_records
from rocking.motions.units import ImplausiblePeakWarning

#: El Centro 1940 NS ships with the package; Chino Hills (PEER NGA-West2 layout) with the tests.
EL_CENTRO = example_record_path()
CHINO_HILLS = Path(__file__).parent / "data" / "RSN8883_14383980_13849360.AT2"


def _values_after_header(path: Path, header_lines: int) -> np.ndarray:
    """Every number after the header, read independently of the package (whitespace split)."""
    text = path.read_text().splitlines()[header_lines:]
    return np.array(" ".join(text).split(), dtype=float)


@pytest.mark.parametrize(
    "path,npts,dt",
    [
        (EL_CENTRO, 1559, 0.02),  # src/rocking/data/records/README.md
        (CHINO_HILLS, 16396, 0.005),  # tests/data/README.md
    ],
)
def test_real_records(path, npts, dt):
    name = path.name
    rec = read_record(path)
    assert rec.acc.shape == (npts,) and rec.dt == dt
    assert rec.name == Path(name).stem and rec.source.endswith(name)
    # Both files are in g (stated in their headers): m/s² = g·9.80665, to rounding.
    expected = _values_after_header(path, 4)
    np.testing.assert_allclose(rec.acc, expected * G, rtol=1e-15)
    assert rec.pga == pytest.approx(np.abs(expected).max(), rel=1e-15)
    np.testing.assert_allclose(rec.t[[0, -1]], [0.0, (npts - 1) * dt], rtol=1e-12)


def test_el_centro_pga():
    # The largest |value| in the file (Peknold version of El Centro 1940 NS) is 0.31882 g.
    assert read_record(EL_CENTRO).pga == pytest.approx(0.31882, rel=1e-12)


VALUES = [-0.2098335e-03, -0.2108988e-03, -0.2119629e-03, 0.15, -0.25, 0.0031, 0.5]


def _at2(
    count_line: str,
    units_line: str = "ACCELERATION TIME SERIES IN UNITS OF G",
    per_line: int = 3,
    newline: str = "\n",
    trailing: str = "",
) -> str:
    head = [
        "PEER NGA STRONG MOTION DATABASE RECORD",
        "Helena Montana-01, 10/31/1935, Carroll College, 180",
        units_line,
        count_line,
    ]
    rows = [
        " ".join(f"{v: .7E}" for v in VALUES[i : i + per_line]) + trailing
        for i in range(0, len(VALUES), per_line)
    ]  # last line short (7 = 3 + 3 + 1)
    return newline.join(head + rows) + newline


@pytest.mark.parametrize(
    "text",
    [
        _at2("NPTS=      7, DT=   .0100 SEC,"),  # trailing comma, no leading zero
        _at2("NPTS=      7, DT=   .0100 SEC"),  # no trailing comma
        _at2("NPTS=  7, DT=   0.0100 SEC      ", trailing="   "),  # trailing spaces
        _at2("NPTS=7,DT=0.01SEC"),  # no spaces at all
        _at2("NPTS=      7, DT=   .0100 SEC,", newline="\r\n"),  # CRLF
        _at2("7 0.01000 NPTS, DT"),  # older NGA header line
        _at2("NPTS=      7, DT=   .0100 SEC,", per_line=5),
        _at2("NPTS=      7, DT=   .0100 SEC,", units_line="The units are (g)"),
        _at2("NPTS=      7, DT=   .0100 SEC,", units_line="free text, no units"),  # g assumed
    ],
)
def test_at2_header_variants(tmp_path, text):
    path = tmp_path / "rec.AT2"
    path.write_bytes(text.encode())
    rec = read_record(path)
    assert rec.dt == pytest.approx(0.01, rel=1e-15)
    np.testing.assert_allclose(rec.acc, np.array(VALUES) * G, rtol=1e-15)


@pytest.mark.parametrize(
    "units_line,factor",
    [
        ("ACCELERATION TIME SERIES IN UNITS OF CM/S/S", 0.01),
        ("acceleration in cm/sec2", 0.01),
        ("Units: gal", 0.01),
        ("ACCELERATION TIME SERIES IN UNITS OF M/S/S", 1.0),
        ("acceleration [m/s^2]", 1.0),
        # issue 49: these were read as g (in/s² and ft/s²: exact inch and foot, 0.0254 m and
        # 0.3048 m)
        ("ACCELERATION TIME SERIES IN UNITS OF IN/S/S", 0.0254),
        ("acceleration in ft/sec2", 0.3048),
        ("The units are (m/s²)", 1.0),
    ],
)
def test_at2_stated_units(tmp_path, units_line, factor):
    path = tmp_path / "rec.at2"
    path.write_text(_at2("NPTS= 7, DT= .01 SEC", units_line=units_line))
    np.testing.assert_allclose(read_record(path).acc, np.array(VALUES) * factor, rtol=1e-15)
    stated = read_record(path).units
    # units= that agree with the file (in any spelling) change nothing; others are refused,
    # naming both (issue 48: --units cm/s2 for a file in g was taken silently)
    np.testing.assert_allclose(
        read_record(path, units=stated.upper()).acc, np.array(VALUES) * factor, rtol=1e-15
    )
    other = "g" if stated != "g" else "cm/s2"
    with pytest.raises(InputError, match=rf"units {other} given, but the file states {stated}"):
        read_record(path, units=other)


@pytest.mark.parametrize(
    "name,text,where",
    [
        ("rec.AT2", _at2("NPTS= 7, DT= .01 SEC", units_line="The units are (furlongs)"), ""),
        ("rec.AT2", _at2("NPTS= 7, DT= .01 SEC", units_line="UNITS OF FURLONGS/S2"), ""),
        ("rec.csv", "time [s], acc [furlongs]\n0,0.1\n0.01,0.2\n", ": line 1"),
        ("rec.txt", "acc (furlongs/s^2)\n0.1\n0.2\n", ": line 1"),
    ],
)
def test_units_not_understood_are_refused(tmp_path, name, text, where):
    # Issue 49: a unit that is not understood was read as g. The error names the file, the
    # line of a column header and the unit.
    path = tmp_path / name
    path.write_text(text)
    with pytest.raises(InputError, match=rf"(?i){name}{where}: unit '[^']*furlongs[^']*' is not a"):
        read_record(path, dt=0.01)


def test_header_units_per_second_squared(tmp_path):
    # Issue 49: "acc [mm/s2]" gave PGA 0.2993 g instead of 0.0003 g (1000x); in/s² and ft/s²
    # were read as g too. The peak 2.935 in mm/s² is 2.935e-3 / 9.80665 g.
    for header, factor in (
        ("time [s], acc [mm/s2]", 1e-3),
        ("t (sec), a (in/s^2)", 0.0254),
        ("time_s; acceleration [ft/s²]", 0.3048),
        ("t [s], a [cm/sec/sec]", 0.01),
        ("t,a [gal]", 0.01),
    ):
        path = tmp_path / "rec.csv"
        path.write_text(f"{header}\n0,0.1\n0.01,-2.935\n0.02,1.0\n")
        rec = read_record(path)
        assert rec.pga == pytest.approx(2.935 * factor / G, rel=1e-14), header


@pytest.mark.parametrize(
    "text,match",
    [
        (_at2("NPTS=      8, DT=   .0100 SEC,"), r"NPTS = 8 values, the file holds 7"),
        (_at2("NPTS=      6, DT=   .0100 SEC,"), r"NPTS = 6 values, the file holds 7"),
        (_at2("NPTS=      7, DT=   0.0 SEC,"), r"line 4: DT must be > 0"),
        (_at2("NPTS=      7, DT=   -.01 SEC,"), r"line 4: DT must be > 0"),
        (_at2("NPTS=      7.5, DT=   .01 SEC,"), r"line 4: NPTS is not a whole number"),
        (
            _at2("NPTS=      7, DT=   .0100 SEC,").replace("1.5000000E-01", "1.5O00000E-01"),
            r"line 6: not a finite number: '1.5O00000E-01'",
        ),
        (
            _at2("NPTS=      7, DT=   .0100 SEC,").replace("1.5000000E-01", "nan"),
            r"line 6: not a finite number: 'nan'",
        ),
        (_at2("no count line here"), r"no 'NPTS=..., DT=...' line"),
        (
            _at2("NPTS= 7, DT= .01 SEC", units_line="VELOCITY TIME SERIES IN UNITS OF CM/S"),
            r"velocity or displacement",
        ),
        ("", r"empty file"),
        ("  \n\n", r"empty file"),
    ],
)
def test_at2_errors(tmp_path, text, match):
    path = tmp_path / "bad.AT2"
    path.write_text(text)
    with pytest.raises(InputError, match=match) as err:
        read_record(path)
    assert "bad.AT2" in str(err.value)


def test_one_column_text(tmp_path):
    path = tmp_path / "one.txt"
    path.write_text("# acceleration in g, dt = 0.01 s\n0.1\n-0.2\n  0.3  # peak\n\n0.0\n")
    rec = read_record(path, dt=0.01)
    np.testing.assert_allclose(rec.acc, np.array([0.1, -0.2, 0.3, 0.0]) * G, rtol=1e-15)
    assert rec.dt == 0.01 and rec.pga == pytest.approx(0.3)
    np.testing.assert_allclose(
        read_record(path, dt=0.01, units="cm/s2").acc, [0.001, -0.002, 0.003, 0.0], rtol=1e-15
    )
    with pytest.raises(InputError, match="one-column file needs the time step dt"):
        read_record(path)
    with pytest.raises(InputError, match="dt"):
        read_record(path, dt=-0.01)


def test_two_column_text(tmp_path):
    path = tmp_path / "two.csv"
    path.write_text(
        "# exported\ntime [s], acc [m/s2]\n0.000, 0.0\n0.005, 1.5\n0.010, -2.0\n0.015, 0.5\n"
    )
    rec = read_record(path)
    assert rec.dt == pytest.approx(0.005, rel=1e-12)
    np.testing.assert_allclose(rec.acc, [0.0, 1.5, -2.0, 0.5], rtol=1e-15)  # header: m/s2
    plain = tmp_path / "two.txt"
    plain.write_text("0.0 0.1\n0.02 0.2\n0.04 0.3\n")  # no header: g
    np.testing.assert_allclose(read_record(plain).acc, np.array([0.1, 0.2, 0.3]) * G)
    # a dt that agrees is accepted, one that does not is refused
    assert read_record(plain, dt=0.02).dt == pytest.approx(0.02)
    with pytest.raises(InputError, match="disagrees"):
        read_record(plain, dt=0.01)


@pytest.mark.parametrize(
    "text,match",
    [
        ("0.0 0.1\n0.01 0.2\n0.03 0.3\n0.04 0.1\n", r"line 3: unequal time spacing"),
        ("0.0 0.1\n0.01 0.2\n0.02\n", r"line 3: expected 2 value\(s\)"),
        ("0.0 0.1 1\n0.01 0.2 2\n", r"line 1: expected 1 column .* or 2 .* got 3"),
        ("t,a\n0.0,0.1\n0.01,x\n", r"line 3: not a finite number: 'x'"),
        ("t,a\n0.0,0.1\n", r"at least 2 rows"),
        ("0.0 0.1\n0.0 0.2\n", r"times must increase"),
        ("# only a comment\n", r"no data"),
        ("", r"empty file"),
    ],
)
def test_text_errors(tmp_path, text, match):
    path = tmp_path / "bad.txt"
    path.write_text(text)
    with pytest.raises(InputError, match=match) as err:
        read_record(path)
    assert "bad.txt" in str(err.value)


def test_bad_units_name(tmp_path):
    with pytest.raises(InputError, match="units: unit 'furlongs' is not a unit of acceleration"):
        read_record(EL_CENTRO, units="furlongs")


def test_absurd_peaks_are_refused_and_implausible_ones_warned(tmp_path):
    # Issue 49: a sample of 1e30 g imported as "A_gx = 1e+30 g". Above 100 g no value can be a
    # ground or floor acceleration in the units read. Issue 48: a record in gal read as g
    # (peak 312.7 "g") was taken without a word; the message names the likely units first:
    # 312.7 cm/s² = 312.7 / 980.665 g = 0.3189 g.
    for text, match in (
        ("t,a\n0,0.1\n0.01,1e30\n", r"peak 1e\+30 g \(read in g\) is implausible"),
        ("t,a\n0,0.1\n0.01,-312.7\n", r"peak 312\.7 g .* likely in cm/s2 \(peak 0\.3189 g\)"),
    ):
        path = tmp_path / "huge.txt"
        path.write_text(text)
        with pytest.raises(InputError, match=rf"huge\.txt: {match}.*above 100 g: refused"):
            read_record(path)
    # Below 100 g it is a warning: 45 gal read as g is 45 "g" (0.04589 g in cm/s², 0.1166 g in
    # in/s², 1.399 g in ft/s²)
    gal = tmp_path / "gal.txt"
    gal.write_text("t,a\n0,0.1\n0.01,-45\n")
    likely = r"gal\.txt: peak 45 g .* cm/s2 \(peak 0\.04589 g\)"
    with pytest.warns(ImplausiblePeakWarning, match=likely):
        read_record(gal)
    # and a record far too weak (values in g read as m/s², say)
    weak = tmp_path / "weak.txt"
    weak.write_text("t,a [m/s2]\n0,0.0001\n0.01,-0.0002\n")
    with pytest.warns(ImplausiblePeakWarning, match=r"weak\.txt: peak 2\.039e-05 g"):
        read_record(weak)
    with warnings.catch_warnings():
        warnings.simplefilter("error")  # a plausible record warns of nothing
        read_record(EL_CENTRO)


def test_unrecognised_formats_say_so_and_list_the_formats(tmp_path):
    # Issue 48: a file in another format got "line 4: expected 2 value(s) like the first data
    # line". A made-up multi-line header over three-column data, and text among numbers:
    for text in (
        "STATION ABC\nCHANNEL 1\n1 2\n3 4 5\n",
        "a b c\n1 2 3\n",
        "header\n1\nmore text\n",
    ):
        path = tmp_path / "odd.dat"
        path.write_text(text)
        with pytest.raises(InputError, match=r"odd\.dat: format not recognised \(line \d") as err:
            read_record(path, dt=0.01)
        assert "PEER .AT2" in str(err.value) and "netCDF" in str(err.value)


def test_read_records_folder_and_list(tmp_path):
    (tmp_path / "b.txt").write_text("0 0.1\n0.01 0.2\n")
    (tmp_path / "a.AT2").write_text(_at2("NPTS= 7, DT= .01 SEC"))
    (tmp_path / "c.csv").write_text("t,a\n0,0.3\n0.01,0.4\n")
    (tmp_path / "notes.md").write_text("not a record")
    recs = read_records(tmp_path)
    assert [r.name for r in recs] == ["a", "b", "c"]
    recs = read_records([tmp_path / "c.csv", EL_CENTRO])
    assert [r.name for r in recs] == ["c", "ElCentro1940_NS"]
    empty = tmp_path / "empty"
    empty.mkdir()
    with pytest.raises(InputError, match="holds no .AT2"):
        read_records(empty)
    with pytest.raises(FileNotFoundError):
        read_records(tmp_path / "missing.AT2")


def test_binary_files_are_refused_for_what_they_are(tmp_path):
    # A netCDF file (classic format starts with "CDF" and a version byte; netCDF-4 is HDF5) is
    # an ensemble, not a record; other binary data is no text record either. Before, these were
    # parsed as text and failed with "line N: not a finite number".
    for name, head in (("m.nc", b"CDF\x02"), ("m4.nc", b"\x89HDF\r\n\x1a\n"), ("x.AT2", b"\0\1")):
        (tmp_path / name).write_bytes(head + b"\0" * 64 + b"1 2 3\n")
    for name in ("m.nc", "m4.nc"):
        with pytest.raises(InputError, match=rf"{name}: a netCDF \(binary\) file, not a ground"):
            read_record(tmp_path / name)
    with pytest.raises(InputError, match=r"x\.AT2: a binary file, not a ground-motion record"):
        read_record(tmp_path / "x.AT2")


def test_records_carry_their_peer_title_and_units(tmp_path):
    # The second header line of _at2 is the PEER NGA documentation's example title line
    # (written by _at2): event, date, station, component.
    path = tmp_path / "rec.AT2"
    path.write_text(_at2("NPTS= 7, DT= .01 SEC", units_line="ACCELERATION IN UNITS OF CM/S/S"))
    rec = read_record(path)
    assert (rec.event, rec.date, rec.station, rec.component) == (
        "Helena Montana-01",
        "10/31/1935",
        "Carroll College",
        "180",
    )
    assert rec.units == "cm/s2" and read_record(path, units="gal").units == "cm/s2"
    # Chino Hills in the NGA-West2 layout (tests/data/README.md): event 14383980, 7/29/2008,
    # Anaheim - Lakeview & Riverdale, 360°; El Centro's header has no such line.
    ch = read_record(CHINO_HILLS)
    assert (ch.event, ch.date, ch.station, ch.component) == (
        "14383980",
        "7/29/2008",
        "Anaheim - Lakeview & Riverdale",
        "360",
    )
    assert read_record(EL_CENTRO).event == "" and read_record(EL_CENTRO).units == "g"
    plain = tmp_path / "plain.txt"
    plain.write_text("0 0.1\n0.01 0.2\n")
    assert read_record(plain).units == "g" and read_record(plain).station == ""
