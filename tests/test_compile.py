"""The compiled helpers of rocking.core.compile agree with their plain-Python definitions; a
borrowing kernel counts no references."""

from __future__ import annotations

import math
import sys

import numba
import numpy as np
import pytest

from rocking.core.compile import LINE_BYTES, aligned_zeros, borrowing_kernel, fetch_add, fma, maxnum


@numba.njit
def _maxnum_compiled(a, b):
    return maxnum(a, b)


@numba.njit
def _fma_compiled(a, b, c):
    return fma(a, b, c)


@numba.njit(parallel=True)
def _take_all(n, takers, taken):
    queue = np.zeros(1, np.int64)
    for _ in numba.prange(takers):
        while True:
            i = fetch_add(queue, 1)
            if i >= n:
                break
            taken[i] += 1


def test_fetch_add_hands_every_position_of_a_queue_to_exactly_one_thread():
    # The batched kernel's lane machines (one per thread) take their cases from one queue with
    # fetch_add: every case must be taken once, none twice (a queue copied per thread would
    # take each case once per thread), however the threads interleave.
    n, takers = 200_000, 4 * numba.get_num_threads()
    taken = np.zeros(n, np.int64)
    _take_all(n, takers, taken)
    assert (taken == 1).all()


@numba.njit
def _aligned_many(sizes):
    kept = []  # every array alive at once, so that the allocator cannot hand back one address
    for n in sizes:
        kept.append(aligned_zeros(n))
    starts = np.empty(len(kept), np.int64)
    for i, a in enumerate(kept):
        starts[i] = a.ctypes.data
    return starts, kept


def test_aligned_zeros_start_a_cache_line_and_hold_n_zeros():
    # The lane tables of the batched kernel and of the response spectra are rows of whole cache
    # lines; Numba aligns arrays to 32 bytes only, and a table starting mid-line made every
    # 512-bit load of its SIMD loops touch two lines (23-35 % more time per step, measured).
    # Many sizes, all alive at once: with 32-byte alignment alone about half would start mid-line.
    sizes = [1, 7, 8, 63, 64, 100, 43 * 128, 14 * 16, 5000] * 4
    starts, arrays = _aligned_many(np.array(sizes))
    assert (starts % LINE_BYTES == 0).all()
    for n, a in zip(sizes, arrays):
        assert a.shape == (n,) and a.dtype == np.float64 and not a.any()


def test_maxnum_is_the_larger_number_and_ignores_a_nan():
    # The batched kernel keeps each lane's peak with maxnum (a vector maximum, no masked store);
    # it must be the larger of two numbers, and the number when the other is NaN (IEEE
    # maxNum), in compiled code and in Python alike.
    values = [0.0, 1.5, -2.0, 1e-300, math.inf, 3.0]
    for a in values:
        for b in values:
            assert _maxnum_compiled(a, b) == maxnum(a, b) == max(a, b)
    for x in values:
        assert _maxnum_compiled(math.nan, x) == maxnum(math.nan, x) == x
        assert _maxnum_compiled(x, math.nan) == maxnum(x, math.nan) == x


def test_fma_rounds_once_in_kernels_and_in_python():
    # a·b + c rounded once: (1 + 2⁻³⁰)² − 1 keeps the 2⁻⁶⁰ term that a multiply then add loses
    # (exact arithmetic: 2⁻²⁹ + 2⁻⁶⁰); compiled and Python results must be the same bits.
    x = 1.0 + 2.0**-30
    exact = 2.0**-29 + 2.0**-60
    assert fma(x, x, -1.0) == exact == _fma_compiled(x, x, -1.0)
    assert x * x - 1.0 != exact
    rng = np.random.default_rng(5)
    for a, b, c in rng.normal(size=(200, 3)) * 1e3:
        assert _fma_compiled(a, b, c) == fma(a, b, c)


@borrowing_kernel
def _weighted_sum(x, w):
    total = 0.0
    for i in range(x.size):
        total += x[i] * w[i]
    return total


@numba.njit
def _many_weighted_sums(x, w, n):
    total = 0.0
    for _ in range(n):
        total += _weighted_sum(x, w)
    return total


def test_borrowing_kernel_counts_no_references_and_computes_as_numpy():
    # Invariants: the arrays' reference counts are the same before and after 1000 calls (from
    # Python and from a compiled caller; sys.getrefcount), and the result is NumPy's dot
    # product of small integers (exact in float64, so equality).
    x = np.arange(10.0)
    w = np.arange(10.0)[::-1].copy()
    before = sys.getrefcount(x), sys.getrefcount(w)
    for _ in range(1000):
        assert _weighted_sum(x, w) == float(np.dot(x, w))
    assert _many_weighted_sums(x, w, 1000) == 1000 * float(np.dot(x, w))
    assert (sys.getrefcount(x), sys.getrefcount(w)) == before


def test_borrowing_kernel_refuses_to_allocate():
    # Without reference counting an allocated array could not be freed: Numba refuses to
    # compile it (rather than leak), which is what the lane machine relies on.
    @borrowing_kernel(cache=False)
    def allocates(n):
        return np.zeros(n).sum()

    with pytest.raises(numba.core.errors.TypingError, match="zeros"):
        allocates(3)


CACHE_SCRIPT = """
import numpy as np
from rocking.core import portable
portable.matmul(np.eye(2), np.ones((2, 2)))
kernel = portable._matmul_kernel
print(kernel._cache._cache_path)
print(sum(kernel.stats.cache_hits.values()))
"""


@pytest.mark.parametrize("variable", ["ROCKING_CACHE_DIR", "NUMBA_CACHE_DIR"])
def test_a_cache_folder_that_cannot_be_written_falls_back_with_one_warning(tmp_path, variable):
    # The defect (issue 49): with ROCKING_CACHE_DIR or NUMBA_CACHE_DIR on a folder where nothing
    # can be written, the kernels were compiled again in every run (27 s instead of 2 s), with no
    # word. Here the folder lies under a regular file (not writable even by root); the kernels
    # go to the user's cache folder (XDG_CACHE_HOME on Linux), with one warning, and the second
    # process loads them from there.
    import os
    import subprocess

    blocker = tmp_path / "a-file"
    blocker.write_text("not a folder")
    env = {k: v for k, v in os.environ.items() if k not in ("ROCKING_CACHE_DIR", "NUMBA_CACHE_DIR")}
    env.update({variable: str(blocker / "cache"), "XDG_CACHE_HOME": str(tmp_path / "xdg")})
    fallback = tmp_path / "xdg" / "rocking" / "numba"
    hits = []
    for _ in range(2):
        proc = subprocess.run(
            [sys.executable, "-c", CACHE_SCRIPT], env=env, capture_output=True, text=True
        )
        assert proc.returncode == 0, proc.stderr
        path, hit = proc.stdout.split()
        assert path.startswith(str(fallback)), path
        assert proc.stderr.count("cannot hold the compiled kernels") == 1, proc.stderr
        assert f"{variable} {blocker / 'cache'}" in proc.stderr
        hits.append(int(hit))
    assert hits == [0, 1]  # compiled once, then loaded


def test_kernels_of_changed_sources_are_not_loaded_from_the_cache(tmp_path):
    # Numba checks only the time stamp of a kernel's own file, not of the files whose kernels it
    # inlines: the batched friction kernel (batch_modes.py) cached before modes.py changed was
    # loaded stale and gave other results than simulate (seen after a merge, 24-32 of 120 cases).
    # The cache subfolder is named by the digest of every module that compiles code, so a change
    # to any of them (here modes.py, called by batch_modes.py) gives a new folder, while a change
    # to a module without kernels (a command) keeps the compiled code
    import shutil
    from pathlib import Path

    import rocking
    from rocking.core.compile import sources_stamp

    copy = tmp_path / "rocking"
    shutil.copytree(Path(rocking.__file__).parent, copy, ignore=shutil.ignore_patterns("*.pyc"))
    before = sources_stamp(copy)
    assert before == sources_stamp()  # the same sources, wherever they lie
    with open(copy / "cli" / "screen.py", "a") as f:
        f.write("\n# a command changed\n")
    assert sources_stamp(copy) == before
    with open(copy / "dynamics" / "modes.py", "a") as f:
        f.write("\n# a kernel's callee changed\n")
    assert sources_stamp(copy) != before
    # the kernels of this process were compiled into the subfolder of the current sources
    from rocking.dynamics.modes import modes_case

    assert Path(modes_case._cache._cache_path).parent.name == sources_stamp()
