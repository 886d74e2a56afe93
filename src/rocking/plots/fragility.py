"""Figures of overturning probability and of Housner's energy balance (paper Figs. 9–11,
13–16)."""

from __future__ import annotations

from collections.abc import Hashable, Mapping
from typing import TYPE_CHECKING, Any

import numpy as np
from numpy.typing import ArrayLike

from ..defaults import BAND_HZ
from . import legend_beside, new_figure

if TYPE_CHECKING:
    import pandas as pd
    import xarray as xr
    from matplotlib.figure import Figure

    from ..montecarlo.statistics import LognormalFit

#: Most curves on one axis (each with a legend entry); more bodies are drawn as small multiples.
MAX_LEGEND = 12
#: Panels per row of the small multiples.
PANEL_COLUMNS = 4


#: Label of the intensity axis of the paper's fragility curves.
AGX_LABEL = "ensemble mean peak acceleration A_gx [g]"


def plot_fragility(
    ds: xr.Dataset,
    *,
    fits: Mapping[Hashable, LognormalFit] | None = None,
    title: str = "",
    xlabel: str = AGX_LABEL,
    ylabel: str = "probability of overturning [-]",
) -> Figure:
    """Overturning probability against A_gx, one curve per body (paper Figs. 9–11, 13).

    Each curve has a lightly shaded band between ``ci_low`` and ``ci_high`` (the Wilson
    interval at the level of attribute ``confidence``, default 0.95; light, so that the bands
    of several curves stay readable where they overlap) and, when ``fits`` has an entry for it, the
    fitted lognormal curve Φ(ln(A_gx/median)/β) dashed.

    Up to :data:`MAX_LEGEND` curves share one axis, each named in the legend (beside the axes,
    where it covers no curve). More bodies
    (e.g. the paper's 72, without a ``case`` dimension) are drawn as small multiples: one panel
    per size R, one curve per γ coloured from light (small γ, stocky) to dark (slender) the
    same way in every panel, named in one legend (a colour bar when there are more than
    :data:`MAX_LEGEND` values of γ). Small multiples rather than a heat map of P over (γ, A_gx)
    keep the Wilson bands and the fits visible and the probabilities readable off an axis.

    Parameters
    ----------
    ds : xarray.Dataset
        Result of :func:`rocking.montecarlo.probability.overturning_probability`:
        ``probability``, ``ci_low``, ``ci_high`` [-] on dimensions (``body``, ``agx``) or
        (``case``, ``body``, ``agx``), ``agx`` [g]; coordinates ``R`` [m] and ``gamma`` [-] on
        ``body``.
    fits : dict, optional
        :class:`~rocking.LognormalFit` objects keyed by body label, or by (case, body) when
        ``ds`` has a ``case`` dimension.
    title : str
        Figure title.
    xlabel : str
        Label of the intensity axis (another IM than A_gx: its name and unit; the values are
        still those of the ``agx`` coordinate).
    ylabel : str
        Label of the probability axis (of a limit state other than overturning: its name).
    """
    fits = fits or {}
    if "case" not in ds.dims and ds.sizes["body"] > MAX_LEGEND:
        return _plot_by_size(ds, fits, title, xlabel)
    agx = ds["agx"].values
    fig = new_figure(figsize=(9.0, 4.8), layout="constrained")
    ax = fig.add_subplot()
    curves = _curves(ds)
    for k, (key, label, sel) in enumerate(curves):
        _draw_curve(
            ax,
            agx,
            sel,
            fits.get(key),
            f"C{k % 10}",
            label=label if k < MAX_LEGEND else None,
            alpha=0.2 if len(curves) == 1 else 0.08,  # a band alone can be darker
        )
    _probability_axes(ax)
    ax.set_xlabel(xlabel)
    ax.set_ylabel(ylabel)
    extra = f" ({len(curves) - MAX_LEGEND} more not listed)" if len(curves) > MAX_LEGEND else ""
    legend_beside(ax, _key_text(ds, fits).replace("; ", "\n") + extra)
    if title:
        ax.set_title(title)
    return fig


def _plot_by_size(
    ds: xr.Dataset, fits: Mapping[Hashable, LognormalFit], title: str, xlabel: str
) -> Figure:
    """Small multiples of :func:`plot_fragility`: one panel per R, one curve per γ."""
    from matplotlib import colormaps
    from matplotlib.cm import ScalarMappable
    from matplotlib.colors import ListedColormap, Normalize
    from matplotlib.lines import Line2D

    agx = ds["agx"].values
    r_mm = np.round(1000.0 * ds["R"].values)  # bodies of one size share a panel
    sizes = np.unique(r_mm)
    gammas = np.unique(ds["gamma"].values)
    # viridis from light (stocky) to dark (slender), without its palest end (faint on white)
    cmap = ListedColormap(colormaps["viridis_r"](np.linspace(0.15, 1.0, 256)))
    norm = Normalize(gammas.min(), gammas.max() if gammas.size > 1 else gammas.min() + 1.0)
    ncols = min(PANEL_COLUMNS, sizes.size)
    nrows = -(-sizes.size // ncols)
    fig = new_figure(figsize=(2.6 * ncols + 1.8, 2.2 * nrows + 1.0), layout="constrained")
    axes = fig.subplots(nrows, ncols, sharex=True, sharey=True, squeeze=False).ravel()
    for ax, size in zip(axes, sizes):
        index = np.flatnonzero(r_mm == size)
        for i in index[np.argsort(ds["gamma"].values[index])]:
            sel = ds.isel(body=i)
            _draw_curve(
                ax,
                agx,
                sel,
                fits.get(str(sel["body"].values)),
                cmap(norm(float(sel["gamma"]))),
                ms=2.0,
                alpha=0.1,
            )
        _probability_axes(ax)
        ax.set_title(f"R = {size / 1000.0:.2f} m", fontsize="small")
        ax.tick_params(labelsize="small")
    for ax in axes[sizes.size :]:
        ax.remove()
    fig.supxlabel(xlabel, fontsize="medium")
    fig.supylabel("probability of overturning [-]", fontsize="medium")
    key = _key_text(ds, fits).replace("; ", "\n")
    if gammas.size <= MAX_LEGEND:
        handles = [
            Line2D([], [], color=cmap(norm(g)), marker="o", ms=3, label=f"γ = {g:g}")
            for g in gammas
        ]
        fig.legend(
            handles=handles,
            loc="outside right upper",
            fontsize="small",
            title=f"slenderness γ\n{key}",
            title_fontsize="small",
        )
    else:
        fig.colorbar(
            ScalarMappable(norm, cmap),
            ax=axes[: sizes.size].tolist(),
            label=f"slenderness γ [-] ({key})".replace("\n", "; "),
        )
    if title:
        fig.suptitle(title)
    return fig


def _draw_curve(
    ax, agx, sel, fit, color, *, label=None, ms: float = 3.0, alpha: float = 0.08
) -> None:
    """One probability curve with its Wilson band (opacity ``alpha``) and, if fitted, its
    lognormal fit. The band is drawn where the curve rises, from the level before its first
    probability above 0 to the level after its last one below 1: elsewhere every curve of an
    ensemble has the same band (0 of n or n of n), whose stack would hide the others."""
    p = sel["probability"].values
    first = int(np.argmax(p > 0.0)) if (p > 0.0).any() else p.size  # first above 0
    last = int(p.size - 1 - np.argmax(p[::-1] < 1.0)) if (p < 1.0).any() else -1  # last below 1
    where = np.zeros(p.shape, bool)
    where[max(first - 1, 0) : last + 2] = True
    ax.fill_between(
        agx,
        sel["ci_low"].values,
        sel["ci_high"].values,
        where=where,
        color=color,
        alpha=alpha,
        lw=0,
    )
    ax.plot(agx, sel["probability"].values, "o-", color=color, ms=ms, lw=1.2, label=label)
    if fit is not None and np.isfinite(fit.median) and np.isfinite(fit.beta) and fit.beta > 0:
        fine = np.linspace(agx.min(), agx.max(), 200)
        ax.plot(fine, fit.probability(fine), "--", color=color, lw=1.0)


def _probability_axes(ax) -> None:
    ax.axhline(0.5, color="0.5", lw=0.8, ls=":")
    ax.set_ylim(-0.02, 1.02)
    ax.grid(True, lw=0.4, alpha=0.5)


def _key_text(ds, fits) -> str:
    band = f"shaded: {100 * ds.attrs.get('confidence', 0.95):g} % Wilson interval"
    return band + ("; dashed: lognormal fit" if fits else "")


def plot_sv_agx(energy_ds: xr.Dataset, *, title: str = "") -> Figure:
    """Required S_v (Eq. 11) against the A_gx of 50 % overturning probability, with the
    least-squares straight line (paper Figs. 15 and 16) and, dashed, the available S_v1 of the
    ensemble at each A_gx (points on it have S_v1/S_v = 1, Table 3).

    Parameters
    ----------
    energy_ds : xarray.Dataset
        Result of :func:`rocking.assessment.energy.energy_balance` (``sv_required`` and ``sv1``
        [m/s], ``agx50`` [g]); bodies with NaN A_gx50 are left out.  With a ``limit_state``
        dimension (``agx50`` and ``sv1`` per limit state), one series of points and its line
        per limit state.
    title : str
        Figure title.
    """
    states = list(energy_ds["limit_state"].values) if "limit_state" in energy_ds.dims else [None]
    fig = new_figure(figsize=(6.0, 4.8), layout="constrained")
    ax = fig.add_subplot()
    every = energy_ds["agx50"].values
    top = np.nanmax(every) if np.isfinite(every).any() else 1.0
    xs = np.array([0.0, top * 1.05])
    for i, state in enumerate(states):
        one = energy_ds if state is None else energy_ds.sel(limit_state=state)
        x = one["agx50"].values
        y = 100.0 * one["sv_required"].values
        ok = np.isfinite(x) & np.isfinite(y)
        # overturning alone: the paper's black line; limit states: a colour each (not C3, the
        # S_v1 line's)
        color: dict[str, Any] = {} if state is None else {"color": f"C{i + (i >= 3)}"}
        label = f"{int(ok.sum())} bodies" + ("" if state is None else f" ({state})")
        ax.plot(x[ok], y[ok], "o", ms=4, label=label, **color)
        if ok.sum() >= 2 and np.ptp(x[ok]) > 0:
            slope, intercept = np.polyfit(x[ok], y[ok], 1)
            r2 = np.corrcoef(x[ok], y[ok])[0, 1] ** 2
            ax.plot(
                xs,
                intercept + slope * xs,
                "-",
                color=color.get("color", "k"),
                lw=1.2,
                label=f"least squares: S_v = {slope:.1f}·A_gx {'+' if intercept >= 0 else '−'} "
                f"{abs(intercept):.1f} (R² = {r2:.3f})",
            )
    found = np.isfinite(every)
    if found.any():
        # S_v1 is proportional to A_gx (spectra scale with the motions): sv1/agx50 is the same
        # for every body; on this line S_v1 equals the required S_v.
        per_g = 100.0 * float(np.mean(energy_ds["sv1"].values[found] / every[found]))
        ax.plot(
            xs, per_g * xs, "--", color="C3", lw=1.0, label=f"S_v1 = {per_g:.1f}·A_gx (ratio 1)"
        )
    what = "overturning probability" if states == [None] else "probability of the limit state"
    ax.set_xlabel(f"A_gx at 50 % {what} [g]")
    ax.set_ylabel("required S_v, Eq. (11) [cm/s]")
    ax.grid(True, lw=0.4, alpha=0.5)
    ax.legend(fontsize="small")
    if title:
        ax.set_title(title)
    return fig


def plot_sv1_spectrum(
    freqs_hz: ArrayLike,
    psv: ArrayLike,
    *,
    sv_required: float | None = None,
    band_hz: tuple[float, float] = BAND_HZ,
    title: str = "",
) -> Figure:
    """Mean pseudo-velocity spectrum with the band of the available S_v shaded, its maximum in the
    band (S_v1) marked and the required S_v of Eq. (11) drawn (paper Fig. 14).

    Parameters
    ----------
    freqs_hz : array_like, shape (n_freq,)
        Frequencies [Hz].
    psv : array_like, shape (n_freq,)
        Mean pseudo-velocity [m/s] (e.g. of the ensemble scaled to a body's A_gx50); drawn in
        cm/s.
    sv_required : float, optional
        Required S_v [m/s] of the body (Eq. 11).
    band_hz : (float, float)
        Band [Hz] in which S_v1 is the maximum.
    title : str
        Figure title.
    """
    f = np.asarray(freqs_hz, dtype=float)
    v = 100.0 * np.asarray(psv, dtype=float)
    lo, hi = band_hz
    fig = new_figure(figsize=(6.5, 4.8), layout="constrained")
    ax = fig.add_subplot()
    ax.loglog(f, v, lw=1.4, label="mean PSV")
    ax.axvspan(lo, hi, color="0.85", zorder=0, label=f"band {lo:g}–{hi:g} Hz")
    inside = (f >= lo) & (f <= hi)
    if inside.any():
        k = np.flatnonzero(inside)[np.argmax(v[inside])]
        ax.plot(f[k], v[k], "o", color="C3", label=f"S_v1 = {v[k]:.1f} cm/s at {f[k]:.3g} Hz")
    if sv_required is not None:
        ax.axhline(
            100.0 * sv_required,
            color="k",
            ls="--",
            lw=1.0,
            label=f"required S_v (Eq. 11) = {100.0 * sv_required:.1f} cm/s",
        )
    ax.set_xlabel("frequency [Hz]")
    ax.set_ylabel("pseudo-velocity S_v [cm/s]")
    ax.grid(True, which="both", lw=0.4, alpha=0.5)
    ax.legend(fontsize="small")
    if title:
        ax.set_title(title)
    return fig


def plot_im_efficiency(efficiency: pd.DataFrame, *, title: str = "") -> Figure:
    """Dispersion β of the fragility against each intensity measure, per body: one row per
    body, one marker per IM with its bootstrap interval as a bar (smaller β: the IM predicts
    overturning better).

    Parameters
    ----------
    efficiency : pandas.DataFrame
        :func:`rocking.im_efficiency`'s table: columns ``body``, ``im``, ``beta``, ``beta_low``
        and ``beta_high`` [-] (NaN: no interval), optionally ``label`` (the IM's name and unit,
        used in the legend).
    title : str
        Figure title.
    """
    bodies = list(dict.fromkeys(efficiency["body"].astype(str)))
    ims = list(dict.fromkeys(efficiency["im"].astype(str)))
    labels = (
        dict(zip(efficiency["im"].astype(str), efficiency["label"].astype(str)))
        if "label" in efficiency
        else {im: im for im in ims}
    )
    fig = new_figure(figsize=(9.0, 1.2 + 0.42 * len(bodies)), layout="constrained")
    ax = fig.add_subplot()
    row = {b: i for i, b in enumerate(bodies)}
    step = 0.7 / max(len(ims), 1)  # the IMs of a body side by side within its row
    markers = "osD^v<>ph*"
    for k, im in enumerate(ims):
        part = efficiency[efficiency["im"].astype(str) == im]
        y = np.array([row[str(b)] for b in part["body"]]) + (k - (len(ims) - 1) / 2) * step
        beta = part["beta"].to_numpy(float)
        low = part["beta_low"].to_numpy(float) if "beta_low" in part else beta
        high = part["beta_high"].to_numpy(float) if "beta_high" in part else beta
        ax.errorbar(
            beta,
            y,
            xerr=[np.nan_to_num(beta - low), np.nan_to_num(high - beta)],
            fmt=markers[k % len(markers)],
            color=f"C{k % 10}",
            ms=5,
            elinewidth=1.0,
            capsize=0,
            label=labels.get(im, im),
        )
    ax.set_yticks(range(len(bodies)), bodies, fontsize="small")
    ax.set_ylim(len(bodies) - 0.5, -0.5)
    ax.set_xlim(left=0.0)
    ax.set_xlabel("dispersion β of the fragility [-] (smaller: more efficient IM)")
    ax.grid(True, axis="x", lw=0.4, alpha=0.5)
    for y in np.arange(len(bodies) - 1) + 0.5:
        ax.axhline(y, color="0.85", lw=0.6)
    legend_beside(ax, "IM (bars: 95 % bootstrap\ninterval)")
    if title:
        ax.set_title(title)
    return fig


def _curves(ds):
    """(key, legend label, dataset of one curve) for every body (and case)."""
    bodies = [str(b) for b in ds["body"].values]
    if "case" not in ds.dims:
        return [(b, b, ds.isel(body=i)) for i, b in enumerate(bodies)]
    return [
        ((str(c), b), f"{c}: {b}", ds.isel(case=j, body=i))
        for j, c in enumerate(ds["case"].values)
        for i, b in enumerate(bodies)
    ]
