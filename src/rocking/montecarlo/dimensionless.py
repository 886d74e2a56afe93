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
constant), so their per-body β in :func:`rocking.im_efficiency` is PGA's and PGV's.  They differ
when bodies are pooled: :func:`rocking.im_efficiency` fits one fragility to the outcomes of all
bodies against each measure too, and :func:`dimensionless_efficiency` returns those rows for
PGA, PGV and the two dimensionless measures.
"""

from __future__ import annotations

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
from ..motions.intensity import intensity_measures, omega_ratio
from ..motions.wavelets import pulse_period
from .fragility import POOLED, im_efficiency

#: The IMs :func:`dimensionless_efficiency` compares.
DIMENSIONLESS_IMS = ("pga", "pgv", "pga/gtana", "pgv*p/gtana")


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
    pulses = [pulse_period(a, ensemble.dt) for a in ensemble.acc]
    t_p = np.array([p.period for p in pulses])  # [s]
    rows = []
    for b in blocks:
        ims = intensity_measures(ensemble, ["pga/gtana", "pgv*p/gtana"], body=b, g=g)
        rows.append(
            pd.DataFrame(
                {
                    "body": b.label,
                    "motion": list(ensemble.labels),
                    "pga_over_uplift": ims.iloc[:, 0].to_numpy(),
                    "pgv_p_over_uplift": ims.iloc[:, 1].to_numpy(),
                    "pulse_period": t_p,
                    "pulse_like": [p.pulse_like for p in pulses],
                    "omega_ratio": omega_ratio(t_p, b.p_at(g)),
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

    An IDA scales every motion to each PGA of ``levels`` [g] (:func:`rocking.im_efficiency`,
    ``scale_im="pga"``); every (body, level, motion) run is a point of one cloud whose intensity
    is the scaled motion's IM (its PGA and PGV times the scale factor; the dimensionless ones
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
        As for :func:`rocking.im_efficiency` (e, backend, progress, n_boot (default 0 here),
        …).

    Returns
    -------
    DataFrame
        One row per IM, sorted by β: ``im`` (``pga``, ``pgv``, ``pga/gtana``, ``pgv*p/gtana``),
        ``unit``, ``median`` [the IM's unit], ``beta``: :func:`rocking.im_efficiency`'s pooled
        rows (its rows of the one body if there is one).
    """
    blocks = block_list(blocks)
    options.setdefault("n_boot", 0)
    table = im_efficiency(blocks, ensemble, DIMENSIONLESS_IMS, levels=levels, g=g, **options)
    if len(blocks) > 1:
        table = table[table["body"] == POOLED]
    return table[["im", "unit", "median", "beta"]].reset_index(drop=True)
