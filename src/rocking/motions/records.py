"""Reading recorded ground accelerations (PEER NGA .AT2 files, plain text and the formats of
strong-motion networks).

Formats
-------
PEER .AT2
    Free-text header lines, then a line with the number of points and the time step, then the
    values (any number per line, the last line may be short). The count/step line is found by
    pattern, in either form seen in real files::

        NPTS=   5093, DT=   .0100 SEC,        (trailing comma, "SEC" and spaces optional)
        3930 0.00500 NPTS, DT                 (older NGA files)

    Units are read from the header ("UNITS OF G", "The units are (g)", "cm/s/s", "m/s/s",
    "in/sec2", "gal", ...); a header that states none is taken to be in g. Headers announcing
    velocity or displacement time series (.VT2, .DT2) are refused.
Plain text (any file without an NPTS/DT line)
    One column of accelerations (the time step ``dt`` must be given) or two columns
    (time [s], acceleration), separated by blanks, commas or semicolons. ``#`` starts a comment.
    One header line of column names is allowed; if it states units (e.g. "acc [m/s2]") they are
    used, otherwise accelerations are in g. Times must be equally spaced (to 0.1 % of the step);
    the first sample is taken as t = 0.

K-NET/KiK-net ASCII, ESM/ITACA ASCII, COSMOS V1/V2, SAC and miniSEED
    Recognised by their headers (their first lines or bytes, whatever the file's name) and read
    by :mod:`rocking.motions.formats`, which describes them; SAC and miniSEED need ObsPy
    (``pip install 'rocking[formats]'``) and the ``units`` of their values (with
    ``calibration``, units per count, for counts).

Anything else is refused as a format not recognised, with the list of these formats.

Units
-----
g, m/s², cm/s² (gal), mm/s², in/s² and ft/s², in the usual spellings
(:mod:`rocking.motions.units`). A stated unit that is none of these is refused, naming it; units
given by the caller must agree with those the file states. A peak above 100 g is refused (the
values are certainly in other units); a peak outside 1e-4–5 g gets an
:class:`~rocking.motions.units.ImplausiblePeakWarning` naming the likely units.

Every reader returns accelerations in m/s² (g = 9.80665 m/s²) and the units the file was read in.
Binary files (a netCDF ensemble of motions, say) are refused with an
:class:`~rocking.errors.InputError` that says so.

Metadata
--------
The second header line of a PEER file names the record: ``EVENT, DATE, STATION, COMPONENT``,
e.g. "Helena Montana-01, 10/31/1935, Carroll College, 180" or, in NGA-West2 files,
"14383980, 7/29/2008, Anaheim - Lakeview & Riverdale, 360" (the event as its network number).
The date (month/day/year) anchors the split, so an event or station with commas in its name
("Chi-Chi, Taiwan") is kept whole; a line without a date gives no metadata
(:func:`peer_title`).

Resampling
----------
:func:`resample` changes the time step with :func:`scipy.signal.resample_poly`: the record is
upsampled by ``up``, low-pass filtered and downsampled by ``down``, where dt / new_dt =
up / down exactly (to 1e-9) with both at most :data:`MAX_RESAMPLING_FACTOR`. The filter is
SciPy's default: a linear-phase FIR filter of 20·max(up, down) + 1 taps designed with a Kaiser
window (β = 5, stop-band attenuation about 54 dB, pass-band ripple about 0.2 %), its cut-off at
the lower of the two Nyquist frequencies, so downsampling removes what the new step cannot
carry instead of folding it back (aliasing). Ratios that are no such fraction are refused.

Manifests
---------
A manifest (:func:`read_manifest`) is a CSV file with one row per motion: column
``horizontal`` (required: its record file), ``vertical`` (optional: the vertical record of the
same motion), ``scale`` (optional factor > 0 applied to both, default 1) and ``dt`` (optional:
the time step [s] of one-column files, which state none). Paths are relative to the manifest's
folder.

Shipped records
---------------
The package ships seven real records (public domain; sources, processing and format in
``rocking/data/records/README.md``): El Centro 1940 north–south and both horizontal components of
the 2019 M7.1 Ridgecrest earthquake at three stations, with each station's vertical component.
:func:`example_record_path` gives El Centro's path; wherever record files are named
(:func:`read_records`, the command line), the word ``example`` stands for it unless a file of
that name exists. :func:`example_manifest_path` is the manifest of all seven (with the verticals);
wherever a manifest is named, the word ``example`` stands for it.
"""

from __future__ import annotations

import csv
import math
import os
import re
import warnings
from collections.abc import Iterable
from dataclasses import dataclass, field
from fractions import Fraction
from importlib.resources import files
from pathlib import Path

import numpy as np
from numpy.typing import ArrayLike

from ..core import portable
from ..core.checks import positive
from ..core.files import read_text
from ..dynamics.body import G
from ..errors import InputError
from .formats import (
    ParsedRecord,
    binary_format,
    finite_number,
    is_cosmos,
    is_esm,
    is_knet,
    numbers,
    read_cosmos,
    read_esm,
    read_knet,
    read_obspy,
)
from .units import (
    ACCELERATION_UNITS,
    MAX_PEAK_G,
    ImplausiblePeakWarning,
    acceleration_unit,
    implausible_peak,
)

#: Unit statements of a header, tried in this order; the first found gives the unit's text
#: (group 1), which :func:`rocking.motions.units.acceleration_unit` reads or refuses:
#: "units of g", "The units are (g)", "UNITS: cm/s/s"; a unit per second squared anywhere
#: ("acceleration in cm/sec2", "furlongs/s^2"); the word gal; "[g]" or "(g)".
_UNIT_PATTERNS = (
    re.compile(r"\bunits?\s*(?:of|are|in|:|=)\s*(?:\(([^)]*)\)|\[([^\]]*)\]|([^\s,;]+))", re.I),
    re.compile(r"(\b[a-z]+\s*/\s*(?:sec|s)\s*(?:/\s*(?:sec|s)\b|\^?\s*-?2|\*\*\s*2|²))", re.I),
    re.compile(r"\b(gals?)\b", re.I),
    re.compile(r"[(\[]\s*(g)\s*[)\]]", re.I),
)
#: Text in brackets of a column header: its unit ("time [s], acc [cm/s2]").
_BRACKETED = re.compile(r"[(\[]([^)\]]*)[)\]]")
#: Units of time in column headers (the time column of a two-column file).
_TIME_UNITS = {"s", "sec", "secs", "second", "seconds"}
_NUM = r"[-+]?(?:\d+\.?\d*|\.\d+)(?:[eE][-+]?\d+)?"  # a number ("SEC" may follow unspaced)
_NPTS_DT = (
    re.compile(rf"npts\s*=\s*(?P<n>{_NUM}|[^\s,]*)\s*,?\s*dt\s*=\s*(?P<dt>{_NUM}|[^\s,]*)", re.I),
    re.compile(r"^\s*(?P<n>\S+)\s+(?P<dt>\S+)\s+npts\s*,?\s*dt\b", re.I),
)
#: Lines searched for the NPTS/DT line of a PEER file.
_HEADER_LINES = 12
#: Relative tolerance on the spacing of the times of a two-column file.
_DT_RTOL = 1e-3


@dataclass(frozen=True, eq=False)
class Record:
    """One recorded ground acceleration.

    Attributes
    ----------
    acc : ndarray, shape (n_t,)
        Ground acceleration [m/s²].
    dt : float
        Time step [s].
    name : str
        Label (the file name without suffix; with it for K-NET/KiK-net files, whose suffix is
        the component).
    source : str
        Path of the file it was read from.
    units : str
        Units of the values in the file (a name of
        :data:`~rocking.motions.units.ACCELERATION_UNITS`; "" when not read from a file).
    event, date, station, component : str
        From the file's header: a PEER header's second line (see :func:`peer_title`), the
        fields of K-NET/KiK-net, ESM, COSMOS, SAC and miniSEED headers
        (:mod:`rocking.motions.formats`: ``date`` states its time zone, a KiK-net component
        its sensor, borehole or surface); "" when the file does not say.
    dt_given : bool
        True when the file does not state its time step (a one-column text file) and ``dt``
        was given for it.
    format : str
        The file's format: "PEER", "text", "K-NET", "KiK-net", "ESM", "COSMOS V1",
        "COSMOS V2", "SAC", "miniSEED" ("" when not read from a file).
    header : dict
        The fields of the file's header as written (name -> text), for the formats of
        :mod:`rocking.motions.formats`; empty for the others.
    """

    acc: np.ndarray
    dt: float
    name: str
    source: str
    units: str = ""
    event: str = ""
    date: str = ""
    station: str = ""
    component: str = ""
    dt_given: bool = False
    format: str = ""
    header: dict[str, str] = field(default_factory=dict)

    @property
    def t(self) -> np.ndarray:
        """Sample times [s], starting at 0."""
        return np.arange(self.acc.size) * self.dt

    @property
    def pga(self) -> float:
        """Peak ground acceleration max abs(acc) [g]."""
        return float(np.abs(self.acc).max()) / G


def _stated_units(text: str, where: str, columns: bool = False) -> str | None:
    """The unit of acceleration (a name of :data:`~rocking.motions.units.ACCELERATION_UNITS`)
    that a header states, None when it states none. With ``columns`` (a line of column names)
    the text in brackets is the unit of its column, the time column's (s) aside. A unit that
    is stated but not understood is an InputError that names it (``where`` starts the
    message)."""
    stated: list[str] = []
    if columns:
        inner = (m[1].strip() for m in _BRACKETED.finditer(text))
        stated = [u for u in inner if u.lower() not in _TIME_UNITS]
    if not stated:
        found = next((m for p in _UNIT_PATTERNS if (m := p.search(text)) is not None), None)
        stated = [] if found is None else [next(g for g in found.groups() if g is not None)]
    names = {acceleration_unit(u, where) for u in stated}
    if len(names) > 1:
        raise InputError(f"{where}: states several units ({', '.join(sorted(names))})")
    return names.pop() if names else None


def _npts_dt(line: str) -> tuple[str, str] | None:
    for pattern in _NPTS_DT:
        m = pattern.search(line)
        if m:
            return m["n"], m["dt"]
    return None


#: A date of a PEER title line: month/day/year.
_DATE = re.compile(r"\d{1,2}/\d{1,2}/\d{2,4}")
#: Fields of a PEER title line, in the order of :func:`peer_title`'s result.
TITLE_FIELDS = ("event", "date", "station", "component")


def peer_title(line: str) -> dict[str, str]:
    """Event, date, station and component of a PEER header's second line.

    Parameters
    ----------
    line : str
        E.g. "Helena Montana-01, 10/31/1935, Carroll College, 180".

    Returns
    -------
    dict
        Keys ``event``, ``date``, ``station`` and ``component`` (text as written, stripped): the
        fields before the date, the date, the fields between the date and the last one, and the
        last field. Empty (every value "") when the line has no date field followed by at least
        two more fields.
    """
    parts = [p.strip() for p in line.split(",")]
    at = next((i for i, p in enumerate(parts) if _DATE.fullmatch(p)), None)
    if at is None or at == 0 or len(parts) - at < 3:
        return dict.fromkeys(TITLE_FIELDS, "")
    return {
        "event": ", ".join(parts[:at]),
        "date": parts[at],
        "station": ", ".join(parts[at + 1 : -1]),
        "component": parts[-1],
    }


def _read_at2(path: Path, lines: list[str], head: int, found: tuple[str, str]):
    """Values, dt, units and title of a PEER file whose NPTS/DT line is ``lines[head]``."""
    lineno = head + 1
    try:
        npts = int(found[0])
    except ValueError:
        raise InputError(
            f"{path}: line {lineno}: NPTS is not a whole number: {found[0]!r}"
        ) from None
    dt = finite_number(found[1], f"{path}: line {lineno}")
    if not dt > 0.0:
        raise InputError(f"{path}: line {lineno}: DT must be > 0 [s], got {found[1]!r}")
    header = "\n".join(lines[:head])
    if re.search(r"\b(velocity|displacement)\s+time\s+series", header, re.I):
        raise InputError(
            f"{path}: the header announces a velocity or displacement time series, "
            "not an acceleration"
        )
    values = numbers(path, lines, lineno)
    if values.size != npts:
        raise InputError(
            f"{path}: the header announces NPTS = {npts} values, the file holds {values.size}"
        )
    title = peer_title(lines[1]) if head > 1 else dict.fromkeys(TITLE_FIELDS, "")
    return values, dt, _stated_units(header, str(path)), title


def _read_columns(path: Path, lines: list[str], dt: float | None):
    """Values, dt, units (None: not stated) and whether the step is ``dt`` (a one-column file)
    of a one- or two-column text file."""
    rows: list[tuple[int, list[str]]] = []
    header: tuple[int, str] | None = None
    for lineno, line in enumerate(lines, start=1):
        cells = [c for c in re.split(r"[\s,;]+", line.split("#", 1)[0].strip()) if c]
        if not cells:
            continue
        if not rows and header is None and not _looks_numeric(cells[0]):
            header = lineno, line  # the header line of column names
            continue
        rows.append((lineno, cells))
    if not rows:
        raise InputError(f"{path}: no data")
    ncol = len(rows[0][1])
    if ncol not in (1, 2):
        raise _unrecognised(
            path,
            f"line {rows[0][0]}: expected 1 column (acceleration) or 2 (time [s], "
            f"acceleration), got {ncol}",
        )
    for lineno, cells in rows:
        if len(cells) != ncol:
            raise _unrecognised(
                path,
                f"line {lineno}: expected {ncol} value(s) like the first data line, "
                f"got {len(cells)}",
            )
        if not _looks_numeric(cells[0]):
            raise _unrecognised(path, f"line {lineno}: text where numbers are expected")
    units = None if header is None else _stated_units(header[1], f"{path}: line {header[0]}", True)
    data = np.array([[finite_number(c, f"{path}: line {n}") for c in cells] for n, cells in rows])
    if ncol == 1:
        if dt is None:
            raise InputError(f"{path}: a one-column file needs the time step dt [s]")
        return data[:, 0], dt, units, True
    t = data[:, 0]
    if t.size < 2:
        raise InputError(f"{path}: a two-column file needs at least 2 rows to give the time step")
    steps = np.diff(t)
    typical = np.median(steps)
    if not typical > 0.0:
        raise InputError(f"{path}: times must increase, got {t[0]:g} s, {t[1]:g} s, ...")
    bad = np.flatnonzero(np.abs(steps - typical) > _DT_RTOL * typical)
    if bad.size:
        i = bad[0]
        raise InputError(
            f"{path}: line {rows[i + 1][0]}: unequal time spacing: step "
            f"{steps[i]:g} s from t = {t[i]:g} s where the typical step is "
            f"{typical:g} s"
        )
    return data[:, 1], (t[-1] - t[0]) / (t.size - 1), units, False


#: The formats of record files, for the message of a file in none of them.
RECORD_FORMATS = (
    "PEER .AT2 (an 'NPTS=..., DT=...' line in the first 12 lines, then the values), "
    "one-column text (accelerations, the step given), two-column text or CSV (time [s], "
    "acceleration; at most one header line of column names), K-NET/KiK-net ASCII (17 header "
    "lines from 'Origin Time' to 'Memo.'), ESM/ITACA ASCII ('KEY: value' header lines with "
    "SAMPLING_INTERVAL_S, NDATA, UNITS), COSMOS V1/V2 (first line '... (Format v01.20 with 13 "
    "text lines)'), SAC and miniSEED (binary, with ObsPy: rocking[formats]) and, as ensembles "
    "of motions, netCDF files (.nc) written by rocking"
)


def _unrecognised(path: Path, detail: str) -> InputError:
    """The error of a file that is in none of the formats read (``detail``: where it failed)."""
    return InputError(
        f"{path}: format not recognised ({detail}); the formats read are {RECORD_FORMATS}"
    )


#: Leading bytes of netCDF files: classic and 64-bit offset ("CDF" and a version byte), and
#: netCDF-4 (an HDF5 file).
_NETCDF_MAGIC = (b"CDF\x01", b"CDF\x02", b"CDF\x05", b"\x89HDF\r\n\x1a\n")
#: Bytes looked at to tell a binary file from a text record.
_SNIFF_BYTES = 4096


def _refuse_binary(path: Path, head: bytes) -> None:
    """InputError for a netCDF or other binary file given where a text record is expected."""
    if head.startswith(_NETCDF_MAGIC):
        raise InputError(
            f"{path}: a netCDF (binary) file, not a ground-motion record; an "
            "ensemble of motions is read with rocking.Ensemble.load (on the command "
            "line: --motions of fragility, agx50 and frame spectra; its spectra: "
            "rocking motions show)"
        )
    if b"\0" in head:
        raise InputError(
            f"{path}: a binary file, not a ground-motion record (neither SAC nor miniSEED)"
        )


def _looks_numeric(token: str) -> bool:
    try:
        float(token)
    except ValueError:
        return False
    return True


def read_record(
    path: str | os.PathLike[str],
    *,
    dt: float | None = None,
    units: str | None = None,
    calibration: float | None = None,
) -> Record:
    """Read one ground-acceleration record (PEER .AT2, plain text, K-NET/KiK-net, ESM/ITACA,
    COSMOS V1/V2, SAC or miniSEED; see the module notes and :mod:`rocking.motions.formats`).

    Parameters
    ----------
    path : str or Path
        The file.
    dt : float, optional
        Time step [s]. Required for one-column text files; for other files, if given, it must
        agree with the file's own step.
    units : str, optional
        Units of the values in the file: g, m/s2, cm/s2 (gal), mm/s2, in/s2 or ft/s2 (usual
        spellings accepted, :func:`rocking.motions.units.acceleration_unit`), for a file that
        does not state them; a file that states other units is refused (default: the file's
        statement, else g). Required for SAC and miniSEED files (the units of their values
        times ``calibration``).
    calibration : float, optional
        For SAC and miniSEED files only: ``units`` per stored value (per count), > 0
        (default 1: the values are in ``units``).

    Returns
    -------
    Record
        Acceleration [m/s²], time step [s], name (file stem), source path, the units the values
        were read in, the format and, where the file states them, event, date, station,
        component and the header's fields.

    Raises
    ------
    InputError
        For a file in none of the formats, a unit that is not understood, units that disagree
        with ``units``, or a peak above :data:`~rocking.motions.units.MAX_PEAK_G` (100 g:
        certainly other units than read).

    Warns
    -----
    ImplausiblePeakWarning
        When the peak lies outside :data:`~rocking.motions.units.PLAUSIBLE_PEAK_G` (1e-4 to
        5 g), naming the units the values are likely in.
    RecordHeaderWarning
        When a header's stated peak (K-NET/KiK-net, ESM, COSMOS) or its time disagrees with
        the values (:class:`rocking.motions.formats.RecordHeaderWarning`).
    """
    path = Path(path)
    given = None if units is None else acceleration_unit(units, "units")
    dt_arg = None if dt is None else positive("dt", dt, "s")
    calib = None if calibration is None else positive("calibration", calibration)
    data = path.read_bytes()
    netcdf = data.startswith(_NETCDF_MAGIC)
    binary = None if netcdf else binary_format(data[:_SNIFF_BYTES])
    if calib is not None and binary is None:
        raise InputError(
            f"{path}: calibration is for SAC and miniSEED files (counts), not for this file"
        )
    dt_given = False
    if binary is not None:
        parsed = read_obspy(path, binary, given, 1.0 if calib is None else calib)
    else:
        _refuse_binary(path, data[:_SNIFF_BYTES])
        parsed, dt_given = _read_text(path, data, dt_arg)
    values, step, stated = parsed.values, parsed.dt, parsed.units
    if dt_arg is not None and abs(dt_arg - step) > _DT_RTOL * step:
        raise InputError(f"{path}: dt = {dt_arg:g} s disagrees with the file's step {step:g} s")
    if values.size < 2:
        raise InputError(f"{path}: a record needs at least 2 samples, got {values.size}")
    if given is not None and stated is not None and given != stated:
        raise InputError(f"{path}: units {given} given, but the file states {stated}")
    used = given or stated or "g"
    _check_peak(float(np.abs(values).max()), used, str(path))
    return Record(
        acc=values * ACCELERATION_UNITS[used],
        dt=float(step),
        name=parsed.name or path.stem,
        source=str(path),
        units=used,
        event=parsed.event,
        date=parsed.date,
        station=parsed.station,
        component=parsed.component,
        dt_given=dt_given,
        format=parsed.format,
        header=parsed.header,
    )


def _read_text(path: Path, data: bytes, dt: float | None) -> tuple[ParsedRecord, bool]:
    """A text record in any of the formats read (by its header), and whether its step is
    ``dt`` [s] (a one-column file, which states none)."""
    text = data.decode("utf-8", errors="replace")
    lines = text.splitlines()
    if not text.strip():
        raise InputError(f"{path}: empty file")
    for recognised, reader in ((is_knet, read_knet), (is_cosmos, read_cosmos), (is_esm, read_esm)):
        if recognised(lines):
            return reader(path, lines), False
    head = next(
        (
            (i, f)
            for i, line in enumerate(lines[:_HEADER_LINES])
            if (f := _npts_dt(line)) is not None
        ),
        None,
    )
    if head is not None:
        values, step, stated, title = _read_at2(path, lines, *head)
        return ParsedRecord(values, step, stated, "PEER", **title), False
    if path.suffix.lower() == ".at2":
        raise InputError(f"{path}: no 'NPTS=..., DT=...' line in the first {_HEADER_LINES} lines")
    values, step, stated, dt_given = _read_columns(path, lines, dt)
    return ParsedRecord(values, step, stated, "text"), dt_given


def _check_peak(peak: float, units: str, where: str) -> None:
    """Refuse a record whose ``peak`` [``units``] is above :data:`MAX_PEAK_G`, warn when it is
    implausible (:func:`~rocking.motions.units.implausible_peak`); ``where`` names it."""
    why = implausible_peak(peak, units)
    if why is None:
        return
    if peak * ACCELERATION_UNITS[units] / G > MAX_PEAK_G:
        raise InputError(f"{where}: {why} (above {MAX_PEAK_G:g} g: refused)")
    warnings.warn(f"{where}: {why}", ImplausiblePeakWarning, stacklevel=3)


#: The word that stands for the shipped example record.
EXAMPLE = "example"


def example_record_path() -> Path:
    """Path of the shipped example record: El Centro 1940, north–south component, a PEER-style
    .AT2 file of 1559 accelerations [g] at 0.02 s (public domain)."""
    return Path(str(files("rocking") / "data" / "records" / "ElCentro1940_NS.AT2"))


def example_manifest_path() -> Path:
    """Path of the shipped manifest of real records: El Centro 1940 NS and six horizontal
    components of the 2019 M7.1 Ridgecrest earthquake, each with its station's vertical
    component (30 s at 0.01 s, in g; public domain)."""
    return Path(str(files("rocking") / "data" / "records" / "examples.csv"))


def record_path(spec: str | os.PathLike[str]) -> Path:
    """``spec`` as a path, the word ``example`` (when no file of that name exists) standing for
    :func:`example_record_path`."""
    path = Path(spec)
    return example_record_path() if str(spec) == EXAMPLE and not path.exists() else path


#: File suffixes picked up when a folder is given to :func:`read_records` (any case): PEER,
#: text, K-NET (.NS, .EW, .UD), KiK-net (borehole 1, surface 2), ESM (.ASC), COSMOS, SAC and
#: miniSEED files (a file's format is then told by its header, not by its suffix).
RECORD_SUFFIXES = (
    ".AT2",
    ".txt",
    ".csv",
    ".NS",
    ".EW",
    ".UD",
    ".NS1",
    ".EW1",
    ".UD1",
    ".NS2",
    ".EW2",
    ".UD2",
    ".ASC",
    ".V1",
    ".V2",
    ".V1c",
    ".V2c",
    ".sac",
    ".mseed",
    ".miniseed",
)


def record_paths(
    paths: str | Path | Iterable[str | os.PathLike[str]],
    suffixes: tuple[str, ...] = RECORD_SUFFIXES,
) -> list[Path]:
    """Expand a path or a list of paths: a folder gives its files with one of ``suffixes``
    (any case; default :data:`RECORD_SUFFIXES`) sorted by name, the word ``example`` the
    shipped example record (see :func:`record_path`)."""
    if isinstance(paths, (str, Path)):
        paths = [paths]
    wanted = {s.lower() for s in suffixes}
    out: list[Path] = []
    for p in map(record_path, paths):
        if p.is_dir():
            found = sorted(
                (q for q in p.iterdir() if q.is_file() and q.suffix.lower() in wanted),
                key=lambda q: q.name,
            )
            if not found:
                listed = f"{', '.join(suffixes[:-1])} or {suffixes[-1]}"
                raise InputError(f"{p}: folder holds no {listed} files")
            out.extend(found)
        else:
            out.append(p)
    if not out:
        raise InputError("no record files given")
    return out


def read_records(
    paths: str | Path | Iterable[str | os.PathLike[str]],
    *,
    dt: float | None = None,
    units: str | None = None,
    calibration: float | None = None,
) -> list[Record]:
    """Read several records; ``paths`` is a path or a list of paths, a folder standing for its
    record files (:data:`RECORD_SUFFIXES`) sorted by name and the word ``example`` for the
    shipped example record. ``dt`` [s], ``units`` and ``calibration`` as in
    :func:`read_record`; ``dt`` gives the step of one one-column file only (several may have
    different rates: refused)."""
    records = [
        read_record(p, dt=dt, units=units, calibration=calibration) for p in record_paths(paths)
    ]
    given = [r.name for r in records if r.dt_given]
    if dt is not None and len(given) > 1:
        _refuse_shared_step(given, dt, "read them one at a time, or as two-column files")
    return records


def _refuse_shared_step(names: list[str], dt: float, remedy: str) -> None:
    """The InputError of one step ``dt`` [s] given for several one-column files ``names``
    (which state no step: one of them may be at 100 Hz and another at 200 Hz)."""
    listed = ", ".join(names[:3]) + (f" and {len(names) - 3} more" if len(names) > 3 else "")
    raise InputError(
        f"one time step ({dt:g} s) for {len(names)} one-column files ({listed}), which state "
        f"none: their rates may differ; {remedy}"
    )


#: Coarsest time step of an ensemble of motions [s], a Nyquist frequency of 10 Hz: motions must
#: carry the amplified region of design spectra, up to 9 Hz (RG 1.60's control point B), which
#: holds the acceleration peaks that set every motion's PGA and so A_gx. A coarser step filters
#: it out (resampling) or never held it.
MAX_DT = 0.05
#: Largest up- and down-sampling factors of :func:`resample` (its filter has 20·max + 1 taps).
MAX_RESAMPLING_FACTOR = 1000
#: Relative tolerance within which dt / new_dt must equal a fraction up / down.
RATIO_RTOL = 1e-9
#: Window of the anti-alias filter of :func:`scipy.signal.resample_poly` (SciPy's default).
RESAMPLING_WINDOW = ("kaiser", 5.0)
#: How :func:`resample` resamples, for the metadata of ensembles.
RESAMPLING = {
    "method": "scipy.signal.resample_poly (polyphase, up by p then down by q, dt/new_dt = p/q)",
    "filter": "linear-phase FIR low-pass, Kaiser window beta = 5.0, 20*max(p, q) + 1 taps, "
    "cut-off at the lower Nyquist frequency (anti-alias when downsampling)",
}


def resampling_factors(dt: float, new_dt: float) -> tuple[int, int]:
    """Whole numbers (up, down) with dt / new_dt = up / down (to :data:`RATIO_RTOL`).

    Parameters
    ----------
    dt, new_dt : float
        Time step of a record and the step wanted [s], > 0.

    Returns
    -------
    tuple of int
        (up, down), coprime, each at most :data:`MAX_RESAMPLING_FACTOR`; (1, 1) when the steps
        are equal.
    """
    ratio = positive("dt", dt, "s") / positive("new_dt", new_dt, "s")
    frac = Fraction(ratio).limit_denominator(MAX_RESAMPLING_FACTOR)
    if (
        frac.numerator > MAX_RESAMPLING_FACTOR
        or abs(frac.numerator - ratio * frac.denominator) > RATIO_RTOL * frac.numerator
    ):
        raise InputError(
            f"dt = {new_dt:g} s: the record step {dt:g} s is not p/q times it with whole "
            f"p, q <= {MAX_RESAMPLING_FACTOR}; choose a step such as {dt:g} s times or "
            f"divided by a whole number"
        )
    return frac.numerator, frac.denominator


def resample(acc: ArrayLike, dt: float, new_dt: float) -> np.ndarray:
    """A record at another time step, alias-free (see the module notes, "Resampling").

    Parameters
    ----------
    acc : array_like, shape (n_t,)
        Acceleration [any unit, returned in the same] sampled at ``dt`` from t = 0.
    dt : float
        Its time step [s].
    new_dt : float
        The time step wanted [s]; dt / new_dt must be a fraction p/q with p, q at most
        :data:`MAX_RESAMPLING_FACTOR` (e.g. 0.02 → 0.005, 0.005 → 0.0025, 0.0025 → 0.005).

    Returns
    -------
    ndarray, shape (m,)
        Samples at t = 0, new_dt, … up to the last time of the record, (n_t - 1)·dt (a copy
        when the steps are equal). Outside the record the signal is taken as zero (the ground
        at rest), so samples within the filter's half length (10·max(p, q) input samples) of
        either end feel the start and the end.
    """
    x = np.asarray(acc, dtype=np.float64)
    up, down = resampling_factors(dt, new_dt)
    if up == down:
        return x.copy()
    n = math.floor((x.size - 1) * up / down + 1e-9) + 1
    from scipy.signal import resample_poly  # here, not at import: scipy.signal takes ~0.3 s

    return resample_poly(x, up, down, window=antialias_filter(up, down))[:n]


def antialias_filter(up: int, down: int) -> np.ndarray:
    """The FIR low-pass filter of :func:`resample` for factors ``up``, ``down`` (coprime): the
    taps that ``scipy.signal.resample_poly`` designs by default (``firwin`` of 20·max(up, down)
    + 1 taps, cut-off 1/max(up, down) of the Nyquist frequency, Kaiser window β = 5, unit gain
    at 0 Hz), in the same operations but with the sinc's sine from
    :func:`rocking.core.portable.sin`: NumPy's sine differs on AVX-512 machines, and so would
    every resampled record (the Kaiser window, SciPy's Bessel function I0, is the same on all).

    Returns
    -------
    ndarray
        The taps [-] (resample_poly multiplies them by ``up``).
    """
    from scipy.signal import get_window

    max_rate = max(up, down)
    numtaps = 2 * 10 * max_rate + 1
    cutoff = 1.0 / max_rate  # [Nyquist frequencies]
    m = np.arange(numtaps) - 0.5 * (numtaps - 1)
    x = cutoff * m
    y = np.pi * np.where(x == 0, 1.0e-20, x)  # sinc(x) = sin(πx)/(πx), as numpy.sinc
    h = cutoff * (portable.sin(y) / y)
    h *= get_window(RESAMPLING_WINDOW, numtaps, fftbins=False)
    return h / np.sum(h)  # unit gain at 0 Hz


@dataclass(frozen=True)
class ManifestRow:
    """One motion of a manifest (see :func:`read_manifest`).

    Attributes
    ----------
    horizontal : Path
        Its horizontal record.
    vertical : Path or None
        Its vertical record, if any.
    scale : float
        Factor applied to both components [-].
    row, line : int
        Its row (1 = the first after the header) and line in the file (for messages).
    dt : float or None
        Time step [s] of its records if they are one-column files (which state none).
    """

    horizontal: Path
    vertical: Path | None
    scale: float
    row: int
    line: int
    dt: float | None = None


#: Columns of a manifest: the first is required.
MANIFEST_COLUMNS = ("horizontal", "vertical", "scale", "dt")


def _manifest_path(folder: Path, spec: str) -> Path:
    """A record named in a manifest: relative to its folder; ``example`` as in
    :func:`record_path` (when no file of that name is in the folder)."""
    path = folder / spec
    return example_record_path() if spec == EXAMPLE and not path.exists() else path


def read_manifest(path: str | os.PathLike[str]) -> list[ManifestRow]:
    """Read a manifest of motions: a CSV with one row per motion (see the module notes).

    Parameters
    ----------
    path : str or Path
        The CSV file: a header row naming columns ``horizontal`` (required), ``vertical``,
        ``scale`` and ``dt`` (any case, any order), then one row per motion. Blank lines and
        lines starting with ``#`` are skipped; an empty ``vertical`` means none, an empty
        ``scale`` 1, an empty ``dt`` none (``dt`` [s] is the step of one-column files). The
        word ``example`` (when no file of that name exists) stands for
        :func:`example_manifest_path`.

    Returns
    -------
    list of ManifestRow
        In file order; the files are checked to exist, not read.
    """
    path = (
        example_manifest_path() if str(path) == EXAMPLE and not Path(path).exists() else Path(path)
    )
    text = read_text(path, "manifest")
    numbered = [
        (n, line)
        for n, line in enumerate(text.splitlines(), start=1)
        if line.strip() and not line.lstrip().startswith("#")
    ]
    if not numbered:
        raise InputError(f"{path}: empty manifest")
    table = list(csv.reader(line for _, line in numbered))
    header = [h.strip().lower() for h in table[0]]
    unknown = [h for h in header if h not in MANIFEST_COLUMNS]
    if unknown or "horizontal" not in header or len(set(header)) < len(header):
        raise InputError(
            f"{path}: line {numbered[0][0]}: the header must name the columns horizontal "
            f"(required), vertical, scale and dt, once each; got {', '.join(table[0])}"
        )
    rows = []
    folder = path.parent
    for i, ((lineno, _), cells) in enumerate(zip(numbered[1:], table[1:]), start=1):
        where = f"{path}: row {i} (line {lineno})"
        if len(cells) > len(header):
            raise InputError(f"{where}: {len(cells)} cells for {len(header)} columns")
        entry = dict(zip(header, (c.strip() for c in cells)))
        if not entry.get("horizontal"):
            raise InputError(f"{where}: no horizontal record")
        try:
            scale = float(entry.get("scale") or 1.0)
        except ValueError:
            scale = math.nan
        if not (math.isfinite(scale) and scale > 0.0):
            raise InputError(f"{where}: scale must be a number > 0, got {entry['scale']!r}")
        step = None
        if entry.get("dt"):
            try:
                step = positive("dt", entry["dt"], "s")
            except InputError as exc:
                raise InputError(f"{where}: {exc}") from None
        files = {
            key: _manifest_path(folder, entry[key])
            for key in ("horizontal", "vertical")
            if entry.get(key)
        }
        for key, file in files.items():
            if not file.is_file():
                raise InputError(f"{where}: {key} record {file}: no such file")
        rows.append(ManifestRow(files["horizontal"], files.get("vertical"), scale, i, lineno, step))
    if not rows:
        raise InputError(f"{path}: the manifest names no motions (a header and no rows)")
    return rows
