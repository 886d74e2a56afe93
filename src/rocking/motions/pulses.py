"""Idealised near-fault acceleration pulses (issue 46): :func:`pulse`.

Every pulse has an amplitude a_p [m/s²] (its largest abs(acceleration)) and a period T_p [s],
with ω_p = 2π/T_p; time t [s] starts at 0 with the pulse:

=================================  ===========================================================
shape                              acceleration a(t)
=================================  ===========================================================
``half-sine``                      a_p·sin(ω_p·t) on [0, T_p/2]
``one-sine``                       a_p·sin(ω_p·t) on [0, T_p]
``one-cosine``                     a_p·cos(ω_p·t) on [0, T_p]
``rectangular``                    a_p on [0, T_p] (T_p is the duration t_d)
``ricker``                         symmetric Ricker wavelet: a_p·(1 − 2π²τ²/T_p²)·exp(−π²τ²/T_p²)
``ricker-antisymmetric``           a_p/β·(x² − 3)·x·exp(−x²/2), x = 2π·τ/(√3·T_p),
                                   β = √(3 − √6)·(3 − (3 − √6))·exp(−(3 − √6)/2) ≈ 1.38
``mavroeidis-papageorgiou``        Mavroeidis & Papageorgiou (2003), Eq. (2) differentiated:
                                   a(τ) = −(A·π·f_p/γ)·[sin(2π·f_p·τ/γ)·cos(2π·f_p·τ + ν)
                                   + γ·sin(2π·f_p·τ + ν)·(1 + cos(2π·f_p·τ/γ))]
                                   for abs(τ) ≤ γ/(2·f_p), f_p = 1/T_p, with A such that the
                                   largest abs(a) is a_p
=================================  ===========================================================

The Ricker wavelets are the second and third derivatives of a Gaussian whose Fourier amplitude
peaks at the frequency 1/T_p (Vassiliou & Makris 2011, "Estimating time scales and length scales
in pulselike earthquake acceleration records with wavelet analysis", Bull. Seism. Soc. Am. 101);
they are centred at τ = t − 2·T_p and cut to [0, 4·T_p] (beyond, abs(a) < 1e-8·a_p). The
Mavroeidis–Papageorgiou pulse is the velocity pulse v(τ) = (A/2)·(1 + cos(2π·f_p·τ/γ))·
cos(2π·f_p·τ + ν) ("A mathematical representation of near-fault ground motions", Bull. Seism.
Soc. Am. 93(3), 2003): γ > 1 sets the number of its half cycles, ν [rad] its phase; it is
centred at τ = t − γ·T_p/2 and lasts γ·T_p.

Samples are at t = k·dt, linear in between (as every motion of ``rocking``).  A pulse that ends
on a jump (``rectangular``, ``one-cosine``) has half the jump at the sample of its end, when that
falls on a sample: the linear interpolant then carries the pulse's exact velocity change
(impulse) a_p·T_p (``rectangular``).  Choose dt so that T_p (and T_p/2 for ``half-sine``) is a
whole number of steps, as :func:`rocking.overturning_spectrum` does.
"""

from __future__ import annotations

import math
import re

import numpy as np

from ..core.checks import in_range, positive
from ..defaults import PULSE_SHAPES
from ..errors import InputError

#: Default oscillatory parameter γ [-] of the Mavroeidis & Papageorgiou (2003) pulse.
MP_GAMMA = 2.0
#: Default phase ν [rad] of the Mavroeidis & Papageorgiou (2003) pulse.
MP_NU = 0.0
#: Half-length of the support of the Ricker wavelets, in periods T_p.
RICKER_HALF_SPAN = 2.0
_SPEC = re.compile(r"^\s*([a-z-]+)\s*(?::(.*))?$")


def parse_pulse(text: str) -> tuple[str, dict[str, float]]:
    """The shape and parameters of a pulse specification: a name of
    :data:`rocking.defaults.PULSE_SHAPES`, for ``mavroeidis-papageorgiou`` optionally followed
    by ``:gamma=G,nu=N`` (ν in rad), e.g. ``"mavroeidis-papageorgiou:gamma=2.5,nu=1.57"``."""
    m = _SPEC.match(str(text).lower())
    name = m.group(1) if m else ""
    if name not in PULSE_SHAPES:
        raise InputError(f"pulse shape must be one of {', '.join(PULSE_SHAPES)}, got {text!r}")
    params: dict[str, float] = {}
    if m and m.group(2):
        if name != "mavroeidis-papageorgiou":
            raise InputError(f"pulse shape {name!r} takes no parameters, got {text!r}")
        for item in m.group(2).split(","):
            key, _, value = item.partition("=")
            key = key.strip()
            if key not in ("gamma", "nu"):
                raise InputError(
                    f"pulse {text!r}: unknown parameter {key!r} (mavroeidis-papageorgiou takes "
                    "gamma and nu [rad])"
                )
            try:
                params[key] = float(value)
            except ValueError:
                raise InputError(f"pulse {text!r}: {key} must be a number, got {value!r}") from None
    return name, params


def _mp_shape(tau: np.ndarray, gamma: float, nu: float) -> np.ndarray:
    """Mavroeidis & Papageorgiou (2003) acceleration of unit A at f_p = 1, τ in periods."""
    x = 2.0 * math.pi * tau
    return -(math.pi / gamma) * (
        np.sin(x / gamma) * np.cos(x + nu) + gamma * np.sin(x + nu) * (1.0 + np.cos(x / gamma))
    )


def _mp_peak(gamma: float, nu: float) -> float:
    """Largest abs(acceleration) of :func:`_mp_shape` over its support, from a fine grid
    polished by parabolic interpolation (relative error below 1e-10)."""
    tau = np.linspace(-gamma / 2.0, gamma / 2.0, 20001)
    a = np.abs(_mp_shape(tau, gamma, nu))
    k = int(np.clip(np.argmax(a), 1, tau.size - 2))
    h = tau[1] - tau[0]
    for _ in range(3):  # refine around the grid's largest value
        tau = np.linspace(tau[k] - h, tau[k] + h, 201)
        a = np.abs(_mp_shape(tau, gamma, nu))
        k = int(np.clip(np.argmax(a), 1, tau.size - 2))
        h = tau[1] - tau[0]
    return float(a[k])


def pulse_duration(shape: str, period: float, *, gamma: float | None = None) -> float:
    """Length [s] of the pulse ``shape`` of period ``period`` [s] (without tail): T_p/2 for
    ``half-sine``, T_p for the one-cycle shapes and ``rectangular``, 4·T_p for the Ricker
    wavelets, γ·T_p for ``mavroeidis-papageorgiou``."""
    name, params = parse_pulse(shape)
    period = positive("period", period, "s")
    if name == "half-sine":
        return 0.5 * period
    if name.startswith("ricker"):
        return 2.0 * RICKER_HALF_SPAN * period
    if name == "mavroeidis-papageorgiou":
        return _mp_gamma(params, gamma) * period
    return period


def _mp_gamma(params: dict[str, float], gamma: float | None) -> float:
    value = gamma if gamma is not None else params.get("gamma", MP_GAMMA)
    value = positive("gamma", value, "-")
    if value <= 1.0:
        raise InputError(f"gamma of the Mavroeidis-Papageorgiou pulse must be > 1, got {value:g}")
    return value


def pulse(
    shape: str,
    amplitude: float,
    period: float,
    dt: float,
    *,
    tail: float = 0.0,
    gamma: float | None = None,
    nu: float | None = None,
) -> np.ndarray:
    """Acceleration history [m/s²] of an idealised pulse (formulas: :mod:`rocking.motions.pulses`).

    Parameters
    ----------
    shape : str
        One of :data:`rocking.defaults.PULSE_SHAPES`; ``mavroeidis-papageorgiou`` may carry its
        parameters, ``"mavroeidis-papageorgiou:gamma=2.5,nu=1.57"`` (see :func:`parse_pulse`).
    amplitude : float
        a_p [m/s²], the largest abs(acceleration) of the pulse (may be negative: the pulse
        mirrored).
    period : float
        T_p [s], > 0 (ω_p = 2π/T_p); the duration t_d for ``rectangular``.
    dt : float
        Sample interval [s], > 0.
    tail : float
        Time [s] of zero acceleration appended after the pulse (free rocking), ≥ 0.
    gamma, nu : float, optional
        Mavroeidis & Papageorgiou's γ [-] (> 1; default :data:`MP_GAMMA`) and ν [rad] (in
        [−2π, 2π]; default :data:`MP_NU`); only for that shape.

    Returns
    -------
    ndarray
        a(k·dt) [m/s²] for k = 0 … up to the end of the pulse plus ``tail``.
    """
    name, params = parse_pulse(shape)
    if name != "mavroeidis-papageorgiou" and (gamma is not None or nu is not None):
        raise InputError(
            f"gamma and nu are parameters of the mavroeidis-papageorgiou pulse, not {name}"
        )
    a_p = in_range("amplitude", amplitude, -math.inf, math.inf, unit="m/s²")
    period = positive("period", period, "s")
    dt = positive("dt", dt, "s")
    tail = in_range("tail", tail, 0.0, math.inf, unit="s")
    length = pulse_duration(shape, period, gamma=gamma)
    n_pulse = math.floor(length / dt * (1.0 + 1e-12)) + 1  # samples on [0, length]
    n_total = math.floor((length + tail) / dt * (1.0 + 1e-12)) + 1
    if n_total > 100_000_000:
        raise InputError(
            f"pulse of {length + tail:g} s at dt = {dt:g} s would have {n_total} samples; "
            "use a larger dt or a shorter tail"
        )
    t = np.arange(n_pulse) * dt
    on_end = abs(t[-1] - length) <= 1e-9 * dt  # the pulse's end falls on a sample
    w = 2.0 * math.pi / period
    if name == "half-sine" or name == "one-sine":
        a = np.sin(w * t)
    elif name == "one-cosine":
        a = np.cos(w * t)
    elif name == "rectangular":
        a = np.ones_like(t)
    elif name == "ricker":
        tau = (t - RICKER_HALF_SPAN * period) / period
        a = (1.0 - 2.0 * math.pi**2 * tau**2) * np.exp(-(math.pi**2) * tau**2)
    elif name == "ricker-antisymmetric":
        x = 2.0 * math.pi * (t - RICKER_HALF_SPAN * period) / (math.sqrt(3.0) * period)
        x2 = 3.0 - math.sqrt(6.0)  # x² at the largest abs value, a root of x⁴ − 6x² + 3
        beta = math.sqrt(x2) * (3.0 - x2) * math.exp(-x2 / 2.0)
        a = (x**2 - 3.0) * x * np.exp(-(x**2) / 2.0) / beta
    else:
        g_mp = _mp_gamma(params, gamma)
        nu_mp = nu if nu is not None else params.get("nu", MP_NU)
        nu_mp = in_range("nu", nu_mp, -2.0 * math.pi, 2.0 * math.pi, unit="rad")
        tau = t / period - g_mp / 2.0
        a = _mp_shape(tau, g_mp, nu_mp) / _mp_peak(g_mp, nu_mp)
    if on_end and name in ("one-cosine", "rectangular"):
        a[-1] *= 0.5  # half the jump at the end: the exact impulse for the linear interpolant
    elif on_end:
        a[-1] = 0.0  # sin(2π), sin(π), the wavelets' ends: exactly zero
    out = np.zeros(n_total)
    out[:n_pulse] = a_p * a
    return out
