"""Pulse-like records and their pulse period (issue 46): :func:`pulse_period`.

The method of Shahi & Baker (2014), "An efficient algorithm to identify strong-velocity pulses
in multicomponent ground motions", Bull. Seism. Soc. Am. 104(5), 2456–2466, which refines Baker
(2007), "Quantitative classification of near-fault ground motions using wavelet analysis",
Bull. Seism. Soc. Am. 97(5), 1486–1501, applied to the one component given:

1. the ground velocity v(t) is the cumulative trapezoid integral of the acceleration;
2. its continuous wavelet transform C(s, b) = ∫ v(t)·ψ((t − b)/s)/√s dt with the Daubechies
   wavelet of order 4 (db4: eight coefficients), at scales s [s] whose pseudo-periods
   T = s/f_c span 0.25–15 s, with f_c = 5/7 ≈ 0.7143 (:data:`CENTRE_FREQUENCY`);
3. the wavelet of the largest abs(C) is the pulse's first part; nine more wavelets of the same
   scale, each the largest within ±0.4·s of the first, are taken from what is left (a matching
   pursuit); their sum is the pulse, T_p the pseudo-period of their scale;
4. the record is pulse-like when the score −7.817 − 0.5679·P² − 0.1516·V² − 3.0253·P − 1.7396·V
   − 2.7156·P·V > 0, with P = (PC − 1.208421)/0.2462717, V = (PGV [cm/s] − 11.58861)/18.88015 and
   PC = 0.63·(PGV of the residual/PGV) + 0.777·(energy of the residual/energy), energy = ∫v² dt,
   and the pulse is not late: the record has not yet reached 17 % of its energy when the pulse
   reaches 5 % of its own.

Shahi & Baker rotate two horizontal components to the orientation of the largest coefficient
first; with one component that step is absent (give the component to test, e.g. the
fault-normal one).  PyWavelets is not needed: the db4 wavelet is computed here from its eight
published filter coefficients (Daubechies 1992, "Ten lectures on wavelets", Table 6.1, N = 4)
by the cascade (dyadic refinement) algorithm, and the transform by FFT convolution (SciPy).
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from functools import cache

import numpy as np
from scipy.integrate import cumulative_trapezoid
from scipy.signal import fftconvolve

from ..core.checks import finite_array, positive
from ..errors import InputError

#: Daubechies (1992) db4 low-pass filter, Table 6.1 (N = 4), normalised to sum √2.
DB4 = (
    0.2303778133088964,
    0.7148465705529154,
    0.6308807679298587,
    -0.0279837694168599,
    -0.1870348117190931,
    0.0308413818355607,
    0.0328830116668852,
    -0.0105974017850690,
)
#: Range of pulse periods searched [s] and number of scales (Shahi & Baker 2014).
PERIOD_RANGE = (0.25, 15.0)
N_SCALES = 50
#: Wavelets summed into the pulse, and the window (in scales s) around the first.
N_WAVELETS = 10
WINDOW = 0.4
_LEVELS = 10  # dyadic refinements of the cascade: ψ on a grid of 2^-10
#: Centre frequency of db4 [cycles per unit of x] that defines the pseudo-period T = s/f_c:
#: 5/7, the value MATLAB's ``centfrq('db4')`` gives (0.7143: the largest bin of the FFT of ψ
#: over its support of length 7, bins 1/7 apart) and with which Shahi & Baker's periods were
#: computed; abs(Ψ) itself peaks at 0.6986 (:func:`db4_wavelet`), 2.2 % lower.
CENTRE_FREQUENCY = 5.0 / 7.0


@cache
def db4_wavelet() -> tuple[np.ndarray, np.ndarray, float]:
    """The db4 wavelet ψ on a fine grid x ∈ [−3.5, 3.5] (centred support of length 7), with
    ∫ψ² dx = 1, and the frequency at which abs(Ψ(f)) peaks [cycles per unit x].

    Cascade algorithm: φ at the integers is the eigenvector of the refinement matrix
    √2·h[2i − j] of eigenvalue 1 (sum 1); each refinement halves the grid,
    φ(y) = √2·Σ h_m·φ(2y − m); finally ψ(y) = √2·Σ g_m·φ(2y − m), g_m = (−1)^m·h[7 − m].
    """
    h = np.array(DB4)
    n = h.size
    T = np.zeros((n, n))
    for i in range(n):
        for j in range(n):
            if 0 <= 2 * i - j < n:
                T[i, j] = math.sqrt(2.0) * h[2 * i - j]
    w, v = np.linalg.eig(T)
    phi = np.real(v[:, np.argmin(np.abs(w - 1.0))])
    phi /= phi.sum()  # φ at x = 0 … 7
    for level in range(_LEVELS):
        step = 2**level  # grid spacing 2^-level on entry: φ at k/2^level, k = 0 … 7·2^level
        finer = np.zeros(7 * 2 * step + 1)
        k = np.arange(finer.size)
        for m in range(n):
            idx = k - m * step  # 2y − m on the coarse grid, y = k/2^(level+1)
            ok = (idx >= 0) & (idx < phi.size)
            finer[ok] += math.sqrt(2.0) * h[m] * phi[idx[ok]]
        phi = finer
    size = 2**_LEVELS
    g = np.array([(-1) ** m * h[n - 1 - m] for m in range(n)])
    k = np.arange(7 * size + 1)
    psi = np.zeros(k.size)
    for m in range(n):
        idx = 2 * k - m * size
        ok = (idx >= 0) & (idx < phi.size)
        psi[ok] += math.sqrt(2.0) * g[m] * phi[idx[ok]]
    x = k / size - 3.5
    psi /= math.sqrt(np.trapezoid(psi**2, x))
    spec = np.abs(np.fft.rfft(psi, 64 * psi.size))
    f = np.fft.rfftfreq(64 * psi.size, 1.0 / size)
    return x, psi, float(f[np.argmax(spec)])


@dataclass(frozen=True)
class VelocityPulse:
    """The largest velocity pulse of a record (:func:`pulse_period`).

    Attributes
    ----------
    pulse_like : bool
        Whether the record is pulse-like: positive score and not late.
    period : float
        Pseudo-period T_p of the pulse [s] (reported whether or not the record is pulse-like).
    score : float
        Shahi & Baker's (2014) classification score (> 0: pulse).
    late : bool
        The pulse arrives late (the record has 17 % of its energy when the pulse has 5 %).
    pgv : float
        PGV of the record [m/s].
    pgv_ratio, energy_ratio : float
        PGV and energy ∫v² dt of the residual (record − pulse) over those of the record [-].
    velocity, pulse : ndarray
        The record's velocity and the extracted pulse [m/s] at its samples.
    dt : float
        Sample interval [s].
    """

    pulse_like: bool
    period: float
    score: float
    late: bool
    pgv: float
    pgv_ratio: float
    energy_ratio: float
    velocity: np.ndarray
    pulse: np.ndarray
    dt: float


def _coefficients(v: np.ndarray, dt: float, s: float) -> tuple[np.ndarray, np.ndarray]:
    """C(s, b) at b = every sample [m/s·√s], and the wavelet sampled at dt (centred, odd)."""
    x, psi, _peak = db4_wavelet()
    half = int(3.5 * s / dt)
    tk = np.arange(-half, half + 1) * dt
    w = np.interp(tk / s, x, psi, left=0.0, right=0.0) / math.sqrt(s)
    # correlation of v with the wavelet centred at each sample
    return fftconvolve(v, w[::-1], mode="same") * dt, w


def _sample_wavelet(n: int, centre: int, w: np.ndarray) -> np.ndarray:
    """The sampled wavelet ``w`` centred at sample ``centre`` of a record of ``n`` samples."""
    out = np.zeros(n)
    half = w.size // 2
    lo, hi = max(0, centre - half), min(n, centre + half + 1)
    out[lo:hi] = w[lo - centre + half : hi - centre + half]
    return out


def pulse_period(record, dt: float | None = None) -> VelocityPulse:
    """Whether a record is pulse-like and its pulse period, by Shahi & Baker (2014) (see
    :mod:`rocking.motions.wavelets`).

    Parameters
    ----------
    record : Record or array_like
        A :class:`rocking.Record` (its ``acc`` [m/s²] and ``dt``) or ground accelerations
        [m/s²] (then ``dt`` is needed).
    dt : float, optional
        Sample interval [s] of an array.

    Returns
    -------
    VelocityPulse
    """
    if hasattr(record, "acc") and hasattr(record, "dt"):
        acc, step = record.acc, record.dt
        if dt is not None and not math.isclose(positive("dt", dt, "s"), step):
            raise InputError(f"dt = {dt:g} s differs from the record's {step:g} s")
    else:
        if dt is None:
            raise InputError("dt [s] is needed with an array of accelerations")
        acc, step = record, dt
    step = positive("dt", step, "s")
    acc = finite_array("record", acc, ndim=(1,), min_len=2)
    v = cumulative_trapezoid(acc, dx=step, initial=0.0)
    pgv = float(np.abs(v).max())
    if pgv == 0.0:
        raise InputError("record: the ground velocity is zero everywhere; no pulse to find")
    fc = CENTRE_FREQUENCY
    duration = (acc.size - 1) * step
    t_max = min(PERIOD_RANGE[1], duration)
    if t_max <= PERIOD_RANGE[0]:
        raise InputError(
            f"record: {duration:g} s is too short for pulses of {PERIOD_RANGE[0]:g} s or longer"
        )
    periods = np.linspace(PERIOD_RANGE[0], t_max, N_SCALES)
    best = (0.0, 0, 0.0)
    for period in periods:
        c, _w = _coefficients(v, step, period * fc)
        k = int(np.argmax(np.abs(c)))
        if abs(c[k]) > best[0]:
            best = (abs(c[k]), k, period)
    # refine the period between the neighbouring scales
    spacing = periods[1] - periods[0]
    for period in np.linspace(best[2] - spacing, best[2] + spacing, 21):
        if PERIOD_RANGE[0] <= period <= t_max:
            c, _w = _coefficients(v, step, period * fc)
            k = int(np.argmax(np.abs(c)))
            if abs(c[k]) > best[0]:
                best = (abs(c[k]), k, period)
    _c0, centre, t_p = best
    s = t_p * fc
    window = max(1, math.ceil(WINDOW * s / step))
    pulse = np.zeros_like(v)
    for _ in range(N_WAVELETS):
        c, w = _coefficients(v - pulse, step, s)
        lo, hi = max(0, centre - window), min(v.size, centre + window + 1)
        k = lo + int(np.argmax(np.abs(c[lo:hi])))
        pulse += c[k] * _sample_wavelet(v.size, k, w)
    resid = v - pulse
    pgv_ratio = float(np.abs(resid).max()) / pgv
    energy_ratio = float(np.sum(resid**2) / np.sum(v**2))
    pc = 0.63 * pgv_ratio + 0.777 * energy_ratio
    P = (pc - 1.208421) / 0.2462717
    V = (100.0 * pgv - 11.58861) / 18.88015  # PGV in cm/s
    score = -7.817 - 0.5679 * P**2 - 0.1516 * V**2 - 3.0253 * P - 1.7396 * V - 2.7156 * P * V
    e_record = np.cumsum(v**2) / np.sum(v**2)
    e_pulse = np.cumsum(pulse**2) / np.sum(pulse**2)
    k5 = max(0, int(np.searchsorted(e_pulse, 0.05, side="right")) - 1)  # last sample ≤ 5 %
    late = bool(e_record[k5] >= 0.17)
    return VelocityPulse(
        pulse_like=bool(score > 0.0 and not late),
        period=float(t_p),
        score=float(score),
        late=late,
        pgv=pgv,
        pgv_ratio=pgv_ratio,
        energy_ratio=energy_ratio,
        velocity=v,
        pulse=pulse,
        dt=step,
    )
