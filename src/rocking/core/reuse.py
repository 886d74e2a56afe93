"""Results computed once per run from the same inputs (issue 18).

``rocking reproduce all`` computed the same results several times: the studies of Section 8
and the soundness checks take the mean PSV of the same ground motions, the soundness check's
located and step-end searches that of the same refined motions (at paper fidelity 3.3 s of its
26 s of spectra), and the soundness check searched Section 8's ground motions for the same
bodies' A_gx50 again (517 M steps).  Inside :func:`reusing`, :func:`reused` returns the value
computed earlier from inputs with the same bytes instead of computing it again (and
:func:`key_of`, :func:`recall`, :func:`remember` do it in steps, for a caller that computes
several values at once: :func:`rocking.montecarlo.probability.agx_50`'s cases); outside, it
just computes.  The key is a SHA-256 digest of the inputs' contents (about 1 GB/s), never an
object's identity, so that an array changed in place or a new array with the old one's address
can never return another input's result.  Only small results belong here (the memory is kept to
the end of the block); callers get a copy, which they may change.  :func:`shared` gives instead a
dict that callers fill piece by piece: the Monte Carlo engines keep there the outcome of every
simulation of the run, so that none is simulated twice (the soundness checks asked again for 2.7 %
of the paper run's steps and 5.8 % of the quick run's: member outcomes at levels that searches had
visited, bootstrap grids, searches of the same motions at other resolutions).

Python's ``functools.lru_cache`` keys by hashable arguments and keeps results past the run; NumPy
arrays are not hashable, hence this small module.
"""

from __future__ import annotations

import copy
import hashlib
import math
from collections.abc import Callable, Iterator
from contextlib import contextmanager
from contextvars import ContextVar
from typing import Any, TypeVar

import numpy as np

T = TypeVar("T")

#: The results of the innermost :func:`reusing` block, by (kind, digest of the inputs); None
#: outside any block.
_MEMO: ContextVar[dict[tuple[str, str], Any] | None] = ContextVar("rocking_reuse", default=None)


@contextmanager
def reusing() -> Iterator[None]:
    """Within this block (and blocks nested in it, which share its results), :func:`reused`
    computes a value once per distinct input."""
    token = _MEMO.set({} if _MEMO.get() is None else _MEMO.get())
    try:
        yield
    finally:
        _MEMO.reset(token)


def reused(kind: str, inputs: tuple, compute: Callable[[], T]) -> T:
    """``compute()``, or a copy of its value from an earlier call of the same ``kind`` whose
    ``inputs`` had the same contents, inside a :func:`reusing` block.  ``inputs`` must determine
    the value (arrays, numbers, strings, None, and tuples/lists/dicts of them)."""
    if _MEMO.get() is None:
        return compute()
    key = (kind, digest(inputs))
    found = recall(key)
    if found is None:
        found = compute()
        remember(key, found)
    return found


def key_of(kind: str, inputs: tuple) -> tuple[str, str] | None:
    """The key of a result of ``kind`` from ``inputs`` (see :func:`reused`), or None outside a
    :func:`reusing` block (nothing to recall or remember: the inputs are not even hashed)."""
    return None if _MEMO.get() is None else (kind, digest(inputs))


def recall(key: tuple[str, str] | None) -> Any:
    """A copy of the value remembered under ``key`` (:func:`key_of`), or None."""
    memo = _MEMO.get()
    if memo is None or key is None or key not in memo:
        return None
    return copy.deepcopy(memo[key])


def remember(key: tuple[str, str] | None, value: Any) -> None:
    """Keep a copy of ``value`` under ``key`` (:func:`key_of`) to the end of the
    :func:`reusing` block (nothing outside one)."""
    memo = _MEMO.get()
    if memo is not None and key is not None:
        memo[key] = copy.deepcopy(value)


def shared(kind: str) -> dict | None:
    """A dict that every caller asking for the same ``kind`` shares, and may add to, until the end
    of the innermost :func:`reusing` block; None outside one.  For results that accumulate
    piece by piece (the Monte Carlo engines' simulated outcomes,
    :class:`rocking.montecarlo.engine.Engine`) rather than one value per input; the caller keys
    its entries by contents, as :func:`reused` does, and must not change what it stored."""
    memo = _MEMO.get()
    if memo is None:
        return None
    return memo.setdefault((kind, ""), {})


def digest(value: Any) -> str:
    """SHA-256 of ``value``'s contents: an array's dtype, shape and bytes (C order), a float's
    exact bits, the type and text of other scalars, containers item by item."""
    h = hashlib.sha256()
    _feed(h, value)
    return h.hexdigest()


def array_digest(a: np.ndarray) -> str:
    """SHA-256 of an array's dtype, shape and bytes: how a chunk store's ``params`` name large
    inputs (:class:`rocking.montecarlo.store.ChunkStore`; its format is part of the folders' and
    may not change) and what :attr:`rocking.Ensemble.sha256` is built from."""
    a = np.ascontiguousarray(a)
    h = hashlib.sha256(f"{a.dtype.str}{a.shape}".encode())
    h.update(a.data)
    return h.hexdigest()


def _feed(h, value: Any) -> None:
    if isinstance(value, np.ndarray) and not value.dtype.hasobject:
        a = np.ascontiguousarray(value)
        h.update(f"array {a.dtype.str} {a.shape}:".encode())
        if a.size:  # (a memoryview of no elements cannot be cast to bytes)
            h.update(a.data.cast("B"))
    elif isinstance(value, (float, np.floating)):
        # float.hex is exact; NaN has many bit patterns, but all of them compute the same
        h.update(b"float " + (float(value).hex() if not math.isnan(value) else "nan").encode())
    elif value is None or isinstance(value, (bool, int, str, np.integer, np.bool_)):
        h.update(f"{type(value).__name__} {value!r};".encode())
    elif isinstance(value, (tuple, list)):
        h.update(f"{type(value).__name__} {len(value)}(".encode())
        for item in value:
            _feed(h, item)
        h.update(b")")
    elif isinstance(value, dict):
        h.update(f"dict {len(value)}(".encode())
        for k in sorted(value, key=repr):
            _feed(h, k)
            _feed(h, value[k])
        h.update(b")")
    else:  # a caller's mistake, not the user's: every input must be listed by its contents
        raise TypeError(f"reused() cannot key on a {type(value).__name__}")
