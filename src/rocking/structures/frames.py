"""Linear shear frames and the absolute floor accelerations they feed to bodies on their floors.

Paper Section 7: a 5-story shear frame with lumped floor masses, story stiffnesses and 5 % modal
damping in every mode. Floor i (1..n) has mass m_i [kg]; story i has stiffness k_i [N/m] and joins
floor i to floor i−1 (story 1 to the ground). The equation of motion of the relative floor
displacements u (n,) under ground acceleration a_g(t) is

    M u'' + C u' + K u = −M 1 a_g,

with classical (modal) damping C. Its modes come from K φ = ω² M φ
(:func:`rocking.core.portable.eigh`) and the floor motions from modal superposition; a body
standing on a floor is driven by that floor's absolute acceleration (reference.md §8).
"""

from __future__ import annotations

import dataclasses
import math
import os
from dataclasses import dataclass
from functools import cached_property
from pathlib import Path
from typing import TYPE_CHECKING, overload

import numpy as np

from ..core import portable
from ..core.checks import finite_array, in_range, positive, read_toml
from ..core.compile import parallel_kernel, prange
from ..dynamics.body import G
from ..errors import InputError
from ..motions.response import foh_coefficients

if TYPE_CHECKING:
    from numpy.typing import ArrayLike

    from ..motions.ensemble import Ensemble


@overload
def kN_per_g_to_kg(w: float) -> float: ...
@overload
def kN_per_g_to_kg(w: ArrayLike) -> np.ndarray: ...
def kN_per_g_to_kg(w: ArrayLike) -> float | np.ndarray:
    """Mass [kg] of a floor whose weight is given in the paper's unit kN/g.

    "444.82 kN/g" is a weight of 444.82 kN (100 kip), i.e. a mass of 444.82e3 / 9.80665 kg
    (reference.md §1). Accepts a number or an array.
    """
    return np.multiply(w, 1e3 / G)


@overload
def kN_per_cm_to_N_per_m(k: float) -> float: ...
@overload
def kN_per_cm_to_N_per_m(k: ArrayLike) -> np.ndarray: ...
def kN_per_cm_to_N_per_m(k: ArrayLike) -> float | np.ndarray:
    """Stiffness [N/m] from the paper's unit kN/cm (55.23 kN/cm = 5.523e6 N/m)."""
    return np.multiply(k, 1e5)


def _uniform_stiffness_for_period(mass: float, n_stories: int, period: float) -> float:
    """Story stiffness [N/m] that gives a uniform frame of floor mass ``mass`` [kg] the
    fundamental period ``period`` [s], from ω_1 = 2·sqrt(k/m)·sin(π/(2(2n+1))) (reference.md §8)."""
    omega1 = 2.0 * math.pi / period
    return mass * (omega1 / (2.0 * math.sin(math.pi / (2 * (2 * n_stories + 1))))) ** 2


_M_2S = kN_per_g_to_kg(444.82)  # paper Section 7, T_n = 2.0 s frame: 444.82 kN/g per floor
_K_2S = kN_per_cm_to_N_per_m(55.23)  # and 55.23 kN/cm per story

#: Preset frames: name -> (description, floor mass [kg], story stiffness [N/m]); all are uniform
#: 5-story frames with 5 % damping in every mode. The paper gives no data for its T_n = 1.0 s and
#: 1.5 s frames. For a uniform frame the mode shapes, participation and floor accelerations
#: depend only on k/m (the ω_r scale with sqrt(k/m)), so any frame with the right k/m is
#: equivalent; we keep the 2.0 s frame's floor mass and choose k from the closed form so that
#: T_1 is exactly 1.0 / 1.5 s.
_K_1_5S = _uniform_stiffness_for_period(_M_2S, 5, 1.5)  # 98.24 kN/cm
_K_1S = _uniform_stiffness_for_period(_M_2S, 5, 1.0)  # 221.04 kN/cm
_PRESET_DATA = {
    "paper-2.0": (
        "paper Section 7, T1 = 2.0 s: 444.82 kN/g per floor, 55.23 kN/cm per story "
        "(gives T1 = 2.0005 s)",
        _M_2S,
        _K_2S,
    ),
    "paper-1.5": (
        f"T1 = 1.5 s (no data in the paper): 444.82 kN/g per floor as the 2.0 s frame, "
        f"{_K_1_5S / 1e5:.2f} kN/cm per story for T1 = 1.5 s exactly",
        _M_2S,
        _K_1_5S,
    ),
    "paper-1.0": (
        f"T1 = 1.0 s (no data in the paper): 444.82 kN/g per floor as the 2.0 s frame, "
        f"{_K_1S / 1e5:.2f} kN/cm per story for T1 = 1.0 s exactly",
        _M_2S,
        _K_1S,
    ),
    "paper-0.5": (
        "paper Section 7, T1 = 0.5 s: 87.59 kN/g per floor, 175.11 kN/cm per story "
        "(gives T1 = 0.4986 s)",
        kN_per_g_to_kg(87.59),
        kN_per_cm_to_N_per_m(175.11),
    ),
}

#: Names and descriptions of the preset frames of :meth:`ShearFrame.preset` (all uniform,
#: 5 stories, 5 % damping in every mode).
PRESETS = {
    name: f"5-story uniform frame, 5 % modal damping; {desc}"
    for name, (desc, _, _) in _PRESET_DATA.items()
}

#: Keys under which a floor ensemble's ``meta`` records its frame (see :meth:`ShearFrame.to_meta`).
_META_KEYS = ("frame_name", "frame_masses_kg", "frame_stiffnesses_N_per_m", "frame_damping")


def _positive_list(name: str, values, unit: str) -> tuple[float, ...]:
    """``values`` as a tuple of floats, each finite and > 0 (errors name ``name[i]``)."""
    if isinstance(values, (str, bytes)) or not hasattr(values, "__iter__"):
        raise InputError(f"{name} must be a list of numbers [{unit}], got {values!r}")
    return tuple(positive(f"{name}[{i}]", v, unit) for i, v in enumerate(values))


@dataclass(frozen=True)
class ShearFrame:
    """A linear shear frame with lumped floor masses and classical modal damping.

    Parameters
    ----------
    masses : sequence of float
        Floor masses m_1..m_n [kg], ground up; finite, > 0.
    stiffnesses : sequence of float
        Story stiffnesses k_1..k_n [N/m]; story i joins floor i to floor i−1 (story 1 to the
        ground); finite, > 0.
    damping : float
        Damping ratio of every mode [-], in [0, 1).
    name : str, optional
        Label used in plots and in floor ensembles' ``location``; default "<n>-story frame".
    """

    masses: tuple[float, ...]
    stiffnesses: tuple[float, ...]
    damping: float = 0.05
    name: str = ""

    def __post_init__(self) -> None:
        m = _positive_list("masses", self.masses, "kg")
        k = _positive_list("stiffnesses", self.stiffnesses, "N/m")
        if not m:
            raise InputError("masses must list at least one story, got none")
        if len(m) != len(k):
            raise InputError(
                f"masses has {len(m)} entries but stiffnesses has {len(k)}; "
                "give one mass and one stiffness per story"
            )
        object.__setattr__(self, "masses", m)
        object.__setattr__(self, "stiffnesses", k)
        object.__setattr__(
            self, "damping", in_range("damping", self.damping, 0.0, 1.0, hi_open=True, unit="-")
        )
        object.__setattr__(self, "name", str(self.name) or f"{len(m)}-story frame")

    # ---- constructors -------------------------------------------------------------------------
    @classmethod
    def uniform(
        cls, n_stories: int, mass: float, stiffness: float, damping: float = 0.05, name: str = ""
    ) -> ShearFrame:
        """Frame of ``n_stories`` equal floors of ``mass`` [kg] and equal stories of
        ``stiffness`` [N/m]."""
        if (
            isinstance(n_stories, bool)
            or not isinstance(n_stories, (int, np.integer))
            or n_stories < 1
        ):
            raise InputError(f"n_stories must be an integer >= 1, got {n_stories!r}")
        return cls((mass,) * int(n_stories), (stiffness,) * int(n_stories), damping, name)

    @classmethod
    def from_paper_units(
        cls,
        weights_kN_per_g: ArrayLike,
        stiffness_kN_per_cm: ArrayLike,
        damping: float = 0.05,
        name: str = "",
    ) -> ShearFrame:
        """Frame from floor weights [kN/g, i.e. kN of weight] and story stiffnesses [kN/cm]."""
        w = _positive_list("weights_kN_per_g", weights_kN_per_g, "kN/g")
        k = _positive_list("stiffness_kN_per_cm", stiffness_kN_per_cm, "kN/cm")
        return cls(tuple(kN_per_g_to_kg(w)), tuple(kN_per_cm_to_N_per_m(k)), damping, name)

    @classmethod
    def preset(cls, name: str) -> ShearFrame:
        """One of the frames of the paper's Section 7 by name (see :data:`PRESETS`)."""
        try:
            _, m, k = _PRESET_DATA[name]
        except (KeyError, TypeError):
            raise InputError(
                f"unknown frame preset {name!r}; known presets: {', '.join(PRESETS)}"
            ) from None
        return cls.uniform(5, m, k, 0.05, name)

    @classmethod
    def from_mapping(cls, data: dict, name: str, where: str = "frame") -> ShearFrame:
        """Frame from a mapping (a TOML table) with the keys of :meth:`from_toml`.

        ``masses_kg`` and ``stiffnesses_N_per_m`` (lists, SI), or ``weights_kN_per_g`` and
        ``stiffness_kN_per_cm`` (lists, the paper's units); optional ``damping`` [-] (default
        0.05) and ``name`` (overrides ``name``). ``where`` prefixes every error message.
        """
        si = {"masses_kg", "stiffnesses_N_per_m"}
        paper = {"weights_kN_per_g", "stiffness_kN_per_cm"}
        keys = set(data) - {"damping", "name"}
        unknown = keys - si - paper
        if unknown:
            raise InputError(
                f"{where}: unknown key(s) {', '.join(sorted(unknown))}; expected "
                f"{', '.join(sorted(si | paper))}, damping, name"
            )
        damping = data.get("damping", 0.05)
        name = str(data.get("name", name))
        try:
            if keys == si:
                return cls(data["masses_kg"], data["stiffnesses_N_per_m"], damping, name)
            if keys == paper:
                return cls.from_paper_units(
                    data["weights_kN_per_g"], data["stiffness_kN_per_cm"], damping, name
                )
        except InputError as exc:
            raise InputError(f"{where}: {exc}") from None
        raise InputError(
            f"{where}: give either masses_kg and stiffnesses_N_per_m, or "
            "weights_kN_per_g and stiffness_kN_per_cm (one pair, both lists); got "
            f"{', '.join(sorted(data)) or 'nothing'}"
        )

    @classmethod
    def from_toml(cls, path: str | os.PathLike[str]) -> ShearFrame:
        """Frame from a TOML file with the keys of :meth:`from_mapping` (name defaults to the
        file's stem)."""
        path = Path(path)
        return cls.from_mapping(read_toml(path), path.stem, str(path))

    def to_meta(self) -> dict:
        """The frame as flat ``meta`` entries (numbers and lists only; survives netCDF attrs)."""
        return {
            "frame_name": self.name,
            "frame_masses_kg": list(self.masses),
            "frame_stiffnesses_N_per_m": list(self.stiffnesses),
            "frame_damping": self.damping,
        }

    @classmethod
    def from_meta(cls, meta: dict) -> ShearFrame:
        """Inverse of :meth:`to_meta` (e.g. ``ShearFrame.from_meta(floor_ensemble.meta)``)."""
        missing = [key for key in _META_KEYS if key not in meta]
        if missing:
            raise InputError(f"meta has no frame description (missing {', '.join(missing)})")
        return cls(
            np.atleast_1d(meta["frame_masses_kg"]).tolist(),
            np.atleast_1d(meta["frame_stiffnesses_N_per_m"]).tolist(),
            float(meta["frame_damping"]),
            str(meta["frame_name"]),
        )

    # ---- matrices and modes -------------------------------------------------------------------
    @property
    def n_stories(self) -> int:
        """Number of stories (= floors above the ground)."""
        return len(self.masses)

    @property
    def mass_matrix(self) -> np.ndarray:
        """Diagonal mass matrix M (n, n) [kg]."""
        return np.diag(self.masses)

    @property
    def stiffness_matrix(self) -> np.ndarray:
        """Tridiagonal stiffness matrix K (n, n) [N/m] of the shear frame."""
        k = np.asarray(self.stiffnesses)
        k_above = np.append(k[1:], 0.0)  # story i+1 also acts on floor i; none above the roof
        return np.diag(k + k_above) - np.diag(k[1:], 1) - np.diag(k[1:], -1)

    @property
    def damping_matrix(self) -> np.ndarray:
        """Classical modal damping matrix C = M Φ diag(2ζω_r) Φᵀ M (n, n) [N·s/m]."""
        mphi = self.mode_shapes * np.asarray(self.masses)[:, None]  # M Φ, M diagonal
        return portable.matmul(mphi * (2.0 * self.damping * self.omegas), mphi.T)

    @cached_property
    def _modes(self) -> tuple[np.ndarray, np.ndarray]:
        # K φ = ω² M φ with M diagonal: the symmetric A = M^-½ K M^-½ has eigenvectors y = M^½ φ
        # (Φᵀ M Φ = YᵀY = I); portable.eigh (the same bits on every CPU, unlike LAPACK) gives
        # ascending ω² and every mode's roof component > 0
        s = 1.0 / np.sqrt(np.asarray(self.masses))
        lam, y = portable.eigh(self.stiffness_matrix * (s[:, None] * s[None, :]))
        return np.sqrt(lam), y * s[:, None]

    @property
    def omegas(self) -> np.ndarray:
        """Circular natural frequencies ω_r (n,) [rad/s], lowest first."""
        return self._modes[0].copy()

    @property
    def periods(self) -> np.ndarray:
        """Natural periods T_r = 2π/ω_r (n,) [s], longest (fundamental) first."""
        return 2.0 * math.pi / self._modes[0]

    @property
    def frequencies_hz(self) -> np.ndarray:
        """Natural frequencies f_r = ω_r/2π (n,) [Hz], lowest first."""
        return self._modes[0] / (2.0 * math.pi)

    @property
    def mode_shapes(self) -> np.ndarray:
        """Mass-normalised mode shapes Φ (n_stories, n_modes) [kg^-½], columns = modes in the
        order of :attr:`periods`, rows = floors 1..n; Φᵀ M Φ = I and the roof entry is > 0."""
        return self._modes[1].copy()

    @property
    def participation_factors(self) -> np.ndarray:
        """Modal participation factors Γ_r = φ_rᵀ M 1 (n_modes,) [kg^½] (with mass-normalised
        modes); Σ_r φ_ir Γ_r = 1 on every floor i."""
        return portable.matmul(self._modes[1].T, np.asarray(self.masses)[:, None])[:, 0]

    # ---- floor motions ------------------------------------------------------------------------
    def floor_accelerations(self, acc: ArrayLike, dt: float) -> np.ndarray:
        """Absolute floor accelerations of the frame, starting at rest, under ground motion ``acc``.

        Parameters
        ----------
        acc : array_like
            Ground acceleration [m/s²], (n_t,) or (n_motions, n_t), linear between samples.
        dt : float
            Time step [s].

        Returns
        -------
        ndarray
            Absolute accelerations [m/s²] of floors 1..n: (n_stories, n_t) for one motion,
            (n_motions, n_stories, n_t) for several (row i−1 is floor i).
        """
        a = finite_array("acc", acc, ndim=(1, 2))
        out = self._floors(np.atleast_2d(a), positive("dt", dt, "s"), np.arange(self.n_stories))
        return out[:, 0] if a.ndim == 1 else np.moveaxis(out, 0, 1)

    def floor_ensemble(self, ensemble: Ensemble, floor: int) -> Ensemble:
        """The absolute accelerations of one floor, as a :class:`rocking.motions.ensemble.Ensemble`.

        Parameters
        ----------
        ensemble : rocking.motions.ensemble.Ensemble
            Ground motions [m/s²] at the frame's base.
        floor : int
            0 (the ground: ``ensemble`` itself is returned) to ``n_stories`` (the roof).

        Returns
        -------
        rocking.motions.ensemble.Ensemble
            Same dt, labels and generation metadata (seed, scale, ...); ``meta`` also holds
            ``location`` ("floor <i> of <frame name>"), ``floor``, the frame (:meth:`to_meta`),
            ``kind`` = "floor" and ``ground_kind`` (the ground ensemble's kind). Not scaled:
            call ``.scaled(agx)`` to give it the ground's A_gx, as the paper does. A vertical
            component (``ensemble.av``) is kept as it is: the shear frame has no vertical
            degrees of freedom, so each floor is taken to move vertically with the ground
            (columns axially rigid; an assumption, not a result).
        """
        floor = self._check_floor(floor)
        if floor == 0:
            return ensemble
        acc = self._floors(self._ground(ensemble), ensemble.dt, np.array([floor - 1]))[0]
        return self._wrap(ensemble, floor, acc)

    def floor_ensembles(self, ensemble: Ensemble) -> dict[int, Ensemble]:
        """All floors' ensembles in one pass: {0: ``ensemble``, 1: floor 1, ..., n: roof}
        (each as :meth:`floor_ensemble` returns it)."""
        acc = self._floors(self._ground(ensemble), ensemble.dt, np.arange(self.n_stories))
        out = {0: ensemble}
        for i in range(self.n_stories):
            out[i + 1] = self._wrap(ensemble, i + 1, acc[i])
        return out

    def _check_floor(self, floor) -> int:
        if (
            isinstance(floor, bool)
            or not isinstance(floor, (int, np.integer))
            or not 0 <= floor <= self.n_stories
        ):
            raise InputError(
                f"floor must be an integer from 0 (ground) to {self.n_stories} "
                f"(roof of {self.name}), got {floor!r}"
            )
        return int(floor)

    @staticmethod
    def _ground(ensemble) -> np.ndarray:
        if "frame_name" in ensemble.meta:
            raise InputError(
                "ensemble is already a floor motion "
                f"({ensemble.meta.get('location')}); give the ground ensemble"
            )
        return np.ascontiguousarray(ensemble.acc, dtype=np.float64)

    def _wrap(self, ensemble, floor: int, acc: np.ndarray):
        # kind changes so that rocking.regenerate (ground motions only) refuses a floor ensemble
        meta = {
            **ensemble.meta,
            **self.to_meta(),
            "floor": floor,
            "location": f"floor {floor} of {self.name}",
            "kind": "floor",
            "ground_kind": ensemble.meta.get("kind", "unknown"),
        }
        return dataclasses.replace(ensemble, acc=acc, meta=meta)

    def _floors(self, ag: np.ndarray, dt: float, rows: np.ndarray) -> np.ndarray:
        omega = self._modes[0]
        # Absolute acceleration of floor i = Σ_r φ_ir Γ_r A_r(t), A_r being the absolute
        # acceleration of a unit-participation oscillator r (u'' + 2ζω u' + ω² u = −a_g), because
        # q_r = Γ_r u_r and Σ_r φ_ir Γ_r = 1 when every mode is kept.
        weights = self._modes[1][rows] * self.participation_factors
        coef = foh_coefficients(omega, self.damping, np.full(omega.size, dt))
        # (row, motion, sample): each floor's motions contiguous, as an Ensemble holds them.
        # Allocated by NumPy, which asks Linux for huge pages for large arrays: filled by the
        # kernel's own np.empty (4 kB pages), a 1000-motion 5-story frame's 320 MB took 80,000
        # page faults, ~1.3 s of system time on a VM
        out = np.empty((rows.size, ag.shape[0], ag.shape[1]))
        _floor_kernel(
            ag, coef, 2.0 * self.damping * omega, omega**2, np.ascontiguousarray(weights), out
        )
        return out

    def __str__(self) -> str:
        stories = "story" if self.n_stories == 1 else "stories"
        return (
            f"ShearFrame({self.name!r}: {self.n_stories} {stories}, "
            f"T1 = {self.periods[0]:.4g} s, damping {self.damping:g})"
        )


@parallel_kernel
def _floor_kernel(ag, coef, c, k, weights, out):
    """Floor absolute accelerations ``out`` (n_rows, n_motions, n_t) [m/s²] by modal
    superposition.

    ag (n_motions, n_t) ground acceleration [m/s²]; coef (n_modes, 8): the exact (Nigam &
    Jennings 1969) one-step recurrence of each mode for ground acceleration linear over a step,
    from :func:`rocking.motions.response.foh_coefficients`; c = 2ζω_r [1/s] and k = ω_r² [1/s²] per
    mode;
    weights (n_rows, n_modes) = φ_ir Γ_r [-].

    Hand-written rather than ``scipy.signal.lfilter`` per mode plus a matrix product: one pass
    over memory, parallel over motions, and a fixed summation order, so each motion's floors are
    bit-identical whatever the number of threads or motions in the batch.
    """
    n_mot, n_t = ag.shape
    n_rows, n_modes = weights.shape
    for m in prange(n_mot):
        u = np.zeros(n_modes)
        v = np.zeros(n_modes)
        a_abs = np.empty(n_modes)
        for j in range(n_t):
            for r in range(n_modes):
                a_abs[r] = -c[r] * v[r] - k[r] * u[r]  # absolute acceleration of oscillator r
            for i in range(n_rows):
                s = 0.0
                for r in range(n_modes):
                    s += weights[i, r] * a_abs[r]
                out[i, m, j] = s
            if j + 1 < n_t:
                a0 = ag[m, j]
                a1 = ag[m, j + 1]
                for r in range(n_modes):
                    e = coef[r]
                    u[r], v[r] = (
                        e[0] * u[r] + e[1] * v[r] + e[2] * a0 + e[3] * a1,
                        e[4] * u[r] + e[5] * v[r] + e[6] * a0 + e[7] * a1,
                    )
