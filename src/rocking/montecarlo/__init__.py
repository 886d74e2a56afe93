"""Overturning probability over ensembles of motions (paper Sections 6–8).

* :mod:`~rocking.montecarlo.probability` — probability against A_gx, A_gx of 50 %;
* :mod:`~rocking.montecarlo.pulse_spectrum` — overturning spectra under pulses (issue 46);
* :mod:`~rocking.montecarlo.dimensionless` — PGA/(g·tan α), PGV·p/(g·tan α), Ω and their β;
* :mod:`~rocking.montecarlo.statistics` — Wilson intervals, lognormal fragility fits and their
  bootstrap intervals;
* :mod:`~rocking.montecarlo.engine` — the chunked, resumable engine behind both;
* :mod:`~rocking.montecarlo.backends` — where chunks run: this process or a Dask cluster;
* :mod:`~rocking.montecarlo.store` — the on-disk store of finished chunks.
* :mod:`~rocking.montecarlo.export` — fragility curves written for loss tools (pelicun,
  OpenQuake).
"""

from ..core.exports import lazy_exports

__getattr__, __dir__, __all__ = lazy_exports(__name__, globals())
