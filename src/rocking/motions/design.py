"""Building-code design spectra as target spectra, and a one-line syntax to name any spectrum.

* :class:`ASCE7` — ASCE/SEI 7-16 §11.4.6 (ASCE/SEI 7-22 §11.4.5.2, the "two-period" spectrum):
  design response spectrum from S_DS, S_D1 and T_L (5 % damping).
* :class:`EC8` — Eurocode 8, EN 1998-1:2004 §3.2.2.2: horizontal elastic response spectrum,
  Type 1 or Type 2, ground types A–E, importance factor and damping correction η.
* :func:`parse_spectrum` — ``rg160:0.3``, ``asce7:SDS=1.0,SD1=0.6,TL=8``,
  ``ec8:type=1,ground=B,ag=0.25`` or a CSV path
  (:meth:`rocking.motions.targets.TabulatedSpectrum.from_csv`,
  e.g. a floor response spectrum computed elsewhere).

All of them are :class:`rocking.motions.targets.TargetSpectrum` objects (PSA [g], PSV [m/s], SD [m]
at
frequencies [Hz]), so they can drive :func:`rocking.motions.synthesis.generate` and the energy
balance.
:func:`design_pga` gives the A_gx [g] at which a spectrum is the design level (its ZPA).
"""

from __future__ import annotations

import dataclasses
import math
import os
from abc import abstractmethod
from dataclasses import dataclass
from pathlib import Path
from typing import ClassVar, Self

import numpy as np
from numpy.typing import ArrayLike

from ..core.checks import MAX_G, finite_array, in_range, positive, too_strong
from ..defaults import SPECTRUM_SYNTAX
from ..errors import InputError
from .targets import RG160, TabulatedSpectrum, TargetSpectrum, _freqs

#: EN 1998-1:2004 Table 3.2 (Type 1) and Table 3.3 (Type 2), recommended values:
#: ground type -> (S [-], T_B [s], T_C [s], T_D [s]).
EC8_PARAMETERS = {
    1: {
        "A": (1.0, 0.15, 0.4, 2.0),
        "B": (1.2, 0.15, 0.5, 2.0),
        "C": (1.15, 0.20, 0.6, 2.0),
        "D": (1.35, 0.20, 0.8, 2.0),
        "E": (1.4, 0.15, 0.5, 2.0),
    },
    2: {
        "A": (1.0, 0.05, 0.25, 1.2),
        "B": (1.35, 0.05, 0.25, 1.2),
        "C": (1.5, 0.10, 0.25, 1.2),
        "D": (1.8, 0.10, 0.30, 1.2),
        "E": (1.6, 0.05, 0.25, 1.2),
    },
}


def _periods(freqs_hz) -> tuple[np.ndarray, tuple]:
    """Periods T = 1/f [s] (flat) of frequencies [Hz] (finite, > 0) and the caller's shape."""
    f, shape = _freqs(freqs_hz)
    return 1.0 / f, shape


def _check_periods(periods_s) -> tuple[np.ndarray, tuple]:
    """Periods [s] as a flat float array (all finite, > 0) and the caller's shape."""
    shape = np.shape(periods_s)
    t = finite_array("periods_s", np.ravel(periods_s), ndim=(1,))
    if (t <= 0.0).any():
        raise InputError(f"periods_s must be > 0 [s], got {t[t <= 0.0][0]!r}")
    return t, shape


class CodeSpectrum(TargetSpectrum):
    """A building-code spectrum: defined by its spectral acceleration S_a(T) [g] at periods
    T [s], and scaled by multiplying its intensity parameters (those named in
    ``SCALED_FIELDS``), so that a scaled spectrum is again the code's spectrum of other
    parameters (e.g. S_DS and S_D1 for ASCE 7, with T_L unchanged)."""

    #: Names of the fields that :meth:`scaled` multiplies.
    SCALED_FIELDS: ClassVar[tuple[str, ...]] = ()

    @abstractmethod
    def sa(self, periods_s: ArrayLike) -> np.ndarray:
        """Spectral acceleration [g] at periods [s] (> 0; any shape)."""

    def psa(self, freqs_hz: ArrayLike) -> np.ndarray:
        """PSA [g] at ``freqs_hz`` [Hz]: S_a at T = 1/f."""
        t, shape = _periods(freqs_hz)
        return self.sa(t).reshape(shape)

    def scaled(self, factor: float) -> Self:
        """The spectrum with the fields of ``SCALED_FIELDS`` times ``factor`` [-] (> 0)."""
        factor = positive("factor", factor, "-")
        changes = {name: getattr(self, name) * factor for name in self.SCALED_FIELDS}
        return dataclasses.replace(self, **changes)  # type: ignore[type-var]


@dataclass(frozen=True)
class ASCE7(CodeSpectrum):
    """ASCE/SEI 7 design response spectrum (ASCE 7-16 §11.4.6, Fig. 11.4-1; ASCE 7-22 §11.4.5.2).

    With T_0 = 0.2·S_D1/S_DS and T_s = S_D1/S_DS, the spectral acceleration S_a [g] is
    (Eqs. 11.4-5 to 11.4-8 of ASCE 7-16)::

        T < T_0:          S_a = S_DS·(0.4 + 0.6·T/T_0)
        T_0 ≤ T ≤ T_s:    S_a = S_DS
        T_s < T ≤ T_L:    S_a = S_D1/T
        T > T_L:          S_a = S_D1·T_L/T²

    for 5 % damping. The ZPA (T → 0) is 0.4·S_DS.

    Parameters
    ----------
    SDS : float
        Design spectral acceleration at short periods S_DS [g], > 0.
    SD1 : float
        Design spectral acceleration at 1 s S_D1 [g], > 0.
    TL : float
        Long-period transition period T_L [s] (ASCE 7 Chapter 22 maps), > T_s.
    """

    SCALED_FIELDS = ("SDS", "SD1")  # T_L unchanged (T_0 and T_s too)

    SDS: float
    SD1: float
    TL: float
    damping = 0.05  # the code's spectrum is for 5 % damping only

    def __post_init__(self):
        object.__setattr__(self, "SDS", positive("SDS", self.SDS, "g"))
        object.__setattr__(self, "SD1", positive("SD1", self.SD1, "g"))
        object.__setattr__(self, "TL", positive("TL", self.TL, "s"))
        if self.Ts >= self.TL:
            raise InputError(f"TL ({self.TL:g} s) must exceed Ts = SD1/SDS ({self.Ts:g} s)")

    @property
    def name(self) -> str:  # type: ignore[override]
        return f"ASCE 7 (SDS {self.SDS:g} g, SD1 {self.SD1:g} g, TL {self.TL:g} s)"

    @property
    def T0(self) -> float:
        """T_0 = 0.2·S_D1/S_DS [s] (ASCE 7-16 §11.4.6)."""
        return 0.2 * self.SD1 / self.SDS

    @property
    def Ts(self) -> float:
        """T_s = S_D1/S_DS [s] (ASCE 7-16 §11.4.6)."""
        return self.SD1 / self.SDS

    @property
    def pga(self) -> float:
        """Zero-period acceleration 0.4·S_DS [g] (Eq. 11.4-5 at T = 0)."""
        return 0.4 * self.SDS

    def sa(self, periods_s: ArrayLike) -> np.ndarray:
        """Design spectral acceleration S_a [g] at periods [s] (> 0; any shape)."""
        t, shape = _check_periods(periods_s)
        sa = np.select(
            [t < self.T0, t <= self.Ts, t <= self.TL],
            [
                self.SDS * (0.4 + 0.6 * t / self.T0),  # Eq. 11.4-5
                np.full_like(t, self.SDS),  # Eq. 11.4-6 (S_a = S_DS)
                self.SD1 / t,
            ],  # Eq. 11.4-7
            self.SD1 * self.TL / t**2,
        )  # Eq. 11.4-8
        return sa.reshape(shape)


@dataclass(frozen=True)
class EC8(CodeSpectrum):
    """Eurocode 8 horizontal elastic response spectrum (EN 1998-1:2004 §3.2.2.2).

    With a_g = γ_I·a_gR (§3.2.1(3)), soil factor S and corner periods T_B, T_C, T_D from
    Table 3.2 (Type 1) or 3.3 (Type 2), and η = sqrt(10/(5 + ξ)) ≥ 0.55, ξ in percent
    (Eq. 3.6), S_e [g] is (Eqs. 3.2–3.5)::

        0 ≤ T ≤ T_B:    S_e = a_g·S·(1 + T/T_B·(2.5·η − 1))
        T_B ≤ T ≤ T_C:  S_e = 2.5·a_g·S·η
        T_C ≤ T ≤ T_D:  S_e = 2.5·a_g·S·η·T_C/T
        T_D ≤ T:        S_e = 2.5·a_g·S·η·T_C·T_D/T²

    The code defines S_e up to T = 4 s; beyond it Eq. 3.5 is continued (constant spectral
    displacement), because rocking bodies respond at 0.04–0.6 Hz (periods up to 25 s) and this
    is what :class:`rocking.motions.targets.TargetSpectrum` does below its lowest frequency too. The
    informative Annex A (displacement spectrum beyond 4 s) is not applied.

    Parameters
    ----------
    ag : float
        Reference peak ground acceleration on type A ground a_gR [g], > 0.
    ground : str
        Ground type "A" … "E".
    type : int
        Spectrum type 1 (surface-wave magnitude M_s > 5.5) or 2 (M_s ≤ 5.5).
    importance : float
        Importance factor γ_I [-], > 0 (1.0 for ordinary buildings, §4.2.5).
    damping : float
        Viscous damping ratio ξ [-] (0.05 gives η = 1), in (0, 1).
    """

    SCALED_FIELDS = ("ag",)  # a_gR: the same ground type, type and importance

    ag: float
    ground: str = "A"
    type: int = 1
    importance: float = 1.0
    damping: float = 0.05

    def __post_init__(self):
        object.__setattr__(self, "ag", positive("ag", self.ag, "g"))
        object.__setattr__(self, "importance", positive("importance", self.importance, "-"))
        object.__setattr__(
            self,
            "damping",
            in_range("damping", self.damping, 0.0, 1.0, lo_open=True, hi_open=True, unit="-"),
        )
        ground = str(self.ground).strip().upper()
        if ground not in EC8_PARAMETERS[1]:
            raise InputError(f"ground must be one of A, B, C, D, E, got {self.ground!r}")
        object.__setattr__(self, "ground", ground)
        if str(self.type).strip() not in ("1", "2"):
            raise InputError(f"type must be 1 or 2, got {self.type!r}")
        object.__setattr__(self, "type", int(str(self.type).strip()))

    @property
    def name(self) -> str:  # type: ignore[override]
        imp = f", γI {self.importance:g}" if self.importance != 1.0 else ""
        return (
            f"EC8 Type {self.type}, ground {self.ground} (agR {self.ag:g} g{imp}, "
            f"{100 * self.damping:g} %)"
        )

    @property
    def parameters(self) -> tuple[float, float, float, float]:
        """(S [-], T_B [s], T_C [s], T_D [s]) from EN 1998-1 Table 3.2 / 3.3."""
        return EC8_PARAMETERS[self.type][self.ground]

    @property
    def eta(self) -> float:
        """Damping correction η = sqrt(10/(5 + ξ)) ≥ 0.55, ξ in percent (Eq. 3.6) [-]."""
        return max(math.sqrt(10.0 / (5.0 + 100.0 * self.damping)), 0.55)

    @property
    def design_ag(self) -> float:
        """Design ground acceleration on type A ground a_g = γ_I·a_gR [g] (§3.2.1(3))."""
        return self.importance * self.ag

    @property
    def pga(self) -> float:
        """Zero-period acceleration a_g·S [g] (Eq. 3.2 at T = 0)."""
        return self.design_ag * self.parameters[0]

    def sa(self, periods_s: ArrayLike) -> np.ndarray:
        """Elastic spectral acceleration S_e [g] at periods [s] (> 0; any shape)."""
        t, shape = _check_periods(periods_s)
        s, tb, tc, td = self.parameters
        plateau = 2.5 * self.design_ag * s * self.eta
        se = np.select(
            [t <= tb, t <= tc, t <= td],
            [
                self.design_ag * s * (1.0 + t / tb * (2.5 * self.eta - 1.0)),  # Eq. 3.2
                np.full_like(t, plateau),  # Eq. 3.3
                plateau * tc / t,
            ],  # Eq. 3.4
            plateau * tc * td / t**2,
        )  # Eq. 3.5 (continued beyond 4 s, see class notes)
        return se.reshape(shape)


#: Frequency [Hz] at which :func:`design_pga` reads the ZPA of a spectrum without a ``pga``
#: attribute: every spectrum here is flat above 33 Hz (RG 1.60) or rises to its ZPA as T → 0.
_ZPA_FREQ_HZ = 100.0


def design_pga(spectrum: TargetSpectrum) -> float:
    """Design intensity A_gx [g] of a spectrum: its zero-period acceleration.

    The ``pga`` attribute when the spectrum has one (RG 1.60, ASCE 7, EC8), else the PSA at
    100 Hz (a tabulated spectrum is flat above its highest frequency, so that is its last row
    when the table stops below 100 Hz).
    """
    pga = getattr(spectrum, "pga", None)
    if pga is None:
        pga = float(spectrum.psa(np.array([_ZPA_FREQ_HZ]))[0])
    return float(pga)


#: Help text of :func:`parse_spectrum` (also shown by ``rocking screen --help``).
_KINDS = {
    "rg160": (RG160, {"pga": "pga", "damping": "damping"}, "pga"),
    "asce7": (ASCE7, {"sds": "SDS", "sd1": "SD1", "tl": "TL"}, None),
    "ec8": (
        EC8,
        {
            "ag": "ag",
            "ground": "ground",
            "type": "type",
            "importance": "importance",
            "damping": "damping",
        },
        None,
    ),
}
_TEXT_KEYS = {"ground", "type"}


def parse_spectrum(
    text: str, base_dir: str | os.PathLike[str] | None = None, damping: float = 0.05
) -> TargetSpectrum:
    """A target spectrum from a short specification (:data:`rocking.defaults.SPECTRUM_SYNTAX`).

    ``KIND:key=value,key=value`` with KIND one of rg160, asce7, ec8 (keys are case-insensitive;
    ``rg160:0.3`` is short for ``rg160:pga=0.3``; a zero-period acceleration above
    :data:`rocking.core.checks.MAX_G` is refused as a mistake of units); anything else is read
    as a CSV file (:meth:`rocking.motions.targets.TabulatedSpectrum.from_csv`; relative paths
    are taken from ``base_dir`` when given, else the working directory). ``FILE:NAME`` reads the
    spectrum
    NAME of a file that holds several (a record of ``rocking spectrum --csv``, a location such
    as ``floor_1`` of ``rocking frame spectra --csv``).

    Parameters
    ----------
    text : str
        The specification.
    base_dir : str or Path, optional
        Folder for relative CSV paths.
    damping : float
        Damping ratio [-] of a CSV spectrum (the kinds take theirs as a key).
    """
    text = str(text).strip()
    kind, sep, args = text.partition(":")
    if sep and kind.strip().lower() in _KINDS:
        cls, keys, positional = _KINDS[kind.strip().lower()]
        kwargs: dict[str, str | float] = {}
        for part in filter(None, (p.strip() for p in args.split(","))):
            key, eq, value = part.partition("=")
            if not eq and positional and not kwargs:
                key, value = positional, key
            elif not eq:
                raise InputError(f"spectrum {text!r}: expected key=value, got {part!r}")
            name = keys.get(key.strip().lower())
            if name is None:
                raise InputError(
                    f"spectrum {text!r}: unknown key {key.strip()!r} for {kind}; "
                    f"known: {', '.join(keys.values())}"
                )
            if name in kwargs:
                raise InputError(f"spectrum {text!r}: {name} is given twice")
            kwargs[name] = value.strip() if name in _TEXT_KEYS else _number(text, name, value)
        try:
            spectrum = cls(**kwargs)
        except TypeError:
            missing = [k for k in keys.values() if k not in kwargs]
            raise InputError(
                f"spectrum {text!r}: missing {', '.join(missing)} (syntax: {SPECTRUM_SYNTAX})"
            ) from None
        except InputError as exc:
            raise InputError(f"spectrum {text!r}: {exc}") from None
        zpa = design_pga(spectrum)
        if zpa > MAX_G:
            raise InputError(
                f"spectrum {text!r}: " + too_strong("its zero-period acceleration", zpa)
            )
        return spectrum

    def located(name: str) -> Path:
        path = Path(name)
        return Path(base_dir) / path if base_dir is not None and not path.is_absolute() else path

    path, select = located(text), None
    if not path.is_file() and ":" in text:
        head, _, name = text.rpartition(":")
        if located(head).is_file():
            path, select = located(head), name
    if not path.is_file():
        raise InputError(
            f"spectrum {text!r} is neither a known kind (rg160:…, asce7:…, ec8:…) "
            f"nor an existing CSV file; syntax: {SPECTRUM_SYNTAX}"
        )
    return TabulatedSpectrum.from_csv(path, damping, select=select)


def _number(text: str, name: str, value: str) -> float:
    try:
        return float(value)
    except ValueError:
        raise InputError(
            f"spectrum {text!r}: {name} must be a number, got {value.strip()!r}"
        ) from None
