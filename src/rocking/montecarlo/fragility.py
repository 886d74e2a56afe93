"""Fragility of bodies against any intensity measure, from any suite of motions (issue 16, part 2):
incremental dynamic analysis (IDA), multiple-stripe analysis (MSA) and cloud analysis, each with a
lognormal fragility fitted by maximum likelihood (Baker 2015) and bootstrap confidence intervals
(:func:`rocking.bootstrap_fragility`), and the ranking of intensity measures by how well they
predict overturning (:func:`im_efficiency`).

* IDA: every motion is scaled, on its own, so that its IM equals each level in turn
  (:mod:`rocking.montecarlo.engine`: per-motion scale factors (level/IM)^(1/k), k the IM's
  scaling exponent); the paper's A_gx (``im="agx"``) scales all motions by one factor instead,
  to the ensemble's mean PGA (:func:`rocking.overturning_probability`).
* MSA: stripes given as (IM level, motion, scale factor) rows; each stripe's motions scaled by
  their factors, the outcome counted at the stripe's level.
* Cloud: the motions as they are, each motion's outcome against its own IM; the probabilities
  shown for cloud analysis are those of bins of equal count (the fit uses every motion).
"""

from __future__ import annotations

import math
import os
import warnings
from collections.abc import Callable, Iterable, Sequence
from dataclasses import dataclass
from typing import TYPE_CHECKING, Any

import numpy as np
import pandas as pd
import xarray as xr
from numpy.typing import ArrayLike

from ..core import portable
from ..core.checks import finite_array, in_range, record
from ..defaults import AGX, N_BOOT, N_BOOT_EFFICIENCY, G
from ..dynamics.batch import block_list
from ..dynamics.limits import OVERTURN, LimitState, limit_state_coords, parse_limit_states
from ..dynamics.physics import FROM_PHYSICS, Physics, as_physics
from ..errors import InputError
from ..motions.ensemble import Ensemble
from ..motions.intensity import IntensityMeasure, intensity_measures, parse_im
from .backends import Compute
from .engine import LEVEL_UNIT, Engine, level_agx, level_key
from .statistics import (
    _FIT_BLOCK_ELEMENTS,
    CROSSING_TOLERANCE,
    Crossing,
    CrossingWarning,
    ExtrapolationWarning,
    FragilityFit,
    Interval,
    LognormalFit,
    _bootstrap_resamples,
    _fit_rows,
    _mle,
    bootstrap_fragility,
    bootstrap_limit_states,
    fit_lognormal,
    severity_order,
    wilson_interval,
)

if TYPE_CHECKING:
    from ..dynamics.body import Block

#: Methods of :func:`fragility_analysis`.
METHODS = ("ida", "msa", "cloud")


@dataclass(frozen=True)
class AnalysisIM:
    """The intensity measure of an analysis: A_gx (``name`` "agx", the ensemble's mean PGA [g],
    ``measure`` None) or one of :func:`rocking.intensity_measures` (``measure``); ``label``
    names it with its unit, ``exponent`` is how it grows with a scale factor."""

    name: str
    label: str
    unit: str
    exponent: int
    measure: IntensityMeasure | None

    @classmethod
    def parse(cls, im: str | IntensityMeasure, *, per_body: bool = False) -> AnalysisIM:
        """From ``"agx"`` or any form of :func:`rocking.parse_im`; the per-body IMs
        (PGA/(g tan α), ...) only with ``per_body`` (not as the IM of a fragility analysis,
        whose levels are the same for every body)."""
        if isinstance(im, str) and im.strip().lower() == AGX:
            return cls(AGX, "A_gx (mean PGA of the ensemble) [g]", "g", 1, None)
        m = parse_im(im)
        if m.per_body and not per_body:
            instead = (
                f": analyse the fragility against {m.dimensional} and compare {m.name} with "
                "im_efficiency (--im-efficiency)"
                if m.dimensional
                else "; scaling does not change it either: it cannot be the IM of a fragility "
                "analysis"
            )
            raise InputError(
                f"im {m.name} is per body, so one level of it is a different motion for each "
                f"body{instead}"
            )
        return cls(m.name, m.label, m.unit, m.scaling_exponent, m)

    @property
    def per_body(self) -> bool:
        """True for the IMs whose value depends on the body (PGA/(g tan α), ...)."""
        return self.measure is not None and self.measure.per_body

    def of_motions(self, ensemble: Ensemble, body: Block | None = None, g: float = G) -> np.ndarray:
        """The IM of every motion as it is (A_gx: the PGA of each motion) [unit], for ``body``
        under gravity ``g`` [m/s²] if it is per body."""
        if self.measure is None:
            return ensemble.pga
        return intensity_measures(ensemble, [self.measure], body=body, g=g).iloc[:, 0].to_numpy()


def _checked_levels(levels, unit: str) -> np.ndarray:
    x = finite_array("levels", np.atleast_1d(levels), ndim=(1,))
    if np.any(x < LEVEL_UNIT):
        raise InputError(f"levels must be >= {LEVEL_UNIT:g} {unit}, got {x[x < LEVEL_UNIT][0]}")
    return np.array([level_agx(level_key(v)) for v in x.tolist()])


def read_stripes(
    stripes: pd.DataFrame | str | os.PathLike[str], ensemble: Ensemble
) -> pd.DataFrame:
    """The stripes of a multiple-stripe analysis, checked against the ensemble.

    Parameters
    ----------
    stripes : DataFrame, str or Path
        Rows (``level``, ``motion``, ``scale``): the stripe's IM level [the IM's unit], a motion
        of the ensemble (its label, or its position 0 … n − 1) and the factor that scales it in
        that stripe [-]; a CSV file with that header.  Every stripe holds the same number of
        motions (so that the bootstrap resamples whole motions of equal weight).
    ensemble : Ensemble

    Returns
    -------
    DataFrame
        Columns ``level`` (float), ``member`` (position in the ensemble, int), ``scale``.
    """
    if isinstance(stripes, pd.DataFrame):
        table, where = stripes.copy(), "stripes"
    else:
        where = str(stripes)
        try:
            table = pd.read_csv(stripes, dtype={"motion": str}, comment="#", skipinitialspace=True)
        except (OSError, ValueError, pd.errors.ParserError) as exc:
            raise InputError(f"{where}: cannot read the stripes ({exc})") from None
    table.columns = [str(c).strip().lower() for c in table.columns]
    missing = {"level", "motion", "scale"} - set(table.columns)
    if missing:
        raise InputError(f"{where}: need columns level, motion, scale; missing {sorted(missing)}")
    if table.empty:
        raise InputError(f"{where}: no stripes")
    position = {label: i for i, label in enumerate(ensemble.labels)}
    members = []
    for row, (motion, level, scale) in enumerate(
        zip(table["motion"], table["level"], table["scale"]), start=1
    ):
        text = str(motion).strip()
        if text in position:
            members.append(position[text])
        elif text.isdigit() and int(text) < ensemble.n:
            members.append(int(text))
        else:
            raise InputError(f"{where}: row {row}: no motion {text!r} in the ensemble")
        for name, value in (("level", level), ("scale", scale)):
            try:
                ok = math.isfinite(float(value)) and float(value) > 0.0
            except (TypeError, ValueError):
                ok = False
            if not ok:
                raise InputError(f"{where}: row {row}: {name} must be a number > 0, got {value!r}")
    out = pd.DataFrame(
        {
            "level": table["level"].astype(float),
            "member": members,
            "scale": table["scale"].astype(float),
        }
    )
    sizes = out.groupby("level").size()
    if sizes.nunique() > 1:
        raise InputError(
            f"{where}: every stripe must hold the same number of motions, got "
            + ", ".join(f"{n} at {lv:g}" for lv, n in sizes.items())
        )
    return out


#: The keyword options of :func:`fragility_analysis` and their defaults.
_ANALYSIS_OPTIONS: dict[str, Any] = {
    "confidence": 0.95,
    "n_boot": N_BOOT,
    "seed": 0,
    "im_values": None,
}


def fragility_analysis(
    blocks: Block | Sequence[Block],
    ensemble: Ensemble,
    *,
    im: str | IntensityMeasure = AGX,
    method: str = "ida",
    levels: ArrayLike | None = None,
    stripes: pd.DataFrame | str | os.PathLike[str] | None = None,
    physics: Physics | None = None,
    compute: Compute | None = None,
    limit_states: str | Sequence[str | LimitState] | None = None,
    **options: Any,
) -> xr.Dataset:
    """Fragility curves of bodies against an intensity measure, from IDA, MSA or cloud analysis:
    of overturning, or of each of several limit states on the response.

    Parameters
    ----------
    blocks : Block or sequence of Block
        The bodies (one Block: a list of one).
    ensemble : Ensemble
        The motions [m/s²]: generated (:func:`rocking.generate`) or imported records
        (:meth:`rocking.Ensemble.from_records`, ``rocking motions import``).
    im : str
        ``"agx"`` (the paper's A_gx [g], default) or any form of :func:`rocking.parse_im`, e.g.
        ``"pgv"`` [m/s], ``"sa(1.0)"`` [g].
    method : {"ida", "msa", "cloud"}
        Incremental dynamic analysis (``levels``), multiple-stripe analysis (``stripes``) or
        cloud analysis (the motions as they are).
    levels : array_like, optional
        IDA: IM levels [the IM's unit], > 0.
    stripes : DataFrame, str or Path, optional
        MSA: (level, motion, scale) rows (:func:`read_stripes`).
    physics, compute :
        As for :func:`rocking.overturning_probability`.
    limit_states : str or sequence of str or LimitState, optional
        Limit states on the response (below).
    **options
        Keyword arguments ``confidence``, ``n_boot``, ``seed`` and ``im_values`` (below); and
        ``e``, ``overturn_angle``, ``g``, ``impacts``: shorthands for physics's fields, one
        release, and ``mu``, ``mu_k`` (friction coefficients [-], one value or one per block;
        issue 45); ``backend``, ``out``, ``progress``, ``chunk_size``: for compute's.  Any other
        keyword is an InputError.
    confidence : float
        Keyword (in ``options``; default 0.95).
        Level of the Wilson intervals and of the bootstrap intervals, in (0, 1) [-].
    n_boot : int
        Keyword (in ``options``; default :data:`rocking.defaults.N_BOOT`): bootstrap resamples
        of the motions for the intervals of median and β (≥ 0; 0: the point fit only,
        intervals NaN).
    seed : int
        Keyword (in ``options``; default 0): seed of the bootstrap (the simulations draw
        nothing at random).
    im_values : array_like, optional
        Keyword (in ``options``).  IDA and cloud: the IM of each motion as given [the IM's
        unit], instead of the IM computed from the motions themselves. For floor motions,
        give the IM of the ground motions they respond to: a linear building's floor motion
        scales with its ground motion, so the curves are then against the ground's IM (what
        a site hazard curve gives).
    limit_states
        Limit states on the response (:class:`~rocking.LimitState`, or their text form, e.g.
        ``"uplift, theta/alpha>=0.5, overturn"``), each with its probabilities and fit from the
        same simulations, along a last dimension ``limit_state`` (coordinates ``quantity``,
        ``threshold``); the variables ``overturned`` / ``overturned_motion`` are then named
        ``exceeded`` / ``exceeded_motion``.  Each limit state is fitted alone (its own median and
        β, as overturning alone is); where the curves of two nested limit states (each
        exceeded in every case a severer one is: uplift, θ/α ≥ x and overturning always are)
        cross inside the intensities tested, the severer the likelier by more than 1e-3
        (:data:`~rocking.montecarlo.statistics.CROSSING_TOLERANCE`), they are refitted
        together under the constraint that they do not
        (:func:`~rocking.montecarlo.statistics.bootstrap_limit_states`), flagged in
        ``fit_constrained`` (per body and limit state).  Every crossing of the own fits is
        reported by a :class:`~rocking.montecarlo.statistics.CrossingWarning` naming body and
        states, and in ``crossing_excess`` (of the severer state).  A state that the
        intensity separates (uplift, nearly a step) keeps a β near its lower bound without
        changing the others' β.  Whether the states are nested: attribute ``fits``.  None
        (default): overturning alone, without that dimension.

    Returns
    -------
    xarray.Dataset
        Dimensions (body, level[, member]): ``probability``, ``count``, ``n``, ``ci_low``,
        ``ci_high`` (Wilson) and, for IDA and MSA, ``overturned`` (body, level, member); for
        cloud, ``overturned`` and ``im_value`` per (body, member) / member.  Per body: the
        lognormal fit ``median`` [the IM's unit] and ``beta`` [-] with their bootstrap intervals
        ``median_low``, ``median_high``, ``beta_low``, ``beta_high`` (NaN where no motion or
        every motion overturned: nothing to fit), ``median_extrapolated`` (bool: the median
        lies at or outside the intensities tested, an extrapolation; each such body also gets
        an :class:`~rocking.montecarlo.statistics.ExtrapolationWarning`).  Attributes ``im``,
        ``im_label``, ``im_unit``, ``method``, ``confidence``, ``n_boot``, ``seed``.
    """
    blocks = block_list(blocks)  # one Block is a list of one
    if not isinstance(ensemble, Ensemble):
        raise InputError(f"ensemble must be a rocking Ensemble, got {type(ensemble).__name__}")
    measure = AnalysisIM.parse(im)
    method = str(method).strip().lower()
    if method not in METHODS:
        raise InputError(f"method must be one of {', '.join(METHODS)}, got {method!r}")
    confidence, n_boot, seed, im_values = (
        options.pop(name, default) for name, default in _ANALYSIS_OPTIONS.items()
    )
    confidence = in_range("confidence", confidence, 0.0, 1.0, lo_open=True, hi_open=True)
    if not (isinstance(n_boot, int) and n_boot >= 0):
        raise InputError(f"n_boot must be an integer >= 0, got {n_boot!r}")
    compute = record(Compute, compute, options, "compute")
    physics = as_physics(physics, **options)
    states = None if limit_states is None else parse_limit_states(limit_states)
    settings: dict[str, Any] = dict(physics=physics, compute=compute)
    if method == "ida":
        if levels is None:
            raise InputError("method 'ida' needs levels (the IM values to scale the motions to)")
        if stripes is not None:
            raise InputError("stripes belong to method 'msa', not 'ida'")
        own = _im_values(ensemble, measure, im_values)
        levels = _checked_levels(levels, measure.unit)
        build = _ida(blocks, ensemble, measure, levels, own, settings)
    elif method == "msa":
        if stripes is None:
            raise InputError("method 'msa' needs stripes (level, motion, scale rows)")
        if levels is not None:
            raise InputError("method 'msa' takes its levels from the stripes, not from levels")
        build = _msa(blocks, ensemble, measure, read_stripes(stripes, ensemble), settings)
    else:
        if levels is not None or stripes is not None:
            raise InputError("method 'cloud' uses the motions as they are: no levels or stripes")
        own = _im_values(ensemble, measure, im_values)
        build = _cloud(blocks, ensemble, measure, own, settings)

    def counted(state: LimitState) -> xr.Dataset:
        ds = build(state)
        low, high = wilson_interval(ds["count"].values, ds["n"].values, confidence)
        ds["probability"] = ds["count"] / ds["n"]
        ds["ci_low"] = (("body", "level"), low, {"units": "1"})
        ds["ci_high"] = (("body", "level"), high, {"units": "1"})
        return ds

    fit: tuple[str, AnalysisIM, int, float, int] = (method, measure, n_boot, confidence, seed)
    if states is None:
        ds = counted(OVERTURN)
        _add_fits(ds, *fit)
    else:
        ds = _limit_states([counted(ls) for ls in states], states, fit)
    ds["level"].attrs.update(units=measure.unit, long_name=measure.label)
    ds.attrs.update(
        im=measure.name,
        im_label=measure.label,
        im_unit=measure.unit,
        method=method,
        confidence=confidence,
        n_boot=n_boot,
        seed=seed,
        g=physics.g,
    )
    return ds


def _coords(blocks, table) -> dict:
    return {
        "body": ("body", [b.label for b in blocks]),
        "R": ("body", [b.R for b in blocks], {"units": "m"}),
        "gamma": ("body", [b.gamma for b in blocks], {"units": "1"}),
        "e": ("body", table.e, {"units": "1", "long_name": "coefficient of restitution"}),
    }


def _outcomes(
    engine: Engine, keys: list[tuple[int, int]], nb: int, state: LimitState
) -> np.ndarray:
    """(body, len(keys), motions) flags of (case, level key) pairs: the limit state exceeded."""
    return np.array(
        [[state.exceeded(engine.results[(c, b, k)]) for c, k in keys] for b in range(nb)]
    )


def _limit_states(
    parts: list[xr.Dataset], states, fit: tuple[str, AnalysisIM, int, float, int]
) -> xr.Dataset:
    """The datasets of each limit state along a last dimension ``limit_state``, with their
    fitted curves (:func:`_add_fits`)."""
    names = {"overturned": "exceeded", "overturned_motion": "exceeded_motion"}
    ds = xr.concat(parts, dim="limit_state", data_vars="all", coords="minimal", compat="override")
    ds = ds.rename({k: v for k, v in names.items() if k in ds}).assign_coords(
        limit_state_coords(states)
    )
    if "im_value" in ds:  # the motions' intensities: the same for every limit state
        ds["im_value"] = ds["im_value"].isel(limit_state=0, drop=True)
    _add_fits(ds, *fit, states=states)
    return ds.transpose(..., "limit_state")


def _add_fits(
    ds: xr.Dataset,
    method: str,
    measure: AnalysisIM,
    n_boot: int,
    confidence: float,
    seed: int,
    states: Sequence[LimitState] | None = None,
) -> None:
    """The lognormal fit of each body (``median``, ``beta``, their bootstrap intervals,
    ``n_unfitted``, ``median_extrapolated``), and of each limit state if ``states`` are given
    (dimensions (limit_state, body), and ``fit_constrained``): one by one
    (:func:`_fit_one`), or, for nested limit states, each alone unless two cross inside the
    intensities tested (:func:`~rocking.montecarlo.statistics.bootstrap_limit_states`).  One
    warning per extrapolated median and per crossing refitted."""
    key = "overturned_motion" if method == "cloud" else "overturned"
    if states is None:
        flags = ds[key].values[None]  # (state, body, ...)
    else:
        flags = ds[key.replace("overturned", "exceeded")].transpose("limit_state", ...).values
    nested = states is not None and not severity_order(flags)[1]
    ns, nb = flags.shape[0], ds.sizes["body"]
    labels = [""] if states is None else [f" ({ls.name})" for ls in states]
    depth = 3 if states is None else 4  # the warnings point at the caller of fragility_analysis
    names = ("median", "beta", "median_low", "median_high", "beta_low", "beta_high")
    table = np.full((ns, nb, len(names)), np.nan)
    unfitted = np.zeros((ns, nb), dtype=np.int64)
    extrapolated = np.zeros((ns, nb), dtype=bool)
    constrained = np.zeros((ns, nb), dtype=bool)
    excess = np.zeros((ns, nb))
    for b in range(nb):
        body = ds["body"].values[b]
        if method == "cloud":
            x = ds["im_value"].values
            keep = x > 0.0  # (a motion of zero intensity has no logarithm; it cannot overturn)
            x, y = x[keep], flags[:, b][:, keep]
        else:
            x, y = ds["level"].values, flags[:, b]
        if np.unique(x).size < 2:
            continue
        if nested:
            joint = bootstrap_limit_states(
                x,
                y,
                n_boot=n_boot,
                confidence=confidence,
                seed=seed,
                measure=measure.name,
                unit=measure.unit,
            )
            fits, constrained[:, b] = joint.fits, joint.constrained
            for cross in joint.crossings:
                excess[cross.severer, b] = cross.excess
                text = _crossing_text(body, states, cross, measure.unit)
                warnings.warn(text, CrossingWarning, stacklevel=depth)
        else:
            fits = [_fit_one(x, one, measure, n_boot, confidence, seed) for one in y]
        for i, fit in enumerate(fits):
            if fit is None:
                continue
            table[i, b] = (fit.median, fit.beta, *fit.median_ci, *fit.beta_ci)
            unfitted[i, b] = fit.n_unfitted
            extrapolated[i, b] = fit.extrapolated
            if fit.extrapolated and fit.fit.im_range is not None:
                lo, hi = fit.fit.im_range
                warnings.warn(
                    f"body {body}{labels[i]}: the fitted median {fit.median:.3g} "
                    f"{measure.unit} lies at or outside the intensities tested ({lo:.3g} to "
                    f"{hi:.3g} {measure.unit}), an extrapolation: extend the levels",
                    ExtrapolationWarning,
                    stacklevel=depth,
                )
    dims: tuple[str, ...] = ("body",) if states is None else ("limit_state", "body")
    part = (lambda a: a[0]) if states is None else (lambda a: a)
    for j, name in enumerate(names):
        unit = "1" if name.startswith("beta") else measure.unit
        ds[name] = (dims, part(table[:, :, j]), {"units": unit})
    ds["n_unfitted"] = (
        dims,
        part(unfitted),
        {"long_name": "bootstrap resamples with nothing to fit"},
    )
    ds["median_extrapolated"] = (
        dims,
        part(extrapolated),
        {"long_name": "median at or outside the intensities tested (an extrapolation)"},
    )
    if states is not None:
        ds["fit_constrained"] = (
            dims,
            constrained,
            {
                "long_name": "fitted under the constraint that nested curves do not cross "
                "inside the intensities tested (its own fit crossed a neighbour's)"
            },
        )
        ds["crossing_excess"] = (
            dims,
            excess,
            {
                "units": "1",
                "long_name": "largest excess of the state's own fit over its milder "
                "neighbour's inside the intensities tested (0: no crossing)",
            },
        )
        ds.attrs["fits"] = (
            "each limit state alone; nested curves that crossed refitted without crossing"
            if nested
            else "each limit state alone (not nested)"
        )


def _crossing_text(body, states, cross: Crossing, unit: str) -> str:
    """The warning of a crossing of two limit states' own fits: refitted without it, or kept
    (below :data:`~rocking.montecarlo.statistics.CROSSING_TOLERANCE`)."""
    milder, severer = states[cross.milder].name, states[cross.severer].name
    where = (
        f"cross at {cross.at:.3g} {unit}, inside the intensities tested"
        if math.isfinite(cross.at)
        else "lie reversed across the intensities tested"
    )
    done = (
        "refitted under the constraint that they do not cross there (fit_constrained)"
        if cross.excess > CROSSING_TOLERANCE
        else f"kept, as this is below the data's resolution ({CROSSING_TOLERANCE:g})"
    )
    return (
        f"body {body}: the curves of {severer} and of the milder {milder}, each fitted alone, "
        f"{where} ({severer} the likelier by up to {cross.excess:.2g}, which nested data "
        f"cannot be): {done}"
    )


def _im_values(ensemble: Ensemble, measure: AnalysisIM, given) -> np.ndarray | None:
    """The IM of each motion: ``given`` (checked), else computed (None for A_gx, whose
    motions are all scaled by one factor)."""
    if given is None:
        return None if measure.measure is None else measure.of_motions(ensemble)
    if measure.measure is None:
        raise InputError("im_values are IMs of single motions; A_gx is the ensemble's mean PGA")
    values = finite_array("im_values", given, ndim=(1,))
    if values.shape != (ensemble.n,):
        raise InputError(f"im_values must give one value per motion ({ensemble.n})")
    return values


def _refuse_lifting(ensemble: Ensemble, factors: np.ndarray, what: str, physics: Physics) -> None:
    """InputError when a motion's vertical component, multiplied by its largest scale factor
    ``factors`` [-] (one per motion), reaches −g: the block would leave the ground, which only
    the model with friction (``physics`` with a μ for every block, issue 45) allows."""
    mu = physics.mu if isinstance(physics.mu, tuple) else (physics.mu,)
    if ensemble.av is None or None not in mu:
        return
    low = factors * ensemble.av.min(axis=1) / G
    bad = np.flatnonzero(low <= -1.0)
    if bad.size:
        i = bad[np.argmin(low[bad])]
        raise InputError(
            f"{what}: motion {ensemble.labels[i]!r} scaled by {factors[i]:.3g} has a vertical "
            f"acceleration reaching {low[i]:.2f} g ({bad.size} of {ensemble.n} motions reach "
            "-g): the block would leave the ground, which is not modelled without friction; "
            "give a friction coefficient mu (--mu), lower the levels or leave the vertical "
            "components out (motions import --horizontal-only)"
        )


def _ida(
    blocks, ensemble, measure: AnalysisIM, levels: np.ndarray, own, options: dict
) -> Callable[[LimitState], xr.Dataset]:
    nb = len(blocks)
    if measure.exponent == 0:
        raise InputError(
            f"{measure.name} does not change when a motion is scaled, so motions cannot be "
            "scaled to its levels: use method 'cloud' for it"
        )
    basis = None if own is None else [own]
    if basis is not None and not np.all(basis[0] > 0.0):
        zero = [ensemble.labels[i] for i in np.flatnonzero(~(basis[0] > 0.0))]
        raise InputError(f"motions with {measure.name} = 0 cannot be scaled: {zero[:5]}")
    base = np.full(ensemble.n, ensemble.agx) if basis is None else basis[0]
    top = (levels.max() / base) ** (1.0 / measure.exponent)
    what = f"{measure.name} = {levels.max():g} {measure.unit}"
    _refuse_lifting(ensemble, top, what, options["physics"])
    engine = Engine(
        blocks, [ensemble], desc="IDA", basis=basis, exponent=measure.exponent, **options
    )
    engine.require_memory(nb * levels.size * 2, "levels")
    keys = [(0, level_key(v)) for v in levels.tolist()]
    with engine:
        engine.run([(0, b, k) for b in range(nb) for _, k in keys])
    return lambda state: _outcome_dataset(
        blocks, engine, levels, _outcomes(engine, keys, nb, state), list(ensemble.labels)
    )


def _msa(
    blocks, ensemble, measure: AnalysisIM, stripes: pd.DataFrame, options: dict
) -> Callable[[LimitState], xr.Dataset]:
    nb = len(blocks)
    groups = list(stripes.groupby("level", sort=True))
    largest = np.zeros(ensemble.n)
    np.maximum.at(largest, stripes["member"].to_numpy(), stripes["scale"].to_numpy())
    _refuse_lifting(ensemble, largest, "stripes", options["physics"])
    cases = [ensemble.subset(rows["member"].to_numpy()) for _, rows in groups]
    # level 1 of a case whose basis is 1/scale gives each motion exactly its factor
    basis = [1.0 / rows["scale"].to_numpy() for _, rows in groups]
    engine = Engine(blocks, cases, desc="MSA", basis=basis, exponent=1, **options)
    engine.require_memory(nb * len(cases) * 2, "stripes")
    one = level_key(1.0)
    with engine:
        engine.run([(c, b, one) for c in range(len(cases)) for b in range(nb)])
    levels = np.array([level for level, _ in groups], dtype=float)
    keys = [(c, one) for c in range(len(cases))]
    members = list(range(cases[0].n))
    return lambda state: _outcome_dataset(
        blocks, engine, levels, _outcomes(engine, keys, nb, state), members
    )


def _outcome_dataset(blocks, engine, levels, flags, members) -> xr.Dataset:
    count = flags.sum(axis=2).astype(np.int64)
    return xr.Dataset(
        {
            "overturned": (("body", "level", "member"), flags),
            "count": (("body", "level"), count, {"long_name": "motions that overturn the body"}),
            "n": (("body", "level"), np.full(count.shape, flags.shape[2], dtype=np.int64)),
        },
        coords={**_coords(blocks, engine.table), "level": levels, "member": members},
        attrs=dict(engine.stats),
    )


def _cloud(
    blocks, ensemble, measure: AnalysisIM, own, options: dict
) -> Callable[[LimitState], xr.Dataset]:
    nb = len(blocks)
    values = ensemble.pga if own is None else own
    engine = Engine(
        blocks, [ensemble], desc="cloud", basis=[np.ones(ensemble.n)], exponent=1, **options
    )
    one = level_key(1.0)
    with engine:
        engine.run([(0, b, one) for b in range(nb)])
    return lambda state: _cloud_dataset(
        blocks, ensemble, measure, engine, values, _outcomes(engine, [(0, one)], nb, state)[:, 0, :]
    )


def _cloud_dataset(blocks, ensemble, measure: AnalysisIM, engine, values, flags) -> xr.Dataset:
    """The dataset of a cloud analysis from its ``flags`` (body, motion)."""
    nb = len(blocks)
    # probabilities shown in bins of about equal count (ten motions or more each), at the
    # geometric mean IM of the bin; the fit uses every motion
    order = np.argsort(values, kind="stable")
    bins = np.array_split(order, max(1, min(10, ensemble.n // 10)))
    positive = values > 0.0
    levels = np.array([math.exp(np.mean(portable.log(values[i][positive[i]]))) for i in bins])
    count = np.array([[int(flags[b, i].sum()) for i in bins] for b in range(nb)], dtype=np.int64)
    n = np.broadcast_to(np.array([i.size for i in bins], dtype=np.int64), count.shape).copy()
    return xr.Dataset(
        {
            "overturned_motion": (("body", "member"), flags),
            "im_value": ("member", values, {"long_name": f"{measure.label} of each motion"}),
            "count": (("body", "level"), count),
            "n": (("body", "level"), n),
        },
        coords={
            **_coords(blocks, engine.table),
            "level": levels,
            "member": list(ensemble.labels),
        },
        attrs=dict(engine.stats),
    )


def _fit_one(
    x: np.ndarray, y: np.ndarray, measure: AnalysisIM, n_boot: int, confidence: float, seed: int
) -> FragilityFit | None:
    """The bootstrap fit of outcomes ``y`` (levels × motions, or one per motion of a cloud) at
    intensities ``x`` [the IM's unit], or None when they hold no information on the median
    (never or always exceeded)."""
    if not y.any() or y.all() or np.unique(x).size < 2:
        return None
    if n_boot == 0:  # the point fit only
        counts = y.sum(axis=-1) if y.ndim == 2 else y
        fit = fit_lognormal(
            x,
            counts.astype(np.int64),
            y.shape[-1] if y.ndim == 2 else 1,
            measure=measure.name,
            unit=measure.unit,
        )
        nan = Interval(math.nan, math.nan)
        return FragilityFit(fit, nan, nan, confidence, 0, seed, 0, 0)
    return bootstrap_fragility(
        x,
        y,
        n_boot=n_boot,
        confidence=confidence,
        seed=seed,
        measure=measure.name,
        unit=measure.unit,
    )


#: The ``body`` of :func:`im_efficiency`'s rows of the fit to all bodies at once.
POOLED = "all bodies (pooled)"


def im_efficiency(
    blocks: Block | Sequence[Block],
    ensemble: Ensemble,
    ims: str | Iterable[str | IntensityMeasure],
    *,
    levels: ArrayLike | None,
    scale_im: str | IntensityMeasure = "pga",
    names: Iterable[str] | None = None,
    n_boot: int = N_BOOT_EFFICIENCY,
    seed: int = 0,
    confidence: float = 0.95,
    **options: Any,
) -> pd.DataFrame:
    """Rank intensity measures by how well they predict overturning: the dispersion β of the
    lognormal fragility fitted against each of them (smaller: more efficient), per body and,
    for several bodies, of one fragility of all bodies pooled.

    One IDA scales every motion to each of ``levels`` of ``scale_im``; every (motion, scale)
    run is then a point of a cloud whose intensity, for each IM of ``ims``, is
    factor^k·IM(motion) (k its scaling exponent; an IM that does not scale, such as PGV/PGA or
    Ω, is refused: compare it by cloud analysis of unscaled records).  A lognormal fitted by
    maximum likelihood to each cloud (:func:`rocking.fit_lognormal`, one trial per point) gives
    β; its bootstrap interval resamples whole motions.  With more than one body, the runs of
    all bodies also make one cloud per IM (rows ``body`` = :data:`POOLED`): the β of a
    fragility meant for bodies of any size.

    The per-body IMs ``pga/gtana`` = PGA/(g tan α) and ``pgv*p/gtana`` = PGV·p/(g tan α)
    (:func:`rocking.intensity_measures`) are, for one body, PGA and PGV times a constant: a
    lognormal's β does not change when its variable is multiplied by a constant, so their
    per-body β is that of PGA and PGV (said in the ``note`` of those rows).  Only the pooled
    rows compare them: rocking depends on the motion only through a_g/(g tan α) and the time
    p·t (Makris & Konstantinidis 2003, "The rocking spectrum and the limitations of practical
    design methodologies", Earthq. Eng. Struct. Dyn. 32; Dimitrakopoulos & DeJong 2012,
    "Revisiting the rocking block: closed-form solutions and similarity laws", Proc. R. Soc.
    A 468), so they remove the size of the bodies that PGA and PGV leave in the pooled cloud.

    Parameters
    ----------
    blocks : Block or sequence of Block
    ensemble : Ensemble
    ims : sequence of str
        The IMs compared (forms of :func:`rocking.parse_im`, per-body ones included).
    levels : array_like
        Levels of ``scale_im`` [its unit] that span the bodies' fragility.
    scale_im : str
        The IM the motions are scaled by (default PGA; not a per-body IM).
    names : sequence of str, optional
        Names of the bodies in the table (default: their labels, e.g. "R=1.22 m, γ=4").
    n_boot, seed, confidence :
        Bootstrap of the β intervals (n_boot 0: no intervals).
    **options :
        As for :func:`fragility_analysis` (e, g, physics, backend, out, progress, …); the
        per-body IMs use the gravity g of the simulations.

    Returns
    -------
    DataFrame
        One row per (body, IM), sorted by body then β, then, for several bodies, the pooled
        rows sorted by β: ``body``, ``im``, ``label``, ``unit``, ``median`` [the IM's unit],
        ``beta``, ``beta_low``, ``beta_high``, ``note``.
    """
    parsed = efficiency_measures(ims)
    blocks = block_list(blocks)
    bodies = [b.label for b in blocks] if names is None else [str(n) for n in names]
    if len(bodies) != len(blocks):
        raise InputError(f"names has {len(bodies)} names for {len(blocks)} bodies")
    if POOLED in bodies:
        raise InputError(f"names: {POOLED!r} names the rows of the pooled fit, not a body")
    if not (isinstance(n_boot, int) and n_boot >= 0):
        raise InputError(f"n_boot must be an integer >= 0, got {n_boot!r}")
    with warnings.catch_warnings():  # of the fits below, which are not used: only the runs
        warnings.simplefilter("ignore", ExtrapolationWarning)
        ida = fragility_analysis(
            blocks, ensemble, im=scale_im, method="ida", levels=levels, n_boot=0, **options
        )
    g = as_physics(options.get("physics"), g=options.get("g", FROM_PHYSICS)).g
    scaled_by = AnalysisIM.parse(scale_im)
    base = scaled_by.of_motions(ensemble)
    factors = ida["level"].values[:, None] / base[None, :]  # (level, motion)
    if scaled_by.exponent == 2:
        factors = np.sqrt(factors)
    resamples = _bootstrap_resamples(seed, n_boot, ensemble.n)
    y = ida["overturned"].values  # (body, level, motion)
    shared = {m.name: m.of_motions(ensemble) for m in parsed if not m.per_body}
    x = np.array(  # (body, IM, level, motion): each run's intensity
        [
            [
                (shared[m.name] if m.name in shared else m.of_motions(ensemble, block, g))[None, :]
                * factors**m.exponent
                for m in parsed
            ]
            for block in blocks
        ]
    )
    table = pd.DataFrame(
        [
            _efficiency_row(body, m, x[b, i], y[b], resamples, confidence)
            for b, body in enumerate(bodies)
            for i, m in enumerate(parsed)
        ]
    ).sort_values(["body", "beta"], kind="stable", ignore_index=True)
    if len(blocks) == 1:
        return table
    n_runs = y.shape[0] * y.shape[1]  # the pooled cloud: (body·level, motion)
    pooled = pd.DataFrame(
        [
            _efficiency_row(
                POOLED,
                m,
                x[:, i].reshape(n_runs, -1),
                y.reshape(n_runs, -1),
                resamples,
                confidence,
                note=f"{len(blocks)} bodies in one fit",
            )
            for i, m in enumerate(parsed)
        ]
    ).sort_values("beta", kind="stable", ignore_index=True)
    return pd.concat([table, pooled], ignore_index=True)


def efficiency_measures(ims: str | Iterable[str | IntensityMeasure]) -> list[AnalysisIM]:
    """The IMs :func:`im_efficiency` can compare, parsed (per-body ones included), or an
    :class:`~rocking.errors.InputError` naming the one that cannot be (one that scaling does
    not change)."""
    items = [ims] if isinstance(ims, (str, IntensityMeasure)) else list(ims)
    parsed = [AnalysisIM.parse(i, per_body=True) for i in items]
    if not parsed:
        raise InputError("ims must name at least one intensity measure")
    for measure in parsed:
        if measure.exponent == 0:
            # every scaled copy of a motion has the motion's own value: the cloud of scaled
            # runs would mix outcomes of many intensities at one value of this IM
            raise InputError(
                f"{measure.name} does not change when a motion is scaled, so its efficiency "
                "cannot be measured on scaled motions: compare it by cloud analysis of the "
                "unscaled records (fragility_analysis(..., method='cloud'))"
            )
    return parsed


def _efficiency_row(
    body: str, measure: AnalysisIM, x, y, resamples, confidence, note: str = ""
) -> dict:
    """:func:`im_efficiency`'s row of one cloud (intensities ``x`` and outcomes ``y``, of
    shape (run, motion)): the fit against the IM and the β interval of its bootstrap
    ``resamples`` of the motions."""
    fit = _cloud_fit(x, y)
    betas_ok = _cloud_betas(x, y, resamples)
    q = ((1 - confidence) / 2, (1 + confidence) / 2)
    low, high = np.quantile(betas_ok, q) if betas_ok.size else (math.nan, math.nan)
    dimensional = None if measure.measure is None else measure.measure.dimensional
    if not note and dimensional is not None:
        note = (
            f"for one body {measure.name} is {dimensional} times a constant: the β of {dimensional}"
        )
    return {
        "body": body,
        "im": measure.name,
        "label": measure.label,
        "unit": measure.unit,
        "median": math.nan if fit is None else fit.median,
        "beta": math.nan if fit is None else fit.beta,
        "beta_low": low,
        "beta_high": high,
        "note": note,
    }


def _cloud_betas(x: np.ndarray, y: np.ndarray, resamples: np.ndarray) -> np.ndarray:
    """β of :func:`_cloud_fit` of every resample of the motions (rows of ``resamples``, the
    motions' indices) that has information on the median, all fitted at once; x and y of
    shape (level, motion). A resample's β is the one _cloud_fit gives it alone."""
    if not np.all(x > 0.0):  # points left out: resamples of different sizes, one at a time
        fits = [_cloud_fit(x[:, j], y[:, j]) for j in resamples]
        return np.array([f.beta for f in fits if f is not None])
    betas = [np.empty(0)]
    step = max(1, _FIT_BLOCK_ELEMENTS // x.size)  # resamples at a time (memory)
    for block in (resamples[i : i + step] for i in range(0, len(resamples), step)):
        # (resample, level, motion), each resample's points in the order of x[:, j].ravel()
        xb = np.transpose(x[:, block], (1, 0, 2)).reshape(len(block), -1)
        yb = np.transpose(y[:, block], (1, 0, 2)).reshape(len(block), -1)
        some = np.any(yb, axis=1) & ~np.all(yb, axis=1)
        xb, yb = portable.log(xb[some]), yb[some].astype(float)
        betas.append(_fit_rows(xb, yb, np.ones(yb.shape))[1])
    return np.concatenate(betas)


def _cloud_fit(x: np.ndarray, y: np.ndarray) -> LognormalFit | None:
    """Maximum-likelihood lognormal of (intensity, outcome) points, one trial each (None: no
    information on the median): :func:`rocking.fit_lognormal`'s fit, without its checks of
    counts that are 0/1 here by construction."""
    x, y = x.ravel(), y.ravel()
    keep = x > 0.0
    x, y = x[keep], y[keep]
    if not y.any() or y.all():
        return None
    return _mle(portable.log(x), y.astype(float), np.ones(x.size))
