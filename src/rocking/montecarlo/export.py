"""Fragility curves written for loss tools (issue 47): :func:`export_fragility`.

Each body is one component with one limit state per fitted curve: overturning, or every limit
state of a result with a ``limit_state`` dimension (``fragility_analysis(...,
limit_states=...)``). A lognormal curve P(x) = Φ(ln(x/θ)/β) has median θ [the IM's unit] and
dispersion β [-].

Several limit states are written in order of increasing severity (LS1 the most often exceeded,
whatever the order they were given in), since both tools take them as sequential damage
states: pelicun draws one capacity per component for all its limit states (perfectly
correlated, pelicun 3.10 ``model/damage_model.py``) and puts the component in the highest
limit state its demand exceeds; OpenQuake takes the probability of damage state n as the
difference of the curves of limit states n and n+1. So P(DS ≥ n) is the curve of limit state n
only if the states are nested and their medians θ₁ < θ₂ < … increase with severity. Each limit
state is written with its own β (both formats take one per limit state: pelicun's
``LSn-Theta_1``, OpenQuake's ``stddev``). The fits of nested states do not cross inside the
intensities tested (:func:`~rocking.montecarlo.statistics.bootstrap_limit_states`); curves of
different β still cross once outside that range, where both are extrapolations. States that
are not nested, or a body whose medians do not increase (two states exceeded in the same cases
have the same median: a damage state that never occurs), are refused, naming them; one
state at a time can still be exported (``result.sel(limit_state=[name])``).

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
by ``_`` (the NRML rule), at most 100 characters; so are the names of limit states in NRML
(``theta/alpha>=0.5`` is ``theta_alpha__0_5``; the description lists them as given).
"""

from __future__ import annotations

import csv
import io
import itertools
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
from .statistics import severity_order

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
        ``beta`` [-] per body, and per limit state if it has them, its IM from
        ``attrs["im"]``), one fit (named ``body``) or fits by name. Bodies without a finite
        fit of every limit state (nothing exceeded it, or everything) are left out with a
        warning.
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
        of the paper, is none: it is not the demand of one event), no body with a fit, limit
        states that are not nested or a body whose medians do not increase with severity.
    """
    fmt, demand = check_exportable(_measure(result, im), format)
    curves, title = _curves(result)
    if fmt == "pelicun":
        text = _pelicun_csv(curves, *demand)
    else:
        if loss_category not in LOSS_CATEGORIES:
            raise InputError(
                f"loss_category must be one of {', '.join(LOSS_CATEGORIES)}, got {loss_category!r}"
            )
        text = _nrml(curves, title, *demand, loss_category)
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


def _curves(result: Any) -> tuple[Curves, str]:
    """(name, [(limit state, θ, β), …]) of each body with a finite fit of every limit state,
    and what the curves are of (the start of the NRML description)."""
    states, title = [OVERTURNING], "Overturning of free-standing rigid blocks"
    if hasattr(result, "data_vars") and "limit_state" in result.dims:
        states, fits = _limit_state_fits(result)
        title = (
            "Limit states of free-standing rigid blocks by increasing severity "
            f"({', '.join(states)}), nested, a beta per limit state"
        )
    elif hasattr(result, "data_vars"):  # the Dataset of fragility_analysis
        fits = {
            str(b): [(float(m), float(s))]
            for b, m, s in zip(
                result["body"].values, result["median"].values, result["beta"].values
            )
        }
    elif isinstance(result, Mapping):
        nothing = (math.nan, math.nan)  # a body without a fit: None
        fits = {
            str(k): [nothing if v is None else (float(v.median), float(v.beta))]
            for k, v in result.items()
        }
    elif hasattr(result, "median") and hasattr(result, "beta"):
        fits = {"body": [(float(result.median), float(result.beta))]}
    else:
        raise InputError(
            "result must be the Dataset of rocking.fragility_analysis, a rocking.LognormalFit "
            f"or a mapping of names to fits, got {type(result).__name__}"
        )
    labels = _identifiers(states, "limit state")
    good = {
        name: [(ls, m, b) for ls, (m, b) in zip(labels, pairs)]
        for name, pairs in fits.items()
        if all(math.isfinite(m) and m > 0.0 and math.isfinite(b) and b > 0.0 for m, b in pairs)
    }
    left = [name for name in fits if name not in good]
    if not good:
        raise InputError("no body has a fitted curve (finite median and beta > 0) to export")
    if left:
        warnings.warn(
            f"not exported, no finite fit: {', '.join(left)}", RuntimeWarning, stacklevel=3
        )
    return list(zip(_identifiers(list(good), "body"), good.values())), title


def _identifiers(names: list[str], what: str) -> list[str]:
    """``names`` as NRML identifiers (letters, digits, - and _, at most 100 characters)."""
    ids = [_ID_CHARS.sub("_", name)[:100] for name in names]
    if len(set(ids)) < len(ids):
        raise InputError(
            f"the {what} names {', '.join(names)} give the same identifier once characters "
            "other than letters, digits, - and _ are replaced: rename them"
        )
    return ids


def _limit_state_fits(ds: Any) -> tuple[list[str], dict[str, list[tuple[float, float]]]]:
    """The limit states of a result of ``fragility_analysis(..., limit_states=...)`` by
    increasing severity, and each body's (θ, β) of each in that order; InputError where they
    are not nested or a body's medians do not increase with severity (module notes)."""
    names = [str(s) for s in ds["limit_state"].values]
    key = next((k for k in ("exceeded_motion", "exceeded") if k in ds), None)
    if key is None:
        raise InputError(
            "result: a limit_state dimension without the variable exceeded of "
            "rocking.fragility_analysis (each case's outcome), which orders the limit states"
        )
    order, loose = severity_order(ds[key].transpose("limit_state", ...).values)
    if loose:
        pairs = "; ".join(f"{names[s]!r} is exceeded where {names[m]!r} is not" for m, s in loose)
        raise InputError(
            f"limit states not nested ({pairs}): a loss tool takes limit states as sequential "
            "damage states, each severer one exceeded only where the one before it is; export "
            "them one at a time (result.sel(limit_state=[name]))"
        )
    median = ds["median"].transpose("body", "limit_state").values[:, order]
    beta = ds["beta"].transpose("body", "limit_state").values[:, order]
    unit = ds.attrs.get("im_unit", "")
    for body, row in zip(ds["body"].values, median):
        for i, j in itertools.pairwise(range(len(order))):
            # a NaN median (no fit) leaves the body out, with a warning
            if row[j] <= row[i]:
                raise InputError(
                    f"body {body}: the median of limit state {names[order[j]]!r} "
                    f"({row[j]:.6g} {unit}) is not above that of the milder "
                    f"{names[order[i]]!r} ({row[i]:.6g} {unit}): a loss tool's damage states "
                    "need medians that increase with severity (equal ones: the two states are "
                    "exceeded in the same cases); drop one of them"
                )
    fits = {
        str(b): [(float(m), float(s)) for m, s in zip(ms, ss)]
        for b, ms, ss in zip(ds["body"].values, median, beta)
    }
    return [names[i] for i in order], fits


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


def _nrml(
    curves: Curves, title: str, imt: str, unit: str, factor: float, loss_category: str
) -> str:
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
    ET.SubElement(
        model, f"{{{NRML}}}description"
    ).text = (
        f"{title}: lognormal curves against {imt} [{unit}] fitted by rocking (maximum likelihood)"
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
