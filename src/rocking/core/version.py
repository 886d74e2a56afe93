"""The installed version of the package, read once on first use: ``importlib.metadata`` takes
about 0.1 s to import, which ``import rocking`` (and every command's start) need not pay.
Standard library only."""

from __future__ import annotations

import functools


@functools.cache
def package_version() -> str:
    """The installed version of ``rocking`` (``"0+unknown"`` when run from a source tree that
    was not installed)."""
    from importlib.metadata import PackageNotFoundError, version

    try:
        return version("rocking")
    except PackageNotFoundError:  # pragma: no cover - not installed
        return "0+unknown"
