"""rocking: rocking and overturning of free-standing rigid blocks under earthquakes.

SI units throughout (m, s, m/s², rad); intensities such as A_gx and PGA are in g.
"""

from .backends import DaskBackend, LocalBackend, get_backend
from .batch import overturn_batch, overturn_cases
from .bodies import NamedBody, read_bodies, read_bodies_table
from .body import FOOT, G, Block, housner_sv, paper_bodies
from .design_spectra import ASCE7, EC8, design_pga, parse_spectrum
from .dynamics import RockingResponse, simulate
from .energy import assess, available_sv, energy_balance
from .errors import InputError, RockingError
from .fragility import LognormalFit, agx_50, fit_lognormal, overturning_probability, wilson_interval
from .frames import PRESETS, ShearFrame, kN_per_cm_to_N_per_m, kN_per_g_to_kg
from .inventory import Inventory, Item, SlidingWarning, read_inventory
from .motions import Ensemble, baseline_correct, generate, limit_peaks, spectral_fit
from .records import Record, read_record, read_records
from .report import Report, provenance
from .screen import results_table, screen
from .spectra import RG160, ResponseSpectrum, TabulatedSpectrum, TargetSpectrum, response_spectrum, rg160

__all__ = [
    "DaskBackend", "LocalBackend", "get_backend",
    "overturn_batch", "overturn_cases",
    "NamedBody", "read_bodies", "read_bodies_table",
    "FOOT", "G", "Block", "housner_sv", "paper_bodies",
    "ASCE7", "EC8", "design_pga", "parse_spectrum",
    "RockingResponse", "simulate",
    "assess", "available_sv", "energy_balance",
    "InputError", "RockingError",
    "LognormalFit", "agx_50", "fit_lognormal", "overturning_probability", "wilson_interval",
    "PRESETS", "ShearFrame", "kN_per_cm_to_N_per_m", "kN_per_g_to_kg",
    "Inventory", "Item", "SlidingWarning", "read_inventory",
    "Ensemble", "baseline_correct", "generate", "limit_peaks", "spectral_fit",
    "Record", "read_record", "read_records",
    "Report", "provenance",
    "results_table", "screen",
    "RG160", "ResponseSpectrum", "TabulatedSpectrum", "TargetSpectrum", "response_spectrum", "rg160",
    "reproduce",
]


def __getattr__(name):
    # rocking.reproduce is loaded on first use: the studies import Matplotlib, which the
    # simulation API does not need (PEP 562 module __getattr__).
    if name == "reproduce":
        from .studies import reproduce

        return reproduce
    raise AttributeError(f"module 'rocking' has no attribute {name!r}")

try:
    from importlib.metadata import version as _version

    __version__ = _version("rocking")
except Exception:  # pragma: no cover - not installed (running from a source tree)
    __version__ = "0+unknown"
