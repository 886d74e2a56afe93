"""Fragility curves written for loss tools (issue 47): :func:`export_fragility`.

Each body is one component with one limit state per fitted curve (today one, overturning: the
files carry LS1 … LSn, so more limit states come as more entries of the same loop). A lognormal
curve P(x) = Φ(ln(x/θ)/β) has median θ [the IM's unit] and dispersion β [-].

* ``pelicun`` — the damage-model CSV of pelicun 3.x (``damage_DB_…csv``): one row per component,
  columns ``ID``, ``Demand-Directional`` (1), ``Demand-Offset`` (0), ``Demand-Type``,
  ``Demand-Unit`` and, per limit state n, ``LSn-Family`` (``lognormal``), ``LSn-Theta_0`` (θ in
  the demand unit), ``LSn-Theta_1`` (β). Demand types of pelicun's vocabulary: ``Peak Ground
  Acceleration`` [g] for ``pga``, ``Peak Ground Velocity`` [mps] for ``pgv``, ``Peak Spectral
  Acceleration|T`` [g] for ``sa(T)``, ``Peak Spectral Velocity|T`` [mps] for ``psv(T)`` (5 %
  damping). pelicun 3.10 needs the offset and directional columns (without them it stops with
  a ``KeyError: ('Demand', 'Offset')``).
* ``openquake`` — a fragility model of the OpenQuake engine, NRML 0.5 XML: ``fragilityModel``
  (``id``, ``assetCategory``, ``lossCategory``) with ``description``, ``limitStates`` and one
  ``fragilityFunction`` per body, ``format="continuous" shape="logncdf"``, an ``imls`` element
  (``imt``, ``minIML``, ``maxIML``) and ``params`` (``ls``, ``mean``, ``stddev``) per limit
  state. The engine takes the mean and standard deviation of the IML itself, not of its
  logarithm: mean = θ·exp(β²/2), stddev = mean·√(exp(β²) − 1). IMTs ``PGA`` and ``SA(T)`` [g],
  ``PGV`` [cm/s] (θ in m/s is converted), ``PGD`` [cm]. ``minIML``/``maxIML``, the range
  where the functions are valid, span θ·exp(±4β) over the limit states (probabilities from
  3e-5 to 1 − 3e-5): the curve is not cut where it matters, and the fit's own extrapolation
  beyond the levels tested is what the fragility report warns about.

Identifiers: a body's name with every character but letters, digits, ``-`` and ``_`` replaced
by ``_`` (the NRML rule), at most 100 characters.
"""

from __future__ import annotations

import csv
import io
import math
import os
import re
import warnings
import xml.etree.ElementTree as ET
from collections.abc import Mapping
from pathlib import Path
from typing import Any

from ..core.files import atomic_write
from ..defaults import IM_DAMPING
from ..errors import InputError
from ..motions.intensity import IntensityMeasure, parse_im

#: The formats :func:`export_fragility` writes, and the file ``rocking fragility --export``
#: writes in its output folder.
EXPORT_FILES = {"pelicun": "fragility_pelicun.csv", "openquake": "fragility_openquake.xml"}
FORMATS = tuple(EXPORT_FILES)
#: The limit state of every curve fitted today.
OVERTURNING = "overturning"
#: NRML 0.5 namespace.
NRML = "http://openquake.org/xmlns/nrml/0.5"
#: OpenQuake loss categories (the manual's list).
LOSS_CATEGORIES = ("structural", "nonstructural", "contents", "business_interruption")
_ID_CHARS = re.compile(r"[^A-Za-z0-9_-]")

Curves = list[tuple[str, list[tuple[str, float, float]]]]


def export_fragility(
    result: Any,
    path: str | os.PathLike[str],
    format: str = "pelicun",
    *,
    im: str | IntensityMeasure | None = None,
    loss_category: str = "nonstructural",
) -> Path:
    """Write fragility curves for a loss tool (formats in the module notes).

    Parameters
    ----------
    result : xarray.Dataset, LognormalFit or mapping of name to LognormalFit (or None: no fit)
        The Dataset of :func:`rocking.fragility_analysis` (its ``median`` [the IM's unit] and
        ``beta`` [-] per body, its IM from ``attrs["im"]``), one fit (named ``body``) or fits
        by name. Bodies without a finite fit (nothing overturned, or everything) are left out
        with a warning.
    path : str or Path
        The file to write (its folder must exist); written atomically.
    format : str
        ``"pelicun"`` (damage-model CSV) or ``"openquake"`` (NRML fragility model).
    im : str or IntensityMeasure, optional
        The IM of the curves, e.g. ``"pga"``; needed for fits that do not carry it (read from
        the fit's ``im`` attribute otherwise, or the Dataset's).
    loss_category : str
        OpenQuake only: ``lossCategory`` of the model (``structural``, ``nonstructural``,
        ``contents``, ``business_interruption``).

    Returns
    -------
    Path
        The file written.

    Raises
    ------
    InputError
        For an unknown format, an IM the format has no name for (A_gx, the ensemble mean PGA
        of the paper, is none: it is not the demand of one event), or no body with a fit.
    """
    fmt, demand = check_exportable(_measure(result, im), format)
    curves = _curves(result)
    if fmt == "pelicun":
        text = _pelicun_csv(curves, *demand)
    else:
        if loss_category not in LOSS_CATEGORIES:
            raise InputError(
                f"loss_category must be one of {', '.join(LOSS_CATEGORIES)}, got {loss_category!r}"
            )
        text = _nrml(curves, *demand, loss_category)
    return atomic_write(path, text)


def check_exportable(im: str | IntensityMeasure, format: str) -> tuple[str, tuple[str, str, float]]:
    """The format's name (lower case) and its name of ``im`` with the unit and factor
    (:func:`pelicun_demand`, :func:`openquake_imt`); InputError if it has none (A_gx, the
    paper's ensemble mean PGA, is no demand of one event) or the format is unknown."""
    fmt = str(format).strip().lower()
    if fmt not in FORMATS:
        raise InputError(f"format must be one of {', '.join(FORMATS)}, got {format!r}")
    if isinstance(im, str) and im.strip().lower() == "agx":
        raise InputError(
            "im agx: A_gx is the mean PGA of an ensemble of motions, not the demand of one "
            "event that a loss tool feeds to a fragility; fit against pga (or another IM)"
        )
    return fmt, pelicun_demand(im) if fmt == "pelicun" else openquake_imt(im)


def pelicun_demand(im: str | IntensityMeasure) -> tuple[str, str, float]:
    """pelicun's demand type of ``im``, its unit and the factor from the IM's unit to it."""
    measure = parse_im(im)
    period = repr(float(measure.periods[0])) if measure.periods else ""
    names = {
        "pga": ("Peak Ground Acceleration", "g"),
        "pgv": ("Peak Ground Velocity", "mps"),
        "sa": (f"Peak Spectral Acceleration|{period}", "g"),
        "psv": (f"Peak Spectral Velocity|{period}", "mps"),
    }
    if measure.kind not in names or measure.damping not in (None, IM_DAMPING):
        raise InputError(
            f"im {measure.name}: pelicun has no demand type for it (pga, pgv, sa(T) and psv(T) "
            "at 5 % damping have one)"
        )
    return (*names[measure.kind], 1.0)


def openquake_imt(im: str | IntensityMeasure) -> tuple[str, str, float]:
    """The OpenQuake engine's IMT of ``im``, its unit and the factor from the IM's unit."""
    measure = parse_im(im)
    names = {
        "pga": ("PGA", "g", 1.0),
        "pgv": ("PGV", "cm/s", 100.0),
        "pgd": ("PGD", "cm", 100.0),
    }
    if measure.kind == "sa" and measure.damping == IM_DAMPING:
        return f"SA({float(measure.periods[0])!r})", "g", 1.0
    if measure.kind not in names:
        raise InputError(
            f"im {measure.name}: the OpenQuake engine has no IMT for it (pga, pgv, pgd and "
            "sa(T) at 5 % damping have one)"
        )
    return names[measure.kind]


def lognormal_moments(median: float, beta: float) -> tuple[float, float]:
    """Mean and standard deviation of a lognormal variable of median θ and dispersion β:
    θ·exp(β²/2) and mean·√(exp(β²) − 1) [the unit of θ]."""
    mean = median * math.exp(beta * beta / 2.0)
    return mean, mean * math.sqrt(math.expm1(beta * beta))


def _measure(result: Any, im: str | IntensityMeasure | None) -> str | IntensityMeasure:
    """The IM of the fits: ``im``, or the one they carry (which ``im`` must then equal)."""
    attrs = getattr(result, "attrs", None)
    found = attrs.get("im") if isinstance(attrs, Mapping) else getattr(result, "im", None)
    if found is None and isinstance(result, Mapping) and result:
        found = getattr(next(iter(result.values())), "im", None)
    if im is None:
        if found is None:
            raise InputError(
                "im: the fits do not say their intensity measure; give im (e.g. 'pga')"
            )
        return found
    if found is not None and _name(im) != _name(found):
        raise InputError(f"im {_name(im)} is not the fits' own, {_name(found)}")
    return im


def _name(im: str | IntensityMeasure) -> str:
    return "agx" if str(im).strip().lower() == "agx" else parse_im(im).name


def _curves(result: Any) -> Curves:
    """(name, [(limit state, θ, β), …]) of each body with a finite fit."""
    if hasattr(result, "data_vars"):  # the Dataset of fragility_analysis
        fits = {
            str(b): (float(m), float(s))
            for b, m, s in zip(
                result["body"].values, result["median"].values, result["beta"].values
            )
        }
    elif isinstance(result, Mapping):
        nothing = (math.nan, math.nan)  # a body without a fit: None
        fits = {
            str(k): nothing if v is None else (float(v.median), float(v.beta))
            for k, v in result.items()
        }
    elif hasattr(result, "median") and hasattr(result, "beta"):
        fits = {"body": (float(result.median), float(result.beta))}
    else:
        raise InputError(
            "result must be the Dataset of rocking.fragility_analysis, a rocking.LognormalFit "
            f"or a mapping of names to fits, got {type(result).__name__}"
        )
    good = {
        name: [(OVERTURNING, m, b)]
        for name, (m, b) in fits.items()
        if math.isfinite(m) and m > 0.0 and math.isfinite(b) and b > 0.0
    }
    left = [name for name in fits if name not in good]
    if not good:
        raise InputError("no body has a fitted curve (finite median and beta > 0) to export")
    if left:
        warnings.warn(
            f"not exported, no finite fit: {', '.join(left)}", RuntimeWarning, stacklevel=3
        )
    ids = [_ID_CHARS.sub("_", name)[:100] for name in good]
    if len(set(ids)) < len(ids):
        raise InputError(
            f"the body names {', '.join(good)} give the same identifier once characters other "
            "than letters, digits, - and _ are replaced: rename them"
        )
    return [(i, states) for i, states in zip(ids, good.values())]


def _pelicun_csv(curves: Curves, demand: str, unit: str, factor: float) -> str:
    n_states = max(len(states) for _, states in curves)
    header = ["ID", "Demand-Directional", "Demand-Offset", "Demand-Type", "Demand-Unit"]
    for n in range(1, n_states + 1):
        header += [f"LS{n}-Family", f"LS{n}-Theta_0", f"LS{n}-Theta_1"]
    buffer = io.StringIO()
    writer = csv.writer(buffer, lineterminator="\n")
    writer.writerow(header)
    for name, states in curves:
        row = [name, "1", "0", demand, unit]
        for _, median, beta in states:
            row += ["lognormal", repr(median * factor), repr(beta)]
        writer.writerow(row + [""] * (len(header) - len(row)))
    return buffer.getvalue()


def _nrml(curves: Curves, imt: str, unit: str, factor: float, loss_category: str) -> str:
    states = list(dict.fromkeys(ls for _, lss in curves for ls, _, _ in lss))
    ET.register_namespace("", NRML)
    root = ET.Element(f"{{{NRML}}}nrml")
    model = ET.SubElement(
        root,
        f"{{{NRML}}}fragilityModel",
        id="rocking_fragility",
        assetCategory="buildings",
        lossCategory=loss_category,
    )
    ET.SubElement(model, f"{{{NRML}}}description").text = (
        f"Overturning of free-standing rigid blocks: lognormal curves against {imt} [{unit}] "
        "fitted by rocking (maximum likelihood)"
    )
    ET.SubElement(model, f"{{{NRML}}}limitStates").text = " ".join(states)
    for name, lss in curves:
        function = ET.SubElement(
            model, f"{{{NRML}}}fragilityFunction", id=name, format="continuous", shape="logncdf"
        )
        low = min(m * math.exp(-4.0 * b) for _, m, b in lss) * factor
        high = max(m * math.exp(4.0 * b) for _, m, b in lss) * factor
        ET.SubElement(function, f"{{{NRML}}}imls", imt=imt, minIML=repr(low), maxIML=repr(high))
        for ls, median, beta in lss:
            mean, stddev = lognormal_moments(median * factor, beta)
            ET.SubElement(
                function, f"{{{NRML}}}params", ls=ls, mean=repr(mean), stddev=repr(stddev)
            )
    ET.indent(root)
    return ET.tostring(root, encoding="unicode", xml_declaration=True) + "\n"
