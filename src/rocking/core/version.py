"""The version of the installed package, standard library only: what run.json, the chunk
store's fingerprints and the command line's bug reports record, without importing the package
root from inside it."""

from __future__ import annotations

from importlib.metadata import PackageNotFoundError, version


def _installed() -> str:
    try:
        return version("rocking")
    except PackageNotFoundError:  # pragma: no cover - not installed (running from a source tree)
        return "0+unknown"


#: The version of the installed package ("0+unknown" when it is not installed).
VERSION = _installed()
