"""Figures of overturning spectra under pulses (issue 46), in the style of Zhang & Makris (2001):
the smallest overturning amplitude, the overturning branches and the safe bands above it."""

from __future__ import annotations

from typing import TYPE_CHECKING

import numpy as np

from ..defaults import G
from . import new_figure

if TYPE_CHECKING:
    import xarray as xr
    from matplotlib.figure import Figure

#: Fill of the amplitudes that overturn the block, and of the safe bands above the minimum.
OVERTURNING_COLOUR = "#f4b6b0"
SAFE_BAND_COLOUR = "#b9e3b0"


def plot_overturning_spectrum(ds: xr.Dataset, *, physical: bool = False) -> Figure:
    """The overturning spectrum ``ds`` (:func:`rocking.overturning_spectrum`).

    Dimensionless (default): κ = a_p/(g·tan α) [-] against Ω = ω_p/p [-], with the uplift line
    κ = 1 (below it the block does not move).  ``physical``: the pulse amplitude a_p [g] against
    its period T_p [s] for the block of ``ds`` (uplift at tan α g).  Amplitudes that overturn
    the block are shaded red, the safe bands above the smallest overturning amplitude green;
    the search stopped at ``kappa_max`` (dotted line).
    """
    tan_a = float(np.tan(ds.attrs["alpha"]))
    if physical:
        x = ds["period"].values
        scale, limit, uplift = tan_a, ds.attrs["kappa_max"] * tan_a, tan_a
        xlabel, ylabel = "pulse period T_p [s]", "pulse amplitude a_p [g]"
    else:
        x = ds["omega_ratio"].values
        scale, limit, uplift = 1.0, ds.attrs["kappa_max"], 1.0
        xlabel, ylabel = "Ω = ω_p/p [-]", "κ = a_p/(g·tan α) [-]"
    order = np.argsort(x)
    x = x[order]
    sw = ds["switch_kappa"].values[order] * scale
    over = ds["overturns"].values[order]
    # each period a column reaching halfway to its neighbours, one box per branch
    mids = (x[1:] + x[:-1]) / 2
    first = x[1] - x[0] if x.size > 1 else 0.1 * x[0]
    last = x[-1] - x[-2] if x.size > 1 else 0.1 * x[0]
    left = np.concatenate([[x[0] - first / 2], mids])
    right = np.concatenate([mids, [x[-1] + last / 2]])
    fig = new_figure(figsize=(7.0, 4.6), layout="constrained")
    ax = fig.add_subplot()
    for i in range(x.size):
        found = sw[i][np.isfinite(sw[i])]
        tops = np.append(found[1:], limit)
        for k, (lower, upper) in enumerate(zip(found, tops)):
            colour = OVERTURNING_COLOUR if over[i, k] else SAFE_BAND_COLOUR
            ax.fill_between([left[i], right[i]], lower, upper, color=colour, lw=0)
    ax.plot(x, sw[:, 0], color="k", lw=1.4, label="smallest overturning amplitude")
    ax.axhline(uplift, color="0.3", ls="--", lw=1.0, label="uplift (a_p = g·tan α, κ = 1)")
    ax.axhline(limit, color="0.5", ls=":", lw=1.0, label="limit of the search")
    ax.fill_between([], [], color=OVERTURNING_COLOUR, label="overturns")
    ax.fill_between([], [], color=SAFE_BAND_COLOUR, label="safe band above the minimum")
    ax.set_xlim(left[0], right[-1])
    ax.set_ylim(0.0, limit * 1.05)
    ax.set_xlabel(xlabel)
    ax.set_ylabel(ylabel)
    block = f"R = {ds.attrs['R']:.3g} m, γ = {ds.attrs['gamma']:.3g}, e = {ds.attrs['e']:.3g}"
    what = f"{ds.attrs['shape']} pulse; {block}"
    if physical:
        what += f" (uplift at {tan_a:.3g} g = {tan_a * G:.3g} m/s²)"
    ax.set_title(what, fontsize="medium")
    ax.legend(fontsize="small", loc="upper left" if not physical else "upper right")
    ax.grid(True, alpha=0.3)
    return fig
