"""
Screening an inventory
======================

Screen the shipped example inventory (sixteen pieces of equipment, on the ground and on the
floors of a five-story shear frame) against an ASCE 7 design spectrum: for every item, the
Monte Carlo probability of overturning at the design level with its 95 % Wilson interval and
the verdict it gives (at risk from 50 %), the ground A_gx at which it overturns with 50 %
probability, its response with friction (the share of motions in which it rests, slides,
rocks, slide-rocks or overturns, and its slip), and Housner's Eq. (11) with its margin, the
conservative quick screen. This is ``rocking screen example`` in Python.
"""

from importlib.resources import files

import rocking
from rocking.plots.screen import plot_screen

# %%
# The inventory: name, height and width [m], location (``ground`` or ``floor N``), frame,
# restitution e, friction coefficients μ (static) and μ_k (kinetic); ``frame`` is the building
# of the ``floor N`` items. With μ the simulations model every response mode: rest, slide,
# rock, slide-rock and flight (no μ: infinite friction, rocking only).
path = files("rocking") / "data" / "example_inventory.csv"
inventory = rocking.read_inventory(str(path), frame="paper-2.0")
print(f"{len(inventory.items)} items")

# %%
# The design spectrum: ASCE 7 with S_DS = 1.0 g, S_D1 = 0.6 g, T_L = 8 s. Its zero-period
# acceleration, 0.4·S_DS, is the design A_gx.
spectrum = rocking.parse_spectrum("asce7:SDS=1.0,SD1=0.6,TL=8")
print(f"design A_gx = {rocking.design_pga(spectrum):.2f} g")

# %%
# Screen with 30 spectrum-compatible motions (200 by default: here fewer, for speed; the
# intervals are wide). Floor motions are the frame's response to the same ground motions.
ds = rocking.screen(inventory, spectrum, n=30, seed=0, resolution=0.02, progress=False)
table = rocking.results_table(ds)
table

# %%
# The items on the S_v–A_gx plane, numbered as the rows of the table: left of the dashed
# design line they overturn with more than 50 % probability; below the dotted line of their
# location they fail Eq. (11).
fig = plot_screen(ds, title="Example inventory, ASCE 7 (S_DS = 1.0 g), 30 motions")

# %%
# The response at the design level, from the same simulations: the most frequent response of
# each item, the share of the motions of each, and the median and largest peak slip [mm] over
# the motions that leave it standing.
columns = ["item", "mu [-]", "mode", "P(rest) [-]", "P(slide) [-]", "P(rock) [-]"]
columns += ["P(slide-rock) [-]", "P(overturn) [-]"]
columns += ["median slip if standing [mm]", "max slip if standing [mm]"]
table[columns]
