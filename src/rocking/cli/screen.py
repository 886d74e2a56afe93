"""``rocking screen``: screen an inventory of free-standing items against a design spectrum."""

from __future__ import annotations

import time
import warnings
from importlib.resources import files
from pathlib import Path
from typing import TYPE_CHECKING

import click

from ..defaults import SPECTRUM_SYNTAX
from ._options import G_LEVEL, SEED, count, quiet_option, reporter

if TYPE_CHECKING:
    import pandas as pd
    import xarray as xr

    from ..assessment.inventory import Inventory
    from ..assessment.risk import HazardCurve
    from ..motions.ensemble import Ensemble
    from ..motions.targets import TargetSpectrum

#: Files shipped with the package that ``example`` stands for.
EXAMPLE_INVENTORY = Path(str(files("rocking") / "data" / "example_inventory.csv"))
EXAMPLE_SPECTRUM = Path(str(files("rocking") / "data" / "example_spectrum.csv"))


@click.command("screen")
@click.argument("inventory", metavar="INVENTORY")
@click.option(
    "--spectrum",
    "spectrum_text",
    required=True,
    metavar="SPEC",
    help=f"Design spectrum at the ground: {SPECTRUM_SYNTAX}; or 'example' (the "
    "shipped site spectrum).",
)
@click.option(
    "--frame",
    default=None,
    metavar="FRAME",
    help="Default frame of 'floor N' items without one: a preset (paper-2.0, "
    "paper-1.5, paper-1.0, paper-0.5) or a frame TOML file.",
)
@click.option(
    "--out",
    "out_dir",
    required=True,
    type=click.Path(file_okay=False, writable=True),
    help="Output folder.",
)
@click.option(
    "--n",
    "n_motions",
    type=count("motions"),
    default=200,
    show_default=True,
    help="Number of spectrum-compatible motions.",
)
@click.option("--seed", type=SEED, default=0, show_default=True, help="Seed of the motions.")
@click.option(
    "--duration",
    type=click.FloatRange(0.0, min_open=True),
    default=20.0,
    show_default=True,
    help="Duration of the motions [s].",
)
@click.option(
    "--resolution",
    type=click.FloatRange(1e-6),
    default=0.01,
    show_default=True,
    help="Resolution of the A_gx50 search [g], >= 1e-6 (as agx50's).",
)
@click.option(
    "--agx-max",
    type=G_LEVEL,
    default=5.0,
    show_default=True,
    help="Upper end of the A_gx50 search [g].",
)
@click.option(
    "--floor-motions",
    type=click.Choice(["building", "paper"]),
    default="building",
    show_default=True,
    help="Floor motions: the frame's response to the design-level ground motions "
    "('building'), or rescaled to the ground's A_gx as in the paper's Section 7 "
    "('paper').",
)
@click.option(
    "--scheduler",
    default=None,
    metavar="SCHED",
    help="Where to run: 'local' (default, threads), 'dask-local' or a Dask scheduler "
    "address tcp://HOST:PORT.",
)
@click.option(
    "--motions",
    "motions_path",
    default=None,
    type=click.Path(dir_okay=False, exists=True),
    help="Ground motions to use instead of generating --n of them: an ensemble file from "
    "'rocking motions generate' or 'rocking motions import' (with vertical components if it "
    "has them), scaled to the design A_gx; they should be compatible with --spectrum.",
)
@click.option(
    "--hazard",
    "hazard_text",
    default=None,
    metavar="FILE",
    help="Site hazard curve (CSV: 'IM [unit],annual_rate'; 'example': the shipped "
    "illustrative PGV curve): adds each item's fragility against that IM of the ground "
    "motion and its mean annual rate of overturning.",
)
@click.option(
    "--years",
    type=click.FloatRange(0.0, min_open=True),
    default=50.0,
    show_default=True,
    help="Exposure time [yr] of the probability of overturning with --hazard.",
)
@quiet_option
def screen_command(
    inventory: str,
    spectrum_text: str,
    frame: str | None,
    out_dir: str,
    n_motions: int,
    seed: int,
    duration: float,
    resolution: float,
    agx_max: float,
    floor_motions: str,
    scheduler: str | None,
    motions_path: str | None,
    hazard_text: str | None,
    years: float,
    quiet: bool,
) -> None:
    """Screen every item of INVENTORY (CSV or TOML) against a design spectrum.

    For each item: Housner's energy balance (paper Eq. 11) against the available S_v at its
    location (ground: the spectrum's PSV in 0.04–0.6 Hz; floor N: the mean PSV of the floor
    motions, the frame's response to spectrum-compatible ground motions at the design A_gx), and
    the Monte Carlo probability of overturning at the design level (ground A_gx = the spectrum's
    zero-period acceleration) with its 95 % Wilson interval and the ground A_gx of 50 %
    probability.

    INVENTORY columns: name, height and width [m] (or R [m] and gamma), location ('ground' or
    'floor N'), optional frame, e, mu; 'example' is the shipped example inventory.

    Writes to --out: tables/screen.csv (sorted, most at risk first), figures/sv-agx.png,
    report.md, report.html and run.json. Example:

    \b
        rocking screen example --spectrum asce7:SDS=1.0,SD1=0.6,TL=8 --frame paper-2.0 --out out
    """
    from ..assessment.screen import screen
    from ..core.runs import RunFolder
    from ..montecarlo.backends import get_backend
    from ..motions.design import design_pga
    from ..report import remove_report

    started = time.perf_counter()
    out = Path(out_dir)
    remove_report(out)  # a failed run must not leave an older report looking like its result
    inv_path, spectrum, inv, notes = _read_inputs(inventory, spectrum_text, frame)
    hazard = None if hazard_text is None else _read_hazard(hazard_text)
    ensemble = None if motions_path is None else _read_motions(motions_path)
    backend = get_backend(scheduler)
    params = {
        "inventory": str(inv_path),
        "spectrum": spectrum.name,
        "spectrum_spec": spectrum_text,
        "design_agx": design_pga(spectrum),
        "frame": frame,
        "n_motions": n_motions,
        "seed": seed,
        "duration": duration,
        "resolution": resolution,
        "agx_max": agx_max,
        "floor_motions": floor_motions,
        "scheduler": scheduler or "local",
        "motions": motions_path,
        "hazard": None if hazard is None else hazard.source,
        "years": years,
    }
    progress = reporter(quiet)
    with RunFolder(out, command="screen", params=params) as run, progress:
        progress.write(
            f"screening {len(inv)} items against {spectrum.name} at the design "
            f"A_gx = {design_pga(spectrum):.3g} g with {n_motions} motions"
        )
        with backend, progress.stage(f"screening {len(inv)} items", unit="sim"):
            ds = screen(
                inv,
                spectrum,
                n=n_motions,
                seed=seed,
                duration=duration,
                resolution=resolution,
                agx_max=agx_max,
                floor_motions=floor_motions,
                backend=backend,
                progress=progress,
                ensemble=ensemble,
                hazard=hazard,
                years=years,
            )
        for name in _write_report(ds, out, inv_path, notes):
            run.file(name)
        run.update(at_risk=int(ds["at_risk"].sum()))
    wall = time.perf_counter() - started
    click.echo(
        f"{int(ds['at_risk'].sum())} of {len(inv)} items at risk; wrote "
        f"{out / 'report.html'} ({wall:.1f} s)"
    )


def _read_inputs(
    inventory: str, spectrum_text: str, frame: str | None
) -> tuple[Path, TargetSpectrum, Inventory, list[str]]:
    """The inventory file (``example``: the shipped one), the design spectrum, the inventory
    read with the default ``frame`` (a preset or a frame TOML file) and the warnings of reading
    it (each echoed to standard error)."""
    from ..assessment.energy import available_sv
    from ..assessment.inventory import read_inventory
    from ..motions.design import parse_spectrum
    from ..structures.frames import ShearFrame

    inv_path = (
        EXAMPLE_INVENTORY
        if inventory == "example" and not Path(inventory).exists()
        else Path(inventory)
    )
    if not inv_path.is_file():
        raise click.BadParameter(f"no such file: {inventory}", param_hint="INVENTORY")
    spectrum = parse_spectrum(
        str(EXAMPLE_SPECTRUM)
        if spectrum_text == "example" and not Path(spectrum_text).exists()
        else spectrum_text
    )
    available_sv(spectrum, damping=spectrum.damping)  # refuses one that does not cover the band
    default_frame = ShearFrame.from_toml(frame) if frame and Path(frame).is_file() else frame
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        inv = read_inventory(inv_path, frame=default_frame)
    notes = [str(w.message) for w in caught]
    for note in notes:
        click.echo(f"warning: {note}", err=True)
    return inv_path, spectrum, inv, notes


def _read_hazard(hazard_text: str) -> HazardCurve:
    """The site hazard curve of ``--hazard`` (``example``: the shipped one)."""
    from ..assessment.risk import HazardCurve

    return HazardCurve.from_csv(hazard_text)


def _read_motions(motions_path: str) -> Ensemble:
    """The ground motions of ``--motions``."""
    from ..motions.ensemble import Ensemble

    return Ensemble.load(motions_path)


def _write_report(ds: xr.Dataset, out: Path, inv_path: Path, notes: list[str]) -> list[str]:
    """Write the report of the screening ``ds`` (summary, figure, table) to ``out``; the names
    of the files written."""
    from ..assessment.screen import results_table
    from ..plots.screen import plot_screen
    from ..report import Report

    table = results_table(ds)
    report = Report(f"Screening of {inv_path.name}", out)
    report.text(_summary(ds, table, inv_path, notes))
    report.figure(
        plot_screen(ds),
        "sv-agx",
        "Items on the S_v–A_gx plane (paper Fig. 15 style): required S_v of "
        "Eq. (11) against the A_gx of 50 % overturning probability; dashed: design "
        "A_gx; dotted: available S_v at each location.",
    )
    report.table(table, "Items, most at risk first.", name="screen")
    report.write()
    return list(report.files)


_FLOORS = {
    "building": "floor motions: the frame's response to these ground motions (A_gx50 of every "
    "item is the ground A_gx).",
    "paper": "floor motions rescaled to the same A_gx as the ground (paper Section 7; A_gx50 of "
    "a floor item is the floor's A_gx).",
}


def _summary(ds: xr.Dataset, table: pd.DataFrame, inv_path: Path, notes: list[str]) -> str:
    """Markdown paragraph(s) above the figure (``table``:
    :func:`rocking.assessment.screen.results_table` of ``ds``)."""
    from ..assessment.screen import AGREE, eq11_vs_monte_carlo_note

    a = ds.attrs
    n_fail_eq11 = int((ds["margin"].values <= 0.0).sum())
    n_fail_mc = int((ds["probability"].values >= 0.5).sum())
    differ = [
        str(item)
        for item, c in zip(table["item"], table["Eq. (11) vs Monte Carlo"])
        if not c.startswith(AGREE)
    ]
    text = (
        f"Inventory `{inv_path}`: {ds.sizes['item']} items. Design spectrum: {a['spectrum']}; "
        f"design A_gx = {a['design_agx']:.3g} g (its zero-period acceleration). "
        f"{a['n_motions']} spectrum-compatible motions of {a['duration']:g} s (seed {a['seed']}); "
        f"{_FLOORS[a['floor_motions']]} Available S_v: "
        f"largest {100 * a['damping']:g} %-damped PSV in {a['band_hz'][0]:g}–{a['band_hz'][1]:g} "
        f"Hz.\n\n"
        f"- Housner's check (Eq. 11) fails for {n_fail_eq11} item(s) (margin ≤ 0).\n"
        f"- Monte Carlo: {n_fail_mc} item(s) overturn with probability ≥ 50 % at the design "
        f"A_gx ({100 * a['confidence']:g} % Wilson intervals in the table).\n"
        f"- The two disagree for {len(differ)} item(s){': ' if differ else ''}"
        f"{', '.join(differ)} (column 'Eq. (11) vs Monte Carlo' says which way).\n\n"
        + eq11_vs_monte_carlo_note(a["band_hz"])
    )
    if notes:
        text += "\n\n" + "\n".join(f"- **Warning:** {note}" for note in notes)
    return text


COMMANDS = [screen_command]
