"""Figures specific to the paper's studies: rocking time histories (paper Figs. 3–8)."""

from __future__ import annotations

from collections.abc import Sequence
from typing import TYPE_CHECKING

import numpy as np
from numpy.typing import ArrayLike

from . import new_figure

if TYPE_CHECKING:
    from matplotlib.figure import Figure

#: Margins of :func:`plot_responses` [in], fixed instead of a layout engine (constrained layout
#: took 40 % of the time to save the figure): left for y tick labels of up to five characters
#: ("−12.5"; |θ|/α stays below (π/2)/α, which is below 10⁴ for γ < 6000) and the y label, right
#: for half the last x tick label ("20.0"), bottom for the x tick labels and label, top and
#: between panels for a panel's title, and above that the figure title when there is one.
MARGINS = {"left": 0.8, "right": 0.2, "bottom": 0.5, "top": 0.25, "gap": 0.32, "title": 0.3}


def plot_responses(
    t: ArrayLike,
    theta_over_alpha: ArrayLike,
    labels: Sequence[str],
    *,
    overturned: ArrayLike | None = None,
    title: str = "",
) -> Figure:
    """Rocking responses θ(t)/α, one panel per case, on a shared time axis (paper Figs. 3–8).

    Parameters
    ----------
    t : array_like, shape (n_t,)
        Times [s].
    theta_over_alpha : array_like, shape (n_cases, n_t)
        Rotation over the body's critical angle, θ/α [-] (NaN after overturning).
    labels : sequence of str
        One panel title per case (e.g. "γ = 5").
    overturned : sequence of float, optional
        Time of overturning of each case [s] (NaN: did not overturn); marked with a red line.
    title : str
        Figure title.
    """
    y = np.atleast_2d(np.asarray(theta_over_alpha, dtype=float))
    n = y.shape[0]
    width, height = 7.5, 1.7 * n + 0.8
    top = MARGINS["top"] + (MARGINS["title"] if title else 0.0)
    panel = (height - MARGINS["bottom"] - top - MARGINS["gap"] * (n - 1)) / n
    fig = new_figure(figsize=(width, height))
    axes = fig.subplots(
        n,
        1,
        sharex=True,
        squeeze=False,
        gridspec_kw={
            "left": MARGINS["left"] / width,
            "right": 1.0 - MARGINS["right"] / width,
            "bottom": MARGINS["bottom"] / height,
            "top": 1.0 - top / height,
            "hspace": MARGINS["gap"] / panel,
        },
    )[:, 0]
    t_ov = np.full(n, np.nan) if overturned is None else np.asarray(overturned, dtype=float)
    for ax, row, label, tov in zip(axes, y, labels, t_ov):
        ax.plot(t, row, lw=0.8, color="C0")
        ax.axhline(1.0, color="0.6", lw=0.6, ls="--")
        ax.axhline(-1.0, color="0.6", lw=0.6, ls="--")
        if np.isfinite(tov):
            ax.axvline(tov, color="C3", lw=1.0)
            label = f"{label}: overturns at t = {tov:.2f} s"
        else:
            peak = np.nanmax(np.abs(row)) if np.isfinite(row).any() else np.nan
            label = f"{label}: max |θ|/α = {peak:.3g}"
        ax.set_title(label, fontsize="small", loc="left")
        ax.set_ylabel("θ/α [-]")
        ax.grid(True, lw=0.4, alpha=0.5)
    axes[-1].set_xlabel("time t [s]")
    if title:
        fig.suptitle(title, fontsize="medium", y=1.0 - 0.25 * MARGINS["title"] / height)
    return fig
