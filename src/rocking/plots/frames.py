"""Figures of shear frames: mode shapes and floor response spectra (paper Fig. 12)."""

from __future__ import annotations

from collections.abc import Sequence
from typing import TYPE_CHECKING

import numpy as np
from numpy.typing import ArrayLike

from . import new_figure

if TYPE_CHECKING:
    from matplotlib.figure import Figure

    from ..structures.frames import ShearFrame


def plot_mode_shapes(frame: ShearFrame) -> Figure:
    """Mode shapes of a :class:`rocking.structures.frames.ShearFrame`, each scaled so that its
    largest entry in absolute value is 1, drawn against the floor level (0 = ground)."""
    fig = new_figure(figsize=(5.0, 5.5), layout="constrained")
    ax = fig.add_subplot()
    levels = np.arange(frame.n_stories + 1)
    phi = frame.mode_shapes
    for r, period in enumerate(frame.periods):
        shape = np.concatenate([[0.0], phi[:, r] / np.abs(phi[:, r]).max()])
        ax.plot(shape, levels, marker="o", label=f"mode {r + 1}, T = {period:.3g} s")
    ax.axvline(0.0, color="0.6", lw=0.8)
    ax.set_yticks(levels, ["ground"] + [str(i) for i in levels[1:]])
    ax.set_xlabel("mode shape, scaled to max |φ| = 1 [-]")
    ax.set_ylabel("floor")
    ax.set_title(f"{frame.name}: mode shapes")
    ax.legend(fontsize="small")
    return fig


def plot_floor_spectra(
    freqs_hz: ArrayLike, psv: ArrayLike, labels: Sequence[str], *, title: str = ""
) -> Figure:
    """Pseudo-velocity spectra of the ground and floors on log-log axes (as paper Fig. 12).

    Parameters
    ----------
    freqs_hz : array_like
        Frequencies (n_freq,) [Hz].
    psv : array_like
        Pseudo-velocities (n_locations, n_freq) [m/s]; drawn in cm/s.
    labels : sequence of str
        One legend entry per row of ``psv`` (e.g. "ground", "floor 1", ...).
    title : str
        Figure title.
    """
    fig = new_figure(figsize=(6.5, 4.8), layout="constrained")
    ax = fig.add_subplot()
    for row, label in zip(np.asarray(psv), labels):
        ax.loglog(freqs_hz, 100.0 * row, label=label)
    ax.set_xlabel("frequency [Hz]")
    ax.set_ylabel("pseudo-velocity S_v [cm/s]")
    ax.grid(True, which="both", lw=0.4, alpha=0.5)
    ax.legend()
    if title:
        ax.set_title(title)
    return fig
