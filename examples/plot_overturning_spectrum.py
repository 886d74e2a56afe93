"""
Overturning spectrum under one-sine pulses
==========================================

The block of Zhang & Makris (2001, "Rocking response of free-standing blocks under cycloidal
pulses"): p = 2.14 rad/s (R = 3g/(4p²) = 1.61 m), α = 0.25 rad, restitution 0.9, under one-sine
acceleration pulses a_p·sin(ω_p·t), 0 ≤ t ≤ T_p. :func:`rocking.overturning_spectrum` finds, for
each Ω = ω_p/p, the smallest κ = a_p/(g·tan α) that overturns it and every κ above it, up to
κ = 15, at which the outcome switches: above the minimum lie safe bands, where a stronger pulse
leaves the block standing.
"""

import math

import numpy as np

import rocking
from rocking.plots.pulses import plot_overturning_spectrum

block = rocking.Block(3 * rocking.G / (4 * 2.14**2), 1 / math.tan(0.25))
omegas = np.linspace(1.0, 10.0, 46)
ds = rocking.overturning_spectrum(
    block, "one-sine", 2 * np.pi / (omegas * block.p), e=0.9, kappa_max=15.0
)

# %%
# Zhang & Makris's example, ω_p = 15.7 rad/s (Ω = 7.34): they find the first overturning at
# 2.22 g.
one = rocking.overturning_spectrum(block, "one-sine", [2 * math.pi / 15.7], e=0.9, kappa_max=15.0)
for amp, over, impacts in zip(
    one["switch_amplitude"].values[0] / rocking.G,
    one["overturns"].values[0],
    one["impacts_before_overturning"].values[0],
):
    if np.isfinite(amp):
        what = f"overturns after {impacts} impact(s)" if over else "safe"
        print(f"from a_p = {amp:.3f} g: {what}")

# %%
# The spectrum: overturning amplitudes red, safe bands green.
plot_overturning_spectrum(ds)
