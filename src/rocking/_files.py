"""Writing files so that nothing half-written ever carries its final name.

:func:`atomic_write` writes to a temporary file in the destination folder, flushes it to disk and
renames it over the final name (:func:`os.replace`, atomic on POSIX and Windows): a process killed
at any instant leaves either the old file or the new one, never a truncated one (at worst a stray
hidden temporary file).  The file gets the permissions an ordinary ``open(path, "w")`` would give
(0666 minus the umask); :func:`tempfile.mkstemp` alone would leave it private (0600).
"""

from __future__ import annotations

import functools
import os
import tempfile
from pathlib import Path


@functools.cache
def _umask() -> int:
    # The only portable way to read the umask is to set it and put it back (once per process).
    mask = os.umask(0o022)
    os.umask(mask)
    return mask


def atomic_write(path, data) -> Path:
    """Write ``data`` to ``path`` atomically; return the path.

    Parameters
    ----------
    path : str or Path
        Destination file; its folder must exist.
    data : bytes, str or callable
        The content (str is written as UTF-8), or a function called with a binary file object
        that writes it (e.g. ``lambda f: numpy.savez(f, ...)``).
    """
    path = Path(path)
    fd, tmp = tempfile.mkstemp(prefix=f".{path.name}.", suffix=".tmp", dir=path.parent)
    try:
        if hasattr(os, "fchmod"):
            os.fchmod(fd, 0o666 & ~_umask())
        with os.fdopen(fd, "wb") as fh:
            if callable(data):
                data(fh)
            else:
                fh.write(data.encode("utf-8") if isinstance(data, str) else data)
            fh.flush()
            os.fsync(fh.fileno())
        if not hasattr(os, "fchmod"):  # Windows: permissions by name
            os.chmod(tmp, 0o666 & ~_umask())
        os.replace(tmp, path)
    except BaseException:
        Path(tmp).unlink(missing_ok=True)
        raise
    return path


def save_figure(fig, path, dpi: int = 150) -> Path:
    """Save a Matplotlib ``Figure`` to ``path`` atomically (format from the suffix, PNG if
    none); return the path."""
    fmt = Path(path).suffix.lstrip(".") or "png"
    return atomic_write(path, lambda fh: fig.savefig(fh, format=fmt, dpi=dpi))
