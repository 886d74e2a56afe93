"""Section 6: effect of the duration and of the intensity function on overturning probability.

For each intensity function (boxcar, trapezoidal, compound) and duration (10–30 s), ``n``
motions (500 in the paper) are simulated and the overturning probability of each body is
estimated over a grid of A_gx (each ensemble scaled to its mean PGA). Every case uses the same
seed, so the motions of different cases share their phase angles: the comparisons between
durations and shapes are paired, which removes much of the sampling noise from the differences.
The envelope shapes follow the duration rule of :mod:`rocking.motions.envelopes`.

Fig. 9: boxcar, all durations, (a) R = 1.22 m, γ = 4 and (b) R = 3.66 m, γ = 4.
Fig. 10: R = 1.22 m, γ = 4, the three shapes, for durations 15–30 s.
"""

from __future__ import annotations

from dataclasses import dataclass

import pandas as pd
import xarray as xr

from ..montecarlo.probability import overturning_probability
from ..plots.fragility import plot_fragility
from ..report import Report
from .config import RunContext, resolve_bodies

TITLE = "Section 6: duration and intensity function (Figs. 9-10)"


@dataclass(frozen=True)
class Sec6Result:
    """``probability``: Dataset of :func:`rocking.montecarlo.probability.overturning_probability`
    with extra
    leading dimensions ``envelope`` and ``duration`` [s]."""

    probability: xr.Dataset
    label: str


def run(ctx: RunContext) -> Sec6Result:
    """Overturning probabilities for every intensity function and duration."""
    p, physics = ctx.cfg["sec6"], ctx.physics
    blocks = resolve_bodies(p["bodies"], "sec6.bodies")
    by_env = []
    for env in p["envelopes"]:
        by_dur = []
        for dur in p["durations"]:
            ens = ctx.motions("sec6", p["n"], envelope=env, duration=dur, envelope_params=None)
            by_dur.append(
                overturning_probability(
                    blocks,
                    ens,
                    p["agx"],
                    physics=physics,
                    backend=ctx.backend,
                    progress=ctx.progress,
                    out=ctx.store("sec6", f"{env}-T{dur:g}"),
                )
            )
        by_env.append(xr.concat(by_dur, pd.Index(p["durations"], name="duration")))
    prob = xr.concat(by_env, pd.Index(p["envelopes"], name="envelope"))
    return Sec6Result(prob, ctx.label(n=p["n"]))


def _cases(ds: xr.Dataset, dim: str, fmt: str) -> xr.Dataset:
    """``ds`` with dimension ``dim`` renamed to ``case`` labelled by ``fmt.format(value)``."""
    labels = [fmt.format(v) for v in ds[dim].values]
    return ds.rename({dim: "case"}).assign_coords(case=labels)


def report(result: Sec6Result, rep: Report, ctx: RunContext) -> None:
    """Figures 9–10 and a table of the mean probability by duration and shape."""
    ds = result.probability
    rep.heading(TITLE)
    rep.text(
        "Paper: the probability grows with the duration, but little from 25 to 30 s "
        "(Fig. 9); the shape of the intensity function matters little (Fig. 10). "
        f"Shaded bands: 95 % Wilson intervals of the sampling error of {int(ds['n'].max())} "
        "motions."
    )
    env9 = "boxcar" if "boxcar" in ds["envelope"].values else str(ds["envelope"].values[0])
    for i, body in enumerate(ds["body"].values):
        panel = chr(ord("a") + i) if i < 26 else f"-{i + 1}"
        sel = _cases(ds.sel(envelope=env9, body=[body]), "duration", "T = {:g} s")
        rep.plot(
            plot_fragility,
            sel,
            name=f"fig9{panel}",
            caption=f"Fig. 9{panel}: {body}, {env9} [{result.label}]",
        )
    body10 = ds["body"].values[0]
    fig10 = [d for d in ctx.cfg["sec6"]["fig10_durations"] if d in ds["duration"].values]
    for d in fig10:
        sel = _cases(ds.sel(duration=d, body=[body10]), "envelope", "{}")
        rep.plot(
            plot_fragility,
            sel,
            name=f"fig10-T{d:g}",
            caption=f"Fig. 10 (T = {d:g} s): {body10}, three intensity functions [{result.label}]",
        )
    mean = ds["probability"].mean("agx").to_dataframe().reset_index()
    table = mean.pivot_table(index=["body", "envelope"], columns="duration", values="probability")
    table.columns = [f"T = {d:g} s" for d in table.columns]
    rep.table(
        table,
        "Section 6: overturning probability averaged over the A_gx grid "
        f"({', '.join(f'{a:g}' for a in ds['agx'].values)} g) by body, intensity "
        f"function and duration [{result.label}]",
        name="sec6-mean-probability",
        floatfmt=".3f",
    )
