"""``rocking risk``: the mean annual rate of overturning of the bodies of a fragility run at a site
(the risk integral of :func:`rocking.annual_rate`), with the report that brings the fragility,
the efficiency of intensity measures and the rates together."""

from __future__ import annotations

import json
import math
from pathlib import Path
from typing import TYPE_CHECKING

import click

from ..defaults import AGX
from ..errors import InputError
from ._options import overwrite_option, print_table, quiet_option, reporter

if TYPE_CHECKING:
    import pandas as pd

    from ..assessment.risk import HazardCurve
    from ..montecarlo.statistics import LognormalFit


def _fragility_run(folder: Path) -> tuple[dict, list[tuple[str, LognormalFit | None]]]:
    """The record (run.json: parameters and status) and the fitted curves (lognormal.csv: each
    body's name and curve, None where nothing was fitted) of a completed ``rocking fragility``
    run."""
    run_json = folder / "run.json"
    try:
        run = json.loads(run_json.read_text())
    except FileNotFoundError:
        raise InputError(
            f"--fragility {folder}: no run.json (not a rocking fragility folder)"
        ) from None
    except (OSError, ValueError) as exc:
        raise InputError(f"--fragility {run_json}: cannot read it ({exc})") from None
    if run.get("command") != "fragility":
        raise InputError(f"--fragility {folder}: a folder of 'rocking {run.get('command')}'")
    if run.get("status") != "completed":
        raise InputError(
            f"--fragility {folder}: the run is {run.get('status')!r}, not completed; run the "
            "same fragility command again to finish it"
        )
    if run.get("im", AGX) == AGX:
        raise InputError(
            f"--fragility {folder}: its curves are against A_gx, the mean PGA of an ensemble, "
            "which no site hazard curve gives; run fragility with --im pga (or the IM of your "
            "hazard curve)"
        )
    return run, _read_fits(folder / "lognormal.csv", run["im"])


#: Columns of lognormal.csv that ``risk`` needs.
_FIT_NEEDS = ("body", "median", "beta")


def _read_fits(path: Path, im: str) -> list[tuple[str, LognormalFit | None]]:
    """Each body's name and fitted curve (None where nothing was fitted: median and β empty)
    from the lognormal.csv of a fragility run against ``im`` (its run.json's), checked: every
    error names the file and the row."""
    import pandas as pd

    from ..montecarlo.statistics import LognormalFit
    from ..motions.intensity import parse_im

    try:
        table = pd.read_csv(path, dtype=str, keep_default_na=False)
    except FileNotFoundError:
        raise InputError(f"--fragility: {path} is missing (the fitted curves of the run)") from None
    except (OSError, ValueError, pd.errors.ParserError) as exc:  # binary, empty, ragged
        text = " ".join(str(exc).split())
        raise InputError(f"--fragility: cannot read {path} ({text})") from None
    table.columns = [str(c).strip() for c in table.columns]
    missing = [c for c in _FIT_NEEDS if c not in table.columns]
    if missing:
        raise InputError(
            f"--fragility: {path} has no column {', '.join(missing)} (a fragility run's "
            f"lognormal.csv has {', '.join(_FIT_NEEDS)} and more), got "
            f"{', '.join(map(repr, table.columns[:6]))}"
        )
    if table.empty:
        raise InputError(f"--fragility: {path} lists no bodies")
    fits: list[tuple[str, LognormalFit | None]] = []
    for row, cells in enumerate(table.to_dict("records"), start=1):
        where = f"--fragility: {path}: row {row} (body {cells['body']!r})"
        values = {}
        for name in ("median", "beta"):
            try:
                values[name] = float(cells[name] or "nan")
            except ValueError:
                raise InputError(f"{where}: {name} {cells[name]!r} is not a number") from None
        if all(math.isnan(v) for v in values.values()):  # nothing to fit for this body
            fits.append((cells["body"], None))
            continue
        try:
            # runs before the unit column: im holds the IM with its unit, e.g. 'pgv [m/s]'
            fit = LognormalFit(
                values["median"],
                values["beta"],
                im=cells.get("im") or im,
                unit=cells.get("unit") or None,
            )
        except InputError as exc:
            raise InputError(f"{where}: {exc}") from None
        if fit.im != parse_im(im).name:
            raise InputError(f"{where}: the curve is of {fit.im}, the run (run.json) of {im}")
        fits.append((cells["body"], fit))
    return fits


@click.command("risk")
@click.option(
    "--fragility",
    "fragility_dir",
    required=True,
    type=click.Path(file_okay=False, exists=True),
    help="Folder of a completed 'rocking fragility --im IM' run.",
)
@click.option(
    "--hazard",
    "hazard_text",
    required=True,
    metavar="FILE",
    help="Hazard curve: a CSV with the header 'IM [unit],annual_rate', one row per intensity, "
    "rates decreasing; an OpenQuake-engine hazard-curve CSV (PoE in the investigation time, "
    "one row per site: see --site); or a USGS NSHM hazard JSON (its curve of the fragility's "
    "IM). Its IM must be the fragility's. 'example': the shipped illustrative PGV curve (not a "
    "real site).",
)
@click.option(
    "--site",
    type=click.IntRange(0),
    default=None,
    help="OpenQuake hazard curves: the site's row, 0 for the first (needed when the file has "
    "several sites).",
)
@click.option(
    "--years",
    type=click.FloatRange(0.0, min_open=True),
    default=50.0,
    show_default=True,
    help="Exposure time [yr] of the probability of at least one overturning (Poisson).",
)
@click.option(
    "--out",
    required=True,
    type=click.Path(file_okay=False),
    help="Output folder: risk.csv, disaggregation.png, report.html, run.json; not the "
    "--fragility folder.",
)
@overwrite_option
@quiet_option
def risk_cmd(
    fragility_dir: str,
    hazard_text: str,
    site: int | None,
    years: float,
    out: str,
    overwrite: bool,
    quiet: bool,
) -> None:
    """Mean annual rate of overturning of each body of a fragility run, and the probability
    of at least one overturning in --years, from a site hazard curve.

    The rate integrates the fitted lognormal fragility against the hazard curve,
    log-log interpolated between its points. Above the last point the curve is extrapolated
    (the table shows that part and its bounds). Below the first point nothing is added (the
    table shows an estimate of what is left out).
    """
    import numpy as np
    import pandas as pd

    from ..assessment.risk import HazardCurve, annual_rate, check_hazard_im, hazard_path
    from ..core.runs import RunFolder

    folder = Path(fragility_dir)
    params, fits = _fragility_run(folder)
    path = hazard_path(hazard_text)
    hazard = HazardCurve.from_csv(path, site=site, im=params["im"])
    im = check_hazard_im(hazard, params["im"])
    if hazard.origin:
        click.echo(f"hazard: {hazard.origin}")
    progress = reporter(quiet)
    run_params = {"fragility": str(folder), "hazard": str(path), "years": years, "im": im.name}
    if hazard.origin:
        run_params.update(site=site, hazard_origin=hazard.origin)
    reads = {"--fragility": folder, "--hazard": path}
    with (
        RunFolder(out, command="risk", params=run_params, overwrite=overwrite, reads=reads) as run,
        progress,
    ):
        rows = []
        for body, fit in fits:
            if fit is None:
                rows.append({"body": body, "annual_rate": np.nan})
                continue
            result = annual_rate(fit, hazard)
            rows.append(
                {
                    "body": body,
                    "median": fit.median,
                    "beta": fit.beta,
                    "annual_rate": result.annual_rate,
                    "return_period_yr": result.return_period,
                    f"p_in_{years:g}_yr": float(result.probability_in(years)),
                    "upper_tail": result.upper_tail,
                    "upper_tail_bound": result.upper_tail_bounds[1],
                    "lower_tail_left_out": result.lower_tail,
                    "p_at_first_point": result.p_first,
                    "p_at_last_point": result.p_last,
                    "_result": result,
                }
            )
        table = pd.DataFrame(rows)
        results = table.pop("_result") if "_result" in table else pd.Series(dtype=object)
        run.write_csv("risk.csv", table)
        figure = _plot_disaggregation(results.dropna().tolist(), table, hazard)
        run.write_figure("disaggregation.png", figure)
        _report(run, folder, params, table, figure, hazard, years)
    _print_rates(table, im.unit, years)
    for name in run.outputs:
        click.echo(f"wrote {run.path / name}")


def _print_rates(table: pd.DataFrame, unit: str, years: float) -> None:
    """Per body: median, β, annual rate, return period and probability in ``years``, aligned,
    units in the header (a body without a fitted curve: '-')."""
    head = (
        f"median [{unit}]",
        "beta [-]",
        "annual rate [1/yr]",
        "return period [yr]",
        f"P in {years:g} yr [-]",
    )
    rows = []
    for cells in table.to_dict("records"):
        rate = cells["annual_rate"]
        if not math.isfinite(rate):
            rows.append((str(cells["body"]), *(["-"] * len(head))))
            continue
        rows.append(
            (
                str(cells["body"]),
                f"{cells['median']:.3g}",
                f"{cells['beta']:.3g}",
                f"{rate:.3g}",
                f"{cells['return_period_yr']:.3g}",
                f"{cells[f'p_in_{years:g}_yr']:.3g}",
            )
        )
    print_table(("body", *head), rows)


def _plot_disaggregation(results: list, table: pd.DataFrame, hazard: HazardCurve):
    """Hazard curve and, per body, the density of the overturning rate over ln IM."""
    from matplotlib.figure import Figure

    from ..plots import legend_beside

    fig = Figure(figsize=(11.0, 4.0), layout="constrained")
    left, right = fig.subplots(1, 2)
    left.loglog(hazard.values, hazard.rates, "o-", color="k", ms=3)
    left.set_xlabel(hazard.im.label)
    left.set_ylabel("annual rate of exceedance [1/yr]")
    left.grid(True, which="both", alpha=0.3)
    names = table.loc[table["annual_rate"].notna(), "body"].tolist()
    for name, result in zip(names, results):
        x, density = result.disaggregation()
        right.semilogx(x, x * density, label=f"{name}: {result.annual_rate:.2e}/yr")
    right.set_xlabel(hazard.im.label)
    right.set_ylabel("x·dλ_f/dx [1/yr per unit of ln x]")
    right.grid(True, which="both", alpha=0.3)
    if names:
        legend_beside(right, fontsize="x-small")
    return fig


def _report(run, folder: Path, params: dict, table, figure, hazard, years: float) -> None:
    """report.html: the result per body in words, the fragility, the efficiency of IMs (if the
    run ranked them) and the annual rates (``table``: risk.csv's rows)."""
    import pandas as pd
    from matplotlib.image import imread

    from ..assessment.risk import illustrative_note
    from ..report import Report
    from .fragility import efficiency_section, extrapolation_warning

    report = Report(f"Annual rate of overturning ({hazard.im.label})", run.path)
    report.text(
        f"At this site, with the hazard curve `{Path(hazard.source).name}` and the fragility "
        f"of `{folder}`:\n\n" + "\n".join(_sentence(row, years) for _, row in table.iterrows())
    )
    if hazard.origin:
        report.text(f"Hazard file read as: {hazard.origin}.")
    note = illustrative_note(hazard.source)
    if note:
        report.warning(note)
    tested = params.get("levels")  # the IDA's levels (msa, cloud: its report warns)
    if isinstance(tested, list) and tested:
        lo, hi = min(tested), max(tested)
        medians = dict(zip(table["body"].astype(str), table.get("median", [])))
        outside = {b: m for b, m in medians.items() if math.isfinite(m) and not lo < m < hi}
        warning = extrapolation_warning(outside, (lo, hi), hazard.im.unit)
        if warning:
            report.warning(warning)
    report.text(
        f"Fragility from `{folder}` ({params.get('method', 'ida').upper()} on "
        f"{params.get('n_motions')} motions from `{params.get('motions')}`), hazard from "
        f"`{hazard.source}`. Rate λ_f = ∫ P_f(x)·|dλ/dx| dx with the hazard interpolated "
        "log-log; above the last tabulated intensity the last segment is extrapolated (its "
        "share and the model-free bound are in the second table); below the first point "
        "nothing is added (the estimate left out is in the second table). Probability in "
        f"{years:g} years: 1 − exp(−λ_f·years) (Poisson)."
    )
    fragility_png = folder / "fragility.png"
    if fragility_png.exists():
        from matplotlib.figure import Figure

        image = imread(fragility_png)
        height, width = image.shape[:2]
        fig = Figure(figsize=(width / 100, height / 100), layout="constrained")
        ax = fig.add_subplot()
        ax.imshow(image)
        ax.set_axis_off()
        report.figure(fig, "fragility", "Fragility curves of the fragility run.")
    efficiency = folder / "im_efficiency.csv"
    if efficiency.exists():
        efficiency_section(report, pd.read_csv(efficiency))
    report.heading("Annual rate of overturning")
    report.figure(
        figure, "disaggregation", "Hazard curve (left) and contributions to the rate (right)."
    )
    unit = hazard.im.unit
    rates = pd.DataFrame(
        {
            "body": table["body"],
            f"median [{unit}]": table.get("median"),
            "β [-]": table.get("beta"),
            "annual rate [1/yr]": table["annual_rate"],
            "return period [yr]": table.get("return_period_yr"),
            f"P in {years:g} years [-]": table.get(f"p_in_{years:g}_yr"),
        }
    )
    report.table(rates, "Rate per body.", "risk", floatfmt=".3g", csv=table)
    tails = pd.DataFrame(
        {
            "body": table["body"],
            "above the last point, extrapolated [1/yr]": table.get("upper_tail"),
            "its model-free bound [1/yr]": table.get("upper_tail_bound"),
            "below the first point, left out [1/yr]": table.get("lower_tail_left_out"),
            "P_f at the first point [-]": table.get("p_at_first_point"),
            "P_f at the last point [-]": table.get("p_at_last_point"),
        }
    )
    report.table(
        tails,
        "The tails of the integral: what the rate holds above the hazard curve's last point, "
        "and what it leaves out below its first point (parts of the rate above, in 1/yr; "
        "values like 1e-100 are zero for any purpose).",
        "tails",
        floatfmt=".2g",
    )
    report.write()
    for name in report.files:
        run.file(name)


def _sentence(row, years: float) -> str:
    """One line of Markdown: a body's result in words (``row``: a row of risk.csv)."""

    rate = row["annual_rate"]
    if not math.isfinite(rate):
        return f"- **{row['body']}**: no rate (its fragility has no finite median or β)."
    if rate <= 0.0:
        return f"- **{row['body']}**: never overturns at this site (annual rate 0)."
    p = row[f"p_in_{years:g}_yr"]
    return (
        f"- **{row['body']}** overturns on average once in {float(f'{1.0 / rate:.2g}'):,.0f} "
        f"years (annual "
        f"rate {rate:.2g}/yr): a probability of {100 * p:.2g} % of overturning at least once "
        f"in {years:g} years."
    )


COMMANDS = [risk_cmd]
