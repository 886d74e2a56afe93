"""Target (design) spectra of pseudo-acceleration: :class:`RG160` (US AEC Regulatory Guide 1.60,
horizontal) and :class:`TabulatedSpectrum` (a table, e.g. read from CSV).

Target spectra give PSA in g, PSV in m/s and SD in m. Between table points they are straight lines
on log-log axes; below the lowest point the spectral displacement is constant (PSA ∝ f²) and above
the highest point the PSA is constant (for RG 1.60 that constant is the ZPA).
"""

from __future__ import annotations

import math
import os
import re
from abc import ABC, abstractmethod
from dataclasses import dataclass
from pathlib import Path

import numpy as np
from numpy.typing import ArrayLike

from ..core import portable
from ..core.checks import finite_array, in_range, positive
from ..core.files import csv_rows
from ..defaults import G
from ..errors import InputError
from .units import unit_factor


def _freqs(freqs_hz) -> tuple[np.ndarray, tuple]:
    """Frequencies [Hz] as a flat float array (all finite, > 0) and the caller's shape."""
    shape = np.shape(freqs_hz)
    f = finite_array("freqs_hz", np.ravel(freqs_hz), ndim=(1,))
    if (f <= 0.0).any():
        raise InputError(f"freqs_hz must be > 0 [Hz], got {f[f <= 0.0][0]!r}")
    return f, shape


def _loglog(f: np.ndarray, knots_f: np.ndarray, knots_psa: np.ndarray) -> np.ndarray:
    """PSA at ``f`` from knots (increasing ``knots_f``): straight lines on log-log axes inside,
    constant SD (PSA ∝ f²) below the first knot and constant PSA above the last one."""
    psa = portable.exp(np.interp(portable.log(f), portable.log(knots_f), portable.log(knots_psa)))
    low = f < knots_f[0]
    psa[low] = knots_psa[0] * (f[low] / knots_f[0]) ** 2
    return psa


class TargetSpectrum(ABC):
    """A target (design) spectrum of pseudo-acceleration.

    Subclasses define :meth:`psa` and :meth:`scaled` and have the attributes ``name`` (a label)
    and ``damping`` (the oscillator damping ratio the spectrum is meant for [-]).
    """

    # (subclasses made from parameters compute their name: a read-only property overriding the
    # attribute, which mypy reports as [override])
    name: str
    damping: float

    @abstractmethod
    def psa(self, freqs_hz: ArrayLike) -> np.ndarray:
        """Pseudo-spectral acceleration [g] at frequencies ``freqs_hz`` [Hz] (same shape)."""

    @abstractmethod
    def scaled(self, factor: float) -> TargetSpectrum:
        """The spectrum with every ordinate multiplied by ``factor`` [-] (> 0)."""

    def __call__(self, freqs_hz) -> np.ndarray:
        """Same as :meth:`psa` [g], so a spectrum can stand where a function of frequency is
        expected."""
        return self.psa(freqs_hz)

    def psv(self, freqs_hz: ArrayLike) -> np.ndarray:
        """Pseudo-spectral velocity PSV = PSA·g/ω [m/s] at ``freqs_hz`` [Hz]."""
        f, shape = _freqs(freqs_hz)
        return (self.psa(f) * G / (2.0 * math.pi * f)).reshape(shape)

    def sd(self, freqs_hz: ArrayLike) -> np.ndarray:
        """Spectral displacement SD = PSA·g/ω² [m] at ``freqs_hz`` [Hz]."""
        f, shape = _freqs(freqs_hz)
        return (self.psa(f) * G / (2.0 * math.pi * f) ** 2).reshape(shape)


#: RG 1.60 Table 1 (horizontal): damping ratios [-] and amplification factors at the control
#: points B (9 Hz) and C (2.5 Hz) (of the ZPA) and D (0.25 Hz, of the peak ground displacement).
#: At A (33 Hz) the factor is 1 for every damping.
RG160_DAMPINGS = (0.005, 0.02, 0.05, 0.07, 0.10)
RG160_FACTORS = {  # damping: (B, C, D)
    0.005: (4.96, 5.95, 3.20),
    0.02: (3.54, 4.25, 2.50),
    0.05: (2.61, 3.13, 2.05),
    0.07: (2.27, 2.72, 1.88),
    0.10: (1.90, 2.28, 1.70),
}
#: Control frequencies A, B, C, D [Hz].
RG160_FREQS = {"A": 33.0, "B": 9.0, "C": 2.5, "D": 0.25}
#: Peak ground displacement per 1 g of ZPA: 36 in [m].
RG160_PGD_PER_G = 36 * 0.0254


@dataclass(frozen=True)
class RG160(TargetSpectrum):
    """US AEC Regulatory Guide 1.60 (1973) horizontal design spectrum.

    Control points (reference.md §3): PSA = ZPA at A (33 Hz), PSA = B·ZPA at 9 Hz and C·ZPA at
    2.5 Hz, and SD = D·PGD at D (0.25 Hz), where the peak ground displacement PGD is 36 in
    (0.9144 m) per g of ZPA. Straight lines on log-log axes between the control points, constant SD
    below
    0.25 Hz, PSA = ZPA above 33 Hz.

    Between the tabulated dampings (0.5, 2, 5, 7, 10 %) the factors B, C and D are interpolated
    linearly in ln(damping) — the tabulated factors are close to linear in ln(damping), and the
    rule reproduces every tabulated value exactly. Dampings outside [0.5 %, 10 %] are refused.

    Parameters
    ----------
    damping : float
        Damping ratio [-], in [0.005, 0.10].
    pga : float
        Zero-period acceleration (peak ground acceleration) [g], > 0.
    """

    damping: float = 0.05
    pga: float = 1.0

    def __post_init__(self):
        object.__setattr__(
            self,
            "damping",
            in_range("damping", self.damping, RG160_DAMPINGS[0], RG160_DAMPINGS[-1], unit="-"),
        )
        object.__setattr__(self, "pga", positive("pga", self.pga, "g"))

    @property
    def name(self) -> str:  # type: ignore[override]
        return f"RG 1.60 ({100 * self.damping:g} %, {self.pga:g} g)"

    def factors(self) -> tuple[float, float, float]:
        """Amplification factors (B, C, D) [-] at this damping (see class notes)."""
        x = portable.log(RG160_DAMPINGS)
        table = np.array([RG160_FACTORS[z] for z in RG160_DAMPINGS])
        b, c, d = (float(np.interp(math.log(self.damping), x, col)) for col in table.T)
        return b, c, d

    def control_points(self) -> tuple[np.ndarray, np.ndarray]:
        """Frequencies of D, C, B, A [Hz] (increasing) and the PSA there [g]."""
        b, c, d = self.factors()
        f = np.array([RG160_FREQS[k] for k in "DCBA"])
        sd_d = d * RG160_PGD_PER_G * self.pga  # [m]
        psa_d = sd_d * (2.0 * math.pi * f[0]) ** 2 / G  # [g]
        return f, np.array([psa_d, c * self.pga, b * self.pga, self.pga])

    def psa(self, freqs_hz: ArrayLike) -> np.ndarray:
        """PSA [g] at ``freqs_hz`` [Hz] (any shape, every value finite and > 0)."""
        f, shape = _freqs(freqs_hz)
        return _loglog(f, *self.control_points()).reshape(shape)

    def scaled(self, factor: float) -> RG160:
        """RG 1.60 spectrum for ZPA ``pga·factor`` [g]."""
        return RG160(self.damping, self.pga * positive("factor", factor, "-"))


def rg160(freqs_hz: ArrayLike, damping: float = 0.05, pga: float = 1.0) -> np.ndarray:
    """RG 1.60 horizontal spectrum: PSA [g] at ``freqs_hz`` [Hz] for ``damping`` [-] and ZPA
    ``pga`` [g]. See :class:`RG160`."""
    return RG160(damping, pga).psa(freqs_hz)


def _check_table(
    x: np.ndarray,
    psa: np.ndarray,
    where: list[str],
    source: str,
    xname: str = "frequency",
    xunit: str = "Hz",
    yname: str = "PSA",
    yunit: str = "g",
) -> None:
    """Validate a spectrum table of abscissae ``x`` (frequencies or periods) and ordinates
    (PSA [g] unless ``yname``/``yunit`` say otherwise).

    ``where[i]`` names row i and ``source`` the whole table in error messages.
    """
    if len(x) < 2:
        raise InputError(f"{source}: a tabulated spectrum needs at least 2 rows, got {len(x)}")
    for name, values, unit in ((xname, x, xunit), (yname, psa, yunit)):
        bad = np.flatnonzero(~np.isfinite(values) | (values <= 0.0))
        if bad.size:
            i = bad[0]
            raise InputError(
                f"{where[i]}: {name} must be a finite number > 0 [{unit}], got {values[i]!r}"
            )
    order = np.argsort(x, kind="stable")
    dup = np.flatnonzero(np.diff(x[order]) == 0.0)
    if dup.size:
        i, j = sorted(order[dup[0] : dup[0] + 2])
        raise InputError(f"{where[j]}: {xname} {x[j]:g} {xunit} repeats that of {where[i]}")


@dataclass(frozen=True, eq=False)
class TabulatedSpectrum(TargetSpectrum):
    """A target spectrum given as a table of PSA [g] against frequency [Hz].

    Rows may come in any order (they are sorted by frequency); frequencies must be distinct.
    Between rows: straight lines on log-log axes. Below the lowest frequency: constant spectral
    displacement (PSA ∝ f²); above the highest: constant PSA (the last row's value).

    Parameters
    ----------
    freqs_hz : array_like
        Frequencies [Hz], finite, > 0, distinct; at least 2.
    psa_g : array_like
        PSA [g] at those frequencies, finite, > 0.
    damping : float
        Damping ratio the spectrum is meant for [-], in (0, 1).
    name : str
        Label.
    """

    freqs_hz: np.ndarray
    psa_g: np.ndarray
    damping: float = 0.05
    name: str = "tabulated"

    def __post_init__(self):
        f = np.ravel(np.asarray(self.freqs_hz, dtype=np.float64))
        a = np.ravel(np.asarray(self.psa_g, dtype=np.float64))
        if f.size != a.size:
            raise InputError(
                f"freqs_hz and psa_g must have the same length, got {f.size} and {a.size}"
            )
        _check_table(f, a, [f"row {i}" for i in range(f.size)], "freqs_hz")
        order = np.argsort(f)
        object.__setattr__(self, "freqs_hz", f[order])
        object.__setattr__(self, "psa_g", a[order])
        object.__setattr__(
            self,
            "damping",
            in_range("damping", self.damping, 0.0, 1.0, lo_open=True, hi_open=True, unit="-"),
        )

    @classmethod
    def from_csv(
        cls, path: str | os.PathLike[str], damping: float = 0.05, select: str | None = None
    ) -> TabulatedSpectrum:
        """Read a spectrum from a CSV file with a header row; columns are found by their header.

        * Abscissa: the first column whose header names a frequency [Hz] ("freq", "Hz") or a
          period [s] ("period", "T", or the unit s/sec in brackets, e.g. "T (s)").
        * Ordinates: PSA ("psa", "sa" or "acceleration"; in g unless a unit in brackets says
          otherwise: any unit of :data:`rocking.motions.units.ACCELERATION_UNITS`, e.g.
          "PSA [m/s2]", "Sa (gal)"; any other is refused) or PSV ("psv", "sv" or "velocity",
          with its unit cm/s or m/s stated, e.g. "psv_cm_s", "PSV [m/s]"), converted to
          PSA = PSV·2πf/g. Other columns (SD, notes) are ignored.
        * Several spectra in one file: one per ordinate column that names a location besides
          quantity and unit (``psv_floor_1_cm_s`` is "floor 1", as ``rocking frame spectra
          --csv`` writes), and, where a label column ("record", "name", "label", "location")
          is present, one per label value (as ``rocking spectrum --csv`` writes). Where one
          spectrum has both PSA and PSV, PSA is used.

        Blank lines and lines starting with ``#`` are skipped.

        Parameters
        ----------
        path : str or Path
            CSV file.
        damping : float
            Damping ratio of the spectrum [-].
        select : str, optional
            Name of the spectrum to read from a file that holds several: a label value, a
            location, or both separated by a space (case, spaces, "_" and "-" do not matter).
            Needed when the file holds more than one; the error lists the choices.
        """
        path = Path(path)
        rows = csv_rows(path, "spectrum file")
        if not rows:
            raise InputError(f"{path}: empty spectrum file")
        head_line, head = rows[0]
        cols = _SpectrumColumns(head, f"{path}: line {head_line}")
        spectra = cols.spectra([cells for _, cells in rows[1:]])
        key = _select_spectrum(spectra, select, path)
        label, group = key
        xcol = cols.x
        ycol, quantity, factor = cols.groups[group]
        needed = max(xcol, ycol, -1 if cols.label is None else cols.label) + 1
        xs: list[float] = []
        ys: list[float] = []
        where: list[str] = []
        for lineno, cells in rows[1:]:
            if len(cells) < needed:
                raise InputError(f"{path}: line {lineno}: need {needed} values, got {len(cells)}")
            if cols.label is not None and cells[cols.label] != label:
                continue
            for column, out in ((xcol, xs), (ycol, ys)):
                try:
                    out.append(float(cells[column]))
                except ValueError:
                    raise InputError(
                        f"{path}: line {lineno}: not a number: {cells[column]!r}"
                    ) from None
            where.append(f"{path}: line {lineno}")
        x, a = np.array(xs), np.array(ys)
        xname = ("period", "s") if cols.is_period else ("frequency", "Hz")
        _check_table(x, a, where, str(path), *xname, quantity.upper(), head[ycol])
        f = 1.0 / x if cols.is_period else x
        a = a * factor  # PSA [g] or PSV [m/s]
        if quantity == "psv":  # PSA = ω·PSV [g]
            a = a * 2.0 * math.pi * f / G
        name = spectra[key]
        return cls(f, a, damping=damping, name=path.stem if not name else f"{path.stem}:{name}")

    def psa(self, freqs_hz: ArrayLike) -> np.ndarray:
        """PSA [g] at ``freqs_hz`` [Hz] (any shape, every value finite and > 0)."""
        f, shape = _freqs(freqs_hz)
        return _loglog(f, self.freqs_hz, self.psa_g).reshape(shape)

    def scaled(self, factor: float) -> TabulatedSpectrum:
        """The table with every PSA multiplied by ``factor`` [-] (> 0)."""
        return TabulatedSpectrum(
            self.freqs_hz,
            self.psa_g * positive("factor", factor, "-"),
            damping=self.damping,
            name=self.name,
        )


def _is_frequency(header: str) -> bool:
    h = header.strip().lower()
    return "freq" in h or "hz" in h


def _is_period(header: str) -> bool:
    h = header.strip().lower()
    return (
        "period" in h
        or re.fullmatch(r"t\b.*", h) is not None
        or re.search(r"[\[(]\s*(s|sec)\s*[\])]", h) is not None
    )


#: Header words of the ordinates: the quantity they name.
_QUANTITY_WORDS = {
    "psa": "psa",
    "sa": "psa",
    "acceleration": "psa",
    "psv": "psv",
    "sv": "psv",
    "velocity": "psv",
}
#: Words of an ordinate header that name neither quantity, unit nor location.
_FILLER_WORDS = {"pseudo", "spectral", "spectrum", "response", "mean"}
#: Units of PSV (header words in order) and their factor to m/s.
_PSV_UNITS = ((("cm", "s"), 0.01), (("m", "s"), 1.0))
#: Units of PSV in brackets ("PSV [cm/s]") and their factor to m/s.
_PSV_UNIT_NAMES = {"cm/s": 0.01, "cm/sec": 0.01, "m/s": 1.0, "m/sec": 1.0}
#: The unit of a column header, in brackets: "PSA [g]", "PSV (cm/s)".
_BRACKETED = re.compile(r"[\[(]([^\])]*)[\])]")
#: Headers of a column that names the spectrum of each row.
_LABEL_HEADERS = {"record", "name", "label", "location"}


def _words(header: str) -> list[str]:
    return re.findall(r"[a-z]+|\d+", header.lower())


def _take(words: list[str], unit: tuple[str, ...]) -> list[str] | None:
    """``words`` without the first occurrence of the word sequence ``unit`` (None: absent)."""
    n = len(unit)
    for i in range(len(words) - n + 1):
        if tuple(words[i : i + n]) == unit:
            return words[:i] + words[i + n :]
    return None


class _SpectrumColumns:
    """Meaning of the columns of a spectrum CSV file, from its header (see
    :meth:`TabulatedSpectrum.from_csv`).

    Attributes: ``x`` (index of the abscissa), ``is_period``, ``label`` (index of the label
    column or None) and ``groups``: location name -> (column index, quantity "psa" or "psv",
    factor to g of PSA or to m/s of PSV), PSA preferred where a location has both.
    """

    def __init__(self, head: list[str], where: str):
        x: int | None = None
        self.is_period = False
        self.label: int | None = None
        found: dict[str, dict[str, tuple[int, str, float]]] = {}
        for i, header in enumerate(head):
            unit = _BRACKETED.search(header)
            words = _words(header if unit is None else _BRACKETED.sub(" ", header))
            quantity = next((_QUANTITY_WORDS[w] for w in words if w in _QUANTITY_WORDS), None)
            if quantity is not None:
                words = [w for w in words if w not in _QUANTITY_WORDS and w not in _FILLER_WORDS]
                column = f"{where}: column {header!r}"
                if quantity == "psa" and unit is not None:  # any unit of acceleration, to g
                    factor = unit_factor(unit[1], column) / G
                elif quantity == "psa":
                    rest = _take(words, ("g",))
                    if rest is None and _take(words, ("s",)) is not None:
                        raise InputError(f"{column}: state the unit of PSA, e.g. 'PSA [g]'")
                    factor, words = 1.0, words if rest is None else rest
                elif unit is not None:
                    psv_unit = re.sub(r"\s+", "", unit[1].lower())
                    if psv_unit not in _PSV_UNIT_NAMES:
                        raise InputError(
                            f"{column}: unit {unit[1].strip()!r} of PSV is not understood; "
                            "use cm/s or m/s"
                        )
                    factor = _PSV_UNIT_NAMES[psv_unit]
                else:
                    found_unit, rest = next(
                        ((k, r) for u, k in _PSV_UNITS if (r := _take(words, u)) is not None),
                        (None, None),
                    )
                    if found_unit is None or rest is None:
                        raise InputError(
                            f"{column}: state the unit of PSV, cm/s or m/s (e.g. 'PSV [cm/s]')"
                        )
                    factor, words = found_unit, rest
                found.setdefault(" ".join(words), {})[quantity] = (i, quantity, factor)
            elif x is None and (_is_frequency(header) or _is_period(header)):
                x, self.is_period = i, not _is_frequency(header)
            elif self.label is None and header.strip().lower() in _LABEL_HEADERS:
                self.label = i
        if x is None:
            raise InputError(
                f"{where}: first column header {head[0]!r} names neither a "
                "frequency ('freq', 'Hz') nor a period ('period', 'T', '(s)'), nor "
                f"does any other ({','.join(head)})"
            )
        if not found:
            raise InputError(
                f"{where}: need a column of PSA [g] or PSV [cm/s or m/s] (headers "
                f"such as 'psa_g', 'PSV [cm/s]'), got {','.join(head)!r}"
            )
        self.x: int = x
        self.groups: dict[str, tuple[int, str, float]] = {
            loc: q["psa"] if "psa" in q else q["psv"] for loc, q in found.items()
        }

    def spectra(self, data: list[list[str]]) -> dict[tuple[str, str], str]:
        """(label, location) -> display name of every spectrum in the file, in file order."""
        labels = (
            [""]
            if self.label is None
            else list(dict.fromkeys(cells[self.label] for cells in data if len(cells) > self.label))
        )
        return {
            (lab, loc): " ".join(p for p in (lab, loc) if p)
            for lab in labels
            for loc in self.groups
        }


def _normalised(name: str) -> str:
    return re.sub(r"[\s_\-]+", "", name.lower())


def _select_spectrum(spectra: dict, select: str | None, path: Path):
    """Key of the spectrum named ``select`` (or of the only one)."""
    names = ", ".join(repr(n) for n in spectra.values() if n)
    if select is None:
        if len(spectra) == 1:
            return next(iter(spectra))
        raise InputError(
            f"{path}: holds {len(spectra)} spectra ({names}): choose one, "
            f"e.g. {path}:{next(iter(spectra.values()))}"
        )
    match = [k for k, n in spectra.items() if _normalised(n) == _normalised(select)]
    if not match:
        match = [k for k in spectra if _normalised(select) in map(_normalised, k)]
    if len(match) != 1:
        raise InputError(
            f"{path}: no single spectrum named {select!r}; the file holds "
            f"{names or 'one unnamed spectrum'}"
        )
    return match[0]


@dataclass(frozen=True, eq=False)
class StoredTarget(TargetSpectrum):
    """The target a simulated ensemble was fitted to, known only at the frequencies it was fitted
    at (kept in the ensemble's metadata; :meth:`rocking.Ensemble.target_spectrum`).

    Parameters
    ----------
    name : str
        Label.
    freqs_hz : sequence of float
        The fitted frequencies [Hz], increasing.
    values : sequence of float
        PSA [g] at those frequencies.
    damping : float
        Damping ratio [-].
    """

    name: str
    freqs_hz: tuple
    values: tuple
    damping: float

    def psa(self, freqs_hz: ArrayLike) -> np.ndarray:
        """PSA [g] at ``freqs_hz`` [Hz], which must be among the stored frequencies."""
        known = np.asarray(self.freqs_hz)
        f = np.asarray(freqs_hz, dtype=float)
        idx = np.clip(np.searchsorted(known, f), 0, known.size - 1)
        if not np.array_equal(known[idx], f):
            raise InputError(
                "the stored target spectrum is known only at the stored frequencies:"
                " pass target= when changing n_freq, fmin or fmax"
            )
        return np.asarray(self.values)[idx]

    def scaled(self, factor: float) -> StoredTarget:
        """The stored spectrum with every PSA multiplied by ``factor`` [-] (> 0)."""
        factor = positive("factor", factor, "-")
        return StoredTarget(
            f"{self.name} × {factor:.4g}",
            self.freqs_hz,
            tuple(v * factor for v in self.values),
            self.damping,
        )
