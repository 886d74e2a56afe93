"""``rocking frame``: shear frames and the response spectra of their floors (paper Section 7)."""

from __future__ import annotations

import time
from typing import TYPE_CHECKING

import click

from ..core.files import save_figure
from ..defaults import BAND_HZ, FRAME_PRESETS, G
from ..errors import InputError
from ._options import G_LEVEL, SEED, count, figure_file, quiet_option, reporter, writable_file

if TYPE_CHECKING:
    from ..structures.frames import ShearFrame

#: Frequencies of the floor spectra [Hz]: 0.04–30 Hz as paper Fig. 12, 100 per decade (289),
#: those above the Nyquist frequency of the motions left out.
_FREQS = (0.04, 30.0, 289)

_frame_arg = click.argument("preset", required=False, metavar="[PRESET]")
_frame_file_opt = click.option(
    "--frame-file",
    type=click.Path(exists=True, dir_okay=False),
    help="TOML file defining the frame (masses_kg + stiffnesses_N_per_m, or weights_kN_per_g + "
    "stiffness_kN_per_cm; optional damping, name) instead of a PRESET.",
)


def _frame(preset: str | None, frame_file: str | None) -> ShearFrame:
    """The ShearFrame of a PRESET argument or a --frame-file."""
    if (preset is None) == (frame_file is None):
        raise InputError(
            f"give either a PRESET ({', '.join(FRAME_PRESETS)}) or --frame-file, "
            "not both nor neither"
        )
    from ..structures.frames import ShearFrame

    if frame_file is not None:
        return ShearFrame.from_toml(frame_file)
    assert preset is not None  # one of the two, checked above
    return ShearFrame.preset(preset)


@click.group("frame")
def frame_group() -> None:
    """Shear frames (paper Section 7). Presets: paper-2.0, paper-1.5, paper-1.0, paper-0.5."""


@frame_group.command("show")
@_frame_arg
@_frame_file_opt
@click.option(
    "--plot",
    "plot_path",
    type=click.Path(dir_okay=False, writable=True),
    help="Draw the mode shapes into this image file.",
)
def show(preset: str | None, frame_file: str | None, plot_path: str | None) -> None:
    """Print a frame's floors, periods, participation factors and mode shapes."""
    from ..structures.frames import PRESETS

    figure_file(plot_path, "--plot")
    frame = _frame(preset, frame_file)
    stories = "story" if frame.n_stories == 1 else "stories"
    click.echo(
        f"{frame.name}: {frame.n_stories} {stories}, damping ratio {frame.damping:.3g} in "
        "every mode"
    )
    if frame.name in PRESETS:
        click.echo(PRESETS[frame.name])
    click.echo("\nfloor   mass [kg]   weight [kN/g]   story stiffness [N/m]   [kN/cm]")
    for i, (m, k) in enumerate(zip(frame.masses, frame.stiffnesses), start=1):
        click.echo(f"{i:5d} {m:11.5g} {m * G / 1e3:15.5g} {k:23.5g} {k / 1e5:9.5g}")
    click.echo("\nmode   period [s]   frequency [Hz]   omega [rad/s]   participation [kg^0.5]")
    for r, (t, f, w, gam) in enumerate(
        zip(frame.periods, frame.frequencies_hz, frame.omegas, frame.participation_factors), start=1
    ):
        click.echo(f"{r:4d} {t:12.5g} {f:16.5g} {w:15.5g} {gam:24.5g}")
    click.echo("\nmode shapes, mass-normalised [kg^-0.5] (rows: floors 1..n; columns: modes)")
    for i, row in enumerate(frame.mode_shapes, start=1):
        click.echo(f"{i:5d} " + " ".join(f"{x:11.4e}" for x in row))
    if plot_path:
        from ..plots.frames import plot_mode_shapes  # matplotlib only when a figure is asked for

        save_figure(plot_mode_shapes(frame), plot_path)
        click.echo(f"\nwrote {plot_path}")


@frame_group.command("spectra")
@_frame_arg
@_frame_file_opt
@click.option(
    "--agx",
    type=G_LEVEL,
    default=0.6,
    show_default=True,
    help="A_gx [g] to which the ground and every floor ensemble are scaled.",
)
@click.option(
    "--n",
    "n_motions",
    type=count("motions"),
    help="Number of motions to generate (RG 1.60, compound, 20 s)  [default: 200]",
)
@click.option("--seed", type=SEED, help="Seed of the generated motions  [default: 0]")
@click.option(
    "--motions",
    "motions_path",
    type=click.Path(exists=True, dir_okay=False),
    help="Use this saved ground-motion ensemble instead of generating motions.",
)
@click.option(
    "--damping",
    type=click.FloatRange(0.0, 1.0, max_open=True),
    default=0.05,
    show_default=True,
    help="Damping ratio of the response spectra [-] (the frame keeps its own).",
)
@click.option(
    "--out",
    "plot_path",
    type=click.Path(dir_okay=False, writable=True),
    help="Draw the mean PSV spectra into this image file.",
)
@click.option(
    "--csv",
    "csv_path",
    type=click.Path(dir_okay=False, writable=True),
    help="Write the mean PSV spectra [cm/s] to this CSV file.",
)
@quiet_option
def spectra(
    preset: str | None,
    frame_file: str | None,
    agx: float,
    n_motions: int | None,
    seed: int | None,
    motions_path: str | None,
    damping: float,
    plot_path: str | None,
    csv_path: str | None,
    quiet: bool,
) -> None:
    """Mean pseudo-velocity spectra of the ground and every floor, all scaled to the same A_gx
    (paper Fig. 12)."""
    frame = _frame(preset, frame_file)
    figure_file(plot_path, "--out")
    writable_file(csv_path, "--csv")
    if motions_path and (n_motions is not None or seed is not None):
        raise InputError("--n and --seed describe generated motions; leave them out with --motions")
    import numpy as np

    from ..core import portable
    from ..motions.ensemble import Ensemble
    from ..motions.response import response_spectrum
    from ..motions.synthesis import generate

    freqs_hz = portable.geomspace(*_FREQS)
    start = time.perf_counter()
    progress = reporter(quiet)
    with progress:
        if motions_path:
            ground = Ensemble.load(motions_path)
        else:
            n = 200 if n_motions is None else n_motions
            with progress.stage(f"generating {n} motions", unit="motions") as stage:
                ground = generate(
                    n, duration=20.0, envelope="compound", seed=0 if seed is None else seed
                )
                stage.update(n)
        freqs_hz = freqs_hz[freqs_hz <= 0.5 / ground.dt]  # a record's Nyquist frequency
        locations = frame.floor_ensembles(ground)
        labels = ["ground"] + [f"floor {i}" for i in range(1, frame.n_stories + 1)]
        rows = []
        with progress.stage("floor spectra", total=len(labels), unit="locations") as stage:
            for ens in locations.values():
                rows.append(
                    response_spectrum(ens.scaled(agx).acc, ens.dt, freqs_hz, damping).mean().psv
                )
                stage.update()
    psv = np.array(rows)
    elapsed = time.perf_counter() - start

    low = (freqs_hz >= BAND_HZ[0]) & (freqs_hz <= BAND_HZ[1])
    click.echo(
        f"{frame.name}: mean {damping:g}-damped PSV of {ground.n} motions, every location "
        f"scaled to A_gx = {agx:g} g ({elapsed:.1f} s)"
    )
    click.echo("location   max S_v in 0.04-0.6 Hz [cm/s]   peak S_v [cm/s]   at [Hz]")
    for label, row in zip(labels, psv):
        k = int(np.argmax(row))
        click.echo(
            f"{label:<10} {100 * row[low].max():30.2f} {100 * row[k]:17.2f} {freqs_hz[k]:9.3g}"
        )
    if csv_path:
        import pandas as pd

        from ..core.files import atomic_write

        table = pd.DataFrame(
            {
                "freq_hz": freqs_hz,
                **{
                    f"psv_{lab.replace(' ', '_')}_cm_s": 100.0 * row
                    for lab, row in zip(labels, psv)
                },
            }
        )
        atomic_write(csv_path, table.to_csv(index=False, float_format="%.6g"))
        click.echo(f"wrote {csv_path}")
    if plot_path:
        from ..plots.frames import plot_floor_spectra  # matplotlib only when a figure is asked for

        title = (
            f"{frame.name} (T1 = {frame.periods[0]:.3g} s): mean PSV, "
            f"ζ = {damping:g}, A_gx = {agx:g} g, {ground.n} motions"
        )
        save_figure(plot_floor_spectra(freqs_hz, psv, labels, title=title), plot_path)
        click.echo(f"wrote {plot_path}")


COMMANDS = [frame_group]
