"""Hazard curves from the files of hazard engines (issue 47), for
:meth:`rocking.HazardCurve.from_csv`:

* **OpenQuake engine**, the hazard-curve CSV of ``oq export`` (``hazard_curve-mean-PGA_1.csv``):
  a first line that is a comment holding ``investigation_time=T`` and ``imt='PGA'``, then the
  header ``lon,lat,depth,poe-x1,poe-x2,…`` and one row per site with the probabilities of
  exceeding each x in T years. They become annual rates λ = −ln(1 − PoE)/T (Poisson
  occurrences, as the engine assumes). A PoE of 1 has no finite rate and a PoE of 0 no place
  on a log-log curve: such levels are left out (and said so); at least two must remain.
  Intensities: PGA and SA(T) in g, PGV in cm/s, PGD in cm.
* **USGS NSHM**, the JSON of the hazard web service (nshmp-haz-ws ``/hazard``):
  ``response[]``, one entry per IMT, each with ``metadata.imt`` (``{"value": "PGA", …}`` or
  ``"PGA"``), ``metadata.xvalues`` (the ground motions, "Ground Motion (g)") and
  ``data[]``, one curve per source type, of which ``component`` ``"Total"`` holds the total
  hazard's ``yvalues`` ("Annual Frequency of Exceedance", used as annual rates). IMTs ``PGA``,
  ``SA0P2`` (Sa at 0.2 s), ``SA1P0``, … in g, ``PGV`` in cm/s. Zero rates are left out.

Either way the IMT becomes an intensity measure of ``rocking`` in its unit (PGA → ``pga`` [g],
SA(T) → ``sa(T)`` [g] at 5 % damping, the engines' damping; PGV [cm/s] → ``pgv`` [m/s]; PGD
[cm] → ``pgd`` [m]), and :attr:`EngineCurve.origin` says what was found.
"""

from __future__ import annotations

import csv
import itertools
import json
import math
import os
import re
from dataclasses import dataclass
from pathlib import Path

import numpy as np

from ..core.files import read_text
from ..errors import InputError
from ..motions.intensity import IntensityMeasure, parse_im

_OQ_TIME = re.compile(r"investigation_time\s*=\s*([^,\s\"']+)")
_OQ_IMT = re.compile(r"imt\s*=\s*'([^']*)'")
_OQ_SA = re.compile(r"^SA\(\s*([0-9.eE+-]+)\s*\)$")
_USGS_SA = re.compile(r"^SA(\d+)P(\d+)$")
#: Engine IMT kind → (rocking kind, the engine's unit, factor to rocking's unit).
_KINDS = {
    "PGA": ("pga", "g", 1.0),
    "PGV": ("pgv", "cm/s", 0.01),
    "PGD": ("pgd", "cm", 0.01),
    "SA": ("sa", "g", 1.0),
}


@dataclass(frozen=True, eq=False)
class EngineCurve:
    """A hazard curve read from an engine's file.

    Attributes
    ----------
    im : IntensityMeasure
        The IM of ``rocking`` the engine's IMT maps to.
    values : ndarray
        Intensities in the IM's unit (converted from the engine's).
    rates : ndarray
        Annual rates of exceedance [1/yr], > 0.
    origin : str
        One sentence: the format, the site, the IMT and units found, the conversions made.
    """

    im: IntensityMeasure
    values: np.ndarray
    rates: np.ndarray
    origin: str


def detect_format(path: str | os.PathLike[str], text: str | None = None) -> str:
    """``"usgs"`` (a JSON file: ``.json`` or starting with ``{``), ``"openquake"`` (a first
    line starting with ``#`` that holds ``investigation_time``) or ``"csv"`` (the two-column
    hazard CSV of :class:`rocking.HazardCurve`). ``text``: the file's text, when already read."""
    head = _text(path, text)[:4096]
    if Path(path).suffix.lower() == ".json" or head.lstrip().startswith("{"):
        return "usgs"
    first = head.lstrip().split("\n", 1)[0]
    if first.startswith("#") and "investigation_time" in first:
        return "openquake"
    return "csv"


def _text(path: str | os.PathLike[str], text: str | None) -> str:
    """``text``, or the hazard file's text read now when it is None."""
    return read_text(path, "hazard file") if text is None else text


def poe_to_rate(poe: np.ndarray, years: float) -> np.ndarray:
    """Annual rate λ = −ln(1 − PoE)/T [1/yr] of a probability of exceedance ``poe`` in
    ``years`` = T (Poisson occurrences); PoE = 1 gives inf."""
    return np.array([-math.log1p(-p) / years if p < 1.0 else math.inf for p in np.ravel(poe)])


def engine_im(imt: str, where: str) -> tuple[IntensityMeasure, str, float]:
    """The IM of ``rocking`` of an engine's IMT (``PGA``, ``PGV``, ``PGD``, ``SA(0.3)`` or
    ``SA0P3``), the engine's unit and the factor from it to the IM's unit."""
    text = imt.strip().upper()
    m = _OQ_SA.match(text) or _USGS_SA.match(text)
    if m:
        period = m.group(1) if m.lastindex == 1 else f"{m.group(1)}.{m.group(2)}"
        _, unit, factor = _KINDS["SA"]
        return parse_im(f"sa({float(period)!r})"), unit, factor
    if text in _KINDS:
        kind, unit, factor = _KINDS[text]
        return parse_im(kind), unit, factor
    raise InputError(
        f"{where}: IMT {imt!r} has no intensity measure in rocking (PGA, PGV, PGD, SA(T))"
    )


def read_openquake(
    path: str | os.PathLike[str], site: int | None = None, text: str | None = None
) -> EngineCurve:
    """Read one site's curve of an OpenQuake-engine hazard-curve CSV (module notes).

    Parameters
    ----------
    path : str or Path
    site : int, optional
        The site: its row among the data rows, 0 for the first (the engine's site order);
        may be left out when the file has one site.
    text : str, optional
        The file's text, when already read (not read again).
    """
    lines = _text(path, text).splitlines()
    comment = lines[0] if lines else ""
    found = {}
    for key, pattern in (("investigation_time", _OQ_TIME), ("imt", _OQ_IMT)):
        m = pattern.search(comment)
        if m is None:
            raise InputError(f"{path}: line 1: no {key} in the OpenQuake header comment")
        found[key] = m.group(1)
    try:
        years = float(found["investigation_time"])
    except ValueError:
        years = math.nan
    if not (math.isfinite(years) and years > 0.0):
        raise InputError(
            f"{path}: line 1: investigation_time must be a number > 0 [yr], "
            f"got {found['investigation_time']!r}"
        )
    im, unit, factor = engine_im(found["imt"], f"{path}: line 1")
    table = [(n, [c.strip() for c in cells]) for n, cells in enumerate(csv.reader(lines), 1)]
    table = [(n, cells) for n, cells in table[1:] if any(cells)]
    if not table:
        raise InputError(f"{path}: no header 'lon,lat,depth,poe-…' below the comment line")
    header_line, header = table[0]
    columns = [i for i, name in enumerate(header) if name.lower().startswith("poe-")]
    if "lon" not in header or "lat" not in header or not columns:
        raise InputError(
            f"{path}: line {header_line}: expected the header 'lon,lat,depth,poe-…', got "
            f"{','.join(header[:4])}…"
        )
    levels = [_number(path, header_line, header[i], header[i][4:], "intensity") for i in columns]
    rows = table[1:]
    if not rows:
        raise InputError(f"{path}: no site rows below the header (line {header_line})")
    if site is None:
        if len(rows) > 1:
            raise InputError(
                f"{path}: {len(rows)} sites (rows); choose one with site / --site "
                f"(0 to {len(rows) - 1})"
            )
        site = 0
    if not (isinstance(site, int) and 0 <= site < len(rows)):
        raise InputError(
            f"{path}: site {site!r} is not a site of the file: it has {len(rows)} site row(s), "
            f"0 to {len(rows) - 1}"
        )
    lineno, cells = rows[site]
    if len(cells) != len(header):
        raise InputError(
            f"{path}: site {site} (line {lineno}): {len(cells)} values for {len(header)} columns"
        )
    poe = np.array([_number(path, lineno, header[i], cells[i], "PoE") for i in columns])
    bad = np.flatnonzero(poe > 1.0)
    if bad.size:
        i = columns[bad[0]]
        raise InputError(
            f"{path}: site {site} (line {lineno}), column {header[i]}: PoE {cells[i]} is above 1"
        )
    where = f"{path}: site {site} (line {lineno})"
    x, rates, dropped = _positive(
        np.array(levels) * factor, poe_to_rate(poe, years), where, [header[i] for i in columns]
    )
    lon, lat = cells[header.index("lon")], cells[header.index("lat")]
    return EngineCurve(
        im,
        x,
        rates,
        f"OpenQuake hazard curve, site {site} (lon {lon}, lat {lat}), IMT {found['imt']} "
        f"[{unit}] read as {im.column}, PoE in {years:g} years converted to annual rates "
        f"λ = −ln(1 − PoE)/{years:g}{dropped}",
    )


def read_usgs(
    path: str | os.PathLike[str], im: str | None = None, text: str | None = None
) -> EngineCurve:
    """Read the total hazard curve of a USGS NSHM hazard web service JSON file (module notes).

    Parameters
    ----------
    path : str or Path
    im : str, optional
        The IM to take (e.g. ``"pga"``, ``"sa(1.0)"``) when the file holds curves of several
        IMTs; may be left out when it holds one.
    text : str, optional
        The file's text, when already read (not read again).
    """
    try:
        doc = json.loads(_text(path, text))
    except json.JSONDecodeError as exc:
        raise InputError(f"{path}: line {exc.lineno}: not valid JSON ({exc.msg})") from None
    responses = doc.get("response") if isinstance(doc, dict) else None
    if isinstance(responses, dict):
        responses = [responses]
    if not isinstance(responses, list) or not responses:
        raise InputError(
            f"{path}: not a USGS NSHM hazard curve: no list 'response' (the hazard web "
            "service's JSON, one entry per IMT)"
        )
    curves = []
    for k, entry in enumerate(responses):
        where = f"{path}: response[{k}]"
        meta = entry.get("metadata") if isinstance(entry, dict) else None
        if not isinstance(meta, dict) or "imt" not in meta or "xvalues" not in meta:
            raise InputError(f"{where}: no metadata with imt and xvalues")
        imt = str(_value(meta["imt"]))
        curves.append((where, imt, engine_im(imt, f"{where}.metadata.imt"), meta, entry))
    if im is not None:
        wanted = parse_im(im)
        chosen = [c for c in curves if c[2][0] == wanted]
        if not chosen:
            raise InputError(
                f"{path}: no curve of {wanted.name}; the file has {', '.join(c[1] for c in curves)}"
            )
    elif len(curves) > 1:
        raise InputError(
            f"{path}: curves of {len(curves)} IMTs ({', '.join(c[1] for c in curves)}); "
            "choose one with im (rocking risk takes the fragility's)"
        )
    else:
        chosen = curves
    where, imt, (measure, unit, factor), meta, entry = chosen[0]
    totals = [
        d for d in entry.get("data") or [] if isinstance(d, dict) and d.get("component") == "Total"
    ]
    if not totals or "yvalues" not in totals[0]:
        raise InputError(f"{where}: no data entry with component 'Total' and its yvalues")
    x = _numbers(where, "metadata.xvalues", meta["xvalues"])
    y = _numbers(where, "data[Total].yvalues", totals[0]["yvalues"])
    if x.size != y.size:
        raise InputError(f"{where}: {x.size} xvalues but {y.size} yvalues")
    if np.any(y < 0.0):
        raise InputError(f"{where}: data[Total].yvalues holds a negative rate")
    x, rates, dropped = _positive(x * factor, y, where, [f"xvalues[{i}]" for i in range(x.size)])
    site = ", ".join(
        f"{key} {_value(meta[key])}"
        for key in ("edition", "region", "latitude", "longitude", "vs30")
        if key in meta
    )
    return EngineCurve(
        measure,
        x,
        rates,
        f"USGS NSHM hazard curve ({site}), IMT {imt} [{unit}] read as {measure.column}, "
        f"component Total, annual frequencies of exceedance as annual rates{dropped}",
    )


def _value(item):
    """An enum of the USGS JSON: ``{"value": …, "display": …}`` or the bare value."""
    return item.get("value", item.get("display")) if isinstance(item, dict) else item


def _numbers(where: str, key: str, items) -> np.ndarray:
    try:
        a = np.array(items, dtype=float)
    except (TypeError, ValueError):
        raise InputError(f"{where}: {key} must be a list of numbers") from None
    if a.ndim != 1 or not np.all(np.isfinite(a)):
        raise InputError(f"{where}: {key} must be a list of finite numbers")
    return a


def _number(path, lineno: int, column: str, text: str, what: str) -> float:
    try:
        x = float(text)
    except ValueError:
        x = math.nan
    if not (math.isfinite(x) and x >= 0.0):
        raise InputError(
            f"{path}: line {lineno}, column {column}: {what} {text!r} is not a number >= 0"
        )
    return x


def _positive(
    x: np.ndarray, rates: np.ndarray, where: str, names: list[str]
) -> tuple[np.ndarray, np.ndarray, str]:
    """The points with a finite rate > 0 (the others said in a clause), checked: at least two,
    intensities increasing, rates decreasing."""
    keep = np.isfinite(rates) & (rates > 0.0)
    n_inf, n_zero = int(np.sum(~np.isfinite(rates))), int(np.sum(rates == 0.0))
    dropped = "".join(
        f"; {n} level(s) with {what} left out"
        for n, what in ((n_inf, "PoE 1"), (n_zero, "rate 0"))
        if n
    )
    idx = np.flatnonzero(keep)
    if idx.size < 2:
        raise InputError(
            f"{where}: fewer than 2 intensities with a rate > 0 and finite (PoE strictly "
            "between 0 and 1): no curve to interpolate"
        )
    for a, b in itertools.pairwise(idx):
        if x[b] <= x[a]:
            raise InputError(f"{where}: the intensity of {names[b]} is not above {names[a]}'s")
        if rates[b] >= rates[a]:
            raise InputError(
                f"{where}: the rate at {names[b]} ({rates[b]:.6g}/yr) is not below the one "
                f"at {names[a]} ({rates[a]:.6g}/yr): rates of exceedance must decrease"
            )
    return x[idx], rates[idx], dropped
