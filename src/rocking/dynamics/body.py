"""Rigid bodies and Housner's energy-balance equation (paper Section 2 and Eq. 11).

Geometry (paper Fig. 1): height H [m], width B [m], size R = ½·sqrt(H² + B²) [m],
slenderness γ = H/B [-], critical angle α = θc = atan(B/H) [rad],
frequency parameter p = sqrt(3g/(4R)) [rad/s] (from I_O = (4/3)·M·R²).

A general rigid body (equipment whose mass is not uniform; issue 16) rocks by the same equation
once its mass properties are known: the centre of mass at height h_cg [m] above the base and at
horizontal distance b [m] from each pivot edge, and its radius of gyration r_g [m] about the
centre of mass.  Then R = sqrt(h_cg² + b²) is the distance from a pivot to the centre of mass,
α = atan(b/h_cg), I_O = M·(r_g² + R²) and p² = g·R/(r_g² + R²); a uniform block is the case
r_g² = R²/3.
"""

from __future__ import annotations

import math
import warnings
from dataclasses import dataclass

from ..core.checks import HOUSNER, in_range, positive, restitution
from ..defaults import GAMMA_RANGE, R_MAX_M, R_RANGE_M, G
from ..errors import InputError

#: One international foot [m]; the paper's sizes are whole feet printed in metres.
FOOT = 0.3048
#: Size parameters of the paper's 72 bodies (Tables 1–3): R = 4…11 ft, printed as 1.22…3.35 m.
PAPER_R_FT = tuple(range(4, 12))
#: Slenderness ratios of the paper's 72 bodies (Tables 1–3) [-].
PAPER_GAMMAS = tuple(2.0 + 0.5 * i for i in range(9))


class BodyWarning(UserWarning):
    """A body that is legal but unusual (sizes outside the usual range, height below width)."""


def _size(name: str, value: float) -> float:
    """A length of a body [m]: finite, > 0 and smaller than the Earth (larger is no body that
    stands on the ground, and Eq. (11) overflows to inf, "safe", near R = 1e308 m)."""
    value = positive(name, value, "m")
    if value > R_MAX_M:
        raise InputError(
            f"{name} = {value:g} m is larger than the Earth (radius {R_MAX_M:g} m): not a body "
            "that stands on the ground; check the units"
        )
    return value


@dataclass(frozen=True)
class Block:
    """A rigid body that can rock on either of two bottom edges: a homogeneous rectangular block,
    or (with ``r_g``) any body symmetric about the vertical through its centre of mass.

    Parameters
    ----------
    R : float
        Size parameter [m], finite, > 0: half the diagonal ½·sqrt(H² + B²) of a block; in
        general the distance from a pivot edge to the centre of mass, sqrt(h_cg² + b²).
    gamma : float
        Slenderness ratio [-], finite, > 0 (γ < 1 is a squat block: legal, just stable): H/B of
        a block, h_cg/b in general.
    r_g : float or None
        Radius of gyration about the centre of mass [m], finite, > 0; ``None`` (default)
        for a homogeneous rectangular block, whose r_g² = R²/3 (computed by the block's own
        formulas, so that ``Block(R, gamma)`` gives the paper's numbers exactly).  See
        :meth:`from_mass_properties`.

    Warns
    -----
    BodyWarning
        When R, γ or r_g lies outside the usual range of bodies (:data:`rocking.defaults.R_RANGE_M`,
        1 mm to 1 km, and :data:`rocking.defaults.GAMMA_RANGE`, 0.01 to 100): legal (a slender
        limit study may want γ = 200), but more often a mistake of units.

    Raises
    ------
    InputError
        When a value is not finite or ≤ 0, or R or r_g exceeds the Earth's radius
        (:data:`rocking.defaults.R_MAX_M`): no body at all.
    """

    R: float
    gamma: float
    r_g: float | None = None

    def __post_init__(self):
        R = _size("R", self.R)
        gamma = positive("gamma", self.gamma, "-")
        checks = [("R", R, R_RANGE_M, " m"), ("gamma", gamma, GAMMA_RANGE, "")]
        if self.r_g is not None:
            r_g = _size("r_g", self.r_g)
            checks.append(("r_g", r_g, R_RANGE_M, " m"))
            object.__setattr__(self, "r_g", r_g)
        for name, value, (lo, hi), unit in checks:
            if not lo <= value <= hi:
                warnings.warn(
                    f"{name} = {value:g}{unit} is outside the usual range of bodies ({lo:g} to "
                    f"{hi:g}{unit}); check the units if that is not meant",
                    BodyWarning,
                    stacklevel=3,
                )
        object.__setattr__(self, "R", R)
        object.__setattr__(self, "gamma", gamma)

    @classmethod
    def from_dimensions(cls, H: float, B: float) -> Block:
        """Block of height ``H`` [m] and width ``B`` [m] (both finite, > 0).

        Warns (:class:`BodyWarning`) when H < B (γ < 1): a squat block is legal, but the two
        may have been swapped."""
        H = positive("H", H, "m")
        B = positive("B", B, "m")
        if H < B:
            warnings.warn(
                f"H = {H:g} m is less than B = {B:g} m (gamma = {H / B:.3g}, a squat block): "
                "check that the height and the width are not swapped",
                BodyWarning,
                stacklevel=2,
            )
        return cls(R=0.5 * math.hypot(H, B), gamma=H / B)

    @classmethod
    def from_mass_properties(cls, h_cg: float, b: float, *, radius_of_gyration: float) -> Block:
        """A general rigid body from its mass properties (issue 16).

        Parameters
        ----------
        h_cg : float
            Height of the centre of mass above the base [m], > 0.
        b : float
            Horizontal distance from the centre of mass to each pivot edge [m], > 0 (half the
            width of the footprint in the plane of rocking, for a body symmetric about the
            vertical through its centre of mass).
        radius_of_gyration : float
            Radius of gyration r_g about the centre of mass [m], > 0, for rotation in the plane
            of rocking (I_cg = M·r_g²).

        Returns
        -------
        Block
            R = sqrt(h_cg² + b²) [m], γ = h_cg/b (so α = atan(b/h_cg)) and r_g: rocking with
            p² = g·R/(r_g² + R²).  A uniform block has r_g² = R²/3 and p² = 3g/(4R).
        """
        h_cg = positive("h_cg", h_cg, "m")
        b = positive("b", b, "m")
        r_g = positive("radius_of_gyration", radius_of_gyration, "m")
        return cls(R=math.hypot(h_cg, b), gamma=h_cg / b, r_g=r_g)

    @property
    def is_uniform(self) -> bool:
        """True for a homogeneous rectangular block (no ``r_g`` given)."""
        return self.r_g is None

    @property
    def radius_of_gyration(self) -> float:
        """Radius of gyration about the centre of mass [m]: ``r_g``, or R/sqrt(3) for a uniform
        block."""
        return self.R / math.sqrt(3.0) if self.r_g is None else self.r_g

    @property
    def h_cg(self) -> float:
        """Height of the centre of mass above the base, R·cos α [m]."""
        return self.R * math.cos(self.alpha)

    @property
    def b(self) -> float:
        """Horizontal distance from the centre of mass to a pivot edge, R·sin α [m]."""
        return self.R * math.sin(self.alpha)

    @property
    def alpha(self) -> float:
        """Critical angle α = θc = atan(B/H) [rad]."""
        return math.atan(1.0 / self.gamma)

    @property
    def H(self) -> float:
        """Height of a block, 2R·cos α [m] (for a general body: twice h_cg)."""
        return 2.0 * self.R * math.cos(self.alpha)

    @property
    def B(self) -> float:
        """Width of a block, 2R·sin α [m] (for a general body: the distance between the pivot
        edges, 2b)."""
        return 2.0 * self.R * math.sin(self.alpha)

    def p_squared(self, g: float = G) -> float:
        """p² = g·R/(r_g² + R²) = M·g·R/I_O [1/s²], the coefficient of Eq. (1), for gravity ``g``
        [m/s²]; 3g/(4R) for a uniform block, computed so (the one place it is computed:
        :func:`rocking.simulate`, the batched kernel and the reference solver integrate the same
        number)."""
        if self.r_g is None:
            return 3.0 * g / (4.0 * self.R)
        return g * self.R / (self.r_g**2 + self.R**2)

    def p_at(self, g: float = G) -> float:
        """Frequency parameter p = sqrt(p²) [rad/s] for gravity ``g`` [m/s²]
        (:meth:`p_squared`)."""
        return math.sqrt(self.p_squared(positive("g", g, "m/s²")))

    @property
    def p(self) -> float:
        """Frequency parameter p [rad/s] at standard gravity (sqrt(3g/(4R)) for a block)."""
        return self.p_at(G)

    def uplift_acceleration_at(self, g: float = G) -> float:
        """Ground acceleration that starts rocking from rest, g·tan α [m/s²]."""
        return positive("g", g, "m/s²") * math.tan(self.alpha)

    @property
    def uplift_acceleration(self) -> float:
        """Ground acceleration that starts rocking from rest, g·tan α = g/γ [m/s²]."""
        return self.uplift_acceleration_at(G)

    def housner_e(self) -> float:
        """Housner's (1963) restitution [-]: angular momentum about the new pivot conserved at
        the impact, e = 1 − 2b²/(r_g² + R²) = 1 − 2R²·sin²α/(r_g² + R²); for a rectangle
        (r_g² = R²/3) e = 1 − 1.5·sin²α, computed so for a uniform block.

        Derivation: just before the impact the body turns at θ' about O and its centre of mass,
        at (b, h_cg) from O, moves at θ'·(−h_cg, b); its angular momentum about O', at (−2b, 0)
        from O, is M·θ'·(r_g² + h_cg² − b²) = M·θ'·(r_g² + R² − 2b²).  Just after it, it turns
        at e·θ' about O': M·(r_g² + R²)·e·θ'.
        """
        if self.r_g is None:
            return 1.0 - 1.5 * math.sin(self.alpha) ** 2
        return 1.0 - 2.0 * self.b**2 / (self.r_g**2 + self.R**2)

    @property
    def label(self) -> str:
        """Short name for tables and plots, e.g. ``"R=1.22 m, γ=4"`` (R to the cm), with
        ``", r_g=0.50 m"`` for a general body."""
        name = f"R={self.R:.2f} m, γ={self.gamma:g}"
        return name if self.r_g is None else f"{name}, r_g={self.r_g:.2f} m"

    def __str__(self) -> str:
        name = f"Block(R={self.R:g} m, gamma={self.gamma:g}"
        return name + (")" if self.r_g is None else f", r_g={self.r_g:g} m)")


def resolve_e(e: float | str, block: Block) -> float:
    """Coefficient of restitution [-]: a number in (0, 1], or ``"housner"`` for
    :meth:`Block.housner_e` (1 − 1.5·sin²α for a uniform block)."""
    value = restitution(e)
    if value != HOUSNER:
        return value
    housner = block.housner_e()
    if housner <= 0.0:
        # b² ≥ (r_g² + R²)/2: so squat a body loses all its rotation at the first impact
        # (Housner's rule gives e ≤ 0), which the rocking model does not describe
        raise InputError(
            f"e = 'housner' gives {housner:.3g} <= 0 for {block}: the body is too squat to rock "
            "by Housner's impact rule; give e as a number in (0, 1]"
        )
    return housner


def resolve_overturn_angle(overturn_angle: float | str, block: Block) -> float:
    """Overturning angle [rad]: a number in (0, π/2], or ``"alpha"`` for the critical angle α."""
    if isinstance(overturn_angle, str):
        if overturn_angle.strip().lower() == "alpha":
            return block.alpha
        raise InputError(
            f"overturn_angle must be an angle in (0, pi/2] rad or 'alpha', got {overturn_angle!r}"
        )
    return in_range("overturn_angle", overturn_angle, 0.0, math.pi / 2, lo_open=True, unit="rad")


def paper_bodies() -> list[Block]:
    """The paper's 72 bodies of Tables 1–3, R-major (R = 4…11 ft, then γ = 2.0…6.0)."""
    return [Block(r_ft * FOOT, gamma) for r_ft in PAPER_R_FT for gamma in PAPER_GAMMAS]


def housner_sv(block: Block, g: float = G) -> float:
    """Pseudo-velocity that overturns ``block`` with about 50 % probability [m/s].

    Paper Eq. (11), from the energy balance of Eq. (10):
    S_v = (1/cos α)·sqrt((8/3)·g·R·(1 − cos α)), with R [m] and g [m/s²].

    For a general body (``block.r_g`` given) the same energy balance with I_O = M·(r_g² + R²).
    In Eq. (1), I_O·θ'' + W·R·sin(α − θ) = −M·R·cos(α − θ)·a_g, the ground acceleration drives
    θ'' through M·R·cos α·a_g/I_O at small θ, so Housner takes the angular velocity the ground
    gives the body as that factor times the ground's pseudo-velocity, θ' = (M·R·cos α/I_O)·S_v.
    Eq. (10) equates its kinetic energy with the work that lifts the centre of mass from θ = 0
    to θ = α, W·Δ with Δ = R·(1 − cos α):

        ½·I_O·θ'² = ½·(M²·R²·cos²α/I_O)·S_v² = M·g·R·(1 − cos α),                    (10)

    (the printed Eq. (10), ½·(W·M·R²/g)·S_v²·cos²θc = W·Δ, lacks the division by I_O), hence

        S_v = (1/cos α)·sqrt(2·g·(r_g² + R²)·(1 − cos α)/R).

    With r_g² = R²/3 (uniform block, I_O = (4/3)·M·R²) 2·(r_g² + R²)/R = (8/3)·R: Eq. (11)
    exactly; a uniform block is computed by Eq. (11) as printed.
    """
    if not isinstance(block, Block):
        raise InputError(f"block must be a rocking.Block, got {type(block).__name__} {block!r}")
    g = positive("g", g, "m/s²")
    ca = math.cos(block.alpha)
    if block.r_g is None:
        return math.sqrt(8.0 / 3.0 * g * block.R * (1.0 - ca)) / ca  # Eq. (11)
    # Eq. (11) generalised: I_O = M·(r_g² + R²) in Eq. (10)
    return math.sqrt(2.0 * g * (block.r_g**2 + block.R**2) / block.R * (1.0 - ca)) / ca
