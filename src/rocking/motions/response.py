"""Response spectra of ground motions: :func:`response_spectrum`.

SD, PSV and PSA of damped single-degree-of-freedom oscillators under sampled accelerations, by the
exact piecewise-linear recurrence (Nigam & Jennings 1969) with the peak between samples located
(reference.md §7).  The recurrence (:func:`foh_coefficients`) also drives the shear frames of
:mod:`rocking.structures.frames`.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np
from numba.extending import overload
from numpy.typing import ArrayLike

from ..core import portable
from ..core.checks import finite_array, in_range, positive
from ..core.compile import (
    aligned_zeros,
    borrowing_kernel,
    highest_bit,
    kernel,
    maxnum,
    parallel_kernel,
    prange,
    readonly,
)
from ..core.reuse import reused
from ..errors import InputError
from .targets import _freqs


def check_nyquist(f_max_hz: float, dt: float, name: str = "freqs_hz") -> None:
    """Refuse a frequency ``f_max_hz`` [Hz] above the Nyquist frequency 1/(2·dt) of motions
    sampled at ``dt`` [s]: their samples hold no information there (the spectrum would only show
    the interpolation between them); ``name`` names the parameter in the message."""
    nyquist = 0.5 / dt
    if f_max_hz > nyquist * (1.0 + 1e-9):
        raise InputError(
            f"{name}: {f_max_hz:g} Hz is above the Nyquist frequency 1/(2 dt) = {nyquist:g} Hz "
            f"of motions sampled at dt = {dt:g} s, which hold no information there"
        )


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

    def mean(self) -> ResponseSpectrum:
        """Ensemble-mean spectrum (itself for a single motion)."""
        if self.sd.ndim == 1:
            return self
        return ResponseSpectrum(
            self.freqs_hz,
            self.damping,
            self.sd.mean(axis=0),
            self.psv.mean(axis=0),
            self.psa.mean(axis=0),
        )


def foh_coefficients(omega: np.ndarray, zeta: float, h: np.ndarray) -> np.ndarray:
    """Exact one-step recurrence of u'' + 2ζωu' + ω²u = −a(t) for a(t) linear over a step h.

    Returns c of shape (n, 8) with
    u₁ = c0·u₀ + c1·v₀ + c2·a₀ + c3·a₁ and v₁ = c4·u₀ + c5·v₀ + c6·a₀ + c7·a₁.
    These are Nigam & Jennings' (1969) coefficients. They are obtained here from the matrix
    exponential of the system augmented with the input and its slope rather than from their
    closed form, whose terms cancel catastrophically when ω·h is small
    (:func:`rocking.core.portable.expm`: ``scipy.linalg.expm``'s BLAS products would give bits
    that depend on the CPU).
    """
    n = omega.size
    m = np.zeros((n, 4, 4))  # state (u, v, a, Δa); da/dt = Δa/h
    m[:, 0, 1] = h
    m[:, 1, 0] = -(omega**2) * h
    m[:, 1, 1] = -2.0 * zeta * omega * h
    m[:, 1, 2] = -h
    m[:, 2, 3] = 1.0
    e = portable.expm(m)
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
    return (
        (2.0 * s3 - 3.0 * s2 + 1.0) * u0
        + (s3 - 2.0 * s2 + s) * h * v0
        + (3.0 * s2 - 2.0 * s3) * u1
        + (s3 - s2) * h * v1
    )


@kernel
def _hermite_bound(u0, v0, u1, v1, h):
    """A bound of |:func:`_hermite_extremum`| as computed in floating point, wherever the
    extremum lies.

    On s ∈ [0, 1] the cubic's weights of u0 and u1, (1 − s)²(1 + 2s) and s²(3 − 2s), are ≥ 0
    with sum 1, and those of h·v0 and h·v1, s(1 − s)² and −s²(1 − s), are within ±4/27; 0.15
    instead of 4/27 and the factor 1 + 1e-9 cover the rounding of the evaluation (below 1e-14
    relative), 1e-300 its underflow.
    """
    return (max(abs(u0), abs(u1)) + 0.15 * h * (abs(v0) + abs(v1))) * (1.0 + 1e-9) + 1e-300


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
        u * math.cos(phi) + (v + zeta * omega * u) / wd * math.sin(phi)
    )


#: Oscillators integrated side by side, in the SIMD lanes of :func:`_lane_steps`: 4 AVX2 vectors
#: of 4 float64 (with 8 lanes LLVM left the loop scalar; 32 were no faster on Zen 3).
_LANES = 16

# Rows of the work array W of one block of lanes (one array, rows at constant offsets
# row·_LANES, so that the compiler can prove the SIMD loop's loads and stores independent).
_U = 0  # u [length] at the end of the last sub-step
_V = 1  # v [length/s] likewise
_U0 = 2  # u and v at its start, read where v changed sign (:func:`_lane_extrema`)
_V0 = 3
_PEAK = 4  # max |u| so far [length]
_OMEGA = 5  # ω [rad/s]
_C = 6  # 8 rows: the coefficients c0 … c7 of foh_coefficients
_ROWS = 14
#: Sub-steps per period from which :func:`_block_peaks` tests only the sign of v in the SIMD loop
#: (``bounded=False`` in :func:`_lane_steps`): v changes sign so rarely that evaluating the
#: Hermite extremum at every change costs less than the bound in every sub-step.  Measured (500
#: motions, 16 frequencies, interleaved runs): without the bound 1.72x the time at 25 sub-steps
#: per period, 1.16x at 100, 1.08x at 200, 0.96x at 400, 0.93x at 800; 0.87x over the paper's
#: band of S_v (0.04-0.6 Hz at dt = 1/400 s: 670-10,000 sub-steps).
_SPARSE_STEPS = 400


@kernel(inline="always")
def _lane_steps(ab, db, i, k, h, W, bounded):
    """Sub-step k (of length h [s]) of sample interval i of every lane (a SIMD loop): (u, v)
    advanced by the recurrence, the peak raised to |u| at the sub-step's end.

    ``ab[:, j]`` is lane j's ground acceleration, linear over each interval, and ``db[i, j]`` its
    change over one sub-step of interval i (1-D ``ab`` and ``db``: the same for every lane).
    Returns as a bit mask (bit j for lane j) the lanes whose peak the extremum inside the
    sub-step may still raise: v changed sign and, if ``bounded`` (a constant where this is
    inlined), :func:`_hermite_bound` is not below the peak.
    The bound is tested here, in every lane, rather than in :func:`_lane_extrema`: after the
    first strong cycles almost no lane is left, the mask is almost always 0 and the branch on
    it predictable (v changes sign in one sub-step in five of a lane at 10 steps per period, so
    some lane of 16 did in almost every one).  Each lane does a lone oscillator's operations in
    the same order (no fastmath: no reassociation, no fused multiply-add), so its bits do not
    depend on its lane.
    """
    L = _LANES
    bits = np.uint64(0)
    for j in range(L):
        a0, da = _lane_input(ab, db, i, j)
        if k == 0:  # the only sub-step where nsub = 1: two products and a sum fewer
            # a0 + 0·da is a0 but for the sign of a zero (−0 + 0 = +0), which moves only the
            # signs of zeros of u and v: not max |u|, nor the tail (where v is a zero of either
            # sign, _free_vibration_extremum's tail is at most |u|, which the peak holds)
            g0 = a0
            g1 = a0 + da  # (0 + 1)·da is da exactly
        else:
            g0 = a0 + k * da
            g1 = a0 + (k + 1) * da
        u = W[_U * L + j]
        v = W[_V * L + j]
        c = _C * L + j
        u1 = W[c] * u + W[c + L] * v + W[c + 2 * L] * g0 + W[c + 3 * L] * g1
        v1 = W[c + 4 * L] * u + W[c + 5 * L] * v + W[c + 6 * L] * g0 + W[c + 7 * L] * g1
        W[_U0 * L + j] = u
        W[_V0 * L + j] = v
        W[_U * L + j] = u1
        W[_V * L + j] = v1
        peak = maxnum(W[_PEAK * L + j], abs(u1))
        W[_PEAK * L + j] = peak
        open_ = (v * v1 < 0.0) & (not bounded or not _hermite_bound(u, v, u1, v1, h) < peak)
        bits |= np.uint64(1 if open_ else 0) << np.uint64(j)
    return bits


def _lane_input(ab, db, i, j):
    """(a, Δa) of lane j at interval i: ``ab[i, j], db[i, j]``, or ``ab[i], db[i]`` for 1-D
    arrays (one motion in every lane; compiled per number of dimensions)."""
    if np.ndim(ab) == 1:
        return ab[i], db[i]
    return ab[i, j], db[i, j]


@overload(_lane_input)
def _lane_input_in_kernels(ab, db, i, j):
    if ab.ndim == 1:
        return lambda ab, db, i, j: (ab[i], db[i])
    return lambda ab, db, i, j: (ab[i, j], db[i, j])


@borrowing_kernel
def _lane_extrema(W, bits, h):
    """The peaks of the lanes in ``bits`` (v changed sign in their last sub-step, of length h
    [s], and, in the bounded loop, the bound there is not below their peak: :func:`_lane_steps`)
    raised to the extremum inside that sub-step (:func:`_hermite_extremum`)."""
    L = _LANES
    while bits:
        j = highest_bit(bits)
        bits ^= np.uint64(1) << np.uint64(j)
        u0 = W[_U0 * L + j]
        v0 = W[_V0 * L + j]
        extremum = abs(_hermite_extremum(u0, v0, W[_U * L + j], W[_V * L + j], h))
        W[_PEAK * L + j] = max(W[_PEAK * L + j], extremum)


@kernel(inline="always")
def _interval(ab, db, i, nsub, h, W, bounded):
    """The nsub sub-steps of sample interval i of every lane: :func:`_lane_steps`, then
    :func:`_lane_extrema` for the lanes it names.  Sub-step 0 apart, with k a constant: the
    branch on k == 0 in that inlined copy of the SIMD loop is compiled out (for nsub = 1 the
    only sub-step; 2-6 % less time per call in interleaved runs)."""
    bits = _lane_steps(ab, db, i, 0, h, W, bounded)
    if bits:
        _lane_extrema(W, bits, h)
    for k in range(1, nsub):
        bits = _lane_steps(ab, db, i, k, h, W, bounded)
        if bits:
            _lane_extrema(W, bits, h)


@borrowing_kernel
def _block_peaks(ab, db, W, nsub, h, zeta, out):
    """max |u(t)| [length] of each lane into ``out``: the oscillators of W's ω and coefficient
    rows, starting at rest, under the accelerations ``ab`` (``db``: their changes over one
    sub-step of each sample interval; 1-D: the same for every lane) in sub-steps of h = dt/nsub
    [s], then in free vibration (ground at rest).

    Lanes whose periods all span :data:`_SPARSE_STEPS` sub-steps or more are integrated by the
    SIMD loop without the bound (``bounded=False``): every change of sign of v goes to
    :func:`_lane_extrema`.  The peaks are the same: the extrema the bound passes over are below
    the peak already.  Compiled without reference counting
    (:func:`rocking.core.compile.borrowing_kernel`, which the inlined helpers need to take the
    arrays without counting references to them in every sample interval).
    """
    L = _LANES
    W[: _OMEGA * L] = 0.0
    sparse = True
    for j in range(L):
        sparse &= W[_OMEGA * L + j] * h * _SPARSE_STEPS <= 2.0 * math.pi
    if sparse:  # two copies of the loop, each with its constant
        for i in range(ab.shape[0] - 1):
            _interval(ab, db, i, nsub, h, W, False)
    else:
        for i in range(ab.shape[0] - 1):
            _interval(ab, db, i, nsub, h, W, True)
    for j in range(L):
        tail = _free_vibration_extremum(W[_U * L + j], W[_V * L + j], W[_OMEGA * L + j], zeta)
        out[j] = max(W[_PEAK * L + j], abs(tail))


@parallel_kernel
def _all_block_peaks(at, diff, groups, coef, nsub, h, omega, zeta):
    """:func:`_block_peaks` of every block of accelerations ``at[a]`` (``diff[a]``: their changes
    over the sample intervals) with every group of frequencies ``groups[g]`` (indices into
    ``coef``, ``nsub``, ``h`` and ``omega``; one nsub per group): row a·n_groups + g."""
    L = _LANES
    n_g = groups.shape[0]
    out = np.empty((at.shape[0] * n_g, L))
    for p in prange(out.shape[0]):  # every pair is independent
        a = p // n_g
        freqs = groups[p % n_g]
        W = aligned_zeros(_ROWS * L)  # rows start cache lines (see there)
        for j in range(L):
            W[_OMEGA * L + j] = omega[freqs[j]]
            for r in range(8):
                W[(_C + r) * L + j] = coef[freqs[j], r]
        m = nsub[freqs[0]]
        # the change over one sub-step, (a[i+1] − a[i])/nsub, once per interval rather than once
        # per sub-step; without the division for nsub = 1 (x/1 = x exactly)
        db = diff[a] if m == 1 else diff[a] / m
        _block_peaks(at[a], db, W, m, h[freqs[0]], zeta, out[p])
    return out


def _lane_layout(acc, nsub):
    """The oscillators' lanes for :func:`_all_block_peaks`: ``_LANES`` motions at one frequency
    (zero motions after the last) or, when that integrates fewer sub-steps (few motions), one
    motion at ``_LANES`` frequencies of equal nsub (the last one repeated).

    Returns the blocks of accelerations, shape (n_blocks, n_t, _LANES) (:func:`_lane_blocks`),
    or in the second layout ``acc`` itself, shape (n_motions, n_t): one motion read by every
    lane (not copied into each); their changes over the sample intervals (``np.diff`` along
    time); the motion of each lane of each block, shape (n_blocks, _LANES); and the groups of
    frequencies (indices of ``nsub``), shape (n_groups, _LANES); every block goes with every
    group.
    """
    L = _LANES
    n_m = acc.shape[0]
    order = np.argsort(nsub, kind="stable")
    runs = np.split(order, np.flatnonzero(np.diff(nsub[order])) + 1)  # frequencies of one nsub
    n_blocks = -(-n_m // L)
    if n_blocks * nsub.sum() <= n_m * sum(-(-run.size // L) * nsub[run[0]] for run in runs):
        # one compiled variant, without copying a read-only ensemble
        at, diff = _lane_blocks(readonly(np.ascontiguousarray(acc)))
        lane_motion = np.arange(n_blocks * L).reshape(n_blocks, L)
        groups = np.repeat(np.arange(nsub.size)[:, None], L, axis=1)
        return at, diff, lane_motion, groups
    at = np.require(acc, requirements=["C", "W"])  # one compiled variant
    lane_motion = np.repeat(np.arange(n_m)[:, None], L, axis=1)
    chunks = [run[q : q + L] for run in runs for q in range(0, run.size, L)]
    groups = np.stack([np.pad(c, (0, L - c.size), mode="edge") for c in chunks])
    return at, np.diff(at, axis=1), lane_motion, groups


@parallel_kernel
def _lane_blocks(acc):
    """The motions ``acc`` (n_m, n_t) as n_blocks = ⌈n_m/_LANES⌉ blocks of ``_LANES`` side by
    side, shape (n_blocks, n_t, _LANES), lanes after the last motion zero, and their changes over
    the sample intervals (n_blocks, n_t − 1, _LANES): what ``np.diff`` of the blocks gives, in
    one pass on all threads.

    Written by hand because NumPy's copy of the transposed view runs on one thread with the
    source read ``_LANES`` rows apart, after a zero-padded copy of the whole ensemble: for 6,000
    floor motions of 8,001 samples (``rocking screen --n 1000`` on a 5-story frame) 2.4 s, where
    the oscillators take 3.9 s.  Here each block reads its rows as they are stored, sample by
    sample.
    """
    L = _LANES
    n_m, n_t = acc.shape
    n_blocks = -(-n_m // L)
    at = np.empty((n_blocks, n_t, L))
    diff = np.empty((n_blocks, max(n_t - 1, 0), L))
    for b in prange(n_blocks):
        rows = min(L, n_m - b * L)
        for i in range(n_t):
            for j in range(rows):
                at[b, i, j] = acc[b * L + j, i]
            for j in range(rows, L):
                at[b, i, j] = 0.0
            if i > 0:
                for j in range(L):
                    diff[b, i - 1, j] = at[b, i, j] - at[b, i - 1, j]
    return at, diff


def _peak_displacements(acc, coef, nsub, h, omega, zeta):
    """max |u(t)| [length] of every oscillator (motion, frequency), shape (n_motions, n_freq),
    ``_LANES`` oscillators at a time (:func:`_lane_layout`).  Each lane computes what a lone
    oscillator would, so the result does not depend on the grouping."""
    at, diff, lane_motion, groups = _lane_layout(acc, nsub)
    out = _all_block_peaks(at, diff, groups, coef, nsub, h, omega, zeta)
    sd = np.empty((lane_motion.max() + 1, omega.size))
    sd[lane_motion[:, None, :], groups[None, :, :]] = out.reshape(at.shape[0], -1, _LANES)
    return sd[: acc.shape[0]]


def response_spectrum(
    acc: ArrayLike,
    dt: float,
    freqs_hz: ArrayLike,
    damping: float = 0.05,
    *,
    steps_per_period: int = 10,
) -> ResponseSpectrum:
    """Response spectra of ground accelerations by the Nigam & Jennings (1969) recurrence.

    Each oscillator u'' + 2ζωu' + ω²u = −a(t) starts at rest; a(t) is the piecewise-linear
    interpolant of the samples, for which the recurrence is exact. At the record's own step the
    peaks between samples would be missed (reference.md §7), so each step dt is cut into
    m = ceil(steps_per_period·dt·f) sub-steps and the peak inside a sub-step is located by cubic
    Hermite interpolation of (u, v): with the default 10 steps per period the peaks are within
    (2π/10)⁴/384 ≈ 4e-4 (relative) of the exact ones. The ground is taken to be at rest after the
    last
    sample, so the free vibration that follows the record counts too (it matters at long periods:
    Boore 2005, "On pads and filters").

    Parameters
    ----------
    acc : array_like, shape (n_t,) or (n_motions, n_t)
        Ground acceleration [any unit, e.g. m/s² or g]; finite; n_t ≥ 2.
    dt : float
        Time step [s], > 0.
    freqs_hz : array_like, shape (n_freq,)
        Oscillator frequencies [Hz], finite, > 0, at most the Nyquist frequency 1/(2·dt).
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
    check_nyquist(float(f.max()), dt)
    omega = 2.0 * math.pi * f
    spp = steps_per_period
    if isinstance(spp, bool) or not isinstance(spp, (int, np.integer)) or spp < 1:
        raise InputError(f"steps_per_period must be an integer >= 1, got {spp!r}")
    nsub = np.maximum(1, np.ceil(spp * dt * f - 1e-9)).astype(np.int64)
    h = dt / nsub
    coef = foh_coefficients(omega, zeta, h)
    sd = reused(
        "response_spectrum",
        (a, dt, f, zeta, int(spp)),
        lambda: _peak_displacements(np.atleast_2d(a), coef, nsub, h, omega, zeta),
    )
    if a.ndim == 1:
        sd = sd[0]
    return ResponseSpectrum(f, zeta, sd, omega * sd, omega**2 * sd)
