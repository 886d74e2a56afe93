"""Figure of an inventory screening on the S_v–A_gx plane (in the style of paper Fig. 15)."""

from __future__ import annotations

from typing import TYPE_CHECKING

import numpy as np

from . import new_figure

if TYPE_CHECKING:
    import xarray as xr
    from matplotlib.figure import Figure

#: Up to this many items every point is named; above it only those at risk.
MAX_NAMED = 25


def plot_screen(ds: xr.Dataset, *, title: str = "") -> Figure:
    """Every item at (A_gx of 50 % overturning probability, required S_v of Eq. 11).

    One colour per location. The dashed vertical line is the design A_gx: items to its left
    overturn with more than 50 % probability in the Monte Carlo runs. Each location's available
    S_v (the largest PSV in the band) is a dotted horizontal line of its colour: items below
    their line fail Housner's check. Items whose A_gx50 lies beyond the search range are drawn
    at its end with a ▸ marker.

    Parameters
    ----------
    ds : xarray.Dataset
        Result of :func:`rocking.assessment.screen.screen` (``agx50`` [g], ``sv_required`` and
        ``sv_available`` [m/s], ``location``, ``at_risk``; attributes
        ``design_agx`` and ``agx_max`` [g]).
    title : str
        Figure title.
    """
    agx50 = ds["agx50"].values
    sv = 100.0 * ds["sv_required"].values
    names = [str(v) for v in ds["item"].values]
    at_risk = ds["at_risk"].values
    design = float(ds.attrs["design_agx"])
    beyond = ~np.isfinite(agx50)
    x_end = float(ds.attrs.get("agx_max", np.nanmax(agx50, initial=design)))
    x = np.where(beyond, x_end, agx50)
    fig = new_figure(figsize=(7.0, 5.2), layout="constrained")
    ax = fig.add_subplot()
    # the ground first, then each frame's floors upwards
    keys = sorted(
        set(zip(ds["frame"].values.astype(str), ds["floor"].values.astype(int))),
        key=lambda key: (key[1] != 0, key),
    )
    for k, (frame, floor) in enumerate(keys):
        color = f"C{k % 10}"
        sel = (ds["floor"].values == floor) & ((floor == 0) | (ds["frame"].values == frame))
        available = 100.0 * float(ds["sv_available"].values[sel][0])
        label = f"{ds['location'].values[sel][0]} (available {available:.0f} cm/s)"
        ax.plot(x[sel & ~beyond], sv[sel & ~beyond], "o", color=color, ms=5, label=label)
        ax.plot(x[sel & beyond], sv[sel & beyond], ">", color=color, ms=6)
        ax.axhline(available, color=color, ls=":", lw=1.0)
    ax.axvline(design, color="k", ls="--", lw=1.0, label=f"design A_gx = {design:.3g} g")
    for i, name in enumerate(names):
        if len(names) <= MAX_NAMED or at_risk[i]:
            ax.annotate(name, (x[i], sv[i]), xytext=(4, 3), textcoords="offset points", fontsize=7)
    ax.set_xlim(left=0.0)
    ax.set_ylim(bottom=0.0)
    ground = ds.attrs.get("floor_motions", "building") == "building"
    ax.set_xlabel(("ground " if ground else "") + "A_gx at 50 % overturning probability [g]")
    ax.set_ylabel("required S_v, Eq. (11) [cm/s]")
    ax.grid(True, lw=0.4, alpha=0.5)
    ax.legend(
        fontsize="small", title="dotted: available S_v at the location", title_fontsize="small"
    )
    ax.set_title(title or f"Screening: {ds.attrs.get('spectrum', '')}", fontsize="medium")
    return fig
