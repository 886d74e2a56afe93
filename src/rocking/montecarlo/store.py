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
  loaded: its work is computed again and its file replaced.
"""

from __future__ import annotations

import hashlib
import json
import zipfile
from collections.abc import Iterator
from functools import cache
from importlib import resources
from pathlib import Path
from typing import TYPE_CHECKING, Any

import numpy as np

from ..core.files import atomic_write
from ..errors import InputError

if TYPE_CHECKING:
    from numpy.typing import ArrayLike

MANIFEST = "chunks.json"
LOCK = ".rocking.lock"
_FORMAT = "rocking-chunks-2"
#: Modules whose source decides the numbers a chunk holds.
KERNEL_MODULES = (
    "core/compile.py",
    "dynamics/equation.py",
    "dynamics/impacts.py",
    "dynamics/batch.py",
)


def fingerprint(params: dict) -> str:
    """SHA-256 of the JSON form of ``params`` (keys sorted)."""
    return hashlib.sha256(json.dumps(params, sort_keys=True).encode()).hexdigest()


@cache
def code_version() -> dict:
    """The package version and the SHA-256 of the source of the integration kernels."""
    from .. import __version__

    h = hashlib.sha256()
    for name in KERNEL_MODULES:
        h.update(resources.files("rocking").joinpath(name).read_bytes())
    return {"version": __version__, "kernel_sha256": h.hexdigest()}


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

    def __enter__(self) -> ChunkStore:
        import filelock

        try:
            self.folder.mkdir(parents=True, exist_ok=True)
        except OSError as exc:
            raise InputError(f"out: cannot create folder {self.folder} ({exc.strerror})") from None
        lock = filelock.FileLock(self.folder / LOCK, timeout=0)
        try:
            lock.acquire()
        except filelock.Timeout:
            raise InputError(
                f"out: {self.folder} is in use by another run; wait for it to end "
                "or use another folder"
            ) from None
        self._lock = lock
        try:
            self._check_manifest()
        except BaseException:
            lock.release()
            raise
        return self

    def __exit__(self, *exc) -> None:
        self._lock.release()

    def _check_manifest(self) -> None:
        digest = fingerprint(self.params)
        manifest = self.folder / MANIFEST
        if manifest.exists():
            old = self._read_manifest(manifest)
            if old.get("sha256") != digest:
                differ = sorted(
                    k
                    for k in set(self.params) | set(old.get("params", {}))
                    if self.params.get(k) != old.get("params", {}).get(k)
                )
                raise InputError(
                    f"out: {self.folder} holds results of a different run (differs in "
                    f"{', '.join(differ) or 'format'}); use another folder or empty this one"
                )
        else:
            text = json.dumps(
                {"format": _FORMAT, "sha256": digest, "params": self.params}, indent=1
            )
            atomic_write(manifest, text)

    @staticmethod
    def _read_manifest(path: Path) -> dict:
        try:
            data = json.loads(path.read_text())
        except (OSError, ValueError) as exc:
            raise InputError(f"out: cannot read {path} ({exc})") from None
        if not isinstance(data, dict) or data.get("format") != _FORMAT:
            raise InputError(
                f"out: {path} is not a chunk manifest of this version of rocking; "
                "use another folder or empty this one"
            )
        return data

    def path(self, key: str) -> Path:
        """File of chunk ``key``."""
        return self.folder / f"chunk-{key}.npz"

    def save(self, key: str, **arrays: ArrayLike) -> None:
        """Write chunk ``key`` (arrays by name) atomically, with the store's fingerprint.

        Not flushed to the disk one by one (``durable=False``; 0.5-1 ms each here, more on
        network disks, for hundreds of chunks a run): a chunk whose bytes a system crash lost
        fails the CRC-32 of its zip member or the zip's structure when :meth:`load_all` reads
        it, and is computed again."""
        atomic_write(
            self.path(key),
            # numpy's stub types savez's **kwds as its keyword allow_pickle (bool)
            lambda f: np.savez(f, fingerprint=np.array(self.fingerprint), **arrays),  # type: ignore[arg-type]
            durable=False,
        )

    def load_all(self) -> Iterator[tuple[str, dict[str, np.ndarray]]]:
        """Yield (key, dict of arrays) for every complete chunk of this run, in key order.

        A file that cannot be read (not written by :meth:`save`, e.g. copied in half) or whose
        fingerprint is not the store's is skipped: its chunk counts as missing and is computed
        again.
        """
        for path in sorted(self.folder.glob("chunk-*.npz")):
            try:
                with np.load(path) as data:
                    arrays = {name: data[name] for name in data.files}
            except (OSError, ValueError, zipfile.BadZipFile, EOFError):
                continue
            if str(arrays.pop("fingerprint", "")) != self.fingerprint:
                continue
            yield path.name[len("chunk-") : -len(".npz")], arrays
