"""``rocking fragility``, ``rocking agx50`` and ``rocking assess``: overturning probability of
bodies under an ensemble (paper Sections 6–8) and Housner's energy-balance screening (Eq. 11).

Every input (bodies file, frame preset, floor, A_gx range, restitution, band) is checked before
any work starts; a bad one ends the command with a one-line message.  The output folders are
:class:`rocking.core.runs.RunFolder`: claimed by one run, with ``run.json`` and its status, every
file written atomically; the Monte Carlo chunks in ``chunks/`` let the same command resume.
"""

from __future__ import annotations

import json
import math
import warnings
from collections.abc import Hashable
from dataclasses import dataclass
from pathlib import Path
from typing import TYPE_CHECKING, cast

import click

from ..defaults import AGX, N_BOOT
from ..errors import InputError
from ._options import (
    BAND_TEXT,
    G_LEVEL,
    SEED,
    OutFolder,
    agx_max_option,
    band_option,
    bodies_option,
    compute_options,
    count,
    frame_and_floor,
    frame_option,
    friction_params,
    load_bodies,
    option_group,
    options,
    parse_band,
    parse_range,
    physics_options,
    quiet_option,
    reporter,
    resolution_option,
    run_folder_options,
)

if TYPE_CHECKING:
    import numpy as np
    import pandas as pd
    import xarray as xr

    from ..assessment.bodies import NamedBody
    from ..core.progress import Reporter
    from ..dynamics.physics import Physics
    from ..montecarlo.backends import Backend, Compute
    from ..montecarlo.fragility import AnalysisIM
    from ..motions.ensemble import Ensemble
    from ..motions.targets import TargetSpectrum
    from ..report import Report
    from ..structures.frames import ShearFrame

#: Files written by ``rocking agx50`` for the paper's Tables 1–3 (when the bodies form a grid),
#: with the paper's decimals.
_TABLES = {
    "sv_required": ("table1_sv_required_cm_s.csv", "%.2f"),
    "sv1": ("table2_sv1_cm_s.csv", "%.2f"),
    "ratio": ("table3_ratio.csv", "%.3f"),
}


# --------------------------------------------------------------------------- helpers


def _location(ensemble: Ensemble, frame: ShearFrame | None, floor: int) -> Ensemble:
    return ensemble if frame is None else frame.floor_ensemble(ensemble, floor)


@dataclass(frozen=True)
class _Inputs:
    """--bodies, --motions, --floor and --frame of a run."""

    bodies_spec: str
    motions_path: str
    floor: int | None
    frame_name: str | None


def _prepare(
    inputs: _Inputs, compute: Compute, physics: Physics
) -> tuple[list[NamedBody], Ensemble, Physics]:
    """Check every input, then load the motions (at the bodies' location) and connect the
    backend to a remote scheduler (a local Dask cluster is only started when the run starts).

    Returns the bodies, the ensemble and ``physics`` with the bodies' own friction."""
    from ..assessment.bodies import with_body_friction
    from ..motions.ensemble import Ensemble

    bodies = load_bodies(inputs.bodies_spec)
    physics = with_body_friction(physics, bodies)
    frame, level = frame_and_floor(inputs.frame_name, inputs.floor)
    ensemble = _location(Ensemble.load(inputs.motions_path), frame, level)
    assert compute.backend is not None  # made by compute_options
    compute.backend.connect()  # an unreachable scheduler is refused before the run folder is made
    return bodies, ensemble, physics


def _names(ds: xr.Dataset, bodies: list[NamedBody]) -> xr.Dataset:
    """``ds`` with the user's body names as the ``body`` coordinate."""
    return ds.assign_coords(body=[b.name for b in bodies])


def _describe(ensemble: Ensemble) -> dict:
    """netCDF attributes saying what the motions were."""
    return {
        "location": str(ensemble.meta.get("location", "")),
        "n_motions": ensemble.n,
        "dt_s": ensemble.dt,
        "duration_s": ensemble.duration,
    }


def _run_params(
    bodies: list[NamedBody], motions_path: str, ensemble: Ensemble, e: float | str, **more: object
) -> dict:
    """What run.json records about the inputs of a fragility or agx50 run."""
    return {
        "bodies": [[b.name, b.block.R, b.block.gamma] for b in bodies],
        "motions": str(motions_path),
        "motions_sha256": ensemble.sha256,
        "location": ensemble.meta.get("location", "ground"),
        "n_motions": ensemble.n,
        "dt_s": ensemble.dt,
        "e": e,
        **more,
    }


_motions_option = click.option(
    "--motions",
    "motions_path",
    required=True,
    type=click.Path(dir_okay=False),
    help="Ground-motion ensemble, netCDF from 'rocking motions generate' (accelerations [m/s^2]).",
)
_floor_option = click.option(
    "--floor",
    type=int,
    default=None,
    help="Put the bodies on this floor of --frame (0 = ground); the floor motions are scaled to "
    "the same A_gx as the ground (paper Sec. 7).",
)
_out_option = click.option(
    "--out",
    required=True,
    type=click.Path(file_okay=False),
    help="Output folder (created); finished chunks are kept in it, so the same command resumes "
    "an interrupted run. A folder of another run is refused (see --overwrite).",
)


def _limit_states_option(effect: str):
    """The --limit-states option, its help ending with ``effect`` (what it does to the run)."""
    return click.option(
        "--limit-states",
        "limit_states_text",
        default=None,
        metavar="LIST",
        help="Limit states on the response instead of overturning alone, e.g. 'uplift, "
        "theta/alpha>=0.5, overturn' (uplift: the body rocks at all; theta/alpha>=X: its peak "
        "rotation reaches X times alpha; overturn; with --mu also slip>=X, residual_slip>=X, "
        f"lift>=X [m]). {effect}",
    )


_run_options = options(
    option_group("inputs", _Inputs, bodies_option, _motions_option, _floor_option, frame_option),
    run_folder_options(_out_option),
    compute_options(),
    physics_options(),
    quiet_option,
)


@dataclass(frozen=True)
class _Analysis:
    """--agx, --im, --method, --levels and --stripes of ``rocking fragility``, parsed: the IM,
    the method and its levels (None for msa and cloud) or stripes file."""

    measure: AnalysisIM
    method: str
    levels: np.ndarray | None
    stripes_path: str | None


def _analysis(
    agx_text: str | None,
    im_text: str,
    method: str,
    levels_text: str | None,
    stripes_path: str | None,
) -> _Analysis:
    # a range too long or too strong is refused at once: the IMs' module takes a second to load
    for option, text in (("--agx", agx_text), ("--levels", levels_text)):
        if text is not None:
            parse_range(text, option, unit="g" if option == "--agx" else "of the IM's unit")
    from ..montecarlo.fragility import AnalysisIM

    measure = AnalysisIM.parse(im_text)
    levels = _levels(measure.name, method, agx_text, levels_text, stripes_path, measure.unit)
    return _Analysis(measure, method, levels, stripes_path)


_analysis_options = option_group(
    "analysis",
    _analysis,
    click.option(
        "--agx",
        "agx_text",
        default=None,
        metavar="START:STOP:STEP",
        help="A_gx levels [g] (ensemble mean PGA) as start:stop:step, stop included "
        "[default: 0.1:1.5:0.05 when --im is agx and no --levels].",
    ),
    click.option(
        "--im",
        "im_text",
        default=AGX,
        show_default=True,
        help="Intensity measure of the levels: agx (the paper's ensemble mean PGA [g]) or pga [g], "
        "pgv [m/s], pgd [m], sa(T[,zeta]) [g], psv(T[,zeta]) [m/s], saavg(T1:T2[:N]) [g], "
        "arias [m/s], cav [m/s], pgv/pga [s].",
    ),
    click.option(
        "--method",
        type=click.Choice(["ida", "msa", "cloud"]),
        default="ida",
        show_default=True,
        help="ida: every motion scaled to each level of --im; msa: the stripes of --stripes; "
        "cloud: the motions as they are, each against its own IM.",
    ),
    click.option(
        "--levels",
        "levels_text",
        default=None,
        metavar="START:STOP:STEP",
        help="IDA levels of --im [its unit] as start:stop:step, stop included.",
    ),
    click.option(
        "--stripes",
        "stripes_path",
        default=None,
        type=click.Path(dir_okay=False),
        help="MSA stripes: CSV with columns level (of --im), motion (label or position in "
        "--motions), scale (factor of that motion in that stripe).",
    ),
)


# --------------------------------------------------------------------------- commands


@click.command("fragility")
@_run_options
@_analysis_options
@click.option(
    "--n-boot",
    type=count("bootstrap resamples", 0),
    default=N_BOOT,
    show_default=True,
    help="Bootstrap resamples of the motions for the intervals of median and beta (0: none).",
)
@click.option("--seed", type=SEED, default=0, show_default=True, help="Bootstrap seed.")
@_limit_states_option(
    "The tables gain a limit_state column, and each body a figure with one curve per limit state."
)
@click.option(
    "--im-efficiency",
    "compare_text",
    default=None,
    metavar="IM,IM,...",
    help="Also rank these IMs (e.g. 'pga,pgv,sa(1.0)') by the dispersion beta of the fragility "
    "fitted to the same IDA runs (--method ida only).",
)
@click.option(
    "--export",
    "exports",
    multiple=True,
    type=click.Choice(["pelicun", "openquake"], case_sensitive=False),
    help="Also write the fitted curves for a loss tool: pelicun (damage-model CSV, "
    "fragility_pelicun.csv) or openquake (NRML fragility model, fragility_openquake.xml); "
    "may be repeated. Needs an IM the tool knows (pga, pgv, sa(T), ...; not agx). With "
    "--limit-states: every limit state, by increasing severity (LS1, LS2, ...).",
)
def fragility_cmd(
    inputs: _Inputs,
    folder: OutFolder,
    compute: Compute,
    physics: Physics,
    analysis: _Analysis,
    n_boot: int,
    seed: int,
    limit_states_text: str | None,
    compare_text: str | None,
    exports: tuple[str, ...],
) -> None:
    """Overturning probability of each body against an intensity measure: A_gx as in the
    paper (Figs. 9-11, 13), or PGV, Sa(T), ... of recorded or generated motions by IDA,
    multiple-stripe or cloud analysis.

    Writes to --out: probabilities.csv (one row per body and level, with the count of
    overturned motions and the Wilson 95 % interval), probabilities.nc (the same, netCDF, with
    every motion's outcome), lognormal.csv (maximum-likelihood median and dispersion beta per
    body, with bootstrap 95 % intervals, the IM and its unit, and median_extrapolated: the
    median lies at or outside the levels tested), fragility.png, im_efficiency.csv with
    --im-efficiency, report.html and run.json (parameters and status).  With --limit-states:
    the probabilities and fits of every limit state (a limit_state column in
    probabilities.csv and lognormal.csv) and fragility-<body>.png per body.
    """
    from ..dynamics.limits import parse_limit_states
    from ..montecarlo.fragility import efficiency_measures

    states = None if limit_states_text is None else parse_limit_states(limit_states_text)
    measure, method, levels = analysis.measure, analysis.method, analysis.levels
    motions_path, stripes_path = inputs.motions_path, analysis.stripes_path
    compare = _im_list(compare_text) if compare_text is not None else None
    if compare is not None and method != "ida":
        raise click.UsageError("--im-efficiency needs --method ida")
    if compare is not None:
        efficiency_measures(compare)  # an IM it cannot compare is refused before any work
    exports = tuple(dict.fromkeys(f.lower() for f in exports))
    if exports:
        from ..montecarlo.export import check_exportable

        for fmt in exports:
            check_exportable(measure.name, fmt)
    bodies, ensemble, physics = _prepare(inputs, compute, physics)
    from ..core.reuse import reusing
    from ..montecarlo.fragility import fragility_analysis, im_efficiency
    from ..montecarlo.statistics import CrossingWarning, ExtrapolationWarning

    blocks = [b.block for b in bodies]
    e = cast("float | str", physics.e)  # one value, of --e
    backend, progress = cast("Backend", compute.backend), cast("Reporter", compute.progress)
    params = _run_params(
        bodies,
        motions_path,
        ensemble,
        e,
        im=measure.name,
        im_unit=measure.unit,
        method=method,
        levels=None if levels is None else levels.tolist(),
        stripes=stripes_path,
        n_boot=n_boot,
        seed=seed,
        im_efficiency=compare,
        limit_states=None if states is None else [ls.name for ls in states],
        **friction_params(physics),
    )
    if measure.name == AGX:
        params["agx_g"] = params["levels"]
    reads = {"--motions": motions_path, "--stripes": stripes_path}
    with (
        folder.claim("fragility", params, reads=reads) as run,
        progress,
    ):
        n_levels = (
            "stripes" if method == "msa" else f"{0 if levels is None else levels.size} levels"
        )
        progress.write(
            f"fragility ({method}, {measure.name}): {len(blocks)} bodies x "
            f"{n_levels if method != 'cloud' else 'as recorded'} x {ensemble.n} motions "
            f"({ensemble.meta.get('location', 'ground')})"
        )
        # reusing: the comparison of IMs, scaled by the same IM to the same levels, reads the
        # fragility's simulations instead of making them again
        with backend, reusing(), warnings.catch_warnings():
            # an extrapolated median and a refit of crossing limit states are said in one line
            # each below the table (_print_fits)
            warnings.simplefilter("ignore", ExtrapolationWarning)
            warnings.simplefilter("ignore", CrossingWarning)
            ds = fragility_analysis(
                blocks,
                ensemble,
                im=measure.name,
                method=method,
                levels=levels,
                stripes=stripes_path,
                physics=physics,
                backend=backend,
                out=run.chunks / "fragility",
                progress=progress,
                n_boot=n_boot,
                seed=seed,
                limit_states=states,
            )
            efficiency = (
                None
                if compare is None
                else im_efficiency(
                    blocks,
                    ensemble,
                    compare,
                    levels=levels,
                    scale_im=measure.name if measure.name != AGX else "pga",
                    names=[b.name for b in bodies],
                    physics=physics,
                    backend=backend,
                    out=run.chunks / "im-efficiency",
                    progress=progress,
                    seed=seed,
                )
            )
        ds = _names(ds, bodies)
        ds.attrs.update(_describe(ensemble), e=str(e), motions=str(motions_path))
        _write_fragility(run, ds, measure, efficiency, ensemble, e)
        _export(run, ds, exports)
    _print_fits(ds, measure)
    for name in run.outputs:
        click.echo(f"wrote {run.path / name}")


def _print_fits(ds: xr.Dataset, measure) -> None:
    """Per body: the fitted median with its bootstrap interval and β, aligned, units in the
    header; then one warning line per body whose median is an extrapolation, and one per body
    whose fits of nested limit states were refitted not to cross."""
    import numpy as np

    from ._options import print_table

    pct = f"{100 * ds.attrs['confidence']:g} %"
    states = list(ds["limit_state"].values) if "limit_state" in ds.dims else [None]
    rows = []
    for body in ds["body"].values:
        for state in states:
            b = ds.sel(body=body) if state is None else ds.sel(body=body, limit_state=state)
            first = (str(body),) if state is None else (str(body), str(state))
            median, beta = float(b["median"]), float(b["beta"])
            if not np.isfinite(median):
                done = "overturned" if state is None else "exceeded"
                why = f"never {done}" if int(b["count"].sum()) == 0 else f"{done} in every run"
                rows.append((*first, "-", "-", "-", f"({why}: nothing to fit)"))
                continue
            low, high = float(b["median_low"]), float(b["median_high"])
            interval = f"{low:.3g} to {high:.3g}" if np.isfinite(low) else "-"
            rows.append((*first, f"{median:.3g}", interval, f"{beta:.3g}", ""))
    head = ("body",) if states == [None] else ("body", "limit state")
    print_table((*head, f"median [{measure.unit}]", f"{pct} interval", "beta [-]", ""), rows)
    for body, median in _extrapolated(ds).items():
        warning = extrapolation_warning({body: median}, _tested(ds), measure.unit)
        click.echo(f"warning: {warning}", err=True)
    if "fit_constrained" in ds:
        from ..montecarlo.statistics import CROSSING_TOLERANCE

        for body in ds["body"].values:
            b = ds.sel(body=body)
            refitted = [str(s) for s in b["limit_state"].values[b["fit_constrained"].values]]
            if refitted:
                excess = float(b["crossing_excess"].max())
                click.echo(
                    f"warning: {body}: the fits of {', '.join(refitted)}, each alone, crossed "
                    f"inside the levels (a severer state the likelier by up to {excess:.2g} > "
                    f"{CROSSING_TOLERANCE:g}): refitted so that they do not (fit_constrained)",
                    err=True,
                )


def _tested(ds: xr.Dataset) -> tuple[float, float]:
    """Lowest and highest intensity tested [the IM's unit] (cloud: the motions' own IMs)."""
    tested = ds["im_value"] if "im_value" in ds else ds["level"]
    return float(tested.min()), float(tested.max())


def _extrapolated(ds: xr.Dataset) -> dict[str, float]:
    """The bodies (``"body (limit state)"`` with --limit-states) whose fitted median is an
    extrapolation (``median_extrapolated``), with it."""
    if "limit_state" not in ds.dims:
        flagged = ds["median_extrapolated"].values
        return {str(b): float(ds["median"].sel(body=b)) for b in ds["body"].values[flagged]}
    table = ds[["median", "median_extrapolated"]].to_dataframe().reset_index()
    table = table[table["median_extrapolated"]]
    return {
        f"{body} ({state})": float(median)
        for body, state, median in zip(table["body"], table["limit_state"], table["median"])
    }


def _levels(
    im: str,
    method: str,
    agx_text: str | None,
    levels_text: str | None,
    stripes: str | None,
    unit: str,
) -> np.ndarray | None:
    """The IDA levels of the options (None for MSA and cloud), checked before any work."""
    if agx_text is not None and im != AGX:
        raise click.UsageError(f"--agx gives A_gx levels; for --im {im} give --levels")
    if agx_text is not None and levels_text is not None:
        raise click.UsageError("give the levels once: --agx or --levels")
    if method != "ida":
        if agx_text is not None or levels_text is not None:
            raise click.UsageError(f"--method {method} takes no --levels or --agx")
        if (stripes is None) == (method == "msa"):
            raise click.UsageError("--stripes goes with --method msa, and it needs them")
        return None
    if stripes is not None:
        raise click.UsageError("--stripes goes with --method msa")
    if im == AGX:
        return parse_range(agx_text or levels_text or "0.1:1.5:0.05")
    if levels_text is None:
        raise click.UsageError(f"--method ida needs --levels of {im}")
    return parse_range(levels_text, "--levels", unit=unit)


def _im_list(text: str) -> list[str]:
    """IMs of a comma-separated list; commas inside parentheses belong to an IM (sa(1.0,0.02))."""
    items, depth, current = [], 0, ""
    for ch in text:
        depth += (ch == "(") - (ch == ")")
        if ch == "," and depth == 0:
            items.append(current.strip())
            current = ""
        else:
            current += ch
    items.append(current.strip())
    if not all(items):
        raise click.UsageError(f"--im-efficiency must list IMs separated by commas, got {text!r}")
    return items


def _write_fragility(run, ds: xr.Dataset, measure, efficiency, ensemble: Ensemble, e) -> None:
    """probabilities.csv/.nc, lognormal.csv, the figures, im_efficiency.csv and report.html of
    a fragility run: fragility.png with one curve per body, or, with --limit-states (a
    ``limit_state`` dimension), a ``limit_state`` column in both tables and a figure per body
    with one curve per limit state (fragility-<body>.png)."""
    import numpy as np

    from ..montecarlo.statistics import CROSSING_TOLERANCE, LognormalFit
    from ..plots.fragility import plot_fragility
    from ..report import Report, slug

    limit_states = "limit_state" in ds.dims
    agx = measure.name == AGX
    column = "agx" if agx else f"{measure.name} [{measure.unit}]"
    states = ["limit_state", "quantity", "threshold"] if limit_states else []
    counted = ["probability", "count", "n", "ci_low", "ci_high"]
    curves = ds[counted].rename(level="agx")
    tidy = curves.to_dataframe().reset_index()[["body", "R", "gamma", *states, "agx", *counted]]
    run.write_csv("probabilities.csv", tidy.rename(columns={"agx": column}))
    run.write_netcdf("probabilities.nc", ds.rename(level="agx") if agx else ds)
    flags = ["median_extrapolated", *(["fit_constrained", "crossing_excess"] * limit_states)]
    fits = ds[[*_FIT_COLUMNS, *flags]].to_dataframe().reset_index()
    fits["im"], fits["unit"] = measure.name, measure.unit
    fit_table = fits[["body", "R", "gamma", *states, "im", "unit", *_FIT_COLUMNS, *flags]]
    run.write_csv("lognormal.csv", fit_table)

    def fitted(names, medians, betas) -> dict[Hashable, LognormalFit]:
        return {
            str(name): LognormalFit(float(m), float(b), im=measure.name, unit=measure.unit)
            for name, m, b in zip(names, medians, betas)
            if np.isfinite(m)
        }

    where = ensemble.meta.get("location", "ground")
    method = ds.attrs["method"].upper()
    intervals = (
        "intervals: Wilson 95 % for the probabilities, bootstrap over motions "
        f"({ds.attrs['n_boot']} resamples, seed {ds.attrs['seed']}) for the median and β "
        "(NaN: none drawn, or nothing to fit)."
    )
    lo, hi = _tested(ds)
    if limit_states:
        report = Report(
            f"Limit states of {ds.sizes['body']} bodies against {measure.label}", run.path
        )
        names = ", ".join(str(s) for s in ds["limit_state"].values)
        report.text(
            f"{ensemble.n} motions ({where}) from `{ds.attrs['motions']}`, method {method}, "
            f"restitution e = {e}, limit states {names}. Lognormal fragility curves fitted by "
            "maximum likelihood (Baker 2015), each limit state alone; nested limit states whose "
            "curves crossed inside the levels (the severer the likelier by more than "
            f"{CROSSING_TOLERANCE:g}: crossing_excess) refitted together so that they do not "
            f"(fit_constrained); {intervals}"
        )
        for i, body in enumerate(ds["body"].values):
            one = curves.isel(body=i, drop=True).rename(limit_state="body")
            one = one.drop_vars(["quantity", "threshold"]).transpose("body", "agx")
            one.attrs = dict(ds.attrs)
            b = ds.isel(body=i)
            figure = plot_fragility(
                one,
                fits=fitted(b["limit_state"].values, b["median"].values, b["beta"].values),
                title=f"{body}: {ensemble.n} motions, {where}, e = {e}, {method}",
                xlabel=measure.label,
                ylabel="probability of exceeding the limit state [-]",
            )
            name = f"fragility-{slug(str(body))}.png"
            run.write_figure(name, figure)
            report.figure(figure, name[:-4], f"{body}: probability of each limit state.")
        what = "of each limit state "
    else:
        figure = plot_fragility(
            curves,
            fits=fitted(ds["body"].values, ds["median"].values, ds["beta"].values),
            title=f"{ensemble.n} motions, {where}, e = {e}, {method}",
            xlabel=measure.label,
        )
        run.write_figure("fragility.png", figure)
        report = Report(f"Fragility of {ds.sizes['body']} bodies against {measure.label}", run.path)
        report.text(
            f"{ensemble.n} motions ({where}) from `{ds.attrs['motions']}`, method {method}, "
            f"restitution e = {e}. Lognormal fragility fitted by maximum likelihood (Baker "
            f"2015); {intervals}"
        )
        report.figure(figure, "fragility", f"Overturning probability against {measure.label}.")
        what = ""
    warning = extrapolation_warning(_extrapolated(ds), (lo, hi), measure.unit)
    if warning:
        report.warning(warning)
    report.table(
        fit_page_table(fit_table, measure.unit),
        f"Fitted median and β {what}with their bootstrap 95 % intervals (intensities tested "
        f"{lo:g} to {hi:g} {measure.unit}).",
        "fit",
    )
    _finish_report(run, report, efficiency)


def _finish_report(run, report: Report, efficiency) -> None:
    """The IM ranking (im_efficiency.csv and its section, if any), then the report written and
    its files recorded in the run."""
    if efficiency is not None:
        run.write_csv("im_efficiency.csv", efficiency)
        efficiency_section(report, efficiency)
    report.write()
    for name in report.files:
        run.file(name)


def _export(run, ds: xr.Dataset, exports: tuple[str, ...]) -> None:
    """fragility_<format>.csv/.xml: the fitted curves for a loss tool (--export); a body left
    out is a warning, printed as every warning is (one ``warning:`` line)."""
    from ..montecarlo.export import EXPORT_FILES, export_fragility

    for fmt in exports:
        export_fragility(ds, run.file(EXPORT_FILES[fmt]), fmt)


_FIT_COLUMNS = ("median", "median_low", "median_high", "beta", "beta_low", "beta_high")


def extrapolation_warning(medians: dict[str, float], tested: tuple[float, float], unit: str) -> str:
    """The warning for the bodies whose fitted median (``medians``: by body, in ``unit``) lies
    at or outside the intensities tested (``tested``: lowest and highest, in ``unit``): an
    extrapolation of the fit, not a measurement (issue 48); "" if there is none."""
    if not medians:
        return ""
    listed = ", ".join(f"{b} ({m:.3g} {unit})" for b, m in medians.items())
    lo, hi = tested
    return (
        f"The fitted median of {listed} lies at or outside the intensities tested, {lo:.3g} "
        f"to {hi:.3g} {unit}: it is an extrapolation of the lognormal fit, not a measurement; "
        "run the fragility over a wider range of levels to measure it."
    )


def fit_page_table(fit_table: pd.DataFrame, unit: str) -> pd.DataFrame:
    """The fitted curves (lognormal.csv's columns; with their limit state where there are
    several) with the headers of a report: names and units (``unit``: the IM's)."""
    states = ["limit_state"] if "limit_state" in fit_table else []
    crossings = [c for c in ("fit_constrained", "crossing_excess") if c in fit_table]
    return fit_table[["body", *states, "R", "gamma", *_FIT_COLUMNS, *crossings]].rename(
        columns={
            "limit_state": "limit state",
            "R": "R [m]",
            "gamma": "γ [-]",
            "median": f"median [{unit}]",
            "median_low": f"median, 95 % low [{unit}]",
            "median_high": f"median, 95 % high [{unit}]",
            "beta": "β [-]",
            "beta_low": "β, 95 % low [-]",
            "beta_high": "β, 95 % high [-]",
            "fit_constrained": "refitted not to cross",
            "crossing_excess": "crossing of the own fits [-]",
        }
    )


def efficiency_section(report: Report, efficiency: pd.DataFrame) -> None:
    """Add the efficiency of intensity measures (:func:`rocking.im_efficiency`'s table) to a
    report: β per IM and body as a figure, the table folded below it."""
    import pandas as pd

    from ..plots.fragility import plot_im_efficiency

    report.heading("Efficiency of intensity measures")
    report.text(
        "Dispersion β of the lognormal fragility fitted to the same IDA runs, each run "
        "placed at its motion's value of each IM (smaller β: the IM predicts overturning "
        "better), with bootstrap 95 % intervals over motions; with several bodies, also of "
        "one fragility fitted to the runs of all bodies pooled (the last row)."
    )
    verdict = dimensionless_verdict(efficiency)
    if verdict:
        report.text(verdict)
    report.figure(
        plot_im_efficiency(efficiency),
        "im-efficiency",
        "β per body and IM, with its bootstrap 95 % interval: the IM furthest left is the "
        "most efficient for that body.",
    )
    label = efficiency["label"] if "label" in efficiency else efficiency["im"]
    page = pd.DataFrame(
        {
            "body": efficiency["body"],
            "IM [unit]": label,
            "median [the IM's unit]": efficiency["median"],
            "β [-]": efficiency["beta"],
            "β, 95 % low [-]": efficiency["beta_low"],
            "β, 95 % high [-]": efficiency["beta_high"],
            "note": efficiency["note"].fillna("") if "note" in efficiency else "",
        }
    )
    report.table(page, "IMs ranked by β per body.", "im", csv=efficiency, collapsed=True)


def dimensionless_verdict(efficiency: pd.DataFrame) -> str:
    """One sentence: whether the dimensionless IMs of an :func:`rocking.im_efficiency` table
    (PGA/(g tan α), PGV·p/(g tan α)) predict overturning better than PGA and PGV, by the β of
    the fragility of all bodies pooled; "" if the table has no such pair of IMs."""
    from ..montecarlo.fragility import POOLED
    from ..motions.intensity import parse_im

    ims = {str(im): parse_im(str(im)) for im in efficiency["im"]}
    name = {im: m.label.rsplit(" [", 1)[0] for im, m in ims.items()}  # without the unit
    pairs = [(im, m.dimensional) for im, m in ims.items() if m.dimensional in ims]
    if not pairs:
        return ""
    pooled = efficiency[efficiency["body"] == POOLED].set_index("im")["beta"]
    if pooled.empty:
        return (
            "With one body, "
            + " and ".join(f"{name[a]} is {name[str(b)]} times a constant" for a, b in pairs)
            + ", with the same β: only bodies of different sizes, pooled, compare them."
        )

    def compared(a: str, b: str) -> str:
        x, y = float(pooled[a]), float(pooled[b])
        if not (math.isfinite(x) and math.isfinite(y)):
            return f"{name[a]} cannot be compared with {name[b]} (nothing to fit)"
        same = abs(x - y) <= 1e-9 * y  # equal but for rounding (bodies of one slenderness)
        word = "as well as" if same else "better than" if x < y else "worse than"
        return f"{name[a]} predicts overturning {word} {name[b]} (β {x:.2f} against {y:.2f})"

    n = len(set(efficiency["body"])) - 1
    return f"Pooled over the {n} bodies, " + "; ".join(compared(a, str(b)) for a, b in pairs) + "."


@click.command("agx50")
@_run_options
@resolution_option
@agx_max_option
@band_option
@_limit_states_option(
    "The A_gx of 50 % probability of each: the tables gain a limit_state column, sv_agx.png a "
    "series of points per limit state."
)
def agx50_cmd(
    inputs: _Inputs,
    folder: OutFolder,
    compute: Compute,
    physics: Physics,
    resolution: float,
    agx_max: float,
    band_text: str,
    limit_states_text: str | None,
) -> None:
    """A_gx of 50 % overturning probability per body and Housner's energy balance (Section 8).

    Writes to --out: agx50.csv and agx50.nc (A_gx50 [g], required S_v of Eq. 11 and S_v1 [cm/s]
    in the CSV, their ratio), the paper's Tables 1-3 as R x gamma grids when the bodies form
    one (table1_sv_required_cm_s.csv, table2_sv1_cm_s.csv, table3_ratio.csv), sv_agx.png
    (required S_v against A_gx50 with a least-squares line, paper Figs. 15-16) and run.json.
    With --limit-states: the A_gx50 of every limit state (a limit_state column in agx50.csv,
    S_v1 and the ratio at each one's A_gx50; Tables 2-3 once per limit state, named
    table2_sv1_cm_s-<state>.csv, ...) and one series of points per limit state in sv_agx.png.
    """
    from ..dynamics.limits import parse_limit_states

    states = None if limit_states_text is None else parse_limit_states(limit_states_text)
    band = parse_band(band_text)
    bodies, ensemble, physics = _prepare(inputs, compute, physics)
    import numpy as np

    from ..assessment.energy import forms_grid, grid_table
    from ..montecarlo.probability import agx_50
    from ..motions.response import check_nyquist
    from ..plots.fragility import plot_sv_agx

    check_nyquist(band[1], ensemble.dt, f"--band {band_text}")  # before the search, not after

    blocks = [b.block for b in bodies]
    e = cast("float | str", physics.e)  # one value, of --e
    backend, progress = cast("Backend", compute.backend), cast("Reporter", compute.progress)
    motions_path = inputs.motions_path
    params = _run_params(
        bodies,
        motions_path,
        ensemble,
        e,
        resolution_g=resolution,
        agx_max_g=agx_max,
        band_hz=list(band),
        **({} if states is None else {"limit_states": [ls.name for ls in states]}),
        **friction_params(physics),
    )
    reads = {"--motions": motions_path}
    with (
        folder.claim("agx50", params, reads=reads) as run,
        progress,
    ):
        progress.write(
            f"agx50: {len(blocks)} bodies x {ensemble.n} motions "
            f"({ensemble.meta.get('location', 'ground')}), A_gx to {resolution:g} g"
        )
        with backend:
            a50 = agx_50(
                blocks,
                ensemble,
                resolution=resolution,
                agx_max=agx_max,
                physics=physics,
                backend=backend,
                out=run.chunks / "agx50",
                progress=progress,
                limit_states=states,
            )
        energy = _names(_energy(blocks, ensemble, a50, band), bodies)
        ds = _names(a50, bodies).merge(energy, compat="override")
        ds.attrs.update(
            {**energy.attrs, **_describe(ensemble)}, e=str(e), motions=str(motions_path)
        )
        run.write_netcdf("agx50.nc", ds)
        # a row per body (and limit state)
        table = ds[["agx50", "sv_required", "sv1", "ratio"]].to_dataframe().reset_index()
        table = table.rename(columns={"agx50": "agx50_g"})
        for column in ("sv_required", "sv1"):
            table[f"{column}_cm_s"] = 100.0 * table.pop(column)
        state = [] if states is None else ["limit_state", "quantity", "threshold"]
        columns = ["body", "R", "gamma", *state, "agx50_g", "sv_required_cm_s", "sv1_cm_s"]
        table = table[[*columns, "ratio"]]
        run.write_csv("agx50.csv", table, float_format="%.6g")
        if forms_grid(energy):
            for var, (name, fmt) in _TABLES.items():
                for suffix, one in _per_state(energy, var):
                    grid = grid_table(one, var)
                    # float_format would also cut R and gamma: write them as text (R to 0.1 mm)
                    grid = grid.rename(index=lambda r: f"{r:.4f}", columns=lambda g: f"{g:g}")
                    # the header says what the rows and the columns are
                    run.write_csv(
                        name.replace(".csv", f"{suffix}.csv"),
                        grid,
                        float_format=fmt,
                        index=True,
                        index_label="R [m] \\ gamma [-]",
                    )
        title = f"{ensemble.n} motions, {ensemble.meta.get('location', 'ground')}, e = {e}"
        run.write_figure("sv_agx.png", plot_sv_agx(energy, title=title))
        found = np.isfinite(energy["ratio"].values)
        if states is None:
            summary = f"for {int(found.sum())}" + (
                f"; mean S_v1/S_v {np.mean(energy['ratio'].values[found]):.3f}"
                if found.any()
                else ""
            )
        else:
            summary = "for " + ", ".join(
                f"{n} ({ls.name})" for n, ls in zip(found.sum(axis=0).tolist(), states)
            )
    click.echo(
        f"{len(blocks)} bodies, {ensemble.n} motions "
        f"({ensemble.meta.get('location', 'ground')}): A_gx50 found below {agx_max:g} g "
        f"{summary}"
    )
    for name in run.outputs:
        click.echo(f"wrote {run.path / name}")


def _energy(blocks, ensemble: Ensemble, a50: xr.Dataset, band) -> xr.Dataset:
    """Housner's energy balance (:func:`rocking.energy_balance`) at the A_gx50 of ``a50``: per
    body, or with a ``limit_state`` dimension at each limit state's A_gx50 (S_v1 and the ratio
    per limit state, the required S_v per body; one spectrum of the motions for all)."""
    import xarray as xr

    from ..assessment.energy import energy_balance

    if "limit_state" not in a50.dims:
        return energy_balance(blocks, ensemble, a50, band_hz=band)
    nb, ns = a50.sizes["body"], a50.sizes["limit_state"]
    per_state = a50["agx50"].transpose("limit_state", "body").values.ravel()
    flat = energy_balance(blocks * ns, ensemble, per_state, band_hz=band)
    parts = [flat.isel(body=slice(s * nb, (s + 1) * nb)) for s in range(ns)]
    energy = xr.concat(
        parts,
        dim="limit_state",
        data_vars=["agx50", "sv1", "ratio"],
        coords="minimal",
        compat="override",
    )
    states = a50[["limit_state", "quantity", "threshold"]].coords
    return energy.assign_coords(states).transpose("body", "limit_state")


def _per_state(energy: xr.Dataset, var: str):
    """(file name suffix, dataset) of each limit state's ``var`` (one, without suffix, when
    ``var`` has no ``limit_state`` dimension)."""
    from ..report import slug

    if "limit_state" not in energy[var].dims:
        yield "", energy
        return
    for state in energy["limit_state"].values:
        yield f"-{slug(str(state))}", energy.sel(limit_state=state)


@click.command("assess")
@bodies_option
@click.option(
    "--spectrum",
    "spectrum_path",
    required=True,
    type=click.Path(dir_okay=False),
    help="Spectrum at the bodies' location: a CSV table (frequency [Hz] or period "
    "[s]; PSA [g] or PSV [cm/s or m/s]), e.g. from 'rocking spectrum --csv' or "
    "'rocking frame spectra --csv', FILE:NAME choosing one record or floor of a "
    "file that holds several (FILE.csv:floor_1); a saved ensemble (.nc), whose "
    "mean PSV is used; or a design spectrum as for 'rocking screen' (e.g. "
    "asce7:SDS=1.0,SD1=0.6,TL=8).",
)
@click.option(
    "--band",
    "band_text",
    default=BAND_TEXT,
    show_default=True,
    metavar="LOW:HIGH",
    help="Frequency band [Hz] in which the available S_v is the largest PSV.",
)
@click.option(
    "--damping",
    type=click.FloatRange(0.0, 1.0, min_open=True, max_open=True),
    default=0.05,
    show_default=True,
    help="Damping ratio of the spectrum [-].",
)
@click.option(
    "--agx",
    type=G_LEVEL,
    default=None,
    help="Scale an ensemble (.nc) to this A_gx [g] (mean PGA) first.",
)
@click.option(
    "--floor",
    type=int,
    default=None,
    help="With an ensemble: use the motions of this floor of --frame (0 = ground).",
)
@frame_option
@click.option("--json", "as_json", is_flag=True, help="Print JSON instead of a table.")
def assess_cmd(
    bodies_spec: str,
    spectrum_path: str,
    band_text: str,
    damping: float,
    agx: float | None,
    floor: int | None,
    frame_name: str | None,
    as_json: bool,
) -> None:
    """Screen bodies with Housner's energy balance (paper Eq. 11 and Section 8 examples).

    A body is 'safe' when its required S_v [cm/s] exceeds the available S_v (the largest PSV
    of the spectrum in the band) and 'overturn>50%' otherwise. margin = required / available
    - 1 [-] (> 0: safe). Bodies are listed most at risk first.
    """
    band = parse_band(band_text)
    bodies = load_bodies(bodies_spec)
    frame, level = frame_and_floor(frame_name, floor)
    is_ensemble = Path(spectrum_path).suffix.lower() == ".nc"
    if not is_ensemble and (agx is not None or frame is not None):
        raise InputError("--agx, --floor and --frame apply to an ensemble (.nc) spectrum only")
    import numpy as np

    from ..assessment.energy import assess
    from ..motions.design import parse_spectrum
    from ..motions.ensemble import Ensemble

    with reporter():
        if is_ensemble:
            source: Ensemble | TargetSpectrum = _location(
                Ensemble.load(spectrum_path), frame, level
            )
        else:
            source = parse_spectrum(spectrum_path, damping=damping)
        ds = assess(
            [b.block for b in bodies],
            source,
            band_hz=band,
            damping=damping,
            agx=agx,
            names=[b.name for b in bodies],
        )
    order = np.argsort(ds["margin"].values, kind="stable")
    ds = ds.isel(body=order)
    available = 100.0 * float(ds["sv_available"].values[0])
    if as_json:
        rows = [
            {
                "name": str(n),
                "R_m": float(r),
                "gamma": float(g),
                "sv_required_cm_s": 100.0 * float(req),
                "sv_available_cm_s": available,
                "margin": float(m),
                "verdict": str(v),
            }
            for n, r, g, req, m, v in zip(
                ds["body"].values,
                ds["R"].values,
                ds["gamma"].values,
                ds["sv_required"].values,
                ds["margin"].values,
                ds["verdict"].values,
            )
        ]
        click.echo(
            json.dumps(
                {
                    "spectrum": str(spectrum_path),
                    "band_hz": list(band),
                    "damping": damping,
                    "sv_available_cm_s": available,
                    "bodies": rows,
                },
                indent=2,
            )
        )
        return
    click.echo(
        f"available S_v = {available:.2f} cm/s (max PSV, {100 * damping:g} % damping, "
        f"{band[0]:g}-{band[1]:g} Hz, {spectrum_path})"
    )
    width = max(4, *(len(str(n)) for n in ds["body"].values))
    click.echo(
        f"{'name':<{width}}  {'required S_v [cm/s]':>19}  {'available [cm/s]':>16}  "
        f"{'margin [-]':>10}  verdict"
    )
    for n, req, m, v in zip(
        ds["body"].values, ds["sv_required"].values, ds["margin"].values, ds["verdict"].values
    ):
        click.echo(f"{n!s:<{width}}  {100.0 * req:19.2f}  {available:16.2f}  {m:+10.3f}  {v}")


COMMANDS = [fragility_cmd, agx50_cmd, assess_cmd]
