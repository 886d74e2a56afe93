"""Intensity measures of ground motions: :func:`intensity_measures`, :func:`parse_im`.

An intensity measure (IM) is named by a short string (the command line's ``--im``), in any case
and with any spaces; the forms are those of :data:`rocking.defaults.IM_SYNTAX`:

============================  =====  ============================================================
form                          unit   what
============================  =====  ============================================================
``pga``                       g      peak ground acceleration, max abs(a)
``pgv``                       m/s    peak ground velocity, max abs(v)
``pgd``                       m      peak ground displacement, max abs(d)
``sa(T)``, ``sa(T,zeta)``     g      pseudo-spectral acceleration at period T [s], damping ratio
                                     zeta [-] (default 0.05)
``psv(T)``, ``psv(T,zeta)``   m/s    pseudo-spectral velocity, Sa·g·T/(2π)
``saavg(T1:T2:n,zeta)``       g      geometric mean of Sa at n periods log-spaced from T1 to T2
                                     [s], both included; ``:n`` (default 10) and ``,zeta``
                                     (default 0.05) may be left out: ``saavg(0.2:2)`` (Eads et
                                     al. 2015, "An efficient method for estimating the collapse
                                     risk of structures in seismic regions")
``arias``                     m/s    Arias intensity, I_A = π/(2g)·∫a² dt
``cav``                       m/s    cumulative absolute velocity, ∫abs(a) dt over the whole
                                     record (no threshold: not the "standardized" CAV of EPRI 1991)
``pgv/pga``                   s      PGV [m/s] over PGA [m/s²]
``pga/gtana``                 ``-``  per body: PGA [m/s²] over the body's uplift acceleration
                                     g·tan α
``pgv*p/gtana``               ``-``  per body: PGV·p/(g·tan α), p the body's frequency
                                     parameter [rad/s]
``omega``                     ``-``  per body: Ω = ω_p/p, ω_p = 2π/T_p with T_p the motion's
                                     pulse period (:func:`rocking.pulse_period`, Shahi & Baker
                                     2014, whether or not the motion is pulse-like)
============================  =====  ============================================================

The last three are the dimensionless measures of rocking (Makris & Konstantinidis 2003,
Dimitrakopoulos & DeJong 2012): they need the body (``intensity_measures(..., body=block)``).
For one body, PGA/(g·tan α) and PGV·p/(g·tan α) are PGA and PGV times a constant; they differ
from them only when bodies are compared or pooled (:func:`rocking.im_efficiency`).

A name may carry its unit in brackets, which must then be the one above (``"pgv [m/s]"``); the
columns of :func:`intensity_measures` and the headers of hazard files are written that way.

How they are computed. The acceleration a(t) is the piecewise-linear interpolant of the samples,
as for :func:`rocking.response_spectrum`, and every integral is exact for it: the velocity v is
its cumulative trapezoid integral from v(0) = 0, the displacement its exact integral (a
trapezoid with the end correction −dt²·Δa/12 per step) from d(0) = 0, Arias intensity and CAV
the exact integrals of a² and abs(a) over each step. Peaks are taken at the samples (between
samples a peak of v or d is at most (π·f·dt)²/2 higher, relatively, for a component of
frequency f: 1e-4 at f = 1 Hz and dt = 0.005 s). The motion is used as given: no baseline
correction before PGV and PGD, as the rocking literature uses the velocity of the record (a
record with a drifting baseline has a PGD that means nothing; see
:func:`rocking.baseline_correct`). Sa and PSV come from :func:`rocking.response_spectrum` at the
frequency 1/T.

Scaling a motion by λ > 0 scales an IM by λ^k (:func:`im_scaling_exponent`): k = 1 for all but
Arias intensity (k = 2) and PGV/PGA and Ω (k = 0, so they cannot serve as the scaled IM of an
incremental dynamic analysis).
"""

from __future__ import annotations

import math
import re
from collections.abc import Iterable
from dataclasses import dataclass

import numpy as np
import pandas as pd
from numpy.typing import ArrayLike

from ..core import portable
from ..core.checks import count
from ..defaults import IM_DAMPING, IM_SYNTAX, SAAVG_PERIODS, G
from ..dynamics.body import Block
from ..errors import InputError
from .ensemble import Ensemble
from .response import check_nyquist, response_spectrum
from .wavelets import pulse_period

#: kind → (unit, label without parameters, scaling exponent k in IM(λ·a) = λ^k·IM(a)).
_KINDS = {
    "pga": ("g", "PGA", 1),
    "pgv": ("m/s", "PGV", 1),
    "pgd": ("m", "PGD", 1),
    "sa": ("g", "Sa", 1),
    "psv": ("m/s", "PSV", 1),
    "saavg": ("g", "Sa_avg", 1),
    "arias": ("m/s", "Arias intensity", 2),
    "cav": ("m/s", "CAV", 1),
    "pgv/pga": ("s", "PGV/PGA", 0),
    "pga/gtana": ("-", "PGA/(g tan α)", 1),
    "pgv*p/gtana": ("-", "PGV·p/(g tan α)", 1),
    "omega": ("-", "Ω = ω_p/p", 0),
}
#: per-body kind → the IM it is a constant multiple of for one body (None: none).
_PER_BODY = {"pga/gtana": "pga", "pgv*p/gtana": "pgv", "omega": None}
_NUM = r"([^,:()]+)"
_SPECTRAL = re.compile(rf"(sa|psv)\({_NUM}(?:,{_NUM})?\)")
_SAAVG = re.compile(rf"saavg\({_NUM}:{_NUM}(?::{_NUM})?(?:,{_NUM})?\)")
_UNIT = re.compile(r"^(.*?)\[(.*)\]$")


@dataclass(frozen=True)
class IntensityMeasure:
    """One intensity measure, as parsed by :func:`parse_im` (compare them with ``==``).

    Attributes
    ----------
    kind : str
        ``"pga"``, ``"pgv"``, ``"pgd"``, ``"sa"``, ``"psv"``, ``"saavg"``, ``"arias"``,
        ``"cav"``, ``"pgv/pga"``, or per body ``"pga/gtana"``, ``"pgv*p/gtana"``, ``"omega"``.
    periods : tuple of float
        Sa and PSV: (T,); Sa_avg: (T1, T2) [s]; others: ().
    n_periods : int
        Sa_avg: number of log-spaced periods from T1 to T2; others: 0.
    damping : float or None
        Damping ratio of Sa, PSV and Sa_avg [-]; None for the others.
    """

    kind: str
    periods: tuple[float, ...] = ()
    n_periods: int = 0
    damping: float | None = None

    @property
    def unit(self) -> str:
        """Unit of the values: ``"g"``, ``"m/s"``, ``"m"``, ``"s"`` or ``"-"``."""
        return _KINDS[self.kind][0]

    @property
    def per_body(self) -> bool:
        """True for the dimensionless IMs, whose value depends on the body (α, p)."""
        return self.kind in _PER_BODY

    @property
    def dimensional(self) -> str | None:
        """The IM of which this per-body IM is a constant multiple for one body (``"pga"``,
        ``"pgv"``; so its fragility has that IM's β), None for the others."""
        return _PER_BODY.get(self.kind)

    @property
    def scaling_exponent(self) -> int:
        """k in IM(λ·a) = λ^k·IM(a) for a motion a scaled by λ > 0 [-]."""
        return _KINDS[self.kind][2]

    @property
    def name(self) -> str:
        """Canonical name: lower case, no spaces, the default damping and number of periods
        left out, e.g. ``"pgv"``, ``"sa(1)"``, ``"sa(0.5,0.02)"``, ``"saavg(0.2:2)"``."""
        if not self.periods:
            return self.kind
        sep = ":" if self.kind == "saavg" else ","
        args = sep.join(_fmt(t) for t in self.periods)
        if self.kind == "saavg" and self.n_periods != SAAVG_PERIODS:
            args += f":{self.n_periods}"
        if self.damping != IM_DAMPING:
            args += f",{_fmt(self.damping)}"
        return f"{self.kind}({args})"

    @property
    def column(self) -> str:
        """Name with unit, as in the columns of :func:`intensity_measures` and the header of a
        hazard file, e.g. ``"pgv [m/s]"``."""
        return f"{self.name} [{self.unit}]"

    @property
    def label(self) -> str:
        """Human-readable name with unit for plots and reports, e.g. ``"Sa(1 s, 5 %) [g]"``."""
        base = _KINDS[self.kind][1]
        if self.damping is not None:
            zeta = f"{_fmt(100 * self.damping)} %"
            if self.kind == "saavg":
                t1, t2 = self.periods
                base += f"({_fmt(t1)}–{_fmt(t2)} s, {self.n_periods} periods, {zeta})"
            else:
                base += f"({_fmt(self.periods[0])} s, {zeta})"
        return f"{base} [{self.unit}]"

    def spectral_periods(self) -> np.ndarray:
        """Periods [s] whose Sa this IM needs (empty for the others)."""
        if self.kind == "saavg":
            return portable.geomspace(self.periods[0], self.periods[1], self.n_periods)
        return np.asarray(self.periods, dtype=float)


def _fmt(x) -> str:
    return f"{x:.12g}"


def parse_im(im: str | IntensityMeasure) -> IntensityMeasure:
    """The intensity measure named by ``im`` (forms in the module notes).

    Parameters
    ----------
    im : str or IntensityMeasure
        E.g. ``"pgv"``, ``"Sa(1.0)"``, ``"sa(0.5, 0.02)"``, ``"saavg(0.2:2.0:10)"``,
        ``"pgv [m/s]"`` (a unit in brackets must be the IM's own).

    Returns
    -------
    IntensityMeasure

    Raises
    ------
    InputError
        For anything else, listing the valid forms.
    """
    if isinstance(im, IntensityMeasure):
        return im
    if not isinstance(im, str):
        raise InputError(f"im must be a string such as 'pgv', got {im!r} (valid: {IM_SYNTAX})")
    text = "".join(im.split()).lower()
    unit = None
    m = _UNIT.match(text)
    if m:
        text, unit = m.groups()
    out = _parse(text, im)
    if unit is not None and unit != out.unit:
        raise InputError(f"im {im!r}: {out.name} is in [{out.unit}], not [{unit}]")
    return out


def _parse(text: str, im: str) -> IntensityMeasure:
    if text in _KINDS and text not in ("sa", "psv", "saavg"):
        return IntensityMeasure(text)
    m = _SPECTRAL.fullmatch(text)
    if m:
        kind, period, zeta = m.groups()
        return IntensityMeasure(
            kind, (_period(period, im),), damping=_damping(zeta, im) if zeta else IM_DAMPING
        )
    m = _SAAVG.fullmatch(text)
    if m:
        t1, t2, n, zeta = m.groups()
        lo, hi = _period(t1, im), _period(t2, im)
        if not lo < hi:
            raise InputError(f"im {im!r}: the period range T1:T2 needs T1 < T2")
        n_periods = SAAVG_PERIODS if n is None else _count(n, im)
        damping = _damping(zeta, im) if zeta else IM_DAMPING
        return IntensityMeasure("saavg", (lo, hi), n_periods, damping)
    raise InputError(f"unknown intensity measure {im!r}; valid forms: {IM_SYNTAX}")


def _number(text: str, im: str, what: str) -> float:
    try:
        x = float(text)
    except ValueError:
        raise InputError(f"im {im!r}: {what} {text!r} is not a number") from None
    if not math.isfinite(x):
        raise InputError(f"im {im!r}: {what} {text!r} is not finite")
    return x


def _period(text: str, im: str) -> float:
    t = _number(text, im, "period")
    if t <= 0.0:
        raise InputError(f"im {im!r}: a period must be > 0 [s], got {text}")
    return t


def _damping(text: str, im: str) -> float:
    zeta = _number(text, im, "damping")
    if not 0.0 <= zeta < 1.0:
        raise InputError(f"im {im!r}: damping is a fraction in [0, 1) (5 % is 0.05), got {text}")
    return zeta


def _count(text: str, im: str) -> int:
    if not text.isdigit():
        raise InputError(f"im {im!r}: the number of periods must be an integer >= 2, got {text}")
    return count(f"im {im!r}: the number of periods", int(text), "frequencies", 2)


def im_scaling_exponent(im: str | IntensityMeasure) -> int:
    """k in IM(λ·a) = λ^k·IM(a) for a motion a scaled by λ > 0.

    1 for PGA, PGV, PGD, Sa, PSV, Sa_avg, CAV, PGA/(g tan α) and PGV·p/(g tan α); 2 for Arias
    intensity; 0 for PGV/PGA and Ω, which scaling does not change (they cannot be the IM of an
    incremental dynamic analysis).

    Parameters
    ----------
    im : str or IntensityMeasure
        As for :func:`parse_im`.

    Returns
    -------
    int
    """
    return parse_im(im).scaling_exponent


def intensity_measures(
    ensemble: Ensemble,
    ims: str | IntensityMeasure | Iterable[str | IntensityMeasure],
    *,
    body: Block | None = None,
    g: float = G,
) -> pd.DataFrame:
    """Intensity measures of every motion of an ensemble.

    Parameters
    ----------
    ensemble : Ensemble
        The motions (accelerations [m/s²] at step dt [s]).
    ims : str, IntensityMeasure or sequence of them
        The IMs (forms in the module notes), e.g. ``["pga", "pgv", "sa(1.0)"]``; each at most
        once.
    body : Block, optional
        The body of the per-body IMs (``pga/gtana``, ``pgv*p/gtana``, ``omega``), which are
        refused without it.
    g : float
        Gravity of the body's g·tan α and p [m/s²] (PGA [m/s²] is PGA [g] times standard
        gravity, whatever ``g``).

    Returns
    -------
    pandas.DataFrame
        One row per motion (index ``ensemble.labels``, named ``"motion"``), one column per IM
        in the order given, named by :attr:`IntensityMeasure.column` (canonical name and unit,
        e.g. ``"pgv [m/s]"``, ``"sa(1) [g]"``); values in that unit (see the module notes for
        how each is computed).
    """
    if not isinstance(ensemble, Ensemble):
        raise InputError(
            f"ensemble must be a rocking.Ensemble, got {type(ensemble).__name__} (make one with "
            "rocking.Ensemble(acc, dt) or Ensemble.load(path))"
        )
    items = [ims] if isinstance(ims, (str, IntensityMeasure)) else list(ims)
    if not items:
        raise InputError(f"ims must name at least one intensity measure ({IM_SYNTAX})")
    parsed = [parse_im(s) for s in items]
    seen: dict[IntensityMeasure, str] = {}
    for text, im in zip(items, parsed):
        if im in seen:
            raise InputError(f"ims names {im.name} twice ({seen[im]!r} and {text!r})")
        seen[im] = str(text)
    if body is None:
        needy = [im.name for im in parsed if im.per_body]
        if needy:
            raise InputError(
                f"ims {', '.join(needy)} are per body (they divide by its g·tan α): give "
                "body=rocking.Block(R, gamma)"
            )
    elif not isinstance(body, Block):
        raise InputError(f"body must be a rocking.Block, got {type(body).__name__}")
    return pd.DataFrame(
        dict(zip((im.column for im in parsed), _values(ensemble, parsed, body, g))),
        index=pd.Index(ensemble.labels, name="motion"),
    )


def omega_ratio(pulse_period: ArrayLike, p: float) -> np.ndarray:
    """Ω = ω_p/p [-] of pulse periods ``pulse_period`` T_p [s] for a body of frequency
    parameter ``p`` [rad/s], with ω_p = 2π/T_p (Zhang & Makris 2001)."""
    return 2.0 * math.pi / (np.asarray(pulse_period, dtype=float) * p)


def _values(
    ens: Ensemble, ims: list[IntensityMeasure], body: Block | None, g: float
) -> list[np.ndarray]:
    # on first use: scipy.integrate takes 0.5 s to import, which the commands' refusals (they
    # parse IM names with this module) must not wait for
    from scipy.integrate import cumulative_trapezoid

    a, dt = ens.acc, ens.dt
    v = cumulative_trapezoid(a, dx=dt, axis=1, initial=0.0)
    # exact integral of the piecewise-quadratic v: trapezoid − dt²·(a_{i+1} − a_i)/12 per step,
    # which telescopes to − dt²·(a_j − a_0)/12 at sample j
    d = cumulative_trapezoid(v, dx=dt, axis=1, initial=0.0) - dt**2 / 12.0 * (a - a[:, :1])
    sa = _spectral_accelerations(a, dt, ims)
    a0, a1 = a[:, :-1], a[:, 1:]
    if body is not None:  # the body's uplift acceleration g·tan α [m/s²] and p [rad/s]
        uplift, p = body.uplift_acceleration_at(g), body.p_at(g)
    out = []
    for im in ims:
        k = im.kind
        if k == "pga":
            out.append(ens.pga)
        elif k == "pgv":
            out.append(np.abs(v).max(axis=1))
        elif k == "pga/gtana":
            out.append(ens.pga * G / uplift)
        elif k == "pgv*p/gtana":
            out.append(np.abs(v).max(axis=1) * p / uplift)
        elif k == "omega":  # Ω = ω_p/p, ω_p = 2π/T_p
            periods = np.array([pulse_period(row, dt).period for row in a])
            out.append(omega_ratio(periods, p))
        elif k == "pgd":
            out.append(np.abs(d).max(axis=1))
        elif k == "pgv/pga":
            pga = np.abs(a).max(axis=1)
            with np.errstate(divide="ignore", invalid="ignore"):
                out.append(np.abs(v).max(axis=1) / pga)
        elif k == "arias":
            # I_A = π/(2g)·∫a² dt; over a step ∫a² = dt·(a0² + a0·a1 + a1²)/3 (a linear)
            sq = (a0 * a0 + a0 * a1 + a1 * a1).sum(axis=1) * dt / 3.0
            out.append(math.pi / (2.0 * G) * sq)
        elif k == "cav":
            out.append(_abs_integral(a0, a1, dt))
        elif k == "saavg":
            periods = im.spectral_periods()
            logs = np.stack([portable.log(sa[(t, im.damping)]) for t in periods])
            out.append(portable.exp(logs.mean(axis=0)))
        else:  # sa, psv: PSV = PSA/ω = PSA·T/(2π)
            psa = sa[(im.periods[0], im.damping)]
            out.append(psa if k == "sa" else psa * G * im.periods[0] / (2.0 * math.pi))
    return out


def _spectral_accelerations(a: np.ndarray, dt: float, ims: list[IntensityMeasure]) -> dict:
    """PSA [g] of every motion at each (period, damping) the IMs need, one response-spectrum
    computation per damping ratio."""
    wanted: dict[float, set[float]] = {}
    for im in ims:
        if im.damping is not None:
            wanted.setdefault(im.damping, set()).update(im.spectral_periods().tolist())
    out = {}
    for zeta, periods in wanted.items():
        ts = sorted(periods)
        check_nyquist(1.0 / ts[0], dt, f"the spectral period {ts[0]:g} s (1/T)")
        psa = response_spectrum(a, dt, 1.0 / np.asarray(ts), zeta).psa / G
        out.update({(t, zeta): psa[:, j] for j, t in enumerate(ts)})
    return out


def _abs_integral(a0: np.ndarray, a1: np.ndarray, dt: float) -> np.ndarray:
    """∫abs(a) dt of the piecewise-linear a, per row: a step whose ends have one sign gives
    dt·(abs(a0) + abs(a1))/2; one where a crosses zero, dt·(a0² + a1²)/(2·(abs(a0) + abs(a1)))."""
    total = np.abs(a0) + np.abs(a1)
    crossing = a0 * a1 < 0.0  # then total > 0
    sq = (a0 * a0 + a1 * a1) / (2.0 * np.where(crossing, total, 1.0))
    return np.where(crossing, sq, total / 2.0).sum(axis=1) * dt
