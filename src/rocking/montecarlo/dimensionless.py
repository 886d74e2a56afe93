"""Dimensionless intensity measures of rocking (issue 46): PGA/(g·tan α) and PGV·p/(g·tan α)
per body, the pulse frequency ratio Ω = ω_p/p per motion, and whether they predict overturning
better than PGA and PGV.

Rocking depends on the ground motion only through u = a_g/g and time, and a block only through
α, p and e (Eq. 1): a motion's PGA over the uplift acceleration g·tan α, and its PGV over the
velocity g·tan α/p that the block's own time scale 1/p gives it, are the measures of rocking
that do not depend on the units (Dimitrakopoulos & Paraskeva 2015, "Dimensionless fragility
curves for rocking response to near-fault excitations", Earthq. Eng. Struct. Dyn. 44).

For one body these are PGA and PGV times a constant: a fragility fitted against them has the
same dispersion β (a lognormal's β does not change when its variable is multiplied by a
constant), so :func:`rocking.im_efficiency` would rank them exactly as PGA and PGV.  They differ
when bodies are pooled: :func:`dimensionless_efficiency` fits one fragility to the outcomes of
all bodies against each measure and compares the β.
"""

from __future__ import annotations

import math
from collections.abc import Sequence
from typing import Any

import numpy as np
import pandas as pd
from numpy.typing import ArrayLike

from ..defaults import G
from ..dynamics.batch import block_list
from ..dynamics.body import Block
from ..errors import InputError
from ..motions.ensemble import Ensemble
from ..motions.intensity import intensity_measures
from ..motions.wavelets import pulse_period
from .fragility import fragility_analysis
from .statistics import fit_lognormal


def dimensionless_intensities(
    blocks: Block | Sequence[Block], ensemble: Ensemble, *, g: float = G
) -> pd.DataFrame:
    """PGA/(g·tan α), PGV·p/(g·tan α) and Ω = ω_p/p of every (body, motion).

    ω_p = 2π/T_p with T_p the pulse period of the motion (:func:`rocking.pulse_period`, Shahi &
    Baker 2014; reported whether or not the motion is pulse-like, which ``pulse_like`` says).

    Returns
    -------
    DataFrame
        One row per (body, motion): ``body`` (label), ``motion``, ``pga_over_uplift`` [-],
        ``pgv_p_over_uplift`` [-], ``pulse_period`` [s], ``pulse_like`` (bool),
        ``omega_ratio`` [-].
    """
    blocks = block_list(blocks)
    if not isinstance(ensemble, Ensemble):
        raise InputError(f"ensemble must be a rocking.Ensemble, got {type(ensemble).__name__}")
    ims = intensity_measures(ensemble, ["pga", "pgv"])
    pga = ims.iloc[:, 0].to_numpy() * G  # [m/s²] (PGA comes in units of standard gravity)
    pgv = ims.iloc[:, 1].to_numpy()  # [m/s]
    pulses = [pulse_period(a, ensemble.dt) for a in ensemble.acc]
    t_p = np.array([p.period for p in pulses])
    rows = []
    for b in blocks:
        uplift = g * math.tan(b.alpha)
        p = b.p_at(g)
        rows.append(
            pd.DataFrame(
                {
                    "body": b.label,
                    "motion": list(ensemble.labels),
                    "pga_over_uplift": pga / uplift,
                    "pgv_p_over_uplift": pgv * p / uplift,
                    "pulse_period": t_p,
                    "pulse_like": [p.pulse_like for p in pulses],
                    "omega_ratio": 2.0 * math.pi / (t_p * p),
                }
            )
        )
    return pd.concat(rows, ignore_index=True)


def dimensionless_efficiency(
    blocks: Block | Sequence[Block],
    ensemble: Ensemble,
    *,
    levels: ArrayLike,
    g: float = G,
    **options: Any,
) -> pd.DataFrame:
    """Dispersion β of one lognormal fragility fitted to all bodies at once against PGA, PGV,
    PGA/(g·tan α) and PGV·p/(g·tan α): smaller β, a better predictor of overturning.

    An IDA scales every motion to each PGA of ``levels`` [g] (:func:`rocking.fragility_analysis`,
    ``im="pga"``); every (body, level, motion) run is a point of one cloud whose intensity is
    the scaled motion's IM (its PGA and PGV times the scale factor; the dimensionless ones
    divided by the body's g·tan α, times p for PGV), and a lognormal is fitted to it by maximum
    likelihood (:func:`rocking.fit_lognormal`, one trial per point).

    Parameters
    ----------
    blocks : sequence of Block
        The bodies pooled (of different sizes and slenderness: for one body, or bodies alike,
        the dimensionless measures have the β of PGA and PGV).
    ensemble : Ensemble
        The motions [m/s²].
    levels : array_like
        PGA levels [g] of the IDA, spanning the bodies' fragility.
    g : float
        Gravity [m/s²].
    **options :
        As for :func:`rocking.fragility_analysis` (e, backend, progress, …).

    Returns
    -------
    DataFrame
        One row per IM, sorted by β: ``im``, ``unit``, ``median`` [the IM's unit], ``beta``.
    """
    blocks = block_list(blocks)
    ida = fragility_analysis(
        blocks, ensemble, im="pga", method="ida", levels=levels, g=g, n_boot=1, **options
    )
    ims = intensity_measures(ensemble, ["pga", "pgv"])
    pga, pgv = ims.iloc[:, 0].to_numpy(), ims.iloc[:, 1].to_numpy()  # [g], [m/s]
    factors = ida["level"].values[:, None] / pga[None, :]  # (level, motion)
    y = ida["overturned"].values  # (body, level, motion)
    uplift = np.array([g * math.tan(b.alpha) for b in blocks])[:, None, None]  # [m/s²]
    p = np.array([b.p_at(g) for b in blocks])[:, None, None]  # [rad/s]
    ones = np.ones_like(uplift)
    measures = {
        ("pga", "g"): ones * factors * pga,
        ("pgv", "m/s"): ones * factors * pgv,
        ("pga/(g tan alpha)", "-"): factors * pga * G / uplift,
        ("pgv p/(g tan alpha)", "-"): factors * pgv * p / uplift,
    }
    rows = []
    for (name, unit), x in measures.items():
        count = y.ravel().astype(np.int64)
        fit = fit_lognormal(x.ravel(), count, np.ones_like(count))
        rows.append({"im": name, "unit": unit, "median": fit.median, "beta": fit.beta})
    return pd.DataFrame(rows).sort_values("beta", kind="stable", ignore_index=True)
