"""Where the chunks of a Monte Carlo run are computed (issue 5, part 4).

A backend (a :class:`Backend`) does two things for the engine of
:mod:`rocking.montecarlo.engine` (and says, as ``workers``, how many tasks it runs at the same
time):

``scatter(data)``
    make the run's shared, read-only inputs (motions, block constants) available to the workers
    once, returning a handle;
``map(func, handle, tasks)``
    compute ``func(data, task)`` for every task and yield ``(index, result)`` pairs as they finish,
    in any order.

The engine keys every result by its task index, and every task by the indices of the cases it
holds, so the outcome does not depend on the backend, the number of workers, the completion order
or the chunk size.

:class:`LocalBackend` (the default) computes the tasks one after the other in this process; the
compiled kernel spreads each task over all cores with Numba threads.  :class:`DaskBackend` sends
them to a Dask distributed cluster: an existing one by scheduler address, or a local cluster of
worker processes started on demand.
"""

from __future__ import annotations

import dataclasses
import importlib.util
import math
import os
import weakref
from abc import ABC, abstractmethod
from collections.abc import Callable, Iterator, Sequence
from typing import TYPE_CHECKING, Any

import numba

from ..core.compile import numba_threads
from ..errors import BackendError, InputError

if TYPE_CHECKING:
    from ..core.progress import Reporter


def _call(func, threads, handle, task):
    """``func(handle, task)`` with at most ``threads`` Numba threads (None: as configured)."""
    with numba_threads(threads):
        return func(handle, task)


class Backend(ABC):
    """Where the chunks of a Monte Carlo run are computed: the interface the engine uses (see
    the module notes). A context manager: leaving it calls :meth:`close`."""

    @property
    @abstractmethod
    def workers(self) -> int:
        """Tasks that run at the same time."""

    @abstractmethod
    def scatter(self, data: Any) -> Any:
        """Make the run's shared, read-only ``data`` available to the workers; return a handle."""

    @abstractmethod
    def map(
        self, func: Callable[[Any, Any], Any], handle: Any, tasks: Sequence[Any]
    ) -> Iterator[tuple[int, Any]]:
        """Yield ``(i, func(data, tasks[i]))`` for every task, in any order."""

    def connect(self) -> None:  # noqa: B027 (a backend of this machine has nothing to reach)
        """Reach the machines the backend computes on now, so that an unreachable scheduler is
        refused before the run starts (InputError)."""

    def close(self) -> None:  # noqa: B027 (a backend holding nothing has nothing to release)
        """Release what the backend holds (a cluster, connections)."""

    def __enter__(self) -> Backend:
        return self

    def __exit__(self, *exc) -> None:
        self.close()


class LocalBackend(Backend):
    """Compute tasks in this process, each with Numba's threads.

    Parameters
    ----------
    n_threads : int, optional
        Numba threads for the kernel (default: all, ``numba.config.NUMBA_NUM_THREADS``).
    """

    def __init__(self, n_threads: int | None = None):
        limit = numba.config.NUMBA_NUM_THREADS
        if n_threads is not None and not (isinstance(n_threads, int) and 1 <= n_threads <= limit):
            raise InputError(f"n_threads must be an integer in [1, {limit}], got {n_threads!r}")
        self.n_threads = n_threads

    @property
    def workers(self) -> int:
        """Tasks that run at the same time (one; each uses all the Numba threads)."""
        return 1

    def scatter(self, data: Any) -> Any:
        """Nothing to send: the handle is ``data`` itself."""
        return data

    def map(
        self, func: Callable[[Any, Any], Any], handle: Any, tasks: Sequence[Any]
    ) -> Iterator[tuple[int, Any]]:
        """Yield ``(i, func(handle, tasks[i]))`` in task order."""
        for i, task in enumerate(tasks):
            yield i, _call(func, self.n_threads, handle, task)

    def __repr__(self) -> str:
        return f"LocalBackend(n_threads={self.n_threads})"


def _close(client, cluster) -> None:
    client.close()
    if cluster is not None:
        cluster.close()


class DaskBackend(Backend):
    """Compute tasks on a Dask distributed cluster.

    Parameters
    ----------
    address : str, optional
        Scheduler address (e.g. ``"tcp://10.0.0.5:8786"``); its workers must have this package
        installed, and should run one task thread each with ``NUMBA_NUM_THREADS`` set to their
        share of the cores (``dask worker --nthreads 1``).  Without it, a local cluster of
        ``n_workers`` worker processes is started on first use (and closed by :meth:`close`, at
        the latest when the backend is garbage collected), with one task thread per worker and
        each task limited to cores // n_workers Numba threads, so that the workers together do
        not oversubscribe the cores (reference.md §10).
    n_workers : int
        Worker processes of the local cluster (ignored with ``address``).
    connect_timeout : float, optional
        Seconds to wait for the scheduler at ``address`` before giving up (default
        :func:`connect_timeout`: 5 s for a loopback or private address, 30 s for others).

    Notes
    -----
    Losing a worker loses no work and duplicates none: the scheduler runs the tasks that were on
    the dead worker again elsewhere (up to ``distributed.scheduler.allowed-failures`` times); the
    client receives exactly one result per task index; tasks are pure (the same task always
    gives the same arrays) and chunk files are written by the client only, keyed by the cases they
    hold and replaced atomically, so a repeated task changes nothing.  The shared inputs are
    broadcast to every worker, so they survive the loss of any one worker: in the local cluster,
    whose Active Memory Manager is off (distributed's default one runs ReduceReplicas, which
    leaves one copy within seconds).  On a cluster of yours, disable it (or its ReduceReplicas
    policy) for the same guarantee; otherwise a lost worker may hold the only copy, and the
    command stops with one line (BackendError) and resumes from its chunks when run again.
    """

    def __init__(
        self, address: str | None = None, n_workers: int = 2, connect_timeout: float | None = None
    ):
        if importlib.util.find_spec("distributed") is None:
            raise InputError(
                "scheduler: Dask distributed is not installed; install the cluster extra "
                "(pip install 'rocking[cluster]') to run on a Dask cluster"
            )
        if address is not None and not isinstance(address, str):
            raise InputError(f"address must be a scheduler address string, got {address!r}")
        if not (isinstance(n_workers, int) and n_workers >= 1):
            raise InputError(f"n_workers must be an integer >= 1, got {n_workers!r}")
        if connect_timeout is not None and not (
            isinstance(connect_timeout, (int, float)) and 0 < connect_timeout < math.inf
        ):
            raise InputError(f"connect_timeout must be > 0 [s], got {connect_timeout!r}")
        self.address = address
        self.n_workers = n_workers
        #: Seconds to wait for the scheduler at ``address``.
        self.connect_timeout = (
            connect_timeout if connect_timeout is not None else default_connect_timeout(address)
        )
        #: Numba threads per task: the worker's share of this machine's cores (local cluster).
        self.threads = None if address else max(1, (os.cpu_count() or 1) // n_workers)
        self._client = None
        self._finalizer: weakref.finalize | None = None

    @property
    def client(self) -> Any:
        """The ``distributed.Client`` (connecting or starting the cluster on first use)."""
        if self._client is None:
            self._client, cluster = self._connect()
            self._finalizer = weakref.finalize(self, _close, self._client, cluster)
        return self._client

    def connect(self) -> None:
        """Connect to the scheduler at ``address`` now (InputError if it cannot be reached within
        ``connect_timeout``); a local cluster is still started on first use."""
        if self.address is not None:
            self.client  # noqa: B018 (the property connects)

    def _connect(self):
        import dask
        from distributed import Client, LocalCluster

        if self.address is not None:
            try:
                return Client(self.address, timeout=f"{self.connect_timeout}s"), None
            except (OSError, TimeoutError) as exc:
                raise InputError(
                    f"scheduler: cannot connect to {self.address} within "
                    f"{self.connect_timeout:g} s ({exc}); is it running? (--connect-timeout "
                    "waits longer)"
                ) from None
        # The thread budget is applied by each task (numba.set_num_threads) rather than through
        # NUMBA_NUM_THREADS in distributed.nanny.pre-spawn-environ: Dask also writes those
        # variables into this process's environment, and Numba re-reads it at every compilation,
        # failing ("Cannot set NUMBA_NUM_THREADS to a different value") once its threads run.
        # The Active Memory Manager (on by default) would reduce the broadcast inputs to one
        # copy within seconds (ReduceReplicas), and losing that worker would end the run.
        with dask.config.set({"distributed.scheduler.active-memory-manager.start": False}):
            cluster = LocalCluster(
                n_workers=self.n_workers,
                threads_per_worker=1,
                processes=True,
                dashboard_address=":0",
            )
        return Client(cluster), cluster

    @property
    def workers(self) -> int:
        """Tasks that run at the same time: the cluster's task threads (connects)."""
        return max(1, sum(self.client.nthreads().values()))

    def scatter(self, data: Any) -> Any:
        """Send ``data`` to every worker once; the handle is its future."""
        [future] = self.client.scatter([data], broadcast=True)
        return future

    def map(
        self, func: Callable[[Any, Any], Any], handle: Any, tasks: Sequence[Any]
    ) -> Iterator[tuple[int, Any]]:
        """Submit one Dask task per entry of ``tasks``; yield ``(i, result)`` as they finish.

        Raises :class:`~rocking.errors.BackendError` when the cluster can no longer compute the
        tasks (every worker lost, a task's workers killed too often, the scheduler gone); an
        exception raised by ``func`` itself is raised again as it is.
        """
        from concurrent.futures import CancelledError

        from distributed import KilledWorker, as_completed

        try:
            futures = [
                self.client.submit(_call, func, self.threads, handle, task, pure=False)
                for task in tasks
            ]
            index = {f.key: i for i, f in enumerate(futures)}
            done = as_completed(futures, with_results=True, raise_errors=False)
            for future, result in done:
                # a result was gathered: use it, whatever became of the worker holding it since
                # (a future may read "lost" then, and its task is recomputed for nobody)
                if not isinstance(result, BaseException):
                    yield index[future.key], result
                elif isinstance(result, (KilledWorker, CancelledError)):
                    raise BackendError(
                        f"the Dask cluster lost the workers of a task "
                        f"({type(result).__name__}: {result})"
                    )
                else:
                    raise result  # the task itself failed: not the cluster's doing
        except OSError as exc:  # the scheduler went away (CommClosedError is an OSError)
            raise BackendError(f"lost the connection to the Dask scheduler ({exc})") from None

    def close(self) -> None:
        """Close the client (and the local cluster if this backend started it)."""
        if self._finalizer is not None:
            self._finalizer()
        self._client = None
        self._finalizer = None

    def __repr__(self) -> str:
        where = self.address or f"local cluster, {self.n_workers} workers"
        return f"DaskBackend({where})"


#: Seconds to wait for a scheduler on this machine or a private network (a refused or
#: unanswered connection there is not slow, it is absent), and for one elsewhere.
NEAR_TIMEOUT_S, FAR_TIMEOUT_S = 5.0, 30.0


def default_connect_timeout(address: str | None) -> float:
    """Seconds to wait for the scheduler at ``address``: :data:`NEAR_TIMEOUT_S` for a loopback,
    private or link-local IP address or ``localhost``, else :data:`FAR_TIMEOUT_S` (host names may
    take a while to resolve, remote clusters to answer)."""
    import ipaddress
    from urllib.parse import urlsplit

    host = urlsplit(address or "").hostname or ""
    if host == "localhost":
        return NEAR_TIMEOUT_S
    try:
        ip = ipaddress.ip_address(host)
    except ValueError:
        return FAR_TIMEOUT_S
    return NEAR_TIMEOUT_S if ip.is_loopback or ip.is_private or ip.is_link_local else FAR_TIMEOUT_S


def get_backend(scheduler: str | None = None, connect_timeout: float | None = None) -> Backend:
    """Backend named by ``scheduler``.

    ``None`` or ``"local"``: :class:`LocalBackend`; ``"dask-local"``: :class:`DaskBackend` with
    a local cluster of worker processes; a scheduler address (``"tcp://host:port"``, or another
    Dask protocol such as ``"tls://"``): :class:`DaskBackend` connected to it, waiting at most
    ``connect_timeout`` seconds for it (default :func:`default_connect_timeout`).
    """
    if scheduler is None or scheduler == "local":
        return LocalBackend()
    if scheduler == "dask-local":
        return DaskBackend()
    if isinstance(scheduler, str) and "://" in scheduler:
        return DaskBackend(scheduler, connect_timeout=connect_timeout)
    raise InputError(
        f"scheduler must be 'local', 'dask-local' or a scheduler address like "
        f"'tcp://host:8786', got {scheduler!r}"
    )


@dataclasses.dataclass(frozen=True)
class Compute:
    """How a Monte Carlo run is computed (none of it changes a result): the settings that travel
    together from the command line to the engine (:class:`rocking.montecarlo.engine.Engine`).

    Parameters
    ----------
    backend : LocalBackend or DaskBackend, optional
        Where the chunks run (default: this process, all cores; :func:`get_backend`).
    out : str or Path, optional
        Folder of the finished chunks (:class:`rocking.montecarlo.store.ChunkStore`): a later
        call with the same inputs computes only what the folder lacks; a folder of another run
        is refused.
    progress : Reporter or bool, optional
        Progress bar (default: only if stderr is a terminal).
    chunk_size : int, optional
        Largest number of simulations per chunk (default
        :data:`rocking.montecarlo.engine.CHUNK_SIMULATIONS`; smaller when needed to give each
        worker of the backend about four).
    """

    backend: Backend | None = None
    out: str | os.PathLike[str] | None = None
    progress: Reporter | bool | None = None
    chunk_size: int | None = None
