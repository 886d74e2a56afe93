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
    slides or slide-rocks without overturning, at its A_gx50 with friction (middle) and at the
    paper's A_gx50 (right; bars stacked per slenderness γ and μ, the mean over the bodies of
    that γ).  One colour per γ.

    Parameters
    ----------
    ds : xarray.Dataset
        Result of :func:`rocking.studies.friction.friction_study`: ``agx50`` [g] on (mu, body)
        and ``share`` [-] on (mu, body, level, mode), body coordinates ``gamma`` [-], ``R`` [m]
        and ``b_over_h`` [-]; ``mu`` [-] ends with inf; attribute
        ``agx_max`` [g] (optional): where a NaN A_gx50 (50 % not reached) is marked.
    title : str
        Figure title.
    """
    from matplotlib.lines import Line2D
    from matplotlib.patches import Patch

    mus = ds["mu"].values
    finite = np.isfinite(mus)
    step = float(np.diff(mus[finite]).min()) if finite.sum() > 1 else 0.1
    # infinite friction two steps right of the largest μ
    x = np.where(finite, mus, (mus[finite].max() if finite.any() else 0.0) + 2 * step)
    ticks = [f"{m:g}" if np.isfinite(m) else "∞" for m in mus]
    fig = new_figure(figsize=(13.0, 4.2), layout="constrained")
    axes = fig.subplots(1, 3)
    # one colour per slenderness γ (the paper's 72 bodies: 8 sizes of each of 9 γ)
    gammas = np.unique(ds["gamma"].values)
    group = np.searchsorted(gammas, ds["gamma"].values)
    top = float(ds.attrs.get("agx_max", np.nan))
    handles = []
    for j, g in enumerate(gammas):
        members = np.flatnonzero(group == j)
        for b in members:
            y = ds["agx50"].isel(body=b).values
            (line,) = axes[0].plot(x, y, "o-", ms=3, lw=1.0, color=f"C{j % 10}")
            if np.isfinite(top) and np.isnan(y).any():  # 50 % not reached: a mark at the top
                axes[0].plot(
                    x[np.isnan(y)], np.full(np.isnan(y).sum(), top), "^", color=line.get_color()
                )
        bh = float(ds["b_over_h"].values[members[0]])
        many = (
            f", {members.size} bodies"
            if members.size > 1
            else f", R={float(ds['R'][members[0]]):.2f} m"
        )
        line.set_label(f"γ={g:g} (B/H={bh:.2g}{many})")
        handles.append(line)
    if np.isfinite(top) and ds["agx50"].isnull().any():
        axes[0].axhline(top, color="0.6", lw=0.6, ls="--")
        handles.append(Line2D([], [], color="0.5", marker="^", ls="", label="50 % not reached"))
    axes[0].set_ylabel("A_gx50 [g]")
    width = 0.8 * step / gammas.size
    for ax, level in zip(axes[1:], ds["level"].values):
        # the mean share over the bodies of each γ (NaN, where A_gx50 is not found, as 0)
        at = ds["share"].sel(level=level).fillna(0.0)
        for j in range(gammas.size):
            xs = x + (j - (gammas.size - 1) / 2) * width
            slide = at.sel(mode="slide").values[:, group == j].mean(axis=1)
            both = at.sel(mode="slide-rock").values[:, group == j].mean(axis=1)
            ax.bar(xs, slide, width, color=f"C{j % 10}", alpha=0.45)
            ax.bar(xs, both, width, bottom=slide, color=f"C{j % 10}", hatch="//", alpha=0.9)
        ax.set_ylim(0.0, 1.0)
        ax.set_ylabel(f"share of the motions at {level} [-]")
        ax.grid(True, axis="y", lw=0.4, alpha=0.5)
    for ax in axes:
        ax.set_xticks(x, ticks)
        ax.set_xlabel("friction coefficient μ [-]")
    axes[0].grid(True, lw=0.4, alpha=0.5)
    handles += [
        Patch(color="0.6", alpha=0.45, label="slide"),
        Patch(facecolor="0.6", hatch="//", label="slide-rock"),
    ]
    axes[-1].legend(handles=handles, loc="upper left", bbox_to_anchor=(1.01, 1.0), fontsize="small")
    if title:
        fig.suptitle(title, fontsize="medium")
    return fig
