"""Rocking of one rigid block under one ground motion (paper Section 2): :func:`simulate`.

The public wrapper around the compiled kernels of :mod:`rocking.dynamics.equation` (Eq. 1, the
Runge–Kutta step) and :mod:`rocking.dynamics.impacts` (impacts, uplift, rest, overturning), and,
with friction (``mu``), of :mod:`rocking.dynamics.modes` (slide, slide-rock, flight; issue 45).
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field
from typing import Any

import numpy as np
from numpy.typing import ArrayLike

from ..core.checks import finite_array, in_range, positive
from ..core.compile import kernel
from ..defaults import DEFAULT_E, OVERTURN_ANGLE
from ..errors import InputError
from .body import Block
from .impacts import _OVERTURNED, Body, Interval, _advance, _initial, resolve_impacts
from .modes import REST, ROCK, Contact, modes_case
from .physics import FROM_PHYSICS, Physics, as_physics


@kernel
def _simulate_kernel(u, gv, dt, body, located, theta0, omega0, theta_out, omega_out):
    """Integrate one block ``body`` (:class:`~rocking.dynamics.impacts.Body`) over the whole
    motion ``u`` = a_g/g [-] sampled at dt [s], with the vertical factor ``gv`` = 1 + a_v/g [-]
    at the same samples (None: no vertical motion).

    Writes θ [rad] and θ' [rad/s] at every sample into the output arrays (NaN after overturning).
    Returns (overturned, t_overturn [s] or NaN, n_impacts, max abs(θ) [rad]).
    """
    n = u.shape[0]
    theta = theta0
    omega = omega0
    s, state = _initial(theta0, omega0)
    theta_out[0] = theta
    omega_out[0] = omega
    n_imp = 0
    peak = abs(theta)
    t_ov = math.nan
    overturned = False
    if abs(theta) >= body.th_ov:
        overturned = True
        t_ov = 0.0
    for k in range(n - 1):
        if overturned:
            theta_out[k + 1] = math.nan
            omega_out[k + 1] = math.nan
            continue
        g0 = None if gv is None else gv[k]
        g1 = None if gv is None else gv[k + 1]
        iv = Interval(u[k], u[k + 1], g0, g1, dt)
        theta, omega, s, state, ni, tev = _advance(theta, omega, s, state, iv, body, located)
        n_imp += ni
        if state == _OVERTURNED:
            overturned = True
            t_ov = k * dt + tev
            peak = body.th_ov
            theta_out[k + 1] = math.nan
            omega_out[k + 1] = math.nan
            continue
        theta_out[k + 1] = theta
        omega_out[k + 1] = omega
        if abs(theta) > peak:
            peak = abs(theta)
    return overturned, t_ov, n_imp, peak


@dataclass(frozen=True)
class RockingResponse:
    """Response of one block to one base motion.

    Attributes
    ----------
    t : ndarray
        Sample times [s].
    theta : ndarray
        Rotation θ [rad] at the samples (positive about corner O); NaN after overturning.
    omega : ndarray
        Angular velocity θ' [rad/s] at the samples; NaN after overturning.
    overturned : bool
        Whether abs(θ) reached the overturning angle.
    t_overturn : float
        Time of overturning [s], NaN if the block did not overturn.
    n_impacts : int
        Number of impacts (pivot changes at θ = 0); a chatter summed in closed form counts one
        impact per flight longer than ``ZENO_TIME_FRACTION·dt``.
    max_abs_theta : float
        Largest abs(θ) [rad] (the overturning angle if the block overturned).
    slip : ndarray
        Horizontal displacement of the block relative to the ground due to sliding [m] (the
        displacement of its contact corner(s), in flight of its lowest corner, from where that
        corner stood at rest; 0 for pure rocking); NaN after overturning.
    lift : ndarray
        Height of the base's lowest corner above the ground [m]; NaN after overturning.
    mode : ndarray of int
        The response mode at the samples, an index into :data:`rocking.MODES`
        (rest, slide, rock, slide-rock, flight); after overturning, the mode it overturned in.
    max_abs_slip, residual_slip, max_lift : float
        Largest abs(slip) [m], slip at the end (at overturning if the block overturned) [m],
        largest lift [m]; the largest at the samples and at overturning (not between samples).
    block, e, overturn_angle, mu, mu_k :
        The inputs that produced the response (e [-], overturn_angle [rad], the friction
        coefficients [-]: both None for infinite friction, μ_k = μ_s where it was not given).
    """

    t: np.ndarray
    theta: np.ndarray
    omega: np.ndarray
    overturned: bool
    t_overturn: float
    n_impacts: int
    max_abs_theta: float
    block: Block = field(repr=False)
    e: float = DEFAULT_E
    overturn_angle: float = OVERTURN_ANGLE
    slip: np.ndarray = field(default_factory=lambda: np.zeros(0), repr=False)
    lift: np.ndarray = field(default_factory=lambda: np.zeros(0), repr=False)
    mode: np.ndarray = field(default_factory=lambda: np.zeros(0, dtype=np.int8), repr=False)
    max_abs_slip: float = 0.0
    residual_slip: float = 0.0
    max_lift: float = 0.0
    mu: float | None = None
    mu_k: float | None = None

    @property
    def uplift(self) -> bool:
        """Whether the block left rest at all: rocking at some sample (θ ≠ 0 at a sample after
        the first), lifted off (lift > 0) or overturned; the batched kernel's ``uplift`` for a
        block starting at rest (sliding alone is not uplift)."""
        return bool(self.overturned or np.any(self.theta[1:] != 0.0) or np.any(self.lift[1:] > 0.0))

    @property
    def theta_over_alpha(self) -> np.ndarray:
        """θ/α [-] at the samples."""
        return self.theta / self.block.alpha

    def summary(self) -> dict:
        """Plain-number summary (JSON-friendly); with friction also μ_s, μ_k [-], the largest
        and the residual slip [m] and the largest lift [m]."""
        out = {
            "R_m": self.block.R,
            "gamma": self.block.gamma,
            "alpha_rad": self.block.alpha,
            "e": self.e,
            "overturned": bool(self.overturned),
            "t_overturn_s": None if math.isnan(self.t_overturn) else float(self.t_overturn),
            "n_impacts": int(self.n_impacts),
            "max_abs_theta_rad": float(self.max_abs_theta),
            "max_abs_theta_over_alpha": float(self.max_abs_theta / self.block.alpha),
        }
        if self.mu is not None:  # with friction (issue 45): its settings and results
            out.update(
                mu=self.mu,
                mu_k=self.mu_k,
                max_abs_slip_m=float(self.max_abs_slip),
                residual_slip_m=float(self.residual_slip),
                max_lift_m=float(self.max_lift),
            )
        return out


def _vertical_factor(av, n_t: int, g: float, flight: bool) -> np.ndarray:
    """gv = 1 + a_v/g [-] at the samples of the vertical ground acceleration ``av`` [m/s²], after
    checking that it has ``n_t`` finite samples, all above −g [m/s²] unless ``flight`` (the
    response-modes model, with friction) is modelled."""
    av = finite_array("av", av, ndim=(1,), min_len=1)
    if av.size != n_t:
        raise InputError(f"av has {av.size} samples but ag has {n_t}: give both at the same times")
    low = float(av.min())
    if low <= -g and not flight:
        raise InputError(
            f"av reaches {low:g} m/s², at or below -g = {-g:g} m/s²: the block would leave "
            "the ground, which the rocking-only model (mu=None) does not model; give a "
            "friction coefficient mu for the model with sliding and flight"
        )
    return 1.0 + av / g


def simulate(
    block: Block,
    ag: ArrayLike,
    dt: float,
    *,
    mu: float | None = None,
    mu_k: float | None = None,
    av: ArrayLike | None = None,
    physics: Physics | None = None,
    theta0: float = 0.0,
    omega0: float = 0.0,
    **shorthands: Any,
) -> RockingResponse:
    """Rocking response of ``block`` to the ground acceleration history ``ag``.

    Eq. (1) of :mod:`rocking.dynamics.equation`: θ'' = −p²·[(1 + a_v/g)·sin(sα − θ) +
    (a_g/g)·cos(sα − θ)] with p² = g·R/(r_g² + R²) (3g/(4R) for a uniform block).

    Parameters
    ----------
    block : Block
        The rigid block.
    ag : array_like, shape (n_t,)
        Horizontal ground acceleration [m/s²] at times 0, dt, 2·dt, … (linear in between).
    dt : float
        Sample interval [s]; also the Runge–Kutta step (the paper uses 1/400 s).
    physics : Physics, optional
        The physics (:class:`~rocking.Physics`; default ``Physics()``): ``mu``, ``mu_k`` and
        the shorthands below stand for its fields.
    theta0, omega0 : float
        Initial rotation [rad] and angular velocity [rad/s]; rest by default.
    **shorthands
        Shorthands for ``physics``'s fields, one release (issue 44): ``e`` (coefficient of
        restitution θ'⁺/θ'⁻ [-] in (0, 1], the paper's 0.925 by default, or ``"housner"``:
        1 − 1.5·sin²α, :meth:`Block.housner_e` for a general body), ``overturn_angle``
        (abs(θ) [rad] at which the block counts as overturned: π/2, the paper, or
        ``"alpha"``), ``g`` (gravity [m/s²]) and ``impacts`` ("located", the default, finds the
        instant of each impact inside the Runge–Kutta step; "step-end", a plain fixed-step
        scheme kept for comparison, issue 17, puts θ = 0 and θ' ← e·θ' at the end of a step
        that ends on the other side of θ = 0: :mod:`rocking.dynamics.impacts`).  Any other
        keyword is an :class:`~rocking.errors.InputError` naming it.
    av : array_like, shape (n_t,), optional
        Vertical ground acceleration [m/s², up positive] at the samples of ``ag`` (linear in
        between), which adds to gravity: the block lifts from rest when abs(a_g) > (g + a_v)·tan α.
        Every sample must exceed −g unless ``mu`` is given (the block then flies where the
        ground falls faster than gravity).  None (default): no vertical motion, exactly as
        without it.
    mu : float, optional
        Static friction coefficient μ_s [-] of the base: the block may then rest, slide, rock,
        slide-rock and fly (:mod:`rocking.dynamics.modes`).  None (default): not given, the
        ``physics``' field (whose default, None, is infinite friction: rocking only, the
        paper's model).
    mu_k : float, optional
        Kinetic friction coefficient μ_k ≤ μ_s [-]; None: the ``physics``' field (μ_s by
        default).

    Returns
    -------
    RockingResponse
    """
    if not isinstance(block, Block):
        raise InputError(f"block must be a rocking.Block, got {type(block).__name__}")
    dt = positive("dt", dt, "s")
    physics = as_physics(
        physics,
        **shorthands,
        mu=FROM_PHYSICS if mu is None else mu,
        mu_k=FROM_PHYSICS if mu_k is None else mu_k,
    )
    g = physics.g
    # e, the overturning angle and friction as numbers, once (for_blocks checks per-block ones)
    resolved = physics.for_blocks([block])
    e_val, th_ov = resolved.resolve(block)
    mu_s, mu_kin = resolved.friction(0)
    ag = finite_array("ag", ag, ndim=(1,), min_len=1)
    gv = None if av is None else _vertical_factor(av, ag.size, g, mu_s is not None)
    located = resolve_impacts(physics.impacts)
    theta0 = in_range("theta0", theta0, -math.pi / 2, math.pi / 2, unit="rad")
    try:
        omega0 = float(omega0)
    except (TypeError, ValueError):
        raise InputError(f"omega0 must be a number [rad/s], got {omega0!r}") from None
    if not math.isfinite(omega0):
        raise InputError(f"omega0 must be finite [rad/s], got {omega0!r}")
    alpha = block.alpha
    body = Body(block.p_squared(g), math.sin(alpha), math.cos(alpha), math.tan(alpha), e_val, th_ov)
    if mu_s is None:
        theta = np.empty_like(ag)
        omega = np.empty_like(ag)
        overturned, t_ov, n_imp, peak = _simulate_kernel(
            ag / g, gv, dt, body, located, theta0, omega0, theta, omega
        )
        moving = (theta != 0.0) | (omega != 0.0)
        mode = np.where(moving, ROCK, REST).astype(np.int8)
        zeros = np.where(np.isnan(theta), np.nan, 0.0)
        slip, lift, max_slip, residual, max_lift = zeros, zeros.copy(), 0.0, 0.0, 0.0
    else:
        out = np.empty((5, ag.size))
        contact = Contact.of(block, e_val, mu_s, mu_kin, g)
        overturned, t_ov, n_imp, peak, _up, max_slip, residual, max_lift, _demand = modes_case(
            ag / g, gv, dt, body, contact, located, theta0, omega0, out
        )
        theta, omega, slip, lift = out[0], out[1], out[2], out[3]
        mode = out[4].astype(np.int8)
    return RockingResponse(
        t=np.arange(ag.size) * dt,
        theta=theta,
        omega=omega,
        overturned=bool(overturned),
        t_overturn=float(t_ov),
        n_impacts=int(n_imp),
        max_abs_theta=float(peak),
        block=block,
        e=e_val,
        overturn_angle=th_ov,
        slip=slip,
        lift=lift,
        mode=mode,
        max_abs_slip=float(max_slip),
        residual_slip=float(residual),
        max_lift=float(max_lift),
        mu=mu_s,
        mu_k=mu_kin,
    )
