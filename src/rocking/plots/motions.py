"""Figures of ground motions: intensity functions (paper Fig. 2) and the effect of baseline
correction on acceleration, velocity and displacement (paper Section 4)."""

from __future__ import annotations

from collections.abc import Mapping, Sequence
from typing import TYPE_CHECKING

import numpy as np
from numpy.typing import ArrayLike
from scipy.integrate import cumulative_trapezoid

from ..dynamics.body import G
from . import new_figure

if TYPE_CHECKING:
    from matplotlib.figure import Figure

    from ..motions.envelopes import Envelope


def plot_envelopes(envelopes: Sequence[Envelope], *, title: str = "") -> Figure:
    """Intensity functions I(t) against time, one line each (cf. paper Fig. 2).

    Parameters
    ----------
    envelopes : sequence
        Intensity functions of :mod:`rocking.motions.envelopes` (called on t [s], with ``duration``
        [s]).
    title : str
        Figure title.
    """
    fig = new_figure(figsize=(6.5, 3.6), layout="constrained")
    ax = fig.add_subplot()
    for env in envelopes:
        t = np.linspace(0.0, env.duration, 1001)
        label = (
            f"{type(env).__name__.lower()}, T = {env.duration:g} s, "
            f"T_e = {env.equivalent_duration():.3g} s"
        )
        ax.plot(t, env(t), lw=1.5, label=label)
    ax.set_xlabel("time t [s]")
    ax.set_ylabel("intensity I(t) [-]")
    ax.set_ylim(0.0, 1.08)
    ax.grid(True, lw=0.4, alpha=0.5)
    ax.legend(fontsize="small")
    if title:
        ax.set_title(title)
    return fig


def plot_baseline_comparison(
    dt: float,
    raw: ArrayLike,
    corrected: ArrayLike,
    labels: Sequence[str] | None = None,
    *,
    title: str = "",
) -> Figure:
    """Acceleration, velocity and displacement of motions before and after baseline correction.

    Velocity and displacement are integrated from rest with the trapezoidal rule.

    Parameters
    ----------
    dt : float
        Time step [s].
    raw, corrected : array_like, shape (n, n_t)
        Accelerations before and after correction [m/s²].
    labels : sequence of str, optional
        One name per motion.
    title : str
        Figure title.
    """
    raw = np.atleast_2d(np.asarray(raw, dtype=float))
    corrected = np.atleast_2d(np.asarray(corrected, dtype=float))
    t = np.arange(raw.shape[1]) * dt
    fig = new_figure(figsize=(7.5, 7.0), layout="constrained")
    axes = fig.subplots(3, 1, sharex=True)
    units = ("acceleration [g]", "velocity [m/s]", "displacement [m]")
    for k, (a_raw, a_cor) in enumerate(zip(raw, corrected)):
        name = f"{labels[k]}: " if labels is not None else ""
        color = f"C{k % 10}"
        for acc, style, what in ((a_raw, "--", "uncorrected"), (a_cor, "-", "corrected")):
            vel = cumulative_trapezoid(acc, dx=dt, initial=0.0)
            disp = cumulative_trapezoid(vel, dx=dt, initial=0.0)
            for ax, y in zip(axes, (acc / G, vel, disp)):
                ax.plot(t, y, style, color=color, lw=0.8, label=f"{name}{what}")
    for ax, unit in zip(axes, units):
        ax.set_ylabel(unit)
        ax.grid(True, lw=0.4, alpha=0.5)
    axes[-1].set_xlabel("time t [s]")
    axes[-1].legend(fontsize="x-small", ncol=2)
    if title:
        fig.suptitle(title)
    return fig


def plot_fit_ratios(
    freqs_hz: ArrayLike,
    ratios: Mapping[str, ArrayLike],
    *,
    tolerance: float = 0.10,
    band: tuple[float, float] | None = None,
    title: str = "",
) -> Figure:
    """Ensemble-mean PSA over the target PSA against frequency, one line per method.

    Parameters
    ----------
    freqs_hz : array_like, shape (n_freq,)
        Frequencies [Hz].
    ratios : dict
        Label -> mean PSA / target PSA [-] at ``freqs_hz``.
    tolerance : float
        Half-width of the shaded acceptance band around 1 [-] (0.10: ±10 %).
    band : (float, float), optional
        Frequency band of the criterion [Hz], marked by vertical lines.
    title : str
        Figure title.
    """
    f = np.asarray(freqs_hz, dtype=float)
    fig = new_figure(figsize=(6.5, 4.2), layout="constrained")
    ax = fig.add_subplot()
    ax.set_xscale("log")
    ax.axhspan(
        1.0 - tolerance, 1.0 + tolerance, color="0.85", label=f"target ± {100 * tolerance:g} %"
    )
    ax.axhline(1.0, color="k", lw=0.8)
    for label, ratio in ratios.items():
        ax.plot(f, np.asarray(ratio, dtype=float), lw=1.3, label=label)
    for edge in band or ():
        ax.axvline(edge, color="0.4", ls=":", lw=1.0)
    ax.set_xlabel("frequency [Hz]")
    ax.set_ylabel("mean PSA / target PSA [-]")
    ax.grid(True, which="both", lw=0.4, alpha=0.5)
    ax.legend(fontsize="small")
    if title:
        ax.set_title(title)
    return fig
