"""Beyond the paper: what its assumption of sufficient friction hides (issue 45).

The paper models rocking alone, assuming "sufficient friction so that no slippage occurs".
This study repeats Section 8's A_gx50 search and Table 3 (S_v1/S_v) with Coulomb friction of
μ = 0.3 … 0.8 (kinetic equal to static by default, or a given fraction of it) and with
infinite friction (the paper's model), for the
same kind of bodies on the ground under ``n`` compound motions, and counts at each body's A_gx50
how the motions moved it: the share of the motions in which it slides (slip > 0, never rocking),
slide-rocks (slip > 0 and rocking) or rocks without slip.  The same shares at the paper's
A_gx50 (infinite friction) give the overturning probability there with friction: what the
paper's A_gx50 means for a body that may slide.

S_v1 scales with the motions (:func:`rocking.assessment.energy.energy_balance`), so the ratio of
Table 3 at μ is the paper's ratio times A_gx50(μ)/A_gx50(∞): friction changes Table 3 exactly as
it changes A_gx50.
"""

from __future__ import annotations

import dataclasses
import math
import os
from collections.abc import Sequence
from dataclasses import dataclass

import numpy as np
import pandas as pd
import xarray as xr
from numpy.typing import ArrayLike

from ..assessment.energy import energy_balance
from ..assessment.screen import RESPONSES, response_shares, standing_slip
from ..core.checks import in_range
from ..defaults import BAND_HZ
from ..dynamics.batch import block_list
from ..dynamics.body import Block
from ..dynamics.physics import Physics
from ..errors import InputError
from ..montecarlo.backends import Compute
from ..montecarlo.probability import agx_50, member_outcomes
from ..montecarlo.search import Agx50Search
from ..motions.ensemble import Ensemble
from ..plots.studies import plot_friction
from ..report import Report
from .config import RunContext, friction_coefficients, resolve_bodies

#: The heading of the report; ``{mus}``: the run's friction coefficients (:func:`_mu_range`).
TITLE = "Beyond the paper: friction (A_gx50 and Table 3 for μ = {mus}, issue 45)"
#: Where the shares are counted: at the body's A_gx50 with the friction of the row, and at its
#: A_gx50 with infinite friction (the paper's).
LEVELS = ("A_gx50(μ)", "A_gx50(∞)")


@dataclass(frozen=True)
class FrictionResult:
    """``data``: :func:`friction_study`'s dataset; ``label``: the fidelity note."""

    data: xr.Dataset
    label: str


def mode_shares(
    blocks: Block | Sequence[Block],
    ensemble: Ensemble,
    agx: ArrayLike,
    *,
    physics: Physics | None = None,
    compute: Compute | None = None,
) -> xr.Dataset:
    """How every motion of ``ensemble`` scaled to each body's ``agx`` moves the body.

    Parameters
    ----------
    blocks : Block or sequence of Block
        The bodies.
    ensemble : Ensemble
        The motions [m/s²].
    agx : array_like, shape (n_bodies,) or (n_bodies, n_levels)
        One intensity A_gx [g] per body, or a row of them (NaN: not simulated, the shares
        NaN).  The levels of all the bodies are simulated (or loaded from ``compute.out``) in
        one run.
    physics, compute :
        As for :func:`rocking.overturning_probability` (friction in ``physics.mu``).

    Returns
    -------
    xarray.Dataset
        Dimensions (body[, level], mode) (``level`` with a row of intensities per body) with
        ``share`` [-], the fraction of the motions whose whole
        response was each of :data:`~rocking.assessment.screen.RESPONSES`
        (:func:`~rocking.assessment.screen.responses`: "overturn"; of the others, "slide":
        slip > 0 without uplift, "slide-rock": slip > 0 with uplift, "rock": uplift without
        slip, "rest": neither).  An overturning body is counted apart: as it falls, the normal
        force at its corner vanishes and any friction coefficient is exceeded, so it slips
        (even with μ = 1000), whatever it did before.  Per body ``max_slip`` [m], the largest
        peak slip of a motion that did not overturn the body (NaN if every motion did).
    """
    blocks = block_list(blocks)
    values = np.asarray(agx, dtype=float)
    if values.ndim not in (1, 2) or values.shape[0] != len(blocks):
        raise InputError(
            f"agx must hold one intensity or one row of intensities per body ({len(blocks)} "
            f"bodies), got shape {values.shape}"
        )
    rows = values if values.ndim == 2 else values[:, None]
    share = np.full((*rows.shape, len(RESPONSES)), np.nan)
    max_slip = np.full(rows.shape, np.nan)
    known = np.isfinite(rows)
    found = np.flatnonzero(known.any(axis=1))
    if found.size:
        # a body's NaN levels are run at one of its known levels (a level asked twice is
        # simulated once), their shares left NaN
        first = rows[found, np.argmax(known[found], axis=1)]
        at = np.where(known[found], rows[found], first[:, None])
        out = member_outcomes(
            blocks, ensemble, at, physics=physics, compute=compute, bodies=found.tolist()
        )
        ov, slip = out["overturned"].values, out["peak_slip"].values  # (body, level, member)
        keep = known[found]
        share[found] = np.where(
            keep[..., None], response_shares(ov, out["uplift"].values, slip), np.nan
        )
        max_slip[found] = np.where(keep, standing_slip(ov, slip), np.nan)
    dims = ("body", "level") if values.ndim == 2 else ("body",)
    return xr.Dataset(
        {
            "share": ((*dims, "mode"), share.reshape(*values.shape, -1), {"units": "1"}),
            "max_slip": (dims, max_slip.reshape(values.shape), {"units": "m"}),
        },
        coords={"body": [b.label for b in blocks], "mode": list(RESPONSES)},
    )


def friction_study(
    blocks: Block | Sequence[Block],
    ensemble: Ensemble,
    mus: Sequence[float],
    *,
    search: Agx50Search | None = None,
    physics: Physics | None = None,
    compute: Compute | None = None,
    band_hz: Sequence[float] = BAND_HZ,
    stores: Sequence[str | os.PathLike[str] | None] | None = None,
    kinetic_ratio: float = 1.0,
) -> xr.Dataset:
    """A_gx50, Table 3 and the modes of the motions for each friction coefficient.

    Parameters
    ----------
    blocks, ensemble :
        The bodies and the ground motions [m/s²], as for :func:`mode_shares`.
    mus : sequence of float
        Static friction coefficients μ [-]; infinite friction (``physics.mu`` None, the
        paper's) is added as μ = inf.
    search : Agx50Search, optional
        The A_gx50 search (:func:`rocking.agx_50`).
    physics : Physics, optional
        The physics without friction (its ``mu`` and ``mu_k`` are replaced per row).
    compute : Compute, optional
        How to compute (:class:`~rocking.montecarlo.backends.Compute`).
    band_hz : (float, float), optional
        Band of S_v1 [Hz].
    stores : sequence of str, Path or None, optional
        One chunk folder per friction coefficient, infinite friction last (replacing
        ``compute.out``: each row's simulations differ, and a folder holds one run's).
    kinetic_ratio : float, optional
        μ_k/μ [-], in (0, 1]: the kinetic coefficient of every row is this fraction of its μ
        (default 1: kinetic equal to static).

    Returns
    -------
    xarray.Dataset
        Dimensions (mu, body[, level, mode]): ``agx50`` [g] (NaN: 50 % not reached by
        ``agx_max``), ``change`` = A_gx50(μ)/A_gx50(∞) − 1 [-], ``ratio`` = S_v1/S_v [-]
        (Table 3), and at each of :data:`LEVELS` the ``share`` of each mode and ``max_slip`` [m]
        of :func:`mode_shares`.  Coordinate ``mu`` [-] (inf last), body
        coordinates ``R`` [m], ``gamma`` [-], ``b_over_h`` (B/H = tan α [-]).  Attribute
        ``kinetic_ratio`` [-].
    """
    blocks = block_list(blocks)
    ratio_k = in_range("kinetic_ratio", kinetic_ratio, 0.0, 1.0, lo_open=True, unit="-")
    base = physics or Physics()
    compute = compute or Compute()
    rows = [*friction_coefficients(mus, "mus"), math.inf]
    where = list(stores) if stores is not None else [compute.out] * len(rows)
    if len(where) != len(rows):
        raise InputError(
            f"stores must hold {len(rows)} folders (one per friction coefficient of mus, then "
            f"one for infinite friction), got {len(where)}"
        )
    physics_of = [
        dataclasses.replace(
            base,
            mu=None if math.isinf(m) else m,
            # ratio 1: mu_k None (= mu), the physics (and chunk folders) of μ_k = μ_s runs
            mu_k=None if math.isinf(m) or ratio_k == 1.0 else ratio_k * m,
        )
        for m in rows
    ]
    computes = [dataclasses.replace(compute, out=out) for out in where]
    a50 = [
        agx_50(blocks, ensemble, search=search, physics=ph, compute=c)["agx50"].values
        for ph, c in zip(physics_of, computes)
    ]
    paper = a50[-1]
    # S_v1 = sv1_per_g · A_gx50: the spectrum (the same for every row) computed once
    table3 = energy_balance(blocks, ensemble, paper, band_hz=band_hz)
    at_levels = [
        mode_shares(blocks, ensemble, np.column_stack([a, paper]), physics=ph, compute=c)
        for a, ph, c in zip(a50, physics_of, computes)
    ]
    shares = xr.concat(at_levels, pd.Index(rows, name="mu")).assign_coords(level=list(LEVELS))
    a50_arr = np.array(a50)
    ds = shares.assign(
        agx50=(("mu", "body"), a50_arr, {"units": "g"}),
        change=(("mu", "body"), a50_arr / paper - 1.0, {"units": "1"}),
        ratio=(
            ("mu", "body"),
            table3.attrs["sv1_per_g"] * a50_arr / table3["sv_required"].values,
            {"units": "1"},
        ),
    )
    ds.attrs["kinetic_ratio"] = ratio_k
    return ds.assign_coords(
        R=("body", [b.R for b in blocks]),
        gamma=("body", [b.gamma for b in blocks]),
        # to 12 digits: μ = B/H compares equal where it should (0.4 = 1/2.5)
        b_over_h=("body", [round(b.b / b.h_cg, 12) for b in blocks]),
    )


def run(ctx: RunContext) -> FrictionResult:
    """The study with the ``[friction]`` parameters of the run."""
    p = ctx.cfg["friction"]
    blocks = resolve_bodies(p["bodies"], "friction.bodies")
    ground = ctx.motions("friction", p["n"])
    mus = [float(m) for m in p["mu"]]
    names = [f"mu{m:g}" for m in mus] + ["mu-inf"]
    data = friction_study(
        blocks,
        ground,
        mus,
        search=Agx50Search(resolution=p["resolution"], agx_max=p["agx_max"]),
        physics=ctx.physics,
        compute=Compute(backend=ctx.backend, progress=ctx.progress),
        band_hz=p["band_hz"],
        stores=[ctx.store("friction", f"agx50-{name}") for name in names],
        kinetic_ratio=p["kinetic_ratio"],
    )
    data.attrs.update(agx_max=p["agx_max"], resolution=p["resolution"], n=ground.n)
    return FrictionResult(data, ctx.label(n=ground.n, bodies=len(blocks)))


def report(result: FrictionResult, rep: Report, ctx: RunContext) -> None:
    """The summary in words, the figure and the tables."""
    ds, lab = result.data, result.label
    rep.heading(TITLE.format(mus=_mu_range(ds)))
    rep.text(summary(ds))
    rep.text(
        "The paper's bodies and motions (Section 8 on the ground), with Coulomb friction of "
        f"coefficient μ ({_kinetic(ds)}) between body and ground. A motion *slides* a body "
        "when it slips (slip > 0) without rocking, *slide-rocks* it when it slips and rocks, "
        "*rocks* it when it rocks without slipping. Overturned motions are counted apart: as a "
        "body falls, the normal force at its corner vanishes and it slips at any μ."
    )
    rep.plot(
        plot_friction,
        ds,
        name="friction",
        caption="A_gx50 against the friction coefficient μ (∞: the paper's sufficient "
        "friction), and the share of the motions in which each body slides or slide-rocks "
        "without overturning, at its A_gx50 with friction μ and at the paper's A_gx50 (infinite "
        f"friction; bars: the mean over the bodies of a γ) [{lab}]",
    )
    by_body = _table(ds, LEVELS[0])
    rep.table(
        _by_slenderness(by_body),
        "By slenderness, over the bodies of each γ: the bodies whose A_gx50 is found, the mean, "
        "smallest and largest change of A_gx50 (and of Table 3's ratio) against infinite "
        "friction, the mean shares of the motions that slide or slide-rock a body at its "
        f"A_gx50, the largest slip of a body left standing [{lab}]",
        name="friction-by-gamma",
        floatfmt=".3f",
    )
    rep.table(
        by_body,
        "Per body: A_gx50, its change against infinite friction, Table 3's ratio S_v1/S_v and "
        "how the motions moved the body at its A_gx50 with friction μ (μ = inf: the paper's "
        f"model; A_gx50 NaN: 50 % not reached by {ds.attrs['agx_max']:g} g) [{lab}]",
        name="friction-agx50",
        floatfmt=".3f",
        collapsed=True,
    )
    rep.table(
        _table(ds, LEVELS[1]).drop(columns=["A_gx50 [g]", "change [-]", "S_v1/S_v [-]"]),
        "Per body, the same motions at the paper's A_gx50 (infinite friction) with friction μ: "
        f"the overturning probability there and how the motions moved the body [{lab}]",
        name="friction-at-paper-agx50",
        floatfmt=".3f",
        collapsed=True,
    )


def _mu_range(ds: xr.Dataset) -> str:
    """The finite friction coefficients of ``ds`` in words: "0.3–0.8", or "0.6" for one."""
    mus = ds["mu"].values[np.isfinite(ds["mu"].values)]
    lo, hi = f"{mus.min():g}", f"{mus.max():g}"
    return lo if lo == hi else f"{lo}–{hi}"


def _kinetic(ds: xr.Dataset) -> str:
    """The kinetic coefficient of ``ds`` in words: "static = kinetic" or "kinetic 0.8 μ"."""
    ratio = float(ds.attrs.get("kinetic_ratio", 1.0))
    return "static = kinetic" if ratio == 1.0 else f"static μ, kinetic {ratio:g} μ"


def _by_slenderness(by_body: pd.DataFrame) -> pd.DataFrame:
    """The per-body table of :func:`_table` summarised per (μ, γ)."""
    groups = by_body.groupby(["μ [-]", "γ [-]"])
    table = groups.agg(
        **{
            "B/H [-]": ("B/H [-]", "mean"),
            "bodies [-]": ("body", "size"),
            "A_gx50 found [-]": ("A_gx50 [g]", "count"),
            "mean change [-]": ("change [-]", "mean"),
            "min change [-]": ("change [-]", "min"),
            "max change [-]": ("change [-]", "max"),
            "share slide [-]": ("share slide [-]", "mean"),
            "share slide-rock [-]": ("share slide-rock [-]", "mean"),
            "max slip, not overturned [m]": ("max slip, not overturned [m]", "max"),
        }
    )
    return table.reset_index()


def _table(ds: xr.Dataset, level: str) -> pd.DataFrame:
    """One row per (μ, body): A_gx50, change, ratio, and the shares at ``level``."""
    at = ds.sel(level=level)
    rows = []
    for mu in ds["mu"].values:
        for b, body in enumerate(ds["body"].values):
            one = at.sel(mu=mu).isel(body=b)
            rows.append(
                {
                    "μ [-]": float(mu),
                    "body": str(body),
                    "γ [-]": float(ds["gamma"][b]),
                    "B/H [-]": float(ds["b_over_h"][b]),
                    "A_gx50 [g]": float(one["agx50"]),
                    "change [-]": float(one["change"]),
                    "S_v1/S_v [-]": float(one["ratio"]),
                    "P(overturn) [-]": float(one["share"].sel(mode="overturn")),
                    **{
                        f"share {mode} [-]": float(one["share"].sel(mode=mode))
                        for mode in RESPONSES[1:4]
                    },
                    "max slip, not overturned [m]": float(one["max_slip"]),
                }
            )
    return pd.DataFrame(rows)


def summary(ds: xr.Dataset) -> str:
    """What the assumption of sufficient friction hides, in numbers of ``ds``
    (:func:`friction_study`)."""
    mus = ds["mu"].values[np.isfinite(ds["mu"].values)]
    finite = ds.sel(mu=mus)
    n_pairs = finite["agx50"].size
    change = finite["change"].values
    both = np.isfinite(change)
    lost = finite["agx50"].isnull() & ds["agx50"].sel(mu=math.inf).notnull()
    own = finite.sel(level=LEVELS[0])
    moved = own["share"].sel(mode=["slide", "slide-rock"]).sum("mode")
    parts = [
        f"**What the paper's assumption of sufficient friction hides.** Over {len(mus)} "
        f"friction coefficients μ = {_mu_range(ds)} and "
        f"{ds['body'].size} bodies ({n_pairs} pairs):"
    ]
    if both.any():
        c = change[both]
        up, down = int((c > 0).sum()), int((c < 0).sum())
        parts.append(
            f"A_gx50 changes against infinite friction by {100 * c.min():+.1f} % to "
            f"{100 * c.max():+.1f} % (lower in {down}, higher in {up}, unchanged in "
            f"{c.size - up - down} of the {c.size} pairs where both are found); Table 3's "
            "ratio S_v1/S_v changes by the same factors."
        )
        if up:
            best = np.unravel_index(np.nanargmax(np.where(both, change, -np.inf)), change.shape)
            bh_best = float(ds["b_over_h"][best[1]])
            why = (
                "at μ = B/H, the boundary between slipping first (μ < B/H: no overturning) and "
                "tipping first"
                if math.isclose(mus[best[0]], bh_best, rel_tol=1e-9)
                else "presumably because slipping limits the force the ground passes to the "
                "body (it isolates it)"
            )
            parts.append(
                f"Friction raises A_gx50 most for {ds['body'].values[best[1]]} (B/H = "
                f"{bh_best:.3g}) at μ = {mus[best[0]]:g} ({100 * change[best]:+.1f} %), {why}."
            )
    bh = ds["b_over_h"].values[None, :]
    below = mus[:, None] < bh
    far = mus[:, None] >= 2.0 * bh
    if (far & both).any():
        most = np.abs(change[far & both]).max()
        parts.append(
            f"Where μ ≥ 2·B/H ({int(far.sum())} pairs), A_gx50 "
            + (f"changes by at most {100 * most:.1f} %." if most else "is the paper's exactly.")
        )
    paper_level = finite.sel(level=LEVELS[1])
    if int(lost.sum()):
        i, j = (int(k[0]) for k in np.nonzero(lost.values))
        there = paper_level.isel(mu=i, body=j)
        slid = float(there["share"].sel(mode=["slide", "slide-rock"]).sum())
        fell = float(there["share"].sel(mode="overturn"))
        n_lost, lost_below = int(lost.sum()), int((lost.values & below).sum())
        parts.append(
            f"In {n_lost} pair{'s' if n_lost > 1 else ''} the body no longer overturns with 50 % "
            f"probability up to {ds.attrs.get('agx_max', math.nan):g} g: {lost_below} of the "
            f"{int(below.sum())} pairs with μ < B/H (where a body at rest slips before it can "
            f"tip, Shenton 1996) and {n_lost - lost_below} others. E.g. "
            f"{ds['body'].values[j]} (B/H = {float(ds['b_over_h'][j]):.3g}) at μ = {mus[i]:g}: "
            f"at the paper's A_gx50 it overturns in {100 * fell:.0f} % of the motions, and "
            f"{100 * slid:.0f} % slide it, by up to "
            f"{float(there['max_slip']):.3g} m."
        )
    if np.isfinite(moved.values).any():
        most = np.unravel_index(np.nanargmax(moved.values), moved.shape)
        parts.append(
            f"At A_gx50 with friction, up to {100 * float(moved.values[most]):.0f} % of the "
            "motions make a body slide or slide-rock without overturning it "
            f"({ds['body'].values[most[1]]} at μ = {mus[most[0]]:g}), with slips up to "
            f"{float(own['max_slip'].max()):.3g} m, a displacement the paper's model cannot show."
        )
    at_paper = paper_level["share"].sel(mode="overturn").values
    if np.isfinite(at_paper).any():
        parts.append(
            "At the paper's A_gx50 (where P = 50 % with infinite friction) the overturning "
            f"probability with friction is {np.nanmin(at_paper):.2f}–{np.nanmax(at_paper):.2f}."
        )
    return " ".join(parts)
