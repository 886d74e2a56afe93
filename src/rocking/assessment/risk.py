"""Seismic risk: the mean annual rate of overturning from a fragility curve and a hazard curve,
:func:`annual_rate`.

λ_f = ∫ P_f(x)·abs(dλ/dx) dx (the "risk integral"; Cornell et al. 2002, "Probabilistic basis
for 2000 SAC Federal Emergency Management Agency steel moment frame guidelines", J. Struct.
Eng. 128(4)), with P_f the probability of overturning at intensity x and λ(x) the annual rate
of exceeding x at the site.

Hazard curves. A :class:`HazardCurve` holds intensities x_0 < … < x_n (> 0) and their annual
rates of exceedance λ_0 > … > λ_n (> 0), with the intensity measure they are of. Between two
points the curve is interpolated log-log: a power law λ = λ_i·(x/x_i)^(−k_i) with
k_i = ln(λ_i/λ_{i+1})/ln(x_{i+1}/x_i) > 0. As a CSV file (:meth:`HazardCurve.from_csv`)::

    # comment lines start with #
    pgv [m/s],annual_rate [1/yr]
    0.01,0.0836
    0.02,0.05
    …

The first column's header names the IM with its unit in brackets, as
:func:`rocking.parse_im` reads it (``pga [g]``, ``sa(1.0) [g]``, ``pgv [m/s]``); the second is
``annual_rate`` (or ``rate``, ``annual rate of exceedance``; unit ``[1/yr]`` optional). The
word ``example`` names the shipped illustrative PGV curve (:func:`example_hazard_path`; not a
real site).

The integral and its tails (:class:`RiskResult`):

* over the table, segment by segment in ln x, each by ``scipy.integrate.quad`` to a relative
  1e-10 (the summed error estimates are reported);
* above the last point (upper tail), the last segment's power law extrapolated to infinity,
  added to the rate; whatever the hazard does there, this tail lies between
  P_f(x_n)·λ_n and λ_n (P_f does not decrease and at most λ_n events a year exceed x_n), and
  both bounds are reported;
* below the first point (lower tail), nothing is added: the table does not say how often
  weaker shaking occurs. The contribution left out is at most P_f(x_0) times the annual rate
  of events with an IM below x_0; P_f(x_0) is reported, and so is the value the first
  segment's power law extrapolated down to 0 would give. Both should be negligible beside the
  rate; if not, extend the table to lower intensities.
"""

from __future__ import annotations

import math
import os
import re
from dataclasses import dataclass
from importlib.resources import files
from pathlib import Path
from typing import Any

import numpy as np
from numpy.typing import ArrayLike

from ..core import portable
from ..core.checks import finite_array
from ..core.files import csv_rows, read_text
from ..defaults import AGX
from ..errors import InputError
from ..motions.intensity import IntensityMeasure, parse_im

#: Accepted names of the rate column (lower case, without unit) and of its unit.
_RATE_NAMES = ("annual_rate", "annual rate", "rate", "annual rate of exceedance")
_RATE_UNITS = ("1/yr", "1/year", "/yr", "1/a")
_BRACKET = re.compile(r"^(.*?)\s*\[(.*)\]\s*$")
#: The word that stands for the shipped example hazard curve.
EXAMPLE = "example"


def example_hazard_path() -> Path:
    """Path of the shipped example hazard curve: annual rates of exceedance of PGV [m/s] at a
    moderately active site, from 0.005 to 3 m/s (illustrative: made up, not a real site)."""
    return Path(str(files("rocking") / "data" / "example_hazard_pgv.csv"))


def illustrative_note(source: str | os.PathLike[str]) -> str:
    """For reports: a sentence saying that the hazard curve read from ``source`` (a path) is the
    shipped illustrative one, or "" for any other curve."""
    if Path(source).resolve() != example_hazard_path().resolve():
        return ""
    return (
        "The hazard curve is the shipped `example`: illustrative, made up for a moderately "
        "active site, not the hazard of any real site; use your site's curve for decisions."
    )


def hazard_path(spec: str | os.PathLike[str]) -> Path:
    """The hazard file ``spec`` names: a path, or the word ``example`` (any case, blanks
    around it ignored; when no file has that name) for :func:`example_hazard_path`."""
    text = str(spec)
    if text.strip().lower() == EXAMPLE and not Path(text).exists():
        return example_hazard_path()
    return Path(spec)


@dataclass(frozen=True, eq=False)
class HazardCurve:
    """A seismic hazard curve: annual rates of exceedance of an intensity measure.

    Parameters
    ----------
    im : str or IntensityMeasure
        The intensity measure, as :func:`rocking.parse_im` reads it (e.g. ``"pgv"``).
    values : array_like, shape (n,)
        Intensities x [the IM's unit], > 0, increasing, n ≥ 2.
    rates : array_like, shape (n,)
        Annual rates of exceeding each x [1/yr], > 0, decreasing.
    source : str
        Where the curve comes from (a file name), for messages.
    origin : str
        What was read: for an engine's file, the format, site, IMT and units found and the
        conversions made (:mod:`rocking.assessment.hazard_formats`); "" otherwise.
    """

    im: Any
    values: np.ndarray
    rates: np.ndarray
    source: str = ""
    origin: str = ""

    def __post_init__(self) -> None:
        object.__setattr__(self, "im", parse_im(self.im))
        x = finite_array("values", self.values, min_len=2)
        lam = finite_array("rates", self.rates, min_len=2)
        if lam.shape != x.shape:
            raise InputError(f"rates has {lam.size} values for {x.size} intensities")
        where = f"{self.source}: " if self.source else ""
        for name, a in (("values", x), ("rates", lam)):
            if np.any(a <= 0.0):
                i = int(np.argmax(a <= 0.0))
                raise InputError(f"{where}{name}[{i}] = {a[i]:g} must be > 0")
        bad = np.flatnonzero(np.diff(x) <= 0.0)
        if bad.size:
            raise InputError(
                f"{where}values must increase: values[{bad[0] + 1}] = {x[bad[0] + 1]:g}"
            )
        bad = np.flatnonzero(np.diff(lam) >= 0.0)
        if bad.size:
            raise InputError(
                f"{where}rates must decrease: rates[{bad[0] + 1}] = {lam[bad[0] + 1]:g}"
            )
        for name, a in (("values", x), ("rates", lam)):
            a.setflags(write=False)
            object.__setattr__(self, name, a)

    def __repr__(self) -> str:
        src = f", {Path(self.source).name}" if self.source else ""
        return (
            f"HazardCurve({self.im.column}, {self.values.size} points from {self.values[0]:.4g} "
            f"to {self.values[-1]:.4g} {self.im.unit}, rates {self.rates[0]:.3g} to "
            f"{self.rates[-1]:.3g} /yr{src})"
        )

    @property
    def exponents(self) -> np.ndarray:
        """k_i of the power law λ = λ_i·(x/x_i)^(−k_i) of each segment [-], shape (n − 1,)."""
        return -np.diff(portable.log(self.rates)) / np.diff(portable.log(self.values))

    def rate(self, x: ArrayLike) -> np.ndarray:
        """Annual rate of exceeding ``x`` [1/yr] (x > 0, the IM's unit): log-log interpolation
        between the points, the end segments' power laws extrapolated outside."""
        x = np.asarray(x, dtype=float)
        i = self._segment(x)
        return self.rates[i] * (x / self.values[i]) ** -self.exponents[i]

    def density(self, x: ArrayLike) -> np.ndarray:
        """abs(dλ/dx) = k_i·λ(x)/x [1/yr per unit of the IM], extrapolated as :meth:`rate`."""
        x = np.asarray(x, dtype=float)
        return self.exponents[self._segment(x)] * self.rate(x) / x

    def _segment(self, x: np.ndarray) -> np.ndarray:
        return np.clip(np.searchsorted(self.values, x, side="right") - 1, 0, self.values.size - 2)

    @classmethod
    def from_csv(
        cls, path: str | os.PathLike[str], *, site: int | None = None, im: str | None = None
    ) -> HazardCurve:
        """Read a hazard curve from a file: the CSV of the module notes, an OpenQuake-engine
        hazard-curve CSV or a USGS NSHM hazard JSON (told apart by their content; see
        :mod:`rocking.assessment.hazard_formats`). The word ``example`` reads
        :func:`example_hazard_path` (see :func:`hazard_path`).

        Parameters
        ----------
        path : str or Path
        site : int, optional
            OpenQuake: the site's row, 0 for the first (needed when the file has several).
        im : str, optional
            USGS: the IM to take when the file holds curves of several IMTs (e.g. ``"pga"``).

        Intensities come out in the IM's unit of ``rocking`` (OpenQuake's and the USGS's PGV
        in cm/s becomes m/s), rates in 1/yr; :attr:`origin` says what was found.
        """
        from . import hazard_formats

        path = hazard_path(path)
        text = read_text(path, "hazard file")  # once: the format is told from it, then parsed
        kind = hazard_formats.detect_format(path, text)
        if kind != "csv":
            read = (
                hazard_formats.read_openquake(path, site, text)
                if kind == "openquake"
                else hazard_formats.read_usgs(path, im, text)
            )
            return cls(read.im, read.values, read.rates, source=str(path), origin=read.origin)
        lines = csv_rows(path, "hazard file", text)
        if not lines:
            raise InputError(
                f"{path}: empty hazard file (need a header such as "
                "'pgv [m/s],annual_rate' and one row per intensity)"
            )
        measure = _header(path, *lines[0])
        if len(lines) < 3:
            raise InputError(f"{path}: a hazard curve needs at least 2 rows below the header")
        values: list[float] = []
        rates: list[float] = []
        for row, (lineno, cells) in enumerate(lines[1:], start=1):
            where = f"{path}: row {row} (line {lineno})"
            if len(cells) != 2:
                raise InputError(f"{where}: {len(cells)} value(s); expected 2 (IM, annual rate)")
            x, lam = (_number(where, what, c) for what, c in zip(("IM", "annual rate"), cells))
            if values and x <= values[-1]:
                raise InputError(
                    f"{where}: IM {x:g} is not above the previous row's {values[-1]:g} "
                    "(intensities must increase)"
                )
            if rates and lam >= rates[-1]:
                raise InputError(
                    f"{where}: annual rate {lam:g} is not below the previous row's "
                    f"{rates[-1]:g} (rates of exceedance must decrease)"
                )
            values.append(x)
            rates.append(lam)
        return cls(measure, np.array(values), np.array(rates), source=str(path))


def _header(path: Path, lineno: int, cells: list[str]) -> IntensityMeasure:
    where = f"{path}: line {lineno} (header)"
    if len(cells) != 2:
        raise InputError(
            f"{where}: expected 2 columns, the IM with its unit and annual_rate "
            f"(e.g. 'pgv [m/s],annual_rate'), got {', '.join(cells)}"
        )
    if not _BRACKET.match(cells[0]):
        raise InputError(
            f"{where}: the first column must name the IM and its unit, e.g. 'pgv [m/s]', "
            f"got {cells[0]!r}"
        )
    try:
        im = parse_im(cells[0])
    except InputError as exc:
        raise InputError(f"{where}: {exc}") from None
    m = _BRACKET.match(cells[1])
    name, unit = (m.group(1), m.group(2).strip()) if m else (cells[1], None)
    if name.strip().lower() not in _RATE_NAMES or (unit is not None and unit not in _RATE_UNITS):
        raise InputError(
            f"{where}: the second column must be annual_rate (optionally [1/yr]), got {cells[1]!r}"
        )
    return im


def _number(where: str, what: str, text: str) -> float:
    try:
        x = float(text)
    except ValueError:
        raise InputError(f"{where}: {what} {text!r} is not a number") from None
    if not math.isfinite(x) or x <= 0.0:
        raise InputError(f"{where}: {what} must be a finite number > 0, got {text!r}")
    return x


def check_hazard_im(hazard: HazardCurve, im: str | IntensityMeasure) -> IntensityMeasure:
    """Check that a hazard curve is of the intensity measure ``im`` of a fragility curve.

    Parameters
    ----------
    hazard : HazardCurve
    im : str or IntensityMeasure
        The fragility's IM (e.g. ``"pgv"``; ``"sa(1.0)"`` and ``"sa(1,0.05)"`` are the same).

    Returns
    -------
    IntensityMeasure
        The common IM.

    Raises
    ------
    InputError
        When they differ (the message names both and the hazard's file).
    """
    im = parse_im(im)
    if hazard.im != im:
        src = f" ({hazard.source})" if hazard.source else ""
        raise InputError(
            f"the hazard curve{src} is of {hazard.im.column}, the fragility of {im.column}: "
            "they must be of the same intensity measure"
        )
    return im


def _check_fragility_im(fragility: Any, hazard: HazardCurve, im: Any) -> None:
    """Refuse a fragility whose IM (its ``im``, else the argument ``im``) is not the hazard's
    or is not known."""
    own = getattr(fragility, "im", None)
    if own is not None and im is not None and _im_key(own) != _im_key(im):
        raise InputError(
            f"the fragility is of {_im_key(own)} but im={_im_key(im)!r} was given: they must "
            "be the same intensity measure"
        )
    im = own if own is not None else im
    if im is None:
        raise InputError(
            f"the fragility's intensity measure is not known and the hazard curve is of "
            f"{hazard.im.column}: give it, e.g. LognormalFit(median, beta, im="
            f"{hazard.im.name!r}) with the median in {hazard.im.unit}, or annual_rate(..., "
            f"im={hazard.im.name!r})"
        )
    if _im_key(im) == AGX:
        raise InputError(
            f"the fragility is of A_gx (the mean PGA of an ensemble [g]), which no site hazard "
            f"curve gives; the hazard curve is of {hazard.im.column}: fit the fragility against "
            f"{hazard.im.name} (fragility_analysis(..., im={hazard.im.name!r}))"
        )
    check_hazard_im(hazard, im)


def _im_key(im: Any) -> str:
    """``"agx"`` for the paper's A_gx, else the canonical name of :func:`rocking.parse_im`."""
    if isinstance(im, str) and im.strip().lower() == AGX:
        return AGX
    return parse_im(im).name


@dataclass(frozen=True, eq=False)
class RiskResult:
    """The mean annual rate of overturning and how it was obtained (:func:`annual_rate`).

    Attributes
    ----------
    annual_rate : float
        λ_f = ``table`` + ``upper_tail`` [1/yr].
    table : float
        The integral over the tabulated intensities [1/yr].
    upper_tail : float
        Above the last point, the last segment's power law extrapolated [1/yr] (included).
    upper_tail_bounds : tuple of float
        (P_f(x_n)·λ_n, λ_n): the upper tail for any hazard beyond the table [1/yr].
    lower_tail : float
        Below the first point, with the first segment's power law extrapolated to 0 [1/yr]:
        an estimate of what is left out (not included).
    p_first, p_last : float
        P_f at the first and the last tabulated intensity [-].
    error : float
        Sum of the error estimates of the quadratures [1/yr].
    fragility : object
        The fragility curve (anything with ``probability(x)``).
    hazard : HazardCurve
    """

    annual_rate: float
    table: float
    upper_tail: float
    upper_tail_bounds: tuple[float, float]
    lower_tail: float
    p_first: float
    p_last: float
    error: float
    fragility: Any
    hazard: HazardCurve

    def __repr__(self) -> str:
        return (
            f"RiskResult(annual_rate={self.annual_rate:.4g} /yr, return period "
            f"{self.return_period:.4g} yr, upper tail {self.upper_tail:.3g} /yr included, "
            f"lower tail {self.lower_tail:.3g} /yr left out; fragility {self.fragility!r}; "
            f"hazard {self.hazard!r})"
        )

    @property
    def return_period(self) -> float:
        """1/λ_f [yr]."""
        return 1.0 / self.annual_rate if self.annual_rate > 0.0 else math.inf

    def probability_in(self, years: ArrayLike) -> np.ndarray:
        """Probability of at least one overturning in ``years`` [yr] (≥ 0, array_like) for
        Poisson occurrences: 1 − exp(−λ_f·years) [-]."""
        t = np.asarray(years, dtype=float)
        if not np.all(np.isfinite(t)) or np.any(t < 0.0):
            raise InputError(f"years must be finite numbers >= 0, got {years!r}")
        return -portable.expm1(-self.annual_rate * t)

    def disaggregation(self, x: ArrayLike | None = None) -> tuple[np.ndarray, np.ndarray]:
        """Contribution of each intensity to the rate: dλ_f/dx = P_f(x)·abs(dλ/dx).

        Parameters
        ----------
        x : array_like, optional
            Intensities [the IM's unit], > 0 (default: 200 log-spaced over the table).

        Returns
        -------
        x, density : ndarray
            The intensities and dλ_f/dx [1/yr per unit of the IM]; its integral over x is the
            rate (and x·dλ_f/dx is the density over ln x, for a logarithmic axis).
        """
        if x is None:
            x = portable.geomspace(self.hazard.values[0], self.hazard.values[-1], 200)
        x = finite_array("x", x)
        if np.any(x <= 0.0):
            raise InputError("x must be > 0")
        return x, np.asarray(self.fragility.probability(x), dtype=float) * self.hazard.density(x)


def annual_rate(
    fragility: Any,
    hazard: HazardCurve | str | os.PathLike[str],
    *,
    im: str | IntensityMeasure | None = None,
) -> RiskResult:
    """Mean annual rate of overturning: λ_f = ∫ P_f(x)·abs(dλ/dx) dx (module notes).

    Parameters
    ----------
    fragility : LognormalFit, FragilityFit or any object with ``probability(x)``
        P_f(x) [-] for intensities x in the hazard's IM and unit (a median in m/s for a PGV
        hazard), not decreasing. Its ``im`` (a :class:`~rocking.LognormalFit`'s) must be the
        hazard's IM.
    hazard : HazardCurve, str or Path
        The hazard curve, or a CSV file of one (or ``"example"``; :meth:`HazardCurve.from_csv`).
    im : str or IntensityMeasure, optional
        The fragility's IM, for a fragility that does not carry one (``im`` None or absent);
        one that does must agree with it.

    Raises
    ------
    InputError
        When the fragility's IM is not the hazard's (the message names both), or is not known
        (neither the fragility nor ``im`` gives it): a curve against A_gx, the mean PGA of an
        ensemble, is refused, as no site hazard curve gives A_gx.

    Returns
    -------
    RiskResult
        The rate [1/yr] with its tails, ``probability_in(years)`` and ``disaggregation()``.
    """
    import scipy.integrate

    if not isinstance(hazard, HazardCurve):
        if not isinstance(hazard, (str, Path)):
            raise InputError(
                f"hazard must be a rocking.HazardCurve or a CSV path, got {type(hazard).__name__}"
            )
        hazard = HazardCurve.from_csv(hazard)
    if not callable(getattr(fragility, "probability", None)):
        raise InputError(
            "fragility must have a probability(x) method (e.g. a rocking.LognormalFit), got "
            f"{type(fragility).__name__}"
        )
    _check_fragility_im(fragility, hazard, im)
    u = portable.log(hazard.values)
    lam, k = hazard.rates, hazard.exponents

    def prob(ui: float) -> float:
        return float(np.asarray(fragility.probability(portable.exp(ui))).reshape(-1)[0])

    def piece(i: int, lo: float, hi: float) -> tuple[float, float]:
        """∫ P_f(e^u)·k_i·λ_i·exp(−k_i·(u − u_i)) du over [lo, hi] of segment i's power law."""

        def f(ui: float) -> float:
            p = prob(ui)
            return 0.0 if p == 0.0 else p * k[i] * lam[i] * math.exp(-k[i] * (ui - u[i]))

        val, err = scipy.integrate.quad(f, lo, hi, epsabs=0.0, epsrel=1e-10, limit=200)
        return float(val), float(err)

    with np.errstate(divide="ignore", over="ignore"):  # P_f(e^u) far below the table
        pieces = [piece(i, u[i], u[i + 1]) for i in range(u.size - 1)]
        upper, err_up = piece(u.size - 2, u[-1], math.inf)
        try:
            lower = piece(0, -math.inf, u[0])[0]
        except OverflowError:  # the fragility decays more slowly than the power law grows
            lower = math.inf
    table = math.fsum(v for v, _ in pieces)
    p_first, p_last = prob(u[0]), prob(u[-1])
    return RiskResult(
        annual_rate=table + upper,
        table=table,
        upper_tail=upper,
        upper_tail_bounds=(p_last * lam[-1], float(lam[-1])),
        lower_tail=lower,
        p_first=p_first,
        p_last=p_last,
        error=math.fsum(e for _, e in pieces) + err_up,
        fragility=fragility,
        hazard=hazard,
    )
