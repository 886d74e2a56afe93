"""Assessing real bodies: Housner's energy balance, body lists, inventories and screening.

* :mod:`~rocking.assessment.energy` — required against available S_v (Section 8, Tables 1–3);
* :mod:`~rocking.assessment.bodies` — lists of bodies read from CSV;
* :mod:`~rocking.assessment.inventory` — inventories of equipment (CSV, TOML);
* :mod:`~rocking.assessment.screen` — screening an inventory against a design spectrum;
* :mod:`~rocking.assessment.risk` — hazard curves and the annual rate of overturning.
"""

from ..core.exports import lazy_exports

__getattr__, __dir__, __all__ = lazy_exports(__name__, globals())
