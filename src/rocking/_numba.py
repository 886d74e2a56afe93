"""All Numba settings in one place.

Every compiled kernel of the package is declared with :func:`kernel` (serial) or
:func:`parallel_kernel`, so that ``cache=True`` (compiled code stored next to the sources and
reused by later processes) and ``fastmath``/``error_model`` choices are uniform.

No kernel uses ``fastmath``: without it LLVM neither reassociates nor contracts floating-point
operations, so the same expression gives the same bits in a scalar loop and in a SIMD loop (the
batched kernel relies on this).  Fused multiply–adds are written explicitly with :func:`fma`.
"""

from __future__ import annotations

import math
from fractions import Fraction

import numba
from llvmlite import ir
from numba.core import types
from numba.extending import intrinsic, overload

#: Options shared by every kernel. ``error_model="numpy"`` lets division skip the Python
#: zero-division check (the kernels guard their divisors themselves).
_COMMON = dict(cache=True, nogil=True, error_model="numpy")


def kernel(*args, **kw):
    """``numba.njit`` with the package's settings (serial)."""
    opts = {**_COMMON, **kw}
    if args and callable(args[0]):
        return numba.njit(**opts)(args[0])
    return numba.njit(*args, **opts)


def parallel_kernel(*args, **kw):
    """``numba.njit(parallel=True)`` with the package's settings."""
    opts = {**_COMMON, "parallel": True, **kw}
    if args and callable(args[0]):
        return numba.njit(**opts)(args[0])
    return numba.njit(*args, **opts)


prange = numba.prange


def fma(a, b, c):
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


@intrinsic
def highest_bit(typingctx, x):
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
