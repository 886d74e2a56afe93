"""``rocking pulse-spectrum``: the overturning spectrum of one block under an idealised pulse
(:func:`rocking.overturning_spectrum`; issue 46), as CSV tables, a report and run.json."""

from __future__ import annotations

from pathlib import Path
from typing import TYPE_CHECKING

import click

from ..defaults import PULSE_KAPPA_MAX, PULSE_N_SCAN, PULSE_SHAPES, G
from ._options import (
    R_option,
    count,
    friction_params,
    gamma_option,
    overwrite_option,
    parse_range,
    physics_options,
    quiet_option,
    reporter,
)

if TYPE_CHECKING:
    import pandas as pd
    import xarray as xr

    from ..dynamics.physics import Physics


@click.command("pulse-spectrum")
@R_option
@gamma_option
@click.option(
    "--shape",
    required=True,
    metavar="SHAPE",
    help=f"Pulse shape: {', '.join(PULSE_SHAPES)}; the last with its parameters as "
    "mavroeidis-papageorgiou:gamma=G,nu=N (nu in rad).",
)
@click.option(
    "--periods",
    required=True,
    metavar="START:STOP:STEP",
    help="Pulse periods T_p [s] (for rectangular, the duration).",
)
@physics_options()
@click.option(
    "--kappa-max",
    type=click.FloatRange(1.0, min_open=True),
    default=PULSE_KAPPA_MAX,
    show_default=True,
    help="Search amplitudes up to kappa = a_p/(g tan alpha) = this [-].",
)
@click.option(
    "--n-scan",
    type=count("levels", 2),
    default=PULSE_N_SCAN,
    show_default=True,
    help="Amplitudes scanned per period before the switches are narrowed: bands narrower "
    "than kappa-max^(1/(n-scan - 1)) - 1 (relative) may be missed.",
)
@click.option(
    "--out",
    required=True,
    type=click.Path(file_okay=False),
    help="Output folder: spectrum.csv, switches.csv, report.html, run.json.",
)
@overwrite_option
@quiet_option
def pulse_spectrum_cmd(
    R: float,
    gamma: float,
    shape: str,
    periods: str,
    physics: Physics,
    kappa_max: float,
    n_scan: int,
    out: str,
    overwrite: bool,
    quiet: bool,
) -> None:
    """Overturning spectrum of one block (R, gamma) under a pulse: the smallest amplitude that
    overturns it at each pulse period, and every amplitude above it, up to --kappa-max, at
    which the outcome switches (the safe bands), with the mode of each overturning branch.

    Writes spectrum.csv (one row per period), switches.csv (one row per switch) and a report
    with kappa against Omega = omega_p/p (omega_p = 2 pi/T_p) and a_p [g] against T_p [s].
    """
    from ..core.runs import RunFolder
    from ..dynamics.body import Block
    from ..montecarlo.pulse_spectrum import overturning_spectrum
    from ..motions.pulses import parse_pulse

    block = Block(R, gamma)
    parse_pulse(shape)  # refused before the folder is claimed
    values = parse_range(periods, "--periods", "s")
    e = physics.e
    params = {
        "R_m": R,
        "gamma": gamma,
        "shape": shape,
        "periods_s": periods,
        "e": e,
        "kappa_max": kappa_max,
        "n_scan": n_scan,
        **friction_params(physics),
    }
    with (
        RunFolder(out, command="pulse-spectrum", params=params, overwrite=overwrite) as run,
        reporter(quiet),
    ):
        ds = overturning_spectrum(
            block, shape, values, physics=physics, kappa_max=kappa_max, n_scan=n_scan
        )
        spectrum, switches = tables(ds)
        run.write_csv("spectrum.csv", spectrum)
        run.write_csv("switches.csv", switches)
        run.update(
            summary={
                "periods": int(ds.sizes["period"]),
                "overturned_below_limit": int(ds["kappa"].notnull().sum()),
                "kappa_min": float(ds["kappa"].min()) if ds["kappa"].notnull().any() else None,
                "settings": dict(ds.attrs),
            }
        )
        _report(run, ds, switches)
    for name in run.outputs:
        click.echo(f"wrote {run.path / name}")


def tables(ds: xr.Dataset) -> tuple[pd.DataFrame, pd.DataFrame]:
    """The spectrum per period and the switches per (period, switch) as tables (SI units and g)."""
    import pandas as pd

    first = ds.isel(switch=0)
    spectrum = pd.DataFrame(
        {
            "period_s": ds["period"].values,
            "omega_ratio": ds["omega_ratio"].values,
            "kappa": ds["kappa"].values,
            "overturning_amplitude_m_s2": ds["overturning_amplitude"].values,
            "overturning_amplitude_g": ds["overturning_amplitude"].values / G,
            "impacts_before_overturning": first["impacts_before_overturning"].values,
            "switches": ds["switch_kappa"].notnull().sum("switch").values,
        }
    )
    names = {
        "period": "period_s",
        "switch_kappa": "kappa",
        "overturns": "overturns_above",
        "overturning_time": "overturning_time_s",
    }
    frame = ds[[*names, "switch_amplitude", "impacts_before_overturning"]].to_dataframe()
    frame = frame.reset_index().rename(columns=names)
    frame = frame[frame["kappa"].notna()]
    frame["amplitude_g"] = frame.pop("switch_amplitude") / G
    columns = ["period_s", "omega_ratio", "switch", "kappa", "amplitude_g", "overturns_above"]
    switches = frame[[*columns, "impacts_before_overturning", "overturning_time_s"]]
    return spectrum, switches


def _report(run, ds: xr.Dataset, switches: pd.DataFrame) -> None:
    """report.html: the spectrum in dimensionless and physical units, and the switches."""
    from ..plots.pulses import plot_overturning_spectrum
    from ..report import Report

    a = ds.attrs
    report = Report(f"Overturning spectrum: {a['shape']} pulse", Path(run.path))
    report.text(
        f"Block R = {a['R']:.4g} m, γ = {a['gamma']:.4g} (α = {a['alpha']:.4f} rad, "
        f"p = {a['p']:.4g} rad/s), e = {a['e']:.4g}. For each pulse period T_p, "
        f"{a['n_scan']} amplitudes from κ = 1 (uplift) to κ = {a['kappa_max']:g} were "
        f"integrated (a ratio {a['scan_ratio']:.5f} apart: an overturning or safe band "
        "narrower than that may be missed), then every change of the outcome was narrowed to "
        f"{a['rtol']:g} (relative); dt = T_p/{a['samples_per_period']} or finer (p·dt ≤ 0.05), "
        "followed by "
        f"{a['tail']:.3g} s of free rocking. κ = a_p/(g·tan α), Ω = ω_p/p, ω_p = 2π/T_p. "
        "The mode of an overturning branch is the number of impacts before the block "
        "overturns at its smallest amplitude (0: without impact)."
    )
    report.figure(
        plot_overturning_spectrum(ds),
        "kappa-omega",
        "Smallest overturning κ against Ω, overturning amplitudes (red) and safe bands above "
        "the minimum (green), uplift line κ = 1.",
    )
    report.figure(
        plot_overturning_spectrum(ds, physical=True),
        "amplitude-period",
        "The same in physical units for this block: pulse amplitude a_p [g] against T_p [s].",
    )
    page = switches.rename(
        columns={
            "period_s": "T_p [s]",
            "omega_ratio": "Ω [-]",
            "switch": "switch [-]",
            "kappa": "κ [-]",
            "amplitude_g": "a_p [g]",
            "overturns_above": "overturns above",
            "impacts_before_overturning": "impacts before overturning [-]",
            "overturning_time_s": "time of overturning [s]",
        }
    ).reset_index(drop=True)
    impacts = page["impacts before overturning [-]"]  # -1 in the CSV: a safe branch
    page["impacts before overturning [-]"] = impacts.astype(object).where(impacts >= 0, "-")
    report.table(
        page,
        "Every amplitude at which the outcome switches, with the outcome above it and the mode "
        "(impacts before overturning) of overturning branches.",
        "switches",
        csv=switches,
    )
    report.write()
    for name in report.files:
        run.file(name)


COMMANDS = [pulse_spectrum_cmd]
