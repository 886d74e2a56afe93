"""Output folders of runs: claimed by one run at a time, with a status, written file by file.

Every command that writes a folder (``rocking fragility``, ``agx50``, ``screen``, ``reproduce``,
``motions show`` and ``motions fit``) writes it through a :class:`RunFolder`:

* **claim**: the run holds an operating-system lock on ``.rocking.lock`` in the folder from start
  to end (``filelock``; released by the system if the process dies, so a crash never leaves the
  folder locked).  A second run into the same folder while the first one works stops at once with
  an error instead of mixing its files with the first's;
* **status**: ``run.json`` says ``"running"`` from the start, then ``"completed"`` or
  ``"failed"`` (an exception, Ctrl-C, SIGTERM), with the parameters, seeds, versions, wall time
  and the list of files the run wrote (``outputs``);
* **no stale results**: the files that the previous run of the folder listed in its ``run.json``
  are deleted before anything else, so an interrupted rerun never leaves the previous run's tables
  beside its own ``"failed"`` status looking like results.  Only files a run recorded are deleted,
  never others, and resumable work (Monte Carlo chunks) is kept;
* **atomic files**: every file goes through :func:`rocking.core.files.atomic_write`.
"""

from __future__ import annotations

import datetime as _dt
import json
import os
import platform
import sys
import time
from collections.abc import Callable
from pathlib import Path
from types import TracebackType
from typing import IO, TYPE_CHECKING, Any

from ..defaults import CSV_FLOAT_FORMAT
from ..errors import InputError
from .files import atomic_write, save_figure

if TYPE_CHECKING:
    import pandas as pd
    import xarray as xr
    from matplotlib.figure import Figure

LOCK = ".rocking.lock"
RUN_JSON = "run.json"
#: Status words of run.json.
RUNNING, COMPLETED, FAILED = "running", "completed", "failed"


class RunFolder:
    """The output folder of one run (a context manager; see the module notes).

    Parameters
    ----------
    path : str or Path
        The folder (created if missing).
    command : str
        What runs, e.g. ``"fragility"`` (recorded in run.json).
    params : dict
        JSON-serialisable parameters and seeds of the run (entries of run.json).
    """

    def __init__(self, path: str | os.PathLike[str], *, command: str, params: dict):
        self.path = Path(path)
        self.command = command
        self.params = dict(params)
        self.outputs: list[str] = []
        self.info: dict = {}
        self._lock: Any = None  # a filelock lock while the folder is claimed
        self._start = 0.0

    # ---- claim and status ----------------------------------------------------------------------
    def __enter__(self) -> RunFolder:
        import filelock

        if self.path.exists() and not self.path.is_dir():
            raise InputError(f"out: {self.path} exists and is not a folder")
        try:
            self.path.mkdir(parents=True, exist_ok=True)
        except OSError as exc:
            raise InputError(f"out: cannot create folder {self.path} ({exc.strerror})") from None
        lock = filelock.FileLock(self.path / LOCK, timeout=0)
        try:
            lock.acquire()
        except filelock.Timeout:
            raise InputError(
                f"out: {self.path} is in use by another rocking run (see its "
                f"{RUN_JSON}); wait for it to end or choose another folder"
            ) from None
        except OSError as exc:
            raise InputError(f"out: cannot write in {self.path} ({exc.strerror})") from None
        self._lock = lock
        try:
            self._remove_previous_outputs()
            self._start = time.perf_counter()
            self._write_status(RUNNING)
        except BaseException:
            lock.release()
            raise
        return self

    def __exit__(
        self,
        exc_type: type[BaseException] | None,
        exc: BaseException | None,
        tb: TracebackType | None,
    ) -> None:
        try:
            if exc_type is None:
                self._write_status(COMPLETED)
            else:
                what = (
                    "interrupted"
                    if issubclass(exc_type, (KeyboardInterrupt, SystemExit))
                    else f"{exc_type.__name__}: {exc}"
                )
                self._write_status(FAILED, error=what)
        finally:
            self._lock.release()

    def _remove_previous_outputs(self) -> None:
        previous = self.path / RUN_JSON
        if not previous.is_file():
            return
        try:
            outputs = json.loads(previous.read_text()).get("outputs", [])
        except (OSError, ValueError, AttributeError):
            return  # not ours to interpret: leave the files alone
        root = self.path.resolve()
        for name in outputs if isinstance(outputs, list) else []:
            target = (self.path / str(name)).resolve()
            if target.parent == root or root in target.parents:  # never outside the folder
                target.unlink(missing_ok=True)

    def _write_status(self, status: str, **extra) -> None:
        wall = round(time.perf_counter() - self._start, 3) if self._start else 0.0
        record = {
            "status": status,
            "command": self.command,
            **self.params,
            "outputs": self.outputs,
            "wall_time_s": wall,
            **self.info,
            **extra,
        }
        provenance(self.path, **record)

    def update(self, **info: Any) -> None:
        """Add entries (JSON-serialisable) to run.json, e.g. a summary of the results."""
        self.info.update(info)
        self._write_status(RUNNING)

    # ---- files ---------------------------------------------------------------------------------
    def file(self, name: str) -> Path:
        """Path of the output ``name`` (relative, '/'-separated), recorded in run.json; its
        folder is created.  For outputs written by other code, which must write atomically."""
        rel = Path(name)
        if rel.is_absolute() or ".." in rel.parts:
            raise ValueError(f"output name {name!r} must be relative and inside the folder")
        path = self.path / rel
        path.parent.mkdir(parents=True, exist_ok=True)
        if rel.as_posix() not in self.outputs:
            self.outputs.append(rel.as_posix())
        return path

    def write(self, name: str, data: bytes | str | Callable[[IO[bytes]], Any]) -> Path:
        """Write ``data`` (bytes, str or a function of a binary file) to ``name`` atomically."""
        return atomic_write(self.file(name), data)

    def write_csv(self, name: str, table: pd.DataFrame, **to_csv: Any) -> Path:
        """Write a pandas DataFrame as CSV (``to_csv`` options; by default ``index=False`` and
        floats to :data:`rocking.defaults.CSV_FLOAT_FORMAT`, no float noise)."""
        to_csv.setdefault("index", False)
        to_csv.setdefault("float_format", CSV_FLOAT_FORMAT)
        return self.write(name, table.to_csv(**to_csv))

    def write_figure(self, name: str, fig: Figure, dpi: int = 150) -> Path:
        """Save a Matplotlib figure (format from the name's suffix) atomically."""
        return save_figure(fig, self.file(name), dpi)

    def write_netcdf(self, name: str, dataset: xr.Dataset) -> Path:
        """Write an xarray Dataset as netCDF-3 (SciPy engine; see :func:`to_netcdf3_bytes`)."""
        return self.write(name, to_netcdf3_bytes(dataset))


def to_netcdf3_bytes(dataset: xr.Dataset) -> bytes:
    """A Dataset as netCDF-3 bytes, integers as int32 and booleans as int8 (netCDF-3 has no
    64-bit integers nor booleans)."""
    import numpy as np

    ds = dataset.copy()
    for name, var in ds.variables.items():
        if var.dtype.kind in "iu":
            ds[name] = var.astype(np.int32)
        elif var.dtype.kind == "b":
            ds[name] = var.astype(np.int8)
    return bytes(ds.to_netcdf(None, engine="scipy"))


def provenance(out_dir: str | os.PathLike[str], **params: Any) -> Path:
    """Write ``run.json`` in ``out_dir`` (atomically) and return its path.

    The file holds ``params`` (e.g. parameters, seeds, backend, ``wall_time_s`` per section,
    ``status``; anything JSON-serialisable, NumPy scalars and arrays included) and the
    environment: package version (``rocking.__version__``), Python, NumPy, Numba, SciPy and
    xarray versions, platform, command line and the UTC time of writing.
    """
    import numba
    import numpy as np
    import scipy
    import xarray

    from .. import __version__

    out_dir = Path(out_dir)
    out_dir.mkdir(parents=True, exist_ok=True)
    record = {
        "package": "rocking",
        "version": __version__,
        "written_utc": _dt.datetime.now(_dt.UTC).isoformat(timespec="seconds"),
        "command_line": [Path(sys.argv[0]).name, *sys.argv[1:]],
        "python": platform.python_version(),
        "numpy": np.__version__,
        "numba": numba.__version__,
        "scipy": scipy.__version__,
        "xarray": xarray.__version__,
        "platform": platform.platform(),
        "cpu_count": os.cpu_count(),
        **params,
    }
    path = out_dir / "run.json"
    atomic_write(path, json.dumps(record, indent=2, default=_json_default) + "\n")
    return path


def _json_default(obj):
    import numpy as np

    if isinstance(obj, np.generic):
        return obj.item()
    if isinstance(obj, np.ndarray):
        return obj.tolist()
    if isinstance(obj, Path):
        return str(obj)
    raise TypeError(f"run.json: cannot store a {type(obj).__name__} ({obj!r})")
