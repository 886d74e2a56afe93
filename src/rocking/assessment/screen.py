"""Screening an inventory of free-standing items against a design spectrum.

For every item of a :class:`rocking.assessment.inventory.Inventory`, at the design level of a target
spectrum (its zero-period acceleration, :func:`rocking.motions.design.design_pga`):

* Housner's energy balance (paper Eq. 11, end of Section 8): required S_v against the available
  S_v at the item's location — on the ground the spectrum's own PSV, on floor N the mean PSV of
  the floor motions — with its margin (:func:`rocking.assessment.energy.assess`): a quick,
  conservative screen;
* the Monte Carlo overturning probability at the design level with its Wilson interval, and the
  ground A_gx of 50 % probability (:mod:`rocking.montecarlo.probability`), from the same ensemble;
* with the item's friction μ (issue 45; none: infinite friction, rocking only), its response at
  the design level from the same simulations: the share of the motions in which it stays at
  rest, slides, rocks, slide-rocks or overturns (:data:`RESPONSES`, :func:`responses`), the
  dominant one, the share in which it flies, and its slip (median and largest peak slip over the
  motions);
* one verdict per item, from the Monte Carlo probability alone (:data:`VERDICT_RULE`): of
  overturning, or with ``max_slip`` of overturning or sliding that far.

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

import dataclasses
import math
import os
from collections.abc import Callable, Iterator, Sequence
from dataclasses import dataclass
from typing import TYPE_CHECKING, Any

import numpy as np
import xarray as xr
from numpy.typing import ArrayLike

from ..core import portable
from ..core.checks import positive, record, unexpected
from ..core.reuse import reusing
from ..defaults import DT
from ..dynamics.body import Block
from ..dynamics.limits import LimitState, limit_state_coords, parse_limit_states
from ..dynamics.physics import Physics
from ..errors import InputError
from ..montecarlo.backends import Compute
from ..montecarlo.fragility import fragility_analysis
from ..montecarlo.probability import agx_50, overturning_probability
from ..montecarlo.search import Agx50Search
from ..montecarlo.statistics import LognormalFit, wilson_interval
from ..motions.design import design_pga, parse_spectrum
from ..motions.ensemble import Ensemble
from ..motions.intensity import intensity_measures
from ..motions.response import ResponseSpectrum, check_nyquist, response_spectrum
from ..motions.synthesis import generate
from ..motions.targets import TargetSpectrum
from ..structures.frames import ShearFrame
from .bodies import with_body_friction
from .energy import BAND_HZ, SAFE, assess, available_sv, band_frequencies
from .inventory import Inventory, Item, read_inventory
from .risk import HazardCurve, annual_rate

if TYPE_CHECKING:
    import pandas as pd

#: Oscillator frequencies of the floor spectra in the band of the available S_v [-]: enough to
#: find the band maximum of a frame's resonance peak (tests/test_screen.py compares 8 times more).
N_BAND_FREQS = 100
#: Choices of ``floor_motions`` (see the module docstring).
FLOOR_MOTIONS = ("building", "paper")
#: IM levels of the fragility curves of a screening with a hazard curve [-].
N_RISK_LEVELS = 20
#: Overturning probability at the design A_gx from which an item is at risk [-]: the level that
#: Eq. (11) and A_gx50 estimate, so that the verdict and the screen ask the same question.
RISK_PROBABILITY = 0.5
#: The verdicts of a screening (:func:`verdicts`), most at risk first.
AT_RISK, BORDERLINE, NOT_AT_RISK = "at risk", "borderline", "not at risk"
#: The rule of the verdict, for reports.
VERDICT_RULE = (
    f"**at risk**: the simulated probability of overturning at the design A_gx is "
    f"{100 * RISK_PROBABILITY:g} % or more; **borderline**: below {100 * RISK_PROBABILITY:g} %, "
    f"but its Wilson interval reaches {100 * RISK_PROBABILITY:g} % (more motions would tell); "
    f"**not at risk**: the whole interval lies below {100 * RISK_PROBABILITY:g} %. Eq. (11) "
    "does not enter the verdict: it is a conservative screen, shown beside it"
)
#: How the verdict counts slip when a largest allowed slip is given (``max_slip``).
SLIP_RULE = (
    "with a largest allowed slip, the probability of the verdict is that of overturning or "
    "sliding at least that far (peak slip) in the same motion"
)
#: The response of an item to one motion, as a screening counts it (issue 45), from the batched
#: kernel's outcome (:func:`responses`): most severe last.
RESPONSES = ("rest", "slide", "rock", "slide-rock", "overturn")


@dataclass(frozen=True)
class _MonteCarlo:
    """Settings of the Monte Carlo runs of a screening (see :func:`screen`)."""

    search: Agx50Search  # the A_gx50 search (resolution, upper end [g])
    confidence: float  # of the Wilson interval [-]
    compute: Compute
    physics: Physics | None = None  # e: the items' own; mu, mu_k: of items without their own
    limit_states: tuple[LimitState, ...] | None = None  # their probabilities besides
    max_slip: float | None = None  # largest allowed peak slip [m]: in the verdict


@dataclass(frozen=True)
class _Risk:
    """The hazard part of a screening: the curve, the exposure time [yr] and the hazard's IM of
    every design-level ground motion (computed once for all locations)."""

    hazard: HazardCurve
    years: float
    ground_im: np.ndarray


@dataclass(frozen=True)
class _Location:
    """The items at one location, the source of their available S_v (TargetSpectrum or
    ResponseSpectrum), their motions at the design level and the ratio of the motions' mean PGA
    to the ground's A_gx [-] (1 on the ground and for ``floor_motions="paper"``)."""

    items: list[Item]
    source: TargetSpectrum | ResponseSpectrum
    motions: Ensemble
    ratio: float


#: The keyword settings of :func:`screen` and their defaults.
_SCREEN_OPTIONS: dict[str, Any] = {
    "n": 200,
    "seed": 0,
    "duration": 20.0,
    "dt": DT,
    "band_hz": BAND_HZ,
    "confidence": 0.95,
    "floor_motions": "building",
    "years": 50.0,
    "max_slip": None,
}


def screen(
    inventory: Inventory | Sequence[Item] | str | os.PathLike[str],
    spectrum: TargetSpectrum | str,
    *,
    frame: str | ShearFrame | None = None,
    ensemble: Ensemble | None = None,
    hazard: HazardCurve | str | os.PathLike[str] | None = None,
    physics: Physics | None = None,
    compute: Compute | None = None,
    search: Agx50Search | None = None,
    limit_states: str | Sequence[str | LimitState] | None = None,
    **options: Any,
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
    ensemble : Ensemble, optional
        Ground motions to use instead of generating them (any scale; they are scaled to the
        design A_gx). They should be compatible with ``spectrum``.
    hazard : HazardCurve, str or Path, optional
        A site hazard curve (:class:`rocking.HazardCurve`, a CSV file of one, or ``"example"``):
        then every item also gets a fragility curve against the hazard's IM of the *ground*
        motion (IDA of the design-level motions at 20 levels spanning the hazard table; on a
        floor, the floor's response to each ground motion scaled to the level, exact for the
        linear frame) and its mean annual rate of overturning (:func:`rocking.annual_rate`).
        Needs ``floor_motions="building"``.
    physics : Physics, optional
        The physics of the simulations (:class:`~rocking.Physics`: overturning angle, g, impact
        scheme); the restitution is each item's own, and so are the friction coefficients of
        the items that give them (``mu``, ``mu_k`` of the inventory): physics's ``mu`` and
        ``mu_k`` are those of the items without (None: infinite friction, rocking only).
    compute : Compute, optional
        How the Monte Carlo runs are computed (:class:`~rocking.montecarlo.backends.Compute`:
        backend, default local; progress; chunk size); a screening keeps no chunk folder
        (``out``).
    search : Agx50Search, optional
        The A_gx50 search (:class:`~rocking.montecarlo.search.Agx50Search`: ``resolution`` and
        ``agx_max`` [g], default 0.01 and 5 g; A_gx50 is NaN above ``agx_max``).
    limit_states : str or sequence of str or LimitState, optional
        Limit states on the response (e.g. ``"uplift, theta/alpha>=0.5, overturn"``): their
        probability at the design A_gx per item, ``limit_state_probability`` (item,
        limit_state), from the simulations of ``probability``.
    **options
        The keyword settings below; ``resolution``, ``agx_max``: shorthands for search's
        fields; ``backend``, ``progress``, ``chunk_size``: for compute's.  Any other keyword
        is an InputError.
    n : int
        Keyword (default 200): number of motions to generate (when ``ensemble`` is not given).
    seed : int
        Keyword (default 0): seed of the generated motions.
    duration, dt : float
        Keywords (default 20 s and :data:`rocking.defaults.DT`): duration [s] and time step
        [s] of the generated motions (compound intensity function).
    band_hz : (float, float)
        Keyword: band of the available S_v [Hz] (default the paper's 0.04–0.6 Hz).
    confidence : float
        Keyword (default 0.95): confidence level of the Wilson interval [-].
    floor_motions : {"building", "paper"}
        Keyword: floor motions as the building's response to the design-level ground motions
        ("building", default), or rescaled to the ground's A_gx (the paper's Section 7
        convention); see the module docstring.
    years : float
        Keyword (default 50): exposure time [yr] of the probability of at least one
        overturning (Poisson), > 0.
    max_slip : float, optional
        Keyword: the largest allowed peak slip [m], > 0 (e.g. the clearance to a wall or the
        edge of a plinth). Given, the verdict counts the motions that overturn the item or
        slide it at least that far (:data:`SLIP_RULE`); None (default): overturning alone,
        the slip reported beside it.

    Returns
    -------
    xarray.Dataset
        Dimension ``item`` (coordinate: item names), sorted most at risk first (highest
        probability at the design A_gx, then lowest A_gx50, then lowest margin). Variables:
        ``location``, ``floor``, ``frame``, ``height`` and ``width`` [m], ``R`` [m], ``gamma``
        [-], ``e`` [-], ``mu`` and ``mu_k`` [-] (the friction simulated; NaN: infinite),
        ``sv_required`` and ``sv_available`` [m/s], ``margin`` [-] (> 0: safe by Eq. 11),
        ``eq11_verdict`` (Eq. 11's "safe" or "overturn>50%"), ``probability``, ``ci_low``,
        ``ci_high`` [-], ``overturned`` and ``n_motions`` (counts), ``agx50`` [g] (ground
        A_gx; with ``floor_motions="paper"`` the floor's own), ``response_share`` (item,
        response) [-] (the share of the motions of each of :data:`RESPONSES`), ``mode`` (the
        most frequent of them), ``flight_share`` [-] (motions in which the base left the
        ground), ``slip_median`` and ``slip_max`` [m] (median and largest peak slip over the
        motions that leave it standing; NaN if none does), with ``max_slip``
        ``slip_probability`` [-] (peak slip ≥ max_slip) and ``failure_probability``,
        ``failure_ci_low``, ``failure_ci_high`` [-] (overturning or that slip), ``verdict``
        (the one verdict: :func:`verdicts`, :data:`VERDICT_RULE`) and ``at_risk`` (verdict
        "at risk"); with ``hazard``: ``fragility_median`` [the IM's
        unit], ``fragility_beta`` [-], ``annual_rate`` [1/yr] (NaN: no overturning up to the
        hazard's largest IM, so below its upper-tail bound) and ``p_years`` [-]. Attributes:
        ``spectrum``, ``design_agx`` [g], the settings and the ensemble's generation
        parameters.
    """
    n, seed, duration, dt, band_hz, confidence, floor_motions, years, max_slip = (
        options.pop(name, default) for name, default in _SCREEN_OPTIONS.items()
    )
    search = record(Agx50Search, search, options, "search")
    compute = record(Compute, compute, options, "compute")
    unexpected(options)
    if compute.out is not None:
        raise InputError("compute.out: a screening keeps no chunk folder (its runs are many)")
    if floor_motions not in FLOOR_MOTIONS:
        raise InputError(
            f"floor_motions must be one of {', '.join(FLOOR_MOTIONS)}, got {floor_motions!r}"
        )
    if max_slip is not None:
        max_slip = positive("max_slip", max_slip, "m")
    inventory = _inventory(inventory, frame)
    physics = _default_friction(physics)
    if not isinstance(spectrum, TargetSpectrum):
        spectrum = parse_spectrum(spectrum)
    available_sv(spectrum, band_hz=band_hz, damping=spectrum.damping)  # it covers the band
    if hazard is not None:
        hazard = _hazard_curve(hazard, floor_motions)
        years = positive("years", years, "yr")
    if ensemble is None:
        ensemble = generate(n, duration=duration, dt=dt, target=spectrum, seed=seed)
    elif ensemble.meta.get("location") != "ground":
        raise InputError(f"ensemble must be ground motions, got {ensemble.meta.get('location')}")
    check_nyquist(max(band_hz), ensemble.dt, "band_hz")  # the floors' spectra, before any work
    agx = design_pga(spectrum)
    ground = ensemble.scaled(agx)
    states = None if limit_states is None else parse_limit_states(limit_states)
    settings = _MonteCarlo(search, confidence, compute, physics, states, max_slip)
    risk = None if hazard is None else _risk(hazard, years, ground)
    parts = [
        _screen_location(location, band_hz, settings, risk)
        for location in _locations(inventory, spectrum, ground, band_hz, floor_motions)
    ]
    ds = _ranked(xr.concat(parts, dim="item"))
    ds.attrs.update(
        spectrum=spectrum.name,
        design_agx=agx,
        band_hz=[float(b) for b in band_hz],
        damping=spectrum.damping,
        confidence=confidence,
        resolution=search.resolution,
        agx_max=search.agx_max,
        floor_motions=floor_motions,
        n_motions=ensemble.n,
        years=years,
        max_slip=math.nan if max_slip is None else max_slip,
        hazard="" if hazard is None else hazard.source,
        duration=ensemble.duration,
        dt=ensemble.dt,
        seed=ensemble.meta.get("seed", ""),
        ensemble_kind=ensemble.meta.get("kind", ""),
        inventory=str(inventory.path or ""),
    )
    return ds


def _inventory(
    inventory: Inventory | Sequence[Item] | str | os.PathLike[str],
    frame: str | ShearFrame | None,
) -> Inventory:
    """The ``inventory`` argument of :func:`screen` as an Inventory, read from its file with the
    default ``frame`` if it is a path; raises InputError naming what is wrong."""
    if isinstance(inventory, (list, tuple)):
        if not inventory:
            raise InputError("inventory is empty: there is no item to screen")
        if not all(isinstance(it, Item) for it in inventory):
            raise InputError(
                "inventory must be an Inventory, a list of rocking.Item or the path "
                "of an inventory file"
            )
        return Inventory(tuple(inventory))
    if isinstance(inventory, Inventory):
        if frame is not None:
            raise InputError(
                "frame is the default frame of an inventory file; the Inventory given "
                "is already resolved"
            )
        return inventory
    if not isinstance(inventory, (str, os.PathLike)):
        raise InputError(
            f"inventory must be an Inventory, a list of rocking.Item or the path "
            f"of an inventory file, got {type(inventory).__name__}"
        )
    return read_inventory(inventory, frame=frame)


def _default_friction(physics: Physics | None) -> Physics | None:
    """``physics`` checked as a screening takes it: its friction is one value, that of the items
    without their own."""
    if physics is not None and (isinstance(physics.mu, tuple) or isinstance(physics.mu_k, tuple)):
        raise InputError(
            "physics.mu and physics.mu_k of a screening are one value each, that of the items "
            "without their own (give per-item friction in the inventory's mu, mu_k columns)"
        )
    return physics


def _hazard_curve(hazard: HazardCurve | str | os.PathLike[str], floor_motions: str) -> HazardCurve:
    """The hazard curve of ``screen(hazard=...)``, checked."""
    if floor_motions != "building":
        raise InputError(
            "hazard needs floor_motions='building': the paper's rescaled floor motions are "
            "not the response of the building to the site's ground motions"
        )
    if isinstance(hazard, HazardCurve):
        return hazard
    return HazardCurve.from_csv(hazard)


def _risk(hazard: HazardCurve, years: float, ground: Ensemble) -> _Risk:
    """The hazard part of a screening with the design-level ground motions ``ground``."""
    ground_im = intensity_measures(ground, hazard.im.name).iloc[:, 0].to_numpy()
    return _Risk(hazard, years, ground_im)


def _locations(
    inventory: Inventory,
    spectrum: TargetSpectrum,
    ground: Ensemble,
    band_hz: Sequence[float],
    floor_motions: str,
) -> Iterator[_Location]:
    """The locations of the inventory's items: the ground first (its source of the available
    S_v is the design spectrum itself), then each frame's floors (:func:`_floor_locations`)."""
    groups: dict[tuple[ShearFrame, int] | None, list[Item]] = {}
    for it in inventory:
        key = None if it.floor == 0 or it.frame is None else (it.frame, it.floor)
        groups.setdefault(key, []).append(it)
    if None in groups:
        yield _Location(groups.pop(None), spectrum, ground, 1.0)
    freqs = band_frequencies(band_hz, N_BAND_FREQS)
    for frame in dict.fromkeys(key[0] for key in groups if key is not None):
        floors = {key[1]: items for key, items in groups.items() if key and key[0] == frame}
        yield from _floor_locations(frame, floors, ground, freqs, spectrum.damping, floor_motions)


def _floor_locations(
    frame: ShearFrame,
    floors: dict[int, list[Item]],
    ground: Ensemble,
    freqs: np.ndarray,
    damping: float,
    floor_motions: str,
) -> Iterator[_Location]:
    """The locations on the floors of one frame (``floors``: floor -> its items), from one pass
    through the frame (rescaled to the ground's A_gx for ``"paper"``); their source of the
    available S_v is the response spectrum of the floor motions at ``freqs`` [Hz], one floor
    at a time (the spectra's lane layout holds two more copies of the motions it is given)."""
    ensembles = frame.floor_ensembles(ground)
    for floor, items in floors.items():
        m = ensembles[floor].scaled(ground.agx) if floor_motions == "paper" else ensembles[floor]
        yield _Location(
            items, response_spectrum(m.acc, ground.dt, freqs, damping), m, m.agx / ground.agx
        )


#: A dataset variable before assembly: values, units ("" for none) and long name.
_Variables = dict[str, tuple[Any, str, str]]


def _screen_location(
    location: _Location,
    band_hz: Sequence[float],
    settings: _MonteCarlo,
    risk: _Risk | None,
) -> xr.Dataset:
    """The screening dataset (dimension ``item``) of the items at one location."""
    blocks = [it.block for it in location.items]
    e = _restitution(location.items)
    physics = with_body_friction(settings.physics or Physics(), location.items)
    settings = dataclasses.replace(settings, physics=physics)
    variables = _item_variables(location.items, physics)
    variables.update(_eq11_variables(location, band_hz))
    variables.update(_monte_carlo_variables(blocks, e, location, settings))
    if risk is not None:
        variables.update(_annual_rates(blocks, e, location.motions, risk, settings))
    states = {} if settings.limit_states is None else limit_state_coords(settings.limit_states)
    second = {"limit_state_probability": "limit_state", "response_share": "response"}
    return xr.Dataset(
        {
            k: (
                ("item", second.get(k, ""))[: np.ndim(v)],
                np.asarray(v),
                {"units": u, "long_name": ln} if u else {"long_name": ln},
            )
            for k, (v, u, ln) in variables.items()
        },
        coords={"item": [it.name for it in location.items], "response": list(RESPONSES), **states},
    )


def _item_variables(items: list[Item], physics: Physics) -> _Variables:
    """What the inventory says of each item: location, geometry, restitution, and the friction
    simulated (``physics``: the location's, with the items' own friction)."""
    blocks = [it.block for it in items]
    friction = [physics.friction(i) for i in range(len(items))]
    mu, mu_k = (np.array([math.nan if f[j] is None else f[j] for f in friction]) for j in (0, 1))
    return {
        "location": ([it.location for it in items], "", "ground or floor N of FRAME"),
        "floor": ([it.floor for it in items], "", "floor (0: ground)"),
        "frame": ([it.frame.name if it.frame else "" for it in items], "", "shear frame"),
        "height": ([b.H for b in blocks], "m", "height H"),
        "width": ([b.B for b in blocks], "m", "width B"),
        "R": ([b.R for b in blocks], "m", "size parameter R"),
        "gamma": ([b.gamma for b in blocks], "1", "slenderness H/B"),
        "e": ([it.e for it in items], "1", "coefficient of restitution"),
        "mu": (mu, "1", "static friction coefficient simulated (NaN: infinite)"),
        "mu_k": (mu_k, "1", "kinetic friction coefficient simulated (NaN: infinite)"),
    }


def _eq11_variables(location: _Location, band_hz: Sequence[float]) -> _Variables:
    """Housner's energy balance (Eq. 11) of the items against the location's available S_v."""
    energy = assess(
        [it.block for it in location.items],
        location.source,
        band_hz=band_hz,
        damping=location.source.damping,
        names=[it.name for it in location.items],
    )
    return {
        "sv_required": (energy["sv_required"].values, "m s-1", "required S_v, Eq. (11)"),
        "sv_available": (
            energy["sv_available"].values,
            "m s-1",
            "max PSV at the location in the band",
        ),
        "margin": (energy["margin"].values, "1", "sv_required / sv_available - 1 (> 0: safe)"),
        "eq11_verdict": (energy["verdict"].values, "", "Eq. (11) verdict (conservative screen)"),
    }


def _monte_carlo_variables(
    blocks: list[Block], e: float | np.ndarray, location: _Location, settings: _MonteCarlo
) -> _Variables:
    """The overturning probability at the design level and the ground A_gx50 of the items.

    The location's motions are at the design level: their mean PGA is ``location.ratio`` × the
    design A_gx [g]. They scale linearly with the ground (linear frame), so the A_gx50 search
    runs on the motions' own A_gx with resolution and upper end × ``ratio`` and is reported in
    ground A_gx.
    """
    motions, ratio = location.motions, location.ratio
    options: dict[str, Any] = dict(physics=settings.physics, e=e, compute=settings.compute)

    def at_design(limit_states, members: bool = False) -> xr.Dataset:
        return overturning_probability(
            blocks,
            motions,
            [motions.agx],
            confidence=settings.confidence,
            limit_states=limit_states,
            members=members,
            **options,
        ).isel(agx=0)

    with reusing():  # the limit states read the outcomes of the overturning run
        mc = at_design(None, members=True)  # with every motion's outcome: the responses
        states = None if settings.limit_states is None else at_design(settings.limit_states)
        a50 = (
            agx_50(
                blocks,
                motions,
                resolution=settings.search.resolution * ratio,
                agx_max=settings.search.agx_max * ratio,
                search=settings.search,
                **options,
            )["agx50"].values
            / ratio
        )
    extra: _Variables = {}
    if states is not None:
        extra["limit_state_probability"] = (
            states["probability"].values,
            "1",
            "probability of the limit state at the design A_gx",
        )
    return {
        **extra,
        "probability": (mc["probability"].values, "1", "overturning probability at design A_gx"),
        "ci_low": (mc["ci_low"].values, "1", "Wilson interval, lower end"),
        "ci_high": (mc["ci_high"].values, "1", "Wilson interval, upper end"),
        "overturned": (mc["count"].values, "", "motions that overturn the item"),
        "n_motions": (mc["n"].values, "", "motions"),
        "agx50": (a50, "g", "ground A_gx at 50 % overturning probability"),
        **_response_variables(mc, settings),
    }


def responses(overturned: ArrayLike, uplift: ArrayLike, peak_slip: ArrayLike) -> np.ndarray:
    """The response of a block to each motion, an index into :data:`RESPONSES`, from the batched
    kernel's outcome (:class:`rocking.dynamics.batch.Outcome`): "overturn" if it overturned,
    else "slide-rock" if it both left rest (``uplift``: rocked or lifted off) and slid
    (``peak_slip`` [m] > 0, not necessarily at the same time), "rock" or "slide" if it did only
    one of them, "rest" if neither."""
    slid = np.asarray(peak_slip, dtype=float) > 0.0
    rocked = np.asarray(uplift, dtype=bool)
    index = np.where(rocked, np.where(slid, 3, 2), np.where(slid, 1, 0))
    return np.where(np.asarray(overturned, dtype=bool), len(RESPONSES) - 1, index)


def response_shares(overturned: ArrayLike, uplift: ArrayLike, peak_slip: ArrayLike) -> np.ndarray:
    """The share [-] of the motions (the last axis of the outcomes, as for :func:`responses`)
    of each of :data:`RESPONSES` (the last axis of the result)."""
    kinds = responses(overturned, uplift, peak_slip)
    counts = np.count_nonzero(kinds[..., None] == np.arange(len(RESPONSES)), axis=-2)
    return counts / kinds.shape[-1]


def standing_slip(
    overturned: ArrayLike,
    peak_slip: ArrayLike,
    statistic: Callable[[np.ndarray], Any] = np.max,
) -> np.ndarray:
    """``statistic`` (default the largest) of the peak slip [m] over the motions (the last axis)
    that do not overturn the block (the slip of one that does is that up to its fall), per
    leading index; NaN where every motion overturns it."""
    ov = np.asarray(overturned, dtype=bool)
    slip = np.asarray(peak_slip, dtype=float)
    rows = zip(ov.reshape(-1, ov.shape[-1]), slip.reshape(-1, ov.shape[-1]))
    values = [float(statistic(s[~o])) if not o.all() else math.nan for o, s in rows]
    return np.array(values).reshape(ov.shape[:-1])


def _response_variables(members: xr.Dataset, settings: _MonteCarlo) -> _Variables:
    """The response of each item at the design level, from the outcomes of its motions
    (``members``: ``overturned``, ``uplift``, ``peak_slip``, ``peak_lift`` on (body, member),
    of :func:`rocking.overturning_probability` with ``members=True``): the share of each of
    :data:`RESPONSES`, the most frequent (the most severe of a tie), the share of flights, the
    median and largest peak slip, and with ``settings.max_slip`` the probability of the
    verdict (:data:`SLIP_RULE`)."""
    ov, slip = members["overturned"].values, members["peak_slip"].values
    share = response_shares(ov, members["uplift"].values, slip)
    mode = [RESPONSES[len(RESPONSES) - 1 - int(np.argmax(row[::-1]))] for row in share]
    variables: _Variables = {
        "response_share": (share, "1", "share of the motions of each response at design A_gx"),
        "mode": (mode, "", "most frequent response at design A_gx"),
        "flight_share": (
            np.mean(members["peak_lift"].values > 0.0, axis=1),
            "1",
            "share of the motions in which the base leaves the ground",
        ),
        "slip_median": (
            standing_slip(ov, slip, np.median),
            "m",
            "median peak slip over the motions that leave the item standing",
        ),
        "slip_max": (
            standing_slip(ov, slip),
            "m",
            "largest peak slip over the motions that leave the item standing",
        ),
    }
    if settings.max_slip is None:
        return variables
    limit = settings.max_slip
    n = np.full(len(ov), ov.shape[1])
    slid = np.count_nonzero(slip >= limit, axis=1)
    failed = np.count_nonzero(ov | (slip >= limit), axis=1)
    low, high = wilson_interval(failed, n, settings.confidence)
    variables.update(
        slip_probability=(slid / n, "1", f"P(peak slip >= {limit:g} m) at design A_gx"),
        failure_probability=(
            failed / n,
            "1",
            f"P(overturn or peak slip >= {limit:g} m) at design A_gx",
        ),
        failure_ci_low=(low, "1", "Wilson interval, lower end"),
        failure_ci_high=(high, "1", "Wilson interval, upper end"),
    )
    return variables


def _annual_rates(
    blocks: list[Block],
    e: float | np.ndarray,
    motions: Ensemble,
    risk: _Risk,
    settings: _MonteCarlo,
) -> _Variables:
    """Fragility against the hazard's IM of the ground motion and the annual rate of every item
    at one location (``motions``: the location's motions at the design level, member i the
    response to the ground motion i, whose IM is ``risk.ground_im[i]``)."""
    hazard = risk.hazard
    levels = portable.geomspace(hazard.values[0], hazard.values[-1], N_RISK_LEVELS)
    curves = fragility_analysis(
        blocks,
        motions,
        im=hazard.im.name,
        levels=np.array([float(f"{x:.6g}") for x in levels]),
        im_values=risk.ground_im,
        physics=settings.physics,
        e=e,
        compute=settings.compute,
        n_boot=0,
    )
    rate = np.full(len(blocks), np.nan)
    for b in range(len(blocks)):
        median, beta = float(curves["median"][b]), float(curves["beta"][b])
        if math.isfinite(median) and math.isfinite(beta):
            fit = LognormalFit(median, beta, im=hazard.im.name, unit=hazard.im.unit)
            rate[b] = annual_rate(fit, hazard).annual_rate
    return {
        "fragility_median": (curves["median"].values, hazard.im.unit, f"median {hazard.im.label}"),
        "fragility_beta": (curves["beta"].values, "1", "lognormal dispersion"),
        "annual_rate": (rate, "yr-1", "mean annual rate of overturning"),
        "p_years": (
            -portable.expm1(-rate * risk.years),
            "1",
            f"P(overturning in {risk.years:g} years)",
        ),
    }


def _restitution(items: list[Item]) -> float | np.ndarray:
    """One e for all items when they agree, else one per item [-]."""
    e = np.array([it.e for it in items])
    return float(e[0]) if np.all(e == e[0]) else e


def _ranked(ds: xr.Dataset) -> xr.Dataset:
    """``ds`` with ``verdict`` and ``at_risk``, sorted most at risk first: highest probability
    of the verdict (with ``max_slip``, of overturning or that slip), then of overturning at the
    design A_gx, then lowest A_gx50, then lowest margin."""
    failure = "failure_probability" if "failure_probability" in ds else "probability"
    high = "failure_ci_high" if "failure_probability" in ds else "ci_high"
    rule = VERDICT_RULE if failure == "probability" else f"{VERDICT_RULE}; {SLIP_RULE}"
    ds["verdict"] = (
        "item",
        verdicts(ds[failure].values, ds[high].values),
        {"long_name": f"verdict from the Monte Carlo probability ({rule})"},
    )
    ds["at_risk"] = (ds["verdict"] == AT_RISK).assign_attrs(
        long_name=f"{ds[failure].attrs['long_name']} >= {100 * RISK_PROBABILITY:g} %"
    )
    order = np.lexsort(
        (
            ds["margin"].values,
            np.nan_to_num(ds["agx50"].values, nan=np.inf),
            -ds["probability"].values,
            -ds[failure].values,
        )
    )
    return ds.isel(item=order)


def verdicts(probability: ArrayLike, ci_high: ArrayLike) -> np.ndarray:
    """The verdict of each item of a screening, from its simulated overturning probability at
    the design A_gx and the upper end of its Wilson interval [-] (:data:`VERDICT_RULE`):
    "at risk", "borderline" or "not at risk"."""
    p = np.asarray(probability, dtype=float)
    high = np.asarray(ci_high, dtype=float)
    return np.where(
        p >= RISK_PROBABILITY,
        AT_RISK,
        np.where(high >= RISK_PROBABILITY, BORDERLINE, NOT_AT_RISK),
    ).astype(object)


#: Entry of :func:`eq11_vs_monte_carlo` when Eq. (11) and the simulation agree.
AGREE = "agree"


def eq11_vs_monte_carlo(
    verdict: ArrayLike, probability: ArrayLike, ci_low: ArrayLike, ci_high: ArrayLike
) -> np.ndarray:
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


def eq11_vs_monte_carlo_note(band_hz: Sequence[float] = BAND_HZ) -> str:
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


def results_table(ds: xr.Dataset) -> pd.DataFrame:
    """The screening result as a table (pandas DataFrame) in the dataset's order: the verdict
    (:data:`VERDICT_RULE`) and the Monte Carlo results first (with ``max_slip``, the probability
    of the verdict after it), the response at the design level (the most frequent of
    :data:`RESPONSES`, the share of each, of flights, and the median and largest peak slip in
    mm of the motions that leave the item standing), then Eq. (11) (S_v in cm/s) and whether
    it agrees with the Monte Carlo (:func:`eq11_vs_monte_carlo`), for CSV files and reports."""
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
            "mu_k [-]": ds["mu_k"].values,
            "verdict": ds["verdict"].values,
            "P(overturn) [-]": ds["probability"].values,
            "CI low [-]": ds["ci_low"].values,
            "CI high [-]": ds["ci_high"].values,
            "Agx50 [g]": ds["agx50"].values,
            "mode": ds["mode"].values,
            **{
                f"P({r}) [-]": ds["response_share"].sel(response=r).values
                for r in RESPONSES[:-1]  # (the last, overturn, is P(overturn))
            },
            "P(flight) [-]": ds["flight_share"].values,
            "median slip if standing [mm]": 1e3 * ds["slip_median"].values,
            "max slip if standing [mm]": 1e3 * ds["slip_max"].values,
            "Sv required [cm/s]": 100.0 * ds["sv_required"].values,
            "Sv available [cm/s]": 100.0 * ds["sv_available"].values,
            "margin [-]": ds["margin"].values,
            "Eq. (11) screen": ds["eq11_verdict"].values,
            "Eq. (11) vs Monte Carlo": eq11_vs_monte_carlo(
                ds["eq11_verdict"].values,
                ds["probability"].values,
                ds["ci_low"].values,
                ds["ci_high"].values,
            ),
        }
    )
    if "failure_probability" in ds:
        limit = f"{ds.attrs['max_slip']:g} m"
        failure = {
            f"P(slip >= {limit}) [-]": ds["slip_probability"].values,
            f"P(overturn or slip >= {limit}) [-]": ds["failure_probability"].values,
            "its CI low [-]": ds["failure_ci_low"].values,
            "its CI high [-]": ds["failure_ci_high"].values,
        }
        at = list(table.columns).index("verdict") + 1
        for offset, (column, values) in enumerate(failure.items()):
            table.insert(at + offset, column, values)
    if "limit_state_probability" in ds:
        for j, name in enumerate(ds["limit_state"].values):
            table[f"P({name}) [-]"] = ds["limit_state_probability"].values[:, j]
    if "annual_rate" in ds:
        unit = ds["fragility_median"].attrs.get("units", "")
        table[f"fragility median [{unit}]"] = ds["fragility_median"].values
        table["fragility beta [-]"] = ds["fragility_beta"].values
        table["annual rate [1/yr]"] = ds["annual_rate"].values
        table[f"P in {ds.attrs['years']:g} yr [-]"] = ds["p_years"].values
    return table


__all__ = [
    "RESPONSES",
    "SLIP_RULE",
    "VERDICT_RULE",
    "eq11_vs_monte_carlo",
    "eq11_vs_monte_carlo_note",
    "response_shares",
    "responses",
    "results_table",
    "screen",
    "standing_slip",
    "verdicts",
]
