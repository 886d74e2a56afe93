"""
Near-fault pulses
=================

The idealised acceleration pulses of :func:`rocking.pulse` (issue 46), each of amplitude
a_p = 1 m/s² and period T_p = 1 s (ω_p = 2π/T_p; the rectangle lasts T_p), with their formulas
in :mod:`rocking.motions.pulses`, and the velocity each one gives the ground.
"""

import numpy as np
from matplotlib.figure import Figure
from scipy.integrate import cumulative_trapezoid

import rocking
from rocking.defaults import PULSE_SHAPES

# %%
# Every shape sampled at 1/200 s, with 0.5 s of tail; the Mavroeidis & Papageorgiou (2003)
# pulse with its default γ = 2 and ν = 0, and with γ = 3, ν = π/2.
dt = 0.005
shapes = [*PULSE_SHAPES, "mavroeidis-papageorgiou:gamma=3,nu=1.5708"]
fig = Figure(figsize=(8.0, 9.0), layout="constrained")
axes = fig.subplots(len(shapes), 2, sharex=True)
for (acc_ax, vel_ax), shape in zip(axes, shapes):
    a = rocking.pulse(shape, 1.0, 1.0, dt, tail=0.5)
    t = np.arange(a.size) * dt
    acc_ax.plot(t, a, color="C0")
    vel_ax.plot(t, cumulative_trapezoid(a, dx=dt, initial=0.0), color="C1")
    acc_ax.set_ylabel(shape.replace(":", "\n"), fontsize="x-small", rotation=0, ha="right")
    for ax in (acc_ax, vel_ax):
        ax.axhline(0.0, color="0.7", lw=0.5)
        ax.tick_params(labelsize="x-small")
axes[0, 0].set_title("acceleration a(t) [m/s²]")
axes[0, 1].set_title("ground velocity v(t) [m/s]")
axes[-1, 0].set_xlabel("t [s]")
axes[-1, 1].set_xlabel("t [s]")
fig
