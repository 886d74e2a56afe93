"""Rocking of a rigid rectangular block on a rigid horizontal base (paper Section 2).

Equation of motion, one form for both pivots (paper Eqs. 1–2, with the sign of Eq. 2's forcing
term corrected so that the response to −a_g is exactly −θ; reference.md §2):

    θ'' = −p²·[ sin(s·α − θ) + (a_g/g)·cos(s·α − θ) ],   s = sgn θ,   p² = 3g/(4R)      (Eq. 1)

Impact at θ = 0: the pivot switches (s → −s) and θ' ← e·θ'.  From rest the block starts to rock
only when |a_g| > g·tan α, tipping to θ > 0 under a negative ground acceleration.

Integration (the paper's scheme): classical fourth-order Runge–Kutta with a fixed step equal to the
motion's sample interval dt, the ground acceleration being linear between samples.  Within a step
the pivot is frozen; when the step ends on the other side of θ = 0, or turns round inside the step
far enough to touch it, the impact instant is located by safeguarded Newton iteration on the length
of a partial Runge–Kutta step, the impact is applied and the rest of the step is integrated from the
impact.  A bounce whose free flight would last less than ``ZENO_TIME_FRACTION·dt`` ends the
chatter: the block is put at rest (the remaining flights of the geometric series carry negligible
energy), and rocking restarts only if |a_g| > g·tan α.

The kernels here are pure functions on arrays; :func:`simulate` is the public wrapper.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field

import numpy as np

from ._numba import kernel
from ._validate import finite_array, in_range, positive
from .body import G, Block
from .errors import InputError

#: A bounce shorter than this fraction of the time step ends an impact sequence (block at rest).
ZENO_TIME_FRACTION = 1e-4
#: Partial-step probes for a return to θ = 0 inside a step that starts near θ = 0.
_N_PROBES = 8
#: Safety cap on events handled within one time step (impacts, uplifts).
_MAX_EVENTS_PER_STEP = 10_000

# Block state codes
_REST = 0
_ROCKING = 1
_OVERTURNED = 2


@kernel
def _accel(theta, s, u, p2, sa, ca):
    """θ'' of Eq. (1) on pivot side ``s`` for ground acceleration ``u`` = a_g/g [-]."""
    st = math.sin(theta)
    ct = math.cos(theta)
    # sin(sα − θ) = s·sinα·cosθ − cosα·sinθ ;  cos(sα − θ) = cosα·cosθ + s·sinα·sinθ
    return -p2 * (s * sa * ct - ca * st + u * (ca * ct + s * sa * st))


@kernel
def _rk4(theta, omega, s, u0, du, tau, h, p2, sa, ca):
    """One RK4 step of length h from local time tau; u(τ) = u0 + du·τ (du per second)."""
    ua = u0 + du * tau
    um = ua + du * 0.5 * h
    ub = ua + du * h
    k1t = omega
    k1w = _accel(theta, s, ua, p2, sa, ca)
    k2t = omega + 0.5 * h * k1w
    k2w = _accel(theta + 0.5 * h * k1t, s, um, p2, sa, ca)
    k3t = omega + 0.5 * h * k2w
    k3w = _accel(theta + 0.5 * h * k2t, s, um, p2, sa, ca)
    k4t = omega + h * k3w
    k4w = _accel(theta + h * k3t, s, ub, p2, sa, ca)
    th = theta + h / 6.0 * (k1t + 2.0 * k2t + 2.0 * k3t + k4t)
    om = omega + h / 6.0 * (k1w + 2.0 * k2w + 2.0 * k3w + k4w)
    return th, om


@kernel
def _locate(theta, omega, s, u0, du, tau, lo, hi, target, sgn, p2, sa, ca):
    """Partial step length h in [lo, hi] where the RK4 solution from (theta, omega) hits ``target``.

    With f(h) = sgn·(θ_RK4(h) − target), the caller guarantees f(lo) ≤ 0 ≤ f(hi); the root kept is
    the first one after leaving ``lo`` (f(lo) = 0 happens when the arc starts at θ = 0, and that
    trivial root is never returned).  Newton's method on h (dθ/dh = ω) safeguarded by bisection.
    Returns (h, theta_h, omega_h).
    """
    h = 0.5 * (lo + hi)
    th, om = _rk4(theta, omega, s, u0, du, tau, h, p2, sa, ca)
    for _ in range(100):
        f = sgn * (th - target)
        if f == 0.0:
            break
        if f < 0.0:
            lo = h
        else:
            hi = h
        # Newton proposal, bisection if it leaves the open bracket
        hn = h - (th - target) / om if om != 0.0 else 0.5 * (lo + hi)
        if not (lo < hn < hi):
            hn = 0.5 * (lo + hi)
        converged = abs(hn - h) <= 1e-15  # [s]: round-off level for steps of a few ms
        h = hn
        th, om = _rk4(theta, omega, s, u0, du, tau, h, p2, sa, ca)
        if converged:
            break
    return h, th, om


@kernel
def _hermite_min(theta, omega, th1, om1, s, h):
    """Time (> 0) of least s·θ of the Hermite cubic through the step's end states, if that cubic
    turns round inside the step (θ' changes sign towards θ = 0 and back), else −1."""
    if not (s * omega < 0.0 and s * om1 > 0.0):
        return -1.0
    # Hermite cubic θ(x) on x = τ/h ∈ [0, 1]; find where its derivative vanishes (the minimum of sθ).
    a = 2.0 * theta - 2.0 * th1 + h * omega + h * om1
    b = -3.0 * theta + 3.0 * th1 - 2.0 * h * omega - h * om1
    c = h * omega
    # derivative 3a x² + 2b x + c = 0
    best = -1.0
    if abs(a) < 1e-300:
        if b != 0.0:
            best = -c / (2.0 * b)
    else:
        disc = 4.0 * b * b - 12.0 * a * c
        if disc >= 0.0:
            r = math.sqrt(disc)
            for x in ((-2.0 * b - r) / (6.0 * a), (-2.0 * b + r) / (6.0 * a)):
                if 0.0 < x < 1.0:
                    val = s * (((a * x + b) * x + c) * x + theta)
                    if best < 0.0 or val < s * (((a * best + b) * best + c) * best + theta):
                        best = x
    if best <= 0.0 or best >= 1.0:
        return -1.0
    return best * h


@kernel
def _interior_touch(theta, omega, th1, om1, s, u0, du, tau, h, p2, sa, ca):
    """Bracket (lo, hi) of partial step lengths around the first return to θ = 0 inside a step that
    ends on the same side (s·θ > 0 at lo, ≤ 0 at hi), or (−1, −1) if none is found.

    Two probes: the turning point of the Hermite cubic through the end states (a swing that turns
    round inside the step); and, when the block starts so close to θ = 0 that it could reach it
    within the step (s·θ ≤ |θ'|·h + ½·max|θ''|·h², i.e. during short bounces or the chatter after
    an impact, where the cubic's error exceeds θ itself), partial RK4 steps at h/_N_PROBES intervals.
    """
    hm = _hermite_min(theta, omega, th1, om1, s, h)
    if hm > 0.0:
        tm, _w = _rk4(theta, omega, s, u0, du, tau, hm, p2, sa, ca)
        if s * tm <= 0.0:
            return 0.0, hm
    ua = abs(u0 + du * tau)
    ub = abs(u0 + du * (tau + h))
    amax = p2 * (1.0 + (ua if ua > ub else ub))  # |θ''| ≤ p²·(1 + |a_g|/g)
    if s * theta > abs(omega) * h + 0.5 * amax * h * h:
        return -1.0, -1.0
    prev = 0.0
    for j in range(1, _N_PROBES):
        hj = h * j / _N_PROBES
        tj, _w = _rk4(theta, omega, s, u0, du, tau, hj, p2, sa, ca)
        if s * tj <= 0.0:
            return prev, hj
        prev = hj
    return -1.0, -1.0


@kernel
def _advance(theta, omega, s, state, u0, u1, dt, p2, sa, ca, tan_a, e, th_ov):
    """Advance a block over one sample interval [0, dt] of linear ground acceleration u0 → u1 (in g).

    Returns (theta, omega, s, state, n_impacts, t_event): ``t_event`` is the local time of
    overturning within the interval [s], or −1.
    """
    du = (u1 - u0) / dt
    tau = 0.0
    n_imp = 0
    t_event = -1.0
    t_start = -1.0  # local time of the last start from rest in this interval
    false_side = 0.0  # sign of u of a start that landed at once (no restart on that side)
    for _ in range(_MAX_EVENTS_PER_STEP):
        if state == _REST:
            ua = u0 + du * tau
            # Uplift test |u|·cos α > sin α rather than |u| > tan α: it is, in floating point,
            # the sign of θ'' at θ = 0 in _accel, so a block never starts with an acceleration
            # of the wrong sign (which, 1 ulp above tan α, restarted and landed it forever).
            if abs(ua) * ca > sa and ua * false_side <= 0.0:
                tstart = tau
            elif abs(u1) * ca > sa and u1 * false_side <= 0.0:
                # linear u crosses ±tan α inside the rest of the interval
                thr = tan_a if u1 > 0.0 else -tan_a
                tstart = (thr - u0) / du
                if tstart < tau:
                    tstart = tau
            else:
                break  # at rest through the whole interval
            tau = tstart
            t_start = tau
            uc = u0 + du * tau
            s = -1.0 if uc > 0.0 else 1.0  # negative a_g tips the block to θ > 0
            theta = 0.0
            omega = 0.0
            state = _ROCKING
            if tau >= dt:
                break
            continue
        h = dt - tau
        if h <= 0.0:
            break
        th1, om1 = _rk4(theta, omega, s, u0, du, tau, h, p2, sa, ca)
        lo = 0.0
        hit = -1.0
        if s * th1 < 0.0 or (th1 == 0.0 and s * om1 < 0.0):
            hit = h
        else:
            lo, hit = _interior_touch(theta, omega, th1, om1, s, u0, du, tau, h, p2, sa, ca)
        if hit > 0.0:
            hz, thz, omz = _locate(theta, omega, s, u0, du, tau, lo, hit, 0.0, -s, p2, sa, ca)
            tau += hz
            if t_start >= 0.0 and tau - t_start < ZENO_TIME_FRACTION * dt:
                # Back at θ = 0 within the Zeno time of starting: |a_g| fell below g·tan α
                # again at once (it exceeded it by a few ulps). The block never left the
                # ground. u is linear in the interval, so |u| keeps falling on this side: a
                # restart on it would land again at the same instant, forever; only a
                # crossing of the threshold on the other side can start it in this interval.
                theta = 0.0
                omega = 0.0
                state = _REST
                false_side = 1.0 if u0 + du * t_start > 0.0 else -1.0
                continue
            n_imp += 1
            s = -s
            omega = e * omz
            theta = 0.0
            # Zeno check: how long would the next free flight last?
            ua = u0 + du * tau
            acc0 = -p2 * (s * sa + ua * ca)  # θ'' at θ = 0 on the new side
            if omega == 0.0 or (acc0 * omega < 0.0 and
                                2.0 * abs(omega) < ZENO_TIME_FRACTION * dt * abs(acc0)):
                omega = 0.0
                state = _REST
            continue
        if abs(th1) >= th_ov:
            target = th_ov if th1 > 0.0 else -th_ov
            hz, thz, omz = _locate(theta, omega, s, u0, du, tau, 0.0, h, target, s, p2, sa, ca)
            t_event = tau + hz
            theta = thz
            omega = omz
            state = _OVERTURNED
            break
        theta = th1
        omega = om1
        break
    return theta, omega, s, state, n_imp, t_event


@kernel
def _simulate_kernel(u, dt, p2, sa, ca, tan_a, e, th_ov, theta0, omega0, theta_out, omega_out):
    """Integrate one block over the whole motion ``u`` = a_g/g [-] sampled at dt [s].

    Writes θ [rad] and θ' [rad/s] at every sample into the output arrays (NaN after overturning).
    Returns (overturned, t_overturn [s] or NaN, n_impacts, max|θ| [rad]).
    """
    n = u.shape[0]
    theta = theta0
    omega = omega0
    if theta0 != 0.0:
        s = 1.0 if theta0 > 0.0 else -1.0
        state = _ROCKING
    elif omega0 != 0.0:
        s = 1.0 if omega0 > 0.0 else -1.0
        state = _ROCKING
    else:
        s = 1.0
        state = _REST
    theta_out[0] = theta
    omega_out[0] = omega
    n_imp = 0
    peak = abs(theta)
    t_ov = math.nan
    overturned = False
    if abs(theta) >= th_ov:
        overturned = True
        t_ov = 0.0
    for k in range(n - 1):
        if overturned:
            theta_out[k + 1] = math.nan
            omega_out[k + 1] = math.nan
            continue
        theta, omega, s, state, ni, tev = _advance(
            theta, omega, s, state, u[k], u[k + 1], dt, p2, sa, ca, tan_a, e, th_ov)
        n_imp += ni
        if state == _OVERTURNED:
            overturned = True
            t_ov = k * dt + tev
            peak = th_ov
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
        Whether |θ| reached the overturning angle.
    t_overturn : float
        Time of overturning [s], NaN if the block did not overturn.
    n_impacts : int
        Number of impacts (pivot changes at θ = 0).
    max_abs_theta : float
        Largest |θ| [rad] (the overturning angle if the block overturned).
    block, e, overturn_angle :
        The inputs that produced the response (e [-], overturn_angle [rad]).
    """

    t: np.ndarray
    theta: np.ndarray
    omega: np.ndarray
    overturned: bool
    t_overturn: float
    n_impacts: int
    max_abs_theta: float
    block: Block = field(repr=False)
    e: float = 0.925
    overturn_angle: float = math.pi / 2

    @property
    def theta_over_alpha(self) -> np.ndarray:
        """θ/α [-] at the samples."""
        return self.theta / self.block.alpha

    def summary(self) -> dict:
        """Plain-number summary (JSON-friendly)."""
        return {
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


def resolve_e(e, block: Block) -> float:
    """Coefficient of restitution [-]: a number in (0, 1], or ``"housner"`` for 1 − 1.5·sin²α."""
    if isinstance(e, str):
        if e.strip().lower() == "housner":
            return block.housner_e()
        raise InputError(f"e must be a number in (0, 1] or 'housner', got {e!r}")
    return in_range("e", e, 0.0, 1.0, lo_open=True)


def resolve_overturn_angle(overturn_angle, block: Block) -> float:
    """Overturning angle [rad]: a number in (0, π/2], or ``"alpha"`` for the critical angle α."""
    if isinstance(overturn_angle, str):
        if overturn_angle.strip().lower() == "alpha":
            return block.alpha
        raise InputError(f"overturn_angle must be an angle in (0, pi/2] rad or 'alpha', "
                         f"got {overturn_angle!r}")
    return in_range("overturn_angle", overturn_angle, 0.0, math.pi / 2, lo_open=True, unit="rad")


def simulate(block: Block, ag, dt: float, *, e=0.925, overturn_angle=math.pi / 2,
             theta0: float = 0.0, omega0: float = 0.0, g: float = G) -> RockingResponse:
    """Rocking response of ``block`` to the ground acceleration history ``ag``.

    Parameters
    ----------
    block : Block
        The rigid block.
    ag : array_like, shape (n_t,)
        Horizontal ground acceleration [m/s²] at times 0, dt, 2·dt, … (linear in between).
    dt : float
        Sample interval [s]; also the Runge–Kutta step (the paper uses 1/400 s).
    e : float or "housner"
        Coefficient of restitution θ'⁺/θ'⁻ [-] in (0, 1]; the paper's 0.925 by default;
        ``"housner"`` gives 1 − 1.5·sin²α.
    overturn_angle : float or "alpha"
        |θ| [rad] at which the block counts as overturned: π/2 (the paper) or ``"alpha"``.
    theta0, omega0 : float
        Initial rotation [rad] and angular velocity [rad/s]; rest by default.
    g : float
        Gravity [m/s²].

    Returns
    -------
    RockingResponse
    """
    if not isinstance(block, Block):
        raise InputError(f"block must be a rocking.Block, got {type(block).__name__}")
    dt = positive("dt", dt, "s")
    g = positive("g", g, "m/s²")
    ag = finite_array("ag", ag, ndim=(1,), min_len=1)
    e_val = resolve_e(e, block)
    th_ov = resolve_overturn_angle(overturn_angle, block)
    theta0 = in_range("theta0", theta0, -math.pi / 2, math.pi / 2, unit="rad")
    try:
        omega0 = float(omega0)
    except (TypeError, ValueError):
        raise InputError(f"omega0 must be a number [rad/s], got {omega0!r}") from None
    if not math.isfinite(omega0):
        raise InputError(f"omega0 must be finite [rad/s], got {omega0!r}")
    alpha = block.alpha
    theta = np.empty_like(ag)
    omega = np.empty_like(ag)
    overturned, t_ov, n_imp, peak = _simulate_kernel(
        ag / g, dt, 3.0 * g / (4.0 * block.R), math.sin(alpha), math.cos(alpha), math.tan(alpha),
        e_val, th_ov, theta0, omega0, theta, omega)
    return RockingResponse(
        t=np.arange(ag.size) * dt, theta=theta, omega=omega, overturned=bool(overturned),
        t_overturn=float(t_ov), n_impacts=int(n_imp), max_abs_theta=float(peak), block=block,
        e=e_val, overturn_angle=th_ov)
