"""Process settings of rocking's commands (rocking.core.process): OpenMP threads that sleep when
idle, a less frequent cyclic garbage collector and no collections at exit; the user's own
OMP_WAIT_POLICY wins, and importing the library changes nothing."""

from __future__ import annotations

import gc
import os
import subprocess
import sys

import pytest

from rocking.core.process import GC_THRESHOLDS


def _printed(code: str, **env: str) -> str:
    """What ``code`` prints in a fresh interpreter, OMP_WAIT_POLICY unset unless given."""
    environ = {k: v for k, v in os.environ.items() if k != "OMP_WAIT_POLICY"}
    out = subprocess.run(
        [sys.executable, "-c", code],
        capture_output=True,
        text=True,
        check=True,
        env={**environ, **env},
    )
    return out.stdout


def _python(code: str, **env: str) -> str:
    """The last line :func:`_printed` by ``code``."""
    return _printed(code, **env).strip().splitlines()[-1]


_AFTER_A_COMMAND = (
    "import gc, os\nfrom rocking.cli import main\n"
    "try:\n    main(['table1', '--help'])\nexcept SystemExit:\n    pass\n"
    "print(os.environ.get('OMP_WAIT_POLICY'), tuple(gc.get_threshold()))"
)


def test_a_command_makes_the_settings_and_keeps_the_users_wait_policy():
    assert _python(_AFTER_A_COMMAND) == f"PASSIVE {GC_THRESHOLDS}"
    assert _python(_AFTER_A_COMMAND, OMP_WAIT_POLICY="ACTIVE") == f"ACTIVE {GC_THRESHOLDS}"


def test_the_objects_are_frozen_at_exit():
    # Python's shutdown runs full collections over every object (0.6 s of a `quick` run's exit);
    # frozen objects are out of their reach.  An exit handler registered before the settings runs
    # after theirs and sees the frozen objects.
    code = (
        "import atexit, gc\n"
        "atexit.register(lambda: print('frozen', gc.get_freeze_count() > 1000))\n"
        "from rocking.core.process import configure_process\n"
        "configure_process()\nconfigure_process()\n"
        "import numpy\n"
    )
    assert _python(code) == "frozen True"
    assert _python(code.replace("configure_process()\nconfigure_process()", "")) == "frozen False"


def test_drawing_workers_keep_the_default_collector():
    # Each figure a worker draws becomes cyclic garbage: with the higher thresholds a worker held
    # 153 MB after the 23 figures of `quick` instead of 104 MB (measured 2026-11-27), so the
    # workers keep Python's own thresholds and only sleep when idle and freeze at exit.
    from rocking.report import drawing_pool

    default = _python("import gc\nprint(tuple(gc.get_threshold()))")
    with drawing_pool(2) as pool:
        assert pool is not None
        assert str(pool.submit(gc.get_threshold).result()) == default
        assert pool.submit(os.getenv, "OMP_WAIT_POLICY").result() == "PASSIVE"


def test_importing_the_library_changes_nothing():
    code = (
        "import atexit, gc, os\nbefore = gc.get_threshold()\n"
        "atexit.register(lambda: print('frozen', gc.get_freeze_count() > 0))\n"
        "import rocking, rocking.cli, rocking.report, rocking.studies\n"
        "print(os.environ.get('OMP_WAIT_POLICY'), gc.get_threshold() == before)"
    )
    assert _printed(code).split() == ["None", "True", "frozen", "False"]


def test_idle_openmp_threads_do_not_spin_after_a_parallel_kernel():
    # Measured with this code on a 2-vCPU AMD EPYC (2026-11-27): with libgomp's default policy the
    # process used 7.7-8.9 ms of CPU in each 0.1 s of sleep after a parallel region (its worker
    # thread spinning), with the settings 0.07-0.12 ms.  The bound, 2 ms, sits between the two
    # with a wide margin for a loaded machine; without the settings this test fails.
    code = (
        "import time, numba, numpy as np\n"
        "from rocking.core.process import configure_process\n"
        "configure_process()\n"
        "@numba.njit(parallel=True)\n"
        "def total(x):\n"
        "    s = 0.0\n"
        "    for i in numba.prange(x.size):\n"
        "        s += x[i]\n"
        "    return s\n"
        "x = np.ones(10_000)\n"
        "total(x)\n"
        "spent = []\n"
        "for _ in range(5):\n"
        "    total(x)\n"
        "    c = time.process_time()\n"
        "    time.sleep(0.1)\n"
        "    spent.append(time.process_time() - c)\n"
        "print(numba.threading_layer(), numba.get_num_threads(), sorted(spent)[2])\n"
    )
    layer, threads, spent = _python(code).split()
    if layer != "omp" or int(threads) < 2:
        pytest.skip(f"Numba's threading layer is {layer} with {threads} thread(s), not OpenMP's")
    assert float(spent) < 2e-3, f"{float(spent) * 1e3:.2f} ms of CPU while idle for 0.1 s"


def _dask_fragility(tmp_path) -> list[str]:
    """A fragility run on a local Dask cluster long enough to be killed mid-run (72 bodies x
    19 levels x 40 motions of 10 s: 20-30 s on 2 cores)."""
    from rocking.motions.synthesis import generate

    motions = generate(40, duration=10.0, dt=0.01, seed=1).save(tmp_path / "m.nc")
    return ["fragility", "--bodies", "paper", "--motions", str(motions), "--agx", "0.1:1.0:0.05"]


@pytest.mark.parametrize(
    "command, workers",
    [
        (lambda tmp: ["reproduce", "4", "--fidelity", "quick"], 1),
        (lambda tmp: [*_dask_fragility(tmp), "--scheduler", "dask-local"], 2),
    ],
    ids=["reproduce-drawing-worker", "fragility-dask-local"],
)
def test_workers_die_with_a_command_killed_outright(tmp_path, command, workers):
    # The defect (issue 49): after `kill -9` of `rocking reproduce`, its drawing worker and
    # Python's resource_tracker stayed alive (13 minutes) and held the caller's standard output
    # open, so that a pipe from the command never closed. The workers now die with it, and the
    # tracker ends when they have. The same holds for the processes of a local Dask cluster
    # (`--scheduler dask-local`: two worker processes and their resource_tracker; its scheduler
    # and nannies live in the command's process): they end within about 1.5 s (measured
    # 2026-12-04), as a Dask worker process exits when the pipe its nanny holds open closes
    # (distributed.process.AsyncProcess).
    import contextlib
    import shutil
    import signal
    import threading
    import time

    import psutil

    if len(os.sched_getaffinity(0)) < 2:
        pytest.skip("one processor: reproduce draws its figures without a worker")
    exe = shutil.which("rocking", path=os.path.dirname(sys.executable))
    launcher = [exe] if exe else [sys.executable, "-m", "rocking.cli"]
    proc = subprocess.Popen(
        [*launcher, *command(tmp_path), "--out", str(tmp_path / "r")],
        stdout=subprocess.PIPE,
        stderr=subprocess.DEVNULL,
        stdin=subprocess.DEVNULL,
    )
    children: list[psutil.Process] = []
    try:
        parent = psutil.Process(proc.pid)
        deadline = time.monotonic() + 60
        # the workers (spawned interpreters) once they have started
        while sum("spawn_main" in " ".join(_cmdline(c)) for c in children) < workers:
            assert proc.poll() is None and time.monotonic() < deadline, "no worker started"
            time.sleep(0.05)
            children = parent.children(recursive=True)
        time.sleep(1.0)  # the workers run their initializers
        children = parent.children(recursive=True)
        assert proc.poll() is None, "the command ended before it was killed"
        os.kill(proc.pid, signal.SIGKILL)
        closed = threading.Event()
        threading.Thread(target=lambda: (proc.stdout.read(), closed.set()), daemon=True).start()
        assert closed.wait(10), "the command's standard output stayed open after kill -9"
        _, alive = psutil.wait_procs(children, timeout=10)
        alive = [p for p in alive if p.status() != psutil.STATUS_ZOMBIE]
        assert not alive, [p.cmdline() for p in alive]
    finally:
        proc.kill()
        proc.wait()
        for child in children:  # only the processes this test started
            with contextlib.suppress(psutil.NoSuchProcess):
                child.kill()


def _cmdline(process) -> list[str]:
    """The command line of ``process``; none for a child that has already ended (a zombie not yet
    reaped, or gone): short-lived helpers of start-up end while the test lists the children."""
    import psutil

    try:
        return process.cmdline()
    except (psutil.ZombieProcess, psutil.NoSuchProcess):
        return []
