"""Figures of response spectra: spectra of records, and an ensemble against its target."""

from __future__ import annotations

from collections.abc import Sequence
from typing import TYPE_CHECKING

import numpy as np
from numpy.typing import ArrayLike

from . import new_figure

if TYPE_CHECKING:
    from matplotlib.axes import Axes
    from matplotlib.figure import Figure

    from ..motions.targets import TargetSpectrum


def _log_axes(fig: Figure, title: str) -> Axes:
    ax = fig.add_subplot()
    ax.set_xscale("log")
    ax.set_yscale("log")
    ax.set_xlabel("frequency [Hz]")
    ax.set_ylabel("pseudo-acceleration PSA [g]")
    ax.grid(True, which="both", lw=0.4, alpha=0.5)
    if title:
        ax.set_title(title)
    return ax


def plot_spectra(
    freqs_hz: ArrayLike,
    psa_g: ArrayLike,
    labels: Sequence[str] | None = None,
    *,
    damping: float | None = None,
    title: str = "",
) -> Figure:
    """PSA spectra against frequency on log-log axes, one line per spectrum.

    Parameters
    ----------
    freqs_hz : array_like, shape (n_freq,)
        Frequencies [Hz].
    psa_g : array_like, shape (n_freq,) or (n_lines, n_freq)
        Pseudo-accelerations [g].
    labels : sequence of str, optional
        One legend entry per line.
    damping : float, optional
        Damping ratio [-], shown in the title.
    title : str
        Figure title (the damping is appended when given).
    """
    psa = np.atleast_2d(np.asarray(psa_g, dtype=float))
    if damping is not None:
        title = f"{title + ', ' if title else ''}{100 * damping:g} % damping"
    fig = new_figure(figsize=(6.5, 4.8), layout="constrained")
    ax = _log_axes(fig, title)
    for k, row in enumerate(psa):
        ax.plot(freqs_hz, row, lw=1.2, label=None if labels is None else labels[k])
    if labels is not None:
        ax.legend(fontsize="small")
    return fig


def plot_mean_vs_target(
    freqs_hz: ArrayLike, psa_members: ArrayLike, target: TargetSpectrum, *, title: str = ""
) -> Figure:
    """Mean ± 1 standard deviation of an ensemble's PSA spectra against a target spectrum.

    Parameters
    ----------
    freqs_hz : array_like, shape (n_freq,)
        Frequencies [Hz].
    psa_members : array_like, shape (n_members, n_freq)
        PSA of each member [g].
    target : rocking.motions.targets.TargetSpectrum
        Target spectrum (its ``psa`` is in g and its ``name`` labels the line).
    title : str
        Figure title.
    """
    f = np.asarray(freqs_hz, dtype=float)
    psa = np.atleast_2d(np.asarray(psa_members, dtype=float))
    mean = psa.mean(axis=0)
    std = psa.std(axis=0)
    fig = new_figure(figsize=(6.5, 4.8), layout="constrained")
    ax = _log_axes(fig, title)
    # On log axes a band reaching zero or below cannot be drawn: clip its lower edge.
    ax.fill_between(
        f,
        np.maximum(mean - std, 1e-3 * mean),
        mean + std,
        alpha=0.25,
        label=f"mean ± 1 std ({psa.shape[0]} members)",
    )
    ax.plot(f, mean, lw=1.5, label="ensemble mean")
    ax.plot(f, target.psa(f), "k--", lw=1.5, label=f"target: {target.name}")
    ax.legend(fontsize="small")
    return fig
