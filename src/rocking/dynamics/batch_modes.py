"""The batched kernel's cases with friction (issue 45): what the lane machine runs where, its
checks and their margins (entry point :func:`rocking.dynamics.batch.run_cases`), and
:func:`modes_kernel`, the plain compiled loop of the same model (one case per thread).

**Where each interval runs.**  :func:`~rocking.dynamics.modes.modes_case` (what
:func:`rocking.simulate` ``(..., mu=...)`` computes) is a loop over sample intervals, each done by
:func:`~rocking.dynamics.modes._modes_interval`: an interval that starts in rock, or at rest
where the base cannot slip, is advanced by the rocking kernel's own step
(:func:`rocking.dynamics.impacts._advance`, the lanes' arithmetic too) and its contact conditions
are checked where the block rocks: at the interval's end N ≥ 0 and abs(F) ≤ μ_s·N (F, N of
:func:`~rocking.dynamics.modes._rock_forces`), and, where the interval had impacts, that their
impulses lie in the friction cone, (1 − e)/((1 + e)·tan α) ≤ μ_s, one constant per body
(:func:`~rocking.dynamics.modes.stick_impact_demand`), and that the contact right after them
does (:func:`~rocking.dynamics.modes._cone_holds_after_impacts`, a bound over the interval from
θ' at its start and u, gv at its ends; where the bound fails, the general integrator's
verdict).  Where a check fails, or in every other mode, it is the general integrator.

The lane machine of :mod:`rocking.dynamics.batch_lanes` (``fric``,
:class:`~rocking.dynamics.batch_lanes.Friction`) carries modes_case's whole state per lane (mode,
s, σ, θ, θ', q, q', y, y' and the running summaries) and runs each interval where it is cheapest:

* rock, and rest where the block may lift but the base cannot slip: the rocking path (the SIMD
  loop and its event handling, the same steps as modes_case's), with the checks at the sample
  that ends the interval, N ≥ :data:`N_MARGIN`·g and abs(F) ≤ μ_s·(1 − :data:`CONE_MARGIN`)·N,
  and those of its impacts (the same functions of the same values: no margin needed).  Where
  one fails, the lane does that interval again from its start (rows of its own) with
  :func:`~rocking.dynamics.modes._modes_interval`: modes_case's own result for it;
* rest where the base can neither slip nor lift: skipped (to the next sample where it may lift,
  slip or fly: :func:`~rocking.dynamics.batch_lanes._rest_until_uplift`);
* slide (where μ_k ≤ tan α: modes_case does nothing else in slide): the SIMD loop's slide step,
  :func:`~rocking.dynamics.modes._slide_rk4`, the Runge–Kutta step of modes_case in slide (the
  same function), kept where it is all that modes_case does in the interval (no event at its
  end, no zero of the slip velocity inside by :func:`~rocking.dynamics.modes._slip_dip`'s
  quick test, :func:`~rocking.dynamics.modes._no_slip_zero`), else the interval from its start
  by :func:`~rocking.dynamics.modes._modes_interval`;
* slide-rock, flight, rest where the base may slip or fly, and the intervals of the
  transitions: in the lane, one after the other, by
  :func:`~rocking.dynamics.modes._modes_interval` (scalar), until the block rocks, slides or
  rests where the SIMD loop or the rocking path takes it again.

The margins: the lanes' θ and θ' at a check are modes_case's own bits (the same steps), and F and
N come from the same function, :func:`~rocking.dynamics.modes._contact_forces`, of sin θ and cos
θ by the lanes' polynomials (:func:`~rocking.dynamics.equation._sincos`), which equal
modes_case's (:func:`~rocking.dynamics.equation._sincos_any`) for every θ below the overturning
angle: the same bits.  The margins guard that reasoning against any difference of rounding (a
few ulps of the terms g·gv and R·θ'², about 1e-15·g each): five orders of magnitude above it,
they only send intervals whose friction demand comes within 1e-9 of μ_s, or whose N comes within
1e-9·g of 0, to the scalar function (which gives modes_case's result either way).  Blocks without
friction (μ_s = None, stored as ∞) keep the lanes without checks (``fric`` None: the lane machine
compiles to the rocking-only one).

**The modes kernel** (:func:`modes_kernel`): a compiled parallel loop over cases, each calling
:func:`~rocking.dynamics.modes.modes_case` on its own scaled motion (u = scale·a_g/g,
gv = 1 + abs(scale)·a_v/g, the expressions of :func:`rocking.simulate` on
``(block, scale * acc, dt, av=abs(scale) * av)``) and writing only its own slot of the
:class:`~rocking.dynamics.batch_records.Outcome`: the plain loop of the model, which the
benchmark (``benchmarks/run.py``) times the lanes against, on one thread.
"""

from __future__ import annotations

import math

import numpy as np

from ..core.compile import kernel, parallel_kernel, prange
from .batch_lanes import Friction
from .batch_records import Contacts
from .impacts import Body
from .modes import _contact_at, modes_case

#: Relative margin of the lanes' friction check: abs(F) ≤ μ_s·(1 − CONE_MARGIN)·N.
CONE_MARGIN = 1e-9
#: The lanes' least normal force per unit mass accepted, as a fraction of g.
N_MARGIN = 1e-9


def lane_friction(contacts: Contacts, g: float) -> Friction:
    """The lanes' contact checks (:class:`~rocking.dynamics.batch_lanes.Friction`) of the blocks
    of ``contacts`` under gravity g [m/s²]."""
    return Friction(*contacts, 1.0 - CONE_MARGIN, N_MARGIN * g)


@kernel(inline="always")
def _scaled_vertical(av, base, n_t, sc, g):
    """gv = 1 + abs(sc)·a_v/g [-] at the samples of one motion (None when ``av`` is None)."""
    if av is None:
        return None
    gv = np.empty(n_t)
    for k in range(n_t):
        gv[k] = 1.0 + abs(sc) * av[base + k] / g
    return gv


@parallel_kernel
def modes_kernel(acc, av, n_t, dt, blocks, contacts, cases, located, out):
    """The cases ``cases.order`` (positions in ``cases``'s arrays) through the response-modes
    model, each from rest, writing their :class:`~rocking.dynamics.batch_records.Outcome` slots.
    ``acc``, ``av``: the horizontal and vertical ground accelerations [m/s²] (``av`` None: none),
    motion after motion, ``n_t`` samples each, ``dt`` [s] apart; ``located``: the impact scheme
    (:func:`rocking.dynamics.impacts.resolve_impacts`)."""
    g = blocks.g
    # the output arrays as locals: writes through the record's fields inside a parallel loop
    # are lost (seen with Numba 0.68: the parallel loop writes to a copy)
    overturned_out, ratio_out, uplift_out = out.overturned, out.peak_theta_ratio, out.uplift
    slip_out, residual_out, lift_out, steps_out = (
        out.peak_slip,
        out.residual_slip,
        out.peak_lift,
        out.steps,
    )
    for j in prange(cases.order.size):
        i = cases.order[j]
        b = cases.body[i]
        sc = cases.scale[i]
        base = cases.motion[i] * n_t
        u = np.empty(n_t)
        for k in range(n_t):
            u[k] = sc * acc[base + k] / g  # as simulate(block, scale * acc, dt)
        gv = _scaled_vertical(av, base, n_t, sc, g)  # as simulate(..., av=abs(scale) * av)
        body = Body(
            blocks.p2[b], blocks.sa[b], blocks.ca[b], blocks.tan_a[b], blocks.e[b], blocks.th_ov[b]
        )
        c = _contact_at(contacts, b, g)
        res = modes_case(u, gv, dt, body, c, located, 0.0, 0.0, None)
        overturned, t_ov, _n_imp, peak, uplift, peak_slip, slip, peak_lift, _demand = res
        overturned_out[i] = overturned
        ratio_out[i] = peak / blocks.alpha[b]
        uplift_out[i] = uplift
        slip_out[i] = peak_slip
        residual_out[i] = abs(slip)
        lift_out[i] = peak_lift
        # every interval is walked, up to the one of overturning (t_ov in it, after its start)
        steps_out[i] = min(n_t - 1, max(1, math.ceil(t_ov / dt))) if overturned else n_t - 1
