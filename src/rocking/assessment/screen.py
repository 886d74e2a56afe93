"""Screening an inventory of free-standing items against a design spectrum.

For every item of a :class:`rocking.assessment.inventory.Inventory`, at the design level of a target
spectrum (its zero-period acceleration, :func:`rocking.motions.design.design_pga`):

* Housner's energy balance (paper Eq. 11, end of Section 8): required S_v against the available
  S_v at the item's location — on the ground the spectrum's own PSV, on floor N the mean PSV of
  the floor motions — with its margin and verdict (:func:`rocking.assessment.energy.assess`);
* the Monte Carlo overturning probability at the design level with its Wilson interval, and the
  ground A_gx of 50 % probability (:mod:`rocking.montecarlo.probability`), from the same ensemble.

Floor motions are, by default (``floor_motions="building"``), the frame's response to the
spectrum-compatible ground motions scaled to the design A_gx: what the floor of that (linear)
building feels in the design earthquake, so that an item upstairs is judged against the same
earthquake as one on the ground, and its A_gx50 is the *ground* A_gx that overturns it with
50 % probability. ``floor_motions="paper"`` instead rescales each floor's ensemble to the
ground's A_gx, as the paper does in Section 7 to compare bodies on floors and on the ground at
one intensity; that removes the building's amplification, so it is not a screening of a real
building.

The work is shaped for speed: one ensemble generation, one pass through each frame for all its
floors, one response-spectrum call per frame, and per location one batched probability run and
one A_gx50 search over all its items.
"""

from __future__ import annotations

import math
import os

import numpy as np
import xarray as xr

from ..core.checks import positive
from ..errors import InputError
from ..montecarlo.fragility import fragility_analysis
from ..montecarlo.probability import agx_50, overturning_probability
from ..montecarlo.statistics import LognormalFit
from ..motions.design import design_pga, parse_spectrum
from ..motions.ensemble import Ensemble
from ..motions.intensity import intensity_measures
from ..motions.response import ResponseSpectrum, response_spectrum
from ..motions.synthesis import generate
from ..motions.targets import TargetSpectrum
from .energy import BAND_HZ, SAFE, assess, band_frequencies
from .inventory import Inventory, Item, read_inventory
from .risk import HazardCurve, annual_rate, example_hazard_path

#: Oscillator frequencies of the floor spectra in the band of the available S_v [-]: 100
#: log-spaced frequencies in 0.04–0.6 Hz find the band maximum of the mean PSV of the floors of
#: the paper's frames within 0.4 % of 800 frequencies (measured on 50 ASCE 7 motions; the
#: T1 = 2 s frame's resonance at 0.5 Hz is the sharpest peak), at an eighth of the cost.
N_BAND_FREQS = 100
#: Choices of ``floor_motions`` (see the module docstring).
FLOOR_MOTIONS = ("building", "paper")


def screen(
    inventory,
    spectrum,
    *,
    frame=None,
    n: int = 200,
    seed: int = 0,
    duration: float = 20.0,
    dt: float = 1 / 400,
    ensemble: Ensemble | None = None,
    band_hz=BAND_HZ,
    resolution: float = 0.01,
    agx_max: float = 5.0,
    confidence: float = 0.95,
    floor_motions: str = "building",
    backend=None,
    progress=None,
    hazard=None,
    years: float = 50.0,
) -> xr.Dataset:
    """Screen every item of an inventory against a design spectrum.

    Parameters
    ----------
    inventory : Inventory, list of Item, str or Path
        The items, or an inventory file (:func:`rocking.assessment.inventory.read_inventory`).
    spectrum : TargetSpectrum or str
        The design spectrum at the ground, or its specification
        (:func:`rocking.motions.design.parse_spectrum`, e.g. ``"asce7:SDS=1,SD1=0.6,TL=8"``).
        Its zero-period acceleration is the design A_gx [g].
    frame : str or ShearFrame, optional
        Default frame of ``floor N`` items without one (only when ``inventory`` is a file).
    n : int
        Number of motions to generate (when ``ensemble`` is not given).
    seed : int
        Seed of the generated motions.
    duration, dt : float
        Duration [s] and time step [s] of the generated motions (compound intensity function).
    ensemble : Ensemble, optional
        Ground motions to use instead of generating them (any scale; they are scaled to the
        design A_gx). They should be compatible with ``spectrum``.
    band_hz : (float, float)
        Band of the available S_v [Hz] (paper: 0.04–0.6 Hz).
    resolution : float
        Resolution of the A_gx50 search [g].
    agx_max : float
        Largest A_gx of the A_gx50 search [g]; A_gx50 is NaN above it.
    confidence : float
        Confidence level of the Wilson interval [-].
    floor_motions : {"building", "paper"}
        Floor motions as the building's response to the design-level ground motions
        ("building", default), or rescaled to the ground's A_gx (the paper's Section 7
        convention); see the module docstring.
    backend : optional
        Backend of the Monte Carlo runs (:func:`rocking.montecarlo.backends.get_backend`); default
        local.
    progress : optional
        Passed on to :func:`rocking.montecarlo.probability.overturning_probability` and ``agx_50``.
    hazard : HazardCurve, str or Path, optional
        A site hazard curve (:class:`rocking.HazardCurve`, a CSV file of one, or ``"example"``):
        then every item also gets a fragility curve against the hazard's IM of the *ground*
        motion (IDA of the design-level motions at 20 levels spanning the hazard table; on a
        floor, the floor's response to each ground motion scaled to the level, exact for the
        linear frame) and its mean annual rate of overturning (:func:`rocking.annual_rate`).
        Needs ``floor_motions="building"``.
    years : float
        Exposure time [yr] of the probability of at least one overturning (Poisson), > 0.

    Returns
    -------
    xarray.Dataset
        Dimension ``item`` (coordinate: item names), sorted most at risk first (highest
        probability at the design A_gx, then lowest A_gx50, then lowest margin). Variables:
        ``location``, ``floor``, ``frame``, ``height`` and ``width`` [m], ``R`` [m], ``gamma``
        [-], ``e`` [-], ``mu`` [-] (NaN: not given), ``may_slide`` (μ ≤ B/H), ``sv_required``
        and ``sv_available`` [m/s], ``margin`` [-] (> 0: safe by Eq. 11), ``verdict``,
        ``probability``, ``ci_low``, ``ci_high`` [-], ``overturned`` and ``n_motions`` (counts),
        ``agx50`` [g] (ground A_gx; with ``floor_motions="paper"`` the floor's own), ``at_risk``
        (probability ≥ 0.5 or margin ≤ 0); with ``hazard``: ``fragility_median`` [the IM's
        unit], ``fragility_beta`` [-], ``annual_rate`` [1/yr] (NaN: no overturning up to the
        hazard's largest IM, so below its upper-tail bound) and ``p_years`` [-]. Attributes:
        ``spectrum``, ``design_agx`` [g], the settings and the ensemble's generation
        parameters.
    """
    if floor_motions not in FLOOR_MOTIONS:
        raise InputError(
            f"floor_motions must be one of {', '.join(FLOOR_MOTIONS)}, got {floor_motions!r}"
        )
    if isinstance(inventory, (list, tuple)):
        if not inventory:
            raise InputError("inventory is empty: there is no item to screen")
        if not all(isinstance(it, Item) for it in inventory):
            raise InputError(
                "inventory must be an Inventory, a list of rocking.Item or the path "
                "of an inventory file"
            )
        inventory = Inventory(tuple(inventory))
    if not isinstance(inventory, Inventory):
        if not isinstance(inventory, (str, os.PathLike)):
            raise InputError(
                f"inventory must be an Inventory, a list of rocking.Item or the path "
                f"of an inventory file, got {type(inventory).__name__}"
            )
        inventory = read_inventory(inventory, frame=frame)
    elif frame is not None:
        raise InputError(
            "frame is the default frame of an inventory file; the Inventory given "
            "is already resolved"
        )
    if not isinstance(spectrum, TargetSpectrum):
        spectrum = parse_spectrum(spectrum)
    if hazard is not None:
        hazard = _hazard_curve(hazard, floor_motions)
        years = positive("years", years, "yr")
    agx = design_pga(spectrum)
    if ensemble is None:
        ensemble = generate(n, duration=duration, dt=dt, target=spectrum, seed=seed)
    elif ensemble.meta.get("location") != "ground":
        raise InputError(f"ensemble must be ground motions, got {ensemble.meta.get('location')}")
    ground = ensemble.scaled(agx)
    risk = None
    if hazard is not None:
        # the hazard's IM of every design-level ground motion, computed once for all locations
        ground_im = intensity_measures(ground, hazard.im.name).iloc[:, 0].to_numpy()
        risk = (hazard, years, ground_im)
    parts = [
        _screen_location(
            items,
            source,
            motions,
            ratio,
            band_hz=band_hz,
            resolution=resolution,
            agx_max=agx_max,
            confidence=confidence,
            backend=backend,
            progress=progress,
            risk=risk,
        )
        for items, source, motions, ratio in _locations(
            inventory, spectrum, ground, band_hz, floor_motions
        )
    ]
    ds = xr.concat(parts, dim="item")
    at_risk = (ds["probability"] >= 0.5) | (ds["margin"] <= 0.0)
    ds["at_risk"] = at_risk.assign_attrs(
        long_name="P(overturn) >= 50 % at the design A_gx, or Eq. (11) margin <= 0"
    )
    order = np.lexsort(
        (
            ds["margin"].values,
            np.nan_to_num(ds["agx50"].values, nan=np.inf),
            -ds["probability"].values,
        )
    )
    ds = ds.isel(item=order)
    ds.attrs.update(
        spectrum=spectrum.name,
        design_agx=agx,
        band_hz=[float(b) for b in band_hz],
        damping=spectrum.damping,
        confidence=confidence,
        resolution=resolution,
        agx_max=agx_max,
        floor_motions=floor_motions,
        n_motions=ensemble.n,
        years=years,
        hazard="" if hazard is None else hazard.source,
        duration=ensemble.duration,
        dt=ensemble.dt,
        seed=ensemble.meta.get("seed", ""),
        ensemble_kind=ensemble.meta.get("kind", ""),
        inventory=str(inventory.path or ""),
    )
    return ds


def _locations(
    inventory: Inventory, spectrum: TargetSpectrum, ground: Ensemble, band_hz, floor_motions: str
):
    """(items, source of the available S_v, motions at the design level, ratio) per location.

    ``ratio`` is the motions' mean PGA over the ground's A_gx [-] (1 on the ground and for
    ``floor_motions="paper"``). The ground first: its source is the design spectrum itself.
    Then each frame's floors, from one pass through the frame (rescaled to the ground's A_gx
    for ``"paper"``); their source is the mean response spectrum of the floor motions in the
    band, computed for all floors of a frame in one call.
    """
    groups: dict = {}
    for it in inventory:
        groups.setdefault(None if it.floor == 0 else (it.frame, it.floor), []).append(it)
    if None in groups:
        yield groups.pop(None), spectrum, ground, 1.0
    freqs = band_frequencies(band_hz, N_BAND_FREQS)
    for frame in dict.fromkeys(frame for frame, _ in groups):
        floors = frame.floor_ensembles(ground)
        keys = [key for key in groups if key[0] == frame]
        motions = [
            floors[floor].scaled(ground.agx) if floor_motions == "paper" else floors[floor]
            for _, floor in keys
        ]
        rs = response_spectrum(
            np.concatenate([m.acc for m in motions]), ground.dt, freqs, spectrum.damping
        )
        for i, (key, m) in enumerate(zip(keys, motions)):
            rows = slice(i * ground.n, (i + 1) * ground.n)
            yield (
                groups[key],
                ResponseSpectrum(freqs, rs.damping, rs.sd[rows], rs.psv[rows], rs.psa[rows]),
                m,
                m.agx / ground.agx,
            )


def _screen_location(
    items,
    source,
    motions: Ensemble,
    ratio: float,
    *,
    band_hz,
    resolution,
    agx_max,
    confidence,
    backend,
    progress,
    risk: tuple[HazardCurve, float, np.ndarray] | None = None,
) -> xr.Dataset:
    """The screening dataset (dimension ``item``) of the items at one location: Eq. (11)
    against ``source`` (TargetSpectrum or ResponseSpectrum), Monte Carlo with ``motions``, which
    are at the design level: their mean PGA is ``ratio`` × the design A_gx [g]. The
    motions scale linearly with the ground (linear frame), so the A_gx50 search runs on the
    motions' own A_gx with resolution and upper end × ``ratio`` and is reported in ground
    A_gx. ``risk`` = (hazard curve, years, the hazard's IM of each design-level ground motion)
    adds the annual rate of overturning (:func:`_annual_rates`)."""
    blocks = [it.block for it in items]
    names = [it.name for it in items]
    energy = assess(
        blocks, source, band_hz=band_hz, damping=source.damping, names=names
    )  # Eq. (11)
    e = _restitution(items)
    mc = overturning_probability(
        blocks,
        motions,
        [motions.agx],
        e=e,
        backend=backend,
        progress=progress,
        confidence=confidence,
    ).isel(agx=0)
    a50 = (
        agx_50(
            blocks,
            motions,
            resolution=resolution * ratio,
            agx_max=agx_max * ratio,
            e=e,
            backend=backend,
            progress=progress,
        )["agx50"].values
        / ratio
    )
    mu = np.array([math.nan if it.mu is None else it.mu for it in items])
    variables = {
        "location": ([it.location for it in items], "", "ground or floor N of FRAME"),
        "floor": ([it.floor for it in items], "", "floor (0: ground)"),
        "frame": ([it.frame.name if it.frame else "" for it in items], "", "shear frame"),
        "height": ([b.H for b in blocks], "m", "height H"),
        "width": ([b.B for b in blocks], "m", "width B"),
        "R": ([b.R for b in blocks], "m", "size parameter R"),
        "gamma": ([b.gamma for b in blocks], "1", "slenderness H/B"),
        "e": ([it.e for it in items], "1", "coefficient of restitution"),
        "mu": (mu, "1", "friction coefficient (NaN: not given)"),
        "may_slide": ([it.may_slide for it in items], "", "mu <= B/H: may slide, not rock"),
        "sv_required": (energy["sv_required"].values, "m s-1", "required S_v, Eq. (11)"),
        "sv_available": (
            energy["sv_available"].values,
            "m s-1",
            "max PSV at the location in the band",
        ),
        "margin": (energy["margin"].values, "1", "sv_required / sv_available - 1 (> 0: safe)"),
        "verdict": (energy["verdict"].values, "", "Eq. (11) verdict"),
        "probability": (mc["probability"].values, "1", "overturning probability at design A_gx"),
        "ci_low": (mc["ci_low"].values, "1", "Wilson interval, lower end"),
        "ci_high": (mc["ci_high"].values, "1", "Wilson interval, upper end"),
        "overturned": (mc["count"].values, "", "motions that overturn the item"),
        "n_motions": (mc["n"].values, "", "motions"),
        "agx50": (a50, "g", "ground A_gx at 50 % overturning probability"),
    }
    if risk is not None:
        variables.update(_annual_rates(blocks, e, motions, *risk, backend, progress))
    return xr.Dataset(
        {
            k: ("item", np.asarray(v), {"units": u, "long_name": ln} if u else {"long_name": ln})
            for k, (v, u, ln) in variables.items()
        },
        coords={"item": names},
    )


#: IM levels of the fragility curves of a screening with a hazard curve [-].
N_RISK_LEVELS = 20


def _hazard_curve(hazard, floor_motions: str) -> HazardCurve:
    """The hazard curve of ``screen(hazard=...)``, checked."""
    if floor_motions != "building":
        raise InputError(
            "hazard needs floor_motions='building': the paper's rescaled floor motions are "
            "not the response of the building to the site's ground motions"
        )
    if isinstance(hazard, HazardCurve):
        return hazard
    if isinstance(hazard, str) and hazard.strip().lower() == "example":
        return HazardCurve.from_csv(example_hazard_path())
    return HazardCurve.from_csv(hazard)


def _annual_rates(
    blocks, e, motions: Ensemble, hazard, years, ground_im, backend, progress
) -> dict:
    """Fragility against the hazard's IM of the ground motion and the annual rate of every item
    at one location (``motions``: the location's motions at the design level, member i the
    response to the ground motion i, whose IM is ``ground_im[i]``)."""
    im = hazard.im.name
    levels = np.geomspace(hazard.values[0], hazard.values[-1], N_RISK_LEVELS)
    curves = fragility_analysis(
        blocks,
        motions,
        im=im,
        levels=np.array([float(f"{x:.6g}") for x in levels]),
        im_values=ground_im,
        e=e,
        backend=backend,
        progress=progress,
        n_boot=0,
    )
    rate = np.full(len(blocks), np.nan)
    for b in range(len(blocks)):
        median, beta = float(curves["median"][b]), float(curves["beta"][b])
        if math.isfinite(median) and math.isfinite(beta):
            rate[b] = annual_rate(LognormalFit(median, beta), hazard).annual_rate
    unit = hazard.im.unit
    return {
        "fragility_median": (curves["median"].values, unit, f"median {hazard.im.label}"),
        "fragility_beta": (curves["beta"].values, "1", "lognormal dispersion"),
        "annual_rate": (rate, "yr-1", "mean annual rate of overturning"),
        "p_years": (-np.expm1(-rate * years), "1", f"P(overturning in {years:g} years)"),
    }


def _restitution(items):
    """One e for all items when they agree, else one per item [-]."""
    e = np.array([it.e for it in items])
    return float(e[0]) if np.all(e == e[0]) else e


#: Entry of :func:`eq11_vs_monte_carlo` when Eq. (11) and the simulation agree.
AGREE = "agree"


def eq11_vs_monte_carlo(verdict, probability, ci_low, ci_high) -> np.ndarray:
    """Whether Housner's Eq. (11) verdict and the Monte Carlo probability agree, per body.

    Eq. (11) estimates the 50 % level: "safe" agrees with a simulated probability below 0.5,
    "overturn>50%" with one of 0.5 or more.

    Parameters
    ----------
    verdict : array_like of str
        Eq. (11) verdicts (:func:`rocking.assessment.energy.assess`).
    probability, ci_low, ci_high : array_like
        Simulated overturning probability and its Wilson interval [-].

    Returns
    -------
    numpy.ndarray of str
        ``"agree"``, ``"disagree: Eq. (11) overturn, simulated P < 50 %"`` or
        ``"disagree: Eq. (11) safe, simulated P ≥ 50 %"``, followed by
        ``"; Wilson interval spans 50 %"`` when the simulation cannot tell the side of 50 %.
    """
    eq11_overturn = np.asarray(verdict) != SAFE
    mc_overturn = np.asarray(probability, dtype=float) >= 0.5
    unsure = (np.asarray(ci_low, dtype=float) <= 0.5) & (np.asarray(ci_high, dtype=float) >= 0.5)
    text = np.where(
        eq11_overturn == mc_overturn,
        AGREE,
        np.where(
            eq11_overturn,
            "disagree: Eq. (11) overturn, simulated P < 50 %",
            "disagree: Eq. (11) safe, simulated P ≥ 50 %",
        ),
    )
    return np.array(
        [t + ("; Wilson interval spans 50 %" if u else "") for t, u in zip(text, unsure)],
        dtype=object,
    )


def eq11_vs_monte_carlo_note(band_hz=BAND_HZ) -> str:
    """Markdown paragraph for reports: why Eq. (11) and the Monte Carlo probability can
    disagree (``band_hz`` [Hz]: the band of the available S_v)."""
    return (
        "**Why Eq. (11) and the Monte Carlo probability can disagree.** Eq. (11) is Housner's "
        "energy balance: it expects a body to overturn with about 50 % probability when the "
        "spectrum offers more pseudo-velocity than the body needs, judged from one number, the "
        f"largest mean PSV in {band_hz[0]:g}–{band_hz[1]:g} Hz. The Monte Carlo probability is "
        "the share of these particular motions, at that level, that overturn the body. The two "
        "can differ near the threshold (margin close to 0, probability close to 50 %), for "
        "small slender bodies (for which the energy balance is a rougher approximation), and on "
        "floors: floor motions are narrow-band, peaking at the frame's frequencies, so the band "
        "maximum of their mean PSV, taken at a resonance, can overstate what the body meets "
        "across the band. The Wilson "
        "interval says how sure the simulation is: when it spans 50 %, more motions are needed "
        "to tell on which side of 50 % the body lies."
    )


def results_table(ds: xr.Dataset):
    """The screening result as a table (pandas DataFrame) in the dataset's order, with S_v in
    cm/s and whether Eq. (11) and the Monte Carlo agree (:func:`eq11_vs_monte_carlo`), for CSV
    files and reports."""
    import pandas as pd

    table = pd.DataFrame(
        {
            "item": ds["item"].values,
            "location": ds["location"].values,
            # H and B are recomputed from R and γ: round off the float noise for display
            "H [m]": np.round(ds["height"].values, 9),
            "B [m]": np.round(ds["width"].values, 9),
            "R [m]": ds["R"].values,
            "gamma [-]": ds["gamma"].values,
            "e [-]": ds["e"].values,
            "mu [-]": ds["mu"].values,
            "may slide": ds["may_slide"].values,
            "at risk": ds["at_risk"].values,
            "Sv required [cm/s]": 100.0 * ds["sv_required"].values,
            "Sv available [cm/s]": 100.0 * ds["sv_available"].values,
            "margin [-]": ds["margin"].values,
            "Eq. (11) verdict": ds["verdict"].values,
            "P(overturn) [-]": ds["probability"].values,
            "CI low [-]": ds["ci_low"].values,
            "CI high [-]": ds["ci_high"].values,
            "Eq. (11) vs Monte Carlo": eq11_vs_monte_carlo(
                ds["verdict"].values,
                ds["probability"].values,
                ds["ci_low"].values,
                ds["ci_high"].values,
            ),
            "Agx50 [g]": ds["agx50"].values,
        }
    )
    if "annual_rate" in ds:
        unit = ds["fragility_median"].attrs.get("units", "")
        table[f"fragility median [{unit}]"] = ds["fragility_median"].values
        table["fragility beta [-]"] = ds["fragility_beta"].values
        table["annual rate [1/yr]"] = ds["annual_rate"].values
        table[f"P in {ds.attrs['years']:g} yr [-]"] = ds["p_years"].values
    return table


__all__ = ["eq11_vs_monte_carlo", "eq11_vs_monte_carlo_note", "results_table", "screen"]
