"""Figures specific to the paper's studies: rocking time histories (paper Figs. 3–8) and the
friction study beyond the paper (issue 45)."""

from __future__ import annotations

from collections.abc import Sequence
from typing import TYPE_CHECKING

import numpy as np
from numpy.typing import ArrayLike

from . import new_figure

if TYPE_CHECKING:
    import xarray as xr
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


def plot_friction(ds: xr.Dataset, *, title: str = "") -> Figure:
    """A_gx50 against the friction coefficient μ per body (left; infinite friction, the paper's
    model, drawn at the right end and marked ∞), and the share of the motions in which each body
    slides or slide-rocks at its A_gx50 with friction (right; bars stacked per body and μ).

    Parameters
    ----------
    ds : xarray.Dataset
        Result of :func:`rocking.studies.friction.friction_study`: ``agx50`` [g] on (mu, body)
        and ``share`` [-] on (mu, body, level, mode); ``mu`` [-] ends with inf; attribute
        ``agx_max`` [g] (optional): where a NaN A_gx50 (50 % not reached) is marked.
    title : str
        Figure title.
    """
    mus = ds["mu"].values
    finite = np.isfinite(mus)
    step = float(np.diff(mus[finite]).min()) if finite.sum() > 1 else 0.1
    # infinite friction two steps right of the largest μ
    x = np.where(finite, mus, (mus[finite].max() if finite.any() else 0.0) + 2 * step)
    fig = new_figure(figsize=(10.0, 4.2), layout="constrained")
    left, right = fig.subplots(1, 2)
    bodies = [str(b) for b in ds["body"].values]
    for j, body in enumerate(bodies):
        y = ds["agx50"].sel(body=body).values
        left.plot(x, y, "o-", ms=4, color=f"C{j % 10}", label=body)
        if "agx_max" in ds.attrs and np.isnan(y).any():  # 50 % not reached: a mark at the top
            top = np.full(y.shape, float(ds.attrs["agx_max"]))
            left.plot(x[np.isnan(y)], top[np.isnan(y)], "^", ms=6, color=f"C{j % 10}")
    if "agx_max" in ds.attrs and ds["agx50"].isnull().any():
        left.axhline(float(ds.attrs["agx_max"]), color="0.6", lw=0.6, ls="--")
        left.annotate(
            "▲ 50 % not reached",
            (0.01, float(ds.attrs["agx_max"])),
            xycoords=("axes fraction", "data"),
            va="top",
            fontsize="small",
            color="0.4",
        )
    left.set_xticks(x, [f"{m:g}" if np.isfinite(m) else "∞" for m in mus])
    left.set_xlabel("friction coefficient μ [-]")
    left.set_ylabel("A_gx50 [g]")
    left.grid(True, lw=0.4, alpha=0.5)
    own = ds["share"].isel(level=0)
    width = 0.8 * step / max(len(bodies), 1)
    for j, body in enumerate(bodies):
        xs = x + (j - (len(bodies) - 1) / 2) * width
        slide = np.nan_to_num(own.sel(body=body, mode="slide").values)
        both = np.nan_to_num(own.sel(body=body, mode="slide-rock").values)
        right.bar(xs, slide, width, color=f"C{j % 10}", alpha=0.45)
        right.bar(xs, both, width, bottom=slide, color=f"C{j % 10}", hatch="//", alpha=0.9)
    from matplotlib.patches import Patch

    kinds = [Patch(color="0.6", alpha=0.45), Patch(facecolor="0.6", hatch="//")]
    right.set_xticks(x, [f"{m:g}" if np.isfinite(m) else "∞" for m in mus])
    right.set_ylim(0.0, 1.0)
    right.set_xlabel("friction coefficient μ [-]")
    right.set_ylabel("share of the motions at A_gx50 [-]")
    right.grid(True, axis="y", lw=0.4, alpha=0.5)
    handles, labels = left.get_legend_handles_labels()
    right.legend(
        [*handles, *kinds],
        [*labels, "slide", "slide-rock"],
        loc="upper left",
        bbox_to_anchor=(1.01, 1.0),
        fontsize="small",
    )
    if title:
        fig.suptitle(title, fontsize="medium")
    return fig
