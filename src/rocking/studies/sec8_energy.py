"""Section 8: Housner's energy balance (Eq. 11) against simulation (Figs. 13–16, Tables 1–3).

``n`` ground motions (compound, 20 s; 200 in the paper) and the absolute accelerations of one
floor of a frame (floor 1 of the T1 = 2.0 s frame) scaled to the same A_gx. For every body the
A_gx of 50 % overturning probability (A_gx50) is searched on both; S_v1 is the largest value of
the ensemble-mean 5 %-damped PSV in 0.04–0.6 Hz with the ensemble scaled to A_gx50
(:func:`rocking.assessment.energy.energy_balance`), to be compared with Eq. (11) (Table 1). Also:
the
probability curve of R = 1.22 m, γ = 2 (Fig. 13) and its spectrum at A_gx50 (Fig. 14), and the
two worked examples (bodies on floor 1 at A_gx = 0.6 g) both by Eq. (11) and by simulation.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
import pandas as pd
import xarray as xr

from ..assessment.energy import assess, energy_balance, grid_table
from ..assessment.screen import eq11_vs_monte_carlo, eq11_vs_monte_carlo_note
from ..core import portable
from ..dynamics.body import housner_sv
from ..montecarlo.probability import agx_50, overturning_probability
from ..motions.response import response_spectrum
from ..plots.fragility import plot_fragility, plot_sv1_spectrum, plot_sv_agx
from ..report import Report, slug
from .conclusions import ratio_stats
from .config import RunContext, resolve_bodies, resolve_frame
from .paper import paper_table, paper_values

TITLE = "Section 8: Housner's energy balance equation (Figs. 13-16, Tables 1-3)"
#: Band [Hz] and number of the log-spaced frequencies of the Fig. 14 spectrum.
FIG14_BAND_HZ = (0.04, 30.0)
FIG14_N_FREQS = 120


@dataclass(frozen=True)
class Sec8Result:
    """``balance``: :func:`rocking.assessment.energy.energy_balance` datasets stacked on
    ``location``
    ("ground", "floor k"); ``fig13``: probability curve of the first example body on the
    ground; ``fig14``: (freqs [Hz], mean PSV [m/s]) at its A_gx50; ``examples``: per example
    body ``sv_required``, ``sv_available`` [m/s], ``verdict`` (Eq. 11) and ``probability``,
    ``ci_low``, ``ci_high`` of overturning on the floor at ``example_agx``."""

    balance: xr.Dataset
    fig13: xr.Dataset
    fig14: tuple
    examples: xr.Dataset
    label: str


def run(ctx: RunContext) -> Sec8Result:
    """A_gx50 of every body on the ground and the floor, S_v1, and the worked examples."""
    p, physics = ctx.cfg["sec8"], ctx.physics
    blocks = resolve_bodies(p["bodies"], "sec8.bodies")
    examples = resolve_bodies(p["examples"], "sec8.examples")
    ground = ctx.motions("sec8", p["n"])
    floor_name = f"floor {p['floor']}"
    floor = resolve_frame(p["frame"]).floor_ensemble(ground, p["floor"])
    cases = {"ground": ground, floor_name: floor}
    a50 = agx_50(
        blocks,
        cases,
        resolution=p["resolution"],
        agx_max=p["agx_max"],
        physics=physics,
        backend=ctx.backend,
        progress=ctx.progress,
        out=ctx.store("sec8", "agx50"),
    )
    balance = xr.concat(
        [
            energy_balance(blocks, ens, a50["agx50"].sel(case=name).values, band_hz=p["band_hz"])
            for name, ens in cases.items()
        ],
        pd.Index(list(cases), name="location"),
    )
    fig13 = overturning_probability(
        examples[:1],
        ground,
        p["fig13_agx"],
        physics=physics,
        backend=ctx.backend,
        progress=ctx.progress,
    )
    same = np.isclose(a50["R"].values, examples[0].R, rtol=1e-9) & np.isclose(
        a50["gamma"].values, examples[0].gamma, rtol=1e-9
    )
    if same.any():
        a50_ex = float(a50["agx50"].sel(case="ground").values[np.argmax(same)])
    else:
        a50_ex = float(
            agx_50(
                examples[:1],
                ground,
                resolution=p["resolution"],
                agx_max=p["agx_max"],
                physics=physics,
                backend=ctx.backend,
            )["agx50"][0]
        )
    freqs = portable.geomspace(*FIG14_BAND_HZ, FIG14_N_FREQS)
    psv = (
        response_spectrum(ground.scaled(a50_ex).acc, ground.dt, freqs, 0.05).mean().psv
        if np.isfinite(a50_ex)
        else np.full(freqs.size, np.nan)
    )
    verdicts = assess(examples, floor, agx=p["example_agx"], band_hz=p["band_hz"])
    sim = overturning_probability(
        examples, floor, [p["example_agx"]], physics=physics, backend=ctx.backend
    )
    ex = xr.merge(
        [
            verdicts,
            sim[["probability", "ci_low", "ci_high", "n"]]
            .isel(agx=0)
            .assign_coords(body=verdicts["body"].values),
        ],
        compat="override",
    )
    ex.attrs.update(agx=p["example_agx"], location=f"{floor_name} of {p['frame']}")
    fig13.attrs.update(agx50=a50_ex, sv_required=housner_sv(examples[0]))
    return Sec8Result(balance, fig13, (freqs, psv), ex, ctx.label(n=ground.n, bodies=len(blocks)))


def report(result: Sec8Result, rep: Report, ctx: RunContext) -> None:
    """Figures 13–16, Tables 1–3 beside the paper's, and the worked examples."""
    b, lab = result.balance, result.label
    locations = [str(x) for x in b["location"].values]
    rep.heading(TITLE)
    paper = paper_values()["section8"]
    f13 = result.fig13
    a50 = f13.attrs["agx50"]
    rep.plot(
        plot_fragility,
        f13,
        name="fig13",
        caption=f"Fig. 13: {f13['body'].values[0]} on the ground (paper: A_gx50 = "
        f"{paper['fig13_agx50']} g; ours {a50:.2f} g) [{lab}]",
    )
    freqs, psv = result.fig14
    caption = (
        f"Fig. 14: mean PSV of the ground motions at A_gx50 = {a50:.2f} g of "
        f"{f13['body'].values[0]} (paper: S_v1 = {paper['fig14_sv1_cm_s']} cm/s) [{lab}]"
    )
    rep.plot(
        plot_sv1_spectrum,
        freqs,
        psv,
        sv_required=f13.attrs["sv_required"],
        name="fig14",
        caption=caption,
    )
    for fig_no, loc in zip((15, 16), locations):
        rep.plot(
            plot_sv_agx,
            b.sel(location=loc),
            name=f"fig{fig_no}",
            caption=f"Fig. {fig_no}: required S_v against A_gx50, bodies on {_the(loc)} [{lab}]",
        )
    _tables(b, rep, lab)
    _examples(result.examples, rep, lab)


def _tables(b: xr.Dataset, rep: Report, lab: str) -> None:
    """Tables 1–3 (ours, the paper's, differences) for the bodies run."""
    what = {1: "required S_v of Eq. (11) [cm/s]", 2: "S_v1 [cm/s]", 3: "ratio S_v1/S_v [-]"}
    for no, var, fmt in ((1, "sv_required", ".2f"), (2, "sv1", ".2f"), (3, "ratio", ".3f")):
        ours = grid_table(b.sel(location="ground"), var)
        theirs = paper_table(no).reindex(index=ours.index, columns=ours.columns)
        both = pd.concat({"ours": ours, "paper": theirs, "ours - paper": ours - theirs}, axis=1)
        top, gamma = (both.columns.get_level_values(i) for i in (0, 1))
        both.columns = [f"{k} γ={g:g}" for k, g in zip(top, gamma)]
        rep.table(
            _r_labels(both),
            f"Table {no}, {what[no]}, bodies on the ground: ours, the "
            f"paper's and the difference, for the bodies run [{lab}]",
            name=f"table{no}",
            floatfmt=fmt,
        )
    for loc in [str(x) for x in b["location"].values[1:]]:
        ratio = grid_table(b.sel(location=loc), "ratio")
        ratio.columns = [f"γ={g:g}" for g in ratio.columns]
        rep.table(
            _r_labels(ratio),
            f"Ratio S_v1/S_v for bodies on {_the(loc)} (no table in the paper) [{lab}]",
            name=f"table3-{slug(loc)}",
            floatfmt=".3f",
        )
    rows = {
        f"ours, {loc}": ratio_stats(b["ratio"].sel(location=loc).values)
        for loc in b["location"].values
    }
    rows["paper, ground"] = ratio_stats(paper_table(3).values)
    rep.table(
        pd.DataFrame.from_dict(rows, orient="index")
        .rename(columns={"mean": "mean [-]", "min": "min [-]", "max": "max [-]"})
        .rename_axis("ratio S_v1/S_v"),
        f"Table 3 in brief: number of bodies, mean, smallest and largest ratio [{lab}]",
        name="table3-stats",
        floatfmt=".3f",
    )


def _the(location: str) -> str:
    """``location`` after "on": "the ground", but "floor 1" (of ...) as it is."""
    return "the ground" if location == "ground" else location


def _r_labels(table: pd.DataFrame) -> pd.DataFrame:
    """Rows labelled by R as the paper prints it (whole feet in metres, two decimals)."""
    return table.set_axis(np.round(table.index.to_numpy(dtype=float), 2), axis=0).rename_axis(
        "R [m]"
    )


def _examples(ex: xr.Dataset, rep: Report, lab: str) -> None:
    """The two worked examples: Eq. (11) verdicts with our spectrum against the paper's, the
    simulated overturning probability at the same A_gx, whether the two agree and why they can
    differ."""
    paper = paper_values()["section8"]
    compared = eq11_vs_monte_carlo(
        ex["verdict"].values, ex["probability"].values, ex["ci_low"].values, ex["ci_high"].values
    )
    rows = []
    for i, body in enumerate(ex["body"].values):
        row = {
            "body": body,
            "required S_v [cm/s]": 100 * float(ex["sv_required"][i]),
            "available S_v, ours [cm/s]": 100 * float(ex["sv_available"][i]),
            "available S_v, paper [cm/s]": paper["example_floor_sv_cm_s"],
            "verdict by Eq. (11), ours": str(ex["verdict"].values[i]),
            "P(overturn) simulated [-]": float(ex["probability"][i]),
            "95 % CI [-]": f"{float(ex['ci_low'][i]):.2f}–{float(ex['ci_high'][i]):.2f}",
            "Eq. (11) vs Monte Carlo": compared[i],
        }
        if i < len(paper["example_verdicts"]):
            row["verdict, paper"] = paper["example_verdicts"][i]
        rows.append(row)
    rep.table(
        pd.DataFrame(rows),
        f"Worked examples of Section 8: bodies on "
        f"{ex.attrs['location']} at A_gx = {ex.attrs['agx']:g} g [{lab}]",
        name="worked-examples",
        floatfmt=".2f",
    )
    rep.text(eq11_vs_monte_carlo_note(ex.attrs["band_hz"]))
