"""Overturning probability over ensembles of motions (paper Sections 6–8).

* :mod:`~rocking.montecarlo.probability` — probability against A_gx, A_gx of 50 %;
* :mod:`~rocking.montecarlo.statistics` — Wilson intervals, lognormal fragility fits and their
  bootstrap intervals;
* :mod:`~rocking.montecarlo.engine` — the chunked, resumable engine behind both;
* :mod:`~rocking.montecarlo.backends` — where chunks run: this process or a Dask cluster;
* :mod:`~rocking.montecarlo.store` — the on-disk store of finished chunks.
* :mod:`~rocking.montecarlo.export` — fragility curves written for loss tools (pelicun,
  OpenQuake).
"""
