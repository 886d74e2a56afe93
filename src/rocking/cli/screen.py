"""``rocking screen``: screen an inventory of free-standing items against a design spectrum."""

from __future__ import annotations

import math
import time
import warnings
from dataclasses import dataclass
from importlib.resources import files
from pathlib import Path
from typing import TYPE_CHECKING, cast

import click

from ..defaults import SPECTRUM_SYNTAX
from ._options import (
    SEED,
    OutFolder,
    agx_max_option,
    compute_options,
    count,
    friction_params,
    option_group,
    physics_options,
    quiet_option,
    resolution_option,
    run_folder_options,
)

if TYPE_CHECKING:
    import pandas as pd
    import xarray as xr

    from ..assessment.inventory import Inventory
    from ..assessment.risk import HazardCurve
    from ..core.progress import Reporter
    from ..dynamics.physics import Physics
    from ..montecarlo.backends import Backend, Compute
    from ..montecarlo.search import Agx50Search
    from ..motions.ensemble import Ensemble
    from ..motions.targets import TargetSpectrum

#: Files shipped with the package that ``example`` stands for.
EXAMPLE_INVENTORY = Path(str(files("rocking") / "data" / "example_inventory.csv"))
EXAMPLE_SPECTRUM = Path(str(files("rocking") / "data" / "example_spectrum.csv"))


@dataclass(frozen=True)
class _Items:
    """INVENTORY, --spectrum and --frame."""

    inventory: str
    spectrum_text: str
    frame: str | None


@dataclass(frozen=True)
class _Motions:
    """--n, --seed, --duration and --motions: the motions to generate, or their file."""

    n: int
    seed: int
    duration: float
    path: str | None


@dataclass(frozen=True)
class _SiteHazard:
    """--hazard and --years."""

    text: str | None
    years: float


def _search(resolution: float, agx_max: float) -> Agx50Search:
    from ..montecarlo.search import Agx50Search

    return Agx50Search(resolution=resolution, agx_max=agx_max)


_items_options = option_group(
    "items",
    _Items,
    click.argument("inventory", metavar="INVENTORY"),
    click.option(
        "--spectrum",
        "spectrum_text",
        required=True,
        metavar="SPEC",
        help=f"Design spectrum at the ground: {SPECTRUM_SYNTAX}; or 'example' (the "
        "shipped site spectrum).",
    ),
    click.option(
        "--frame",
        default=None,
        metavar="FRAME",
        help="Default frame of 'floor N' items without one: a preset (paper-2.0, "
        "paper-1.5, paper-1.0, paper-0.5) or a frame TOML file.",
    ),
)
_out_option = click.option(
    "--out",
    "out_dir",
    required=True,
    type=click.Path(file_okay=False, writable=True),
    help="Output folder. A folder of another run is refused (see --overwrite).",
)
_motions_options = option_group(
    "motions",
    _Motions,
    click.option(
        "--n",
        "n_motions",
        type=count("motions"),
        default=200,
        show_default=True,
        help="Number of spectrum-compatible motions.",
    ),
    click.option("--seed", type=SEED, default=0, show_default=True, help="Seed of the motions."),
    click.option(
        "--duration",
        type=click.FloatRange(0.0, min_open=True),
        default=20.0,
        show_default=True,
        help="Duration of the motions [s].",
    ),
    reads=("motions_path",),
)
_search_options = option_group(
    "search",
    _search,
    resolution_option,
    agx_max_option,
)
_scheduler_option = click.option(
    "--scheduler",
    default=None,
    metavar="SCHED",
    help="Where to run: 'local' (default, threads), 'dask-local' or a Dask scheduler "
    "address tcp://HOST:PORT.",
)
_motions_path_option = click.option(
    "--motions",
    "motions_path",
    default=None,
    type=click.Path(dir_okay=False, exists=True),
    help="Ground motions to use instead of generating --n of them: an ensemble file from "
    "'rocking motions generate' or 'rocking motions import' (with vertical components if it "
    "has them), scaled to the design A_gx; they should be compatible with --spectrum.",
)
_hazard_options = option_group(
    "site_hazard",
    _SiteHazard,
    click.option(
        "--hazard",
        "hazard_text",
        default=None,
        metavar="FILE",
        help="Site hazard curve (CSV: 'IM [unit],annual_rate'; 'example': the shipped "
        "illustrative PGV curve): adds each item's fragility against that IM of the ground "
        "motion and its mean annual rate of overturning.",
    ),
    click.option(
        "--years",
        type=click.FloatRange(0.0, min_open=True),
        default=50.0,
        show_default=True,
        help="Exposure time [yr] of the probability of overturning with --hazard.",
    ),
)


@click.command("screen")
@_items_options
@run_folder_options(_out_option)
@_motions_options
@_search_options
@click.option(
    "--floor-motions",
    type=click.Choice(["building", "paper"]),
    default="building",
    show_default=True,
    help="Floor motions: the frame's response to the design-level ground motions "
    "('building'), or rescaled to the ground's A_gx as in the paper's Section 7 "
    "('paper').",
)
@compute_options(_scheduler_option)
@physics_options(restitution=False)
@_motions_path_option
@_hazard_options
@click.option(
    "--limit-states",
    "limit_states_text",
    default=None,
    metavar="LIST",
    help="Also the probability of each of these limit states at the design level, e.g. "
    "'uplift, theta/alpha>=0.5, slip>=0.05, overturn' (columns P(<limit state>) of "
    "screen.csv).",
)
@click.option(
    "--max-slip",
    "max_slip",
    type=click.FloatRange(0.0, min_open=True),
    default=None,
    metavar="M",
    help="Largest allowed slip [m] (e.g. the clearance to a wall or a plinth's edge): the "
    "verdict then counts the motions that overturn an item or slide it at least this far "
    "(peak slip). Without it the verdict is on overturning, the slip reported beside it.",
)
@quiet_option
def screen_command(
    items: _Items,
    folder: OutFolder,
    motions: _Motions,
    search: Agx50Search,
    floor_motions: str,
    compute: Compute,
    physics: Physics,
    site_hazard: _SiteHazard,
    limit_states_text: str | None,
    max_slip: float | None,
) -> None:
    """Screen every item of INVENTORY (CSV or TOML) against a design spectrum.

    For each item: Housner's energy balance (paper Eq. 11) against the available S_v at its
    location (ground: the spectrum's PSV in 0.04–0.6 Hz; floor N: the mean PSV of the floor
    motions, the frame's response to spectrum-compatible ground motions at the design A_gx), and
    the Monte Carlo probability of overturning at the design level (ground A_gx = the spectrum's
    zero-period acceleration) with its 95 % Wilson interval and the ground A_gx of 50 %
    probability; and, with the item's friction mu, its response at the design level (the share
    of motions in which it rests, slides, rocks, slide-rocks or overturns) and its slip.

    INVENTORY columns: name, height and width [m] (or R [m] and gamma), location ('ground' or
    'floor N'), optional frame, e, mu and mu_k (empty mu: infinite friction, or --mu); 'example'
    is the shipped example inventory.

    Writes to --out: tables/screen.csv (sorted, most at risk first), figures/sv-agx.png,
    report.md, report.html and run.json. Example:

    \b
        rocking screen example --spectrum asce7:SDS=1.0,SD1=0.6,TL=8 --frame paper-2.0 --out out
    """
    from ..assessment.screen import screen
    from ..dynamics.limits import parse_limit_states
    from ..motions.design import design_pga
    from ..report import remove_report

    started = time.perf_counter()
    out = Path(folder.path)
    spectrum_text, frame, motions_path = items.spectrum_text, items.frame, motions.path
    n_motions, resolution, agx_max = motions.n, search.resolution, search.agx_max
    states = None if limit_states_text is None else parse_limit_states(limit_states_text)
    inv_path, spectrum, inv, notes = _read_inputs(items.inventory, spectrum_text, frame)
    hazard = None if site_hazard.text is None else _read_hazard(site_hazard.text)
    ensemble = None if motions_path is None else _read_motions(motions_path)
    backend, progress = compute.backend, cast("Reporter", compute.progress)
    assert backend is not None  # made by compute_options
    backend.connect()  # an unreachable scheduler is refused before the run folder is made
    params = {
        "inventory": str(inv_path),
        "spectrum": spectrum.name,
        "spectrum_spec": spectrum_text,
        "design_agx": design_pga(spectrum),
        "frame": frame,
        "n_motions": n_motions,
        "seed": motions.seed,
        "duration": motions.duration,
        "resolution": resolution,
        "agx_max": agx_max,
        "floor_motions": floor_motions,
        "motions": motions_path,
        "hazard": None if hazard is None else hazard.source,
        "years": site_hazard.years,
        "limit_states": None if states is None else [ls.name for ls in states],
        **friction_params(physics),  # --mu, --mu-k (the items' own: in INVENTORY)
        **({} if max_slip is None else {"max_slip": max_slip}),
    }
    run_folder = folder.claim(
        "screen",
        params,
        settings={"scheduler": _scheduler(backend)},
        reads={"INVENTORY": inv_path, "--motions": motions_path, "--frame": frame},
    )
    with run_folder as run, progress:
        remove_report(out)  # a failed run must not leave an older report looking like its result
        progress.write(
            f"screening {len(inv)} items against {spectrum.name} at the design "
            f"A_gx = {design_pga(spectrum):.3g} g with {n_motions} motions"
        )
        with backend, progress.stage(f"screening {len(inv)} items", unit="sim"):
            ds = screen(
                inv,
                spectrum,
                n=n_motions,
                seed=motions.seed,
                duration=motions.duration,
                search=search,
                floor_motions=floor_motions,
                compute=compute,
                physics=physics,
                ensemble=ensemble,
                hazard=hazard,
                years=site_hazard.years,
                limit_states=states,
                max_slip=max_slip,
            )
        for name in _write_report(ds, out, inv_path, notes):
            run.file(name)
        run.update(at_risk=int(ds["at_risk"].sum()))
    wall = time.perf_counter() - started
    click.echo(f"{int(ds['at_risk'].sum())} of {len(inv)} items at risk")
    for item, mode in zip(ds["item"].values, ds["mode"].values):
        if mode in ("slide", "slide-rock"):
            it = ds.sel(item=item)
            share = float(it["response_share"].sel(response=mode))
            click.echo(
                f"  {item}: {mode} in {100 * share:.3g} % of the motions; peak slip median "
                f"{1e3 * float(it['slip_median']):.3g} mm, largest "
                f"{1e3 * float(it['slip_max']):.3g} mm"
            )
    click.echo(f"wrote {out / 'report.html'} ({wall:.1f} s)")


def _scheduler(backend: Backend) -> str:
    """--scheduler as run.json records it: "local", "dask-local" or the scheduler's address."""
    from ..montecarlo.backends import LocalBackend

    address = getattr(backend, "address", None)
    return address or ("local" if isinstance(backend, LocalBackend) else "dask-local")


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
    from ..assessment.screen import eq11_vs_monte_carlo_note, results_table
    from ..plots.screen import plot_screen
    from ..report import Report

    table = results_table(ds)
    report = Report(f"Screening of {inv_path.name}", out)
    report.text(_summary(ds, table, inv_path))
    for note in notes:
        report.warning(note)
    report.figure(
        plot_screen(ds),
        "sv-agx",
        "Items on the S_v–A_gx plane (paper Fig. 15 style), numbered as the rows of the table: "
        "required S_v of Eq. (11) against the A_gx of 50 % overturning probability; dashed: "
        "design A_gx; dotted: available S_v at each location; □ / ◇ about a point: the item "
        "mostly slides / slide-rocks at the design A_gx.",
    )
    report.table(
        page_table(table),
        "Items, most at risk first (every column, e.g. H, B, R, e, μ and the S_v of Eq. (11): "
        "`tables/screen.csv`).",
        name="screen",
        floatfmt=".3g",
        csv=table,
    )
    report.text(eq11_vs_monte_carlo_note(ds.attrs["band_hz"]))
    report.write()
    return list(report.files)


def page_table(table: pd.DataFrame) -> pd.DataFrame:
    """The columns of a screening's table (:func:`rocking.assessment.screen.results_table`)
    shown on the report's page: number, item, where, the verdict and its Monte Carlo numbers,
    the friction and the response at the design level (the most frequent response, the share
    of each, the slip), then Eq. (11)'s screen and, with a hazard, the annual rate."""
    import pandas as pd

    page = pd.DataFrame(
        {
            "#": range(1, len(table) + 1),
            "item": table["item"],
            "location": table["location"],
            "H × B [m]": [
                f"{h:.3g}\u202f×\u202f{b:.3g}" for h, b in zip(table["H [m]"], table["B [m]"])
            ],
            "verdict": table["verdict"],
            "P(overturn) [-]": table["P(overturn) [-]"],
            "95 % interval [-]": [
                f"{lo:.3f}–\u2060{hi:.3f}"  # a word joiner: no line break after the dash
                for lo, hi in zip(table["CI low [-]"], table["CI high [-]"])
            ],
            "A_gx50 [g]": table["Agx50 [g]"],
            "μ [-]": [_friction(mu, mu_k) for mu, mu_k in zip(table["mu [-]"], table["mu_k [-]"])],
            "response (most frequent)": table["mode"],
            "responses [% of motions]": [_shares(row) for _, row in table.iterrows()],
            "slip if standing, median / largest [mm]": [
                "–" if math.isnan(m) else f"{m:.3g} / {x:.3g}"
                for m, x in zip(
                    table["median slip if standing [mm]"], table["max slip if standing [mm]"]
                )
            ],
            "Eq. (11) screen (conservative)": table["Eq. (11) screen"],
            "Eq. (11) margin [-]": table["margin [-]"],
        }
    )
    slip = [c for c in table.columns if c.startswith("P(overturn or slip")]
    if slip:
        page.insert(list(page.columns).index("verdict") + 1, slip[0], table[slip[0]])
    for column in table.columns:
        if column.startswith(("annual rate", "P in ")):
            page[column] = table[column]
    return page


def _friction(mu: float, mu_k: float) -> str:
    """μ of a page's row: "∞" (infinite friction), μ_s, or "μ_s / μ_k" where they differ."""
    if math.isnan(mu):  # infinite friction
        return "∞"
    return f"{mu:.3g}" if mu_k == mu else f"{mu:.3g} / {mu_k:.3g}"


def _shares(row: pd.Series) -> str:
    """The responses of a page's row that occur, in % of the motions, e.g. "slide 62, rest 38"
    (most frequent first), and "flight N" where the base left the ground."""
    from ..assessment.screen import RESPONSES

    shares = {r: row["P(overturn) [-]" if r == RESPONSES[-1] else f"P({r}) [-]"] for r in RESPONSES}
    text = ", ".join(
        f"{r} {100 * p:.3g}" for r, p in sorted(shares.items(), key=lambda kv: -kv[1]) if p > 0
    )
    flight = row["P(flight) [-]"]
    return text + (f"; flight {100 * flight:.3g}" if flight > 0 else "")


_FLOORS = {
    "building": "floor motions: the frame's response to these ground motions (A_gx50 of every "
    "item is the ground A_gx).",
    "paper": "floor motions rescaled to the same A_gx as the ground (paper Section 7; A_gx50 of "
    "a floor item is the floor's A_gx).",
}


def _modes_summary(ds: xr.Dataset) -> str:
    """Markdown sentence(s) of a screening's summary on the response modes: how many items
    mostly rest, slide, rock, slide-rock or overturn, which ones slide, and the largest slip."""
    from ..assessment.screen import RESPONSES

    items, mode = ds["item"].values, ds["mode"].values
    counts = ", ".join(f"{int((mode == r).sum())} {r}" for r in RESPONSES if (mode == r).any())
    text = (
        f"Response at the design level (the most frequent over the motions; with the item's "
        f"friction μ, infinite where not given): {counts}."
    )
    slipping = [i for i, r in zip(items, mode) if r in ("slide", "slide-rock")]
    if slipping:
        text += f" Sliding mostly: {', '.join(map(str, slipping))}."
    slip = ds["slip_max"].fillna(0.0).values
    worst = int(slip.argmax())
    if slip[worst] > 0.0:
        text += (
            f" Largest peak slip of an item left standing: {1e3 * slip[worst]:.3g} mm "
            f"({items[worst]}; median over the motions that leave it standing "
            f"{1e3 * ds['slip_median'].values[worst]:.3g} mm)."
        )
    else:
        text += " No item left standing slides in any motion."
    return text


def _summary(ds: xr.Dataset, table: pd.DataFrame, inv_path: Path) -> str:
    """Markdown paragraph(s) above the figure (``table``:
    :func:`rocking.assessment.screen.results_table` of ``ds``): the verdict first, with its
    rule, then Eq. (11) as the screen it is, then the inputs."""
    from ..assessment.risk import illustrative_note
    from ..assessment.screen import AGREE, AT_RISK, BORDERLINE, SLIP_RULE, VERDICT_RULE

    a = ds.attrs
    n = ds.sizes["item"]
    verdict = ds["verdict"].values
    at_risk = [str(i) for i, v in zip(ds["item"].values, verdict) if v == AT_RISK]
    borderline = [str(i) for i, v in zip(ds["item"].values, verdict) if v == BORDERLINE]
    n_fail_eq11 = int((ds["margin"].values <= 0.0).sum())
    max_slip = a["max_slip"]
    slip_rule = "" if math.isnan(max_slip) else f"; {SLIP_RULE} ({max_slip:g} m)"
    differ = [
        str(item)
        for item, c in zip(table["item"], table["Eq. (11) vs Monte Carlo"])
        if not c.startswith(AGREE)
    ]
    text = (
        f"**{len(at_risk)} of {n} items at risk"
        f"{': ' + ', '.join(at_risk) if at_risk else ''}.** "
        f"{len(borderline)} borderline{': ' + ', '.join(borderline) if borderline else ''}.\n\n"
        f"Verdict (one rule, from {a['n_motions']} simulated motions at the design A_gx = "
        f"{a['design_agx']:.3g} g): {VERDICT_RULE}{slip_rule}.\n\n"
        f"{_modes_summary(ds)}\n\n"
        f"Housner's Eq. (11), the quick screen, flags {n_fail_eq11} of {n} items (margin ≤ 0); "
        f"it differs from the simulation for {len(differ)} "
        f"item(s){': ' + ', '.join(differ) if differ else ''} (why: see below the table).\n\n"
    )
    if "annual_rate" in ds:
        text += (
            f"With the hazard curve `{Path(a['hazard']).name}`, the table also gives each item's "
            f"mean annual rate of overturning and its probability in {a['years']:g} years. "
            f"{illustrative_note(a['hazard'])}\n\n"
        )
    text += (
        f"Inventory `{inv_path}`: {n} items. Design spectrum: {a['spectrum']}; "
        f"design A_gx = {a['design_agx']:.3g} g (its zero-period acceleration). "
        f"{a['n_motions']} spectrum-compatible motions of {a['duration']:g} s (seed {a['seed']}); "
        f"{_FLOORS[a['floor_motions']]} Available S_v: "
        f"largest {100 * a['damping']:g} %-damped PSV in {a['band_hz'][0]:g}–{a['band_hz'][1]:g} "
        f"Hz. Intervals: {100 * a['confidence']:g} % Wilson."
    )
    return text


COMMANDS = [screen_command]
