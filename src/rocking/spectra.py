"""Response spectra of ground motions and target (design) spectra.

* :func:`response_spectrum` — SD, PSV and PSA of damped single-degree-of-freedom oscillators under
  a ground acceleration (one motion or a stack), by the exact piecewise-linear recurrence of
  Nigam & Jennings (1969).
* :class:`TargetSpectrum` — base class of target spectra; :class:`RG160` (US AEC Regulatory
  Guide 1.60, horizontal) and :class:`TabulatedSpectrum` (a table, e.g. read from CSV).

Target spectra give PSA in g, PSV in m/s and SD in m. Between table points they are straight lines
on log-log axes; below the lowest point the spectral displacement is constant (PSA ∝ f²) and above
the highest point the PSA is constant (for RG 1.60 that constant is the ZPA).
"""

from __future__ import annotations

import csv
import math
import re
from abc import ABC, abstractmethod
from dataclasses import dataclass
from pathlib import Path

import numpy as np
import scipy.linalg
from threadpoolctl import threadpool_limits

from ._numba import kernel, parallel_kernel, prange
from ._validate import finite_array, in_range, positive
from .body import G
from .errors import InputError

# --------------------------------------------------------------------------- target spectra


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
    psa = np.exp(np.interp(np.log(f), np.log(knots_f), np.log(knots_psa)))
    low = f < knots_f[0]
    psa[low] = knots_psa[0] * (f[low] / knots_f[0]) ** 2
    return psa


class TargetSpectrum(ABC):
    """A target (design) spectrum of pseudo-acceleration.

    Subclasses define :meth:`psa` and :meth:`scaled` and have the attributes ``name`` (a label)
    and ``damping`` (the oscillator damping ratio the spectrum is meant for [-]).
    """

    name: str
    damping: float

    @abstractmethod
    def psa(self, freqs_hz) -> np.ndarray:
        """Pseudo-spectral acceleration [g] at frequencies ``freqs_hz`` [Hz] (same shape)."""

    @abstractmethod
    def scaled(self, factor: float) -> "TargetSpectrum":
        """The spectrum with every ordinate multiplied by ``factor`` [-] (> 0)."""

    def __call__(self, freqs_hz) -> np.ndarray:
        """Same as :meth:`psa` [g], so a spectrum can stand where a function of frequency is
        expected."""
        return self.psa(freqs_hz)

    def psv(self, freqs_hz) -> np.ndarray:
        """Pseudo-spectral velocity PSV = PSA·g/ω [m/s] at ``freqs_hz`` [Hz]."""
        f, shape = _freqs(freqs_hz)
        return (self.psa(f) * G / (2.0 * math.pi * f)).reshape(shape)

    def sd(self, freqs_hz) -> np.ndarray:
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
    (0.9144 m) per g of ZPA. Straight lines on log-log axes between the control points, constant SD below
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
        object.__setattr__(self, "damping", in_range(
            "damping", self.damping, RG160_DAMPINGS[0], RG160_DAMPINGS[-1], unit="-"))
        object.__setattr__(self, "pga", positive("pga", self.pga, "g"))

    @property
    def name(self) -> str:
        return f"RG 1.60 ({100 * self.damping:g} %, {self.pga:g} g)"

    def factors(self) -> tuple[float, float, float]:
        """Amplification factors (B, C, D) [-] at this damping (see class notes)."""
        x = np.log(RG160_DAMPINGS)
        table = np.array([RG160_FACTORS[z] for z in RG160_DAMPINGS])
        return tuple(float(np.interp(math.log(self.damping), x, col)) for col in table.T)

    def control_points(self) -> tuple[np.ndarray, np.ndarray]:
        """Frequencies of D, C, B, A [Hz] (increasing) and the PSA there [g]."""
        b, c, d = self.factors()
        f = np.array([RG160_FREQS[k] for k in "DCBA"])
        sd_d = d * RG160_PGD_PER_G * self.pga  # [m]
        psa_d = sd_d * (2.0 * math.pi * f[0]) ** 2 / G  # [g]
        return f, np.array([psa_d, c * self.pga, b * self.pga, self.pga])

    def psa(self, freqs_hz) -> np.ndarray:
        """PSA [g] at ``freqs_hz`` [Hz] (any shape, every value finite and > 0)."""
        f, shape = _freqs(freqs_hz)
        return _loglog(f, *self.control_points()).reshape(shape)

    def scaled(self, factor: float) -> "RG160":
        """RG 1.60 spectrum for ZPA ``pga·factor`` [g]."""
        return RG160(self.damping, self.pga * positive("factor", factor, "-"))


def rg160(freqs_hz, damping: float = 0.05, pga: float = 1.0) -> np.ndarray:
    """RG 1.60 horizontal spectrum: PSA [g] at ``freqs_hz`` [Hz] for ``damping`` [-] and ZPA
    ``pga`` [g]. See :class:`RG160`."""
    return RG160(damping, pga).psa(freqs_hz)


def _check_table(x: np.ndarray, psa: np.ndarray, where: list[str], source: str,
                 xname: str = "frequency", xunit: str = "Hz", yname: str = "PSA",
                 yunit: str = "g") -> None:
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
            raise InputError(f"{where[i]}: {name} must be a finite number > 0 [{unit}], "
                             f"got {values[i]!r}")
    order = np.argsort(x, kind="stable")
    dup = np.flatnonzero(np.diff(x[order]) == 0.0)
    if dup.size:
        i, j = sorted(order[dup[0]:dup[0] + 2])
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
            raise InputError(f"freqs_hz and psa_g must have the same length, got {f.size} "
                             f"and {a.size}")
        _check_table(f, a, [f"row {i}" for i in range(f.size)], "freqs_hz")
        order = np.argsort(f)
        object.__setattr__(self, "freqs_hz", f[order])
        object.__setattr__(self, "psa_g", a[order])
        object.__setattr__(self, "damping", in_range(
            "damping", self.damping, 0.0, 1.0, lo_open=True, hi_open=True, unit="-"))

    @classmethod
    def from_csv(cls, path, damping: float = 0.05, select: str | None = None
                 ) -> "TabulatedSpectrum":
        """Read a spectrum from a CSV file with a header row; columns are found by their header.

        * Abscissa: the first column whose header names a frequency [Hz] ("freq", "Hz") or a
          period [s] ("period", "T", or the unit s/sec in brackets, e.g. "T (s)").
        * Ordinates: PSA [g] ("psa", "sa" or "acceleration"; a stated unit must be g) or PSV
          ("psv", "sv" or "velocity", with its unit cm/s or m/s stated, e.g. "psv_cm_s",
          "PSV [m/s]"), converted to PSA = PSV·2πf/g. Other columns (SD, notes) are ignored.
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
        rows: list[tuple[int, list[str]]] = []
        with open(path, newline="", encoding="utf-8-sig") as fh:
            for lineno, cells in enumerate(csv.reader(fh), start=1):
                cells = [c.strip() for c in cells]
                if any(cells) and not cells[0].startswith("#"):
                    rows.append((lineno, cells))
        if not rows:
            raise InputError(f"{path}: empty spectrum file")
        head_line, head = rows[0]
        cols = _SpectrumColumns(head, f"{path}: line {head_line}")
        spectra = cols.spectra([cells for _, cells in rows[1:]])
        key = _select_spectrum(spectra, select, path)
        label, group = key
        xcol, ycol, factor = cols.x, *cols.groups[group]
        needed = max(xcol, ycol, -1 if cols.label is None else cols.label) + 1
        x, a, where = [], [], []
        for lineno, cells in rows[1:]:
            if len(cells) < needed:
                raise InputError(f"{path}: line {lineno}: need {needed} values, got {len(cells)}")
            if cols.label is not None and cells[cols.label] != label:
                continue
            for column, out in ((xcol, x), (ycol, a)):
                try:
                    out.append(float(cells[column]))
                except ValueError:
                    raise InputError(f"{path}: line {lineno}: not a number: "
                                     f"{cells[column]!r}") from None
            where.append(f"{path}: line {lineno}")
        x, a = np.array(x), np.array(a)
        xname = ("period", "s") if cols.is_period else ("frequency", "Hz")
        yname = ("PSA", "g") if factor is None else ("PSV", head[ycol])
        _check_table(x, a, where, str(path), *xname, *yname)
        f = 1.0 / x if cols.is_period else x
        if factor is not None:  # PSV [unit] -> PSA [g]: PSA = ω·PSV
            a = a * factor * 2.0 * math.pi * f / G
        name = spectra[key]
        return cls(f, a, damping=damping,
                   name=path.stem if not name else f"{path.stem}:{name}")

    def psa(self, freqs_hz) -> np.ndarray:
        """PSA [g] at ``freqs_hz`` [Hz] (any shape, every value finite and > 0)."""
        f, shape = _freqs(freqs_hz)
        return _loglog(f, self.freqs_hz, self.psa_g).reshape(shape)

    def scaled(self, factor: float) -> "TabulatedSpectrum":
        """The table with every PSA multiplied by ``factor`` [-] (> 0)."""
        return TabulatedSpectrum(self.freqs_hz, self.psa_g * positive("factor", factor, "-"),
                                 damping=self.damping, name=self.name)


def _is_frequency(header: str) -> bool:
    h = header.strip().lower()
    return "freq" in h or "hz" in h


def _is_period(header: str) -> bool:
    h = header.strip().lower()
    return ("period" in h or re.fullmatch(r"t\b.*", h) is not None
            or re.search(r"[\[(]\s*(s|sec)\s*[\])]", h) is not None)


#: Header words of the ordinates: the quantity they name.
_QUANTITY_WORDS = {"psa": "psa", "sa": "psa", "acceleration": "psa", "psv": "psv", "sv": "psv",
                   "velocity": "psv"}
#: Words of an ordinate header that name neither quantity, unit nor location.
_FILLER_WORDS = {"pseudo", "spectral", "spectrum", "response", "mean"}
#: Units of PSV (header words in order) and their factor to m/s.
_PSV_UNITS = ((("cm", "s"), 0.01), (("m", "s"), 1.0))
#: Headers of a column that names the spectrum of each row.
_LABEL_HEADERS = {"record", "name", "label", "location"}


def _words(header: str) -> list[str]:
    return re.findall(r"[a-z]+|\d+", header.lower())


def _take(words: list[str], unit: tuple[str, ...]) -> list[str] | None:
    """``words`` without the first occurrence of the word sequence ``unit`` (None: absent)."""
    n = len(unit)
    for i in range(len(words) - n + 1):
        if tuple(words[i:i + n]) == unit:
            return words[:i] + words[i + n:]
    return None


class _SpectrumColumns:
    """Meaning of the columns of a spectrum CSV file, from its header (see
    :meth:`TabulatedSpectrum.from_csv`).

    Attributes: ``x`` (index of the abscissa), ``is_period``, ``label`` (index of the label
    column or None) and ``groups``: location name -> (column index, factor to m/s for PSV or
    None for PSA [g]), PSA preferred where a location has both.
    """

    def __init__(self, head: list[str], where: str):
        self.x, self.is_period, self.label = None, False, None
        found: dict[str, dict[str, tuple[int, float | None]]] = {}
        for i, header in enumerate(head):
            words = _words(header)
            quantity = next((_QUANTITY_WORDS[w] for w in words if w in _QUANTITY_WORDS), None)
            if quantity is not None:
                words = [w for w in words if w not in _QUANTITY_WORDS and w not in _FILLER_WORDS]
                if quantity == "psa":
                    rest = _take(words, ("g",))
                    if rest is None and _take(words, ("s",)) is not None:
                        raise InputError(f"{where}: column {header!r}: PSA must be in g")
                    factor, words = None, words if rest is None else rest
                else:
                    factor, rest = next(((k, r) for unit, k in _PSV_UNITS
                                         if (r := _take(words, unit)) is not None), (None, None))
                    if factor is None:
                        raise InputError(f"{where}: column {header!r}: state the unit of PSV, "
                                         "cm/s or m/s (e.g. 'PSV [cm/s]')")
                    words = rest
                found.setdefault(" ".join(words), {})[quantity] = (i, factor)
            elif self.x is None and (_is_frequency(header) or _is_period(header)):
                self.x, self.is_period = i, not _is_frequency(header)
            elif self.label is None and header.strip().lower() in _LABEL_HEADERS:
                self.label = i
        if self.x is None:
            raise InputError(f"{where}: first column header {head[0]!r} names neither a "
                             "frequency ('freq', 'Hz') nor a period ('period', 'T', '(s)'), nor "
                             f"does any other ({','.join(head)})")
        if not found:
            raise InputError(f"{where}: need a column of PSA [g] or PSV [cm/s or m/s] (headers "
                             f"such as 'psa_g', 'PSV [cm/s]'), got {','.join(head)!r}")
        self.groups = {loc: q.get("psa", q.get("psv")) for loc, q in found.items()}

    def spectra(self, data: list[list[str]]) -> dict[tuple[str, str], str]:
        """(label, location) -> display name of every spectrum in the file, in file order."""
        labels = [""] if self.label is None else list(dict.fromkeys(
            cells[self.label] for cells in data if len(cells) > self.label))
        return {(lab, loc): " ".join(p for p in (lab, loc) if p)
                for lab in labels for loc in self.groups}


def _normalised(name: str) -> str:
    return re.sub(r"[\s_\-]+", "", name.lower())


def _select_spectrum(spectra: dict, select: str | None, path: Path):
    """Key of the spectrum named ``select`` (or of the only one)."""
    names = ", ".join(repr(n) for n in spectra.values() if n)
    if select is None:
        if len(spectra) == 1:
            return next(iter(spectra))
        raise InputError(f"{path}: holds {len(spectra)} spectra ({names}): choose one, "
                         f"e.g. {path}:{next(iter(spectra.values()))}")
    match = [k for k, n in spectra.items() if _normalised(n) == _normalised(select)]
    if not match:
        match = [k for k in spectra if _normalised(select) in map(_normalised, k)]
    if len(match) != 1:
        raise InputError(f"{path}: no single spectrum named {select!r}; the file holds "
                         f"{names or 'one unnamed spectrum'}")
    return match[0]


# --------------------------------------------------------------------------- response spectra

@dataclass(frozen=True, eq=False)
class ResponseSpectrum:
    """Response spectra of one motion or of an ensemble.

    Attributes
    ----------
    freqs_hz : ndarray, shape (n_freq,)
        Oscillator frequencies [Hz].
    damping : float
        Damping ratio [-].
    sd : ndarray, shape (n_freq,) or (n_motions, n_freq)
        Spectral displacement: peak relative displacement [input length unit, m for m/s²].
    psv : ndarray
        Pseudo-velocity ω·SD [m/s for input in m/s²].
    psa : ndarray
        Pseudo-acceleration ω²·SD [units of the input acceleration].
    """

    freqs_hz: np.ndarray
    damping: float
    sd: np.ndarray
    psv: np.ndarray
    psa: np.ndarray

    def mean(self) -> "ResponseSpectrum":
        """Ensemble-mean spectrum (itself for a single motion)."""
        if self.sd.ndim == 1:
            return self
        return ResponseSpectrum(self.freqs_hz, self.damping, self.sd.mean(axis=0),
                                self.psv.mean(axis=0), self.psa.mean(axis=0))


def _foh_coefficients(omega: np.ndarray, zeta: float, h: np.ndarray) -> np.ndarray:
    """Exact one-step recurrence of u'' + 2ζωu' + ω²u = −a(t) for a(t) linear over a step h.

    Returns c of shape (n, 8) with
    u₁ = c0·u₀ + c1·v₀ + c2·a₀ + c3·a₁ and v₁ = c4·u₀ + c5·v₀ + c6·a₀ + c7·a₁.
    These are Nigam & Jennings' (1969) coefficients. They are obtained here from the matrix
    exponential of the system augmented with the input and its slope (scipy.linalg.expm) rather
    than from their closed form, whose terms cancel catastrophically when ω·h is small.
    """
    n = omega.size
    m = np.zeros((n, 4, 4))  # state (u, v, a, Δa); da/dt = Δa/h
    m[:, 0, 1] = h
    m[:, 1, 0] = -omega**2 * h
    m[:, 1, 1] = -2.0 * zeta * omega * h
    m[:, 1, 2] = -h
    m[:, 2, 3] = 1.0
    # One BLAS thread: expm multiplies 4×4 matrices, where OpenBLAS's threads only get in the way
    # (on a busy 2-core machine they made this call take 0.3 s instead of 1 ms for 40
    # frequencies, a known OpenBLAS behaviour with small matrices).
    with threadpool_limits(limits=1, user_api="blas"):
        e = scipy.linalg.expm(m)
    c = np.empty((n, 8))
    for row in (0, 1):  # x₁ = Φ·x₀ + E[:, 2]·a₀ + E[:, 3]·(a₁ − a₀)
        c[:, 4 * row] = e[:, row, 0]
        c[:, 4 * row + 1] = e[:, row, 1]
        c[:, 4 * row + 2] = e[:, row, 2] - e[:, row, 3]
        c[:, 4 * row + 3] = e[:, row, 3]
    return c


@kernel
def _hermite_extremum(u0, v0, u1, v1, h):
    """Extremum of the cubic Hermite interpolant of u over a step where v changes sign.

    The recurrence gives u and v exactly at the sub-step ends only; the cubic through (u, v) at
    both ends locates the peak in between with an error O((ωh)⁴), where taking the larger end
    value would err by O((ωh)²) (up to 5 % at 10 steps per period).
    """
    # p'(s) = qa·s² + qb·s + qc on s ∈ [0, 1]; p'(0) = h·v0 and p'(1) = h·v1 differ in sign,
    # so exactly one root lies in (0, 1).
    qa = 6.0 * (u0 - u1) + 3.0 * h * (v0 + v1)
    qb = 6.0 * (u1 - u0) - h * (4.0 * v0 + 2.0 * v1)
    qc = h * v0
    if qa == 0.0:
        s = -qc / qb
    else:
        q = -0.5 * (qb + math.copysign(math.sqrt(max(qb * qb - 4.0 * qa * qc, 0.0)), qb))
        s = q / qa
        if not 0.0 <= s <= 1.0:
            s = qc / q
    s = min(max(s, 0.0), 1.0)
    s2 = s * s
    s3 = s2 * s
    return ((2.0 * s3 - 3.0 * s2 + 1.0) * u0 + (s3 - 2.0 * s2 + s) * h * v0
            + (3.0 * s2 - 2.0 * s3) * u1 + (s3 - s2) * h * v1)


@kernel
def _free_vibration_extremum(u, v, omega, zeta):
    """First extremum of u in damped free vibration from (u, v). Later extrema are smaller by
    exp(−ζπ/sqrt(1−ζ²)) each, so this and |u| bound the whole free-vibration tail."""
    wd = omega * math.sqrt(1.0 - zeta * zeta)
    # v(τ) ∝ X·cos(ωd·τ) − Y·sin(ωd·τ): first zero at ωd·τ = atan2(X, Y) (+π if ≤ 0).
    phi = math.atan2(v * wd, omega * omega * u + zeta * omega * v)
    if phi <= 0.0:
        phi += math.pi
    return math.exp(-zeta * omega * phi / wd) * (
        u * math.cos(phi) + (v + zeta * omega * u) / wd * math.sin(phi))


@kernel
def _peak_displacement(a, c, nsub, h, omega, zeta):
    """max |u(t)| of one oscillator [length] under the piecewise-linear ground acceleration ``a``,
    starting at rest, including the free vibration after the record (ground at rest)."""
    u = 0.0
    v = 0.0
    peak = 0.0
    for i in range(a.size - 1):
        a0 = a[i]
        da = (a[i + 1] - a0) / nsub
        for k in range(nsub):
            g0 = a0 + k * da
            g1 = a0 + (k + 1) * da
            u1 = c[0] * u + c[1] * v + c[2] * g0 + c[3] * g1
            v1 = c[4] * u + c[5] * v + c[6] * g0 + c[7] * g1
            if v * v1 < 0.0:
                peak = max(peak, abs(_hermite_extremum(u, v, u1, v1, h)))
            peak = max(peak, abs(u1))
            u = u1
            v = v1
    return max(peak, abs(_free_vibration_extremum(u, v, omega, zeta)))


@parallel_kernel
def _peak_displacements(acc, coef, nsub, h, omega, zeta):
    n_m = acc.shape[0]
    n_f = omega.size
    out = np.empty((n_m, n_f))
    for p in prange(n_m * n_f):  # every (motion, frequency) pair is independent
        i = p // n_f
        j = p % n_f
        out[i, j] = _peak_displacement(acc[i], coef[j], nsub[j], h[j], omega[j], zeta)
    return out


def response_spectrum(acc, dt: float, freqs_hz, damping: float = 0.05, *,
                      steps_per_period: int = 10) -> ResponseSpectrum:
    """Response spectra of ground accelerations by the Nigam & Jennings (1969) recurrence.

    Each oscillator u'' + 2ζωu' + ω²u = −a(t) starts at rest; a(t) is the piecewise-linear
    interpolant of the samples, for which the recurrence is exact. At the record's own step the
    peaks between samples would be missed (reference.md §7), so each step dt is cut into
    m = ceil(steps_per_period·dt·f) sub-steps and the peak inside a sub-step is located by cubic
    Hermite interpolation of (u, v): with the default 10 steps per period the peaks are within
    (2π/10)⁴/384 ≈ 4e-4 (relative) of the exact ones. The ground is taken to be at rest after the last
    sample, so the free vibration that follows the record counts too (it matters at long periods:
    Boore 2005, "On pads and filters").

    Parameters
    ----------
    acc : array_like, shape (n_t,) or (n_motions, n_t)
        Ground acceleration [any unit, e.g. m/s² or g]; finite; n_t ≥ 2.
    dt : float
        Time step [s], > 0.
    freqs_hz : array_like, shape (n_freq,)
        Oscillator frequencies [Hz], finite, > 0.
    damping : float
        Damping ratio ζ [-], in [0, 1).
    steps_per_period : int
        Least number of integration steps per oscillator period [-], ≥ 1.

    Returns
    -------
    ResponseSpectrum
        ``sd``, ``psv`` and ``psa`` of shape (n_freq,) for 1-D ``acc`` or (n_motions, n_freq):
        for acc in m/s², SD [m], PSV = ω·SD [m/s] and PSA = ω²·SD [m/s²].
    """
    a = finite_array("acc", acc, ndim=(1, 2), min_len=2)
    dt = positive("dt", dt, "s")
    zeta = in_range("damping", damping, 0.0, 1.0, hi_open=True, unit="-")
    f, shape = _freqs(freqs_hz)
    if len(shape) > 1:
        raise InputError(f"freqs_hz must have 1 dimension, got shape {shape}")
    omega = 2.0 * math.pi * f
    spp = steps_per_period
    if isinstance(spp, bool) or not isinstance(spp, (int, np.integer)) or spp < 1:
        raise InputError(f"steps_per_period must be an integer >= 1, got {spp!r}")
    nsub = np.maximum(1, np.ceil(spp * dt * f - 1e-9)).astype(np.int64)
    h = dt / nsub
    coef = _foh_coefficients(omega, zeta, h)
    sd = _peak_displacements(np.atleast_2d(a), coef, nsub, h, omega, zeta)
    if a.ndim == 1:
        sd = sd[0]
    return ResponseSpectrum(f, zeta, sd, omega * sd, omega**2 * sd)
