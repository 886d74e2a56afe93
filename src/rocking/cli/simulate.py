"""``rocking simulate``: one block under one ground motion (paper Section 2), with a summary, JSON
and a plot of θ/α and the motion against time."""

from __future__ import annotations

import json
import math
from pathlib import Path
from typing import TYPE_CHECKING, Any

import click

from ..defaults import DT, G
from ..errors import InputError
from ._options import (
    G_LEVEL,
    OVERTURN_CHOICES,
    R_option,
    figure_file,
    gamma_option,
    physics_options,
    reporter,
)

if TYPE_CHECKING:
    import numpy as np

    from ..dynamics.body import Block
    from ..dynamics.physics import Physics
    from ..dynamics.simulate import RockingResponse

#: The word that selects the built-in simulated motion for ``--motion``.
SIMULATED = "simulated"
#: The built-in simulated motion: member 0 of a simulated ensemble (seed 0) compatible with
#: RG 1.60 at 1 g, 20 s long with the compound intensity function; sampled at the paper's step
#: :data:`rocking.defaults.DT` unless --dt is given.
SIMULATED_SPEC: dict[str, Any] = {"duration": 20.0, "envelope": "compound", "seed": 0}
_SIMULATED_NAME = "simulated (RG 1.60 at 1 g, 20 s compound envelope, seed 0)"


def load_motion(spec: str, dt: float | None) -> tuple[np.ndarray, float, str]:
    """Ground acceleration [m/s²], its time step [s] and a name, for ``--motion``
    FILE|example|simulated.

    ``example`` is the shipped El Centro 1940 NS record
    (:func:`rocking.motions.records.example_record_path`), ``simulated`` the built-in simulated
    motion (:data:`SIMULATED_SPEC`). ``dt`` [s] is the step of a one-column file (checked against
    the file's own step otherwise), or the step of the simulated motion (:data:`DT` if None).
    """
    from ..motions.records import EXAMPLE, read_record, record_path
    from ..motions.synthesis import generate

    if spec == SIMULATED and not Path(spec).exists():
        ens = generate(1, dt=DT if dt is None else dt, **SIMULATED_SPEC)
        return ens.acc[0], ens.dt, _SIMULATED_NAME
    path = record_path(spec)
    if not path.is_file():
        raise InputError(
            f"--motion {spec}: no such file (give a record file, '{EXAMPLE}' or '{SIMULATED}')"
        )
    rec = read_record(path, dt=dt)
    return rec.acc, rec.dt, str(path) if path == Path(spec) else f"{spec} ({path.name})"


def scale_to_peak(ag: np.ndarray, peak_g: float) -> tuple[np.ndarray, float]:
    """``ag`` [m/s²] (NumPy array) times one factor so that max |a| is ``peak_g`` [g]; returns
    both."""
    import numpy as np

    peak = float(np.abs(ag).max())
    if peak == 0.0:
        raise InputError("--scale-g: the motion is zero everywhere and cannot be scaled")
    factor = peak_g * G / peak
    return ag * factor, factor


def run_summary(
    block: Block, response: RockingResponse, ag: np.ndarray, dt: float, name: str, factor: float
) -> dict:
    """JSON-friendly description of the block, the motion ``ag`` [m/s²] and the response (SI
    units; g where the key says so)."""
    import numpy as np

    return {
        "block": {
            "R_m": block.R,
            "gamma": block.gamma,
            "H_m": block.H,
            "B_m": block.B,
            "alpha_rad": block.alpha,
            "p_rad_s": block.p,
            "uplift_acceleration_g": block.uplift_acceleration / G,
        },
        "motion": {
            "source": name,
            "n_samples": int(ag.size),
            "dt_s": dt,
            "duration_s": (ag.size - 1) * dt,
            "pga_g": float(np.abs(ag).max()) / G,
            "scale_factor": factor,
        },
        "response": {
            **response.summary(),
            "overturn_angle_rad": response.overturn_angle,
            **_modes(response, dt),
        },
    }


def _modes(response: RockingResponse, dt: float) -> dict:
    """With friction: the time [s] spent in each response mode (:data:`rocking.MODES`; the
    samples at which the body is in it, times dt, up to overturning) and the mode at the end
    (at overturning if it overturned); nothing without friction."""
    if response.mu is None:
        return {}
    import numpy as np

    from ..defaults import MODES

    standing = ~np.isnan(response.theta)
    counts = np.bincount(response.mode[standing], minlength=len(MODES))
    return {
        "time_in_mode_s": {m: float(n * dt) for m, n in zip(MODES, counts)},
        "final_mode": MODES[int(response.mode[-1])],
    }


def _text(s: dict) -> list[str]:
    b, m, r = s["block"], s["motion"], s["response"]
    if r["overturned"]:
        outcome = f"OVERTURNED at t = {r['t_overturn_s']:.4f} s"
    else:
        outcome = "did not overturn"
    scaled = f", scaled x{m['scale_factor']:.4g}" if m["scale_factor"] != 1.0 else ""
    return [
        f"block:    R = {b['R_m']:.4g} m, gamma = {b['gamma']:.4g} (H = {b['H_m']:.4g} m, "
        f"B = {b['B_m']:.4g} m), alpha = {b['alpha_rad']:.4f} rad "
        f"({math.degrees(b['alpha_rad']):.2f} deg), p = {b['p_rad_s']:.4g} rad/s, "
        f"uplift at g*tan(alpha) = {b['uplift_acceleration_g']:.4g} g",
        f"motion:   {m['source']}: {m['n_samples']} samples at dt = {m['dt_s']:.6g} s, "
        f"duration {m['duration_s']:.4g} s, PGA {m['pga_g']:.4g} g{scaled}",
        f"settings: e = {r['e']:.4g}, overturning at |theta| = {r['overturn_angle_rad']:.4f} rad",
        f"result:   {outcome}; {r['n_impacts']} impacts; max |theta|/alpha = "
        f"{r['max_abs_theta_over_alpha']:.4g} (max |theta| = {r['max_abs_theta_rad']:.4g} rad)",
        *_friction_text(r),
    ]


def _friction_text(r: dict) -> list[str]:
    """The lines of the response with friction: slip, lift and the modes (none without)."""
    if "mu" not in r:
        return []
    times = ", ".join(f"{m} {t:.4g} s" for m, t in r["time_in_mode_s"].items() if t > 0.0)
    return [
        f"friction: mu = {r['mu']:.4g}, mu_k = {r['mu_k']:.4g}; max |slip| = "
        f"{r['max_abs_slip_m']:.4g} m, residual slip = {r['residual_slip_m']:.4g} m, "
        f"max lift = {r['max_lift_m']:.4g} m",
        f"modes:    {times}; at the end: {r['final_mode']}",
    ]


@click.command("simulate")
@R_option
@gamma_option
@click.option(
    "--motion",
    required=True,
    metavar="FILE|example|simulated",
    help="Ground acceleration: a two-column text file (t [s], a [g]), a one-column file "
    "with --dt, a PEER .AT2 record; 'example' for the shipped record El Centro "
    "1940 NS (PGA 0.319 g, 0.02 s); or 'simulated' for a built-in simulated motion "
    "(RG 1.60 at 1 g, 20 s, compound envelope, seed 0).",
)
@click.option(
    "--scale-g",
    "scale_g",
    type=G_LEVEL,
    default=None,
    help="Scale the motion by one factor so that its peak acceleration (PGA) is this many g, "
    "at most 10 (default: the motion as it is).",
)
@physics_options(overturn_angle=True)
@click.option(
    "--dt",
    type=float,
    default=None,
    help="Time step [s]: needed for one-column files, checked against other files' "
    f"own step; for 'simulated' the step of the generated motion (default {DT:g}).",
)
@click.option(
    "--overturn-angle",
    "overturn",
    type=click.Choice(sorted(OVERTURN_CHOICES)),
    default="pi2",
    show_default=True,
    help="Overturned when the rotation theta reaches pi/2 (the paper) or alpha, either way.",
)
@click.option(
    "--plot",
    "plot_path",
    type=click.Path(dir_okay=False, writable=True),
    help="Save a figure of theta/alpha and the motion against time (e.g. out.png).",
)
@click.option("--json", "as_json", is_flag=True, help="Print the summary as JSON.")
def simulate_cmd(
    R: float,
    gamma: float,
    motion: str,
    scale_g: float | None,
    physics: Physics,
    dt: float | None,
    plot_path: str | None,
    as_json: bool,
) -> None:
    """Rock one block (R, gamma) under one ground motion; print what happened.

    Integrates the rocking equation with fixed-step Runge-Kutta at the motion's time step (the
    paper's scheme) and prints whether and when the block overturned, the number of impacts and
    the largest rotation theta as a fraction of alpha, with the block's and the motion's
    properties.  With --mu (friction): also the largest and the residual slip [m], the largest
    lift [m] of the base, and the time in each response mode (rest, slide, rock, slide-rock,
    flight) with the mode at the end.
    """
    from ..core.checks import positive
    from ..dynamics.body import Block
    from ..dynamics.simulate import simulate

    block = Block(R, gamma)
    dt = None if dt is None else positive("--dt", dt, "s")
    figure_file(plot_path, "--plot")
    with reporter():
        ag, step, name = load_motion(motion, dt)
        ag, factor = (ag, 1.0) if scale_g is None else scale_to_peak(ag, scale_g)
        response = simulate(block, ag, step, physics=physics)
    summary = run_summary(block, response, ag, step, name, factor)
    if as_json:
        click.echo(json.dumps(summary, indent=2))
    else:
        click.echo("\n".join(_text(summary)))
    if plot_path:
        from ..core.files import save_figure
        from ..plots.rocking import plot_response  # matplotlib only when a figure is asked for

        save_figure(plot_response(response, ag / G), plot_path)
        click.echo(f"wrote {plot_path}", err=as_json)


COMMANDS = [simulate_cmd]
