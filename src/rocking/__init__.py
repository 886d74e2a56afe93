"""rocking: rocking and overturning of free-standing rigid blocks under earthquakes.

SI units throughout (m, s, m/s², rad); intensities such as A_gx and PGA are in g.

The public names below are loaded on first use (PEP 562 module ``__getattr__``): ``import rocking``
itself imports nothing heavy, so the command line starts fast and a script pays only for the parts
it uses (Numba, SciPy, xarray and Matplotlib take seconds to import).
"""

from __future__ import annotations

from typing import TYPE_CHECKING

from .core.exports import lazy_exports

_public, __dir__, __all__ = lazy_exports(__name__, globals())


def __getattr__(name: str):
    if name == "__version__":  # read on first use (rocking.core.version)
        from .core.version import package_version

        return package_version()
    return _public(name)


if TYPE_CHECKING:  # the names for type checkers and IDEs
    from .assessment.bodies import NamedBody, read_bodies, read_bodies_table
    from .assessment.energy import assess, available_sv, energy_balance
    from .assessment.inventory import Inventory, Item, read_inventory
    from .assessment.risk import HazardCurve, RiskResult, annual_rate, check_hazard_im
    from .assessment.screen import results_table, screen
    from .core.runs import provenance
    from .dynamics.batch import overturn_batch, overturn_cases
    from .dynamics.body import FOOT, Block, BodyWarning, G, housner_sv, paper_bodies
    from .dynamics.limits import LimitState
    from .dynamics.modes import MODES
    from .dynamics.physics import Physics
    from .dynamics.simulate import RockingResponse, simulate
    from .errors import InputError, RockingError
    from .montecarlo.backends import DaskBackend, LocalBackend, get_backend
    from .montecarlo.dimensionless import dimensionless_efficiency, dimensionless_intensities
    from .montecarlo.export import export_fragility
    from .montecarlo.fragility import fragility_analysis, im_efficiency
    from .montecarlo.probability import agx_50, member_outcomes, overturning_probability
    from .montecarlo.pulse_spectrum import overturning_spectrum
    from .montecarlo.statistics import (
        CrossingWarning,
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
    from .motions.formats import RecordHeaderWarning
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
    from .motions.units import ImplausiblePeakWarning
    from .motions.wavelets import VelocityPulse, pulse_period
    from .report import Report
    from .structures.frames import PRESETS, ShearFrame, kN_per_cm_to_N_per_m, kN_per_g_to_kg
    from .studies import reproduce
