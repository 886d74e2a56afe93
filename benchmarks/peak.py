"""The arithmetic ceiling of this machine, for the benchmarks' "physical limit" (issue 18).

The clock is measured, not read from a label (a VM does not show it): a chain of N dependent
fused multiply-adds takes N x (FMA latency) cycles, so the clock is N * FMA_LATENCY / time.  The
peak rate of double-precision arithmetic then follows from the core's documented issue width.
Both constants are for AMD Zen 4 (the CPU of the benchmark runs, "Software Optimization Guide for
the AMD Zen4 Microarchitecture", 2023): FMA latency 4 cycles; two FMA pipes of 256 bits each
(AVX-512 instructions issue as two halves), so 2 x 4 = 8 double-precision FMAs per cycle and core
with AVX2 and with AVX-512 alike.  AMD Zen 3 (the AVX2 machine of the runs; "Software
Optimization Guide for AMD EPYC 7003 Processors", 2020) has the same FMA latency and the same two
256-bit FMA pipes.  On another CPU the constants must be changed with it.
"""

from __future__ import annotations

import time

import numba

from rocking.core.compile import fma

#: Cycles from an FMA's inputs to its result (Zen 4).
FMA_LATENCY = 4
#: Double-precision FMAs a core can start per cycle (Zen 4: two 256-bit pipes).
FMAS_PER_CYCLE = 8
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


def clock_ghz(n: int = 200_000_000) -> float:
    """The core's clock [GHz] from a dependent FMA chain (best of 5 timings)."""
    _chain(10, 0.5, 0.25)
    best = min(_timed(n) for _ in range(5))
    return n * FMA_LATENCY / best / 1e9


def _timed(n: int) -> float:
    t0 = time.perf_counter()
    _chain(n, 0.999999, 1e-9)
    return time.perf_counter() - t0


def ceiling(cores: int) -> dict:
    """Peak arithmetic rate of ``cores`` cores and the least time a plain step can take."""
    ghz = clock_ghz()
    ops_per_s = ghz * 1e9 * FMAS_PER_CYCLE * cores
    return {
        "clock_ghz": ghz,
        "cores": cores,
        "fma_latency_cycles": FMA_LATENCY,
        "fmas_per_cycle_per_core": FMAS_PER_CYCLE,
        "peak_gflops": 2 * ops_per_s / 1e9,  # an FMA is two floating-point operations
        "ops_per_step": OPS_PER_STEP,
        "floor_ns_per_step": OPS_PER_STEP / ops_per_s * 1e9,
    }


if __name__ == "__main__":
    print(ceiling(numba.config.NUMBA_NUM_THREADS))
