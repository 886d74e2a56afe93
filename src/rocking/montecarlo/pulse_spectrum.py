"""Overturning spectra of a block under idealised pulses (issue 46): :func:`overturning_spectrum`.

Since Housner (1963), Makris & Roussos (2000, "Rocking response of rigid blocks under near-source
ground motions", Géotechnique 50(3)) and Zhang & Makris (2001, "Rocking response of free-standing
blocks under cycloidal pulses", J. Eng. Mech. 127(5)) the response of a block to a pulse
(:func:`rocking.pulse`) is summed up as the smallest pulse amplitude that overturns it,
κ = a_p/(g·tan α), against the pulse's frequency relative to the block's, Ω = ω_p/p with
ω_p = 2π/T_p.  Above that minimum there may be *safe bands*: amplitudes at which the block
survives the stronger pulse.
"""

from __future__ import annotations

import dataclasses
import math
from typing import Any

import numpy as np
import xarray as xr
from numpy.typing import ArrayLike

from ..core.checks import count, finite_array, positive, record
from ..core.compile import numba_threads
from ..defaults import PULSE_KAPPA_MAX, PULSE_N_SCAN
from ..dynamics.batch import BlockTable, motion_peaks, motion_suffixes, run_cases
from ..dynamics.body import Block
from ..dynamics.physics import Physics, as_physics
from ..dynamics.simulate import simulate
from ..errors import InputError
from ..motions.pulses import MP_GAMMA, MP_NU, parse_pulse, pulse

#: Default relative width to which each switch of the outcome is bisected [-].
RTOL = 1e-4
#: Default samples per pulse period T_p (the time step is T_p/N; see ``samples_per_period``).
SAMPLES_PER_PERIOD = 200
#: Largest p·dt [-]: long pulses get more samples per period.  κ of a one-sine spectrum
#: (R = 1 m, γ = 4, T_p = 3–12 s) at p·dt ≤ 0.05 is within 1e-4 of its value at 800 samples
#: per period; at p·dt = 0.11 up to 7e-4 off.
MAX_P_DT = 0.05
#: Default free rocking after the pulse is (TAIL_BASE + ln(1/rtol))/p [s] (see ``tail``).
TAIL_BASE = 12.0
#: Amplitudes tried inside each bracket per refinement round (a 16-ary search: two rounds take
#: the default scan's step to RTOL, each one kernel call with all brackets of the period as
#: lanes).
_SPLIT = 15


def _brackets(amps: np.ndarray, over: np.ndarray) -> list[tuple[float, float, bool]]:
    """(lo, hi, outcome at hi) of every pair of neighbouring amplitudes whose outcomes differ."""
    change = np.nonzero(over[1:] != over[:-1])[0]
    return [(float(amps[j]), float(amps[j + 1]), bool(over[j + 1])) for j in change]


def _switches(table, unit, dt, amps, rtol, impacts) -> list[tuple[float, bool]]:
    """Scan ``amps`` (increasing, the first one safe) of the pulse ``unit`` (of amplitude 1),
    then narrow every change of the outcome to a relative width ``rtol``; returns (smallest
    amplitude found with the new outcome, that outcome) of every switch, increasing."""
    acc = np.ascontiguousarray(unit.reshape(1, -1))
    peaks, suffixes = motion_peaks(acc), motion_suffixes(acc)

    def outcomes(scales: np.ndarray) -> np.ndarray:
        zeros = np.zeros(scales.size, dtype=np.int64)
        out = run_cases(
            table, acc, peaks, dt, zeros, zeros, scales, None, impacts, suffixes=suffixes
        )
        return out.overturned

    over = outcomes(amps)
    brackets = _brackets(amps, over)
    done: list[tuple[float, float, bool]] = []
    while brackets:
        wide = [b for b in brackets if b[1] > b[0] * (1.0 + rtol)]
        done += [b for b in brackets if b[1] <= b[0] * (1.0 + rtol)]
        if not wide:
            break
        # _SPLIT amplitudes inside each bracket, geometric, all brackets in one call
        frac = np.arange(1, _SPLIT + 1) / (_SPLIT + 1)
        inner = np.concatenate([lo * (hi / lo) ** frac for lo, hi, _ in wide])
        inner_over = outcomes(inner).reshape(len(wide), _SPLIT)
        brackets = []
        mids = inner.reshape(len(wide), _SPLIT)
        for (lo, hi, at_hi), mid, mid_over in zip(wide, mids, inner_over):
            pts = np.concatenate([[lo], mid, [hi]])
            outs = np.concatenate([[not at_hi], mid_over, [at_hi]])
            # every change inside: one more bracket each (a band narrower than the scan's step,
            # found now, adds two)
            brackets += _brackets(pts, outs)
    return sorted((hi, at_hi) for _lo, hi, at_hi in done)


@dataclasses.dataclass(frozen=True)
class SpectrumScan:
    """How :func:`overturning_spectrum` searches the amplitudes of each period.

    Parameters
    ----------
    kappa_max : float
        Upper limit of the search, κ = a_p/(g·tan α) [-], > 1: switches above it are not
        looked for; a period whose block survives every amplitude up to it has NaN.
    n_scan : int
        Amplitudes of the scan (≥ 2).
    rtol : float
        Relative width [-] to which each switch is bisected, in (0, 0.1].
    samples_per_period : int
        Samples per pulse period, at least (the time step T_p/N [s]), even, ≥ 20.
    tail : float, optional
        Free rocking after the pulse [s].  Near a threshold the block may overturn long after
        the pulse: it creeps towards the upright unstable equilibrium, and the closer the
        amplitude to the threshold the longer it takes, about (c + ln(1/δ))/p for an amplitude
        δ (relative) above it.  At the Zhang & Makris (2001) minimum (one-sine pulse,
        Ω = 7.34, α = 0.25, e = 0.9), 1e-4 above the threshold, it overturns 17.5/p after
        the pulse (c ≈ 8.3).  Default (12 + ln(1/``rtol``))/p (21.2/p at the default rtol),
        so that the amplitudes of the last bracket still overturn within the tail; a shorter
        tail raises the thresholds found.  ``overturning_time`` tells how late each switch
        overturned.
    """

    kappa_max: float = PULSE_KAPPA_MAX
    n_scan: int = PULSE_N_SCAN
    rtol: float = RTOL
    samples_per_period: int = SAMPLES_PER_PERIOD
    tail: float | None = None


def overturning_spectrum(
    block: Block,
    shape: str,
    periods: ArrayLike,
    *,
    physics: Physics | None = None,
    scan: SpectrumScan | None = None,
    gamma: float | None = None,
    nu: float | None = None,
    **shorthands: Any,
) -> xr.Dataset:
    """Smallest pulse amplitude that overturns ``block``, and every switch of the outcome above
    it, for pulses of each period.

    How it is found.  For each period T_p the pulse (:func:`rocking.pulse`, positive amplitude;
    a block is symmetric, so a mirrored pulse gives the mirrored response) is sampled at
    dt = T_p/N, N = ``samples_per_period`` or, for pulses longer than ``samples_per_period``·
    0.05/p, the even number that keeps p·dt ≤ 0.05 (:data:`MAX_P_DT`), and followed by
    ``tail`` of free rocking.  ``n_scan``
    amplitudes, geometric from κ = 1 (the uplift threshold: below it the block does not move)
    to ``kappa_max``, are integrated at once as lanes of the batched kernel
    (:func:`rocking.dynamics.batch.run_cases`, the physics of :func:`rocking.simulate` bit for
    bit).  Every neighbouring pair whose outcomes differ is then narrowed, fifteen amplitudes
    inside each bracket per round (all brackets of the period in one kernel call), until
    hi/lo − 1 ≤ ``rtol``; a change found inside a bracket during this refinement becomes a
    bracket of its own.

    How the scan is sized: its amplitudes are a ratio r = ``kappa_max``^(1/(``n_scan`` − 1))
    apart (r − 1 = 1.18 % by default), so an overturning band or a safe band narrower than
    that relative width in κ can fall between two scanned amplitudes and be missed; a band at
    least r − 1 wide always contains a scanned amplitude.  The ratio is in the result's
    attributes (``scan_ratio``); raise ``n_scan`` for narrower bands (the cost grows linearly).

    Parameters
    ----------
    block : Block
        The block (its p [rad/s] and α [rad]).
    shape : str
        Pulse shape of :func:`rocking.pulse` (with ``mavroeidis-papageorgiou:gamma=…,nu=…``).
    periods : array_like of float
        Pulse periods T_p [s], > 0 (for ``rectangular``, the duration t_d).
    physics : Physics, optional
        The physics (:class:`~rocking.Physics`; default ``Physics()``), as in
        :func:`rocking.simulate`.
    scan : SpectrumScan, optional
        The search (:class:`SpectrumScan`: ``kappa_max``, ``n_scan``, ``rtol``,
        ``samples_per_period``, ``tail``; defaults of the paper's figures).
    gamma, nu : float, optional
        Parameters γ [-] and ν [rad] of the ``mavroeidis-papageorgiou`` pulse.
    **shorthands
        ``kappa_max``, ``n_scan``, ``rtol``, ``samples_per_period``, ``tail``: shorthands for
        scan's fields; ``e``, ``overturn_angle``, ``g``, ``impacts``: for physics's, one
        release, and ``mu``, ``mu_k`` (friction coefficients [-] of the base, issue 45: the
        block may then slide and fly; the scan still starts at the uplift amplitude g·tan α).
        Any other keyword is an InputError.

    Returns
    -------
    xarray.Dataset
        On dimensions ``period`` (coordinate T_p [s], with ``omega_ratio`` = Ω = ω_p/p [-]
        beside it) and ``switch`` (0, 1, …):

        * ``overturning_amplitude`` [m/s²]: the smallest amplitude found to overturn the block
          (within ``rtol`` above the true threshold), NaN if none up to ``kappa_max``;
        * ``kappa`` [-]: the same over g·tan α;
        * ``switch_amplitude`` [m/s²] and ``switch_kappa`` [-]: every amplitude at which the
          outcome changes, increasing (the smallest amplitude found with the new outcome), NaN
          where a period has fewer switches; switch 0 is ``overturning_amplitude``;
        * ``overturns`` (bool): the outcome of the branch that starts at each switch, up to the
          next one (alternately True and False);
        * ``impacts_before_overturning`` [-]: the mode of each overturning branch, the number of
          impacts before the block overturns at the branch's smallest amplitude (0: overturning
          without impact), from :func:`rocking.simulate` (which counts impacts; the batched
          kernel does not); −1 for safe branches and missing switches;
        * ``overturning_time`` [s]: when the block overturns at that amplitude (from the start
          of the pulse; NaN for safe branches), against the record's length ``duration`` [s]
          (coordinate on ``period``, beside the time step ``dt`` [s]): a time near the end
          means that a longer ``tail`` may find a lower threshold.

        Attributes: the block (``R`` [m], ``gamma``, ``alpha`` [rad], ``p`` [rad/s]), ``e``,
        ``shape``, ``uplift_amplitude`` = g·tan α [m/s²], ``kappa_max``, ``amplitude_max``
        [m/s²], ``n_scan``, ``scan_ratio``, ``rtol``, ``samples_per_period``, ``tail`` [s],
        and with friction ``mu`` and ``mu_k`` [-].
    """
    if not isinstance(block, Block):
        raise InputError(f"block must be a rocking.Block, got {type(block).__name__}")
    scan = record(SpectrumScan, scan, shorthands, "scan")
    kappa_max, n_scan, rtol, samples_per_period, tail = dataclasses.astuple(scan)
    name, params = parse_pulse(shape)
    if name != "mavroeidis-papageorgiou" and (gamma is not None or nu is not None):
        raise InputError(
            f"gamma and nu are parameters of the mavroeidis-papageorgiou pulse, not {name}"
        )
    periods = finite_array("periods", periods, ndim=(1,), min_len=1)
    if periods.min() <= 0.0:
        raise InputError(f"periods must be > 0 [s], got {periods.min():g}")
    kappa_max = positive("kappa_max", kappa_max, "-")
    if kappa_max <= 1.0:
        raise InputError(
            f"kappa_max must be > 1 (kappa = 1 is the uplift threshold), got {kappa_max:g}"
        )
    n_scan = count("n_scan", n_scan, "levels", 2)
    samples_per_period = count("samples_per_period", samples_per_period, "samples per period", 20)
    if samples_per_period % 2:
        raise InputError(
            "samples_per_period must be even (the half-sine ends at T_p/2), got "
            f"{samples_per_period}"
        )
    rtol = positive("rtol", rtol, "-")
    if rtol > 0.1:
        raise InputError(f"rtol must be in (0, 0.1], got {rtol:g}")
    physics = as_physics(physics, **shorthands)
    g = physics.g
    p = block.p_at(g)
    tail = (TAIL_BASE + math.log(1.0 / rtol)) / p if tail is None else float(tail)
    if not (math.isfinite(tail) and tail >= 0.0):
        raise InputError(f"tail must be a time >= 0 [s], got {tail!r}")
    table = BlockTable.from_blocks(block, physics=physics)
    uplift = g * float(table.tan_a[0])
    kappas = kappa_max ** (np.arange(n_scan) / (n_scan - 1))
    kappas[0] = 1.0  # exactly the uplift threshold: no motion
    per_period: list[list[tuple[float, bool, int, float]]] = []
    durations: list[float] = []
    steps: list[float] = []
    # one Numba thread: the kernel calls are small (a few hundred cases), and waking a second
    # thread for each costs more than it brings (100 periods on a loaded 2-core machine:
    # 0.23–0.30 s on one thread, 1.4–3.2 s on two); results do not depend on the threads
    with numba_threads(1):
        for period in periods.tolist():
            n = max(samples_per_period, 2 * math.ceil(p * period / MAX_P_DT / 2))
            dt = period / n
            steps.append(dt)
            unit = pulse(shape, 1.0, period, dt, tail=tail, gamma=gamma, nu=nu)
            durations.append((unit.size - 1) * dt)
            found = []
            for amp, over in _switches(table, unit, dt, kappas * uplift, rtol, physics.impacts):
                mode, t_ov = -1, math.nan
                if over:  # simulate: the kernel's outcome bit for bit, and it counts impacts
                    resp = simulate(block, amp * unit, dt, physics=physics)
                    mode, t_ov = resp.n_impacts, resp.t_overturn
                found.append((amp, over, mode, t_ov))
            per_period.append(found)
    if name == "mavroeidis-papageorgiou":
        name += f":gamma={gamma if gamma is not None else params.get('gamma', MP_GAMMA):g}"
        name += f",nu={nu if nu is not None else params.get('nu', MP_NU):g}"
    attrs = {
        "R": block.R,
        "gamma": block.gamma,
        "alpha": block.alpha,
        "p": p,
        "e": float(table.e[0]),
        "shape": name,
        "uplift_amplitude": uplift,
        "kappa_max": kappa_max,
        "amplitude_max": kappa_max * uplift,
        "n_scan": n_scan,
        "scan_ratio": float(kappa_max ** (1.0 / (n_scan - 1))),
        "rtol": rtol,
        "samples_per_period": samples_per_period,
        "tail": tail,
    }
    mu, mu_k = table.physics.friction(0)
    if mu is not None:  # with friction (issue 45): which, as the physics simulated it
        attrs.update(mu=mu, mu_k=mu_k)
    return _dataset(periods, np.array(durations), np.array(steps), p, uplift, per_period, attrs)


def _dataset(periods, durations, steps, p, uplift, per_period, attrs) -> xr.Dataset:
    """The result of :func:`overturning_spectrum` from the switches of each period."""
    n_sw = max(1, max(len(f) for f in per_period))
    amp = np.full((periods.size, n_sw), np.nan)
    over = np.zeros((periods.size, n_sw), dtype=bool)
    mode = np.full((periods.size, n_sw), -1, dtype=np.int64)
    t_ov = np.full((periods.size, n_sw), np.nan)
    for i, found in enumerate(per_period):
        for k, (a, o, m, t) in enumerate(found):
            amp[i, k], over[i, k], mode[i, k], t_ov[i, k] = a, o, m, t
    first = amp[:, 0]  # the first switch is always safe → overturning
    dims = ("period", "switch")
    return xr.Dataset(
        {
            "overturning_amplitude": ("period", first, {"units": "m/s²"}),
            "kappa": ("period", first / uplift, {"units": "-"}),
            "switch_amplitude": (dims, amp, {"units": "m/s²"}),
            "switch_kappa": (dims, amp / uplift, {"units": "-"}),
            "overturns": (dims, over),
            "impacts_before_overturning": (dims, mode),
            "overturning_time": (dims, t_ov, {"units": "s"}),
        },
        coords={
            "period": ("period", periods, {"units": "s"}),
            "omega_ratio": ("period", 2.0 * np.pi / periods / p, {"units": "-"}),
            "duration": ("period", durations, {"units": "s"}),
            "dt": ("period", steps, {"units": "s"}),
            "switch": np.arange(n_sw),
        },
        attrs=attrs,
    )
