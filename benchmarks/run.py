"""Benchmark suite of the rocking kernel and of the main jobs (issues 6 and 18).

Run from the repository root:

    python benchmarks/run.py [--quick] [--with-paper] [--isa native,avx2] [--out FILE.json]

The suite runs once per instruction set (``--isa``, default both), each in a child process:
``native`` compiles for the CPU of the machine (AVX-512 where it has it, with 512-bit vectors:
:data:`FULL_WIDTH`), ``avx2`` restricts Numba
to a Haswell CPU (``NUMBA_CPU_NAME=haswell NUMBA_CPU_FEATURES=-avx512f``: AVX2 and FMA, no AVX-512;
checked by the registers of compiled code) with its own cache of compiled code; on a machine
without AVX-512 the native run is the AVX2 run, and runs once. It prints a table per run and
writes JSON with the targets and, per instruction set the compiled code used (``runs``:
``avx512``, ``avx2-on-avx512`` the AVX2 run of an AVX-512 machine, ``avx2`` that of a machine
without AVX-512), the machine it ran on (CPU model, SIMD flags, cores, Python/NumPy/Numba
versions, date, commit), what Numba compiled for, the load averages and, measured in the same
run:

* ``kernel``: aggregate throughput of the batched kernel (:func:`rocking.dynamics.batch.run_cases`,
  all Numba threads) in ns per RK4 step, on bodies that keep rocking through 20 s motions (dt =
  1/400 s).  Only steps actually integrated count: the sample intervals in which the block is
  not at rest throughout, up to overturning, counted independently from :func:`rocking.simulate`'s
  response of every case (which must also give the same flags and peaks as the kernel).  Also
  on one thread;
* ``plain_loop``: the same cases by the plain compiled scalar loop of ``plain_loop.py`` (libm
  sin/cos at every stage, one simulation at a time; serially, and over all cores with prange),
  in ns per step it integrates, and the ratio to the kernel;
* ``paired``: the kernel and the plain loop timed in interleaved pairs, on all threads and on
  one: each pair's ratio of wall times (``ratios``) and per integrated step
  (``ratios_per_step``), and the median per step (also ``ratios.vs_plain_loop_paired``): a slow
  spell of a shared host falls on both calls of a pair, where the best times of the two
  separate series (``ratios.vs_plain_loop``) may come from different spells;
* ``modes``: the response-modes kernel of friction (issue 45, :mod:`rocking.dynamics.batch_modes`)
  on the same cases: with μ = 1e6 (they rock as without friction) in ns per step the rocking
  kernel integrates, and its ratio to the rocking kernel (target ≤ 2×); with μ = 0.2, 0.3 and
  0.4 (the bodies slide and slide-rock) in ns per interval walked, and its ratio to the plain
  compiled loop of the same model, ``modes_case`` of every case one after the other on one
  thread (target ≥ 5×), and the SHA-256 of every μ's outcomes (``results_sha256``, compared
  across runs by ``bit_identical.modes``).  ``--modes-only`` runs this entry alone;
* ``ceiling``: the arithmetic floor of a step on this machine (``peak.py``: the clock measured by
  a chain of dependent FMAs, the FMAs a core starts per cycle measured with the run's own vector
  width, the operations of one plain step), and the kernel's time as a multiple of it;
* ``scipy``: :func:`rocking.dynamics.reference.simulate_reference` (``solve_ivp`` DOP853 with
  events) on a few of the cases, seconds per simulation, and the ratio to the kernel's time per
  simulation;
* ``end_to_end``: Table 2 (``rocking motions generate`` of the 200 motions + ``rocking agx50
  --bodies paper``: 72 bodies on the ground, A_gx50 to 0.01 g; best of the runs of each),
  generating 500 motions of 30 s at 400 Hz with their baseline correction, response spectra of
  500 motions (100 frequencies), the floor motions of 500 motions on the 5-story frame
  ``paper-2.0``, an overturning spectrum of 100 pulse periods (:func:`rocking.overturning_spectrum`,
  issue 46; target ≤ 2 s), and ``rocking reproduce all`` at ``--fidelity quick`` (and ``paper`` with
  ``--with-paper``), each with its wall time and, for the commands, peak resident memory (the
  command's process and, sampled, with its worker processes: :func:`run_command`).

A run on another instruction set than this machine's is kept from the file (a machine without
AVX-512 cannot measure it), with its own machine and commit. ``bit_identical`` compares the
SHA-256 of the kernel's flags and peaks (between runs of the same workload, on the same CPU and
across CPUs) and of Table 2's
agx50.csv across all the runs kept, whatever their machine and commit: results must depend on
neither.  Timings are best and median of
repeats (the machine may be shared: see the load averages); compiled code comes from Numba's
cache, warmed up before any timing.
"""

from __future__ import annotations

import argparse
import contextlib
import datetime
import hashlib
import importlib.metadata
import json
import math
import os
import platform
import statistics
import subprocess
import sys
import tempfile
import time
from concurrent.futures import ThreadPoolExecutor
from pathlib import Path

import numba
import numpy as np
import scipy

from rocking.dynamics.batch import (
    BlockTable,
    Cases,
    empty_outcome,
    motion_peaks,
    overturn_batch,
    run_cases,
)
from rocking.dynamics.batch_modes import modes_kernel
from rocking.dynamics.body import Block, G, paper_bodies
from rocking.dynamics.physics import Physics
from rocking.dynamics.reference import simulate_reference
from rocking.dynamics.simulate import simulate
from rocking.montecarlo.pulse_spectrum import overturning_spectrum
from rocking.motions.response import response_spectrum
from rocking.motions.synthesis import generate
from rocking.structures.frames import ShearFrame

sys.path.insert(0, str(Path(__file__).resolve().parent))
import peak
import plain_loop

ROOT = Path(__file__).resolve().parent.parent
DT = 1 / 400  # [s], the paper's
DURATION = 20.0  # [s]
#: Motions of Table 2 (the paper's ensemble size for it).
TABLE2_MOTIONS = 200
#: Targets of issue 18 (each on AVX2 and on AVX-512), and issue 6's ratio to SciPy.
TARGETS = {
    "vs_plain_loop": 10.0,
    "vs_scipy": 10_000.0,
    "table2_s": 3.0,
    "reproduce_paper_s": 30.0,
    "reproduce_paper_peak_gb": 1.0,
    "reproduce_quick_s": 5.0,
    "generate_500_s": 0.3,
    "pulse_spectrum_100_s": 2.0,
    "modes_vs_rocking": 2.0,
    "modes_vs_plain_loop": 5.0,
}
#: Instruction sets the suite runs on: each in a child process with these environment variables
#: (Numba compiles for the named CPU; a separate cache so that no code of another run is reused).
#: NUMBA_CPU_NAME alone is not enough: Numba's JIT adds the host's features to the named CPU's
#: (numba/core/codegen.py, JITCPUCodegen), so AVX-512 must be switched off by name; each run checks
#: which registers its compiled code uses (``vector_registers``).
ISAS = {
    "native": {},
    "avx2": {"NUMBA_CPU_NAME": "haswell", "NUMBA_CPU_FEATURES": "-avx512f"},
}
#: Added to the native run of a machine with AVX-512: LLVM's tuning for Intel's AVX-512 CPUs
#: (Skylake-SP to Emerald Rapids) prefers 256-bit vectors (its ``prefer-256-bit`` feature, against
#: the clock drop of 512-bit code on the older ones), so Numba's native code there uses ymm
#: registers only; AMD's Zen 4 has no such preference.  The native run measures the full width
#: (the same bits: no fastmath, so no reassociation or contraction, at any width).
FULL_WIDTH = {"NUMBA_CPU_FEATURES": "-prefer-256-bit"}


# --------------------------------------------------------------------------- machine


def machine_info() -> dict:
    cpu = {}
    try:
        for line in Path("/proc/cpuinfo").read_text().splitlines():
            key, _, value = line.partition(":")
            cpu.setdefault(key.strip(), value.strip())
    except OSError:
        pass
    model = cpu.get("model name") or platform.processor() or "unknown"
    flags = set(cpu.get("flags", "").split())
    try:
        commit = subprocess.run(
            ["git", "rev-parse", "--short", "HEAD"], cwd=ROOT, capture_output=True, text=True
        ).stdout.strip()
        dirty = bool(
            subprocess.run(
                ["git", "status", "--porcelain", "--untracked-files=no"],
                cwd=ROOT,
                capture_output=True,
                text=True,
            ).stdout.strip()
        )
    except OSError:
        commit, dirty = "unknown", False
    return {
        "cpu_model": model,
        "cpu_family_model": f"{cpu.get('cpu family', '?')}/{cpu.get('model', '?')}",
        "simd": [f for f in ("avx2", "fma", "avx512f") if f in flags],
        "logical_cpus": os.cpu_count(),
        "numba_threads": numba.config.NUMBA_NUM_THREADS,
        "python": platform.python_version(),
        "numpy": np.__version__,
        "scipy": scipy.__version__,
        "numba": numba.__version__,
        "xarray": _installed("xarray"),
        "matplotlib": _installed("matplotlib"),
        # the optional cluster extra: where it is installed, xarray imports dask.array on a
        # process's first Dataset and distributed on its first netCDF file (Zen 3, 2026-11-28:
        # 0.7-1.0 s in a bare script; `agx50` of Table 2 0.3-0.4 s slower in interleaved runs)
        "dask": _installed("dask"),
        "platform": platform.platform(),
        "date_utc": datetime.datetime.now(datetime.UTC).isoformat(timespec="seconds"),
        "rocking_commit": commit + ("+local changes" if dirty else ""),
    }


def _installed(package: str) -> str | None:
    """The installed version of ``package`` (not imported), None if it is not installed."""
    try:
        return importlib.metadata.version(package)
    except importlib.metadata.PackageNotFoundError:
        return None


def load() -> list[float]:
    """1-, 5- and 15-minute load averages (other processes on the machine slow the timings)."""
    return [round(x, 2) for x in os.getloadavg()]


def digest(*arrays: np.ndarray) -> str:
    """SHA-256 of the arrays' bytes: equal digests, bit-identical results."""
    h = hashlib.sha256()
    for a in arrays:
        h.update(np.ascontiguousarray(a).tobytes())
    return h.hexdigest()


def timed(func, repeats: int) -> dict:
    """Wall times [s] of ``repeats`` calls: best, median and all."""
    times = []
    for _ in range(repeats):
        t0 = time.perf_counter()
        func()
        times.append(time.perf_counter() - t0)
    return {"best_s": min(times), "median_s": statistics.median(times), "all_s": times}


# --------------------------------------------------------------------------- kernel workload


def rocking_workload(n_motions: int, seed: int = 11) -> dict:
    """The cases: the paper's 72 bodies under ``n_motions`` stationary (boxcar) 20 s motions,
    each body at the largest A_gx of a grid at which at most 10 % of 20 calibration motions
    overturn it, so that it keeps rocking through most of the motion."""
    ens = generate(n_motions, duration=DURATION, dt=DT, envelope="boxcar", seed=seed)
    blocks = paper_bodies()
    levels = np.geomspace(0.1, 3.0, 24)  # A_gx [g]
    n_cal = min(20, n_motions)
    overturned, _ = overturn_batch(blocks, ens.acc[:n_cal], DT, levels / ens.agx)
    share = overturned.mean(axis=2)  # (body, level)
    ok = share <= 0.1
    level = np.array([levels[np.nonzero(row)[0].max()] if row.any() else levels[0] for row in ok])
    body = np.repeat(np.arange(len(blocks)), n_motions)
    motion = np.tile(np.arange(n_motions), len(blocks))
    scale = (level / ens.agx)[body]
    return {
        "ensemble": ens,
        "blocks": blocks,
        "body": body,
        "motion": motion,
        "scale": scale,
        "agx": level,
    }


def integrated_steps(theta: np.ndarray, omega: np.ndarray) -> int:
    """Sample intervals of a response in which the block is not at rest throughout, up to and
    including the one in which it overturns (θ is NaN after overturning)."""
    nan = np.isnan(theta)
    n_int = int(np.argmax(nan)) if nan.any() else theta.size - 1  # intervals before the NaNs
    still = (theta == 0.0) & (omega == 0.0)
    rest_through = still[:n_int] & still[1 : n_int + 1]
    return int(n_int - np.count_nonzero(rest_through))


def count_with_simulate(w: dict) -> dict:
    """simulate() of every case (threads: its kernel releases the GIL): steps, flags, peaks."""
    acc, blocks = w["ensemble"].acc, w["blocks"]

    def one(i):
        blk = blocks[w["body"][i]]
        r = simulate(blk, w["scale"][i] * acc[w["motion"][i]], DT)
        return integrated_steps(r.theta, r.omega), r.overturned, r.max_abs_theta / blk.alpha

    with ThreadPoolExecutor(os.cpu_count() or 1) as pool:
        res = list(pool.map(one, range(w["body"].size)))
    steps = np.array([r[0] for r in res])
    return {
        "steps": steps,
        "overturned": np.array([r[1] for r in res]),
        "peak": np.array([r[2] for r in res]),
    }


def kernel_args(w: dict) -> tuple:
    """The arguments of :func:`run_cases` for every case of the workload ``w``."""
    acc = np.ascontiguousarray(w["ensemble"].acc)
    table = BlockTable.from_blocks(w["blocks"])
    return (table, acc, motion_peaks(acc), DT, w["body"], w["motion"], w["scale"])


def bench_kernel(w: dict, counted: dict, repeats: int) -> dict:
    args = kernel_args(w)
    table, acc, amax = args[:3]
    run_cases(table, acc, amax, DT, w["body"][:200], w["motion"][:200], w["scale"][:200])
    result = run_cases(*args)
    overturned, peak = result.overturned, result.peak_theta_ratio
    same = bool(
        np.array_equal(overturned, counted["overturned"]) and np.array_equal(peak, counted["peak"])
    )
    steps = int(counted["steps"].sum())
    n_t = acc.shape[1]
    out = {
        "motions_sha256": digest(acc),
        "results_sha256": digest(overturned, peak),
        "cases": int(w["body"].size),
        "steps": steps,
        "share_of_intervals_integrated": steps / (w["body"].size * (n_t - 1)),
        "share_overturned": float(overturned.mean()),
        "equals_simulate": same,
        "threads": numba.get_num_threads(),
    }
    t = timed(lambda: run_cases(*args), repeats)
    out.update({f"all_threads_{k}": v for k, v in t.items()})
    out["ns_per_step"] = t["best_s"] / steps * 1e9
    out["ns_per_step_median"] = t["median_s"] / steps * 1e9
    before = numba.get_num_threads()
    try:
        numba.set_num_threads(1)
        t1 = timed(lambda: run_cases(*args), max(1, repeats // 2))
    finally:
        numba.set_num_threads(before)
    out.update({f"one_thread_{k}": v for k, v in t1.items()})
    out["ns_per_step_one_thread"] = t1["best_s"] / steps * 1e9
    out["s_per_simulation"] = t["best_s"] / w["body"].size
    return out


# --------------------------------------------------------------------------- friction (issue 45)

#: Friction coefficients of the modes entry: "rocking only" (μ so large that the cases rock as
#: without friction, through the modes kernel) and three at which the paper's bodies slide and
#: slide-rock (tan α = 0.17–0.5).
MODES_MU = {"rock_only": 1e6, "slide": (0.2, 0.3, 0.4)}


def _modes_call(w: dict, mu: float | None, cases: slice = slice(None)):
    """``run_cases`` on the workload ``w``'s cases ``cases`` with friction ``mu`` (None: the
    rocking kernel)."""
    acc = np.ascontiguousarray(w["ensemble"].acc)
    table = BlockTable.from_blocks(w["blocks"], physics=Physics(mu=mu))
    args = (table, acc, motion_peaks(acc), DT, w["body"][cases], w["motion"][cases])
    scale = w["scale"][cases]
    return lambda: run_cases(*args, scale)


def _serial_modes(w: dict, mu: float):
    """The plain compiled loop of the same model: ``modes_case`` of every case (none left to
    the lanes), one after the other on one thread (:func:`modes_kernel`'s loop, whose ``prange``
    runs serially on one thread)."""
    acc = np.ascontiguousarray(w["ensemble"].acc)
    table = BlockTable.from_blocks(w["blocks"], physics=Physics(mu=mu))
    order = np.arange(w["body"].size)
    cases = Cases(w["body"], w["motion"], w["scale"], order)
    out = empty_outcome(order.size)

    def call():
        before = numba.get_num_threads()
        try:
            numba.set_num_threads(1)
            modes_kernel(
                acc.reshape(-1),
                None,
                acc.shape[1],
                DT,
                table.arrays(),
                table.contacts,
                cases,
                True,
                out,
            )
        finally:
            numba.set_num_threads(before)
        return out

    return call


def bench_modes(w: dict, repeats: int) -> dict:
    """The response-modes kernel (issue 45) on the workload ``w``: (a) with μ = 1e6 against the
    rocking kernel on the same cases, per step the rocking kernel integrates (the same cases
    and steps: the ratio of wall times); (b) with μ = 0.2, 0.3, 0.4 (slide, slide-rock) against
    the plain compiled loop of the same model (:func:`_serial_modes`), per interval walked
    (every interval up to overturning: the plain loop's ``steps``; the cases that the lanes
    keep count fewer, their intervals not at rest throughout)."""
    sample = slice(0, min(200, w["body"].size))
    rocking = _modes_call(w, None)
    _modes_call(w, None, sample)()  # compile / load
    steps = int(rocking().steps.sum())
    t_rock = timed(rocking, repeats)
    out: dict = {"cases": int(w["body"].size), "rocking_kernel_steps": steps}
    out["rocking_kernel"] = {**t_rock, "ns_per_step": t_rock["best_s"] / steps * 1e9}
    big = _modes_call(w, MODES_MU["rock_only"])
    _modes_call(w, MODES_MU["rock_only"], sample)()
    same = big()
    t_big = timed(big, repeats)
    out["rock_only"] = {
        **t_big,
        "mu": MODES_MU["rock_only"],
        "ns_per_step": t_big["best_s"] / steps * 1e9,
        "vs_rocking_kernel": t_big["best_s"] / t_rock["best_s"],
        "same_flags_and_peaks_as_rocking": bool(
            np.array_equal(same.overturned, rocking().overturned)
            and np.array_equal(same.peak_theta_ratio, rocking().peak_theta_ratio)
        ),
    }
    out["slide"] = {}
    outcomes = list(same[:-1])
    for mu in MODES_MU["slide"]:
        call = _modes_call(w, mu)
        res = call()
        outcomes += res[:-1]
        t = timed(call, repeats)
        serial = _serial_modes(w, mu)
        plain = serial()
        # every interval up to overturning: the plain loop's steps (the lanes count fewer)
        walked = int(plain.steps.sum())
        t_plain = timed(serial, max(1, repeats // 3))
        out["slide"][f"{mu:g}"] = {
            **t,
            "intervals": walked,
            "ns_per_interval": t["best_s"] / walked * 1e9,
            "plain_loop_best_s": t_plain["best_s"],
            "plain_loop_ns_per_interval": t_plain["best_s"] / walked * 1e9,
            "vs_plain_loop": t_plain["best_s"] / t["best_s"],
            "equals_plain_loop": all(np.array_equal(a, b) for a, b in zip(res[:-1], plain[:-1])),
            "share_sliding": float((res.peak_slip > 0).mean()),
            "share_overturned": float(res.overturned.mean()),
        }
    # the outcomes of every μ, to compare across instruction sets and machines (comparable_digests)
    out["results_sha256"] = digest(*outcomes)
    out["threads"] = numba.get_num_threads()
    return out


def plain_calls(w: dict):
    """``call(kind, m)``: the plain loop (``"serial"`` or ``"parallel"``) on the first ``m``
    cases of the workload ``w``; returns (overturned, peak, steps)."""
    blocks = w["blocks"]
    body = w["body"]
    acc = np.ascontiguousarray(w["ensemble"].acc)
    per_case = {
        "motion": w["motion"],
        "scale": w["scale"],
        "p2": np.array([blocks[b].p ** 2 for b in body]),
        "alpha": np.array([blocks[b].alpha for b in body]),
        "e": np.full(body.size, 0.925),
        "th_ov": np.full(body.size, math.pi / 2),
    }

    def call(kind, m):
        c = {k: v[:m] for k, v in per_case.items()}
        return plain_loop.run(
            kind, acc, c["motion"], c["scale"], G, DT, c["p2"], c["alpha"], c["e"], c["th_ov"]
        )

    return call


def bench_plain(w: dict, repeats: int) -> dict:
    call = plain_calls(w)
    n = w["body"].size
    out = {}
    for kind, reps in (("serial", 1), ("parallel", repeats)):
        call(kind, 50)  # compile / load
        _ov, _pk, steps = call(kind, n)
        t = timed(lambda kind=kind: call(kind, n), reps)
        out[kind] = {**t, "steps": int(steps.sum()), "ns_per_step": t["best_s"] / steps.sum() * 1e9}
    return out


def paired(fast, slow, pairs: int) -> dict:
    """Wall times [s] of ``pairs`` calls of ``fast`` and of ``slow``, interleaved (each pair in
    alternating order), and their ratios slow/fast pair by pair: a slow spell of the shared host
    then falls on both calls of a pair, where the best times of two separate series may come
    from different spells (the host moves times by 20-35 % from one run to the next)."""
    fast_s: list[float] = []
    slow_s: list[float] = []
    for i in range(pairs):
        calls = [(fast, fast_s), (slow, slow_s)]
        for f, times in calls if i % 2 == 0 else calls[::-1]:
            t0 = time.perf_counter()
            f()
            times.append(time.perf_counter() - t0)
    ratios = [s / f for f, s in zip(fast_s, slow_s)]
    return {
        "fast_s": fast_s,
        "slow_s": slow_s,
        "ratios": ratios,
        "median_ratio": statistics.median(ratios),
    }


def bench_paired(w: dict, kernel_steps: int, plain: dict, pairs: int) -> dict:
    """The kernel against the plain loop per integrated step, timed in interleaved pairs
    (:func:`paired`): on all threads (``pairs`` pairs) and on one thread (the kernel on one
    Numba thread against the serial loop; fewer pairs, the serial loop takes seconds)."""
    args = kernel_args(w)
    call = plain_calls(w)
    n = w["body"].size
    # ns per step of the plain loop over that of the kernel: the times' ratio scaled by the
    # steps each integrates
    per_step = kernel_steps / plain["parallel"]["steps"]
    out = {"all_threads": paired(lambda: run_cases(*args), lambda: call("parallel", n), pairs)}
    before = numba.get_num_threads()
    try:
        numba.set_num_threads(1)
        out["one_thread"] = paired(
            lambda: run_cases(*args), lambda: call("serial", n), max(1, pairs // 3)
        )
    finally:
        numba.set_num_threads(before)
    for r in out.values():
        r["ratios_per_step"] = [x * per_step for x in r["ratios"]]
        r["median_ratio_per_step"] = r["median_ratio"] * per_step
    return out


def bench_scipy(w: dict, counted: dict, n: int) -> dict:
    acc, blocks = w["ensemble"].acc, w["blocks"]
    # the first case of n bodies spread over the 72 (one motion each)
    idx = [int(np.nonzero(w["body"] == b)[0][0]) for b in np.linspace(0, 71, n).astype(int)]
    times, steps = [], []
    for i in idx:
        blk = blocks[w["body"][i]]
        t0 = time.perf_counter()
        simulate_reference(blk, w["scale"][i] * acc[w["motion"][i]], DT)
        times.append(time.perf_counter() - t0)
        steps.append(int(counted["steps"][i]))
    return {
        "cases": idx,
        "s_per_simulation": statistics.mean(times),
        "all_s": times,
        "ns_per_step": sum(times) / sum(steps) * 1e9,
    }


# --------------------------------------------------------------------------- end to end


#: The ``rocking`` command line, run by :func:`run_command` with ``python -c``: at exit it writes
#: the process's own peak resident memory (VmHWM of /proc/self/status, kB) to the file named by
#: ROCKING_BENCH_HWM.  The peak that wait4/getrusage report is not the command's own: Linux
#: carries a process's maximum RSS across fork and exec, so a command started by this process
#: reported this process's peak whenever it was larger (Table 2's two commands both "used"
#: 410 MB, ``quick`` 731 MB: the benchmark's own size at the time).
_MEASURED_CLI = """
import atexit, os, sys
def _peak(path=os.environ.pop("ROCKING_BENCH_HWM")):
    with open("/proc/self/status") as status:
        kb = next(line.split()[1] for line in status if line.startswith("VmHWM:"))
    with open(path, "w") as out:
        out.write(kb)
atexit.register(_peak)
sys.argv[0] = "rocking"
from rocking.cli import main
main()
"""


def _tree_rss_peak(pid: int, done, interval: float = 0.1) -> float:
    """Largest sum of the resident memory [MB] of process ``pid`` and its descendants (the
    drawing workers of ``reproduce``), sampled every ``interval`` s until ``done`` is set."""
    import psutil

    peak = 0.0
    try:
        root = psutil.Process(pid)
        while not done.is_set():
            procs = [root, *root.children(recursive=True)]
            total = 0
            for p in procs:
                with contextlib.suppress(psutil.Error):  # a worker that just ended
                    total += p.memory_info().rss
            peak = max(peak, total / 2**20)
            done.wait(interval)
    except psutil.Error:  # the command ended
        pass
    return peak


def run_command(args: list[str], cwd: Path) -> dict:
    """Run a ``rocking`` command; its wall time [s], its process's peak resident memory [MB]
    (``peak_rss_mb``: VmHWM, exact) and the largest total of it and its worker processes
    (``peak_tree_rss_mb``: sampled every 0.1 s)."""
    import threading

    hwm = cwd / f".hwm-{os.getpid()}"
    env = dict(os.environ, ROCKING_BENCH_HWM=str(hwm))
    done = threading.Event()
    t0 = time.perf_counter()
    proc = subprocess.Popen(
        [sys.executable, "-c", _MEASURED_CLI, *args],
        cwd=cwd,
        env=env,
        stdout=subprocess.DEVNULL,
        stderr=subprocess.PIPE,
    )
    with ThreadPoolExecutor(1) as pool:
        tree = pool.submit(_tree_rss_peak, proc.pid, done)
        code = proc.wait()
        wall = time.perf_counter() - t0
        done.set()
        tree_peak = tree.result()
    err = proc.stderr.read().decode(errors="replace")
    proc.stderr.close()
    peak = hwm.read_text() if hwm.exists() else ""
    hwm.unlink(missing_ok=True)
    if code != 0:
        raise RuntimeError(f"rocking {' '.join(args)} failed ({code}): {err[-2000:]}")
    peak_kb = float(peak)
    return {
        "command": "rocking " + " ".join(args),
        "wall_s": wall,
        "peak_rss_mb": peak_kb / 1024,
        "peak_tree_rss_mb": tree_peak,
    }


def bench_table2(tmp: Path, runs: int) -> dict:
    """``runs`` times each command (fresh output each time: agx50 would resume from a folder it
    wrote before); the end-to-end time is the sum of the best of each."""
    # warm-up: every kernel the two commands use, on short motions as many as the timed runs',
    # so that the energy balance's response spectra take the same lane layout (with 3 or 20
    # motions they took the other one, and the first timed agx50 compiled ~3 s more)
    n = str(TABLE2_MOTIONS)
    run_command(["motions", "generate", "--n", n, "--duration", "4", "--out", "w.nc"], tmp)
    run_command(
        [
            "agx50",
            "--bodies",
            "paper",
            "--motions",
            "w.nc",
            "--out",
            "w",
            "--quiet",
            "--agx-max",
            "0.3",
            "--resolution",
            "0.1",
        ],
        tmp,
    )
    gen = [
        run_command(["motions", "generate", "--n", n, "--seed", "8", "--out", f"m200-{r}.nc"], tmp)
        for r in range(runs)
    ]
    agx = [
        run_command(
            [
                "agx50",
                "--bodies",
                "paper",
                "--motions",
                "m200-0.nc",
                "--out",
                f"table2-{r}",
                "--quiet",
            ],
            tmp,
        )
        for r in range(runs)
    ]
    results = (tmp / "table2-0" / "agx50.csv").read_bytes()
    from rocking.motions.ensemble import Ensemble

    motions = Ensemble.load(tmp / "m200-0.nc").acc
    best_gen = min(gen, key=lambda x: x["wall_s"])
    best_agx = min(agx, key=lambda x: x["wall_s"])
    return {
        "generate_200": best_gen,
        "agx50": best_agx,
        "all_generate_s": [x["wall_s"] for x in gen],
        "all_agx50_s": [x["wall_s"] for x in agx],
        "wall_s": best_gen["wall_s"] + best_agx["wall_s"],
        "agx50_csv_sha256": hashlib.sha256(results).hexdigest(),
        "motions_sha256": digest(motions),
    }


def bench_spectra_floors(n: int) -> dict:
    t0 = time.perf_counter()
    ens = generate(n, duration=DURATION, dt=DT, seed=3)
    t_gen = time.perf_counter() - t0
    freqs = np.geomspace(0.1, 50.0, 100)  # [Hz], as `rocking spectrum`
    response_spectrum(ens.acc[:2, :400], DT, freqs)  # compile / load
    frame = ShearFrame.preset("paper-2.0")
    frame.floor_ensembles(ens.subset(range(2)))
    spec = timed(lambda: response_spectrum(ens.acc, DT, freqs, 0.05), 1)
    floors = timed(lambda: frame.floor_ensembles(ens), 1)
    return {
        "motions": n,
        "generate_s": t_gen,
        "spectra": {"frequencies": freqs.size, "damping": 0.05, **spec},
        "floors": {"frame": "paper-2.0 (5 stories)", **floors},
    }


def bench_generate(n: int, repeats: int) -> dict:
    """``generate`` (Eq. 9 and the baseline correction) of ``n`` motions of 30 s at 400 Hz."""
    generate(2, duration=2.0, dt=DT, seed=1)  # compile / load
    t = timed(lambda: generate(n, duration=30.0, dt=DT, seed=2, baseline=True), repeats)
    return {"motions": n, "duration_s": 30.0, "dt_s": DT, **t}


def bench_pulse_spectrum(repeats: int) -> dict:
    """An overturning spectrum of 100 periods with all its switches (issue 46): R = 1 m, γ = 4,
    one-sine pulses of 0.2–5 s, the default scan and refinement."""
    block = Block(1.0, 4.0)
    periods = np.linspace(0.2, 5.0, 100)
    overturning_spectrum(block, "one-sine", periods[:2])  # compile / load
    t = timed(lambda: overturning_spectrum(block, "one-sine", periods), repeats)
    ds = overturning_spectrum(block, "one-sine", periods)
    return {
        "periods": periods.size,
        "switches": int(ds["switch_kappa"].notnull().sum()),
        "kappa_digest": digest(ds["switch_kappa"].values),
        **t,
    }


def count_steps(tmp: Path, fidelity: str, exhaustive: bool) -> dict:
    """Integrated steps and simulations of every Monte Carlo simulation of ``rocking reproduce
    all`` at ``fidelity``, run in this process with the engine's ``run_cases`` counting steps
    (``count_steps=True``: the same results).  ``exhaustive``: every A_gx50 search level
    simulated with every motion, as before the early decision (``agx_50(exhaustive=True)``, here
    for every search of the studies by running each level in full before deciding it)."""
    import rocking.montecarlo.engine as engine_module
    from rocking.studies import STUDIES, reproduce

    real_run_cases = engine_module.run_cases
    real_at_least_half = engine_module.Engine.at_least_half
    total = {"steps": 0, "simulations": 0}

    def counting(*args, **kwargs):
        out = real_run_cases(*args, **kwargs)
        total["steps"] += int(out.steps.sum())
        total["simulations"] += int(out.steps.size)
        return out

    def in_full(self, keys):
        self.run(keys)
        return real_at_least_half(self, keys)

    engine_module.run_cases = counting
    if exhaustive:
        engine_module.Engine.at_least_half = in_full
    try:
        t0 = time.perf_counter()
        reproduce(list(STUDIES), fidelity=fidelity, out_dir=tmp / f"steps-{fidelity}-{exhaustive}")
        total["wall_s"] = time.perf_counter() - t0
    finally:
        engine_module.run_cases = real_run_cases
        engine_module.Engine.at_least_half = real_at_least_half
    return total


def bench_reproduce(tmp: Path, fidelity: str, runs: int) -> dict:
    out = {}
    for r in range(runs):
        res = run_command(
            [
                "reproduce",
                "all",
                "--fidelity",
                fidelity,
                "--out",
                f"reproduce-{fidelity}-{r}",
                "--quiet",
            ],
            tmp,
        )
        out["first" if r == 0 else "again"] = res
    return out


# --------------------------------------------------------------------------- report


def summary_rows(res: dict) -> list[tuple[str, str, str]]:
    rows = []
    k = res["kernel"]
    rows.append(
        (
            "kernel, all threads [ns/RK4 step]",
            f"{k['ns_per_step']:.2f}",
            f"median {k['ns_per_step_median']:.2f}; {k['threads']} threads; "
            f"{k['steps'] / 1e6:.1f} M steps, {k['cases']} cases",
        )
    )
    rows.append(("kernel, one thread [ns/RK4 step]", f"{k['ns_per_step_one_thread']:.2f}", ""))
    rows.append(
        (
            "kernel equals simulate() case by case",
            str(k["equals_simulate"]),
            f"{k['share_of_intervals_integrated']:.0%} of intervals integrated, "
            f"{k['share_overturned']:.0%} overturned",
        )
    )
    p = res["plain_loop"]
    rows.append(
        (
            "plain loop, all threads [ns/step]",
            f"{p['parallel']['ns_per_step']:.1f}",
            f"kernel is {res['ratios']['vs_plain_loop']:.1f}× faster (best times; median of "
            f"{len(res['paired']['all_threads']['ratios'])} interleaved pairs "
            f"{res['ratios']['vs_plain_loop_paired']:.1f}×; target ≥ "
            f"{TARGETS['vs_plain_loop']:g}×)",
        )
    )
    rows.append(
        (
            "plain loop, one thread [ns/step]",
            f"{p['serial']['ns_per_step']:.1f}",
            f"kernel on one thread is {res['ratios']['vs_plain_loop_one_thread']:.1f}× faster "
            f"(median of {len(res['paired']['one_thread']['ratios'])} interleaved pairs "
            f"{res['ratios']['vs_plain_loop_one_thread_paired']:.1f}×)",
        )
    )
    c = res["ceiling"]
    rows.append(
        (
            "arithmetic floor [ns/step]",
            f"{c['floor_ns_per_step']:.2f}",
            f"{c['ops_per_step']} ops per step at {c['peak_gflops']:.0f} GFLOP/s "
            f"({c['cores']} cores at {c['clock_ghz']:.2f} GHz, {c['fmas_per_cycle_per_core']} FMAs "
            f"per cycle); the kernel takes "
            f"{c['kernel_vs_floor']:.1f}× the floor, 10× the plain loop needs "
            f"{p['parallel']['ns_per_step'] / TARGETS['vs_plain_loop']:.2f}",
        )
    )
    s = res["scipy"]
    rows.append(
        (
            "SciPy solve_ivp [s/simulation]",
            f"{s['s_per_simulation']:.2f}",
            f"kernel: {k['s_per_simulation'] * 1e6:.0f} µs/simulation, "
            f"{res['ratios']['vs_scipy']:,.0f}× faster (target ≥ "
            f"{TARGETS['vs_scipy']:,.0f}×)",
        )
    )
    rows += modes_rows(res.get("modes"))
    e = res.get("end_to_end", {})
    if "table2" in e:
        t = e["table2"]
        rows.append(
            (
                "Table 2 end to end [s]",
                f"{t['wall_s']:.1f}",
                f"best of {len(t['all_agx50_s'])}: generate "
                f"{t['generate_200']['wall_s']:.1f} s + agx50 {t['agx50']['wall_s']:.1f} s; "
                f"target ≤ {TARGETS['table2_s']:g} s",
            )
        )
    if "generate_500" in e:
        g = e["generate_500"]
        rows.append(
            (
                f"generate {g['motions']} motions of 30 s at 400 Hz [s]",
                f"{g['best_s']:.2f}",
                f"Eq. (9) and baseline correction; target ≤ {TARGETS['generate_500_s']:g} s",
            )
        )
    if "pulse_spectrum" in e:
        ps = e["pulse_spectrum"]
        rows.append(
            (
                f"overturning spectrum, {ps['periods']} periods [s]",
                f"{ps['best_s']:.2f}",
                f"{ps['switches']} switches; target ≤ {TARGETS['pulse_spectrum_100_s']:g} s",
            )
        )
    if "spectra_floors" in e:
        sf = e["spectra_floors"]
        rows.append(
            (
                f"response spectra, {sf['motions']} motions [s]",
                f"{sf['spectra']['best_s']:.2f}",
                f"{sf['spectra']['frequencies']} frequencies; generating the motions "
                f"{sf['generate_s']:.1f} s",
            )
        )
        rows.append(
            (
                f"floor motions, {sf['motions']} motions [s]",
                f"{sf['floors']['best_s']:.2f}",
                sf["floors"]["frame"],
            )
        )
    for fid in ("quick", "paper"):
        key = f"reproduce_{fid}"
        if key in e:
            r = e[key].get("again", e[key]["first"])
            target = TARGETS[f"reproduce_{fid}_s"]
            note = (
                f"peak {r['peak_rss_mb']:.0f} MB (with its workers "
                f"{r['peak_tree_rss_mb']:.0f} MB); target ≤ {target:g} s"
            )
            if fid == "paper":
                note += f", ≤ {TARGETS['reproduce_paper_peak_gb']:g} GB"
            if "again" in e[key]:
                note += f"; first run {e[key]['first']['wall_s']:.1f} s"
            rows.append((f"reproduce all --fidelity {fid} [s]", f"{r['wall_s']:.1f}", note))
    for fid in ("quick", "paper"):
        if f"steps_{fid}" not in e:
            continue
        now, full = e[f"steps_{fid}"]["now"], e[f"steps_{fid}"]["exhaustive_agx50"]
        rows.append(
            (
                f"Monte Carlo of the {fid} studies [M steps]",
                f"{now['steps'] / 1e6:.1f}",
                f"{now['simulations']:,} simulations in {now['wall_s']:.0f} s; every A_gx50 "
                f"level in full: {full['steps'] / 1e6:.1f} M steps, {full['simulations']:,} "
                f"simulations in {full['wall_s']:.0f} s",
            )
        )
    return rows


def modes_rows(m: dict | None) -> list[tuple[str, str, str]]:
    """The summary rows of the response-modes entry (none if it did not run)."""
    if m is None:
        return []
    r = m["rock_only"]
    rows = [
        (
            "modes kernel, rocking only [ns/RK4 step]",
            f"{r['ns_per_step']:.2f}",
            f"mu = {r['mu']:g}: {r['vs_rocking_kernel']:.1f}× the rocking kernel's "
            f"{m['rocking_kernel']['ns_per_step']:.2f} (target ≤ {TARGETS['modes_vs_rocking']:g}×)",
        )
    ]
    for mu, x in m["slide"].items():
        rows.append(
            (
                f"modes kernel, mu = {mu} [ns/interval]",
                f"{x['ns_per_interval']:.1f}",
                f"{x['vs_plain_loop']:.1f}× the plain loop's {x['plain_loop_ns_per_interval']:.1f} "
                f"(target ≥ {TARGETS['modes_vs_plain_loop']:g}×); {x['share_sliding']:.0%} slide",
            )
        )
    return rows


def parse_args(argv):
    ap = argparse.ArgumentParser(
        description=__doc__.split("\n\n")[0], formatter_class=argparse.RawDescriptionHelpFormatter
    )
    ap.add_argument(
        "--quick", action="store_true", help="fewer motions and repeats; reproduce quick run once"
    )
    ap.add_argument(
        "--with-paper",
        action="store_true",
        help="also time `rocking reproduce all --fidelity paper` and its peak memory",
    )
    ap.add_argument(
        "--no-end-to-end", action="store_true", help="kernel, plain loop and SciPy only"
    )
    ap.add_argument(
        "--no-steps",
        action="store_true",
        help="skip counting the integrated steps of the studies (two in-process runs per "
        "fidelity: quick, and paper with --with-paper)",
    )
    ap.add_argument(
        "--modes-only",
        action="store_true",
        help="only the response-modes entry (issue 45), here, on this machine's instruction "
        "set; prints its JSON (and writes it to --out if given)",
    )
    ap.add_argument(
        "--isa",
        default=",".join(ISAS),
        help=f"instruction sets to run on, comma-separated among {', '.join(ISAS)} "
        "(default: all, one after the other)",
    )
    ap.add_argument(
        "--out",
        default=str(ROOT / "benchmarks" / "results.json"),
        help="JSON file to write (default: benchmarks/results.json)",
    )
    return ap.parse_args(argv)


def vector_registers() -> list[str]:
    """The SIMD registers (xmm, ymm, zmm) of a small vectorisable loop as Numba compiles it here:
    zmm means AVX-512 code, ymm at most AVX2."""

    @numba.njit
    def axpy(a, b):
        for i in range(a.size):
            a[i] = a[i] * b[i] + 1.0

    x = np.ones(64)
    axpy(x, x)
    asm = "".join(axpy.inspect_asm().values())
    return [r for r in ("xmm", "ymm", "zmm") if r in asm]


def run_isa(a) -> dict:
    """The whole suite in this process (compiled for the instruction set of its environment)."""
    n_motions = 20 if a.quick else 100
    repeats = 3 if a.quick else 9  # best of many: the machine may be shared
    res = {
        "numba_cpu": {
            "NUMBA_CPU_NAME": numba.config.CPU_NAME or "host",
            "NUMBA_CPU_FEATURES": numba.config.CPU_FEATURES or "host",
            "vector_registers": vector_registers(),
        },
        "load_at_start": load(),
        "settings": {
            "quick": a.quick,
            "motions": n_motions,
            "repeats": repeats,
            "dt_s": DT,
            "duration_s": DURATION,
        },
    }
    print("kernel workload and independent step count ...", flush=True)
    w = rocking_workload(n_motions)
    counted = count_with_simulate(w)
    res["kernel"] = bench_kernel(w, counted, repeats)
    res["kernel"]["agx_per_body_g"] = w["agx"].tolist()
    print("plain compiled loop ...", flush=True)
    res["plain_loop"] = bench_plain(w, repeats)
    print("kernel and plain loop in interleaved pairs ...", flush=True)
    res["paired"] = bench_paired(w, res["kernel"]["steps"], res["plain_loop"], repeats)
    print("SciPy solve_ivp ...", flush=True)
    res["scipy"] = bench_scipy(w, counted, 2 if a.quick else 3)
    k = res["kernel"]
    res["ratios"] = {
        "vs_plain_loop": res["plain_loop"]["parallel"]["ns_per_step"] / k["ns_per_step"],
        "vs_plain_loop_one_thread": res["plain_loop"]["serial"]["ns_per_step"]
        / k["ns_per_step_one_thread"],
        "vs_plain_loop_paired": res["paired"]["all_threads"]["median_ratio_per_step"],
        "vs_plain_loop_one_thread_paired": res["paired"]["one_thread"]["median_ratio_per_step"],
        "vs_scipy": res["scipy"]["s_per_simulation"] / k["s_per_simulation"],
    }
    res["ceiling"] = peak.ceiling(numba.get_num_threads())
    res["ceiling"]["kernel_vs_floor"] = k["ns_per_step"] / res["ceiling"]["floor_ns_per_step"]
    print("response-modes kernel (friction) ...", flush=True)
    res["modes"] = bench_modes(w, repeats)
    res["load_after_kernel"] = load()

    if not a.no_end_to_end:
        e = res["end_to_end"] = {}
        with tempfile.TemporaryDirectory(prefix="rocking-bench-") as tmp:
            tmp = Path(tmp)
            print("Table 2 (rocking agx50, 72 bodies x 200 motions) ...", flush=True)
            e["table2"] = bench_table2(tmp, 2 if a.quick else 3)
            print("generating 500 motions of 30 s ...", flush=True)
            e["generate_500"] = bench_generate(500, repeats)
            print("overturning spectrum of 100 pulse periods ...", flush=True)
            e["pulse_spectrum"] = bench_pulse_spectrum(repeats)
            print("response spectra and floor motions of 500 motions ...", flush=True)
            e["spectra_floors"] = bench_spectra_floors(500)
            print("rocking reproduce all --fidelity quick ...", flush=True)
            e["reproduce_quick"] = bench_reproduce(tmp, "quick", 1 if a.quick else 2)
            if not a.no_steps:
                print("steps of the quick studies, now and exhaustive ...", flush=True)
                e["steps_quick"] = {
                    "now": count_steps(tmp, "quick", exhaustive=False),
                    "exhaustive_agx50": count_steps(tmp, "quick", exhaustive=True),
                }
            if a.with_paper:
                print("rocking reproduce all --fidelity paper ...", flush=True)
                e["reproduce_paper"] = bench_reproduce(tmp, "paper", 1)
                if not a.no_steps:
                    print("steps of the paper's studies, now and exhaustive ...", flush=True)
                    e["steps_paper"] = {
                        "now": count_steps(tmp, "paper", exhaustive=False),
                        "exhaustive_agx50": count_steps(tmp, "paper", exhaustive=True),
                    }
        res["load_at_end"] = load()
    return res


def child_env(isa: str, machine: dict) -> dict:
    """Environment of the child process that runs the suite on ``isa`` on ``machine``
    (:func:`machine_info`)."""
    from rocking.core.compile import cache_dir

    settings = ISAS[isa]
    if isa == "native" and "avx512f" in machine["simd"]:
        settings = FULL_WIDTH
    env = {**os.environ, "ROCKING_BENCH_ISA": isa}
    env.pop("NUMBA_CPU_NAME", None)
    env.pop("NUMBA_CPU_FEATURES", None)
    env.update(settings)
    if settings:
        env["ROCKING_CACHE_DIR"] = str(cache_dir().parent / f"numba-{isa}")
    return env


def run_key(run: dict, machine: dict) -> str:
    """The key of a run in ``runs``: the instruction set its compiled code used, ``avx512`` (zmm
    registers) or ``avx2``, and ``avx2-on-avx512`` for AVX2 code on an AVX-512 machine (kept
    beside the AVX2 run of a machine without AVX-512: both are evidence)."""
    if "zmm" in run["numba_cpu"]["vector_registers"]:
        return "avx512"
    return "avx2-on-avx512" if "avx512f" in machine["simd"] else "avx2"


def read_previous(path: Path) -> dict:
    """The JSON already in ``path`` ({} if there is none)."""
    try:
        return json.loads(path.read_text())
    except (OSError, ValueError):
        return {}


def previous_runs(old: dict) -> dict:
    """The runs already in ``old`` (:func:`read_previous`) by instruction set, each with its
    machine (the format of this script, or the older one with a single ``machine`` and runs
    under ``isas``)."""
    if "runs" in old:
        return old["runs"]
    if "machine" not in old:
        return {}
    m = old["machine"]
    return {run_key(r, m): {"machine": m, **r} for r in old.get("isas", {}).values()}


#: Top-level keys this script writes; the file's other entries (the before/after pairs of
#: ``before_after.py``) are kept as they are.
OWN_KEYS = ("targets", "runs", "bit_identical", "machine", "isas")


def comparable_digests(runs: dict) -> dict:
    """Whether the results are bit-identical across the runs (whatever their machine and
    commit: results must not depend on either): the kernel's flags and peaks among runs of the
    same workload, on the same machine (same motions: only the instruction set differs) and
    across machines, the response-modes entry's outcomes with friction among runs of the same
    workload, Table 2's agx50.csv among all."""
    kernel: dict = {}
    same_cpu: dict = {}
    motions: dict = {}
    for r in runs.values():
        same_workload = json.dumps(r["settings"], sort_keys=True)
        kernel.setdefault(same_workload, set()).add(r["kernel"]["results_sha256"])
        cpu = (same_workload, r["machine"]["cpu_family_model"])
        same_cpu.setdefault(cpu, set()).add(r["kernel"]["results_sha256"])
        if "motions_sha256" in r["kernel"]:
            motions.setdefault(same_workload, set()).add(r["kernel"]["motions_sha256"])
    modes: dict = {}
    for r in runs.values():
        if "results_sha256" in r.get("modes", {}):
            same_workload = json.dumps(r["settings"], sort_keys=True)
            modes.setdefault(same_workload, set()).add(r["modes"]["results_sha256"])
    table2 = {
        r["end_to_end"]["table2"]["agx50_csv_sha256"]
        for r in runs.values()
        if "table2" in r.get("end_to_end", {})
    }
    out = {"runs": {isa: r["machine"]["rocking_commit"] for isa, r in runs.items()}}
    if any(len(v) > 0 for v in kernel.values()) and len(runs) > 1:
        out["kernel"] = all(len(v) == 1 for v in kernel.values())
        out["kernel_same_cpu_across_isas"] = all(len(v) == 1 for v in same_cpu.values())
    if modes and len(runs) > 1:
        out["modes"] = all(len(v) == 1 for v in modes.values())
    if len(table2) and len(runs) > 1:
        out["table2_agx50"] = len(table2) == 1
    if any(len(v) > 1 for v in motions.values()):
        out["kernel_motions"] = False  # the generated motions differ: see the README
    return out


def main(argv=None) -> int:
    a = parse_args(argv)
    isas = [x.strip() for x in a.isa.split(",") if x.strip()]
    unknown = [x for x in isas if x not in ISAS]
    if unknown or not isas:
        raise SystemExit(f"--isa: unknown instruction set(s) {unknown}; choose among {list(ISAS)}")
    out = Path(a.out)
    if a.modes_only:
        w = rocking_workload(10 if a.quick else 30)
        res = {"machine": machine_info(), "load_at_start": load()}
        res["modes"] = bench_modes(w, 3 if a.quick else 5)
        res["load_at_end"] = load()
        text = json.dumps(res, indent=2, default=float)
        print(text)
        if "--out" in (argv or sys.argv):
            out.write_text(text + "\n")
        return 0
    if os.environ.get("ROCKING_BENCH_ISA") in isas and len(isas) == 1:
        # a child: run here, write JSON for the parent
        out.write_text(json.dumps(run_isa(a), indent=2, default=float) + "\n")
        return 0
    machine = machine_info()
    if "avx512f" not in machine["simd"] and "native" in isas and "avx2" in isas:
        isas.remove("avx2")  # the native run is the AVX2 run on this machine
    print(
        f"rocking benchmarks on {machine['cpu_model']} "
        f"({machine['logical_cpus']} CPUs, {', '.join(machine['simd'])})",
        flush=True,
    )
    flags = [
        f
        for f in ("--quick", "--with-paper", "--no-end-to-end", "--no-steps")
        if getattr(a, f[2:].replace("-", "_"))
    ]
    old = read_previous(out)
    runs = previous_runs(old)
    with tempfile.TemporaryDirectory(prefix="rocking-bench-isa-") as tmp:
        for isa in isas:
            env = child_env(isa, machine)
            numba_cpu = {k: v for k, v in env.items() if k.startswith("NUMBA_CPU_")}
            print(f"\n== {isa} {numba_cpu or '(the CPU this machine has)'}", flush=True)
            part = Path(tmp) / f"{isa}.json"
            cmd = [sys.executable, __file__, *flags, "--isa", isa, "--out", str(part)]
            subprocess.run(cmd, env=env, check=True)
            run = json.loads(part.read_text())
            runs[run_key(run, machine)] = {"machine": machine, "requested_isa": isa, **run}
            print_rows(summary_rows(run))
    res = {"targets": TARGETS, "runs": runs, "bit_identical": comparable_digests(runs)}
    res.update({k: v for k, v in old.items() if k not in OWN_KEYS})
    print(f"\nbit-identical across the runs kept in {out.name}: {res['bit_identical']}")
    out.parent.mkdir(parents=True, exist_ok=True)
    out.write_text(json.dumps(res, indent=2, default=float) + "\n")
    print(f"\nwritten {out}")
    return 0


def print_rows(rows: list[tuple[str, str, str]]) -> None:
    w1 = max(len(r[0]) for r in rows)
    w2 = max(len(r[1]) for r in rows)
    print()
    for name, value, note in rows:
        print(f"{name:<{w1}}  {value:>{w2}}  {note}")


if __name__ == "__main__":
    raise SystemExit(main())
