"""Settings of a process that runs ``rocking``'s commands.

They act on the whole process, so importing the library never makes them: a program that imports
``rocking`` keeps its own.  The command-line interface (:mod:`rocking.cli`, also when its ``main``
is called as a function) and the workers that draw a report's figures
(:func:`rocking.report.drawing_pool`) call :func:`configure_process` before any other work.
None of the settings changes a result, only how the processor's time is spent (measured on a
2-vCPU AMD EPYC Zen 3, 2026-11-27; ``docs/performance.md``):

* ``OMP_WAIT_POLICY=PASSIVE``, unless the environment sets it: Numba's parallel kernels run on
  OpenMP threads (GNU libgomp), which by default spin for about 300,000 rounds (~6 ms) after every
  parallel region before they sleep.  A command calls hundreds of short parallel kernels with
  Python work between them: ``reproduce all --fidelity quick`` kept a core busy for 2.2 s of such
  spinning, time taken from its figure-drawing workers on a 2-core machine.  A passive thread
  sleeps at once and is woken by the next region (tens of microseconds).  libgomp reads the
  variable when it is loaded, at the first parallel call, so it is set before that; child
  processes (drawing workers, a local Dask cluster) inherit it.
* Python's cyclic garbage collector runs less often (thresholds (10000, 50, 10) instead of
  (700, 10, 10)): Matplotlib, xarray and Numba create hundreds of thousands of objects that live
  as long as the process, and every full collection walks all of them (0.1–0.3 s each, six in a
  ``quick`` run: the collector took 0.9 s of its main process, 0.35–0.5 s with these
  thresholds).  Reference counting still frees every object outside a reference cycle at once.
  Not in the drawing workers (``thresholds=False``): each figure they draw becomes a reference
  cycle of thousands of objects, which then piled up (a worker held 153 MB after the 23 figures
  of ``quick`` instead of 104 MB, and the ``paper`` run with its two workers peaked at 1037 MB).
* At exit, every object is moved out of the collector's reach (:func:`gc.freeze`): Python's
  shutdown runs full collections while it tears the modules down, 0.6 s of the 0.75 s that a
  ``quick`` run took to exit after its report was written; the process's memory is returned to
  the system whole anyway.

Worker processes that this process starts die with it (:func:`die_with_parent`), also when it is
killed outright (``kill -9``): a drawing worker left alive held the caller's standard output open
(and Python's ``resource_tracker`` with it), so that a pipe from ``rocking reproduce`` never
closed.
"""

from __future__ import annotations

import atexit
import gc
import os
import signal
import sys
import threading

#: Thresholds of :func:`gc.set_threshold` for rocking's processes (Python's default: 700, 10, 10).
GC_THRESHOLDS = (10_000, 50, 10)


def configure_process(thresholds: bool = True) -> None:
    """Make the settings above in this process (and, through the environment, in the processes it
    starts): ``OMP_WAIT_POLICY=PASSIVE`` unless already set, :data:`GC_THRESHOLDS` (unless
    ``thresholds`` is False), and :func:`gc.freeze` at exit (registered once however often this
    is called)."""
    os.environ.setdefault("OMP_WAIT_POLICY", "PASSIVE")
    if thresholds:
        gc.set_threshold(*GC_THRESHOLDS)
    atexit.unregister(gc.freeze)
    atexit.register(gc.freeze)


#: prctl(2) option that asks the kernel for a signal when the parent ends (linux/prctl.h).
PR_SET_PDEATHSIG = 1


def die_with_parent(parent: int) -> None:
    """End this process (SIGKILL) when its parent, the process ``parent``, ends, however it ends;
    at once if it has already ended.  For worker processes, called first thing in them.

    On Linux the kernel sends the signal (``prctl(PR_SET_PDEATHSIG, SIGKILL)``: when the thread
    that started this process ends, which for rocking's pools is the thread that opened them);
    elsewhere a daemon thread checks every second whether the parent is still this process's
    parent.
    """
    if sys.platform.startswith("linux"):
        import ctypes

        libc = ctypes.CDLL(None, use_errno=True)
        libc.prctl(PR_SET_PDEATHSIG, signal.SIGKILL, 0, 0, 0)
    else:
        threading.Thread(target=_watch_parent, args=(parent,), daemon=True).start()
    if os.getppid() != parent:  # it ended before the request was made
        os._exit(1)


def _watch_parent(parent: int) -> None:
    while os.getppid() == parent:
        threading.Event().wait(1.0)
    os._exit(1)
