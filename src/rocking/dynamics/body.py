"""Rigid rectangular bodies and Housner's energy-balance equation (paper Section 2 and Eq. 11).

Geometry (paper Fig. 1): height H [m], width B [m], size R = ½·sqrt(H² + B²) [m],
slenderness γ = H/B [-], critical angle α = θc = atan(B/H) [rad],
frequency parameter p = sqrt(3g/(4R)) [rad/s] (from I_O = (4/3)·M·R²).
"""

from __future__ import annotations

import math
from dataclasses import dataclass

from ..core.checks import HOUSNER, in_range, positive, restitution
from ..defaults import GAMMA_RANGE, R_RANGE_M, G
from ..errors import InputError

#: One international foot [m]; the paper's sizes are whole feet printed in metres.
FOOT = 0.3048
#: Size parameters of the paper's 72 bodies (Tables 1–3): R = 4…11 ft, printed as 1.22…3.35 m.
PAPER_R_FT = tuple(range(4, 12))
#: Slenderness ratios of the paper's 72 bodies (Tables 1–3) [-].
PAPER_GAMMAS = tuple(2.0 + 0.5 * i for i in range(9))


@dataclass(frozen=True)
class Block:
    """A homogeneous rigid rectangular block that can rock on either bottom corner.

    Parameters
    ----------
    R : float
        Size parameter, half the diagonal ½·sqrt(H² + B²) [m], in
        :data:`rocking.defaults.R_RANGE_M` (1 mm to 1 km).
    gamma : float
        Slenderness ratio H/B [-], in :data:`rocking.defaults.GAMMA_RANGE` (0.01 to 100; γ < 1 is
        a squat block: legal, just stable).
    """

    R: float
    gamma: float

    def __post_init__(self):
        R = positive("R", self.R, "m")
        gamma = positive("gamma", self.gamma, "-")
        for name, value, (lo, hi), unit in (
            ("R", R, R_RANGE_M, " m"),
            ("gamma", gamma, GAMMA_RANGE, ""),
        ):
            if not lo <= value <= hi:
                raise InputError(
                    f"{name} = {value:g}{unit} is outside the range of bodies the "
                    f"model is meant for ({lo:g} to {hi:g}{unit}); check the units"
                )
        object.__setattr__(self, "R", R)
        object.__setattr__(self, "gamma", gamma)

    @classmethod
    def from_dimensions(cls, H: float, B: float) -> Block:
        """Block of height ``H`` [m] and width ``B`` [m] (both finite, > 0)."""
        H = positive("H", H, "m")
        B = positive("B", B, "m")
        return cls(R=0.5 * math.hypot(H, B), gamma=H / B)

    @property
    def alpha(self) -> float:
        """Critical angle α = θc = atan(B/H) [rad]."""
        return math.atan(1.0 / self.gamma)

    @property
    def H(self) -> float:
        """Height [m]."""
        return 2.0 * self.R * math.cos(self.alpha)

    @property
    def B(self) -> float:
        """Width [m]."""
        return 2.0 * self.R * math.sin(self.alpha)

    def p_squared(self, g: float = G) -> float:
        """p² = 3g/(4R) [1/s²], the coefficient of Eq. (1), for gravity ``g`` [m/s²] (the one place
        it is computed: :func:`rocking.simulate`, the batched kernel and the reference solver
        integrate the same number)."""
        return 3.0 * g / (4.0 * self.R)

    def p_at(self, g: float = G) -> float:
        """Frequency parameter p = sqrt(3g/(4R)) [rad/s] for gravity ``g`` [m/s²]."""
        return math.sqrt(self.p_squared(positive("g", g, "m/s²")))

    @property
    def p(self) -> float:
        """Frequency parameter p = sqrt(3g/(4R)) [rad/s] at standard gravity."""
        return self.p_at(G)

    def uplift_acceleration_at(self, g: float = G) -> float:
        """Ground acceleration that starts rocking from rest, g·tan α [m/s²]."""
        return positive("g", g, "m/s²") * math.tan(self.alpha)

    @property
    def uplift_acceleration(self) -> float:
        """Ground acceleration that starts rocking from rest, g·tan α = g/γ [m/s²]."""
        return self.uplift_acceleration_at(G)

    def housner_e(self) -> float:
        """Housner's (1963) restitution for a rectangle, e = 1 − 1.5·sin²α [-]."""
        return 1.0 - 1.5 * math.sin(self.alpha) ** 2

    @property
    def label(self) -> str:
        """Short name for tables and plots, e.g. ``"R=1.22 m, γ=4"`` (R to the cm)."""
        return f"R={self.R:.2f} m, γ={self.gamma:g}"

    def __str__(self) -> str:
        return f"Block(R={self.R:g} m, gamma={self.gamma:g})"


def resolve_e(e, block: Block) -> float:
    """Coefficient of restitution [-]: a number in (0, 1], or ``"housner"`` for 1 − 1.5·sin²α."""
    value = restitution(e)
    return block.housner_e() if value == HOUSNER else value


def resolve_overturn_angle(overturn_angle, block: Block) -> float:
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
    """
    g = positive("g", g, "m/s²")
    ca = math.cos(block.alpha)
    return math.sqrt(8.0 / 3.0 * g * block.R * (1.0 - ca)) / ca  # Eq. (11)
