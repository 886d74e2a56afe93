"""Output folders of runs: claimed by one run at a time, with a status, written file by file.

Every command that writes a folder (``rocking fragility``, ``agx50``, ``risk``, ``screen``,
``reproduce``, ``motions show`` and ``motions fit``) writes it through a :class:`RunFolder`:

* **claim**: the run holds an operating-system lock on ``.rocking.lock`` in the folder from start
  to end (``filelock``; released by the system if the process dies, so a crash never leaves the
  folder locked).  A second run into the same folder while the first one works stops at once with
  an error instead of mixing its files with the first's;
* **one run per folder**: a folder whose ``run.json`` records another run (another command, or
  other parameters) is refused at once, before anything in it is touched, naming what differs;
  ``overwrite=True`` (``--overwrite``) replaces that run: its files are deleted once the new run
  is accepted (its inputs checked and the folder claimed), never before.  The same run again
  resumes: it keeps the resumable work (:attr:`RunFolder.chunks`) and first deletes the files the
  previous attempt listed in its ``run.json``, so that an interrupted rerun never leaves the
  previous tables beside its own ``"failed"`` status looking like results.  Only files a run
  recorded, its run.json and its chunks are deleted, never others;
* **inputs are never outputs**: a run never writes into, or clears, a folder it reads (``risk
  --fragility F --out F``), nor deletes an input file the previous run had written;
* **status**: ``run.json`` says ``"running"`` from the start, then ``"completed"`` or
  ``"failed"`` (an exception, Ctrl-C, SIGTERM), with the parameters, seeds, versions, wall time,
  the list of files the run wrote (``outputs``) and its bookkeeping (e.g. Monte Carlo chunks
  computed and loaded), which stays out of the result files so that they are the same bytes
  however the run was computed or resumed;
* **atomic files**: every file goes through :func:`rocking.core.files.atomic_write`.
"""

from __future__ import annotations

import contextlib
import datetime as _dt
import json
import os
import platform
import sys
import time
from collections.abc import Callable, Mapping
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


def claim(folder: Path, whose: str = "") -> Any:
    """Create ``folder`` if needed and lock it for this process (an operating-system lock on
    :data:`LOCK`, released if the process dies): the one home of the claim of an output folder
    (run folders here, the Monte Carlo chunk store). Returns the held ``filelock`` lock; an
    InputError names the folder when it cannot be created or written, or when another run
    holds it (``whose``: where to read about that run, e.g. " (see its run.json)")."""
    import filelock

    try:
        folder.mkdir(parents=True, exist_ok=True)
    except OSError as exc:
        raise InputError(f"out: cannot create folder {folder} ({exc.strerror})") from None
    lock = filelock.FileLock(folder / LOCK, timeout=0)
    try:
        lock.acquire()
    except filelock.Timeout:
        raise InputError(
            f"out: {folder} is in use by another rocking run{whose}; wait for it to end or "
            "choose another folder"
        ) from None
    except OSError as exc:
        raise InputError(f"out: cannot write in {folder} ({exc.strerror})") from None
    return lock


RUN_JSON = "run.json"
#: Subfolder of a run's resumable work (Monte Carlo chunks).
CHUNKS = "chunks"
#: Attributes of result datasets that describe how they were computed, not what they are: moved
#: from netCDF files to run.json (``bookkeeping``).
BOOKKEEPING = ("chunks_computed", "chunks_loaded")
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
        JSON-serialisable parameters and seeds of the run (entries of run.json): what makes it
        the same run as the folder's previous one, or another.
    settings : dict, optional
        Entries of run.json that do not change the results (e.g. the scheduler).
    overwrite : bool
        Replace the results of another run in the folder instead of refusing to.
    reads : dict of str to str or Path
        Files and folders the run reads, by the name of their option (None values ignored):
        refused when the run would write into such a folder or delete such a file.
    """

    def __init__(
        self,
        path: str | os.PathLike[str],
        *,
        command: str,
        params: dict,
        settings: dict | None = None,
        overwrite: bool = False,
        reads: Mapping[str, str | os.PathLike[str] | None] | None = None,
    ):
        self.path = Path(path)
        self.command = command
        self.params = _as_json(params)
        self.settings = dict(settings or {})
        self.overwrite = overwrite
        self.reads = {k: Path(p) for k, p in (reads or {}).items() if p is not None}
        self.outputs: list[str] = []
        self.info: dict = {}
        self._lock: Any = None  # a filelock lock while the folder is claimed
        self._start = 0.0

    # ---- claim and status ----------------------------------------------------------------------
    def __enter__(self) -> RunFolder:
        if self.path.exists() and not self.path.is_dir():
            raise InputError(f"out: {self.path} exists and is not a folder")
        self._check_reads(None)
        lock = claim(self.path, f" (see its {RUN_JSON})")
        self._lock = lock
        try:
            previous = self._previous()
            differs = None if previous is None else self._differs(previous)
            if differs is not None and not self.overwrite:
                raise InputError(
                    f"out: {self.path} holds the results of another run ({differs}); rerun "
                    "with --overwrite to replace them, or choose another --out folder"
                )
            self._check_reads(previous)
            if previous is not None:
                self._remove_previous(previous)
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
                # the run's own error says more than a failure to record it (a full disk)
                with contextlib.suppress(OSError):
                    self._write_status(FAILED, error=what)
        finally:
            self._lock.release()

    def _previous(self) -> dict | None:
        """The previous run's run.json (``{}`` when it cannot be read), or None if there is
        none."""
        previous = self.path / RUN_JSON
        if not previous.is_file():
            return None
        try:
            record = json.loads(previous.read_text())
        except (OSError, ValueError):
            return {}
        return record if isinstance(record, dict) else {}

    def _differs(self, previous: dict) -> str | None:
        """What makes the previous run (its run.json) another run than this one, or None."""
        if not previous:
            return f"its {RUN_JSON} cannot be read"
        if previous.get("command") != self.command:
            return f"a run of 'rocking {previous.get('command')}'"
        differ = [k for k, v in self.params.items() if _same_form(previous.get(k)) != _same_form(v)]
        return f"'rocking {self.command}' with other {', '.join(differ)}" if differ else None

    def _doomed(self, previous: dict | None) -> list[Path]:
        """What entering the folder deletes: the previous run's outputs, and with
        :attr:`overwrite` its run.json and chunks too."""
        if previous is None:
            return []
        outputs = previous.get("outputs", [])
        doomed = [self.path / str(name) for name in outputs if isinstance(outputs, list)]
        if self.overwrite:
            doomed += [self.path / RUN_JSON, self.chunks]
        root = self.path.resolve()
        return [p for p in (d.resolve() for d in doomed) if root in p.parents]  # never outside

    def _check_reads(self, previous: dict | None) -> None:
        """Refuse to write into a folder the run reads, or to delete a file it reads (before
        the folder is created: ``previous`` None; then once its run.json is read)."""
        out = self.path.resolve()
        doomed = self._doomed(previous)
        for option, read in self.reads.items():
            source = read.resolve()
            if read.is_dir() and (source == out or source in out.parents):
                raise InputError(
                    f"out {self.path}: the run reads the folder {option} {read} and never "
                    "writes into it; choose another --out folder"
                )
            if any(source == d or d in source.parents for d in doomed):
                raise InputError(
                    f"out {self.path}: the run reads {option} {read}, a file of the folder's "
                    "previous run, which it would delete; choose another --out folder"
                )

    def _remove_previous(self, previous: dict) -> None:
        """Delete what :meth:`_doomed` lists."""
        import shutil

        for target in self._doomed(previous):
            if target.is_dir():
                shutil.rmtree(target)
            else:
                target.unlink(missing_ok=True)

    @property
    def chunks(self) -> Path:
        """Folder of the run's resumable work (Monte Carlo chunks): kept when the same run is
        started again, deleted with ``overwrite``."""
        return self.path / CHUNKS

    def _write_status(self, status: str, **extra) -> None:
        wall = round(time.perf_counter() - self._start, 3) if self._start else 0.0
        record = {
            "status": status,
            "command": self.command,
            **self.params,
            **self.settings,
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
        """Write an xarray Dataset as netCDF-3 (SciPy engine; see :func:`to_netcdf3_bytes`),
        its :data:`BOOKKEEPING` attributes moved to run.json (``bookkeeping``, by file)."""
        kept = {k: v for k, v in dataset.attrs.items() if k not in BOOKKEEPING}
        moved = {k: v for k, v in dataset.attrs.items() if k in BOOKKEEPING}
        if moved:
            self.info.setdefault("bookkeeping", {})[name] = moved
        results = dataset.copy(deep=False)
        results.attrs = kept
        return self.write(name, to_netcdf3_bytes(results))


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

    from .version import package_version

    out_dir = Path(out_dir)
    out_dir.mkdir(parents=True, exist_ok=True)
    record = {
        "package": "rocking",
        "version": package_version(),
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


def _as_json(params: dict) -> dict:
    """``params`` as run.json stores and reads them back (NumPy values and paths as JSON)."""
    return json.loads(json.dumps(params, default=_json_default))


def _same_form(value: Any) -> str:
    """A JSON value as text with sorted keys, for comparing (NaN equals NaN)."""
    return json.dumps(value, sort_keys=True)


def _json_default(obj):
    import numpy as np

    if isinstance(obj, np.generic):
        return obj.item()
    if isinstance(obj, np.ndarray):
        return obj.tolist()
    if isinstance(obj, Path):
        return str(obj)
    raise TypeError(f"run.json: cannot store a {type(obj).__name__} ({obj!r})")
