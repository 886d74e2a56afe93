"""
Floor motions of a shear frame
==============================

Bodies on the floor of a building feel the building's response, not the ground motion. The
paper's Section 7 puts its bodies on the floors of five-story shear frames and compares the
floors' mean pseudo-velocity spectra with the ground's (its Fig. 12). Here: the paper's 2.0 s
frame, its modes, and the mean 5 %-damped PSV of the ground and of every floor, all scaled to
the same A_gx = 0.6 g as the paper does.
"""

import numpy as np

import rocking
from rocking.assessment.energy import mean_psv
from rocking.plots.frames import plot_floor_spectra, plot_mode_shapes

# %%
# The preset ``paper-2.0``: five equal floors, fundamental period 2.0 s, 5 % modal damping.
frame = rocking.ShearFrame.preset("paper-2.0")
print(f"{frame.name}: periods " + ", ".join(f"{T:.3f}" for T in frame.periods) + " s")
fig_modes = plot_mode_shapes(frame)

# %%
# Thirty simulated ground motions; the frame's absolute floor accelerations under each of them
# (exact modal response, linear between samples), every location scaled to A_gx = 0.6 g.
ground = rocking.generate(30, duration=20.0, seed=0)
floors = {k: motions.scaled(0.6) for k, motions in frame.floor_ensembles(ground).items()}

# %%
# Mean PSV of each location. The floors amplify the band around the frame's first frequency,
# 0.5 Hz, inside the 0.04–0.6 Hz band where Housner's Eq. (11) takes the available S_v.
freqs = np.geomspace(0.04, 20.0, 90)
psv = np.array([mean_psv(motions, freqs) for motions in floors.values()])
labels = ["ground" if k == 0 else f"floor {k}" for k in floors]
fig_spectra = plot_floor_spectra(
    freqs, psv, labels, title=f"{frame.name}, 30 motions, all at A_gx = 0.6 g"
)
for label, row in zip(labels, psv):
    in_band = (freqs >= 0.04) & (freqs <= 0.6)
    print(f"{label:8s} largest PSV in 0.04–0.6 Hz: {100 * row[in_band].max():6.1f} cm/s")
