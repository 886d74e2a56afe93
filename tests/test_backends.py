"""Backends: the same results, bit for bit, locally and on a real Dask cluster of processes."""

import os
import signal
import time

import numba
import numpy as np
import pytest
import xarray as xr

from rocking.dynamics.body import Block
from rocking.errors import InputError
from rocking.montecarlo.backends import Backend, DaskBackend, LocalBackend, get_backend
from rocking.montecarlo.probability import agx_50, overturning_probability
from rocking.motions.synthesis import generate

RUN_STATS = ("chunks_computed", "chunks_loaded")


@pytest.fixture(scope="module")
def ensemble():
    return generate(8, duration=6.0, dt=1 / 200, seed=9)


@pytest.fixture(scope="module")
def dask_backend():
    backend = DaskBackend(n_workers=2)
    yield backend
    backend.close()


BLOCKS = [Block(0.6, 3.0), Block(1.22, 4.0), Block(2.0, 2.5), Block(3.0, 5.0)]
AGX = np.round(np.arange(0.1, 1.6, 0.1), 12)


def _science(ds):
    out = ds.copy()
    out.attrs = {k: v for k, v in ds.attrs.items() if k not in RUN_STATS}
    return out


def _identical(a, b):
    """Datasets equal bit for bit (floats compared by their bytes, NaN included)."""
    xr.testing.assert_identical(_science(a), _science(b))
    for name in a.data_vars:
        assert a[name].values.tobytes() == b[name].values.tobytes(), name


def test_get_backend():
    assert isinstance(get_backend(None), LocalBackend)
    assert isinstance(get_backend("local"), LocalBackend)
    remote = get_backend("tcp://127.0.0.1:8786")  # not connected until used
    assert isinstance(remote, DaskBackend) and remote.address == "tcp://127.0.0.1:8786"
    assert get_backend("dask-local").address is None
    with pytest.raises(InputError, match="scheduler"):
        get_backend("cluster")
    with pytest.raises(InputError, match="n_threads"):
        LocalBackend(n_threads=0)


def test_dask_without_the_cluster_extra_is_named(monkeypatch):
    # Dask is the optional "cluster" extra: without it, asking for a Dask scheduler is refused
    # at once with the install command (never an ImportError in the middle of a run).
    import importlib.util

    find_spec = importlib.util.find_spec
    monkeypatch.setattr(
        importlib.util,
        "find_spec",
        lambda name, *args: None if name == "distributed" else find_spec(name, *args),
    )
    for scheduler in ("dask-local", "tcp://127.0.0.1:8786"):
        with pytest.raises(
            InputError,
            match=r"scheduler: Dask distributed is not installed.*"
            r"rocking\[cluster\]",
        ):
            get_backend(scheduler)


def test_local_results_do_not_depend_on_chunks_or_threads(ensemble):
    one = overturning_probability(
        BLOCKS, ensemble, AGX, members=True, chunk_size=8, backend=LocalBackend(n_threads=1)
    )
    big = overturning_probability(BLOCKS, ensemble, AGX, members=True, chunk_size=10_000)
    assert one.attrs["chunks_computed"] == len(BLOCKS) * AGX.size  # one pair per chunk
    assert big.attrs["chunks_computed"] < 10
    _identical(one, big)


def test_dask_cluster_gives_identical_results(ensemble, dask_backend):
    client = dask_backend.client
    pids = client.run(os.getpid)
    assert len(pids) == 2 and os.getpid() not in pids.values()  # two worker processes
    # each task uses its worker's share of the cores: together they do not oversubscribe them
    threads = dask_backend.map(
        lambda data, task: numba.get_num_threads(), dask_backend.scatter(None), range(4)
    )
    assert {n for _, n in threads} == {max(1, os.cpu_count() // 2)}

    local = overturning_probability(BLOCKS, ensemble, AGX, members=True)
    remote = overturning_probability(
        BLOCKS, ensemble, AGX, members=True, backend=dask_backend, chunk_size=24
    )
    assert remote.attrs["chunks_computed"] > 2  # really spread over tasks
    _identical(local, remote)

    cases = {"all": ensemble, "first six": ensemble.subset(range(6))}
    _identical(
        agx_50(BLOCKS, cases, resolution=0.02),
        agx_50(BLOCKS, cases, resolution=0.02, backend=dask_backend, chunk_size=16),
    )


def test_local_cluster_keeps_every_copy_of_the_shared_inputs(dask_backend):
    # The inputs are broadcast so that they survive the loss of a worker; distributed's Active
    # Memory Manager (on by default, every 2 s) would reduce them to one copy within seconds,
    # and killing that worker then ended a run with "cancelled ... already forgotten" (seen
    # once in CI). 5 s: at least two of its rounds.
    handle = dask_backend.scatter(np.arange(1000.0))
    workers = len(dask_backend.client.nthreads())
    time.sleep(5.0)
    assert workers == 2 and len(dask_backend.client.who_has(handle)[handle.key]) == workers


class KillWorkerAfterFirstChunk(Backend):
    """Runs on the cluster of ``backend`` and kills (-9) a worker that is computing a task as
    soon as the first result has been handed over: the engine writes that chunk to ``out``
    before it asks for the next result, so the kill follows an event, not a guess of timing."""

    def __init__(self, backend, out):
        self.backend, self.out = backend, out
        self.killed = []  # (worker address, its tasks at the kill, chunk files on disk then)

    @property
    def workers(self):
        return self.backend.workers

    def scatter(self, data):
        return self.backend.scatter(data)

    def map(self, func, handle, tasks):
        results = self.backend.map(func, handle, tasks)
        yield next(results)
        client = self.backend.client
        pids = client.run(os.getpid)
        busy = [(address, keys) for address, keys in client.processing().items() if keys]
        address, keys = busy[0] if busy else (next(iter(pids)), ())
        os.kill(pids[address], signal.SIGKILL)
        self.killed.append((address, list(keys), len(list(self.out.glob("chunk-*.npz")))))
        yield from results


def test_dask_worker_killed_mid_run_loses_nothing(ensemble, dask_backend, tmp_path):
    """kill -9 one worker once the first chunk is back: its tasks run again elsewhere."""
    killer = KillWorkerAfterFirstChunk(dask_backend, tmp_path)
    agx = np.round(np.arange(0.1, 2.0, 0.1), 12)
    remote = overturning_probability(
        BLOCKS, ensemble, agx, members=True, out=tmp_path, backend=killer, chunk_size=8
    )
    [(address, keys, chunks_at_kill)] = killer.killed
    assert keys, f"worker {address} held no task when it was killed"
    n_chunks = len(BLOCKS) * agx.size
    assert 0 < chunks_at_kill < n_chunks, "the worker was not killed mid-run"
    assert remote.attrs["chunks_computed"] == n_chunks  # every chunk received exactly once
    assert len(list(tmp_path.glob("chunk-*.npz"))) == n_chunks
    _identical(remote, overturning_probability(BLOCKS, ensemble, agx, members=True))


def test_an_absent_scheduler_is_reported_within_seconds(ensemble, tmp_path):
    # The defect (issue 48): `--scheduler tcp://127.0.0.1:1` waited 30 s before saying it could
    # not connect. Nothing listens on port 1 of this machine: a loopback address waits 5 s by
    # default (the refusal itself is immediate; distributed retries until the timeout), another
    # address 30 s, and --connect-timeout chooses.
    from click.testing import CliRunner

    from rocking.cli import main
    from rocking.montecarlo.backends import default_connect_timeout

    assert default_connect_timeout("tcp://127.0.0.1:8786") == 5.0
    assert default_connect_timeout("tcp://localhost:8786") == 5.0
    assert default_connect_timeout("tcp://10.0.0.5:8786") == 5.0
    assert default_connect_timeout("tcp://scheduler.example.org:8786") == 30.0
    assert default_connect_timeout("tcp://8.8.8.8:8786") == 30.0
    with pytest.raises(InputError, match="connect_timeout must be > 0"):
        DaskBackend("tcp://127.0.0.1:1", connect_timeout=0.0)
    motions = tmp_path / "m.nc"
    ensemble.save(motions)
    for extra, limit in (([], 12.0), (["--connect-timeout", "1"], 6.0)):
        args = ["agx50", "--bodies", "example", "--motions", str(motions), "--quiet"]
        args += ["--scheduler", "tcp://127.0.0.1:1", "--out", str(tmp_path / f"o{len(extra)}")]
        start = time.perf_counter()
        result = CliRunner().invoke(main, [*args, *extra])
        wall = time.perf_counter() - start
        assert result.exit_code == 1, result.output
        assert "cannot connect to tcp://127.0.0.1:1" in result.output
        assert len(result.output.strip().splitlines()) == 1
        assert wall < limit, wall


def test_result_files_are_the_same_bytes_locally_on_dask_and_resumed(ensemble, tmp_path):
    # The defect (issue 49): agx50.nc recorded how many chunks were computed (129 locally, 653
    # or 617 on Dask) and loaded (a resumed run), so its bytes differed between backends and
    # runs. That bookkeeping is in run.json now; the results are the same bytes.
    import json

    from click.testing import CliRunner

    from rocking.cli import main

    motions = tmp_path / "m.nc"
    ensemble.save(motions)
    files = {}
    for name, scheduler in (("local", "local"), ("dask", "dask-local"), ("local", "local")):
        out = tmp_path / name
        args = ["agx50", "--bodies", "example", "--motions", str(motions), "--resolution", "0.1"]
        result = CliRunner().invoke(main, [*args, "--scheduler", scheduler, "--out", str(out)])
        assert result.exit_code == 0, result.output
        files.setdefault(name, []).append(
            {f: (out / f).read_bytes() for f in ("agx50.nc", "agx50.csv")}
        )
        counts = json.loads((out / "run.json").read_text())["bookkeeping"]["agx50.nc"]
        assert set(counts) == set(RUN_STATS)
    assert counts["chunks_computed"] == 0 and counts["chunks_loaded"] > 0  # resumed
    assert files["local"][0] == files["dask"][0] == files["local"][1]
