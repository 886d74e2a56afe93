"""Overturning probability and the A_gx of 50 % probability (paper Sections 6–8).

For a body and an ensemble of motions scaled so that its mean PGA is A_gx (``ensemble.scaled``),
the probability of overturning is the fraction of the motions that overturn it (paper Figs. 9–11,
13).  :func:`overturning_probability` computes it on a grid of A_gx with a Wilson score interval
and :func:`agx_50` searches the A_gx of 50 % probability adaptively (paper Section 8, Figs.
15–16), both with the engine of :mod:`rocking.montecarlo.engine`.
"""

from __future__ import annotations

import math
from collections.abc import Sequence
from typing import TYPE_CHECKING, Any

import numpy as np
import xarray as xr
from numpy.typing import ArrayLike

from ..core.checks import finite_array, in_range, positive, record
from ..core.reuse import key_of, recall, remember
from ..dynamics.batch import QUANTITIES, BlockTable, block_list
from ..dynamics.limits import OVERTURN, LimitState, limit_state_coords, parse_limit_states
from ..dynamics.physics import Physics
from ..errors import InputError
from ..motions.ensemble import Ensemble
from .backends import Compute
from .engine import LEVEL_UNIT, Engine, level_agx, level_key
from .search import Agx50Search, CrossingSearch
from .statistics import wilson_interval

if TYPE_CHECKING:
    from ..dynamics.body import Block


#: The quantities of each motion's Outcome returned besides ``overturned`` and ``peak`` (by
#: :func:`member_outcomes` and ``overturning_probability(members=True)``), under their
#: Outcome's names: whether the body rocked at all, and with friction its slip [m] and lift [m].
_MEMBER_QUANTITIES = ("uplift", "peak_slip", "residual_slip", "peak_lift")


def _cases(ensemble) -> tuple[list[str] | None, list[Ensemble]]:
    """(case labels or None, ensembles) from an Ensemble or a dict label -> Ensemble."""
    items: list[tuple[str | None, Ensemble]]
    if isinstance(ensemble, Ensemble):
        items = [(None, ensemble)]
    elif isinstance(ensemble, dict) and ensemble:
        items = [(str(k), v) for k, v in ensemble.items()]
    else:
        raise InputError(
            "ensemble must be a rocking Ensemble or a non-empty dict label -> "
            f"Ensemble, got {type(ensemble).__name__}"
        )
    for label, ens in items:
        where = "ensemble" if label is None else f"ensemble[{label!r}]"
        if not isinstance(ens, Ensemble):
            raise InputError(f"{where} must be a rocking Ensemble, got {type(ens).__name__}")
        if ens.agx == 0.0:
            raise InputError(f"{where} has only zero motions: it cannot be scaled to an agx")
    labels = None if items[0][0] is None else [str(label) for label, _ in items]
    return labels, [ens for _, ens in items]


def _dataset(
    blocks,
    table: BlockTable,
    labels,
    data_vars: dict,
    coords: dict,
    attrs: dict,
    bodies: Sequence[int] | None = None,
) -> xr.Dataset:
    """Labelled result; ``data_vars`` values have a leading case axis, dropped for one ensemble.
    ``bodies``: the indices of the blocks (and rows of ``table``) the result holds (default
    all)."""
    lead = () if labels is None else ("case",)
    dvars = {}
    for name, (dims, values, vattrs) in data_vars.items():
        values = values[0] if labels is None else values
        dvars[name] = (lead + dims, values, vattrs)
    at = list(range(len(blocks))) if bodies is None else list(bodies)
    blocks = [blocks[b] for b in at]
    all_coords = {
        "body": ("body", [b.label for b in blocks]),
        "R": ("body", [b.R for b in blocks], {"units": "m", "long_name": "size parameter R"}),
        "gamma": ("body", [b.gamma for b in blocks], {"units": "1", "long_name": "H/B"}),
        "e": ("body", table.e[at], {"units": "1", "long_name": "coefficient of restitution"}),
        "overturn_angle": ("body", table.theta_ov[at], {"units": "rad"}),
        **coords,
    }
    if labels is not None:
        all_coords["case"] = ("case", labels)
    return xr.Dataset(dvars, coords=all_coords, attrs={"g": table.g, **attrs})


def overturning_probability(
    blocks: Block | Sequence[Block],
    ensemble: Ensemble | dict[str, Ensemble],
    agx: ArrayLike,
    *,
    physics: Physics | None = None,
    compute: Compute | None = None,
    confidence: float = 0.95,
    members: bool = False,
    limit_states: str | Sequence[str | LimitState] | None = None,
    **shorthands: Any,
) -> xr.Dataset:
    """Probability that each body overturns (or exceeds each of ``limit_states``), as a
    function of the ensemble intensity A_gx.

    At each A_gx the ensemble is scaled so that its mean PGA equals A_gx
    (``ensemble.scaled(agx)``) and every body is simulated under every motion.

    Parameters
    ----------
    blocks : Block or sequence of Block
        The bodies (one Block: a list of one).
    ensemble : Ensemble or dict of str -> Ensemble
        The motions [m/s²] (ground or floor); a dict gives a leading ``case`` dimension
        (e.g. floors, durations, intensity functions).
    agx : array_like
        Intensities A_gx [g], > 0.
    physics : Physics, optional
        The physics (:class:`~rocking.Physics`; default ``Physics()``): restitution e [-] and
        overturning angle [rad] (one for all bodies or one per body), g [m/s²], impact scheme.
    compute : Compute, optional
        How to compute (:class:`~rocking.montecarlo.backends.Compute`; none of it changes the
        results): the backend (default: this process, all cores), ``out``, a folder for
        finished chunks (a later call with the same bodies, motions and physics computes only
        what the folder lacks, after a kill or for new A_gx levels; a folder of another run is
        refused), the progress bar and the chunk size (chunks hold whole (body, A_gx) pairs).
    confidence : float
        Level of the Wilson interval, in (0, 1) [-].
    members : bool
        Also return the outcome of every motion (dimension ``member``; for a dict, all
        ensembles must have the same number of motions): see Returns.
    limit_states : str or sequence of str or LimitState, optional
        Limit states on the response (:class:`~rocking.LimitState`, or their text form, e.g.
        ``"uplift, theta/alpha>=0.5, overturn"``): the probability of each, from the same
        simulations, along a last dimension ``limit_state`` (coordinates ``quantity``,
        ``threshold``).  None (default): overturning, without that dimension.
    **shorthands
        ``e``, ``overturn_angle``, ``g``, ``impacts``: shorthands for physics's fields, one
        release, and ``mu``, ``mu_k`` (friction coefficients [-], one value or one per block;
        issue 45); ``backend``, ``out``, ``progress``, ``chunk_size``: for compute's.  Any other
        keyword is an InputError.

    Returns
    -------
    xarray.Dataset
        Dimensions ([case,] body, agx[, member]); ``probability`` [-], ``count`` (motions that
        overturned the body), ``n`` (motions), ``ci_low``/``ci_high`` (Wilson) [-], and with
        ``members``: ``overturned`` (bool), ``peak`` = max|θ|/α [-], ``uplift`` (bool: the
        body rocked at all), ``peak_slip`` = max|slip| [m], ``residual_slip`` = |slip| at the
        end [m] and ``peak_lift``, the largest lift of the base [m] (the last three 0 without
        friction, ``mu`` None).  Coordinates ``body`` (labels), ``R`` [m], ``gamma`` [-],
        ``e`` [-], ``overturn_angle`` [rad] on body, ``agx`` [g].  Attributes: ``g`` [m/s²],
        ``confidence``, and how many chunks were computed / loaded from ``out``
        (``chunks_computed``, ``chunks_loaded``).
    """
    labels, cases = _cases(ensemble)
    levels = _levels(agx)
    confidence = in_range("confidence", confidence, 0.0, 1.0, lo_open=True, hi_open=True)
    states = None if limit_states is None else parse_limit_states(limit_states)
    if members:
        _same_size(cases, "members=True")
    blocks = block_list(blocks)  # one Block is a list of one
    nb = len(blocks)
    engine, keys = _run_levels(
        blocks,
        cases,
        [levels] * nb,
        "P(overturn)",
        nb * len(levels) * (2 if members else 1),
        dict(physics=physics, compute=compute, **shorthands),
    )
    data_vars = _probability_vars(engine, keys, confidence, states)
    coords: dict[str, Any] = {
        "agx": (
            "agx",
            np.array([level_agx(k) for k in levels]),
            {"units": "g", "long_name": "mean PGA of the ensemble"},
        ),
        **({} if states is None else limit_state_coords(states)),
    }
    if members:
        data_vars.update(_member_vars(engine, keys))
        coords["member"] = _member_coord(labels, cases)
    return _dataset(
        blocks, engine.table, labels, data_vars, coords, {"confidence": confidence, **engine.stats}
    )


def member_outcomes(
    blocks: Block | Sequence[Block],
    ensemble: Ensemble | dict[str, Ensemble],
    agx: ArrayLike,
    *,
    physics: Physics | None = None,
    compute: Compute | None = None,
    bodies: Sequence[int] | None = None,
    **shorthands: Any,
) -> xr.Dataset:
    """What each motion does to each body (overturns it, rocks it, slides it), every body at
    intensities of its own.

    The outcomes of :func:`overturning_probability` with ``members=True`` for one body at a
    time (the same simulations, bit for bit), computed in one batch: a study that needs each
    body at its own A_gx (e.g. at its A_gx50) makes one call instead of one per body.

    Parameters
    ----------
    blocks : Block or sequence of Block
        The bodies (one Block: a list of one).
    ensemble : Ensemble or dict of str -> Ensemble
        The motions [m/s²]; a dict gives a leading ``case`` dimension (ensembles with the same
        number of motions).
    agx : array_like, shape (n_bodies,) or (n_bodies, n_levels)
        Intensities A_gx [g], > 0, of each body: one per body, or a row per body (with
        ``bodies``: per body of ``bodies``).
    bodies : sequence of int, optional
        The indices in ``blocks`` of the bodies to simulate (default: all), e.g. those whose
        A_gx50 a search found; the result holds these only.  The others stay in the run's
        fingerprint, so that a chunk folder ``out`` of a call with all of ``blocks`` (e.g. of
        :func:`agx_50`) serves and its simulations are loaded, not made again.
    physics, compute, **shorthands :
        As for :func:`overturning_probability` (``e``, ``overturn_angle``, ``g``, ``impacts``,
        ``mu``, ``mu_k``: shorthands for physics's fields; ``backend``, ``out``, ``progress``,
        ``chunk_size``: for compute's).

    Returns
    -------
    xarray.Dataset
        Dimensions ([case,] body, level, member): ``overturned`` (bool), ``peak`` =
        max|θ|/α [-], ``uplift``, ``peak_slip`` [m], ``residual_slip`` [m] and ``peak_lift``
        [m] as :func:`overturning_probability` gives them; coordinate ``agx`` (body, level)
        [g], the intensities simulated (each rounded to the engine's level unit, as
        :func:`overturning_probability` rounds them); body coordinates and attributes as for
        :func:`overturning_probability`.
    """
    labels, cases = _cases(ensemble)
    _same_size(cases, "member_outcomes")
    blocks = block_list(blocks)  # one Block is a list of one
    at = _body_indices(bodies, len(blocks))
    nb = len(at)
    values = np.asarray(agx, dtype=float)
    if values.ndim == 1:
        values = values[:, None]
    if values.ndim != 2 or values.shape[0] != nb:
        raise InputError(
            f"agx must hold one level or one row of levels per body ({nb} bodies), "
            f"got shape {np.shape(agx)}"
        )
    levels = [_levels(row) for row in values]
    engine, keys = _run_levels(
        blocks,
        cases,
        dict(zip(at, levels)),
        "outcomes",
        values.size * 2,
        dict(physics=physics, compute=compute, **shorthands),
    )
    coords: dict[str, Any] = {
        "agx": (
            ("body", "level"),
            np.array([[level_agx(k) for k in row] for row in levels]),
            {"units": "g", "long_name": "mean PGA of the ensemble"},
        ),
        "member": _member_coord(labels, cases),
    }
    return _dataset(
        blocks,
        engine.table,
        labels,
        _member_vars(engine, keys, "level"),
        coords,
        engine.stats,
        bodies=at,
    )


def _body_indices(bodies: Sequence[int] | None, nb: int) -> list[int]:
    """The indices ``bodies`` of some of ``nb`` blocks (None: all), checked: at least one, each
    once, in range."""
    if bodies is None:
        return list(range(nb))
    at = list(bodies)
    valid = all(isinstance(b, (int, np.integer)) and 0 <= b < nb for b in at)
    if not at or not valid or len(set(at)) < len(at):
        raise InputError(
            f"bodies must hold indices of the blocks (0 to {nb - 1}), at least one, each once, "
            f"got {at}"
        )
    return [int(b) for b in at]


def _run_levels(
    blocks,
    cases: list[Ensemble],
    levels: list[list[int]] | dict[int, list[int]],
    desc: str,
    pairs: int,
    options: dict,
) -> tuple[Engine, list]:
    """Every motion of every case at the level keys ``levels[b]`` of each body b (a list: of
    every body; a dict: of the bodies it holds, the others not simulated), on an engine made
    with ``options`` (refused first if ``pairs`` (body, level) pairs per case would not fit in
    memory); returns the engine and the keys, nested [case][body][level]."""
    engine = Engine(blocks, cases, desc=desc, **options)
    engine.require_memory(pairs, "agx")
    per_body = dict(enumerate(levels)) if isinstance(levels, list) else levels
    keys = [[[(c, b, k) for k in ks] for b, ks in per_body.items()] for c in range(len(cases))]
    with engine:
        engine.run([k for per_case in keys for per_body in per_case for k in per_body])
    return engine, keys


def _same_size(cases: list[Ensemble], what: str) -> None:
    """Refuse ensembles of different numbers of motions for ``what`` (one member axis)."""
    if len({ens.n for ens in cases}) > 1:
        raise InputError(f"{what} needs ensembles with the same number of motions")


def _member_coord(labels, cases: list[Ensemble]) -> tuple:
    """The ``member`` coordinate: the motions' labels for one ensemble, their indices for a
    dict of ensembles (of the same size)."""
    return ("member", list(cases[0].labels) if labels is None else np.arange(cases[0].n))


def _levels(agx) -> list[int]:
    """The level keys of the intensities ``agx`` [g] (checked: finite, one axis, >= LEVEL_UNIT)."""
    agx = finite_array("agx", np.atleast_1d(agx), ndim=(1,))
    if np.any(agx < LEVEL_UNIT):
        raise InputError(f"agx must be >= {LEVEL_UNIT:g} g, got {agx[agx < LEVEL_UNIT][0]}")
    return [level_key(a) for a in agx.tolist()]


def _probability_vars(
    engine: Engine, keys: list, confidence: float, states: Sequence[LimitState] | None = None
) -> dict[str, Any]:
    """``probability``, ``count``, ``n`` and the Wilson interval at every (case, body, level) of
    ``keys`` (nested [case][body][level]), from the engine's full counts: of overturning, or,
    with ``states``, of each limit state along a last dimension ``limit_state``."""
    count = np.array(
        [[[engine.counts(k, states or (OVERTURN,)) for k in pb] for pb in pc] for pc in keys],
        dtype=np.int64,
    )
    if states is None:
        count = count[..., 0]
        dims: tuple[str, ...] = ("body", "agx")
        what = "overturning probability", "motions that overturn the body"
    else:
        dims = ("body", "agx", "limit_state")
        what = "probability of the limit state", "motions that exceed the limit state"
    n = np.broadcast_to(
        np.array([ens.n for ens in engine.cases]).reshape(-1, *[1] * (count.ndim - 1)),
        count.shape,
    ).copy()
    low, high = wilson_interval(count, n, confidence)
    return {
        "probability": (dims, count / n, {"units": "1", "long_name": what[0]}),
        "count": (dims, count, {"long_name": what[1]}),
        "n": (dims, n, {"long_name": "motions"}),
        "ci_low": (dims, low, {"units": "1", "long_name": f"Wilson {confidence:g} lower bound"}),
        "ci_high": (dims, high, {"units": "1", "long_name": f"Wilson {confidence:g} upper bound"}),
    }


def _member_vars(engine: Engine, keys: list, level_dim: str = "agx") -> dict[str, Any]:
    """``overturned``, ``peak`` and the Outcome's other quantities (``uplift``,
    ``peak_slip``, ``residual_slip``, ``peak_lift``) of every motion at every (case, body,
    level) of ``keys`` (nested [case][body][level]; the levels' dimension named
    ``level_dim``)."""

    def of_motions(name: str) -> np.ndarray:
        return np.array(
            [[[getattr(engine.results[k], name) for k in pb] for pb in pc] for pc in keys]
        )

    dims = ("body", level_dim, "member")
    data = {
        "overturned": (dims, of_motions("overturned"), {}),
        "peak": (
            dims,
            of_motions("peak_theta_ratio"),
            {"units": "1", "long_name": "max |theta| / alpha"},
        ),
    }
    for name in _MEMBER_QUANTITIES:
        _dtype, unit, meaning = QUANTITIES[name]
        data[name] = (
            dims,
            of_motions(name),
            {"long_name": meaning, **({"units": unit} if unit else {})},
        )
    return data


def agx_50(
    blocks: Block | Sequence[Block],
    ensemble: Ensemble | dict[str, Ensemble],
    *,
    search: Agx50Search | None = None,
    physics: Physics | None = None,
    compute: Compute | None = None,
    members: bool = False,
    limit_states: str | Sequence[str | LimitState] | None = None,
    **shorthands: Any,
) -> xr.Dataset:
    """A_gx at which each body overturns (or exceeds each of ``limit_states``) with 50 %
    probability, by an adaptive grid search.

    The search runs on the grid A_k = k·resolution (k = 1 … K, K = ⌊agx_max/resolution⌋, values
    rounded to 12 decimals) with P(A_0 = 0) = 0.  With the counts of a finite ensemble, P(A) need
    not be monotone, so the result is defined by the search itself
    (:class:`rocking.montecarlo.search.CrossingSearch`):

    1. bracket: P is computed at ``coarse`` evenly spread levels (the last is K) in increasing
       order until P ≥ 0.5; the bracket is (previous coarse level or 0, that level).  If
       P < 0.5 at all of them, the result is NaN (not reached by ``agx_max``, or only between
       coarse levels);
    2. bisection on the integer levels inside the bracket, keeping P(lo) < 0.5 ≤ P(hi), until
       hi = lo + 1.

    The result A_hi is thus an upward crossing of 50 % on the grid: P(A_hi) ≥ 0.5 and
    P(A_hi − resolution) < 0.5 (``probability`` and ``probability_below``).  Where P is monotone
    on the grid it is the smallest grid A_gx with P ≥ 0.5.  P ≥ 0.5 means count ≥ n/2.  Each
    round evaluates one level for every body (and case) still searching, in batched calls:
    the motions are simulated, those likeliest to decide first (predicted from the body's other
    levels), only until the count has decided the comparison with n/2
    (:meth:`rocking.montecarlo.engine.Engine.at_least_half`), then
    every motion at the two levels whose probabilities are returned.  The result does not
    depend on this: ``exhaustive`` simulates every motion at every level visited instead.

    Parameters
    ----------
    blocks : Block or sequence of Block
        The bodies (one Block: a list of one).
    ensemble : Ensemble or dict of str -> Ensemble
        The motions [m/s²]; a dict gives a leading ``case`` dimension.
    search : Agx50Search, optional
        The search (:class:`~rocking.montecarlo.search.Agx50Search`): ``resolution``, the grid
        step of A_gx [g] (default 0.01 g, as the paper reads it), ``agx_max``, the largest A_gx
        searched [g] (default 5 g), ``coarse``, the levels of the bracketing round (default
        10), ``exhaustive`` (every motion at every level visited) and ``same_motions`` (the
        cases of a dict are the same motions in other forms).
    physics, compute :
        As for :func:`overturning_probability`.
    members : bool
        Also return whether each motion overturns the body at agx50 (the simulations the
        search made there; those of :func:`member_outcomes` at agx50, bit for bit).  Needs
        ensembles of the same number of motions.
    limit_states : str or sequence of str or LimitState, optional
        Limit states on the response (:class:`~rocking.LimitState`, or their text form, e.g.
        ``"uplift, theta/alpha>=0.5, overturn"``): the search above for each of them, P being
        the fraction of the motions that exceed it, along a last dimension ``limit_state``
        (coordinates ``quantity``, ``threshold``); with ``members``, ``overturned`` is then
        named ``exceeded`` (each state at its own agx50).  The states share their simulations:
        a motion simulated at a level for one state counts for every state there.  Of nested
        states (uplift, θ/α ≥ x, overturning) on the same motions, the less severe has the
        lower or equal agx50 (P of the less severe is at least P of the severer at every
        level, so its search brackets and bisects no later).  None (default): overturning,
        without that dimension.
    **shorthands
        ``resolution``, ``agx_max``, ``coarse``, ``exhaustive``, ``same_motions``: shorthands
        for search's fields; ``e``, ``overturn_angle``, ``g``, ``impacts``, ``mu``, ``mu_k``:
        for physics's; ``backend``, ``out``, ``progress``, ``chunk_size``: for compute's.

    Returns
    -------
    xarray.Dataset
        Dimension ([case,] body[, limit_state]): ``agx50`` [g] (NaN if not reached),
        ``probability`` at agx50 and ``probability_below`` at agx50 − resolution [-];
        coordinates as for :func:`overturning_probability`; attributes ``resolution``,
        ``agx_max`` [g].  With ``members``, ``overturned`` (bool, dimensions ([case,] body,
        member); False where agx50 is NaN) and the ``member`` coordinate as
        :func:`member_outcomes` gives them.
    """
    labels, cases = _cases(ensemble)
    search = record(Agx50Search, search, shorthands, "search")
    resolution = in_range("resolution", search.resolution, 1e-6, math.inf, unit="g")
    agx_max = positive("agx_max", search.agx_max, "g")
    K = math.floor(agx_max / resolution * (1.0 + 1e-12))
    if K < 1:
        raise InputError(f"agx_max ({agx_max:g} g) must be at least resolution ({resolution:g} g)")
    states = None if limit_states is None else parse_limit_states(limit_states)
    searched = (OVERTURN,) if states is None else states
    ns = len(searched)
    if members:
        _same_size(cases, "agx_50(members=True)")
    blocks = block_list(blocks)  # one Block is a list of one
    nb = len(blocks)
    engine = Engine(
        blocks,
        cases,
        desc="A_gx(50%)",
        physics=physics,
        compute=compute,
        same_motions=search.same_motions,
        **shorthands,
    )
    # a case's results depend on its own motions and the settings only (the other cases change
    # at most which motions decide first): inside rocking.core.reuse.reusing (e.g. in
    # reproduce, where the soundness section searches Section 8's ground motions again), a case
    # searched before is not searched again
    settings = (*engine.table.arrays(), K, resolution)  # the kernel's constants, the grid
    graded = tuple((ls.quantity, ls.threshold) for ls in searched)  # what is counted
    reuse = [
        None
        if members
        else key_of(
            "agx_50", (ens.sha256, *settings, search.coarse, engine.physics.fingerprint, graded)
        )
        for ens in cases
    ]
    known = {c: found for c, rk in enumerate(reuse) if (found := recall(rk)) is not None}
    todo = [c for c in range(len(cases)) if c not in known]
    # one search per (case, body, limit state)
    items = [(c, b, s) for c in todo for b in range(nb) for s in range(ns)]
    crossing = CrossingSearch(items, K, search.coarse)

    def key(c, b, k):  # the level key of grid level k (A_gx = k·resolution)
        return (c, b, level_key(round(k * resolution, 12)))

    engine.require_memory(nb * ns * crossing.max_levels, "resolution")
    with engine:
        engine.expect(crossing.typical_rounds * nb * ns * sum(cases[c].n for c in todo))
        while level := crossing.pending():  # one batch of simulations per round and state
            keys = {item: key(item[0], item[1], k) for item, k in level.items()}
            if search.exhaustive:
                engine.run(list(keys.values()))
            above: dict = {}
            for s, state in enumerate(searched):  # P(A_k) >= 0.5
                mine = {item: k for item, k in keys.items() if item[2] == s}
                decided = engine.at_least_half(list(mine.values()), state)
                above.update({item: decided[k] for item, k in mine.items()})
            crossing.update(above)
        hi = crossing.crossings()
        # the probabilities returned: every motion at the crossing and the level below it
        engine.run([key(c, b, k - j) for (c, b, _s), k in hi.items() for j in (0, 1) if k - j > 0])
    shape = (len(cases), nb, ns)
    agx50 = np.full(shape, np.nan)
    p_at = np.full(shape, np.nan)
    p_below = np.full(shape, np.nan)
    for (c, b, s), k in hi.items():
        agx50[c, b, s] = level_agx(key(c, b, k)[2])
        p_at[c, b, s] = engine.counts(key(c, b, k), [searched[s]])[0] / cases[c].n
        p_below[c, b, s] = (
            engine.counts(key(c, b, k - 1), [searched[s]])[0] / cases[c].n if k > 1 else 0.0
        )
    for c in todo:
        remember(reuse[c], (agx50[c], p_at[c], p_below[c]))
    for c, (a50, at, below) in known.items():
        agx50[c], p_at[c], p_below[c] = a50, at, below
    if states is None:  # overturning alone: no limit_state dimension
        agx50, p_at, p_below = (a[..., 0].copy() for a in (agx50, p_at, p_below))
        dims: tuple[str, ...] = ("body",)
        long_name = "A_gx of 50 % overturning probability"
    else:
        dims = ("body", "limit_state")
        long_name = "A_gx of 50 % probability of the limit state"
    data_vars: dict[str, tuple] = {
        "agx50": (dims, agx50, {"units": "g", "long_name": long_name}),
        "probability": (dims, p_at, {"units": "1", "long_name": "probability at agx50"}),
        "probability_below": (
            dims,
            p_below,
            {"units": "1", "long_name": "probability at agx50 - resolution"},
        ),
    }
    coords: dict[str, Any] = {} if states is None else limit_state_coords(states)
    if members:
        flags = np.zeros((*shape, cases[0].n), np.bool_)
        for (c, b, s), k in hi.items():
            flags[c, b, s] = engine.outcomes(key(c, b, k), searched[s])[0]
        if states is None:
            data_vars["overturned"] = (
                ("body", "member"),
                flags[:, :, 0],
                {"long_name": "the motion overturns the body at agx50"},
            )
        else:
            data_vars["exceeded"] = (
                ("body", "member", "limit_state"),
                np.moveaxis(flags, 2, -1),
                {"long_name": "the motion exceeds the limit state at its agx50"},
            )
        coords["member"] = _member_coord(labels, cases)
    return _dataset(
        blocks,
        engine.table,
        labels,
        data_vars,
        coords,
        {"resolution": resolution, "agx_max": agx_max, **engine.stats},
    )
