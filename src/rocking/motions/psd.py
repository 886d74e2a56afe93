"""Power spectral density compatible with a target response spectrum (paper Section 3, Eqs. 4–8).

Park's (1995) method as used by the paper: the PSD is a sum of m power components p_j at
log-spaced frequencies ω_j (Eq. 4); the squared target spectral accelerations at n frequencies
ω_k are fitted by non-negative least squares (Eq. 5) with the peak response of a damped oscillator
to each component estimated by Davenport's peak factor times the harmonic transfer function
(Eq. 6) over the equivalent duration T_e of the intensity function (Eq. 7); S(ω_j) = p_j/Δω_j
(Eq. 8) and A_j are the amplitudes of Eq. (9).

Conventions fixed here because the paper is silent or inconsistent:

* Frequencies: ω_j = 2π·f_j with f_j log-spaced from ``fmin`` to ``fmax`` (both included); the
  fit uses the same frequencies for ω_k and ω_j (the paper's n = m = 100).
* Δω_j = ω_j − ω_{j−1} (the paper's ω_j = ω_{j−1} + Δω_j), with ω_0 = ω_1/r, r = ω_2/ω_1, i.e.
  the log-spaced sequence continued one step down; so Δω_j = ω_j·(1 − 1/r) for every j. Δω_j only
  enters S = p/Δω, not the amplitudes.
* Amplitudes: Eq. (5) treats p_j as the variance that component j contributes (peak = peak
  factor × sqrt(Σ p_j·R²)), so S = p/Δω of Eq. (8) is a one-sided PSD and a sinusoid of variance
  p_j has A_j = sqrt(2·S·Δω) = sqrt(2·p_j) (``convention="one-sided"``, the default). The paper
  prints A_j = sqrt(4·S·Δω), the two-sided formula, which makes every motion √2 stronger
  (``convention="as-printed"``). Simulated ensembles confirm the one-sided rule (tests/test_psd.py).
* Peak factor: Eq. (6) prints 5.772 as the constant of Davenport's (1964) formula; Davenport's
  own constant is Euler's γ = 0.5772 (the default, :data:`DAVENPORT_CONSTANT`), which matches
  the expected peak of a Gaussian process within 1 % for ≥ 100 cycles, where 5.772 is 22–54 %
  too large. With both printed values (5.772 and √4) RG 1.60 motions fall well short of the
  target at low frequencies (tests/test_psd.py compares their peak PSV with the paper's).
* Davenport's formula is asymptotic in ν·T_e (number of zero up-crossings) and diverges as
  ν·T_e → 1; below the argument x* = exp(c/2) at which it is smallest (c the constant), the
  value at x* is used, so the peak factor never increases as ν·T_e decreases.
"""

from __future__ import annotations

import math
from collections.abc import Callable
from dataclasses import dataclass
from typing import Protocol, runtime_checkable

import numpy as np
from numpy.typing import ArrayLike
from scipy.optimize import nnls

from ..core import portable
from ..core.checks import finite_array, in_range, positive
from ..dynamics.body import G
from ..errors import InputError


@runtime_checkable
class SupportsPsa(Protocol):
    """A target spectrum: anything with a ``psa(freqs_hz)`` method giving the PSA [g] (a
    :class:`rocking.motions.targets.TargetSpectrum`, or a user's own class)."""

    def psa(self, freqs_hz: np.ndarray, /) -> ArrayLike:
        """PSA [g] at the frequencies ``freqs_hz`` [Hz]."""
        ...


#: Euler's constant as used by Davenport (1964) in his peak factor.
DAVENPORT_CONSTANT = 0.5772156649015329
#: The constant as printed in the paper's Eq. (6).
PAPER_CONSTANT = 5.772
#: Constant used by default (the one that reproduces the target; see the module docstring).
DEFAULT_PEAK_CONSTANT = DAVENPORT_CONSTANT
#: A_j² / p_j for each amplitude convention (see the module docstring).
CONVENTIONS = {"one-sided": 2.0, "as-printed": 4.0}


@dataclass(frozen=True, eq=False)
class PowerSpectrum:
    """Discretised PSD of ground acceleration and the amplitudes of Eq. (9).

    Attributes
    ----------
    freqs_hz : ndarray
        Component frequencies f_j [Hz].
    omega : ndarray
        Circular frequencies ω_j = 2π·f_j [rad/s].
    domega : ndarray
        Frequency increments Δω_j [rad/s] (see the module docstring).
    p : ndarray
        Power components p_j [(m/s²)²] (Eq. 4).
    S : ndarray
        Equivalent one-sided PSD S(ω_j) = p_j/Δω_j [(m/s²)²·s/rad] (Eq. 8).
    amplitudes : ndarray
        Component amplitudes A_j = sqrt(2·p_j) or sqrt(4·p_j) [m/s²] (Eq. 9, see
        ``convention``).
    equivalent_duration : float
        T_e used in the peak factor [s] (Eq. 7).
    damping : float
        Damping ratio h of the target spectrum [-].
    convention : str
        ``"one-sided"`` or ``"as-printed"`` (see the module docstring).
    """

    freqs_hz: np.ndarray
    omega: np.ndarray
    domega: np.ndarray
    p: np.ndarray
    S: np.ndarray
    amplitudes: np.ndarray
    equivalent_duration: float
    damping: float
    convention: str

    @classmethod
    def from_amplitudes(
        cls,
        freqs_hz: ArrayLike,
        amplitudes: ArrayLike,
        equivalent_duration: float,
        damping: float,
        convention: str = "one-sided",
    ) -> PowerSpectrum:
        """Spectrum whose component amplitudes are ``amplitudes`` [m/s²] at ``freqs_hz`` [Hz].

        p_j = A_j²/2 (one-sided) or A_j²/4 (as printed) and S = p/Δω (Eq. 8), Δω as in the
        module docstring; ``equivalent_duration`` [s], ``damping`` [-] are carried along.
        """
        factor = _convention_factor(convention)
        freqs = np.asarray(freqs_hz, dtype=float)
        amps = np.asarray(amplitudes, dtype=float)
        omega = 2.0 * np.pi * freqs
        domega = frequency_increments(omega)
        p = amps**2 / factor
        return cls(
            freqs, omega, domega, p, p / domega, amps, equivalent_duration, damping, convention
        )


def _convention_factor(convention: str) -> float:
    try:
        return CONVENTIONS[convention]
    except (KeyError, TypeError):
        raise InputError(
            f"convention must be one of {', '.join(CONVENTIONS)}, got {convention!r}"
        ) from None


def _nonnegative_solution(a: np.ndarray, b: np.ndarray) -> np.ndarray:
    """x ≥ 0 of least ‖a·x − b‖: ``scipy.optimize.nnls`` finds which x_j are positive, and the
    least squares on those columns is then recomputed by :func:`rocking.core.portable.lstsq`
    (nnls's arithmetic runs through BLAS kernels chosen by the CPU, so its last bits vary from
    machine to machine; the set of positive components does not)."""
    x, _ = nnls(a, b)
    positive_j = np.flatnonzero(x > 0.0)
    out = np.zeros_like(x)
    if positive_j.size:
        # nnls's solution is the unconstrained least squares on its positive columns; rounding
        # could only take a component a few ulp below zero, hence the clip
        out[positive_j] = np.maximum(portable.lstsq(a[:, positive_j], b), 0.0)
    return out


def log_frequencies(n_freq: int = 100, fmin: float = 0.15, fmax: float = 50.0) -> np.ndarray:
    """``n_freq`` frequencies [Hz] equally spaced on a log scale from ``fmin`` to ``fmax`` [Hz]."""
    n = int(n_freq)
    if n != n_freq or n < 2:
        raise InputError(f"n_freq must be an integer ≥ 2, got {n_freq!r}")
    lo = positive("fmin", fmin, "Hz")
    hi = positive("fmax", fmax, "Hz")
    if hi <= lo:
        raise InputError(f"fmax must exceed fmin, got fmin={fmin!r} Hz, fmax={fmax!r} Hz")
    return portable.geomspace(lo, hi, n)


def frequency_increments(omega: np.ndarray) -> np.ndarray:
    """Δω_j = ω_j − ω_{j−1} [rad/s] for log-spaced ω [rad/s], with ω_0 = ω_1²/ω_2."""
    ratio = omega[1] / omega[0]
    return omega * (1.0 - 1.0 / ratio)


def peak_factor(nu_te: ArrayLike, constant: float = DEFAULT_PEAK_CONSTANT) -> np.ndarray:
    """Davenport's (1964) peak factor, first factor of Eq. (6) [-].

    r = sqrt(2·ln(ν·T_e)) + constant/sqrt(2·ln(ν·T_e)), evaluated at max(ν·T_e, exp(constant/2)),
    the argument of its minimum 2·sqrt(constant), so it never grows as ν·T_e falls (the
    asymptotic formula diverges at ν·T_e = 1).

    Parameters
    ----------
    nu_te : array_like
        Expected number of cycles ν·T_e [-] (ν [Hz], T_e [s]).
    constant : float
        0.5772 (Davenport, Euler's constant; default) or 5.772 (as printed in the paper) [-].
    """
    c = positive("constant", constant)
    x = np.maximum(np.asarray(nu_te, dtype=float), math.exp(0.5 * c))
    s = np.sqrt(2.0 * portable.log(x))
    return s + c / s  # Eq. (6), first factor


def transfer(omega_k: ArrayLike, omega_j: ArrayLike, damping: float) -> np.ndarray:
    """Peak absolute-acceleration response of an oscillator to a unit sinusoid, Eq. (6) [-].

    sqrt((1 + 4h²x²) / ((1 − x²)² + 4h²x²)) with x = ω_j/ω_k; broadcasting ``omega_k`` (oscillator)
    against ``omega_j`` (excitation), both [rad/s]; ``damping`` h [-].
    """
    x2 = (np.asarray(omega_j, dtype=float) / np.asarray(omega_k, dtype=float)) ** 2
    h2 = damping**2
    return np.sqrt((1.0 + 4.0 * h2 * x2) / ((1.0 - x2) ** 2 + 4.0 * h2 * x2))  # Eq. (6)


def target_psa(
    target: SupportsPsa | Callable[..., ArrayLike],
    freqs_hz: ArrayLike,
    damping: float | None = None,
) -> tuple[np.ndarray, float]:
    """Target pseudo-spectral accelerations [g] at ``freqs_hz`` [Hz] and their damping [-].

    ``target`` is anything with a ``psa(freqs_hz)`` method (a
    ``rocking.motions.targets.TargetSpectrum``)
    or a function ``f(freqs_hz, damping=...)`` such as ``rocking.motions.targets.rg160``.
    ``damping``
    defaults to the target's own ``damping`` attribute, else 0.05; an explicit value that
    contradicts the target's raises :class:`InputError`.
    """
    own = getattr(target, "damping", None)
    if damping is None:
        damping = 0.05 if own is None else own
    h = in_range("damping", damping, 0.0, 1.0, lo_open=True, hi_open=True)
    if own is not None and not math.isclose(own, h):
        raise InputError(
            f"damping={damping!r} contradicts the target spectrum's damping "
            f"{own!r}; the fit needs the target's damping"
        )
    freqs = np.asarray(freqs_hz, dtype=float)
    if isinstance(target, SupportsPsa):
        values = target.psa(freqs)
    elif callable(target):
        values = target(freqs, damping=h)
    else:
        raise InputError(
            "target must have a psa(freqs_hz) method or be a function "
            f"f(freqs_hz, damping=...), got {type(target).__name__}"
        )
    values = finite_array("target psa", values)
    if values.shape != freqs.shape or (values <= 0).any():
        raise InputError("target psa must give one positive value [g] per frequency")
    return values, h


def power_spectrum(
    psa_g: ArrayLike,
    freqs_hz: ArrayLike,
    equivalent_duration: float,
    *,
    damping: float = 0.05,
    peak_constant: float = DEFAULT_PEAK_CONSTANT,
    convention: str = "one-sided",
) -> PowerSpectrum:
    """PSD whose components reproduce a target spectrum, by the paper's method (Eqs. 5–8).

    Parameters
    ----------
    psa_g : array_like
        Target pseudo-spectral accelerations R_t [g] at ``freqs_hz``.
    freqs_hz : array_like
        Log-spaced frequencies f_k = f_j [Hz] (e.g. :func:`log_frequencies`), ≥ 2 values.
    equivalent_duration : float
        T_e of the intensity function [s] (Eq. 7).
    damping : float
        Damping ratio h of the target spectrum [-].
    peak_constant : float
        Constant of the peak factor (:func:`peak_factor`) [-].
    convention : str
        How amplitudes follow from the power components (see the module docstring):
        ``"one-sided"`` A_j = sqrt(2·p_j) (default) or ``"as-printed"`` A_j = sqrt(4·p_j).

    Returns
    -------
    PowerSpectrum
        With p [(m/s²)²] from ``scipy.optimize.nnls`` and A_j [m/s²] by ``convention``.
    """
    freqs = finite_array("freqs_hz", freqs_hz, min_len=2)
    rt = finite_array("psa_g", psa_g, min_len=2)
    if rt.shape != freqs.shape:
        raise InputError(f"psa_g has {rt.size} values but freqs_hz has {freqs.size}")
    if (freqs <= 0).any():
        raise InputError(f"freqs_hz must be > 0 [Hz], got {freqs[freqs <= 0][0]!r}")
    steps = np.diff(portable.log(freqs))
    if steps[0] <= 0 or not np.allclose(steps, steps[0]):
        raise InputError("freqs_hz must be increasing and equally spaced on a log scale")
    te = positive("equivalent_duration", equivalent_duration, "s")
    h = in_range("damping", damping, 0.0, 1.0, lo_open=True, hi_open=True)
    omega = 2.0 * np.pi * freqs
    r = peak_factor(freqs * te, peak_constant)  # ν_j·T_e with ν_j = ω_j/2π
    R = r[None, :] * transfer(omega[:, None], omega[None, :], h)  # R_kj, Eq. (6)
    factor = _convention_factor(convention)
    p_g = _nonnegative_solution(R**2, rt**2)  # Eq. (5): p_j of Eq. (4) in g² (converted below)
    amplitudes = np.sqrt(factor * p_g) * G  # Eqs. (8)–(9)
    return PowerSpectrum.from_amplitudes(freqs, amplitudes, te, h, convention)
