"""Record files of strong-motion networks, recognised by their headers (not their names).

K-NET / KiK-net ASCII (NIED, Japan)
    17 header lines, each a fixed name and its value, in this order: ``Origin Time``, ``Lat.``,
    ``Long.``, ``Depth. (km)``, ``Mag.``, ``Station Code``, ``Station Lat.``, ``Station Long.``,
    ``Station Height(m)``, ``Record Time``, ``Sampling Freq(Hz)``, ``Duration Time(s)``,
    ``Dir.``, ``Scale Factor``, ``Max. Acc. (gal)``, ``Last Correction``, ``Memo.``; then the
    samples as whole counts (8 a line). ``Scale Factor`` is written ``3920(gal)/6182761``: gal
    per count. As the network specifies, the record's mean is removed after scaling; the
    header's ``Max. Acc. (gal)`` is then the peak, and a peak that disagrees with it beyond its
    rounding gets a :class:`RecordHeaderWarning`. Times are Japan Standard Time (JST, UTC+9):
    the origin time is kept as written, with its zone. A KiK-net station has a borehole and a
    surface sensor: files ``.NS1``/``.EW1``/``.UD1`` are the borehole's, ``.NS2``/``.EW2``/
    ``.UD2`` the surface's (``Dir.`` 1–6 says the same: 1–3 borehole NS, EW, UD, 4–6 surface);
    K-NET files ``.NS``/``.EW``/``.UD`` are surface records. The component says which, e.g.
    "EW2 (KiK-net surface)"; a file renamed so that neither says is "EW (sensor not stated)".
ESM / ITACA ASCII (ORFEUS Engineering Strong Motion database, Italian archive)
    ``KEY: value`` header lines (``EVENT_NAME``, ``EVENT_ID``, ``EVENT_DATE_YYYYMMDD``,
    ``EVENT_TIME_HHMMSS`` (UTC), ``NETWORK``, ``STATION_CODE``, ``STREAM``,
    ``SAMPLING_INTERVAL_S``, ``NDATA``, ``UNITS``, ``DATA_TYPE``, ``PGA_CM/S^2``,
    ``TIME_PGA_S``, …), then the values. ``SAMPLING_INTERVAL_S``, ``NDATA`` and ``UNITS`` are
    required; a ``DATA_TYPE`` other than ACCELERATION is refused; the stated PGA and its time are
    checked against the values (:class:`RecordHeaderWarning`).
COSMOS V1 / V2 (COSMOS Strong Motion Data Format 1.20; CESMD files)
    For each series: a text header (its first line says "(Format v01.20 with 13 text lines)"),
    the integer header and the real header (each announced by a line "100 Integer-header values
    follow on 10 lines, Format= (10I8)" giving their counts and Fortran formats), the comment
    lines ("N Comment line(s) follow"), the data line ("8000 acceleration pts, approx 40 secs,
    units=cm/sec2 (04), Format=(8F10.5)") and the values in that fixed-width format, then an
    "End-of-data" line. Integer header #1 is the processing level (1: V1, 2: V2), #2 the kind
    of series (1: acceleration), #54 the orientation (azimuth 0–360°, or 400 up, 401 down, 402
    vertical, 500 radial, 501 transverse, 600 longitudinal, 601 tangential, 700 H1, 701 H2);
    real header #62 is the sampling interval [ms], #64 the peak value and #65 its time [s]
    (checked against the values, :class:`RecordHeaderWarning`). The unit is the code of the
    data line: 2 g, 4 cm/s², 7 in/s², 10 gal (others, e.g. counts or mg, are refused). The
    velocity and displacement series of a V2 file are skipped; a file with the accelerations
    of several channels is refused (one record per file).
SAC and miniSEED (binary, through ObsPy: ``pip install 'rocking[formats]'``)
    Recognised by their first bytes (a SAC header of version 6 or 7, a miniSEED 2 fixed header
    or miniSEED 3's "MS"). Their values are counts or units the file does not state reliably,
    so ``units`` is required (refused when missing) and ``calibration`` [units per count]
    multiplies the values (default 1: the values are already in ``units``). One trace per file
    (several channels, or one channel with gaps, are refused).

Each reader returns a :class:`ParsedRecord`: values in the units stated by the file, the time
step [s] as stated, the metadata and the header as read.
"""

from __future__ import annotations

import math
import re
import warnings
from dataclasses import dataclass, field
from pathlib import Path

import numpy as np

from ..errors import InputError
from .units import acceleration_unit


class RecordHeaderWarning(UserWarning):
    """A record file's header disagrees with its values (a stated peak or its time)."""


@dataclass
class ParsedRecord:
    """A record as read from its file, before units are applied.

    Attributes
    ----------
    values : ndarray
        The samples in ``units`` (for SAC and miniSEED: as stored, before calibration).
    dt : float
        Time step [s] as stated by the file.
    units : str or None
        The units the file states (a name of :data:`~rocking.motions.units.ACCELERATION_UNITS`),
        None when it states none.
    format : str
        The format's name, e.g. "K-NET", "ESM", "COSMOS V2".
    event, date, station, component : str
        Metadata ("" when the file does not say); ``date`` states its time zone.
    header : dict
        The header's fields as written (name -> text).
    name : str
        The record's name when the file's stem does not tell it from others ("" otherwise):
        the whole file name of a K-NET/KiK-net file, whose extension is its component.
    """

    values: np.ndarray
    dt: float
    units: str | None
    format: str
    event: str = ""
    date: str = ""
    station: str = ""
    component: str = ""
    header: dict[str, str] = field(default_factory=dict)
    name: str = ""


def finite_number(text: str, where: str) -> float:
    """``text`` as a finite number, else an InputError that ``where`` starts (the file and
    line)."""
    try:
        x = float(text)
    except ValueError:
        x = math.nan
    if not math.isfinite(x):
        raise InputError(f"{where}: not a finite number: {text.strip()!r}")
    return x


def numbers(path: Path, lines: list[str], first: int) -> np.ndarray:
    """The blank-separated numbers of ``lines[first:]`` (a file's values after its header);
    errors name the file and the line."""
    out: list[float] = []
    for n in range(first, len(lines)):
        out += [finite_number(t, f"{path}: line {n + 1}") for t in lines[n].split()]
    return np.array(out)


def _rounding(text: str) -> float:
    """Half a unit of the last digit of a number as written: "2699.951" -> 0.0005,
    "-6.851512E-03" -> 5e-10."""
    m = re.fullmatch(r"\s*[-+]?\d*(?:\.(\d*))?(?:[eEdD]([-+]?\d+))?\s*", text)
    if m is None:
        return 0.0
    return 0.5 * 10.0 ** (int(m[2] or 0) - len(m[1] or ""))


def _check_stated_peak(
    where: str, values: np.ndarray, dt: float, units: str, peak: str, time: str | None = None
) -> None:
    """Warn (:class:`RecordHeaderWarning`) when the largest absolute value of ``values``
    differs from the header's ``peak`` (text, in ``units``) by more than its rounding (half a
    unit of its last digit, 1e-6 relative for the values' own rounding), or its time [s] from
    ``time`` (text) by more than one step and the time's rounding."""
    stated = abs(float(peak))
    i = int(np.argmax(np.abs(values)))
    found = abs(float(values[i]))
    tol = _rounding(peak) + 1e-6 * max(found, stated)
    if abs(found - stated) > tol:
        warnings.warn(
            f"{where}: the header states a peak of {peak.strip()} {units}, the values' peak is "
            f"{found:.6g} {units}",
            RecordHeaderWarning,
            stacklevel=4,
        )
    if time is not None:
        t = i * dt
        if abs(t - float(time)) > dt + _rounding(time):
            warnings.warn(
                f"{where}: the header states the peak at t = {time.strip()} s, the values' "
                f"peak is at t = {t:.6g} s",
                RecordHeaderWarning,
                stacklevel=4,
            )


# ---------------------------------------------------------------------------------------------
# K-NET / KiK-net
# ---------------------------------------------------------------------------------------------

#: The 17 header lines of a K-NET/KiK-net ASCII file, in order.
KNET_HEADER = (
    "Origin Time",
    "Lat.",
    "Long.",
    "Depth. (km)",
    "Mag.",
    "Station Code",
    "Station Lat.",
    "Station Long.",
    "Station Height(m)",
    "Record Time",
    "Sampling Freq(Hz)",
    "Duration Time(s)",
    "Dir.",
    "Scale Factor",
    "Max. Acc. (gal)",
    "Last Correction",
    "Memo.",
)
#: ``Dir.`` of KiK-net files written as a number: direction and sensor.
_KIKNET_DIRS = {
    "1": ("NS", "1"),
    "2": ("EW", "1"),
    "3": ("UD", "1"),
    "4": ("NS", "2"),
    "5": ("EW", "2"),
    "6": ("UD", "2"),
}
#: Sensors of a KiK-net station by the digit ending a file's extension.
_KIKNET_SENSORS = {"1": "borehole", "2": "surface"}
_SCALE = re.compile(r"^\s*(?P<num>[-+.\deE]+)\s*\((?P<unit>[^)]*)\)\s*/\s*(?P<den>[-+.\deE]+)\s*$")


def is_knet(lines: list[str]) -> bool:
    """Whether a file's first line is that of a K-NET/KiK-net ASCII file."""
    return bool(lines) and lines[0].startswith(KNET_HEADER[0])


def _knet_component(path: Path, direction: str, where: str) -> tuple[str, str]:
    """Component (e.g. "EW2 (KiK-net surface)") and format name of a K-NET/KiK-net file,
    from ``Dir.`` and the file's extension."""
    d = direction.strip().upper()
    sensor_of_dir = None
    if d in _KIKNET_DIRS:
        d, sensor_of_dir = _KIKNET_DIRS[d]
    else:
        d = d.replace("-", "")
        if d not in ("NS", "EW", "UD"):
            raise InputError(f"{where}: Dir. must be N-S, E-W, U-D or 1-6, got {direction!r}")
    m = re.fullmatch(r"(NS|EW|UD)([12]?)", path.suffix.lstrip(".").upper())
    if m and m[1] != d:
        raise InputError(
            f"{where}: Dir. {direction.strip()} disagrees with the file's extension {path.suffix}"
        )
    sensor = sensor_of_dir or (m[2] if m else None)
    if m and m[2] and sensor_of_dir and m[2] != sensor_of_dir:
        raise InputError(
            f"{where}: Dir. {direction.strip()} (sensor {sensor_of_dir}) disagrees with the "
            f"file's extension {path.suffix}"
        )
    if sensor:
        return f"{d}{sensor} (KiK-net {_KIKNET_SENSORS[sensor]})", "KiK-net"
    if m:  # .NS, .EW, .UD
        return f"{d} (K-NET surface)", "K-NET"
    return f"{d} (sensor not stated)", "K-NET/KiK-net"


def read_knet(path: Path, lines: list[str]) -> ParsedRecord:
    """A K-NET/KiK-net ASCII file (see the module notes); values in gal, mean removed."""
    header: dict[str, str] = {}
    for i, name in enumerate(KNET_HEADER):
        line = lines[i] if i < len(lines) else ""
        if not line.startswith(name):
            raise InputError(
                f"{path}: line {i + 1}: a K-NET/KiK-net header line {i + 1} starts with "
                f"{name!r}, got {line.strip()[:40]!r}"
            )
        header[name] = line[len(name) :].strip()

    def where(name: str) -> str:
        return f"{path}: line {KNET_HEADER.index(name) + 1}"

    m = _SCALE.match(header["Scale Factor"])
    if m is None:
        raise InputError(
            f"{where('Scale Factor')}: expected a scale factor such as 3920(gal)/6182761, "
            f"got {header['Scale Factor']!r}"
        )
    units = acceleration_unit(m["unit"], where("Scale Factor"))
    num = finite_number(m["num"], where("Scale Factor"))
    den = finite_number(m["den"], where("Scale Factor"))
    if den == 0.0:
        raise InputError(f"{where('Scale Factor')}: the scale factor's denominator is 0")
    freq_text = re.sub(r"\s*hz\s*$", "", header["Sampling Freq(Hz)"], flags=re.I)
    freq = finite_number(freq_text, where("Sampling Freq(Hz)"))
    if not freq > 0.0:
        raise InputError(f"{where('Sampling Freq(Hz)')}: the sampling frequency must be > 0 Hz")
    counts = numbers(path, lines, len(KNET_HEADER))
    if counts.size < 2:
        raise InputError(f"{path}: a record needs at least 2 samples, got {counts.size}")
    acc = counts * (num / den)
    acc -= acc.mean()  # NIED: the mean of the whole record is removed
    peak = header["Max. Acc. (gal)"]
    finite_number(peak, where("Max. Acc. (gal)"))
    _check_stated_peak(str(path), acc, 1.0 / freq, units, peak)
    component, fmt = _knet_component(path, header["Dir."], where("Dir."))
    event = (
        f"M {header['Mag.']}, {header['Lat.']}N {header['Long.']}E, depth "
        f"{header['Depth. (km)']} km"
    )
    return ParsedRecord(
        values=acc,
        dt=1.0 / freq,
        units=units,
        format=fmt,
        event=event,
        date=f"{header['Origin Time']} JST (UTC+9)",
        station=header["Station Code"],
        component=component,
        header=header,
        name=path.name,
    )


# ---------------------------------------------------------------------------------------------
# ESM / ITACA
# ---------------------------------------------------------------------------------------------

#: A header line of an ESM/ITACA file: KEY: value.
_ESM_LINE = re.compile(r"^([A-Z][A-Z0-9_/^().*-]*):(.*)$")
#: Keys of which one in the header makes a file ESM/ITACA; the required ones.
_ESM_KEYS = ("EVENT_NAME", "EVENT_ID", "STATION_CODE", "SAMPLING_INTERVAL_S", "NDATA", "STREAM")
ESM_REQUIRED = ("SAMPLING_INTERVAL_S", "NDATA", "UNITS")


def _esm_header(lines: list[str]) -> dict[str, tuple[int, str]]:
    """The leading ``KEY: value`` lines: key -> (line number, value)."""
    out: dict[str, tuple[int, str]] = {}
    for n, line in enumerate(lines, start=1):
        m = _ESM_LINE.match(line.strip())
        if m is None:
            break
        out[m[1]] = (n, m[2].strip())
    return out


def is_esm(lines: list[str]) -> bool:
    """Whether a file starts with ESM/ITACA ``KEY: value`` lines."""
    return any(k in _esm_header(lines[:100]) for k in _ESM_KEYS)


def read_esm(path: Path, lines: list[str]) -> ParsedRecord:
    """An ESM/ITACA ASCII file (see the module notes)."""
    found = _esm_header(lines)
    missing = [k for k in ESM_REQUIRED if not found.get(k, (0, ""))[1]]
    if missing:
        raise InputError(
            f"{path}: an ESM/ITACA header without {', '.join(missing)} (lines 1-{len(found)})"
        )

    def where(key: str) -> str:
        return f"{path}: line {found[key][0]}"

    value = {k: v for k, (_, v) in found.items()}
    kind = value.get("DATA_TYPE", "ACCELERATION").upper()
    if kind and kind != "ACCELERATION":
        raise InputError(f"{where('DATA_TYPE')}: DATA_TYPE {kind}, not an acceleration")
    units = acceleration_unit(value["UNITS"], where("UNITS"))
    dt = finite_number(value["SAMPLING_INTERVAL_S"], where("SAMPLING_INTERVAL_S"))
    if not dt > 0.0:
        raise InputError(f"{where('SAMPLING_INTERVAL_S')}: the sampling interval must be > 0 s")
    ndata = value["NDATA"]
    if not ndata.isdigit():
        raise InputError(f"{where('NDATA')}: NDATA is not a whole number: {ndata!r}")
    values = numbers(path, lines, len(found))
    if values.size != int(ndata):
        raise InputError(
            f"{where('NDATA')}: the header announces NDATA = {ndata} values, the file holds "
            f"{values.size}"
        )
    if values.size and value.get("PGA_CM/S^2"):
        pga = value["PGA_CM/S^2"]
        finite_number(pga, where("PGA_CM/S^2"))
        scale = {"cm/s2": 1.0, "m/s2": 100.0}.get(units)
        if scale is not None:  # the PGA is stated in cm/s²
            time = value.get("TIME_PGA_S") or None
            if time is not None:
                finite_number(time, where("TIME_PGA_S"))
            _check_stated_peak(str(path), values * scale, dt, "cm/s2", pga, time)
    event = value.get("EVENT_NAME", "")
    if event.lower() in ("", "none"):
        event = value.get("EVENT_ID", "")
    date = ""
    if value.get("EVENT_DATE_YYYYMMDD"):
        d, t = value["EVENT_DATE_YYYYMMDD"], value.get("EVENT_TIME_HHMMSS", "")
        date = f"{d[:4]}-{d[4:6]}-{d[6:8]}"
        if t:
            date += f" {t[:2]}:{t[2:4]}:{t[4:6]}"
        date += " UTC"
    station = ".".join(v for v in (value.get("NETWORK", ""), value.get("STATION_CODE", "")) if v)
    return ParsedRecord(
        values=values,
        dt=dt,
        units=units,
        format="ESM",
        event=event,
        date=date,
        station=station,
        component=value.get("STREAM", ""),
        header=value,
    )


# ---------------------------------------------------------------------------------------------
# COSMOS V1/V2
# ---------------------------------------------------------------------------------------------

_COSMOS_FIRST = re.compile(r"\(\s*format\s+v\s*[\d.]+\s+with\s+(\d+)\s+text\s+lines?\s*\)", re.I)
_FORTRAN = r"\(\s*(\d+)\s*([IFEG])\s*(\d+)(?:\.\d+)?\s*\)"
_COSMOS_INT = re.compile(rf"^\s*(\d+)\s+integer-header\s+values.*format\s*=\s*{_FORTRAN}", re.I)
_COSMOS_REAL = re.compile(rf"^\s*(\d+)\s+real-header\s+values.*format\s*=\s*{_FORTRAN}", re.I)
_COSMOS_COMMENTS = re.compile(r"^\s*(\d+)\s+comment\s+line", re.I)
_COSMOS_DATA = re.compile(
    rf"^\s*(\d+)\s+(\w+)\s+pts\b.*units\s*=\s*([^(,]*?)\s*\(\s*(\d+)\s*\).*format\s*=\s*{_FORTRAN}",
    re.I,
)
#: COSMOS physical-unit codes (Table 2 of the format) of units of acceleration.
COSMOS_UNITS = {2: "g", 4: "cm/s2", 7: "in/s2", 10: "gal"}
#: COSMOS orientation codes (integer header #54) that are not azimuths.
_COSMOS_ORIENTATIONS = {
    400: "Up",
    401: "Down",
    402: "Vertical",
    500: "Radial",
    501: "Transverse",
    600: "Longitudinal",
    601: "Tangential",
    700: "H1",
    701: "H2",
}


def is_cosmos(lines: list[str]) -> bool:
    """Whether a file's first line is that of a COSMOS V0–V3 file."""
    return bool(lines) and _COSMOS_FIRST.search(lines[0]) is not None


def _fixed(path: Path, lines: list[str], start: int, count: int, per_line: int, width: int):
    """``count`` fixed-width fields (``per_line`` of ``width`` characters a line) from
    ``lines[start:]``, as text, and the index of the line after them."""
    n_lines = -(-count // per_line)
    if start + n_lines > len(lines):
        raise InputError(f"{path}: line {len(lines)}: the file ends inside a COSMOS block")
    fields: list[tuple[int, str]] = []
    for k in range(n_lines):
        line = lines[start + k].rstrip("\n")
        for j in range(per_line):
            cell = line[j * width : (j + 1) * width]
            if cell.strip():
                fields.append((start + k + 1, cell))
    if len(fields) != count:
        raise InputError(
            f"{path}: lines {start + 1}-{start + n_lines}: expected {count} values in "
            f"{per_line} columns of {width} characters, got {len(fields)}"
        )
    return fields, start + n_lines


def _cosmos_line(path: Path, lines: list[str], n: int, pattern: re.Pattern, what: str):
    if n >= len(lines) or (m := pattern.match(lines[n])) is None:
        got = lines[n].strip()[:60] if n < len(lines) else "the end of the file"
        raise InputError(f"{path}: line {n + 1}: expected the COSMOS {what} line, got {got!r}")
    return m


def _cosmos_block(path: Path, lines: list[str], start: int) -> tuple[dict, int]:
    """One series of a COSMOS file from ``lines[start]`` (its first text line)."""
    m = _COSMOS_FIRST.search(lines[start])
    if m is None:
        raise InputError(f"{path}: line {start + 1}: expected the first line of a COSMOS series")
    n_text = int(m[1])
    text = lines[start : start + n_text]
    unknown_int, unknown_real = -999, -999.0
    for line in text:
        if "unknown" in line.lower() and ":" in line:
            nums = re.findall(r"[-+]?\d+(?:\.\d*)?", line.split(":", 1)[1])
            if len(nums) >= 2:
                unknown_int, unknown_real = int(float(nums[0])), float(nums[1])
    n = start + n_text
    headers = []
    for pattern, what in ((_COSMOS_INT, "integer-header"), (_COSMOS_REAL, "real-header")):
        h = _cosmos_line(path, lines, n, pattern, what)
        fields, n = _fixed(path, lines, n + 1, int(h[1]), int(h[2]), int(h[4]))
        for ln, c in fields:
            finite_number(c, f"{path}: line {ln}")
        headers.append([c.strip() for _, c in fields])
    ints, reals = [int(float(x)) for x in headers[0]], [float(x) for x in headers[1]]
    h = _cosmos_line(path, lines, n, _COSMOS_COMMENTS, "comment-count")
    n += 1 + int(h[1])
    d = _cosmos_line(path, lines, n, _COSMOS_DATA, "data")
    npts, kind, unit_text, code = int(d[1]), d[2].lower(), d[3], int(d[4])
    data_line = n + 1
    fields, n = _fixed(path, lines, n + 1, npts, int(d[5]), int(d[7]))
    values = np.array([finite_number(c, f"{path}: line {ln}") for ln, c in fields])
    if n < len(lines) and lines[n].strip().lower().startswith("end-of-data"):
        n += 1
    block = {
        "text": text,
        "ints": ints,
        "reals": reals,
        "reals_text": headers[1],
        "unknown": (unknown_int, unknown_real),
        "kind": kind,
        "unit_text": unit_text,
        "unit_code": code,
        "values": values,
        "line": start + 1,
        "data_line": data_line,
    }
    return block, n


def read_cosmos(path: Path, lines: list[str]) -> ParsedRecord:
    """A COSMOS V1/V2 file (see the module notes): its acceleration series."""
    blocks = []
    n = 0
    while n < len(lines):
        if not lines[n].strip():
            n += 1
            continue
        block, n = _cosmos_block(path, lines, n)
        blocks.append(block)
    acc = [b for b in blocks if b["kind"].startswith("acc")]
    if not acc:
        kinds = ", ".join(sorted({b["kind"] for b in blocks}))
        raise InputError(f"{path}: a COSMOS file without an acceleration series ({kinds})")
    if len(acc) > 1:
        starts = ", ".join(str(b["line"]) for b in acc)
        raise InputError(
            f"{path}: a COSMOS file with {len(acc)} acceleration series (channels; at lines "
            f"{starts}): one record per file, split it"
        )
    b = acc[0]
    ints, reals = b["ints"], b["reals"]
    unknown_int, unknown_real = b["unknown"]
    where = f"{path}: line {b['data_line']}"
    if b["unit_code"] not in COSMOS_UNITS:
        raise InputError(
            f"{where}: COSMOS unit code {b['unit_code']} ({b['unit_text'].strip()}) is not a "
            f"unit of acceleration read here (codes {', '.join(map(str, COSMOS_UNITS))})"
        )
    units = acceleration_unit(COSMOS_UNITS[b["unit_code"]], where)
    if len(reals) < 65 or len(ints) < 54:
        raise InputError(
            f"{path}: line {b['line']}: a COSMOS series needs at least 54 integer and 65 real "
            f"header values, got {len(ints)} and {len(reals)}"
        )
    dt_ms = reals[61]  # real header #62: sampling interval [ms]
    if dt_ms == unknown_real or not dt_ms > 0.0:
        raise InputError(
            f"{path}: line {b['line']}: real header #62 (sampling interval [ms]) is "
            f"{dt_ms:g}: unknown or not > 0"
        )
    dt = dt_ms / 1000.0
    values = b["values"]
    if values.size < 2:
        raise InputError(f"{path}: a record needs at least 2 samples, got {values.size}")
    peak, time = reals[63], reals[64]  # real header #64: peak value, #65: its time [s]
    if peak != unknown_real:
        _check_stated_peak(
            str(path),
            values,
            dt,
            units,
            b["reals_text"][63],
            None if time == unknown_real else b["reals_text"][64],
        )
    level = {1: "V1", 2: "V2"}.get(ints[0], f"V{ints[0]}")
    orientation = ints[53]  # integer header #54
    if 0 <= orientation <= 360:
        component = f"{orientation} deg"
    else:
        component = _COSMOS_ORIENTATIONS.get(orientation, "")
    text = b["text"]
    line5 = text[4] if len(text) > 4 else ""
    station = " ".join(s for s in (line5[25:34].strip(), line5[40:].strip()) if s)
    header = {f"text line {i + 1}": line.rstrip() for i, line in enumerate(text)}
    header.update({f"integer #{i + 1}": str(v) for i, v in enumerate(ints) if v != unknown_int})
    stated = zip(reals, b["reals_text"])
    header.update({f"real #{i + 1}": t for i, (v, t) in enumerate(stated) if v != unknown_real})
    return ParsedRecord(
        values=values,
        dt=dt,
        units=units,
        format=f"COSMOS {level}",
        event=" ".join(text[1].split()) if len(text) > 1 else "",
        station=station,
        component=component,
        header=header,
    )


# ---------------------------------------------------------------------------------------------
# SAC and miniSEED (ObsPy)
# ---------------------------------------------------------------------------------------------

#: Byte offset of the SAC header's version number (NVHDR, integer word 7 after 70 floats) and
#: length of the SAC header [bytes].
_SAC_NVHDR = 304
_SAC_HEADER = 632


def binary_format(head: bytes) -> str | None:
    """ "SAC" or "miniSEED" when ``head`` (a file's first bytes) starts such a file, else None:
    a SAC header of version 6 or 7 (either byte order), a miniSEED 2 fixed header (6 digits of
    sequence number, a quality code D, R, Q or M, then a blank or zero byte) or miniSEED 3
    ("MS" and version 3)."""
    if head[:3] == b"MS\x03":
        return "miniSEED"
    seq, quality = head[:6], head[6:7]
    if (
        len(head) >= 48
        and re.fullmatch(rb"[0-9 ]{6}", seq)
        and seq.strip()
        and quality in (b"D", b"R", b"Q", b"M")
        and head[7:8] in (b" ", b"\0")
    ):
        return "miniSEED"
    if len(head) >= _SAC_HEADER:
        word = head[_SAC_NVHDR : _SAC_NVHDR + 4]
        if int.from_bytes(word, "little") in (6, 7) or int.from_bytes(word, "big") in (6, 7):
            return "SAC"
    return None


def read_obspy(path: Path, fmt: str, units: str | None, calibration: float) -> ParsedRecord:
    """A SAC or miniSEED file through ObsPy (see the module notes); ``units`` (a name of
    :data:`~rocking.motions.units.ACCELERATION_UNITS`) is that of the values times
    ``calibration`` [units per stored value]."""
    try:
        import obspy
    except ImportError:
        raise InputError(
            f"{path}: a {fmt} file; reading it needs ObsPy: pip install 'rocking[formats]'"
        ) from None
    if units is None:
        raise InputError(
            f"{path}: a {fmt} file holds counts or units it does not state reliably: give its "
            "units (--units; in Python units=) and, for counts, the calibration (--calibration, "
            "units per count)"
        )
    try:
        stream = obspy.read(str(path), format="MSEED" if fmt == "miniSEED" else "SAC")
    except Exception as exc:  # ObsPy raises many kinds on a damaged file
        raise InputError(f"{path}: not a readable {fmt} file ({exc})") from None
    if len(stream) != 1:
        ids = ", ".join(tr.id for tr in stream[:4]) + (", ..." if len(stream) > 4 else "")
        raise InputError(
            f"{path}: {len(stream)} traces ({ids}; several channels, or gaps in one): one "
            "record per file"
        )
    tr = stream[0]
    stats = tr.stats
    sac = stats.get("sac", {})
    idep = sac.get("idep")
    if idep in (6, 7):  # SAC's IDISP, IVEL
        kind = "displacement" if idep == 6 else "velocity"
        raise InputError(f"{path}: the SAC header (IDEP) says {kind}, not an acceleration")
    event = str(sac.get("kevnm", "")).strip()
    values = np.asarray(tr.data, dtype=np.float64) * calibration
    header = {k: str(v) for k, v in stats.items() if k not in ("sac", "mseed", "_format")}
    header.update({f"sac.{k}": str(v) for k, v in sac.items()})
    return ParsedRecord(
        values=values,
        dt=float(stats.delta),
        units=None,
        format=fmt,
        event="" if event == "-12345" else event,
        date=f"{stats.starttime.isoformat()} UTC (first sample)",
        station=".".join(p for p in (stats.network, stats.station, stats.location) if p),
        component=stats.channel,
        header=header,
    )
