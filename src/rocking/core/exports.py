"""The public names of the package and of each subpackage, loaded on first use.

:data:`PUBLIC` maps every public name to the module that defines it. ``rocking`` serves them
all and each subpackage serves its own (``from rocking.motions import generate`` and
``from rocking import generate`` give the same object), through a PEP 562 module
``__getattr__`` made by :func:`lazy_exports`: importing a package imports nothing heavy, so
the command line starts fast and a script pays only for the parts it uses (Numba, SciPy,
xarray and Matplotlib take seconds to import). Standard library only.
"""

from __future__ import annotations

import importlib
from collections.abc import Callable
from typing import Any

#: Public name → module of the package that defines it (relative to ``rocking``).
PUBLIC = {
    "Compute": "montecarlo.backends",
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
    "BodyWarning": "dynamics.body",
    "housner_sv": "dynamics.body",
    "paper_bodies": "dynamics.body",
    "ASCE7": "motions.design",
    "EC8": "motions.design",
    "design_pga": "motions.design",
    "parse_spectrum": "motions.design",
    "LimitState": "dynamics.limits",
    "MODES": "dynamics.modes",
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
    "CrossingWarning": "montecarlo.statistics",
    "FragilityFit": "montecarlo.statistics",
    "bootstrap_fragility": "montecarlo.statistics",
    "export_fragility": "montecarlo.export",
    "agx_50": "montecarlo.probability",
    "fragility_analysis": "montecarlo.fragility",
    "im_efficiency": "montecarlo.fragility",
    "fit_lognormal": "montecarlo.statistics",
    "overturning_probability": "montecarlo.probability",
    "overturning_spectrum": "montecarlo.pulse_spectrum",
    "SpectrumScan": "montecarlo.pulse_spectrum",
    "Agx50Search": "montecarlo.search",
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
    "read_inventory": "assessment.inventory",
    "Ensemble": "motions.ensemble",
    "baseline_correct": "motions.baseline",
    "generate": "motions.synthesis",
    "Synthesis": "motions.synthesis",
    "regenerate": "motions.synthesis",
    "pulse": "motions.pulses",
    "pulse_period": "motions.wavelets",
    "VelocityPulse": "motions.wavelets",
    "limit_peaks": "motions.synthesis",
    "spectral_fit": "motions.synthesis",
    "Record": "motions.records",
    "read_record": "motions.records",
    "read_records": "motions.records",
    "ImplausiblePeakWarning": "motions.units",
    "RecordHeaderWarning": "motions.formats",
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


def exports(package: str) -> dict[str, str]:
    """The public names that ``package`` serves (``"rocking"`` or a subpackage such as
    ``"rocking.motions"``) → the absolute name of the module that defines each. A subpackage
    does not serve a name that is also one of its modules (``rocking.dynamics.simulate`` and
    ``rocking.assessment.screen`` are the modules; the functions are ``rocking.simulate`` and
    ``rocking.screen``)."""
    prefix = package.removeprefix("rocking").lstrip(".")
    served = {}
    for name, module in PUBLIC.items():
        if prefix and not (module == prefix or module.startswith(prefix + ".")):
            continue
        if prefix and module != prefix and module.split(".")[1] == name:
            continue  # the submodule of that name
        served[name] = f"rocking.{module}"
    return served


def lazy_exports(
    package: str, namespace: dict[str, Any]
) -> tuple[Callable[[str], Any], Callable[[], list[str]], list[str]]:
    """The module ``__getattr__``, ``__dir__`` and ``__all__`` of ``package`` (whose module
    dictionary is ``namespace``): each public name is imported from its module on first use,
    then kept in ``namespace``, so that later look-ups are plain attribute reads."""
    served = exports(package)

    def __getattr__(name: str) -> Any:
        module = served.get(name)
        if module is None:
            raise AttributeError(f"module {package!r} has no attribute {name!r}")
        value = getattr(importlib.import_module(module), name)
        namespace[name] = value
        return value

    def __dir__() -> list[str]:
        return sorted(set(namespace) | set(served))

    return __getattr__, __dir__, list(served)
