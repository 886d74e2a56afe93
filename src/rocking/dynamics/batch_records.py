"""The records of the batched kernel (:mod:`rocking.dynamics.batch`): its inputs
(:class:`Motions`, :class:`Vertical`, :class:`Blocks`, :class:`Cases`), its result
:class:`Outcome`, the response quantities of every case (:data:`QUANTITIES`), and
:class:`BlockTable`, the per-block constants of a batch under a :class:`~rocking.Physics`.
"""

from __future__ import annotations

import math
from collections.abc import Iterable, Sequence
from dataclasses import dataclass
from typing import NamedTuple

import numpy as np

from ..errors import InputError
from .body import Block
from .modes import Contact
from .physics import FROM_PHYSICS, Physics, as_physics

#: A per-block option: one value for all blocks (a number or a keyword) or one per block.
PerBlock = float | str | Sequence[float | str] | np.ndarray


class Motions(NamedTuple):
    """The horizontal ground motions of a batch as the kernel reads them: rows end to end."""

    acc: np.ndarray  #: ground accelerations [m/s²], motion after motion, shape (n_m·n_t,)
    n_t: int  #: samples per motion
    dt: float  #: sample interval and Runge–Kutta step [s]
    amax: np.ndarray  #: max abs(acc) of each motion [m/s²], shape (n_m,)
    asuf: np.ndarray  #: max abs(acc) from each sample to the end of its motion [m/s²], like acc


class Vertical(NamedTuple):
    """The vertical ground accelerations of a batch (absent: ``None`` in its place)."""

    av: np.ndarray  #: vertical accelerations [m/s², up positive], laid out like Motions.acc
    avmin: np.ndarray  #: min av of each motion [m/s²]
    avsuf: np.ndarray  #: min av from each sample to the end of its motion [m/s²], like av


class Blocks(NamedTuple):
    """Per-block constants in the kernel (see :class:`BlockTable`)."""

    p2: np.ndarray  #: p² [1/s²]
    sa: np.ndarray  #: sin α
    ca: np.ndarray  #: cos α
    tan_a: np.ndarray  #: tan α
    e: np.ndarray  #: coefficient of restitution
    th_ov: np.ndarray  #: overturning angle [rad]
    alpha: np.ndarray  #: α [rad]
    g: float  #: gravity [m/s²]


class Contacts(NamedTuple):
    """Per-block contact constants of the modes kernel (:class:`~rocking.dynamics.modes.Contact`
    of each block, field by field; see :class:`BlockTable`)."""

    R: np.ndarray  #: distance centre of mass–corner [m]
    rg2: np.ndarray  #: squared radius of gyration [m²]
    mu_s: np.ndarray  #: static friction coefficient [-] (∞: no friction given, rocking only)
    mu_k: np.ndarray  #: kinetic friction coefficient [-] (∞ likewise)
    e_ratio: np.ndarray  #: e/e_H [-]
    impact_ok: np.ndarray  #: the rule θ'⁺ = e·θ'⁻ from rock is inside the friction cone (bool)


class Cases(NamedTuple):
    """Case i is block ``body[i]`` under motion ``motion[i]`` scaled by ``scale[i]``; the lane
    machines take them in the order ``order`` (a permutation)."""

    body: np.ndarray
    motion: np.ndarray
    scale: np.ndarray
    order: np.ndarray


class Outcome(NamedTuple):
    """What the kernel records for every case: its response quantities (:data:`QUANTITIES`),
    one array each with one entry per case, and the steps it integrated.

    The one carrier of per-case results from the kernel through the Monte Carlo engine, its
    chunk store and the probabilities: a new response quantity is a field here (and in
    :data:`QUANTITIES`) and the kernel's update of it (:func:`_finish`, :func:`_fill`).
    """

    overturned: np.ndarray  #: whether the block overturned (bool)
    peak_theta_ratio: np.ndarray  #: max abs(θ)/α at the samples [-] (θ_ov/α if overturned)
    uplift: np.ndarray  #: whether the block left rest at all: rocking at some sample (bool)
    peak_slip: np.ndarray  #: max abs(slip) at the samples [m] (0 without friction)
    residual_slip: np.ndarray  #: abs(slip) at the end [m] (0 without friction)
    peak_lift: np.ndarray  #: max lift of the base's lowest corner [m] (0 without friction)
    steps: np.ndarray  #: integrated steps (int64; see :func:`run_cases`), not a quantity


#: The response quantities of :class:`Outcome`, with their dtypes, units and meanings (what a
#: :class:`rocking.LimitState` may be defined on).
QUANTITIES = {
    "overturned": (np.bool_, "", "the block overturned"),
    "peak_theta_ratio": (np.float64, "1", "max |theta| / alpha"),
    "uplift": (np.bool_, "", "the block left rest (rocked) at all"),
    "peak_slip": (np.float64, "m", "max |slip|"),
    "residual_slip": (np.float64, "m", "|slip| at the end"),
    "peak_lift": (np.float64, "m", "max lift of the base above the ground"),
}


def empty_outcome(n: int, alloc=np.zeros) -> Outcome:
    """An :class:`Outcome` of ``n`` cases, every quantity zero (False); ``alloc=np.empty``
    leaves them unset, for a kernel that writes every case."""
    return Outcome._make(
        [
            *(alloc(n, dtype) for dtype, _unit, _meaning in QUANTITIES.values()),
            alloc(n, np.int64),
        ]
    )


def take(outcome: Outcome, index) -> Outcome:
    """The cases ``index`` (an index array, a mask or a slice) of ``outcome``."""
    return Outcome(*(field[index] for field in outcome))


def concatenate(outcomes: Sequence[Outcome]) -> Outcome:
    """The cases of ``outcomes`` one after the other."""
    return Outcome(*(np.concatenate(fields) for fields in zip(*outcomes)))


@dataclass(frozen=True, eq=False)
class BlockTable:
    """Per-block constants of Eq. (1) for the kernel, arrays of shape (n_blocks,).

    Attributes
    ----------
    p2 : ndarray
        p² = g·R/(r_g² + R²) [1/s²] (3g/(4R) for a uniform block; :meth:`Block.p_squared`).
    sin_a, cos_a, tan_a : ndarray
        sin α, cos α, tan α of the critical angle [-].
    e : ndarray
        Coefficient of restitution [-].
    theta_ov : ndarray
        Overturning angle [rad].
    alpha : ndarray
        Critical angle α [rad].
    g : float
        Gravity [m/s²].
    physics : Physics
        The physics resolved for the blocks (:meth:`Physics.for_blocks`), whose numbers these
        are.
    contacts : Contacts
        The contact constants of each block with its base (friction coefficients μ_s, μ_k [-],
        ∞ for a block without friction; issue 45).
    """

    p2: np.ndarray
    sin_a: np.ndarray
    cos_a: np.ndarray
    tan_a: np.ndarray
    e: np.ndarray
    theta_ov: np.ndarray
    alpha: np.ndarray
    g: float
    physics: Physics
    contacts: Contacts

    @classmethod
    def from_blocks(
        cls,
        blocks: Block | Iterable[Block],
        *,
        physics: Physics | None = None,
        e: PerBlock = FROM_PHYSICS,
        overturn_angle: PerBlock = FROM_PHYSICS,
        g: float = FROM_PHYSICS,
    ) -> BlockTable:
        """Constants of ``blocks`` (a sequence of :class:`~rocking.Block`) under ``physics``
        (:class:`~rocking.Physics`, resolved here once per block).

        ``e``, ``overturn_angle`` [-, rad] and ``g`` [m/s²] are shorthands for the fields of
        ``physics`` (:func:`~rocking.dynamics.physics.as_physics`): one value for all blocks
        (number, ``"housner"`` / ``"alpha"``) or one per block.
        """
        blocks = block_list(blocks)
        resolved = as_physics(physics, e=e, overturn_angle=overturn_angle, g=g).for_blocks(blocks)
        g = resolved.g
        alpha = np.array([b.alpha for b in blocks])
        # the same expressions as simulate(), so both integrate bit for bit the same equation
        return cls(
            p2=np.array([b.p_squared(g) for b in blocks]),
            sin_a=np.array([math.sin(a) for a in alpha]),
            cos_a=np.array([math.cos(a) for a in alpha]),
            tan_a=np.array([math.tan(a) for a in alpha]),
            e=np.array(resolved.e, dtype=np.float64),
            theta_ov=np.array(resolved.overturn_angle, dtype=np.float64),
            alpha=alpha,
            g=g,
            physics=resolved,
            contacts=_contacts(blocks, resolved),
        )

    def __len__(self) -> int:
        return self.p2.size

    def arrays(self) -> Blocks:
        """The constants as the kernel takes them."""
        return Blocks(
            self.p2, self.sin_a, self.cos_a, self.tan_a, self.e, self.theta_ov, self.alpha, self.g
        )


def _contacts(blocks: Sequence[Block], physics: Physics) -> Contacts:
    """The :class:`Contacts` of ``blocks`` under ``physics`` (resolved for them)."""
    rows = []
    for i, b in enumerate(blocks):
        mu, mu_k = physics.friction(i)
        e = float(physics.e[i] if isinstance(physics.e, tuple) else physics.e)
        rows.append(Contact.of(b, e, math.inf if mu is None else mu, mu_k, physics.g))
    col = [np.array(values) for values in zip(*rows)]
    return Contacts(col[1], col[2], col[3], col[4], col[5], col[6].astype(np.bool_))


def block_list(blocks: Block | Iterable[Block]) -> list[Block]:
    """``blocks`` as a non-empty list of :class:`~rocking.Block` (one Block is a list of one)."""
    if isinstance(blocks, Block):
        blocks = [blocks]
    blocks = list(blocks)
    if not blocks:
        raise InputError("blocks must contain at least one rocking.Block")
    for i, b in enumerate(blocks):
        if not isinstance(b, Block):
            raise InputError(f"blocks[{i}] must be a rocking.Block, got {type(b).__name__}")
    return blocks


def motion_peaks(acc: np.ndarray) -> np.ndarray:
    """max abs(a) of each row of ``acc`` (n_motions, n_t) [m/s²], as the kernel's skip test
    needs."""
    return np.abs(acc).max(axis=1)
