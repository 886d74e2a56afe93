"""``rocking motions``: simulate ground-motion ensembles and inspect them."""

from __future__ import annotations

import math
from dataclasses import astuple, dataclass
from pathlib import Path
from typing import TYPE_CHECKING, Any

import click

from ..defaults import DT, ENVELOPE_NAMES, FIT_BAND
from ..errors import InputError
from ._options import (
    G_LEVEL,
    SEED,
    OutFolder,
    count,
    option_group,
    overwrite_option,
    quiet_option,
    reporter,
    run_folder_options,
    writable_file,
)
from .spectrum import calibration_option, checked_units, record_dt_option, units_option

if TYPE_CHECKING:
    import numpy as np

    from ..motions.ensemble import Ensemble
    from ..motions.targets import TargetSpectrum

_damping_option = click.option(
    "--damping",
    type=click.FloatRange(0.0, 1.0, min_open=True, max_open=True),
    default=0.05,
    show_default=True,
    help="Damping ratio of the target spectrum [-].",
)
_target_option = click.option(
    "--target",
    "target_path",
    type=click.Path(exists=True, dir_okay=False),
    help="Target spectrum CSV (frequency [Hz] or period [s], PSA [g]); default RG 1.60 at 1 g.",
)


@dataclass(frozen=True)
class _Suite:
    """--n, --duration, --dt and --envelope: the motions to simulate."""

    n: int
    duration: float
    dt: float
    envelope: str


#: --n, --duration, --dt and --envelope of a simulated ensemble (in this order in --help), as one
#: parameter ``suite``.
_ensemble_options = option_group(
    "suite",
    _Suite,
    click.option(
        "--n",
        "n",
        type=count("motions"),
        default=200,
        show_default=True,
        help="Number of motions.",
    ),
    click.option(
        "--duration",
        type=click.FloatRange(0.0, min_open=True),
        default=20.0,
        show_default=True,
        help="Total duration T [s].",
    ),
    click.option(
        "--dt",
        type=click.FloatRange(0.0, min_open=True),
        default=DT,
        show_default=True,
        help="Time step [s].",
    ),
    click.option(
        "--envelope",
        type=click.Choice(ENVELOPE_NAMES),
        default="compound",
        show_default=True,
        help="Intensity function (shape scaled with the duration).",
    ),
)


@click.group("motions")
def motions() -> None:
    """Spectrum-compatible simulated ground motions (paper Section 3)."""


@motions.command("generate")
@_ensemble_options
@click.option(
    "--seed",
    type=SEED,
    default=0,
    show_default=True,
    help="Root seed; member k is the same motion for any --n.",
)
@click.option(
    "--baseline/--no-baseline",
    default=True,
    show_default=True,
    help="Quadratic baseline correction.",
)
@click.option(
    "--iterations",
    type=count("iterations", 0),
    default=0,
    show_default=True,
    help="PSD iterations of the iterative correction (0: the paper's method alone).",
)
@click.option(
    "--peak-limit/--no-peak-limit",
    default=True,
    show_default=True,
    help="With --iterations: re-phase motions so their PGA stays near the ZPA.",
)
@_target_option
@_damping_option
@click.option(
    "--out",
    type=click.Path(dir_okay=False),
    required=True,
    help="Output netCDF file, e.g. ens.nc (written when the motions are complete).",
)
@quiet_option
def generate_cmd(
    suite: _Suite,
    seed: int,
    baseline: bool,
    iterations: int,
    peak_limit: bool,
    target_path: str | None,
    damping: float,
    out: str,
    quiet: bool,
) -> None:
    """Simulate an ensemble and save it as netCDF."""
    _ensemble_out(out)  # before the work, not after
    n, duration, dt, envelope = astuple(suite)
    from ..motions.synthesis import generate
    from ..motions.targets import TabulatedSpectrum, rg160

    target = rg160 if target_path is None else TabulatedSpectrum.from_csv(target_path, damping)
    progress = reporter(quiet)
    with progress, progress.stage(f"generating {n} motions", unit="motions") as stage:
        ens = generate(
            n,
            duration=duration,
            dt=dt,
            envelope=envelope,
            seed=seed,
            baseline=baseline,
            iterations=iterations,
            peak_limit=peak_limit,
            target=target,
            damping=damping,
        )
        stage.update(ens.n)
        ens.save(out)
    click.echo(
        f"wrote {out}: {ens.n} motions of {ens.duration:g} s at dt = {ens.dt:g} s "
        f"({envelope}, seed {seed}), A_gx = {ens.agx:.4g} g"
    )


def _ensemble_out(out: str, inputs: list[Path] | None = None) -> None:
    """Refuse, before any work, an ``--out`` that is not named .nc (an ensemble file is netCDF),
    cannot be written, or is one of the ``inputs`` (a command never overwrites what it reads)."""
    if Path(out).suffix.lower() != ".nc":
        raise InputError(
            f"--out {out}: an ensemble is written as a netCDF file, named .nc "
            f"(e.g. {Path(out).with_suffix('.nc').name})"
        )
    writable_file(out, "--out")
    target = Path(out).resolve()
    same = next((p for p in inputs or () if p.resolve() == target), None)
    if same is not None:
        raise InputError(
            f"--out {out} is also an input ({same}): it would be overwritten while it is read; "
            "choose another --out"
        )


def _with_and_without_baseline(ens: Ensemble) -> tuple[np.ndarray, np.ndarray]:
    """(uncorrected, corrected) accelerations [m/s²] of the members of the Ensemble ``ens``."""
    from ..motions.baseline import baseline_correct
    from ..motions.synthesis import regenerate

    if ens.simulated and ens.meta["baseline"]:
        return regenerate(ens, baseline=False).acc, ens.acc
    return ens.acc, baseline_correct(ens.acc, ens.dt)


@motions.command("show")
@click.argument("ensemble", type=click.Path(exists=True, dir_okay=False))
@click.option(
    "--agx",
    type=G_LEVEL,
    default=None,
    help="Scale the ensemble to this mean PGA A_gx [g] first.",
)
@click.option(
    "--samples",
    type=count("sample motions"),
    default=3,
    show_default=True,
    help="Members drawn with and without baseline correction.",
)
@click.option(
    "--target",
    "target_path",
    type=click.Path(exists=True, dir_okay=False),
    help="Target spectrum CSV (frequency [Hz] or period [s], PSA [g]); default the "
    "stored target of a simulated ensemble, else RG 1.60 at the ensemble's A_gx.",
)
@_damping_option
@click.option(
    "--out",
    type=click.Path(file_okay=False, writable=True),
    required=True,
    help="Output folder for the figures.",
)
@overwrite_option
def show(
    ensemble: str,
    agx: float | None,
    samples: int,
    target_path: str | None,
    damping: float,
    out: str,
    overwrite: bool,
) -> None:
    """Plot an ensemble and print how its mean PSA fits the target.

    Writes baseline.png (sample accelerations, velocities and displacements with and without
    baseline correction), spectrum.png (mean ± 1 std PSA against the target), for simulated
    ensembles envelope.png, and run.json.
    """
    import numpy as np

    from ..core.runs import RunFolder
    from ..motions.ensemble import Ensemble
    from ..motions.envelopes import make_envelope
    from ..motions.synthesis import spectral_fit
    from ..motions.targets import RG160, TabulatedSpectrum
    from ..plots.motions import plot_baseline_comparison, plot_envelopes
    from ..plots.spectra import plot_mean_vs_target

    ens = Ensemble.load(ensemble)
    if agx is not None:
        ens = ens.scaled(agx)
    target: TargetSpectrum
    if target_path is not None:
        target = TabulatedSpectrum.from_csv(target_path, damping=damping)
    else:
        target = ens.target_spectrum() if ens.simulated else RG160(damping, pga=ens.agx)
    params = {
        "ensemble": str(ensemble),
        "agx_g": agx,
        "samples": samples,
        "target": target.name,
        "damping": damping,
    }
    progress = reporter()
    with (
        RunFolder(
            out,
            command="motions show",
            params=params,
            overwrite=overwrite,
            reads={"ENSEMBLE": ensemble, "--target": target_path},
        ) as run,
        progress,
        progress.stage("response spectra and figures", unit="figures") as stage,
    ):
        fit = spectral_fit(ens, target)
        sample = ens.subset(range(min(samples, ens.n)))
        raw, corrected = _with_and_without_baseline(sample)
        figures = {
            "baseline.png": plot_baseline_comparison(
                ens.dt, raw, corrected, sample.labels, title="Baseline correction"
            ),
            "spectrum.png": plot_mean_vs_target(
                fit.freqs_hz,
                fit.psa_g,
                target,
                title=f"{ens.n} motions, A_gx = {ens.agx:.3g} g, {100 * fit.damping:g} % damping",
            ),
        }
        if ens.simulated:
            env = make_envelope(
                ens.meta["envelope"], ens.meta["duration"], **ens.meta["envelope_params"]
            )
            figures["envelope.png"] = plot_envelopes([env], title="Intensity function")
        for name, fig in figures.items():
            run.write_figure(name, fig)
            stage.update()
    worst = int(np.argmax(np.abs(fit.ratio - 1.0)))
    click.echo(
        f"{ensemble}: {ens.n} motions of {ens.duration:g} s at dt = {ens.dt:g} s, "
        f"{ens.meta.get('kind', 'motions')} at {ens.meta['location']}, "
        f"A_gx = {ens.agx:.4g} g"
    )
    click.echo(
        f"mean PSA against {target.name} over {fit.freqs_hz[0]:.3g}–{fit.freqs_hz[-1]:.3g} Hz "
        f"({fit.freqs_hz.size} frequencies): max deviation {100 * fit.max_deviation:.1f} % "
        f"(at {fit.freqs_hz[worst]:.3g} Hz), mean deviation "
        f"{100 * fit.mean_deviation:.1f} %"
    )
    click.echo(f"wrote {', '.join(str(run.path / name) for name in figures)}")


@motions.command("fit")
@_ensemble_options
@click.option("--seed", type=SEED, default=0, show_default=True, help="Root seed.")
@click.option(
    "--iterations",
    type=count("iterations"),
    default=2,
    show_default=True,
    help="PSD iterations of the iterative correction.",
)
@click.option(
    "--per-decade",
    type=count("frequencies per decade"),
    default=100,
    show_default=True,
    help="Frequencies per decade at which the fit is checked.",
)
@_target_option
@_damping_option
@run_folder_options(
    click.option(
        "--out",
        type=click.Path(file_okay=False, writable=True),
        required=True,
        help="Output folder for fit.png and fit.csv.",
    )
)
@quiet_option
def fit_cmd(
    suite: _Suite,
    seed: int,
    iterations: int,
    per_decade: int,
    target_path: str | None,
    damping: float,
    folder: OutFolder,
    quiet: bool,
) -> None:
    """Mean PSA against the target: the paper's method alone and with the iterative correction.

    Simulates the same members both ways and checks the ensemble-mean PSA over
    0.2–33 Hz at --per-decade log-spaced frequencies (ends included). Writes fit.png (mean PSA /
    target against frequency, ±10 % band), fit.csv and run.json, and prints the deviations.
    """
    import numpy as np
    import pandas as pd

    from ..motions.synthesis import generate, spectral_fit
    from ..motions.targets import RG160, TabulatedSpectrum
    from ..plots.motions import plot_fit_ratios

    n, duration, dt, envelope = astuple(suite)
    target = (
        RG160(damping) if target_path is None else TabulatedSpectrum.from_csv(target_path, damping)
    )
    settings: dict[str, Any] = dict(
        duration=duration, dt=dt, envelope=envelope, seed=seed, target=target
    )
    labels = {
        0: "paper's method alone",
        iterations: f"with iterative correction ({iterations} iterations)",
    }
    params = {
        "n": n,
        **settings,
        "target": target.name,
        "iterations": iterations,
        "per_decade": per_decade,
        "damping": damping,
    }
    progress = reporter(quiet)
    methods, fits = {}, {}
    with folder.claim("motions fit", params, reads={"--target": target_path}) as run, progress:
        with progress.stage(
            f"motions fit: {n} motions, two ways", total=2 * n, unit="motions"
        ) as stage:
            for its, label in labels.items():
                methods[label] = generate(n, iterations=its, **settings)
                fits[label] = spectral_fit(methods[label], target, per_decade=per_decade)
                stage.update(n)
        freqs = next(iter(fits.values())).freqs_hz
        fig = plot_fit_ratios(
            freqs,
            {k: f.ratio for k, f in fits.items()},
            band=FIT_BAND,
            title=f"{n} motions, {envelope} {duration:g} s, against {target.name}",
        )
        run.write_figure("fit.png", fig)
        paper, corrected = fits.values()
        table = pd.DataFrame(
            {
                "freq_hz": freqs,
                "target_psa_g": paper.target_g,
                "mean_psa_paper_g": paper.mean_g,
                "mean_psa_corrected_g": corrected.mean_g,
            }
        )
        run.write_csv("fit.csv", table, float_format="%.6g")
    for label, fit in fits.items():
        ens = methods[label]
        worst = int(np.argmax(np.abs(fit.ratio - 1.0)))
        click.echo(
            f"{label}: mean PSA / target {fit.ratio.min():.3f}–{fit.ratio.max():.3f} over "
            f"{freqs[0]:.3g}–{freqs[-1]:.3g} Hz ({freqs.size} frequencies), max "
            f"deviation {100 * fit.max_deviation:.1f} % at {freqs[worst]:.3g} Hz; "
            f"A_gx = {ens.agx:.3f} g (std {ens.pga.std():.3f} g)"
        )
    click.echo(f"wrote {run.path / 'fit.png'}, {run.path / 'fit.csv'}")


@motions.command("import")
@click.argument("records", nargs=-1, metavar="[RECORD]...")
@click.option(
    "--manifest",
    help="CSV with one row per motion: columns horizontal (file), vertical (file, optional), "
    "scale (factor > 0, optional) and dt (step [s] of one-column files, optional); paths "
    "relative to the manifest's folder. 'example': the shipped real records (El Centro 1940 "
    "NS; Ridgecrest 2019 M7.1 at three stations, both horizontals, each with its vertical).",
)
@click.option(
    "--dt",
    type=click.FloatRange(0.0, min_open=True),
    default=None,
    help="Common time step [s], at most 0.05 (Nyquist 10 Hz): every record is resampled to "
    "it (scipy.signal.resample_poly, Kaiser-window FIR anti-alias filter). Required when the "
    "records' steps differ.",
)
@units_option
@calibration_option
@record_dt_option
@click.option(
    "--horizontal-only",
    is_flag=True,
    help="Leave out every vertical component (of the manifest and of appended ensembles).",
)
@click.option(
    "--location",
    default="ground",
    show_default=True,
    help='Where the motions act: ground, "floor N" (e.g. "floor 3" for floor acceleration '
    'histories exported from a structural model) or "floor N of FRAME".',
)
@click.option(
    "--out",
    type=click.Path(dir_okay=False),
    required=True,
    help="Output netCDF file, e.g. suite.nc (the ensemble file --motions options take).",
)
def import_cmd(
    records: tuple[str, ...],
    manifest: str | None,
    dt: float | None,
    units: str | None,
    calibration: float | None,
    record_dt: float | None,
    horizontal_only: bool,
    location: str,
    out: str,
) -> None:
    """Import recorded motions as an ensemble file.

    RECORD: PEER .AT2 files, text or CSV files (time [s], acceleration; units from the header,
    e.g. "acc [cm/s2]", or --units), K-NET/KiK-net, ESM/ITACA and COSMOS V1/V2 files, SAC
    and miniSEED files (with ObsPy, rocking[formats]; --units required), folders of them (their
    record files and .nc files, sorted by name), existing ensemble files (.nc: their members
    are appended) or the word 'example' (El Centro 1940 NS). Formats are told by their headers.
    Members shorter than the longest are padded with zeros at the end. Each member keeps its
    file, event, station and component (from the file's header), original time step and
    units. A one-column file (no times) takes its step from
    --record-dt; several need one step each, in a --manifest's dt column.
    """
    if not records and manifest is None:
        raise InputError("name at least one RECORD or give --manifest")
    units = checked_units(units)
    from ..motions.ensemble import IMPORT_SUFFIXES, Ensemble, location_name
    from ..motions.records import RATIO_RTOL, record_paths

    location = location_name(location)
    inputs = record_paths(records, IMPORT_SUFFIXES) if records else []
    _ensemble_out(out, inputs + ([Path(manifest)] if manifest else []))

    ens = Ensemble.from_records(
        records,
        dt,
        units=units,
        calibration=calibration,
        manifest=manifest,
        location=location,
        record_dt=record_dt,
        horizontal_only=horizontal_only,
    )
    ens.save(out)
    m = ens.meta
    resampled = sum(not math.isclose(d, ens.dt, rel_tol=RATIO_RTOL) for d in m["record_dt"])
    padded = sum(
        (n - 1) * d < ens.duration - ens.dt / 2 for n, d in zip(m["record_npts"], m["record_dt"])
    )
    notes = [f"{ens.n} motions of {ens.duration:g} s at dt = {ens.dt:g} s at {m['location']}"]
    if ens.av is not None:
        notes.append(f"{sum(bool(v) for v in m['vertical_sources'])} with a vertical component")
    if resampled:
        notes.append(f"{resampled} resampled to dt (scipy.signal.resample_poly, anti-alias FIR)")
    if padded:
        notes.append(f"{padded} padded with zeros at the end")
    click.echo(f"wrote {out}: {'; '.join(notes)}; A_gx = {ens.agx:.4g} g")


COMMANDS = [motions]
