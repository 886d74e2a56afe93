"""The physical model of a simulation as one record: :class:`Physics` (issue 44, part 2).

What decides a rocking response besides the block and the motion: the impact rule (a
coefficient of restitution e, or Housner's rule), the angle that counts as overturning, gravity
and the impact scheme of the integrator.  The record travels unchanged from the command line
through the Monte Carlo engine to the kernels, which resolve it once per block
(:meth:`Physics.for_blocks`: ``e="housner"`` and ``overturn_angle="alpha"`` become numbers);
its :meth:`Physics.params` are part of the chunk store's fingerprint, taken from
``dataclasses.fields``, so that a field added later (friction μ, μ_k and flight of the
response-modes issue 45) cannot be left out of it.

The keyword arguments ``e``, ``overturn_angle``, ``g`` and ``impacts`` of the functions that
simulate stay as shorthands: :func:`as_physics` maps them into the record, in one place.
"""

from __future__ import annotations

import dataclasses
import hashlib
import json
from collections.abc import Iterable, Sequence
from typing import Any, cast

from ..core.checks import kinetic_friction, positive, restitution, unexpected
from ..defaults import DEFAULT_E, DEFAULT_MU, DEFAULT_MU_K, IMPACT_SCHEMES, OVERTURN_ANGLE, G
from ..errors import InputError
from .body import Block, resolve_e, resolve_overturn_angle
from .impacts import resolve_impacts


class _FromPhysics:
    """The default of a shorthand argument (:data:`SHORTHANDS`): the field of the call's
    :class:`Physics`."""

    def __repr__(self) -> str:
        return "<from physics>"


#: The default of every shorthand argument (None stays a value given, and refused as one).
FROM_PHYSICS: Any = _FromPhysics()
#: The keyword arguments that stand for fields of :class:`Physics`: today's four for one
#: release (issue 44), and friction's (issue 45), whose ``mu=`` reads as the issue writes it.
SHORTHANDS = ("e", "overturn_angle", "g", "impacts", "mu", "mu_k")


@dataclasses.dataclass(frozen=True)
class Physics:
    """The physical model of a rocking simulation (everything but the block and the motion).

    Parameters
    ----------
    e : float, "housner" or sequence
        Coefficient of restitution θ'⁺/θ'⁻ [-] in (0, 1] (the paper's 0.925 by default), or
        ``"housner"`` for 1 − 1.5·sin²α of each block (:meth:`Block.housner_e`); a sequence
        gives one value per block (batched runs).
    overturn_angle : float, "alpha" or sequence
        abs(θ) [rad] that counts as overturning, in (0, π/2]: π/2 (the paper) or ``"alpha"``;
        a sequence gives one value per block.
    g : float
        Gravity [m/s²].
    impacts : {"located", "step-end"}
        Impact handling of the integrator (:func:`rocking.simulate`).
    mu : float or sequence, optional
        Static friction coefficient μ_s [-] of the base (issue 45; :mod:`rocking.dynamics.modes`):
        the body may slide, slide-rock and fly.  None (default): infinite friction, rocking only.
        A sequence gives one value per block (None in it: that block without friction).
    mu_k : float or sequence, optional
        Kinetic friction coefficient μ_k ≤ μ_s [-]; None (default): μ_s.  A sequence gives one
        value per block.
    """

    e: float | str | tuple = DEFAULT_E
    overturn_angle: float | str | tuple = OVERTURN_ANGLE
    g: float = G
    impacts: str = IMPACT_SCHEMES[0]
    mu: float | tuple | None = DEFAULT_MU
    mu_k: float | tuple | None = DEFAULT_MU_K

    def __post_init__(self) -> None:
        set_ = object.__setattr__  # a frozen dataclass: the checked values replace the given
        set_(self, "e", _each(self.e, restitution))
        set_(self, "overturn_angle", _each(self.overturn_angle, _angle))
        set_(self, "g", positive("g", self.g, "m/s²"))
        resolve_impacts(self.impacts)  # refuses an unknown scheme
        set_(self, "impacts", self.impacts.strip().lower())
        mu = _each(self.mu, _friction("mu"))
        mu_k = _each(self.mu_k, _friction("mu_k"))
        if isinstance(mu, tuple) and isinstance(mu_k, tuple) and len(mu) != len(mu_k):
            raise InputError(f"mu_k has {len(mu_k)} values but mu has {len(mu)}: one per block")
        n = max(len(v) if isinstance(v, tuple) else 1 for v in (mu, mu_k))
        for i in range(n):
            kinetic_friction(_pick(mu, i), _pick(mu_k, i), where="" if n == 1 else f" (block {i})")
        set_(self, "mu", mu)
        set_(self, "mu_k", mu_k)

    def resolve(self, block: Block, i: int = 0) -> tuple[float, float]:
        """(e [-], overturning angle [rad]) of ``block`` (the i-th block of a batch when the
        settings are per block)."""
        return (
            resolve_e(_pick(self.e, i), block),
            resolve_overturn_angle(_pick(self.overturn_angle, i), block),
        )

    def friction(self, i: int = 0) -> tuple[float | None, float | None]:
        """(μ_s, μ_k) [-] of the i-th block of a batch: None, None for infinite friction; μ_k is
        μ_s where not given."""
        mu = _pick(self.mu, i)
        mu_k = _pick(self.mu_k, i)
        return mu, mu if mu_k is None else mu_k

    def for_blocks(self, blocks: Sequence[Block]) -> Physics:
        """This physics resolved for ``blocks``: ``e`` and ``overturn_angle`` as tuples of
        numbers, one per block (done once per block)."""
        n = len(blocks)
        for name in ("e", "overturn_angle", "mu", "mu_k"):
            value = getattr(self, name)
            if isinstance(value, tuple) and len(value) != n:
                raise InputError(f"{name} has {len(value)} values for {n} blocks")
        values = [self.resolve(b, i) for i, b in enumerate(blocks)]
        return dataclasses.replace(
            self,
            e=tuple(v[0] for v in values),
            overturn_angle=tuple(v[1] for v in values),
        )

    def params(self) -> dict:
        """Every field by name, JSON-ready (tuples as lists): what the chunk store's
        fingerprint includes (:class:`rocking.montecarlo.engine.Engine`)."""
        return {f.name: _json(getattr(self, f.name)) for f in dataclasses.fields(self)}

    @property
    def fingerprint(self) -> str:
        """SHA-256 of :meth:`params` (keys sorted)."""
        text = json.dumps(self.params(), sort_keys=True)
        return hashlib.sha256(text.encode()).hexdigest()


def as_physics(physics: Physics | None = None, **shorthands: Any) -> Physics:
    """The :class:`Physics` of a call: ``physics`` (default :class:`Physics` ()) with the
    shorthand keyword arguments given (:data:`SHORTHANDS`; those left at :data:`FROM_PHYSICS`
    are not) in place of its fields; any other keyword is an InputError that names it."""
    if physics is None:
        physics = Physics()
    elif not isinstance(physics, Physics):
        raise InputError(f"physics must be a rocking.Physics, got {type(physics).__name__}")
    given = {name: value for name, value in shorthands.items() if value is not FROM_PHYSICS}
    unexpected({name: given[name] for name in given.keys() - set(SHORTHANDS)})
    return dataclasses.replace(physics, **given) if given else physics


def _angle(value):
    """An overturning angle as given: "alpha" or a number in (0, π/2] [rad]."""
    if isinstance(value, str) and value.strip().lower() == "alpha":
        return "alpha"
    return resolve_overturn_angle(value, cast(Block, None))  # a number: no block needed


def _each(value, check):
    """``check`` of one value, or a tuple of the checked values of a sequence."""
    if isinstance(value, str) or not isinstance(value, Iterable) or getattr(value, "ndim", 1) == 0:
        return check(value)
    return tuple(check(v) for v in value)


def _friction(name: str):
    """The check of a friction coefficient ``name``: None (not given) or a positive number."""

    def check(value):
        return None if value is None else positive(name, value, "-")

    return check


def _pick(value, i: int):
    return value[i] if isinstance(value, tuple) else value


def _json(value):
    return list(value) if isinstance(value, tuple) else value
