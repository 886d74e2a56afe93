"""All Numba settings in one place.

Every compiled kernel of the package is declared with :func:`kernel` (serial),
:func:`borrowing_kernel` (serial, without reference counting) or :func:`parallel_kernel`, so that
``cache=True`` (compiled code stored on disk and reused by later processes) and
``fastmath``/``error_model`` choices are uniform.

The compiled code goes to the user's cache folder (:func:`cache_dir`), not next to the sources:
an installation may be read-only (a system or container install), and one cache per user serves
every virtual environment and checkout (Numba keys each entry by the source file's path and time
stamp, so different sources never share one).  ``NUMBA_CACHE_DIR``, when the user sets it, wins.
Numba checks only the time stamp of the file that holds a kernel, not of the files whose kernels it
calls and inlines (the batched kernel compiles in functions of ``modes.py``, ``impacts.py`` and
``equation.py``): a kernel cached before such a file changed would be loaded stale and give other
results than the sources.  So the kernels of one version of the compiled sources go to a
subfolder of their own, named by :func:`sources_stamp` (a digest of every module that compiles
code); changing any of them compiles everything again, into a new subfolder.
A folder where no file can be written (read-only, or under a file) would have the kernels compiled
again in every process (20-40 s): the kernels then go to the first writable one of the user's
cache folder and a folder in the temporary folder, with one warning (:func:`writable_cache`).

No kernel uses ``fastmath``: without it LLVM neither reassociates nor contracts floating-point
operations, so the same expression gives the same bits in a scalar loop and in a SIMD loop (the
batched kernel relies on this).  Fused multiply–adds are written explicitly with :func:`fma`.
"""

from __future__ import annotations

import contextlib
import functools
import hashlib
import math
import os
import re
import warnings
from collections.abc import Iterator
from fractions import Fraction
from pathlib import Path
from typing import Any

import numba
import numpy as np
from llvmlite import ir
from numba.core import types
from numba.extending import intrinsic, overload

#: Options shared by every kernel. ``error_model="numpy"`` lets division skip the Python
#: zero-division check (the kernels guard their divisors themselves).
_COMMON = dict(cache=True, nogil=True, error_model="numpy")


def cache_dir() -> Path:
    """Folder of the compiled kernels: ``$ROCKING_CACHE_DIR`` if set, else ``numba`` in the
    user's cache folder of the platform (e.g. ``~/.cache/rocking/numba`` on Linux)."""
    root = os.environ.get("ROCKING_CACHE_DIR")
    if not root:
        import platformdirs

        root = platformdirs.user_cache_dir("rocking")
    return Path(root) / "numba"


def _can_write(folder: Path) -> str | None:
    """None if files can be created in ``folder`` (created if missing), else the reason."""
    import tempfile

    try:
        folder.mkdir(parents=True, exist_ok=True)
        tempfile.TemporaryFile(dir=folder).close()
    except OSError as exc:
        return exc.strerror or str(exc)
    return None


@functools.cache
def writable_cache(folder: str, name: str) -> str:
    """``folder`` (the cache folder that ``name`` chose) if files can be written there, else the
    first writable one of the user's cache folder and ``rocking-<user id>/numba`` in the
    temporary folder, with a warning (once per folder and process); ``folder`` itself if none is
    (the kernels are then compiled in every process)."""
    import tempfile

    reason = _can_write(Path(folder))
    if reason is None:
        return folder
    import platformdirs

    uid = os.getuid() if hasattr(os, "getuid") else "user"
    for other in (
        Path(platformdirs.user_cache_dir("rocking")) / "numba",
        Path(tempfile.gettempdir()) / f"rocking-{uid}" / "numba",
    ):
        if str(other) != folder and _can_write(other) is None:
            warnings.warn(
                f"{name} {folder} cannot hold the compiled kernels ({reason}); they are kept "
                f"in {other} instead (else they would be compiled again in every run)",
                stacklevel=2,
            )
            return str(other)
    warnings.warn(
        f"{name} {folder} cannot hold the compiled kernels ({reason}), nor can any other "
        "cache folder: they are compiled again in every run (20-40 s)",
        stacklevel=2,
    )
    return folder


#: A module that compiles code: it declares kernels with this module's decorators.
_COMPILES = re.compile(rb"^@(?:kernel|borrowing_kernel|parallel_kernel)\b", re.MULTILINE)


def sources_stamp(root: Path | None = None) -> str:
    """16 hex digits of the SHA-256 of the package's compiled sources under ``root`` (default:
    the installed package): this module and every module that declares a kernel (:data:`_COMPILES`),
    by their paths and contents.  The name of the cache subfolder of their kernels (see the
    module's notes); about 3 ms for the whole package."""
    return _installed_stamp() if root is None else _stamp(Path(root))


@functools.cache
def _installed_stamp() -> str:
    return _stamp(Path(__file__).resolve().parent.parent)


def _stamp(root: Path) -> str:
    digest = hashlib.sha256()
    for path in sorted(root.rglob("*.py")):
        text = path.read_bytes()
        relative = path.relative_to(root).as_posix()
        if relative == "core/compile.py" or _COMPILES.search(text):
            digest.update(relative.encode() + b"\0" + text + b"\0")
    return digest.hexdigest()[:16]


def _compile(options: dict, func):
    """``numba.njit(**options)(func)`` with the cache in :func:`cache_dir`, or the user's
    ``NUMBA_CACHE_DIR``, where writable (:func:`writable_cache`).

    Numba picks the cache folder of a function when it is decorated (from ``config.CACHE_DIR``),
    so the setting is applied for that moment only and other Numba users are not affected.
    """
    user = numba.config.CACHE_DIR  # the user's NUMBA_CACHE_DIR
    if user:
        folder = writable_cache(user, "NUMBA_CACHE_DIR")
    else:
        name = "ROCKING_CACHE_DIR" if os.environ.get("ROCKING_CACHE_DIR") else "the cache folder"
        folder = writable_cache(str(cache_dir()), name)
    numba.config.CACHE_DIR = os.path.join(folder, sources_stamp())
    try:
        return numba.njit(**options)(func)
    finally:
        numba.config.CACHE_DIR = user


def _decorator(options: dict, args):
    if args and callable(args[0]):
        return _compile(options, args[0])
    if args:  # explicit signatures would compile at import: not used by the package
        raise TypeError("kernel() takes options only")
    return lambda func: _compile(options, func)


def kernel(*args: Any, **kw: Any) -> Any:
    """``numba.njit`` with the package's settings (serial)."""
    return _decorator({**_COMMON, **kw}, args)


def borrowing_kernel(*args: Any, **kw: Any) -> Any:
    """:func:`kernel` compiled without reference counting (Numba's ``_nrt=False``): the arrays it
    takes are borrowed from its caller, which keeps them alive, and it may not allocate any.

    For the lane machine of the batched kernel, which reads a dozen arrays in every round:
    Numba increments and decrements their reference counts around calls and inlined helpers,
    atomically, on counters that all threads share (the motions), which cost ~9 % of its time on
    two threads.  The option has an underscore in Numba (not in its documented API) but is the
    one its own tests use; a Numba without it fails at compilation, not silently.
    """
    return _decorator({**_COMMON, "_nrt": False, **kw}, args)


def parallel_kernel(*args: Any, **kw: Any) -> Any:
    """``numba.njit(parallel=True)`` with the package's settings."""
    return _decorator({**_COMMON, "parallel": True, **kw}, args)


prange = numba.prange


@contextlib.contextmanager
def numba_threads(n: int | None) -> Iterator[None]:
    """Run the ``with`` block on at most ``n`` Numba threads (None: as configured), then give
    back the count it had (results do not depend on it)."""
    if n is None:
        yield
        return
    before = numba.get_num_threads()
    numba.set_num_threads(min(n, numba.config.NUMBA_NUM_THREADS))
    try:
        yield
    finally:
        numba.set_num_threads(before)


def readonly(a: np.ndarray) -> np.ndarray:
    """A read-only view of ``a``, for kernels compiled for read-only arrays only: Numba compiles
    a specialization per writeable flag of each array (~40 s each for the batched kernel), and
    memory-mapped ensembles are read-only where arrays built in memory are not."""
    view = a.view()
    view.flags.writeable = False
    return view


def fma(a: float, b: float, c: float) -> float:
    """a·b + c rounded once, for float64 numbers.

    In kernels: ``llvm.fma`` (the FMA instruction, or a correctly rounded software fma where the
    CPU has none).  In plain Python (e.g. a kernel's ``py_func`` when debugging): exact rational
    arithmetic, correctly rounded, so that both give the same bits.
    """
    if math.isfinite(a) and math.isfinite(b) and math.isfinite(c):
        return float(Fraction(a) * Fraction(b) + Fraction(c))
    return a * b + c


@intrinsic
def _llvm_fma(typingctx, a, b, c):
    sig = types.float64(types.float64, types.float64, types.float64)

    def codegen(context, builder, signature, args):
        return builder.fma(*args)

    return sig, codegen


def maxnum(a: float, b: float) -> float:
    """The larger of two float64 numbers (the other one if one is NaN).

    In kernels: ``llvm.maxnum``, which SIMD loops compile to a vector maximum.  A select such
    as ``x if x > y else y`` stored back where ``y`` was loaded from compiles to a *masked*
    store instead, which AMD processors before Zen 4 execute slowly (microcode).
    """
    if math.isnan(a):
        return b
    if math.isnan(b):
        return a
    return a if a >= b else b


@intrinsic
def _llvm_maxnum(typingctx, a, b):
    sig = types.float64(types.float64, types.float64)

    def codegen(context, builder, signature, args):
        double = ir.DoubleType()
        fn = builder.module.declare_intrinsic(
            "llvm.maxnum", [double], ir.FunctionType(double, [double, double])
        )
        return builder.call(fn, args)

    return sig, codegen


@overload(maxnum)
def _maxnum_in_kernels(a, b):
    if all(isinstance(x, types.Float) for x in (a, b)):
        return lambda a, b: _llvm_maxnum(a, b)
    return None


@intrinsic
def highest_bit(typingctx: Any, x: Any) -> tuple[Any, Any]:
    """Index of the highest set bit of a nonzero uint64 (63 − count of leading zeros; the LZCNT
    instruction).  Numba has this only in an internal module, hence the few lines here."""
    sig = types.int64(types.uint64)

    def codegen(context, builder, signature, args):
        lz = builder.ctlz(args[0], ir.Constant(ir.IntType(1), 1))
        return builder.sub(ir.Constant(ir.IntType(64), 63), lz)

    return sig, codegen


@overload(fma)
def _fma_in_kernels(a, b, c):
    if all(isinstance(x, types.Float) for x in (a, b, c)):
        return lambda a, b, c: _llvm_fma(a, b, c)
    return None


@intrinsic
def fetch_add(typingctx: Any, counter: Any, amount: Any) -> tuple[Any, Any] | None:
    """In kernels: add ``amount`` to ``counter[0]`` (a 1-D int64 array) atomically and return
    the value before (LLVM's ``atomicrmw add``, sequentially consistent), so that the threads of
    a parallel loop can take work from one queue.  Numba's CPU target has no atomic operations
    (only its CUDA target does), hence the few lines here."""
    if not (
        isinstance(counter, types.Array)
        and counter.dtype == types.int64
        and counter.ndim == 1
        and isinstance(amount, types.Integer)
    ):
        return None
    sig = types.int64(counter, types.int64)

    def codegen(context, builder, signature, args):
        array = context.make_array(signature.args[0])(context, builder, args[0])
        return builder.atomic_rmw("add", array.data, args[1], "seq_cst")

    return sig, codegen


#: Bytes to which :func:`aligned_zeros` aligns its arrays: a cache line, and one 512-bit vector.
LINE_BYTES = 64


@kernel(inline="always")
def aligned_zeros(n):
    """In kernels: ``np.zeros(n)`` (float64; n elements) whose first element starts a 64-byte
    cache line.

    Numba aligns its arrays to 32 bytes only, so a lane table's rows (multiples of 64 bytes)
    started mid-line in about half the allocations, and then every 512-bit load and store of a
    SIMD loop touched two cache lines: the batched kernel's table 32 bytes off a line took
    1.23-1.35x the time per step with 512-bit code (Emerald Rapids, interleaved runs), so the
    same code ran faster or slower from one process to the next.  (AVX2's 32-byte vectors never
    straddle a line at 32-byte alignment.)  A view into an array 8 elements longer, from its
    first line boundary.
    """
    buf = np.zeros(n + LINE_BYTES // 8)
    skip = (LINE_BYTES - buf.ctypes.data % LINE_BYTES) % LINE_BYTES // 8
    return buf[skip : skip + n]
