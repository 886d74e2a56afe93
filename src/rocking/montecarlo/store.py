"""Resumable on-disk store of finished chunks of a Monte Carlo run (issue 5, part 5).

A run writes each chunk of results as soon as it is finished into its output folder, as one
``chunk-<key>.npz`` file, atomically (:func:`rocking.core.files.atomic_write`).  A process killed at
any instant (kill -9) therefore leaves only complete chunk files (plus, at worst, a stray
temporary file that is ignored).  Writing the same chunk twice (a Dask task run again after a
worker died) replaces a file with an identical one.

Results of two runs are never mixed:

* the folder's ``chunks.json`` manifest records what the chunks are computed from (bodies,
  motions, restitution, …: whatever the caller passes as ``params``) and opening the folder with
  other parameters raises :class:`~rocking.errors.InputError` naming the differences;
* while a store is open its folder is locked (an operating-system lock on ``.rocking.lock``,
  released if the process dies): a second run that opens it at the same time stops at once;
* every chunk carries the *fingerprint* of what produced it: the parameters, the package version
  and a digest of the source of the integration kernels.  A chunk with another fingerprint (left
  by an earlier version of the package, or by a run that slipped in some other way) is never
  loaded: its work is computed again and its file replaced;
* the manifest also holds the SHA-256 of every chunk file the run wrote (``chunks``), rewritten
  at most every :data:`SUMS_EVERY_S` seconds and when the store closes; in between, each sum is
  appended to ``chunks.sums`` (one line per chunk, right after its file is written), which the
  next rewrite folds in.  A chunk file whose bytes are not those (rewritten with a valid
  structure but other values, by a disk error or a stray script), or whose sum was never
  recorded, is computed again;
* a manifest that cannot be read (damaged) is rebuilt, with a warning: the chunk files whose
  fingerprint is this run's are kept (their sums recorded anew), the others computed again.
"""

from __future__ import annotations

import hashlib
import io
import json
import time
import warnings
import zipfile
from collections.abc import Iterator
from functools import cache
from importlib import resources
from pathlib import Path
from typing import IO, TYPE_CHECKING, Any

import numpy as np

from ..core.files import atomic_write
from ..core.runs import claim
from ..errors import InputError

if TYPE_CHECKING:
    from numpy.typing import ArrayLike

MANIFEST = "chunks.json"
#: Sums of the chunks written since the manifest was last rewritten, one "key sha256" a line.
JOURNAL = "chunks.sums"
_FORMAT = "rocking-chunks-2"
#: Seconds between writes of the chunk sums to the manifest (it is rewritten whole: once per
#: chunk would cost O(chunks²); a chunk whose sum a kill -9 lost is computed again).
SUMS_EVERY_S = 1.0
#: Modules whose source decides the numbers a chunk holds.
KERNEL_MODULES = (
    "core/compile.py",
    "dynamics/equation.py",
    "dynamics/impacts.py",
    "dynamics/batch.py",
    "dynamics/batch_lanes.py",
    "dynamics/batch_records.py",
)


def fingerprint(params: dict) -> str:
    """SHA-256 of the JSON form of ``params`` (keys sorted)."""
    return hashlib.sha256(json.dumps(params, sort_keys=True).encode()).hexdigest()


@cache
def code_version() -> dict:
    """The package version and the SHA-256 of the source of the integration kernels."""
    from ..core.version import package_version

    h = hashlib.sha256()
    for name in KERNEL_MODULES:
        h.update(resources.files("rocking").joinpath(name).read_bytes())
    return {"version": package_version(), "kernel_sha256": h.hexdigest()}


class ChunkStore:
    """Folder of finished chunks of one run; open it with ``with`` (it locks the folder).

    Parameters
    ----------
    folder : str or Path
        Output folder (created if missing).
    params : dict
        JSON-serialisable description of everything the chunk results depend on.

    Raises
    ------
    InputError
        If the folder cannot be created, is in use by another run, or holds chunks of a run with
        other parameters.
    """

    def __init__(self, folder, params: dict):
        self.folder = Path(folder)
        self.params = params
        self.fingerprint = fingerprint({"params": params, **code_version()})
        self._lock: Any = None  # a filelock lock while the folder is claimed
        #: SHA-256 of every chunk file of the run, by key (the manifest's ``chunks``).
        self.sums: dict[str, str] = {}
        self._rebuilt = False  # the manifest was damaged: the sums are taken from the files
        self._written = 0.0  # time.monotonic() of the last write of the manifest
        self._pending = False  # sums not yet in the manifest
        self._journal: IO[str] | None = None  # JOURNAL, appended to while the store is open

    def __enter__(self) -> ChunkStore:
        lock = claim(self.folder)
        self._lock = lock
        try:
            self._check_manifest()
        except BaseException:
            lock.release()
            raise
        return self

    def __exit__(self, *exc) -> None:
        try:
            if self._pending:
                self._write_manifest()
            if self._journal is not None:
                self._journal.close()
                (self.folder / JOURNAL).unlink(missing_ok=True)
        finally:
            self._journal = None
            self._lock.release()

    def _write_manifest(self) -> None:
        text = json.dumps(
            {
                "format": _FORMAT,
                "sha256": fingerprint(self.params),
                "params": self.params,
                "chunks": dict(sorted(self.sums.items())),
            },
            indent=1,
        )
        atomic_write(self.folder / MANIFEST, text)
        self._written = time.monotonic()
        self._pending = False
        if self._journal is not None:  # folded in: start it again
            self._journal.truncate(0)

    def _check_manifest(self) -> None:
        digest = fingerprint(self.params)
        manifest = self.folder / MANIFEST
        old = self._read_manifest(manifest) if manifest.exists() else None
        if old is not None:
            if old.get("sha256") != digest:
                differ = sorted(
                    k
                    for k in set(self.params) | set(old.get("params", {}))
                    if self.params.get(k) != old.get("params", {}).get(k)
                )
                raise InputError(
                    f"out: {self.folder} holds results of a different run (differs in "
                    f"{', '.join(differ) or 'format'}); use another folder, or delete this "
                    "one (a command's --overwrite does)"
                )
            sums = old.get("chunks", {})
            self.sums = {str(k): str(v) for k, v in sums.items()} if isinstance(sums, dict) else {}
            self._read_journal()
        else:  # a new run, or a damaged manifest rebuilt from the chunk files
            self._rebuilt = manifest.exists()
            self._write_manifest()
        mode = "a" if old is not None else "w"  # the sums of this manifest only
        self._journal = open(self.folder / JOURNAL, mode, encoding="ascii")  # noqa: SIM115

    def _read_journal(self) -> None:
        """Add the sums of :data:`JOURNAL` (a line cut by a kill is ignored)."""
        try:
            lines = (self.folder / JOURNAL).read_text(encoding="ascii", errors="replace")
        except FileNotFoundError:
            return
        for line in lines.splitlines():
            key, _, digest = line.partition(" ")
            if len(digest) == 64 and all(c in "0123456789abcdef" for c in digest):
                self.sums[key] = digest
                self._pending = True

    @staticmethod
    def _read_manifest(path: Path) -> dict | None:
        """The manifest, or None if it is damaged (not JSON, not a dict)."""
        try:
            data = json.loads(path.read_bytes())
            if not isinstance(data, dict):
                raise ValueError("not a JSON object")
        except ValueError as exc:
            warnings.warn(
                f"{path} is damaged ({exc}); rebuilt from the chunk files (those of this run "
                "are kept, the others computed again)",
                stacklevel=4,
            )
            return None
        except OSError as exc:
            raise InputError(f"out: cannot read {path} ({exc.strerror or exc})") from None
        if data.get("format") != _FORMAT:
            raise InputError(
                f"out: {path} is not a chunk manifest of this version of rocking; use another "
                "folder, or delete this one (a command's --overwrite does)"
            )
        return data

    def path(self, key: str) -> Path:
        """File of chunk ``key``."""
        return self.folder / f"chunk-{key}.npz"

    def save(self, key: str, **arrays: ArrayLike) -> None:
        """Write chunk ``key`` (arrays by name) atomically, with the store's fingerprint, and
        record the SHA-256 of the file (in the manifest within :data:`SUMS_EVERY_S` seconds).

        Not flushed to the disk one by one (``durable=False``; 0.5-1 ms each here, more on
        network disks, for hundreds of chunks a run): a chunk whose bytes a system crash lost
        fails its sum when :meth:`load_all` reads it, and is computed again."""
        buf = io.BytesIO()
        # numpy's stub types savez's **kwds as its keyword allow_pickle (bool)
        np.savez(buf, fingerprint=np.array(self.fingerprint), **arrays)  # type: ignore[arg-type]
        content = buf.getvalue()
        atomic_write(self.path(key), content, durable=False)
        self.sums[key] = digest = hashlib.sha256(content).hexdigest()
        self._pending = True
        if time.monotonic() - self._written >= SUMS_EVERY_S:
            self._write_manifest()
        elif self._journal is not None:
            self._journal.write(f"{key} {digest}\n")
            self._journal.flush()

    def load_all(self) -> Iterator[tuple[str, dict[str, np.ndarray]]]:
        """Yield (key, dict of arrays) for every complete chunk of this run, in key order.

        A file whose SHA-256 is not the one recorded when it was saved (or has none recorded),
        that cannot be read, or whose fingerprint is not the store's is skipped: its chunk
        counts as missing and is computed again.  After a damaged manifest, the sums are those
        of the files whose fingerprint is the store's.
        """
        for path in sorted(self.folder.glob("chunk-*.npz")):
            key = path.name[len("chunk-") : -len(".npz")]
            try:
                content = path.read_bytes()
            except OSError:
                continue
            digest = hashlib.sha256(content).hexdigest()
            if not self._rebuilt and self.sums.get(key) != digest:
                continue
            try:
                with np.load(io.BytesIO(content)) as data:
                    arrays = {name: data[name] for name in data.files}
            except (OSError, ValueError, zipfile.BadZipFile, EOFError):
                continue
            if str(arrays.pop("fingerprint", "")) != self.fingerprint:
                continue
            if self._rebuilt:
                self.sums[key] = digest
                self._pending = True
            yield key, arrays
