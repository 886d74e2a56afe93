"""Spectrum-compatible simulation of ground motions (paper Section 3): :func:`generate`.

* :func:`generate` — ``n`` motions a(t) = I(t)·Σ_j A_j·sin(ω_j·t + φ_j) (Eq. 9) with amplitudes
  from :func:`rocking.motions.psd.power_spectrum` (Eqs. 5–8), optionally refined by an iterative
  correction (PSD iteration and peak limiting, :func:`limit_peaks`), and baseline corrected
  (:func:`rocking.motions.baseline.baseline_correct`).
* :func:`spectral_fit` — how the ensemble-mean PSA fits the target.

Reproducibility: member k draws its phases from its own stream,
``default_rng(SeedSequence(seed, spawn_key=(k,)))`` (the k-th child of ``SeedSequence(seed)``),
so it is the same motion whatever the ensemble size or how the work is split.

Scale: the motions are fitted to the target as given, its PSA [g] times G in m/s², so for
RG 1.60 at 1 g the ensemble-mean PSA approximates the 1-g spectrum (how closely: see
:func:`spectral_fit` and tests/test_motions.py).
"""

from __future__ import annotations

import dataclasses
import math
from collections.abc import Callable, Iterable
from dataclasses import dataclass
from fractions import Fraction
from typing import TYPE_CHECKING, Any

import numpy as np
from numpy.typing import ArrayLike

from ..core import checks, portable
from ..core.checks import finite_array, positive, require_memory
from ..core.compile import parallel_kernel, prange
from ..defaults import DT, FIT_BAND, G
from ..errors import InputError
from .baseline import baseline_correct
from .ensemble import Ensemble, _n_samples
from .envelopes import ENVELOPES, make_envelope
from .psd import DEFAULT_PEAK_CONSTANT, PowerSpectrum, log_frequencies, power_spectrum, target_psa
from .response import response_spectrum
from .targets import StoredTarget, rg160

if TYPE_CHECKING:
    from typing import Protocol

    from .psd import SupportsPsa

    class IntensityFunction(Protocol):
        """An intensity function I(t) [-] with a duration T [s] (the envelopes of
        :mod:`rocking.motions.envelopes`)."""

        @property
        def duration(self) -> float: ...

        def __call__(self, t: np.ndarray, /) -> np.ndarray: ...


#: Members synthesised per call of the compiled kernel (bounds the memory of a chunk; the
#: result does not depend on it).
CHUNK = 256


def member_phases(seed: int, members: Iterable[int], n_freq: int) -> np.ndarray:
    """Phase angles φ_kj [rad], uniform on [0, 2π), one independent stream per member index k.

    Returns shape (len(members), n_freq); row k depends only on ``seed`` and the member index.
    """
    seed = checks.seed("seed", seed)
    rows = [
        np.random.default_rng(np.random.SeedSequence(seed, spawn_key=(int(m),))).uniform(
            0.0, 2.0 * math.pi, n_freq
        )
        for m in members
    ]
    return np.array(rows).reshape(len(rows), n_freq)


#: Samples and members per tile of :func:`_superpose`: a tile's partial sums stay in the
#: first-level cache and its slice of the sine and cosine tables in the second, so the tables
#: are read from memory once per tile of samples rather than once per member (the result does
#: not depend on the tile sizes).
TILE_SAMPLES = 256
TILE_MEMBERS = 8


@parallel_kernel
def _superpose(cos_amp, sin_amp, sin_wt, cos_wt, intensity, tile_samples, tile_members):
    """out[k, i] = I_i·Σ_j (A_j cos φ_kj·sin ω_j t_i + A_j sin φ_kj·cos ω_j t_i), i.e. Eq. (9).

    Tiles of (members, samples) run in parallel; within a tile the sum over j runs in the same
    order for every member and sample (hand-written rather than a BLAS product, whose order
    may depend on the matrix sizes), so member k is bit-identical whatever the ensemble size,
    the tile sizes or the number of threads.
    """
    n, m = cos_amp.shape
    n_t = intensity.size
    out = np.empty((n, n_t))
    n_member_tiles = (n + tile_members - 1) // tile_members
    n_tiles = n_member_tiles * ((n_t + tile_samples - 1) // tile_samples)
    for tile in prange(n_tiles):
        i0 = (tile // n_member_tiles) * tile_samples
        k0 = (tile % n_member_tiles) * tile_members
        i1 = min(i0 + tile_samples, n_t)
        k1 = min(k0 + tile_members, n)
        row = np.zeros((k1 - k0, i1 - i0))
        for j in range(m):
            sin_j = sin_wt[j, i0:i1]
            cos_j = cos_wt[j, i0:i1]
            for k in range(k0, k1):
                b = cos_amp[k, j]
                c = sin_amp[k, j]
                acc = row[k - k0]
                for i in range(i1 - i0):
                    acc[i] += b * sin_j[i] + c * cos_j[i]
        for k in range(k0, k1):
            for i in range(i0, i1):
                out[k, i] = intensity[i] * row[k - k0, i - i0]
    return out


def synthesize(
    spectrum: PowerSpectrum, envelope: IntensityFunction, dt: float, phases: ArrayLike
) -> np.ndarray:
    """Motions a(t) = I(t)·Σ_j A_j·sin(ω_j·t + φ_kj) (Eq. 9) [m/s²], one per row of ``phases``.

    Parameters
    ----------
    spectrum : PowerSpectrum
        Component frequencies ω_j [rad/s] and amplitudes A_j [m/s²].
    envelope : callable
        Intensity function I(t) [-] with a ``duration`` attribute T [s] (see
        :mod:`rocking.motions.envelopes`); samples run t = 0, dt, … ≤ T.
    dt : float
        Time step [s], > 0.
    phases : array_like, shape (n, n_freq)
        Phase angles φ_kj [rad] (see :func:`member_phases`).

    Returns
    -------
    ndarray, shape (n, n_t)

    Notes
    -----
    Frequencies on a uniform grid f_j = q_j/(N·dt) (integers 0 < q_j < N/2, N at most four
    times the number of samples) are summed by one inverse real FFT of length N per motion;
    other frequencies, such as the log-spaced ones of :func:`generate`, by the direct sum in
    cache-sized tiles. Both evaluate the same sum and agree to rounding (tests/test_motions.py).
    """
    dt = positive("dt", dt, "s")
    phi = finite_array("phases", phases, ndim=(2,))
    if phi.shape[1] != spectrum.omega.size:
        raise InputError(
            f"phases has {phi.shape[1]} columns but the spectrum has "
            f"{spectrum.omega.size} frequencies"
        )
    t = np.arange(_n_samples(envelope.duration, dt)) * dt
    intensity = envelope(t)
    amp = spectrum.amplitudes
    period, bins = _fft_grid(spectrum.freqs_hz, dt, t.size)
    if bins is not None:
        # Eq. (9) on the grid f_j = q_j/(N·dt): Σ_j A_j sin(2π q_j i/N + φ_j) is the inverse
        # real FFT of length N whose bin q_j holds (N/2)·A_j·exp(i(φ_j − π/2)); N-periodic in i.
        coef = np.zeros((phi.shape[0], period // 2 + 1), dtype=complex)
        # (NumPy's complex exp is the C library's, on every CPU: no portable.* needed)
        values = 0.5 * period * amp * np.exp(1j * (phi - 0.5 * np.pi))
        for j, q in enumerate(bins):  # components sharing a bin add up
            coef[:, q] += values[:, j]
        import scipy.fft  # here, not at import: only uniform grids take this path

        stationary = scipy.fft.irfft(coef, period, axis=-1, workers=-1)
        return intensity * stationary[:, np.arange(t.size) % period]
    wt = spectrum.omega[:, None] * t
    sin_wt, cos_wt = portable.sin(wt), portable.cos(wt)
    return _superpose(
        amp * portable.cos(phi),
        amp * portable.sin(phi),
        sin_wt,
        cos_wt,
        intensity,
        TILE_SAMPLES,
        TILE_MEMBERS,
    )


def _fft_grid(freqs_hz: np.ndarray, dt: float, n_samples: int) -> tuple[int, np.ndarray | None]:
    """The period N [samples] and bins q_j of frequencies f_j = q_j/(N·dt) [Hz], 0 < q_j < N/2,
    N the least common denominator of the f_j·dt; bins None when the frequencies (e.g.
    log-spaced) do not lie on such a grid with N ≤ 4·``n_samples`` (beyond it the direct sum
    is the cheaper) to within rounding."""
    limit = 4 * n_samples
    period = math.lcm(*(Fraction(c).limit_denominator(limit).denominator for c in freqs_hz * dt))
    if period > limit:
        return period, None
    exact = freqs_hz * period * dt
    bins = np.rint(exact).astype(np.int64)
    # f_j·N·dt is q_j to within the rounding of f_j and of the product (a few ulp)
    on_grid = np.abs(exact - bins) <= 16.0 * np.finfo(float).eps * np.maximum(exact, 1.0)
    if not on_grid.all() or bins.min() <= 0 or 2 * bins.max() >= period:
        return period, None
    return period, bins


#: Clip-and-restore passes per motion in :func:`limit_peaks`, the over-relaxation of the
#: clipping (a sample above the limit is pulled this many times its excess back: the projection
#: spreads the cut over the record, so plain clipping, 1, barely lowers the peak) and the least
#: number of samples per cycle of the highest component on the coarse grid the limiting runs on
#: (the motions themselves are synthesised at ``dt``). Chosen by measuring the mean PGA after
#: limiting against the cost on RG 1.60 ensembles; tests/test_motions.py checks the result.
PEAK_LIMIT_PASSES = 30
PEAK_LIMIT_RELAXATION = 4.0
PEAK_LIMIT_SAMPLES_PER_CYCLE = 4.0


@parallel_kernel
def _limit_kernel(
    cos_amp, sin_amp, amps, free, basis, basis_t, intensity, gram_inv, limit, relaxation, passes
):
    """Clip-and-restore passes on the coefficients (A_j cos φ_kj, A_j sin φ_kj) of each member.

    basis (n_t, 2m) and basis_t (2m, n_t): sin ω_j t_i and cos ω_j t_i on the coarse grid;
    gram_inv: inverse Gram matrix of the basis. Hand-written (not BLAS) so that each member's
    sums run in one fixed order: bit-identical whatever the ensemble size, chunking or threads.
    """
    n, m = cos_amp.shape
    n_t = intensity.size
    out_cos = np.empty((n, m))
    out_sin = np.empty((n, m))
    for k in prange(n):
        x = np.empty(2 * m)
        x[:m] = cos_amp[k]
        x[m:] = sin_amp[k]
        s = np.empty(n_t)
        proj = np.empty(2 * m)
        coef = np.empty(2 * m)
        for _ in range(passes):
            s[:] = 0.0  # stationary part s(t) = Σ_j (x_j sin ω_j t + x_{m+j} cos ω_j t)
            for j in range(2 * m):
                xj = x[j]
                for i in range(n_t):
                    s[i] += xj * basis_t[j, i]
            clipped = False
            for i in range(n_t):
                a = intensity[i] * s[i]
                if abs(a) > limit:  # pull a(t) back past the limit by relaxation × excess
                    clipped = True
                    s[i] -= relaxation * (a - math.copysign(limit, a)) / intensity[i]
            if not clipped:
                break
            proj[:] = 0.0  # least-squares coefficients of the clipped s: G⁻¹·Bᵀs
            for i in range(n_t):
                si = s[i]
                for j in range(2 * m):
                    proj[j] += si * basis[i, j]
            coef[:] = 0.0
            for q in range(2 * m):
                pq = proj[q]
                for j in range(2 * m):
                    coef[j] += pq * gram_inv[q, j]
            for j in range(m):  # keep the new phase, restore the amplitude A_j
                norm = math.hypot(coef[j], coef[m + j])
                if free[j] and norm > 0.0:
                    x[j] = amps[j] * coef[j] / norm
                    x[m + j] = amps[j] * coef[m + j] / norm
        out_cos[k] = x[:m]
        out_sin[k] = x[m:]
    return out_cos, out_sin


def limit_peaks(
    spectrum: PowerSpectrum,
    envelope: IntensityFunction,
    dt: float,
    phases: ArrayLike,
    limit: float,
) -> np.ndarray:
    """Re-phase motions of Eq. (9) so that their peak acceleration stays near ``limit``.

    A motion a(t) = I(t)·Σ_j A_j·sin(ω_j t + φ_j) with independent uniform phases is nearly
    Gaussian, and its peak is about 3 standard deviations. This keeps every amplitude A_j (so the
    PSD, Eq. 8) and the envelope I(t), and changes phases only, to lower that peak factor: the
    clip-and-restore iteration used to bound the crest factor of random drive signals in
    vibration testing and of multitone signals. Each pass, on a grid of every s-th sample
    (≥ :data:`PEAK_LIMIT_SAMPLES_PER_CYCLE` samples per cycle of the highest component, where
    I > 0):

    1. samples with abs(a) > ``limit`` are pulled back past it by :data:`PEAK_LIMIT_RELAXATION`
       times their excess;
    2. the clipped stationary part a/I is projected on the components' sines and cosines (least
       squares; one Gram matrix for all motions);
    3. each component keeps its new phase and gets its amplitude A_j back.

    :data:`PEAK_LIMIT_PASSES` passes, fewer once no sample exceeds the limit. The result is a
    motion of the same amplitudes whose peak is close to ``limit`` whenever the untouched peak
    was higher (tests/test_motions.py).

    Components that complete less than one beat against their lower neighbour over the record,
    (ω_j − ω_{j−1})/2π · T < 1 (below 0.88 Hz for T = 20 s and the paper's grid), keep their
    phases: over the record they are nearly the same sinusoid, and the projection would re-phase
    them into mutual cancellation, lowering the mean PSA at low frequencies. They carry little
    of the PGA anyway.
    Components with A_j = 0 are left out.

    Parameters
    ----------
    spectrum : PowerSpectrum
        Frequencies ω_j [rad/s] and amplitudes A_j [m/s²].
    envelope : callable
        Intensity function I(t) [-] with a ``duration`` T [s].
    dt : float
        Time step of the motions [s], > 0.
    phases : array_like, shape (n, n_freq)
        Phase angles φ_kj [rad] to start from (:func:`member_phases`).
    limit : float
        Peak acceleration to aim at [m/s²], > 0.

    Returns
    -------
    ndarray, shape (n, n_freq)
        Phases [rad]: new ones, in (−π, π], for the re-phased components, the given ones for
        the others; row k depends only on row k of ``phases``.
    """
    dt = positive("dt", dt, "s")
    limit = positive("limit", limit, "m/s²")
    phi = finite_array("phases", phases, ndim=(2,))
    if phi.shape[1] != spectrum.omega.size:
        raise InputError(
            f"phases has {phi.shape[1]} columns but the spectrum has "
            f"{spectrum.omega.size} frequencies"
        )
    active = spectrum.amplitudes > 0.0
    out = phi.copy()
    if not active.any() or phi.shape[0] == 0:
        return out
    amps, omega = spectrum.amplitudes[active], spectrum.omega[active]
    step = max(1, int(2.0 * math.pi / (PEAK_LIMIT_SAMPLES_PER_CYCLE * omega.max() * dt)))
    t = np.arange(0, _n_samples(envelope.duration, dt), step) * dt
    intensity = envelope(t)
    t, intensity = t[intensity > 0.0], intensity[intensity > 0.0]
    basis_t = np.concatenate([portable.sin(omega[:, None] * t), portable.cos(omega[:, None] * t)])
    basis = np.ascontiguousarray(basis_t.T)
    gram_inv = portable.pinv_symmetric(portable.matmul(basis_t, basis))
    free = spectrum.domega[active] / (2.0 * math.pi) * envelope.duration >= 1.0
    columns = np.flatnonzero(active)
    sub = phi[:, columns]
    for i in range(0, sub.shape[0], CHUNK):
        c, s = _limit_kernel(
            amps * portable.cos(sub[i : i + CHUNK]),
            amps * portable.sin(sub[i : i + CHUNK]),
            amps,
            free,
            basis,
            basis_t,
            intensity,
            gram_inv,
            limit,
            PEAK_LIMIT_RELAXATION,
            PEAK_LIMIT_PASSES,
        )
        out[i : i + CHUNK, columns[free]] = portable.arctan2(s[:, free], c[:, free])
    return out


def _count(name: str, value, minimum: int) -> int:
    """``value`` as an int ≥ ``minimum``, or :class:`InputError` naming ``name``."""
    if isinstance(value, bool) or not isinstance(value, (int, np.integer)) or value < minimum:
        raise InputError(f"{name} must be an integer ≥ {minimum}, got {value!r}")
    return int(value)


@dataclass(frozen=True, eq=False)
class SpectralFit:
    """Response spectra of an ensemble's members against a target.

    Attributes
    ----------
    freqs_hz : ndarray, shape (n_freq,)
        Frequencies [Hz].
    psa_g : ndarray, shape (n, n_freq)
        PSA of each member [g].
    target_g : ndarray, shape (n_freq,)
        Target PSA [g].
    damping : float
        Damping ratio [-].
    """

    freqs_hz: np.ndarray
    psa_g: np.ndarray
    target_g: np.ndarray
    damping: float

    @property
    def mean_g(self) -> np.ndarray:
        """Ensemble-mean PSA [g]."""
        return self.psa_g.mean(axis=0)

    @property
    def ratio(self) -> np.ndarray:
        """Mean PSA / target PSA [-]."""
        return self.mean_g / self.target_g

    @property
    def max_deviation(self) -> float:
        """Largest abs(mean/target − 1) over the frequencies [-]."""
        return float(np.abs(self.ratio - 1.0).max())

    @property
    def mean_deviation(self) -> float:
        """Mean abs(mean/target − 1) over the frequencies [-]."""
        return float(np.abs(self.ratio - 1.0).mean())


def spectral_fit(
    ensemble: Ensemble,
    target: SupportsPsa | Callable[..., ArrayLike] | None = None,
    band: tuple[float, float] = FIT_BAND,
    per_decade: int | None = None,
) -> SpectralFit:
    """Mean PSA of ``ensemble`` against ``target`` over ``band`` [Hz].

    The frequencies are those the ensemble was fitted at (``meta["freqs_hz"]``) or else
    :func:`rocking.motions.psd.log_frequencies` defaults, restricted to ``band`` (default 0.2–33
    Hz) and to the Nyquist frequency 1/(2·dt) of the motions (recorded motions sampled at 50 Hz
    hold nothing above 25 Hz);
    or, with ``per_decade``, that many log-spaced frequencies per decade from one end of the
    band to the other, both included (US SRP 3.7.1 asks for 100), which also checks the fit
    between and beyond the fitted frequencies (e.g. at 33 Hz itself, where the paper's grid has
    31.3 and 33.2 Hz). ``target`` defaults to the stored target of a simulated ensemble
    (:meth:`Ensemble.target_spectrum`, known at the fitted frequencies only: pass the target
    itself with ``per_decade``); otherwise as in :func:`generate` (PSA [g]).
    """
    lo, hi = (positive("band", b, "Hz") for b in band)
    hi = min(hi, 0.5 / ensemble.dt)
    target = ensemble.target_spectrum() if target is None else target
    if per_decade is None:
        freqs = np.asarray(ensemble.meta.get("freqs_hz", log_frequencies()))
        freqs = freqs[(freqs >= lo * (1 - 1e-12)) & (freqs <= hi * (1 + 1e-12))]
        if freqs.size == 0:
            raise InputError(f"no fitted frequency lies in the band {lo:g}–{hi:g} Hz")
    else:
        per_decade = checks.count("per_decade", per_decade, "frequencies per decade")
        freqs = log_frequencies(max(2, math.ceil(per_decade * math.log10(hi / lo)) + 1), lo, hi)
    psa_target, h = target_psa(target, freqs)
    psa = response_spectrum(ensemble.acc, ensemble.dt, freqs, h).psa / G
    return SpectralFit(freqs, psa, psa_target, h)


@dataclass(frozen=True)
class Synthesis:
    """The settings of the method of :func:`generate` (its defaults: the paper's method).

    Parameters
    ----------
    damping : float, optional
        Damping ratio of the target [-] (default: the target's own, else 0.05).
    n_freq, fmin, fmax : int, float, float
        Number of log-spaced frequencies and their range [Hz] (paper: 100, 0.15, 50).
    iterations : int
        Number of PSD iterations of the correction (0: the paper's method alone, no peak
        limiting either).
    pilot : int
        Members in the pilot ensemble of the iterations.
    peak_limit : bool
        With ``iterations`` > 0, limit each motion's peak to the target's ZPA by re-phasing
        (:func:`limit_peaks`); False gives the PSD iteration alone.
    peak_constant : float
        Constant of the peak factor in Eq. (6) [-] (:func:`rocking.motions.psd.peak_factor`).
    convention : str
        ``"one-sided"`` (default): A_j = sqrt(2·p_j), or ``"as-printed"``: A_j = sqrt(4·p_j)
        (see :func:`rocking.motions.psd.power_spectrum`).
    """

    damping: float | None = None
    n_freq: int = 100
    fmin: float = 0.15
    fmax: float = 50.0
    iterations: int = 0
    pilot: int = 200
    peak_limit: bool = True
    peak_constant: float = DEFAULT_PEAK_CONSTANT
    convention: str = "one-sided"


#: Parameters of :func:`generate` stored in the metadata (besides the target and members).
_GENERATION_KEYS = (
    "duration",
    "dt",
    "envelope",
    "envelope_params",
    "seed",
    "baseline",
    "damping",
    "n_freq",
    "fmin",
    "fmax",
    "iterations",
    "pilot",
    "peak_limit",
    "peak_constant",
    "convention",
)


def generate(
    n: int,
    *,
    duration: float = 20.0,
    dt: float = DT,
    envelope: str = "compound",
    envelope_params: dict | None = None,
    target: SupportsPsa | Callable[..., ArrayLike] = rg160,
    seed: int = 0,
    baseline: bool = True,
    synthesis: Synthesis | None = None,
    **options: Any,
) -> Ensemble:
    """Simulate ``n`` ground motions compatible with a target response spectrum.

    Steps: the PSD by the paper's method (:func:`rocking.motions.psd.power_spectrum`, Eqs. 5–8);
    with ``iterations`` > 0 the iterative correction (below); synthesis by Eq. (9) with phases from
    :func:`member_phases`; then, if ``baseline``, :func:`baseline_correct` (quadratic).

    The iterative correction (not in the paper; SIMQKE-style, Gasparini & Vanmarcke 1976) has
    two parts:

    * PSD iteration: ``iterations`` times, each amplitude A_j is multiplied by
      target/mean PSA at f_j, at all the fitted frequencies (up to ``fmax``), the mean taken
      over a pilot ensemble (members 0 … ``pilot`` − 1 of the same seed, synthesised as the
      final motions are, so member k does not depend on ``n``); PSD_{i+1} = PSD_i·(target/mean)².
    * Peak limiting (``peak_limit``, default on): every motion, pilot and final, is re-phased
      by :func:`limit_peaks` so that its PGA stays near the target's PSA at ``fmax`` (the ZPA:
      1 g for RG 1.60 at 1 g), its amplitudes A_j unchanged.

    Why the PSD iteration alone cannot fit RG 1.60: above ~20 Hz a 5 %-damped oscillator
    follows the ground, so the mean PSA there tends to the mean PGA, which is set by the
    whole spectrum (mostly 1–10 Hz), not by the 20–50 Hz components the iteration scales down.
    Motions of Eq. (9) with independent phases are nearly Gaussian, and random-vibration theory
    puts the ratio of their PSA at 2.5 Hz to their PGA below the 3.13 that RG 1.60 asks for, so
    no choice of amplitudes alone fits both the ZPA and the amplified range. Lowering the peak
    factor of the ground motion at fixed amplitudes brings both within ±10 % together
    (tests/test_motions.py, ``rocking motions fit``). Side effect: the members' PGAs become
    nearly equal, so the corrected ensemble is less varied than the paper's.

    The pilot motions are not baseline corrected (the correction barely changes their mean
    PSA), so the amplitudes, and each motion before correction, do not depend on ``baseline``:
    ``generate(n)`` is ``baseline_correct`` of ``generate(n, baseline=False)``.

    Parameters
    ----------
    n : int
        Number of motions, ≥ 1; labelled ``sim-0000`` … .
    duration : float
        Total duration T [s], > 0.
    dt : float
        Time step [s], > 0.
    envelope : str
        Intensity function: ``"boxcar"``, ``"trapezoidal"`` or ``"compound"``
        (:func:`rocking.motions.envelopes.make_envelope`).
    envelope_params : dict, optional
        Explicit shape parameters [s, 1/s] overriding the duration rule of
        :mod:`rocking.motions.envelopes`.
    target : TargetSpectrum or callable
        Target spectrum: PSA [g] from ``target.psa(freqs_hz)`` or ``target(freqs_hz,
        damping=...)``; default RG 1.60 at 1 g.
    seed : int
        Root seed, ≥ 0.
    baseline : bool
        Apply the quadratic baseline correction.
    synthesis : Synthesis, optional
        The settings of the method (:class:`Synthesis`: the target's damping, the frequencies,
        the iterative correction, the peak factor and the amplitude convention); default the
        paper's method.
    **options
        ``damping``, ``n_freq``, ``fmin``, ``fmax``, ``iterations``, ``pilot``,
        ``peak_limit``, ``peak_constant``, ``convention``: shorthands for synthesis's fields.
        Any other keyword is an InputError.

    Returns
    -------
    Ensemble
        Accelerations [m/s²]; ``meta`` holds every parameter, the resolved envelope shape
        (``envelope_shape``), T_e [s], the frequencies [Hz], the target PSA [g] there, the
        final amplitudes [m/s²] and the member indices.
    """
    synthesis = checks.record(Synthesis, synthesis, options, "synthesis")
    checks.unexpected(options)
    return _generate(
        range(checks.count("n", n, "motions")),
        duration=duration,
        dt=dt,
        envelope=envelope,
        envelope_params=envelope_params,
        target=target,
        seed=seed,
        baseline=baseline,
        **dataclasses.asdict(synthesis),
    )


def regenerate(ensemble: Ensemble, **overrides: Any) -> Ensemble:
    """Simulate a simulated ground-motion ``ensemble`` again from its metadata (same members,
    phases and scale; accelerations [m/s²]).

    ``overrides`` replace stored generation parameters of :func:`generate` (e.g.
    ``baseline=False``); changing the frequencies needs a new ``target``. Recorded motions and
    floor motions cannot be regenerated (InputError).
    """
    if not ensemble.simulated:
        raise InputError(
            "only simulated ground motions can be regenerated (this ensemble "
            f"is {ensemble.meta.get('kind', 'of unknown kind')!r} at "
            f"{ensemble.meta['location']!r})"
        )
    unknown = set(overrides) - set(_GENERATION_KEYS) - {"target"}
    if unknown:
        raise InputError(
            f"cannot override {', '.join(sorted(unknown))}: not a parameter of generate()"
        )
    m = ensemble.meta
    # Files written before peak limiting existed were generated without it.
    params = {"peak_limit": False, **{k: m[k] for k in _GENERATION_KEYS if k in m}}
    params["target"] = StoredTarget(
        m["target"], tuple(m["freqs_hz"]), tuple(m["target_psa"]), m["damping"]
    )
    params.update(overrides)
    ens = _generate(m["members"], **params)
    return ens.scaled_by(m["scale"]) if m["scale"] != 1.0 else ens


def _generate(
    members,
    *,
    duration,
    dt,
    envelope,
    envelope_params,
    target,
    seed,
    baseline,
    damping,
    n_freq,
    fmin,
    fmax,
    iterations,
    pilot,
    peak_limit,
    peak_constant,
    convention,
) -> Ensemble:
    """:func:`generate` for the given member indices."""
    dt = positive("dt", dt, "s")
    _check_nyquist(dt, positive("fmax", fmax, "Hz"))
    seed = checks.seed("seed", seed)
    n_iter = checks.count("iterations", iterations, "iterations", 0)
    n_pilot = _count("pilot", pilot, 1)
    env = make_envelope(envelope, duration, **(envelope_params or {}))
    n_t = _n_samples(env.duration, dt)
    # the motions, their baseline-corrected copy and the pilot ensemble of the iterations
    require_memory(
        8.0 * n_t * (2 * len(members) + n_pilot * min(n_iter, 1)),
        f"n: {len(members):,} motions of {n_t:,} samples",
    )
    members = [int(m) for m in members]
    freqs = log_frequencies(n_freq, fmin, fmax)
    psa_g, h = target_psa(target, freqs, damping)
    spectrum = power_spectrum(
        psa_g,
        freqs,
        env.equivalent_duration(),
        damping=h,
        peak_constant=peak_constant,
        convention=convention,
    )
    # The ZPA: the target at the stiffest oscillator, where PSA tends to the PGA.
    pga_limit = float(psa_g[-1]) if n_iter and peak_limit else None
    for _ in range(n_iter):
        pilot_acc = _motions(spectrum, env, dt, seed, range(n_pilot), pga_limit)
        spectrum = _corrected_spectrum(spectrum, psa_g, pilot_acc, dt)
    acc = _motions(spectrum, env, dt, seed, members, pga_limit)
    if baseline:
        acc = baseline_correct(acc, dt)
    meta = _metadata(
        target,
        env,
        spectrum,
        psa_g,
        members,
        dt=dt,
        envelope_params=envelope_params,
        seed=seed,
        baseline=baseline,
        fmin=fmin,
        fmax=fmax,
        iterations=n_iter,
        pilot=n_pilot,
        peak_limit=peak_limit,
        pga_limit=pga_limit,
        peak_constant=peak_constant,
    )
    return Ensemble(acc, dt, [f"sim-{m:04d}" for m in members], meta)


def _check_nyquist(dt: float, fmax: float) -> None:
    """:class:`InputError` unless the time step dt [s] samples the highest frequency fmax [Hz]."""
    if fmax > 0.5 / dt:
        raise InputError(
            f"dt = {dt:g} s samples frequencies up to {0.5 / dt:g} Hz (Nyquist), but "
            f"the motions are fitted up to fmax = {fmax:g} Hz: use dt <= "
            f"{0.5 / fmax:g} s or a lower fmax"
        )


def _motions(
    spectrum: PowerSpectrum, envelope, dt: float, seed: int, members, pga_limit: float | None
) -> np.ndarray:
    """Motions of Eq. (9) [m/s²] of the given members: their phases (:func:`member_phases`),
    re-phased by :func:`limit_peaks` to ``pga_limit`` [g] unless it is None, synthesised."""
    phases = member_phases(seed, members, spectrum.omega.size)
    if pga_limit is not None:
        phases = limit_peaks(spectrum, envelope, dt, phases, pga_limit * G)
    return synthesize(spectrum, envelope, dt, phases)


def _corrected_spectrum(
    spectrum: PowerSpectrum, psa_g: np.ndarray, pilot_acc: np.ndarray, dt: float
) -> PowerSpectrum:
    """One PSD iteration: PSD_{i+1} = PSD_i·(target/mean)², i.e. each amplitude A_j [m/s²]
    times the target PSA ``psa_g`` [g] over the mean PSA of the pilot motions ``pilot_acc``
    [m/s²] (time step ``dt`` [s]) at f_j."""
    mean_psa = response_spectrum(pilot_acc, dt, spectrum.freqs_hz, spectrum.damping).mean().psa
    return PowerSpectrum.from_amplitudes(
        spectrum.freqs_hz,
        spectrum.amplitudes * (psa_g * G / mean_psa),
        spectrum.equivalent_duration,
        spectrum.damping,
        spectrum.convention,
    )


def _metadata(
    target, env, spectrum: PowerSpectrum, psa_g: np.ndarray, members: list[int], **settings
) -> dict:
    """The ``meta`` of a generated ensemble: every parameter of :func:`generate` (``settings``,
    already checked), the resolved envelope, the frequencies [Hz], the target PSA [g] there,
    the final amplitudes [m/s²] and the member indices."""
    return {
        "kind": "simulated",
        "location": "ground",
        "scale": 1.0,
        "target": _target_name(target, spectrum.damping),
        "duration": env.duration,
        "dt": settings["dt"],
        "envelope": _envelope_name(env),
        "envelope_params": dict(settings["envelope_params"] or {}),
        "envelope_shape": env.params(),
        "seed": settings["seed"],
        "baseline": bool(settings["baseline"]),
        "damping": spectrum.damping,
        "n_freq": spectrum.freqs_hz.size,
        "fmin": float(settings["fmin"]),
        "fmax": float(settings["fmax"]),
        "iterations": settings["iterations"],
        "pilot": settings["pilot"],
        "peak_limit": bool(settings["peak_limit"]),
        "pga_limit": settings["pga_limit"],
        "peak_constant": float(settings["peak_constant"]),
        "convention": spectrum.convention,
        "equivalent_duration": env.equivalent_duration(),
        "freqs_hz": spectrum.freqs_hz.tolist(),
        "target_psa": psa_g.tolist(),
        "amplitudes": spectrum.amplitudes.tolist(),
        "members": members,
    }


def _target_name(target, damping: float) -> str:
    name = getattr(target, "name", None)
    if name is None:
        name = f"{getattr(target, '__name__', 'target')} ({100 * damping:g} % damping)"
    return str(name)


def _envelope_name(env) -> str:
    return next(name for name, cls in ENVELOPES.items() if isinstance(env, cls))
