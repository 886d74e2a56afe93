"""The batched kernel's cases with friction (issue 45): which need the response-modes model, and
its compiled loop over them (entry point :func:`rocking.dynamics.batch.run_cases`).

**Which cases keep the rocking lanes** (:func:`modes_needed`).  The lane machine of
:mod:`rocking.dynamics.batch_lanes` integrates rest and rock only, with infinite friction.  A case
of a block with a finite static friction coefficient μ_s gives the lanes' result exactly when it
provably never leaves rest, that is when at every sample of its scaled motion

* the block cannot lift: the lanes' own skip test (:func:`~rocking.dynamics.batch_lanes._may_lift`:
  max abs(scale·a_g)·cos α ≤ (g + abs(scale)·min a_v)·sin α, the samples bound the linear
  ground motion), and
* the base cannot slip: max abs(scale·a_g) ≤ μ_s·(g + abs(scale)·min a_v), with
  g + abs(scale)·min a_v > 0 (no flight).

Then the modes model's rest (:mod:`rocking.dynamics.modes`: rest holds while abs(a_g) ≤ μ_s·G and
abs(a_g) ≤ G·tan α) never ends, and :func:`~rocking.dynamics.modes.modes_case` integrates each
interval from rest with the rocking kernel's own step, which stays at rest: not overturned, peak 0,
no uplift, no slip, no lift — the lanes' answer for a case they skip.  The tests are written in the
kernel's expressions on the motion's extremes (abs(sc·a)/g and 1 + abs(sc)·a_v/g round
monotonically, μ_s·x too), so they are the per-sample tests or stricter.

No such a-priori bound exists for a case that may lift: once the block rocks, the friction it
needs, abs(F)/N with N = G + R·sin φ·θ'' − R·cos φ·θ'² (:mod:`rocking.dynamics.modes`), depends on
θ and θ' along the response, and N → 0 as the block turns fast or approaches overturning, so for
every finite μ_s (even 1e6) a rocking case may slide-rock or fly; the a_g and a_v of the motion
alone do not bound it.  Every case that may lift therefore goes to the modes kernel, as does every
case whose motion may make its base slip.  Blocks without friction (μ_s = None, stored as ∞) keep
the lanes throughout.

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
from .batch_lanes import _may_lift
from .equation import _gv_sample
from .impacts import Body
from .modes import Contact, modes_case


@kernel
def modes_needed(amax, avmin, g, blocks, contacts, body, motion, scale):
    """Whether each case (``body``, ``motion``, ``scale`` arrays) needs the modes kernel (see the
    module docstring): its block has a finite μ_s and its scaled motion may lift the block or make
    its base slip.  ``amax``: max abs(a_g) [m/s²] and ``avmin``: min a_v [m/s²] (None: no
    vertical motion) of each motion; g [m/s²]; ``blocks``, ``contacts``: the per-block records
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
        need[i] = not (still and gvmin > 0.0 and abs(sc * amax[m]) / g <= mu * gvmin)
    return need


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
