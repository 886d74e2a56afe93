"""Figure of an inventory screening on the S_v–A_gx plane (in the style of paper Fig. 15)."""

from __future__ import annotations

from typing import TYPE_CHECKING

import numpy as np

from . import legend_beside, new_figure

if TYPE_CHECKING:
    import xarray as xr
    from matplotlib.axes import Axes
    from matplotlib.figure import Figure
    from matplotlib.transforms import Bbox

#: Up to this many items every point is numbered; above it only those at risk.
MAX_NAMED = 40
#: Points closer than this on the figure share one label [points, 1/72 inch].
SAME_POINT = 3.0
#: Least gap between a label and another label or point [points].
GAP = 1.5
#: Half the size of a point's marker, and of the ring about an item that slides [points].
POINT, RING = 3.5, 6.0
#: The ring's marker for each response marked (:data:`rocking.assessment.screen.RESPONSES`).
_RINGS = {"slide": "s", "slide-rock": "D"}
#: Offsets of a label from its point tried in turn, (dx, dy) [points]; the label's corner
#: nearest to the point is placed there.
_OFFSETS = [
    (dx * r, dy * r)
    for r in (4.0, 9.0, 15.0, 22.0)
    for dx, dy in ((1, 1), (1, -1), (-1, 1), (-1, -1), (0, 1.4), (0, -1.4), (1.4, 0), (-1.4, 0))
]


def plot_screen(ds: xr.Dataset, *, title: str = "") -> Figure:
    """Every item at (A_gx of 50 % overturning probability, required S_v of Eq. 11).

    One colour per location. The dashed vertical line is the design A_gx: items to its left
    overturn with more than 50 % probability in the Monte Carlo runs. Each location's available
    S_v (the largest PSV in the band) is a dotted horizontal line of its colour: items below
    their line fail Housner's check. Items whose A_gx50 lies beyond the search range are drawn
    at its end with a ▸ marker. Items whose most frequent response at the design level is to
    slide (□ about the point) or slide-rock (◇) are ringed: with friction, a body may stay
    standing yet move.

    Each point is labelled with its item's number, its row in ``ds`` counted from 1 (the key is
    the report's table); items at one point share a label ("2, 5"). Labels are placed where
    they overlap no other label, point or axis edge (the first free place of a few around the
    point); the legend sits outside the axes.

    Parameters
    ----------
    ds : xarray.Dataset
        Result of :func:`rocking.assessment.screen.screen` (``agx50`` [g], ``sv_required`` and
        ``sv_available`` [m/s], ``location``, ``at_risk``, ``mode`` if given; attributes
        ``design_agx`` and ``agx_max`` [g]).
    title : str
        Figure title.
    """
    agx50 = ds["agx50"].values
    sv = 100.0 * ds["sv_required"].values
    at_risk = ds["at_risk"].values
    design = float(ds.attrs["design_agx"])
    beyond = ~np.isfinite(agx50)
    x_end = float(ds.attrs.get("agx_max", np.nanmax(agx50, initial=design)))
    x = np.where(beyond, x_end, agx50)
    fig = new_figure(figsize=(9.0, 5.2), layout="constrained")
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
    # items that slide or slide-rock at the design level (their most frequent response, with
    # friction): ringed, so the figure shows what the overturning axes alone would hide
    modes = ds["mode"].values.astype(str) if "mode" in ds else np.full(len(x), "")
    ringed = np.isin(modes, list(_RINGS))
    for mode, marker in _RINGS.items():
        sel = modes == mode
        if sel.any():
            ax.plot(x[sel], sv[sel], marker, mfc="none", mec="k", mew=0.9, ms=2 * RING,
                    label=f"{mode}s at design A_gx (most motions)")  # fmt: skip
    ax.axvline(design, color="k", ls="--", lw=1.0, label=f"design A_gx = {design:.3g} g")
    ax.set_xlim(left=0.0, right=float(np.max(x, initial=design)) * 1.08)
    ax.set_ylim(bottom=0.0, top=float(np.max(sv, initial=1.0)) * 1.12)
    ground = ds.attrs.get("floor_motions", "building") == "building"
    ax.set_xlabel(("ground " if ground else "") + "A_gx at 50 % overturning probability [g]")
    ax.set_ylabel("required S_v, Eq. (11) [cm/s]")
    ax.grid(True, lw=0.4, alpha=0.5)
    legend_beside(ax, "dotted: available S_v at the location\nnumbers: rows of the table")
    ax.set_title(title or f"Screening: {ds.attrs.get('spectrum', '')}", fontsize="medium")
    named = np.ones(len(x), bool) if len(x) <= MAX_NAMED else at_risk.astype(bool)
    _label_points(fig, ax, x, sv, named, np.where(ringed, RING, POINT))
    return fig


def _label_points(
    fig: Figure, ax: Axes, x: np.ndarray, y: np.ndarray, named: np.ndarray, half: np.ndarray
) -> None:
    """Number the points (x, y) of ``ax`` that are ``named`` (1 + their index), one label per
    group of points closer than :data:`SAME_POINT`, each at the first offset of
    :data:`_OFFSETS` (from the edge of a ring about the point) where it overlaps no other label
    or point (a square of half-side ``half`` [points] about each) and stays inside the axes
    (the first offset if there is none). The figure's layout is solved first and then fixed,
    so the labels stay where they were placed."""
    from matplotlib.backends.backend_agg import FigureCanvasAgg

    if not named.any():
        return
    canvas = FigureCanvasAgg(fig)
    fig.draw_without_rendering()
    fig.set_layout_engine("none")  # keep the solved layout: the labels are placed in it
    renderer = canvas.get_renderer()
    to_points = 72.0 / fig.dpi
    xy = ax.transData.transform(np.column_stack([x, y])) * to_points  # [points]
    groups: list[list[int]] = []
    for i in np.flatnonzero(named):
        for group in groups:
            if np.hypot(*(xy[group[0]] - xy[i])) < SAME_POINT:
                group.append(int(i))
                break
        else:
            groups.append([int(i)])
    points = [_box(p, h, to_points) for p, h in zip(xy, half)]  # every point, named or not
    labels: list[Bbox] = []
    frame = ax.get_window_extent(renderer)
    for group in groups:
        text = ", ".join(str(i + 1) for i in group)
        others = [b for i, b in enumerate(points) if i not in group] + labels
        # the offsets from a ring's edge as from a point's
        out = float(max(half[i] for i in group)) - POINT
        offsets = [(dx + np.sign(dx) * out, dy + np.sign(dy) * out) for dx, dy in _OFFSETS]
        for dx, dy in offsets:
            label = _annotate(ax, text, (x[group[0]], y[group[0]]), dx, dy)
            box = label.get_window_extent(renderer).expanded(1.0, 1.0).padded(GAP / to_points)
            inside = frame.contains(box.x0, box.y0) and frame.contains(box.x1, box.y1)
            if inside and not any(box.overlaps(other) for other in others):
                break
            label.remove()
        else:  # nowhere free: the first place
            label = _annotate(ax, text, (x[group[0]], y[group[0]]), *offsets[0])
        labels.append(label.get_window_extent(renderer))


def _annotate(ax: Axes, text: str, xy: tuple[float, float], dx: float, dy: float):
    """A label ``text`` at ``(dx, dy)`` points from the data point ``xy``, by its corner (or
    the middle of its side) nearest to the point."""
    return ax.annotate(
        text,
        xy,
        xytext=(dx, dy),
        textcoords="offset points",
        ha="left" if dx > 0 else "right" if dx < 0 else "center",
        va="bottom" if dy > 0 else "top" if dy < 0 else "center",
        fontsize=7,
    )


def _box(center_points: np.ndarray, half: float, to_points: float) -> Bbox:
    """A square of half-side ``half`` [points] about ``center_points`` [points], in pixels."""
    from matplotlib.transforms import Bbox

    (cx, cy), s = center_points / to_points, half / to_points
    return Bbox([[cx - s, cy - s], [cx + s, cy + s]])
