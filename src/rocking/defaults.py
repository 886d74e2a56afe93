"""Constants and defaults of the package, in one place (standard library only).

The modules that compute with these values import them from here, and so does the command line,
whose options need them before anything heavy is loaded (``rocking --help`` and a mistyped
option answer in a fraction of a second).
"""

from __future__ import annotations

import math

#: Standard gravity [m/s²].
G = 9.80665
#: Coefficient of restitution of the paper (Aslam et al. 1980; paper Section 2) [-].
DEFAULT_E = 0.925
#: The usual sizes R [m] and slenderness ratios γ [-] of a Block: a rigid body from a millimetre
#: to a kilometre, from a slab 100 times wider than high to a needle 100 times higher than wide.
#: Outside, a Block warns (rocking.dynamics.body.BodyWarning): the input is more often a mistake
#: of units than meant, but any finite R > 0 and γ > 0 is a body.
R_RANGE_M = (1e-3, 1e3)
#: Largest length of a body [m], the Earth's mean radius: larger is refused as no body at all.
R_MAX_M = 6.371e6
GAMMA_RANGE = (1e-2, 1e2)
#: The paper's time step of the motions and of the Runge–Kutta integration [s].
DT = 1.0 / 400.0
#: Impact schemes of the rocking kernels: "located" (the default: the impact instant found
#: inside the step) and "step-end" (θ = 0 and θ' × e at the end of a step that changes side;
#: issue 17). :func:`rocking.dynamics.impacts.resolve_impacts` reads them.
IMPACT_SCHEMES = ("located", "step-end")
#: Static friction coefficient μ_s [-] of the contact of a body and its base: None is infinite
#: friction (the paper's "sufficient friction so that no slippage occurs"; issue 45).
DEFAULT_MU = None
#: Kinetic friction coefficient μ_k ≤ μ_s [-]: None is μ_s.
DEFAULT_MU_K = None
#: The response modes of a free-standing body (issue 45), in the order of their index in the
#: kernels' ``mode`` (rocking.dynamics.modes).
MODES = ("rest", "slide", "rock", "slide-rock", "flight")
#: The angle abs(θ) at which a block counts as overturned (the paper's: the block on its side,
#: where gravity no longer brings it back for any α < π/2) [rad].
OVERTURN_ANGLE = math.pi / 2
#: The response quantities the batched kernel records per case
#: (:class:`rocking.dynamics.batch.Outcome`), on which a :class:`rocking.LimitState` is defined:
#: overturned (yes/no), max abs(θ)/α [-], uplift (the block left rest at all, yes/no), and
#: with friction (issue 45) the largest and the final abs(slip) [m] and the largest lift of
#: the base above the ground [m].
RESPONSE_QUANTITIES = (
    "overturned",
    "peak_theta_ratio",
    "uplift",
    "peak_slip",
    "residual_slip",
    "peak_lift",
)
#: Names of the response quantities in the text form of limit states (``--limit-states``).
QUANTITY_ALIASES = {
    "overturn": "overturned",
    "theta/alpha": "peak_theta_ratio",
    "slip": "peak_slip",
    "lift": "peak_lift",
}
#: The text form of a list of limit states (:func:`rocking.dynamics.limits.parse_limit_states`).
LIMIT_STATE_SYNTAX = (
    "limit states separated by commas, each 'uplift', 'overturn', 'theta/alpha>=X' [-], "
    "'slip>=X' [m] or 'lift>=X' [m] (X > 0; also any quantity of "
    + ", ".join(RESPONSE_QUANTITIES)
    + " as QUANTITY>=X), "
    "optionally named NAME=…, e.g. 'uplift, theta/alpha>=0.5, overturn'"
)
#: The paper's band of the available pseudo-velocity S_v [Hz] (Section 8).
BAND_HZ = (0.04, 0.6)
#: Band over which the fit of simulated motions to their target is summarised [Hz].
FIT_BAND = (0.2, 33.0)
#: Shapes of the idealised near-fault pulses (:func:`rocking.pulse`; issue 46).
PULSE_SHAPES = (
    "half-sine",
    "one-sine",
    "one-cosine",
    "rectangular",
    "ricker",
    "ricker-antisymmetric",
    "mavroeidis-papageorgiou",
)
#: Default upper limit κ = a_p/(g·tan α) [-] and number of scanned amplitudes of the
#: overturning spectra (:func:`rocking.overturning_spectrum`).
PULSE_KAPPA_MAX = 20.0
PULSE_N_SCAN = 256
#: Extensions of the figure files Matplotlib writes (its ``savefig`` formats; tests/test_cli.py
#: checks this list against the installed Matplotlib), so that a figure's name is checked before
#: the work that draws it.
FIGURE_FORMATS = (
    *("eps", "jpeg", "jpg", "pdf", "pgf", "png", "ps", "raw", "rgba", "svg", "svgz", "tif"),
    *("tiff", "webp"),
)
#: Names of the intensity functions (paper Fig. 2; :mod:`rocking.motions.envelopes`).
ENVELOPE_NAMES = ("boxcar", "compound", "trapezoidal")
#: Names of the shear-frame presets (paper Section 7; :data:`rocking.structures.frames.PRESETS`).
FRAME_PRESETS = ("paper-2.0", "paper-1.5", "paper-1.0", "paper-0.5")
#: Sections of the paper that ``rocking reproduce`` runs, with what they show.
STUDY_SECTIONS = {
    "4": "baseline correction (Figs. 3-4)",
    "5": "sensitivity to motion, intensity, size, slenderness, e (Figs. 5-8)",
    "6": "duration and intensity function (Figs. 9-10)",
    "7": "floors of shear frames (Figs. 11-12)",
    "8": "Housner's energy balance (Figs. 13-16, Tables 1-3, worked examples)",
    "soundness": "time step, ensemble size, ensemble strength, the Section 8 floor (issue 17)",
    "friction": "beyond the paper: A_gx50 and Table 3 with friction mu = 0.3-0.8 (issue 45)",
}
#: Float format of CSV tables: 12 significant digits keep every value to far better than any
#: result needs, and drop binary noise such as 0.23000000000046314 (an A_gx found on a 0.01 g
#: grid, scaled and scaled back) or 1.8288000000000002 (6 ft in metres).
CSV_FLOAT_FORMAT = "%.12g"
#: The syntax of a design-spectrum specification (:func:`rocking.motions.design.parse_spectrum`).
SPECTRUM_SYNTAX = (
    "rg160:PGA (e.g. rg160:0.3; optional damping=0.05), "
    "asce7:SDS=…,SD1=…,TL=… (g, g, s), "
    "ec8:type=1|2,ground=A…E,ag=… (a_gR in g; optional importance=…, damping=…), "
    "or a CSV file of frequency [Hz] or period [s] and PSA [g] or PSV [cm/s or m/s] (e.g. a "
    "floor response spectrum, or the output of 'rocking spectrum --csv' or 'rocking frame "
    "spectra --csv'), FILE:NAME choosing one spectrum of a file that holds several (a record, "
    "a floor)"
)
#: Damping ratio of Sa, PSV and Sa_avg when an intensity measure names none [-].
IM_DAMPING = 0.05
#: Periods, log-spaced over the range, whose geometric mean is Sa_avg when none is named [-].
SAAVG_PERIODS = 10
#: The forms of an intensity measure (:func:`rocking.motions.intensity.parse_im`).
IM_SYNTAX = (
    "pga [g], pgv [m/s], pgd [m], sa(T) or sa(T,zeta) [g], psv(T) or psv(T,zeta) [m/s], "
    "saavg(T1:T2), saavg(T1:T2:n) or saavg(T1:T2:n,zeta) [g], arias [m/s], cav [m/s], "
    "pgv/pga [s], per body pga/gtana, pgv*p/gtana, omega [-] (T in s, zeta a fraction, "
    "default 0.05; n periods, default 10)"
)

#: Bootstrap resamples of the motions for the intervals of a fragility's median and β, in the
#: Python functions and on the command line alike. 1000, the usual number for percentile
#: intervals (Efron & Tibshirani 1993, An Introduction to the Bootstrap: ~1000 for intervals,
#: 25-200 for standard errors): measured, the 2.5 % end of the median's interval varies
#: between seeds by 0.2 % of the median with 1000 resamples, 0.5 % with 200, and 1000 cost
#: ~20 ms per body (29 levels x 27 motions; 5 ms with 200).
N_BOOT = 1000
#: Bootstrap resamples of the β intervals of the IM ranking (``im_efficiency``), API and command
#: line alike: each resample refits clouds of levels x motions points (~1.4 s per IM and body
#: with 1000 resamples for 29 levels x 27 motions, ~0.3 s with 200), and the ranking reads
#: the point βs.
N_BOOT_EFFICIENCY = 200

#: The intensity-measure name of the paper's A_gx (the ensemble's mean PGA [g]) in the
#: fragility analyses and on the command line.
AGX = "agx"
