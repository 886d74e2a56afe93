"""rocking: rocking and overturning of free-standing rigid blocks under earthquakes.

SI units throughout (m, s, m/s², rad); intensities such as A_gx and PGA are in g.

The public names below are loaded on first use (PEP 562 module ``__getattr__``): ``import rocking``
itself imports nothing heavy, so the command line starts fast and a script pays only for the parts
it uses (Numba, SciPy, xarray and Matplotlib take seconds to import).
"""

from __future__ import annotations

import importlib
from typing import TYPE_CHECKING

#: Public name → module of this package that defines it.
_EXPORTS = {
    "DaskBackend": "montecarlo.backends",
    "LocalBackend": "montecarlo.backends",
    "get_backend": "montecarlo.backends",
    "overturn_batch": "dynamics.batch",
    "overturn_cases": "dynamics.batch",
    "NamedBody": "assessment.bodies",
    "read_bodies": "assessment.bodies",
    "read_bodies_table": "assessment.bodies",
    "HazardCurve": "assessment.risk",
    "RiskResult": "assessment.risk",
    "annual_rate": "assessment.risk",
    "check_hazard_im": "assessment.risk",
    "FOOT": "dynamics.body",
    "G": "dynamics.body",
    "Block": "dynamics.body",
    "housner_sv": "dynamics.body",
    "paper_bodies": "dynamics.body",
    "ASCE7": "motions.design",
    "EC8": "motions.design",
    "design_pga": "motions.design",
    "parse_spectrum": "motions.design",
    "LimitState": "dynamics.limits",
    "Physics": "dynamics.physics",
    "RockingResponse": "dynamics.simulate",
    "simulate": "dynamics.simulate",
    "assess": "assessment.energy",
    "available_sv": "assessment.energy",
    "energy_balance": "assessment.energy",
    "InputError": "errors",
    "RockingError": "errors",
    "LognormalFit": "montecarlo.statistics",
    "ExtrapolationWarning": "montecarlo.statistics",
    "FragilityFit": "montecarlo.statistics",
    "bootstrap_fragility": "montecarlo.statistics",
    "agx_50": "montecarlo.probability",
    "fragility_analysis": "montecarlo.fragility",
    "im_efficiency": "montecarlo.fragility",
    "fit_lognormal": "montecarlo.statistics",
    "overturning_probability": "montecarlo.probability",
    "overturning_spectrum": "montecarlo.pulse_spectrum",
    "dimensionless_intensities": "montecarlo.dimensionless",
    "dimensionless_efficiency": "montecarlo.dimensionless",
    "member_outcomes": "montecarlo.probability",
    "wilson_interval": "montecarlo.statistics",
    "PRESETS": "structures.frames",
    "ShearFrame": "structures.frames",
    "kN_per_cm_to_N_per_m": "structures.frames",
    "kN_per_g_to_kg": "structures.frames",
    "Inventory": "assessment.inventory",
    "Item": "assessment.inventory",
    "SlidingWarning": "assessment.inventory",
    "read_inventory": "assessment.inventory",
    "Ensemble": "motions.ensemble",
    "baseline_correct": "motions.baseline",
    "generate": "motions.synthesis",
    "pulse": "motions.pulses",
    "pulse_period": "motions.wavelets",
    "VelocityPulse": "motions.wavelets",
    "limit_peaks": "motions.synthesis",
    "spectral_fit": "motions.synthesis",
    "Record": "motions.records",
    "read_record": "motions.records",
    "read_records": "motions.records",
    "Report": "report",
    "provenance": "core.runs",
    "results_table": "assessment.screen",
    "screen": "assessment.screen",
    "RG160": "motions.targets",
    "ResponseSpectrum": "motions.response",
    "IntensityMeasure": "motions.intensity",
    "im_scaling_exponent": "motions.intensity",
    "intensity_measures": "motions.intensity",
    "parse_im": "motions.intensity",
    "TabulatedSpectrum": "motions.targets",
    "TargetSpectrum": "motions.targets",
    "response_spectrum": "motions.response",
    "rg160": "motions.targets",
    "reproduce": "studies",
}

__all__ = list(_EXPORTS)


def __getattr__(name: str):
    module = _EXPORTS.get(name)
    if module is None:
        raise AttributeError(f"module 'rocking' has no attribute {name!r}")
    value = getattr(importlib.import_module(f".{module}", __name__), name)
    globals()[name] = value  # later look-ups are plain attribute reads
    return value


def __dir__() -> list[str]:
    return sorted(set(globals()) | set(__all__))


try:
    from importlib.metadata import version as _version

    __version__ = _version("rocking")
except Exception:  # pragma: no cover - not installed (running from a source tree)
    __version__ = "0+unknown"

if TYPE_CHECKING:  # the names for type checkers and IDEs
    from .assessment.bodies import NamedBody, read_bodies, read_bodies_table
    from .assessment.energy import assess, available_sv, energy_balance
    from .assessment.inventory import Inventory, Item, SlidingWarning, read_inventory
    from .assessment.risk import HazardCurve, RiskResult, annual_rate, check_hazard_im
    from .assessment.screen import results_table, screen
    from .core.runs import provenance
    from .dynamics.batch import overturn_batch, overturn_cases
    from .dynamics.body import FOOT, Block, G, housner_sv, paper_bodies
    from .dynamics.limits import LimitState
    from .dynamics.physics import Physics
    from .dynamics.simulate import RockingResponse, simulate
    from .errors import InputError, RockingError
    from .montecarlo.backends import DaskBackend, LocalBackend, get_backend
    from .montecarlo.dimensionless import dimensionless_efficiency, dimensionless_intensities
    from .montecarlo.fragility import fragility_analysis, im_efficiency
    from .montecarlo.probability import agx_50, member_outcomes, overturning_probability
    from .montecarlo.pulse_spectrum import overturning_spectrum
    from .montecarlo.statistics import (
        ExtrapolationWarning,
        FragilityFit,
        LognormalFit,
        bootstrap_fragility,
        fit_lognormal,
        wilson_interval,
    )
    from .motions.baseline import baseline_correct
    from .motions.design import ASCE7, EC8, design_pga, parse_spectrum
    from .motions.ensemble import Ensemble
    from .motions.intensity import (
        IntensityMeasure,
        im_scaling_exponent,
        intensity_measures,
        parse_im,
    )
    from .motions.pulses import pulse
    from .motions.records import Record, read_record, read_records
    from .motions.response import ResponseSpectrum, response_spectrum
    from .motions.synthesis import generate, limit_peaks, spectral_fit
    from .motions.targets import RG160, TabulatedSpectrum, TargetSpectrum, rg160
    from .motions.wavelets import VelocityPulse, pulse_period
    from .report import Report
    from .structures.frames import PRESETS, ShearFrame, kN_per_cm_to_N_per_m, kN_per_g_to_kg
    from .studies import reproduce
