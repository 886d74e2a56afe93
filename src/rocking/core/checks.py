"""Small input checks shared by the public functions (errors name the parameter)."""

from __future__ import annotations

import math
import os
import tomllib
from pathlib import Path
from typing import Any

import numpy as np
from numpy.typing import ArrayLike

from ..errors import InputError
from .files import read_text


def positive(name: str, value: float | str, unit: str = "") -> float:
    """Return ``value`` as a float, or raise if it is not a finite number > 0."""
    try:
        x = float(value)
    except (TypeError, ValueError):
        raise InputError(f"{name} must be a number > 0{_u(unit)}, got {value!r}") from None
    if not math.isfinite(x) or x <= 0.0:
        raise InputError(f"{name} must be a finite number > 0{_u(unit)}, got {value!r}")
    return x


def in_range(
    name: str,
    value: float | str,
    lo: float,
    hi: float,
    *,
    lo_open: bool = False,
    hi_open: bool = False,
    unit: str = "",
) -> float:
    """Return ``value`` as a float, or raise if it lies outside [lo, hi] (open ends as given)."""
    try:
        x = float(value)
    except (TypeError, ValueError):
        raise InputError(f"{name} must be a number, got {value!r}") from None
    ok = math.isfinite(x)
    ok = ok and (x > lo if lo_open else x >= lo) and (x < hi if hi_open else x <= hi)
    if not ok:
        rng = f"{'(' if lo_open else '['}{lo:g}, {hi:g}{')' if hi_open else ']'}"
        raise InputError(f"{name} must lie in {rng}{_u(unit)}, got {value!r}")
    return x


def finite_array(
    name: str, values: ArrayLike, *, ndim: tuple[int, ...] = (1,), min_len: int = 1
) -> np.ndarray:
    """Return ``values`` as a C-contiguous float64 array, or raise on NaN/inf/empty/wrong shape."""
    try:
        a = np.ascontiguousarray(values, dtype=np.float64)
    except (TypeError, ValueError):
        raise InputError(f"{name} must be an array of numbers") from None
    if a.ndim not in ndim:
        raise InputError(
            f"{name} must have {' or '.join(map(str, ndim))} dimension(s), got shape {a.shape}"
        )
    if a.shape[-1] < min_len:
        raise InputError(f"{name} must have at least {min_len} sample(s), got {a.shape[-1]}")
    bad = ~np.isfinite(a)
    if bad.any():
        idx = np.argwhere(bad)[0]
        where = ", ".join(str(int(i)) for i in idx)
        raise InputError(f"{name} contains a non-finite value ({a[tuple(idx)]}) at index {where}")
    return a


HOUSNER = "housner"


def restitution(value: float | str, name: str = "e") -> Any:
    """A coefficient of restitution as given by a user: a number in (0, 1] [-] (float), or
    the word ``"housner"`` (returned as such; 1 − 1.5·sin²α of each block, resolved by
    :func:`rocking.dynamics.body.resolve_e`).  Text is accepted for both (command line, tables)."""
    if isinstance(value, str):
        if value.strip().lower() == HOUSNER:
            return HOUSNER
        try:
            value = float(value)
        except ValueError:
            raise InputError(
                f"{name} must be a number in (0, 1] or 'housner', got {value!r}"
            ) from None
    try:
        return in_range(name, value, 0.0, 1.0, lo_open=True, unit="-")
    except InputError:
        raise InputError(f"{name} must be a number in (0, 1] or 'housner', got {value!r}") from None


def read_toml(path: str | os.PathLike[str], label: str | None = None) -> dict:
    """The TOML file ``path`` as a dict; a syntax error is an InputError that starts with
    ``label`` (default: the path), a file that cannot be read or is not text one that names
    it (:func:`rocking.core.files.read_text`)."""
    path = Path(path)
    text = read_text(path, "TOML file")
    try:
        return tomllib.loads(text)
    except tomllib.TOMLDecodeError as exc:
        raise InputError(f"{label or path}: not valid TOML ({exc})") from None


def _u(unit: str) -> str:
    return f" [{unit}]" if unit else ""


def require_memory(nbytes: float, what: str) -> None:
    """Refuse work that would need more memory than is available, before it starts.

    ``nbytes`` is the estimated peak [bytes]; ``what`` says what needs it, e.g.
    ``"--n: 1,000,000,000 motions of 8,001 samples"``.  Raises :class:`InputError` with both
    figures when the estimate exceeds the memory available now (``psutil``).
    """
    import psutil

    available = psutil.virtual_memory().available
    if nbytes > available:
        raise InputError(
            f"{what} would need about {_bytes(nbytes)} of memory; {_bytes(available)} are available"
        )


def _bytes(n: float) -> str:
    for unit in ("bytes", "kB", "MB", "GB", "TB", "PB"):
        if n < 1000.0 or unit == "PB":
            return f"{n:.0f} {unit}" if unit == "bytes" else f"{n:.3g} {unit}"
        n /= 1000.0
    raise AssertionError("unreachable")
