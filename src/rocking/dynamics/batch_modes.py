"""The batched kernel's cases with friction (issue 45): which the rocking lanes can take, and the
compiled loop of the response-modes model over the others (entry point
:func:`rocking.dynamics.batch.run_cases`).

**Which cases the lanes keep.**  The lane machine of :mod:`rocking.dynamics.batch_lanes`
integrates rest and rock only.  :func:`~rocking.dynamics.modes.modes_case` (what
:func:`rocking.simulate` ``(..., mu=...)`` computes) advances every interval that starts in rock,
or at rest where the base cannot slip, with the rocking kernel's own step
(:func:`rocking.dynamics.impacts._advance`, the lanes' arithmetic too), and checks the contact
conditions where the block rocks: at the interval's end N ≥ 0 and abs(F) ≤ μ_s·N (F, N of
:func:`~rocking.dynamics.modes._rock_forces`), and, where the interval had impacts, that
their impulses lie in the friction cone, (1 − e)/((1 + e)·tan α) ≤ μ_s, one constant per body
(:func:`~rocking.dynamics.modes.stick_impact_demand`), and that the contact right after them
does (:func:`~rocking.dynamics.modes._cone_holds_after_impacts`, a bound over the interval from
θ' at its start and u, gv at its ends; where the bound fails, the general integrator's verdict).
Only where a check fails does it redo the interval with its general integrator.  A case whose
checks all pass never leaves stick-rock: modes_case's result is the lanes' result.  So
(:func:`modes_needed`) a case of a block with a finite μ_s goes to the lanes unless

* its base may slip, or its block fly, at rest: max abs(scale·a_g) > μ_s·(g + abs(scale)·min a_v)
  or g + abs(scale)·min a_v ≤ 0 (the rest intervals are then checked a priori: the tests are
  written in the kernel's expressions on the motion's extremes, abs(sc·a)/g and
  1 + abs(sc)·a_v/g round monotonically, μ_s·x too, so they are the per-sample tests or
  stricter), or
* it may lift its block (:func:`~rocking.dynamics.batch_lanes._may_lift`) and the impact's
  impulse lies outside the friction cone (the first impact would fail the check);

and in the lanes (``fric``, :class:`~rocking.dynamics.batch_lanes.Friction`) every state of a
rocking lane at a sample is checked, N ≥ :data:`N_MARGIN`·g and
abs(F) ≤ μ_s·(1 − :data:`CONE_MARGIN`)·N, and an interval with impacts that ends rocking needs
the bound on the contact after them to hold (the same function of the same values: no margin
needed); where it fails the lanes do not try the general integrator, they give the case to the
modes kernel.  A case that fails a check is marked and re-run by :func:`modes_kernel` (the
lanes' result discarded); so is every case routed to it above.  The margins: the lanes' θ and
θ' at a check are modes_case's own bits (the same steps), and F and N come from the same function,
:func:`~rocking.dynamics.modes._contact_forces`, of sin θ and cos θ by the lanes' polynomials
(:func:`~rocking.dynamics.equation._sincos`), which equal modes_case's
(:func:`~rocking.dynamics.equation._sincos_any`) for every θ below the overturning angle: the
same bits.  The margins guard that reasoning against any difference of rounding (a few ulps of
the terms g·gv and R·θ'², about 1e-15·g each): five orders of magnitude above it, they only
send cases whose friction demand comes within 1e-9 of μ_s, or whose N comes within 1e-9·g of
0, to be re-run.  Blocks without friction (μ_s = None, stored as ∞) keep the lanes without
checks (``fric`` None: the lane machine compiles to the rocking-only one).

**The modes kernel** (:func:`modes_kernel`): a compiled parallel loop over the routed cases, each
calling :func:`~rocking.dynamics.modes.modes_case` on its own scaled motion (u = scale·a_g/g,
gv = 1 + abs(scale)·a_v/g, the expressions of :func:`rocking.simulate` on
``(block, scale * acc, dt, av=abs(scale) * av)``) and writing only its own slot of the
:class:`~rocking.dynamics.batch_records.Outcome`: its results equal :func:`rocking.simulate`
``(..., mu=...)`` bit for bit, whatever the threads or the grouping of cases into calls.
"""

from __future__ import annotations

import math

import numpy as np

from ..core.compile import kernel, parallel_kernel, prange
from .batch_lanes import Friction, _may_lift
from .batch_records import Contacts
from .equation import _gv_sample
from .impacts import Body
from .modes import Contact, modes_case

#: Relative margin of the lanes' friction check: abs(F) ≤ μ_s·(1 − CONE_MARGIN)·N.
CONE_MARGIN = 1e-9
#: The lanes' least normal force per unit mass accepted, as a fraction of g.
N_MARGIN = 1e-9


@kernel
def modes_needed(amax, avmin, g, blocks, contacts, body, motion, scale):
    """Whether each case (``body``, ``motion``, ``scale`` arrays) goes to the modes kernel at once
    (see the module docstring): its block has a finite μ_s, and its base may slip or its block
    fly at rest, or it may lift its block, whose impacts lie outside the friction cone.
    ``amax``: max abs(a_g) [m/s²] and ``avmin``: min a_v [m/s²] (None: no vertical motion) of
    each motion; g [m/s²]; ``blocks``, ``contacts``: the per-block records
    (:class:`~rocking.dynamics.batch_records.Blocks`, ``Contacts``)."""
    n = body.size
    need = np.zeros(n, dtype=np.bool_)
    for i in range(n):
        b = body[i]
        m = motion[i]
        sc = scale[i]
        mu = contacts.mu_s[b]
        if mu == math.inf:
            continue
        gv = _gv_sample(avmin, m, sc, g)
        gvmin = 1.0 if gv is None else gv
        still = not _may_lift(amax[m], avmin, m, sc, g, blocks.sa[b], blocks.ca[b])
        rests = gvmin > 0.0 and abs(sc * amax[m]) / g <= mu * gvmin
        need[i] = not (rests and (still or contacts.impact_ok[b]))
    return need


def lane_friction(contacts: Contacts, g: float, n_cases: int) -> Friction:
    """The lanes' contact checks (:class:`~rocking.dynamics.batch_lanes.Friction`) of the blocks
    of ``contacts`` under gravity g [m/s²], for a call of ``n_cases`` cases (none failed yet)."""
    margins = (1.0 - CONE_MARGIN, N_MARGIN * g)
    return Friction(*contacts, *margins, np.zeros(n_cases, dtype=np.bool_))


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
        c = Contact(
            g,
            contacts.R[b],
            contacts.rg2[b],
            contacts.mu_s[b],
            contacts.mu_k[b],
            contacts.e_ratio[b],
            contacts.impact_ok[b],
        )
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
