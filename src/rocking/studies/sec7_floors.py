"""Section 7: bodies on the floors of shear frames against bodies on the ground.

``n`` ground motions (compound, 20 s; 500 in the paper) drive each frame (the four uniform
5-story presets, T1 = 2.0, 1.5, 1.0, 0.5 s). Every floor's ensemble of absolute accelerations is
scaled to the same A_gx as the ground (as the paper does) and the overturning probability of six
bodies (R = 1.22, 2.44, 3.66 m; γ = 3, 4) is estimated on the ground and on floors 1–5 over
A_gx = 0.3–0.8 g (Fig. 11). Fig. 12: mean 5 %-damped pseudo-velocity spectra of every location
at A_gx = 0.6 g.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Any

import numpy as np
import pandas as pd
import xarray as xr

from ..core import portable
from ..defaults import BAND_HZ
from ..dynamics.body import Block
from ..montecarlo.probability import overturning_probability
from ..motions.response import response_spectrum
from ..plots.fragility import plot_fragility
from ..plots.frames import plot_floor_spectra
from ..report import Report, slug
from .config import RunContext, resolve_bodies, resolve_frame

TITLE = "Section 7: floors of shear frames (Figs. 11-12)"
#: Frequency range of the Fig. 12 spectra [Hz] (as the paper's figure).
SPECTRA_BAND_HZ = (0.04, 30.0)
#: Frequency at which the paper orders the floors' S_v for the 2.0 s frame [Hz].
ORDER_FREQ_HZ = 1.0


@dataclass(frozen=True)
class Sec7Result:
    """``probability``: overturning probability Dataset with dimensions (frame, location, body,
    agx) and coordinate ``T1`` [s] on frame; ``psv``: mean PSV [m/s] (frame, location, freq)."""

    probability: xr.Dataset
    psv: xr.DataArray
    label: str


def run(ctx: RunContext) -> Sec7Result:
    """Floor ensembles of every frame, their overturning probabilities and mean spectra."""
    p, physics = ctx.cfg["sec7"], ctx.physics
    blocks = resolve_bodies(p["bodies"], "sec7.bodies")
    ground = ctx.motions("sec7", p["n"])
    freqs = portable.geomspace(*SPECTRA_BAND_HZ, p["n_freq"])
    options: dict[str, Any] = {"physics": physics, "backend": ctx.backend, "progress": ctx.progress}
    # the ground is the same for every frame: its probabilities and spectrum once
    on_ground = overturning_probability(
        blocks, {"ground": ground}, p["agx"], out=ctx.store("sec7", "ground"), **options
    )
    ground_psv = _mean_psv(ground, p["spectra_agx"], freqs)
    probs, spectra, periods = [], [], []
    for i, name in enumerate(p["frames"]):
        frame = resolve_frame(name)
        floors = {f"floor {k}": ens for k, ens in frame.floor_ensembles(ground).items() if k}
        ds = overturning_probability(
            blocks, floors, p["agx"], out=ctx.store("sec7", f"frame-{i}"), **options
        )
        probs.append(xr.concat([on_ground, ds], "case").rename({"case": "location"}))
        spectra.append(
            [ground_psv, *(_mean_psv(ens, p["spectra_agx"], freqs) for ens in floors.values())]
        )
        periods.append(float(frame.periods[0]))
    prob = xr.concat(probs, pd.Index(p["frames"], name="frame"))
    prob = prob.assign_coords(T1=("frame", periods, {"units": "s"}))
    psv = xr.DataArray(
        np.array(spectra),
        dims=("frame", "location", "freq"),
        coords={
            "frame": p["frames"],
            "location": list(probs[0]["location"].values),
            "freq": ("freq", freqs, {"units": "Hz"}),
            "T1": ("frame", periods, {"units": "s"}),
        },
        attrs={"units": "m s-1", "agx": p["spectra_agx"], "damping": 0.05},
    )
    return Sec7Result(prob, psv, ctx.label(n=ground.n))


def _mean_psv(ens, agx: float, freqs: np.ndarray) -> np.ndarray:
    """Ensemble-mean 5 %-damped PSV [m/s] of ``ens`` scaled to ``agx`` [g] at ``freqs`` [Hz]."""
    return response_spectrum(ens.scaled(agx).acc, ens.dt, freqs, 0.05).mean().psv


def floor_order(psv: xr.DataArray, frame: str, freq_hz: float = ORDER_FREQ_HZ) -> list[str]:
    """Locations of ``frame`` ordered by increasing mean S_v at ``freq_hz`` [Hz]."""
    row = psv.sel(frame=frame).interp(freq=freq_hz)
    return [str(loc) for loc in row["location"].values[np.argsort(row.values)]]


def report(result: Sec7Result, rep: Report, ctx: RunContext) -> None:
    """Figures 11 (one per frame) and 12, and tables of mean probability and S_v."""
    ds, psv = result.probability, result.psv
    rep.heading(TITLE)
    rep.text(
        "Paper: on the 2.0 s frame the R = 1.22 m, γ = 4 body is most likely to overturn "
        "on the 4th floor and least on the ground (Fig. 11a); on the 0.5 s frame the "
        "ground is worst and the probability falls floor by floor (Fig. 11b). Around "
        "1 Hz the 2.0 s frame's S_v rises in the order ground, 1, 2, 5, 3, 4 (Fig. 12a)."
    )
    wanted = Block(*ctx.cfg["sec7"]["fig11_body"]).label
    body = wanted if wanted in ds["body"].values else ds["body"].values[0]
    for frame in ds["frame"].values:
        t1 = float(ds["T1"].sel(frame=frame))
        sel = ds.sel(frame=frame, body=[body]).rename({"location": "case"})
        rep.plot(
            plot_fragility,
            sel,
            name=f"fig11-{slug(frame)}",
            caption=f"Fig. 11: {body} on {frame} (T1 = {t1:.2f} s) [{result.label}]",
        )
    for frame in psv["frame"].values:
        caption = (
            f"Fig. 12: mean PSV of {frame} (T1 = "
            f"{float(psv['T1'].sel(frame=frame)):.2f} s) at A_gx = {psv.attrs['agx']:g} g, "
            f"5 % damping [{result.label}]"
        )
        rep.plot(
            plot_floor_spectra,
            psv["freq"].values,
            psv.sel(frame=frame).values,
            list(psv["location"].values),
            name=f"fig12-{slug(frame)}",
            caption=caption,
        )
    mean = ds["probability"].mean("agx").to_dataframe().reset_index()
    table = mean.pivot_table(index=["frame", "body"], columns="location", values="probability")[
        list(ds["location"].values)
    ]
    rep.table(
        table,
        "Section 7: overturning probability averaged over A_gx = "
        f"{', '.join(f'{a:g}' for a in ds['agx'].values)} g, by frame, body and location "
        f"[{result.label}]",
        name="sec7-mean-probability",
        floatfmt=".3f",
    )
    band = psv.sel(freq=slice(*BAND_HZ)).max("freq")
    rows = {
        f: {loc: 100 * float(band.sel(frame=f, location=loc)) for loc in psv["location"].values}
        for f in psv["frame"].values
    }
    rep.table(
        pd.DataFrame.from_dict(rows, orient="index").rename_axis("frame"),
        f"Max of the mean S_v [cm/s] in 0.04–0.6 Hz at A_gx = {psv.attrs['agx']:g} g "
        f"[{result.label}]",
        name="sec7-sv-band",
        floatfmt=".1f",
    )
    by_loc = ds["probability"].sel(body=body).mean("agx")
    ranks = "; ".join(
        f"{f}: "
        + ", ".join(
            str(loc)
            for loc in by_loc["location"].values[
                np.argsort(by_loc.sel(frame=f).values, kind="stable")
            ]
        )
        for f in ds["frame"].values
    )
    rep.text(
        f"Locations of {body} in order of increasing mean probability (ours): {ranks}. "
        "Paper: 2.0 s frame least on the ground, most on floor 4; 0.5 s frame least on "
        "floor 5, rising floor by floor to the ground."
    )
    orders = "; ".join(f"{f}: {', '.join(floor_order(psv, f))}" for f in psv["frame"].values)
    rep.text(
        f"Order of increasing mean S_v at {ORDER_FREQ_HZ:g} Hz (ours): {orders}. "
        "Paper (2.0 s frame): ground, floor 1, floor 2, floor 5, floor 3, floor 4."
    )
