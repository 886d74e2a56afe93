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
    "DaskBackend": "backends", "LocalBackend": "backends", "get_backend": "backends",
    "overturn_batch": "batch", "overturn_cases": "batch",
    "NamedBody": "bodies", "read_bodies": "bodies", "read_bodies_table": "bodies",
    "FOOT": "body", "G": "body", "Block": "body", "housner_sv": "body", "paper_bodies": "body",
    "ASCE7": "design_spectra", "EC8": "design_spectra", "design_pga": "design_spectra",
    "parse_spectrum": "design_spectra",
    "RockingResponse": "dynamics", "simulate": "dynamics",
    "assess": "energy", "available_sv": "energy", "energy_balance": "energy",
    "InputError": "errors", "RockingError": "errors",
    "LognormalFit": "fragility", "agx_50": "fragility", "fit_lognormal": "fragility",
    "overturning_probability": "fragility", "wilson_interval": "fragility",
    "PRESETS": "frames", "ShearFrame": "frames", "kN_per_cm_to_N_per_m": "frames",
    "kN_per_g_to_kg": "frames",
    "Inventory": "inventory", "Item": "inventory", "SlidingWarning": "inventory",
    "read_inventory": "inventory",
    "Ensemble": "motions", "baseline_correct": "motions", "generate": "motions",
    "limit_peaks": "motions", "spectral_fit": "motions",
    "Record": "records", "read_record": "records", "read_records": "records",
    "Report": "report", "provenance": "report",
    "results_table": "screen", "screen": "screen",
    "RG160": "spectra", "ResponseSpectrum": "spectra", "TabulatedSpectrum": "spectra",
    "TargetSpectrum": "spectra", "response_spectrum": "spectra", "rg160": "spectra",
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
    from .backends import DaskBackend, LocalBackend, get_backend
    from .batch import overturn_batch, overturn_cases
    from .bodies import NamedBody, read_bodies, read_bodies_table
    from .body import FOOT, G, Block, housner_sv, paper_bodies
    from .design_spectra import ASCE7, EC8, design_pga, parse_spectrum
    from .dynamics import RockingResponse, simulate
    from .energy import assess, available_sv, energy_balance
    from .errors import InputError, RockingError
    from .fragility import (LognormalFit, agx_50, fit_lognormal, overturning_probability,
                            wilson_interval)
    from .frames import PRESETS, ShearFrame, kN_per_cm_to_N_per_m, kN_per_g_to_kg
    from .inventory import Inventory, Item, SlidingWarning, read_inventory
    from .motions import Ensemble, baseline_correct, generate, limit_peaks, spectral_fit
    from .records import Record, read_record, read_records
    from .report import Report, provenance
    from .screen import results_table, screen
    from .spectra import (RG160, ResponseSpectrum, TabulatedSpectrum, TargetSpectrum,
                          response_spectrum, rg160)
    from .studies import reproduce
