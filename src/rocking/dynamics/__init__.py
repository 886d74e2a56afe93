"""Rocking of rigid blocks (paper Section 2): the bodies, the equation of motion and its kernels.

* :mod:`~rocking.dynamics.body` — :class:`Block` and Housner's energy balance, Eq. (11);
* :mod:`~rocking.dynamics.equation` — Eq. (1) and its Runge–Kutta step (compiled, pure);
* :mod:`~rocking.dynamics.impacts` — impacts, uplift, rest and overturning in one sample interval;
* :mod:`~rocking.dynamics.modes` — every response mode (rest, slide, rock, slide-rock, flight)
  of one block with friction (issue 45), compiled;
* :mod:`~rocking.dynamics.physics` — :class:`Physics`, the physics of a simulation as one record;
* :mod:`~rocking.dynamics.limits` — :class:`LimitState` on the kernel's response quantities;
* :mod:`~rocking.dynamics.simulate` — :func:`simulate`, one block under one motion;
* :mod:`~rocking.dynamics.batch` — many simulations at once (SIMD lanes, threads): the entry
  points, with its records in :mod:`~rocking.dynamics.batch_records`, its lane machine in
  :mod:`~rocking.dynamics.batch_lanes` and its cases with friction in
  :mod:`~rocking.dynamics.batch_modes`;
* :mod:`~rocking.dynamics.reference` — an independent SciPy ``solve_ivp`` solver for the tests.
"""

from ..core.exports import lazy_exports

__getattr__, __dir__, __all__ = lazy_exports(__name__, globals())
