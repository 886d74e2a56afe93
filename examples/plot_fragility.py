"""
Fragility curves of a few bodies
================================

The probability that a body overturns under an ensemble of RG 1.60-compatible simulated ground
motions, as a function of the ensemble's intensity A_gx (its mean peak ground acceleration, in
g): the paper's Figs. 9–11 and 13. Each point is a count of overturned motions out of n, shown
with its 95 % Wilson interval; a lognormal curve is fitted to the counts by maximum likelihood.
"""

import numpy as np

import rocking
from rocking.plots.fragility import plot_fragility

# %%
# Fifty motions of 20 s at the paper's step of 1/400 s, with the paper's compound intensity
# function, from seed 0 (member k is the same motion whatever the ensemble size). The paper
# used 200 (500 for its Section 6); fifty keep this example to seconds, at the price of wide
# intervals.
ensemble = rocking.generate(50, duration=20.0, seed=0)
print(f"{ensemble.n} motions, {ensemble.n_t} samples at {ensemble.dt} s, A_gx {ensemble.agx:.2f} g")

# %%
# Three of the paper's bodies: R = 4 ft at γ = 3 and 5, and R = 8 ft at γ = 5.
bodies = [
    rocking.Block(4 * rocking.FOOT, 3.0),
    rocking.Block(4 * rocking.FOOT, 5.0),
    rocking.Block(8 * rocking.FOOT, 5.0),
]
agx = np.round(np.arange(0.1, 1.51, 0.1), 2)
ds = rocking.overturning_probability(bodies, ensemble, agx, progress=False)
ds["probability"].to_pandas().round(2)

# %%
# The lognormal fit of each body (median A_gx of 50 % probability [g], dispersion β [-]).
fits = {}
for label in ds["body"].values:
    one = ds.sel(body=label)
    fits[label] = rocking.fit_lognormal(agx, one["count"].values, one["n"].values)
    print(f"{label}: median {fits[label].median:.3f} g, β = {fits[label].beta:.3f}")

# %%
# The curves: the slender small block is the most fragile; the larger block of the same
# slenderness needs a stronger motion (the scale effect of Housner's model).
fig = plot_fragility(ds, fits=fits, title="Overturning probability, 50 RG 1.60 motions")
