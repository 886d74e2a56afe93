"""The arithmetic ceiling of this machine, for the benchmarks' "physical limit" (issue 18).

Both numbers the ceiling rests on are measured here, in the process and with the instruction set
of the run, not read from a label (a VM shows neither its clock nor its FMA units):

* the clock: a chain of N dependent fused multiply-adds takes N x (FMA latency) cycles, so the
  clock is N * FMA_LATENCY / time.  FMA_LATENCY is 4 cycles on every CPU the runs have used
  (AMD Zen 3 and Zen 4: AMD's "Software Optimization Guide" for EPYC 7003 (2020) and for Zen 4
  (2023); Intel Golden Cove / Raptor Cove server cores (Sapphire and Emerald Rapids): Intel's
  "64 and IA-32 Architectures Optimization Reference Manual", 2023);
* the double-precision FMAs a core starts per cycle: 256 independent FMA chains, each taken
  through 8 dependent FMAs per visit (far more than two pipes of latency 4 need, with 256-bit or
  512-bit vectors), compiled as Numba compiles the kernels in this process, timed, and rounded to
  the nearest power of two (the issue widths CPUs have; a shared VM's timing is off by 10-20 %).
  This is 8 with AVX2 code on all of these CPUs and with AVX-512 code on Zen 4 (its 512-bit
  instructions issue as two 256-bit halves), and 16 with AVX-512 code on Intel's Xeons with two
  512-bit FMA units (the Emerald Rapids VM of the runs): assuming 8 there put the floor at twice
  its true value.
"""

from __future__ import annotations

import math
import time

import numba
import numpy as np

from rocking.core.compile import fma

#: Cycles from an FMA's inputs to its result (Zen 3, Zen 4, Golden Cove; see above).
FMA_LATENCY = 4
#: Independent FMA chains of the throughput loop: 2 KB, held in the L1 cache.
CHAINS = 256
#: Dependent FMAs per chain and visit: one load and one store per 8 vector FMAs.
DEPTH = 8
#: Arithmetic operations (multiplies, adds and fused multiply-adds, each counted once) of one plain
#: step of the batched kernel without vertical motion: dynamics/equation.py's _plain_step, counted
#: by hand from its source (the sin/cos polynomials 21, the four RK4 stages with their three
#: rotations and the update 63, the no-touch bound 5; compares, selects, absolute values and the
#: loads of the ground motion not counted).  Each is taken to occupy an FMA pipe (Zen 4 can also
#: send adds to two separate pipes, so the true floor is up to ~20 % lower).
OPS_PER_STEP = 90


@numba.njit(cache=True)
def _chain(n, a, b):
    x = 1.0
    for _ in range(n):
        x = fma(x, a, b)
    return x


@numba.njit(cache=True)
def _chains(n, acc, a, b):
    # LLVM vectorises the loop over the chains (the one over DEPTH is unrolled in it): each
    # vector of chains is loaded, taken through DEPTH dependent FMAs and stored, and the
    # out-of-order core overlaps successive vectors, so the FMA pipes, not the latency nor the
    # loads and stores, bound the loop.
    for _ in range(n):
        for j in range(acc.size):
            x = acc[j]
            for _ in range(DEPTH):
                x = fma(x, a, b)
            acc[j] = x


def _best(f, n: int, *args) -> float:
    """Least wall time [s] of five calls of ``f(n, *args)`` (after a short one, ``f(10, *args)``,
    to compile or load it).  Not run.py's ``timed``: run.py imports this module."""
    f(10, *args)
    best = math.inf
    for _ in range(5):
        t0 = time.perf_counter()
        f(n, *args)
        best = min(best, time.perf_counter() - t0)
    return best


def clock_ghz(n: int = 200_000_000) -> float:
    """The core's clock [GHz] from a dependent FMA chain (best of 5 timings)."""
    return n * FMA_LATENCY / _best(_chain, n, 0.999999, 1e-9) / 1e9


def fmas_per_cycle(ghz: float, n: int = 200_000) -> dict:
    """Double-precision FMAs one core starts per cycle at ``ghz`` [GHz]: measured and rounded."""
    acc = 1.0 + 1e-3 * np.arange(CHAINS)
    measured = n * CHAINS * DEPTH / _best(_chains, n, acc, 0.999999, 1e-9) / (ghz * 1e9)
    return {"measured": measured, "issue_width": 2 ** round(math.log2(measured))}


def ceiling(cores: int) -> dict:
    """Peak arithmetic rate of ``cores`` cores and the least time a plain step can take."""
    ghz = clock_ghz()
    width = fmas_per_cycle(ghz)
    ops_per_s = ghz * 1e9 * width["issue_width"] * cores
    return {
        "clock_ghz": ghz,
        "cores": cores,
        "fma_latency_cycles": FMA_LATENCY,
        "fmas_per_cycle_per_core": width["issue_width"],
        "fmas_per_cycle_measured": width["measured"],
        "peak_gflops": 2 * ops_per_s / 1e9,  # an FMA is two floating-point operations
        "ops_per_step": OPS_PER_STEP,
        "floor_ns_per_step": OPS_PER_STEP / ops_per_s * 1e9,
    }


if __name__ == "__main__":
    print(ceiling(numba.config.NUMBA_NUM_THREADS))
