"""Infrastructure shared by every layer, with no physics in it.

* :mod:`~rocking.core.compile` — Numba settings of every compiled kernel (cache folder, ``fma``);
* :mod:`~rocking.core.checks` — input checks whose errors name the parameter;
* :mod:`~rocking.core.files` — atomic writing of files;
* :mod:`~rocking.core.process` — settings of the processes that run rocking's commands;
* :mod:`~rocking.core.progress` — progress reports on a terminal and off it;
* :mod:`~rocking.core.runs` — output folders of runs (claim, status, recorded outputs).
"""
