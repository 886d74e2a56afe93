"""
Sliding, rocking and slide-rocking
==================================

With a friction coefficient μ (issue 45), a free-standing block is no longer held at its pivot:
it may rest, slide, rock, slide-rock or fly, as the contact forces allow. The block of the
README's figure, R = 2 m, γ = 3.5 (B/H = 0.29), on μ_s = 0.32, μ_k = 0.27 under El Centro 1940
NS at a PGA of 0.7 g mostly rocks, but slides and slide-rocks in the strong pulses between 1.7
and 5.2 s; a squat block on the same floor slides without rocking.
"""

import numpy as np

import rocking
from rocking.motions.records import example_record_path
from rocking.plots.rocking import plot_response

record = rocking.read_record(example_record_path())
ag = record.acc * (0.7 / record.pga)  # scaled to a PGA of 0.7 g [m/s²]

# %%
# The slender block: θ/α, the slip [mm] and the ground acceleration, the times it slide-rocks
# shaded. ``mode`` indexes ``rocking.MODES`` at every sample.
block = rocking.Block(R=2.0, gamma=3.5)
response = rocking.simulate(block, ag, record.dt, mu=0.32, mu_k=0.27)
shares = np.bincount(response.mode, minlength=len(rocking.MODES)) / response.mode.size
print({name: round(float(s), 4) for name, s in zip(rocking.MODES, shares) if s})
print(f"max |slip| {1e3 * response.max_abs_slip:.1f} mm")
print(f"residual slip {1e3 * response.residual_slip:.1f} mm")
fig_slide_rock = plot_response(response, ag / rocking.G)

# %%
# The friction needed to rock without slip grows with the acceleration (Shenton 1996; a uniform
# block from rest, β = B/H, a = abs(a_g)/g): μ_cr(a) = [a(1 + 4β²) + 3β]/[4 + β² + 3aβ]. This block
# starts to rock at a = β = 0.29 with μ_cr = β, and needs more than its μ_s = 0.32 from about
# a = 0.43: above that it slide-rocks.
beta = block.B / block.H
for a in (beta, 0.43, 0.5, 0.7):
    mu_cr = (a * (1 + 4 * beta**2) + 3 * beta) / (4 + beta**2 + 3 * a * beta)
    print(f"a = {a:.2f}: mu_cr = {mu_cr:.3f}")

# %%
# A squat block (B/H = 0.8) on μ = 0.2 cannot rock (friction cannot supply the moment that
# tips it: μ < B/H): it slides, Newmark's rigid sliding block.
safe = rocking.Block.from_dimensions(1.0, 0.8)
response = rocking.simulate(safe, ag, record.dt, mu=0.2, mu_k=0.18)
print(
    f"max |theta| {response.max_abs_theta:g} rad, max |slip| {1e3 * response.max_abs_slip:.0f} mm"
)
fig_slide = plot_response(response, ag / rocking.G)
