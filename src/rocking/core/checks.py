"""Small input checks shared by the public functions (errors name the parameter), and the
bounds of every size and intensity a user can type (:data:`LIMITS`, :data:`MAX_G`,
:data:`MAX_SEED`), checked before any work.

NumPy is imported by the functions that need it, so that the command line can check its
options with this module before anything heavy is loaded.
"""

from __future__ import annotations

import dataclasses
import math
import numbers
import os
import tomllib
from collections.abc import Mapping
from pathlib import Path
from typing import TYPE_CHECKING, Any, TypeVar, cast

from ..errors import InputError
from .files import read_text

if TYPE_CHECKING:
    import numpy as np
    from numpy.typing import ArrayLike

#: Largest value of each kind of size a user can give (command-line options, ``--set`` keys,
#: API arguments), with the reason: above it the work would take hours or more memory than a
#: workstation has, for no gain in accuracy.  A size is checked against its limit before
#: anything is built from it (:func:`count`).
LIMITS: dict[str, tuple[int, str]] = {
    "motions": (
        100_000,
        "the paper's studies use 200-500 motions, and 100,000 motions of 20 s at 1/400 s "
        "already take 6.4 GB",
    ),
    "levels": (
        10_000,
        "a fragility curve is drawn from tens of levels, and each level simulates every body "
        "under every motion",
    ),
    "frequencies": (
        10_000,
        "a response spectrum is smooth at 100 frequencies per decade, and each frequency is "
        "an oscillator run through every sample of every motion",
    ),
    "frequencies per decade": (
        1_000,
        "US SRP 3.7.1 checks the fit at 100 per decade, and each frequency is an oscillator "
        "run through every sample of every motion",
    ),
    "iterations": (
        20,
        "the correction brings the mean spectrum to the target in a few iterations, and each "
        "one simulates the pilot motions again",
    ),
    "bootstrap resamples": (
        2_000,
        "1000-2000 resamples are enough for percentile intervals (Efron & Tibshirani 1993, "
        "Sec. 19.3), and each one refits every body",
    ),
    "sample motions": (100, "each one is drawn in the figure"),
    "samples per period": (
        10_000,
        "20 samples per period resolve a pulse (the time step is also kept to p*dt <= 0.05), "
        "and each sample is a step of every amplitude's simulation",
    ),
}
#: Largest acceleration intensity (PGA, A_gx, PSA, a design spectrum's ZPA) accepted [g]: the
#: largest peaks ever recorded are about 3-4 g, so a larger value is a mistake of units.
MAX_G = 10.0
#: Largest seed [-]: seeds are stored in netCDF (classic format) attributes, 32-bit integers.
MAX_SEED = 2**31 - 1


def positive(name: str, value: float | str, unit: str = "") -> float:
    """Return ``value`` as a float, or raise if it is not a finite number > 0."""
    try:
        x = float(value)
    except (TypeError, ValueError):
        raise InputError(f"{name} must be a number > 0{_u(unit)}, got {value!r}") from None
    if not math.isfinite(x) or x <= 0.0:
        raise InputError(f"{name} must be a finite number > 0{_u(unit)}, got {value!r}")
    return x


def kinetic_friction(
    mu: float | None,
    mu_k: float | None,
    *,
    names: tuple[str, str] = ("mu", "mu_k"),
    where: str = "",
) -> None:
    """Refuse a kinetic friction coefficient ``mu_k`` [-] without a static one ``mu`` [-], or
    above it; the error names them ``names`` (e.g. the options ``--mu``, ``--mu-k``), followed
    by ``where`` (e.g. " (block 2)")."""
    static, kinetic = names
    if mu_k is None:
        return
    if mu is None:
        raise InputError(
            f"{kinetic} needs {static}{where}: give the static friction coefficient {static} "
            "as well"
        )
    if mu_k > mu:
        raise InputError(
            f"{kinetic} = {mu_k:g} exceeds {static} = {mu:g}{where}: kinetic friction is at most "
            "the static"
        )


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
    import numpy as np

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


def count(name: str, value: object, kind: str, minimum: int = 1) -> int:
    """``value`` as an int from ``minimum`` to the limit of ``kind`` in :data:`LIMITS`, or an
    :class:`InputError` naming ``name``, the limit and why (checked before anything is built
    from the size)."""
    limit, why = LIMITS[kind]
    if isinstance(value, bool) or not isinstance(value, numbers.Integral):
        raise InputError(f"{name} must be an integer, got {value!r}")
    value = int(value)
    if value < minimum:
        raise InputError(f"{name} must be an integer >= {minimum}, got {value}")
    if value > limit:
        raise InputError(f"{name} {value:,} is above the limit of {limit:,} {kind}: {why}")
    return int(value)


def seed(name: str, value: object) -> int:
    """A seed: an int from 0 to :data:`MAX_SEED`, or an :class:`InputError` naming ``name``."""
    ok = isinstance(value, numbers.Integral) and not isinstance(value, bool)
    if not ok or not 0 <= int(value) <= MAX_SEED:  # type: ignore[call-overload]
        raise InputError(
            f"{name} must be an integer from 0 to {MAX_SEED} (2**31 - 1: seeds are stored "
            f"in netCDF files as 32-bit integers), got {value!r}"
        )
    return int(value)  # type: ignore[call-overload]


def intensity_g(name: str, value: float | str) -> float:
    """An acceleration intensity [g] (PGA, A_gx, PSA, ZPA): a finite number > 0 and at most
    :data:`MAX_G`, or an :class:`InputError` saying that more is a mistake of units."""
    x = positive(name, value, "g")
    if x > MAX_G:
        raise InputError(too_strong(name, x))
    return x


def too_strong(what: str, value_g: float) -> str:
    """The message for an acceleration ``value_g`` [g] above :data:`MAX_G`."""
    return (
        f"{what} = {value_g:g} g is above {MAX_G:g} g, more than any earthquake (the largest "
        "recorded peaks are about 3-4 g): certainly a mistake of units (m/s² or cm/s² read "
        "as g?)"
    )


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


#: A record (frozen dataclass) a function takes with shorthand keyword arguments for its fields.
R = TypeVar("R")


def record(kind: type[R], value: R | None, options: dict[str, Any], name: str) -> R:
    """The record ``name`` of a call: ``value`` (default ``kind()``) with the entries of
    ``options`` named like its fields (the function's shorthand keyword arguments) in their
    place; those entries are taken out of ``options``."""
    if value is None:
        value = kind()
    elif not isinstance(value, kind):
        raise InputError(f"{name} must be a rocking.{kind.__name__}, got {type(value).__name__}")
    fields = dataclasses.fields(cast(Any, value))
    given = {f.name: options.pop(f.name) for f in fields if f.name in options}
    return cast(R, dataclasses.replace(cast(Any, value), **given)) if given else value


def unexpected(options: Mapping[str, Any]) -> None:
    """Refuse keyword arguments that are neither a parameter of the function nor a shorthand,
    named as Python names them."""
    if options:
        names = ", ".join(repr(name) for name in sorted(options))
        many = len(options) > 1
        raise InputError(
            f"got {'' if many else 'an '}unexpected keyword argument{'s' * many} {names}"
        )


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
