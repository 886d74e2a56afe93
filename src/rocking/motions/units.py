"""Units of acceleration that records and spectra may be given in: one table for every reader.

:data:`ACCELERATION_UNITS` maps each unit's name to its factor [m/s² per unit]: g (standard
gravity, 9.80665 m/s²), m/s², cm/s² (= gal), mm/s², in/s² (0.0254 m/s²) and ft/s² (0.3048 m/s²).
:func:`acceleration_unit` reads a unit as people write it (any case and spacing; "s2", "s^2",
"s**2", "s²", "sec2", "/s/s", "/sec/sec", "s-2"; "gal", "gals") and refuses anything else,
naming it: a unit that is not understood is never taken to be g.

:func:`implausible_peak` judges a record's peak acceleration [g] and names the unit the values
were more likely in (a peak of 312.7 "g" is 0.32 g read in cm/s²): :data:`PLAUSIBLE_PEAK_G` is
the range of recorded peaks (the largest recorded PGAs are about 3–4 g, the smallest that
trigger a strong-motion instrument about 1e-4 g), :data:`MAX_PEAK_G` the peak beyond which a
record is certainly in other units than stated.
"""

from __future__ import annotations

import math
import re

from ..defaults import G
from ..errors import InputError


class ImplausiblePeakWarning(UserWarning):
    """A record's peak acceleration is implausible for a ground or floor motion (likely a
    mistake of units; :func:`implausible_peak`)."""


#: Units of acceleration: name -> factor [m/s² per unit].
ACCELERATION_UNITS = {
    "g": G,
    "m/s2": 1.0,
    "cm/s2": 0.01,
    "mm/s2": 0.001,
    "in/s2": 0.0254,
    "ft/s2": 0.3048,
}
#: Other names of the units (after :func:`_normalised`).
_ALIASES = {"gal": "cm/s2", "gals": "cm/s2", "g's": "g", "gs": "g"}
#: The units as listed in messages.
UNITS_TEXT = "g, m/s2, cm/s2 (gal), mm/s2, in/s2, ft/s2"

#: Peaks of recorded ground (and floor) accelerations [g]: outside, a record gets a warning.
PLAUSIBLE_PEAK_G = (1e-4, 5.0)
#: Peak [g] beyond which a record is refused: no ground or floor motion comes near 100 g.
MAX_PEAK_G = 100.0
#: A peak near which a stated unit is "likely" (:func:`implausible_peak`): a moderate PGA [g];
#: the units are listed by how near their peak comes to it, at most _LIKELY of them.
_TYPICAL_PEAK_G = 0.3
_LIKELY = 3


def _normalised(text: str) -> str:
    """``text`` lower case, without spaces, "sec" as "s" and every way of writing s² as "s2"."""
    key = str(text).strip().lower().replace("²", "2").replace("**", "^")
    key = re.sub(r"\s+", " ", key)
    key = re.sub(r"(?<=[a-z]) (?=s\^?-2$)", "/", key).replace(" ", "")  # "m s-2" -> "m/s-2"
    key = re.sub(r"sec(ond)?s?", "s", key)
    key = re.sub(r"/s(?:\^?2|/s|\^?-2)$|/\(s\^?2\)$|[.*·]s\^?-2$", "/s2", key)
    return _ALIASES.get(key, key)


def acceleration_unit(text: str, where: str = "units") -> str:
    """The name in :data:`ACCELERATION_UNITS` of a unit as written (see the module notes).

    Parameters
    ----------
    text : str
        E.g. "cm/sec/sec", "GAL", "m/s^2", "in/s²".
    where : str
        What gave it (a parameter, a file, a column), to start the error message.

    Raises
    ------
    InputError
        For any other unit, naming it and listing the units understood.
    """
    name = _normalised(text)
    if name not in ACCELERATION_UNITS:
        raise InputError(
            f"{where}: unit {str(text).strip()!r} is not a unit of acceleration understood "
            f"here; use one of {UNITS_TEXT}"
        )
    return name


def unit_factor(units: str, where: str = "units") -> float:
    """Factor [m/s² per unit] of a unit as written (:func:`acceleration_unit`)."""
    return ACCELERATION_UNITS[acceleration_unit(units, where)]


def implausible_peak(peak: float, units: str) -> str | None:
    """Why a record's peak acceleration is implausible, or None when it is not.

    Parameters
    ----------
    peak : float
        The largest absolute value of the record, in ``units`` (as it was read).
    units : str
        A name of :data:`ACCELERATION_UNITS`.

    Returns
    -------
    str or None
        E.g. "peak 312.7 g (read in g) is implausible …; the values are likely in cm/s2
        (peak 0.3189 g), in/s2 (peak 0.81 g), mm/s2 (peak 0.03189 g)": the units in which the
        peak would be plausible, nearest to a moderate 0.3 g first; None when the peak lies in
        :data:`PLAUSIBLE_PEAK_G`.
    """
    peak_g = peak * ACCELERATION_UNITS[units] / G
    lo, hi = PLAUSIBLE_PEAK_G
    if lo <= peak_g <= hi or peak == 0.0:  # zero: no motion in any unit (refused where used)
        return None
    text = (
        f"peak {peak_g:.4g} g (read in {units}) is implausible for a ground or floor motion "
        f"(recorded peaks lie within {lo:g}–{hi:g} g)"
    )
    peaks = {u: peak * f / G for u, f in ACCELERATION_UNITS.items() if u != units}
    likely = sorted(
        (u for u, p in peaks.items() if lo <= p <= hi),
        key=lambda u: abs(math.log(peaks[u] / _TYPICAL_PEAK_G)),
    )[:_LIKELY]
    if likely:
        listed = ", ".join(f"{u} (peak {peaks[u]:.4g} g)" for u in likely)
        text += f"; the values are likely in {listed}: state the units"
    return text
