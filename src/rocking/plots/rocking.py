"""Figures of one block's rocking response: θ/α (with friction also the slip and the response
modes) and the ground acceleration against time."""

from __future__ import annotations

import math
from typing import TYPE_CHECKING

import numpy as np
from numpy.typing import ArrayLike

from ..defaults import MODES
from ..errors import InputError
from . import new_figure

if TYPE_CHECKING:
    from matplotlib.figure import Figure

    from ..dynamics.simulate import RockingResponse


def plot_response(
    response: RockingResponse, ag_g: ArrayLike, *, title: str | None = None
) -> Figure:
    """Rotation θ/α (top) and ground acceleration (bottom) against time, sharing the time axis;
    with friction (``response.mu`` given, issue 45) the slip [mm] between them.

    The top panel marks θ = ±α (the static stability limit) and, if the block overturned, the
    instant and angle of overturning; the bottom panel marks the uplift threshold ±g·tan α.
    With friction, the top and middle panels shade the times the block slides, slide-rocks or
    flies (:data:`rocking.MODES`), and the bottom panel marks the sliding threshold ±μ_s·g.

    Parameters
    ----------
    response : rocking.RockingResponse
        Result of :func:`rocking.simulate` (times ``t`` [s], ``theta`` [rad], its ``block``).
    ag_g : array_like, shape (n_t,)
        The ground acceleration [g] at ``response.t``.
    title : str, optional
        Figure title (default: R, γ and the restitution e).
    """
    t = response.t
    ag_g = np.asarray(ag_g, dtype=float)
    if ag_g.shape != t.shape:
        raise InputError(f"ag_g has shape {ag_g.shape}, the response's times {t.shape}")
    block = response.block
    friction = response.mu is not None
    fig = new_figure(figsize=(7.5, 7.5 if friction else 5.5), layout="constrained")
    if friction:
        ax_th, ax_slip, ax_ag = fig.subplots(3, 1, sharex=True, height_ratios=(3, 2, 2))
    else:
        ax_th, ax_ag = fig.subplots(2, 1, sharex=True, height_ratios=(3, 2))

    ax_th.plot(t, response.theta_over_alpha, color="C0", lw=0.9, label="θ/α")
    for sign in (1.0, -1.0):
        ax_th.axhline(
            sign,
            color="0.5",
            ls="--",
            lw=0.8,
            label="θ = ±α (static stability limit)" if sign > 0 else None,
        )
    if response.overturned:
        last = response.theta[np.isfinite(response.theta)][-1]
        y_ov = math.copysign(response.overturn_angle, last) / block.alpha
        ax_th.axvline(response.t_overturn, color="C3", lw=1.0)
        ax_th.plot(
            [response.t_overturn],
            [y_ov],
            "x",
            color="C3",
            ms=9,
            mew=2,
            label=f"overturned at t = {response.t_overturn:.3f} s",
        )
    ax_th.set_ylabel("rotation θ/α [-]")
    ax_th.grid(True, lw=0.4, alpha=0.5)
    if friction:
        _shade_modes(ax_th, response, labels=True)
        ax_slip.plot(t, 1e3 * response.slip, color="C2", lw=0.9, label="slip")
        _shade_modes(ax_slip, response, labels=False)
        ax_slip.set_ylabel("slip [mm]")
        ax_slip.grid(True, lw=0.4, alpha=0.5)
        ax_slip.legend(fontsize="small", loc="best")
    ax_th.legend(fontsize="small", loc="best")

    tan_a = math.tan(block.alpha)
    ax_ag.plot(t, ag_g, color="C1", lw=0.6, label="ground acceleration")
    for sign in (1.0, -1.0):
        ax_ag.axhline(
            sign * tan_a,
            color="0.5",
            ls="--",
            lw=0.8,
            label=f"uplift threshold ±g·tan α = ±{tan_a:.3g} g" if sign > 0 else None,
        )
    if response.mu is not None:
        for sign in (1.0, -1.0):
            ax_ag.axhline(
                sign * response.mu,
                color="C2",
                ls=":",
                lw=0.9,
                label=f"sliding threshold ±μ_s·g = ±{response.mu:.3g} g" if sign > 0 else None,
            )
    ax_ag.set_ylabel("ground acceleration [g]")
    ax_ag.set_xlabel("time t [s]")
    ax_ag.grid(True, lw=0.4, alpha=0.5)
    ax_ag.legend(fontsize="small", loc="best")

    if title is None:
        title = f"R = {block.R:.4g} m, γ = {block.gamma:.4g}, e = {response.e:.4g}"
        if friction:
            title += f", μ_s = {response.mu:.3g}, μ_k = {response.mu_k:.3g}"
    fig.suptitle(title)
    return fig


#: The response modes shaded in a figure with friction, and their colours.
_SHADED = {"slide": "C2", "slide-rock": "C3", "flight": "C4"}


def _shade_modes(ax, response: RockingResponse, *, labels: bool) -> None:
    """Shade on ``ax`` the times at which the block slides, slide-rocks or flies (each sample's
    mode held for half a step either side), with legend labels if ``labels``."""
    mode = np.asarray(response.mode)
    for name, colour in _SHADED.items():
        where = mode == MODES.index(name)
        if where.any():
            ax.fill_between(
                response.t,
                0.0,
                1.0,
                where=where,
                step="mid",
                color=colour,
                alpha=0.18,
                lw=0,
                transform=ax.get_xaxis_transform(),
                label=name if labels else None,
            )
