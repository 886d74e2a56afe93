"""Intensity (envelope) functions I(t) of simulated motions (paper Fig. 2 and Eq. 7).

Three shapes, each a small frozen dataclass that is called on times [s] and returns I(t) [-],
zero outside [0, T]:

* :class:`Boxcar` — I = 1 on [0, T].
* :class:`Trapezoidal` — linear rise over ``rise`` [s], plateau, linear decay to 0 at T over
  ``decay`` [s].
* :class:`Compound` — Jennings, Housner & Tsai (1968): (t/t1)² for t < t1, 1 for t1 ≤ t ≤ t2,
  exp(−c·(t − t2)) for t2 < t ≤ T.

The paper varies the total duration T from 10 to 30 s without saying how the shapes change with
it. Rule used here (:func:`make_envelope` with no explicit parameters), proportional to T:

* trapezoidal: rise = 0.1·T, decay = 0.3·T;
* compound: t1 = 0.1·T, t2 = 0.6·T and c chosen so that I(T) = exp(−2) ≈ 0.135, i.e.
  c = 2/(0.4·T) = 5/T. For T = 20 s this is the common default t1 = 2 s, t2 = 12 s, c = 0.25 /s.

Any parameter can be given explicitly instead (``make_envelope("compound", 20, c=0.3)``).
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from ..core import portable
from ..core.checks import in_range, positive
from ..errors import InputError

#: Fractions of the duration T used by :func:`make_envelope` when a parameter is not given.
TRAPEZOID_RISE_FRACTION = 0.1
TRAPEZOID_DECAY_FRACTION = 0.3
COMPOUND_T1_FRACTION = 0.1
COMPOUND_T2_FRACTION = 0.6
#: Compound decay: c is chosen so that I(T) = exp(−COMPOUND_END_EXPONENT).
COMPOUND_END_EXPONENT = 2.0


def _inside(t: np.ndarray, duration: float) -> np.ndarray:
    return (t >= 0.0) & (t <= duration)


@dataclass(frozen=True)
class Boxcar:
    """Rectangular intensity function: I = 1 on [0, T], 0 elsewhere.

    Parameters
    ----------
    duration : float
        Total duration T [s], > 0.
    """

    duration: float

    def __post_init__(self):
        object.__setattr__(self, "duration", positive("duration", self.duration, "s"))

    def __call__(self, t) -> np.ndarray:
        """Intensity I(t) [-] at times ``t`` [s]."""
        t = np.asarray(t, dtype=float)
        return np.where(_inside(t, self.duration), 1.0, 0.0)

    def equivalent_duration(self) -> float:
        """Equivalent duration T_e = ∫I dτ / max I = T [s] (Eq. 7)."""
        return self.duration

    def params(self) -> dict:
        """Shape parameters besides the duration (none) [s, 1/s]."""
        return {}


@dataclass(frozen=True)
class Trapezoidal:
    """Trapezoidal intensity function: linear rise, plateau of 1, linear decay to 0 at T.

    Parameters
    ----------
    duration : float
        Total duration T [s], > 0.
    rise : float
        Rise time from 0 to 1 [s], ≥ 0.
    decay : float
        Decay time from 1 to 0, ending at T [s], ≥ 0, with rise + decay ≤ T.
    """

    duration: float
    rise: float
    decay: float

    def __post_init__(self):
        T = positive("duration", self.duration, "s")
        object.__setattr__(self, "duration", T)
        object.__setattr__(self, "rise", in_range("rise", self.rise, 0.0, T, unit="s"))
        object.__setattr__(
            self, "decay", in_range("decay", self.decay, 0.0, T - self.rise, unit="s")
        )

    def __call__(self, t) -> np.ndarray:
        """Intensity I(t) [-] at times ``t`` [s]."""
        t = np.asarray(t, dtype=float)
        T, r, d = self.duration, self.rise, self.decay
        with np.errstate(divide="ignore", invalid="ignore"):
            up = np.where(t < r, t / r, 1.0) if r > 0 else np.ones_like(t)
            down = np.where(t > T - d, (T - t) / d, 1.0) if d > 0 else np.ones_like(t)
        return np.where(_inside(t, T), np.minimum(up, down), 0.0)

    def equivalent_duration(self) -> float:
        """Equivalent duration T_e = T − rise/2 − decay/2 [s] (Eq. 7 in closed form)."""
        return self.duration - 0.5 * (self.rise + self.decay)

    def params(self) -> dict:
        """Shape parameters besides the duration: ``rise``, ``decay`` [s]."""
        return {"rise": self.rise, "decay": self.decay}


@dataclass(frozen=True)
class Compound:
    """Compound intensity function of Jennings, Housner & Tsai (1968).

    I = (t/t1)² for 0 ≤ t < t1; 1 for t1 ≤ t ≤ t2; exp(−c·(t − t2)) for t2 < t ≤ T; 0 elsewhere.

    Parameters
    ----------
    duration : float
        Total duration T [s], > 0.
    t1 : float
        End of the quadratic rise [s], 0 ≤ t1 ≤ t2.
    t2 : float
        Start of the exponential decay [s], t1 ≤ t2 ≤ T.
    c : float
        Decay rate [1/s], ≥ 0.
    """

    duration: float
    t1: float
    t2: float
    c: float

    def __post_init__(self):
        T = positive("duration", self.duration, "s")
        object.__setattr__(self, "duration", T)
        object.__setattr__(self, "t2", in_range("t2", self.t2, 0.0, T, unit="s"))
        object.__setattr__(self, "t1", in_range("t1", self.t1, 0.0, self.t2, unit="s"))
        object.__setattr__(self, "c", in_range("c", self.c, 0.0, math.inf, unit="1/s"))

    def __call__(self, t) -> np.ndarray:
        """Intensity I(t) [-] at times ``t`` [s]."""
        t = np.asarray(t, dtype=float)
        t1, t2, c = self.t1, self.t2, self.c
        with np.errstate(divide="ignore", invalid="ignore", over="ignore"):
            rise = (t / t1) ** 2 if t1 > 0 else np.ones_like(t)
            i = np.where(t < t1, rise, np.where(t <= t2, 1.0, portable.exp(-c * (t - t2))))
        return np.where(_inside(t, self.duration), i, 0.0)

    def equivalent_duration(self) -> float:
        """Equivalent duration T_e [s] (Eq. 7 in closed form, max I = 1).

        T_e = t1/3 + (t2 − t1) + (1 − exp(−c·(T − t2)))/c  (the last term is T − t2 when c = 0).
        """
        tail = self.duration - self.t2
        decay = tail if self.c == 0.0 else -math.expm1(-self.c * tail) / self.c
        return self.t1 / 3.0 + (self.t2 - self.t1) + decay

    def params(self) -> dict:
        """Shape parameters besides the duration: ``t1``, ``t2`` [s] and ``c`` [1/s]."""
        return {"t1": self.t1, "t2": self.t2, "c": self.c}


Envelope = Boxcar | Trapezoidal | Compound

ENVELOPES = {"boxcar": Boxcar, "trapezoidal": Trapezoidal, "compound": Compound}


def _default_params(name: str, T: float) -> dict:
    """The duration rule of the module docstring, in [s] and [1/s]."""
    if name == "trapezoidal":
        return {"rise": TRAPEZOID_RISE_FRACTION * T, "decay": TRAPEZOID_DECAY_FRACTION * T}
    if name == "compound":
        t2 = COMPOUND_T2_FRACTION * T
        return {"t1": COMPOUND_T1_FRACTION * T, "t2": t2, "c": COMPOUND_END_EXPONENT / (T - t2)}
    return {}


def make_envelope(name: str, duration: float, **params: float) -> Envelope:
    """Intensity function by name, with parameters scaled to ``duration`` unless given.

    Parameters
    ----------
    name : str
        ``"boxcar"``, ``"trapezoidal"`` or ``"compound"``.
    duration : float
        Total duration T [s], > 0.
    **params
        Explicit shape parameters overriding the duration rule of the module docstring:
        ``rise``, ``decay`` [s] (trapezoidal); ``t1``, ``t2`` [s], ``c`` [1/s] (compound).

    Returns
    -------
    Boxcar, Trapezoidal or Compound
    """
    key = str(name).lower()
    if key not in ENVELOPES:
        raise InputError(f"envelope must be one of {', '.join(ENVELOPES)}, got {name!r}")
    T = positive("duration", duration, "s")
    defaults = _default_params(key, T)
    unknown = set(params) - set(defaults)
    if unknown:
        allowed = ", ".join(defaults) or "none"
        raise InputError(
            f"unknown parameter(s) {', '.join(sorted(unknown))} for the {key} "
            f"envelope (allowed: {allowed})"
        )
    return ENVELOPES[key](T, **{**defaults, **params})
