"""All Numba settings in one place.

Every compiled kernel of the package is declared with :func:`kernel` (serial) or
:func:`parallel_kernel`, so that ``cache=True`` (compiled code stored next to the sources and
reused by later processes) and ``fastmath``/``error_model`` choices are uniform.
"""

from __future__ import annotations

import numba

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
