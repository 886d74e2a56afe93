"""``rocking fragility``, ``rocking agx50`` and ``rocking assess``: overturning probability of
bodies under an ensemble (paper Sections 6–8) and Housner's energy-balance screening (Eq. 11).

Every input (bodies file, frame preset, floor, A_gx range, restitution, band) is checked before
any work starts; a bad one ends the command with a one-line message.
"""

from __future__ import annotations

import json
import math
from pathlib import Path

import click
import numpy as np
import pandas as pd

from ..backends import get_backend
from ..bodies import NamedBody, example_bodies_path, read_bodies_table
from ..body import paper_bodies
from ..design_spectra import parse_spectrum
from ..energy import BAND_HZ, assess, energy_balance, forms_grid, grid_table
from ..errors import InputError
from ..fragility import LognormalFit, agx_50, fit_lognormal, overturning_probability
from ..frames import ShearFrame
from ..motions import NETCDF_ENGINE, Ensemble

#: Files written by ``rocking agx50`` for the paper's Tables 1–3 (when the bodies form a grid),
#: with the paper's decimals.
_TABLES = {"sv_required": ("table1_sv_required_cm_s.csv", "%.2f"),
           "sv1": ("table2_sv1_cm_s.csv", "%.2f"), "ratio": ("table3_ratio.csv", "%.3f")}

#: The paper's band of the available S_v (Section 8) as the --band text.
_BAND_TEXT = f"{BAND_HZ[0]:g}:{BAND_HZ[1]:g}"

# --------------------------------------------------------------------------- input parsing


def parse_range(text: str, option: str = "--agx", unit: str = "g") -> np.ndarray:
    """Values of ``start:stop:step`` [``unit``] (stop included when within 1e-9·step) or of one
    number; all must be > 0.

    Values are rounded to 12 significant digits, so 0.1:0.3:0.1 gives 0.1, 0.2, 0.3 exactly as
    written rather than 0.30000000000000004.
    """
    parts = str(text).split(":")
    try:
        nums = [float(p) for p in parts]
    except ValueError:
        raise InputError(f"{option} must be start:stop:step or one number, got {text!r}") from None
    if len(nums) == 1:
        nums = [nums[0], nums[0], 1.0]
    if len(nums) != 3 or not all(math.isfinite(x) for x in nums):
        raise InputError(f"{option} must be start:stop:step (three finite numbers), got {text!r}")
    start, stop, step = nums
    if step <= 0.0:
        raise InputError(f"{option} {text}: step must be > 0, got {step:g}")
    if start <= 0.0:
        raise InputError(f"{option} {text}: values must be > 0 [{unit}], got start {start:g}")
    if stop < start:
        raise InputError(f"{option} {text} is an empty range: stop ({stop:g} {unit}) is below "
                         f"start ({start:g} {unit})")
    n = int(math.floor((stop - start) / step + 1e-9)) + 1
    return np.array([float(f"{start + i * step:.12g}") for i in range(n)])


def parse_band(text: str) -> tuple[float, float]:
    """``lo:hi`` [Hz] with 0 < lo < hi."""
    try:
        lo, hi = (float(p) for p in str(text).split(":"))
    except ValueError:
        raise InputError(f"--band must be LOW:HIGH in Hz, e.g. 0.04:0.6, got {text!r}") from None
    if not (math.isfinite(lo) and math.isfinite(hi) and 0.0 < lo < hi):
        raise InputError(f"--band {text}: need 0 < LOW < HIGH [Hz]")
    return lo, hi


def parse_e(text: str):
    """Restitution: a number in (0, 1] or ``housner``."""
    if str(text).strip().lower() == "housner":
        return "housner"
    try:
        e = float(text)
    except ValueError:
        raise InputError(f"--e must be a number in (0, 1] or 'housner', got {text!r}") from None
    if not 0.0 < e <= 1.0:
        raise InputError(f"--e must be a number in (0, 1] or 'housner', got {text!r}")
    return e


def load_bodies(spec: str) -> list[NamedBody]:
    """Bodies from a CSV file, the paper's 72 bodies for the word ``paper``, or the shipped
    example file for ``example`` (unless a file of that name exists)."""
    if spec == "paper":
        return [NamedBody(b.label, b) for b in paper_bodies()]
    if spec == "example" and not Path(spec).exists():
        return read_bodies_table(example_bodies_path())
    return read_bodies_table(spec)


def _frame_floor(frame_name: str | None, floor: int | None) -> tuple[ShearFrame | None, int]:
    if frame_name is None and floor is None:
        return None, 0
    if frame_name is None or floor is None:
        raise InputError("--floor and --frame go together: give both (floor 0 is the ground)")
    frame = ShearFrame.preset(frame_name)
    if not 0 <= floor <= frame.n_stories:
        raise InputError(f"--floor must be from 0 (ground) to {frame.n_stories} (roof of "
                         f"{frame.name}), got {floor}")
    return frame, floor


def _location(ensemble: Ensemble, frame: ShearFrame | None, floor: int) -> Ensemble:
    return ensemble if frame is None else frame.floor_ensemble(ensemble, floor)


def _out_dir(out: str) -> Path:
    path = Path(out)
    path.mkdir(parents=True, exist_ok=True)
    return path


# --------------------------------------------------------------------------- shared options

_bodies_option = click.option(
    "--bodies", "bodies_spec", required=True, metavar="FILE|paper|example",
    help="Bodies CSV with columns R [m] and gamma [-], or H [m] and B [m], and optionally name; "
         "'paper' for the paper's 72 bodies (R = 4-11 ft, gamma = 2-6); 'example' for the "
         "shipped example file (the paper's two Section 8 blocks and five pieces of "
         "equipment).")


def _run_options(func):
    """Options shared by ``fragility`` and ``agx50``."""
    options = [
        _bodies_option,
        click.option("--motions", "motions_path", required=True,
                     type=click.Path(dir_okay=False),
                     help="Ground-motion ensemble, netCDF from 'rocking motions generate' "
                          "(accelerations [m/s^2])."),
        click.option("--floor", type=int, default=None,
                     help="Put the bodies on this floor of --frame (0 = ground); the floor "
                          "motions are scaled to the same A_gx as the ground (paper Sec. 7)."),
        click.option("--frame", "frame_name", default=None, metavar="PRESET",
                     help="Shear-frame preset: paper-2.0, paper-1.5, paper-1.0 or paper-0.5."),
        click.option("--out", required=True, type=click.Path(file_okay=False),
                     help="Output folder (created); finished chunks are kept in it, so the same "
                          "command resumes an interrupted run."),
        click.option("--scheduler", default=None, metavar="ADDRESS",
                     help="'local' (default: all cores here), 'dask-local' (a local Dask "
                          "cluster) or a Dask scheduler address tcp://HOST:PORT."),
        click.option("--e", "e_text", default="0.925", show_default=True, metavar="E|housner",
                     help="Coefficient of restitution [-] in (0, 1], or 'housner' "
                          "(1 - 1.5 sin^2 alpha per body)."),
        click.option("--quiet", is_flag=True, help="No progress bar."),
    ]
    for option in reversed(options):
        func = option(func)
    return func


def _prepare(bodies_spec, motions_path, floor, frame_name, e_text, out, scheduler):
    """Check every input, then load the motions (at the bodies' location).

    Returns the bodies, the ensemble, e, the output folder and the backend (a Dask cluster is
    only contacted when the run starts)."""
    bodies = load_bodies(bodies_spec)
    frame, floor = _frame_floor(frame_name, floor)
    e = parse_e(e_text)
    backend = get_backend(scheduler)
    ensemble = _location(Ensemble.load(motions_path), frame, floor)
    out = _out_dir(out)
    return bodies, ensemble, e, out, backend


def _names(ds, bodies: list[NamedBody]):
    """``ds`` with the user's body names as the ``body`` coordinate."""
    return ds.assign_coords(body=[b.name for b in bodies])


def _describe(ensemble: Ensemble) -> dict:
    """netCDF attributes saying what the motions were."""
    return {"location": str(ensemble.meta.get("location", "")), "n_motions": ensemble.n,
            "dt_s": ensemble.dt, "duration_s": ensemble.duration}


def _save_nc(ds, path: Path) -> None:
    """netCDF via the same engine as ensembles (netCDF-3: integers as int32)."""
    ds = ds.copy()
    for name, var in ds.variables.items():
        if var.dtype.kind in "iu":
            ds[name] = var.astype(np.int32)
        elif var.dtype.kind == "b":
            ds[name] = var.astype(np.int8)
    ds.to_netcdf(path, engine=NETCDF_ENGINE)


def _fit(agx, one_body) -> LognormalFit:
    """Lognormal fit of one body's counts; NaN median and beta when the counts carry no
    information on the median (all 0 or all n: fit_lognormal refuses those)."""
    count, n = one_body["count"].values, one_body["n"].values
    if np.all(count == 0) or np.all(count == n):
        return LognormalFit(math.nan, math.nan)
    return fit_lognormal(agx, count, n)


# --------------------------------------------------------------------------- commands


@click.command("fragility")
@_run_options
@click.option("--agx", "agx_text", default="0.1:1.5:0.05", show_default=True,
              metavar="START:STOP:STEP",
              help="A_gx levels [g] (ensemble mean PGA) as start:stop:step, stop included.")
def fragility_cmd(bodies_spec, motions_path, floor, frame_name, out, scheduler, e_text, quiet,
                  agx_text):
    """Overturning probability of each body against A_gx (paper Figs. 9-11, 13).

    Writes to --out: probabilities.csv (one row per body and A_gx, with the count of overturned
    motions and the Wilson 95 % interval), probabilities.nc (the same, netCDF), lognormal.csv
    (maximum-likelihood median [g] and dispersion beta [-] per body) and fragility.png.
    """
    agx = parse_range(agx_text)
    bodies, ensemble, e, out, backend = _prepare(bodies_spec, motions_path, floor, frame_name,
                                                 e_text, out, scheduler)
    blocks = [b.block for b in bodies]
    with backend:
        ds = overturning_probability(blocks, ensemble, agx, e=e, backend=backend,
                                     out=out / "chunks" / "fragility",
                                     progress=False if quiet else None)  # None: bar on a tty
    ds = _names(ds, bodies)
    fits = {name: _fit(agx, ds.sel(body=name)) for name in ds["body"].values}
    ds["lognormal_median"] = ("body", [fits[k].median for k in ds["body"].values],
                              {"units": "g", "long_name": "lognormal fit: median A_gx"})
    ds["lognormal_beta"] = ("body", [fits[k].beta for k in ds["body"].values],
                            {"units": "1", "long_name": "lognormal fit: dispersion"})
    ds.attrs.update(_describe(ensemble), e=str(e), motions=str(motions_path))

    tidy = (ds[["probability", "count", "n", "ci_low", "ci_high"]].to_dataframe().reset_index()
            [["body", "R", "gamma", "agx", "probability", "count", "n", "ci_low", "ci_high"]])
    tidy.to_csv(out / "probabilities.csv", index=False)  # full precision: values round-trip
    _save_nc(ds, out / "probabilities.nc")
    fit_table = pd.DataFrame({"body": ds["body"].values, "R": ds["R"].values,
                              "gamma": ds["gamma"].values,
                              "median_g": ds["lognormal_median"].values,
                              "beta": ds["lognormal_beta"].values})
    fit_table.to_csv(out / "lognormal.csv", index=False, float_format="%.6g")
    from ..plots.fragility import plot_fragility  # matplotlib only when a figure is drawn

    title = f"{ensemble.n} motions, {ensemble.meta.get('location', 'ground')}, e = {e}"
    plot_fragility(ds, fits=fits, title=title).savefig(out / "fragility.png", dpi=150)
    click.echo(f"{len(blocks)} bodies x {agx.size} A_gx levels x {ensemble.n} motions "
               f"({ensemble.meta.get('location', 'ground')})")
    for name in ("probabilities.csv", "probabilities.nc", "lognormal.csv", "fragility.png"):
        click.echo(f"wrote {out / name}")


@click.command("agx50")
@_run_options
@click.option("--resolution", type=click.FloatRange(0.0, min_open=True), default=0.01,
              show_default=True, help="Resolution of A_gx at 50 % probability [g].")
@click.option("--agx-max", type=click.FloatRange(0.0, min_open=True), default=5.0,
              show_default=True, help="Largest A_gx searched [g]; beyond it A_gx50 is NaN.")
@click.option("--band", "band_text", default=_BAND_TEXT, show_default=True,
              metavar="LOW:HIGH",
              help="Frequency band [Hz] of the available S_v1 (max of the mean 5 %-damped "
                   "PSV).")
def agx50_cmd(bodies_spec, motions_path, floor, frame_name, out, scheduler, e_text, quiet,
              resolution, agx_max, band_text):
    """A_gx of 50 % overturning probability per body and Housner's energy balance (Section 8).

    Writes to --out: agx50.csv and agx50.nc (A_gx50 [g], required S_v of Eq. 11 and S_v1 [cm/s]
    in the CSV, their ratio), the paper's Tables 1-3 as R x gamma grids when the bodies form
    one (table1_sv_required_cm_s.csv, table2_sv1_cm_s.csv, table3_ratio.csv) and sv_agx.png
    (required S_v against A_gx50 with a least-squares line, paper Figs. 15-16).
    """
    band = parse_band(band_text)
    bodies, ensemble, e, out, backend = _prepare(bodies_spec, motions_path, floor, frame_name,
                                                 e_text, out, scheduler)
    blocks = [b.block for b in bodies]
    with backend:
        a50 = agx_50(blocks, ensemble, resolution=resolution, agx_max=agx_max, e=e,
                     backend=backend, out=out / "chunks" / "agx50",
                     progress=False if quiet else None)  # None: bar on a terminal only
    energy = _names(energy_balance(blocks, ensemble, a50, band_hz=band), bodies)
    ds = _names(a50, bodies).merge(energy, compat="override")
    ds.attrs.update({**energy.attrs, **_describe(ensemble)}, e=str(e),
                    motions=str(motions_path))
    _save_nc(ds, out / "agx50.nc")
    table = pd.DataFrame({"body": ds["body"].values, "R": ds["R"].values,
                          "gamma": ds["gamma"].values, "agx50_g": ds["agx50"].values,
                          "sv_required_cm_s": 100.0 * ds["sv_required"].values,
                          "sv1_cm_s": 100.0 * ds["sv1"].values, "ratio": ds["ratio"].values})
    table.to_csv(out / "agx50.csv", index=False, float_format="%.6g")
    written = ["agx50.csv", "agx50.nc"]
    if forms_grid(energy):
        for var, (name, fmt) in _TABLES.items():
            grid = grid_table(energy, var)
            # float_format would also cut R and gamma: write them as text (R to 0.1 mm)
            grid = grid.rename(index=lambda r: f"{r:.4f}", columns=lambda g: f"{g:g}")
            grid.to_csv(out / name, float_format=fmt)
            written.append(name)
    from ..plots.fragility import plot_sv_agx  # matplotlib only when a figure is drawn

    title = f"{ensemble.n} motions, {ensemble.meta.get('location', 'ground')}, e = {e}"
    plot_sv_agx(energy, title=title).savefig(out / "sv_agx.png", dpi=150)
    written.append("sv_agx.png")
    found = np.isfinite(energy["ratio"].values)
    summary = (f"; mean S_v1/S_v {np.mean(energy['ratio'].values[found]):.3f}" if found.any()
               else "")
    click.echo(f"{len(blocks)} bodies, {ensemble.n} motions "
               f"({ensemble.meta.get('location', 'ground')}): A_gx50 found below {agx_max:g} g "
               f"for {int(found.sum())}{summary}")
    for name in written:
        click.echo(f"wrote {out / name}")


@click.command("assess")
@_bodies_option
@click.option("--spectrum", "spectrum_path", required=True, type=click.Path(dir_okay=False),
              help="Spectrum at the bodies' location: a CSV table (frequency [Hz] or period "
                   "[s]; PSA [g] or PSV [cm/s or m/s]), e.g. from 'rocking spectrum --csv' or "
                   "'rocking frame spectra --csv', FILE:NAME choosing one record or floor of a "
                   "file that holds several (FILE.csv:floor_1); a saved ensemble (.nc), whose "
                   "mean PSV is used; or a design spectrum as for 'rocking screen' (e.g. "
                   "asce7:SDS=1.0,SD1=0.6,TL=8).")
@click.option("--band", "band_text", default=_BAND_TEXT, show_default=True,
              metavar="LOW:HIGH",
              help="Frequency band [Hz] in which the available S_v is the largest PSV.")
@click.option("--damping", type=click.FloatRange(0.0, 1.0, min_open=True, max_open=True),
              default=0.05, show_default=True, help="Damping ratio of the spectrum [-].")
@click.option("--agx", type=click.FloatRange(0.0, min_open=True), default=None,
              help="Scale an ensemble (.nc) to this A_gx [g] (mean PGA) first.")
@click.option("--floor", type=int, default=None,
              help="With an ensemble: use the motions of this floor of --frame (0 = ground).")
@click.option("--frame", "frame_name", default=None, metavar="PRESET",
              help="Shear-frame preset for --floor: paper-2.0, paper-1.5, paper-1.0, paper-0.5.")
@click.option("--json", "as_json", is_flag=True, help="Print JSON instead of a table.")
def assess_cmd(bodies_spec, spectrum_path, band_text, damping, agx, floor, frame_name, as_json):
    """Screen bodies with Housner's energy balance (paper Eq. 11 and Section 8 examples).

    A body is 'safe' when its required S_v [cm/s] exceeds the available S_v (the largest PSV
    of the spectrum in the band) and 'overturn>50%' otherwise. margin = required / available
    - 1 [-] (> 0: safe). Bodies are listed most at risk first.
    """
    band = parse_band(band_text)
    bodies = load_bodies(bodies_spec)
    frame, floor = _frame_floor(frame_name, floor)
    is_ensemble = Path(spectrum_path).suffix.lower() == ".nc"
    if not is_ensemble and (agx is not None or frame is not None):
        raise InputError("--agx, --floor and --frame apply to an ensemble (.nc) spectrum only")
    if is_ensemble:
        source = _location(Ensemble.load(spectrum_path), frame, floor)
    else:
        source = parse_spectrum(spectrum_path, damping=damping)
    ds = assess([b.block for b in bodies], source, band_hz=band, damping=damping, agx=agx,
                names=[b.name for b in bodies])
    order = np.argsort(ds["margin"].values, kind="stable")
    ds = ds.isel(body=order)
    available = 100.0 * float(ds["sv_available"].values[0])
    if as_json:
        rows = [{"name": str(n), "R_m": float(r), "gamma": float(g),
                 "sv_required_cm_s": 100.0 * float(req), "sv_available_cm_s": available,
                 "margin": float(m), "verdict": str(v)}
                for n, r, g, req, m, v in zip(ds["body"].values, ds["R"].values,
                                              ds["gamma"].values, ds["sv_required"].values,
                                              ds["margin"].values, ds["verdict"].values)]
        click.echo(json.dumps({"spectrum": str(spectrum_path), "band_hz": list(band),
                               "damping": damping, "sv_available_cm_s": available,
                               "bodies": rows}, indent=2))
        return
    click.echo(f"available S_v = {available:.2f} cm/s (max PSV, {100 * damping:g} % damping, "
               f"{band[0]:g}-{band[1]:g} Hz, {spectrum_path})")
    width = max(4, *(len(str(n)) for n in ds["body"].values))
    click.echo(f"{'name':<{width}}  {'required S_v [cm/s]':>19}  {'available [cm/s]':>16}  "
               f"{'margin [-]':>10}  verdict")
    for n, req, m, v in zip(ds["body"].values, ds["sv_required"].values, ds["margin"].values,
                            ds["verdict"].values):
        click.echo(f"{str(n):<{width}}  {100.0 * req:19.2f}  {available:16.2f}  {m:+10.3f}  {v}")


COMMANDS = [fragility_cmd, agx50_cmd, assess_cmd]
