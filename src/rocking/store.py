"""Resumable on-disk store of finished chunks of a Monte Carlo run (issue 5, part 5).

A run writes each chunk of results as soon as it is finished into its output folder, as one
``chunk-<key>.npz`` file, atomically: the arrays go to a temporary file in the same folder, which is
flushed to disk and then renamed over the final name with :func:`os.replace`.  A process killed at
any instant (kill -9) therefore leaves only complete chunk files (plus, at worst, a stray
temporary file that is ignored).  Writing the same chunk twice (a Dask task run again after a worker
died) replaces a file with an identical one.

The folder's ``chunks.json`` manifest records what the chunks were computed from (bodies, motions,
restitution, …: whatever the caller passes as ``params``) and its SHA-256.  Opening the folder with
different parameters raises :class:`~rocking.errors.InputError` naming the differences, so results
of two different runs are never mixed.
"""

from __future__ import annotations

import hashlib
import json
import os
import zipfile
from pathlib import Path

import numpy as np

from .errors import InputError

MANIFEST = "chunks.json"
_FORMAT = "rocking-chunks-1"


def fingerprint(params: dict) -> str:
    """SHA-256 of the JSON form of ``params`` (keys sorted)."""
    return hashlib.sha256(json.dumps(params, sort_keys=True).encode()).hexdigest()


def array_digest(a: np.ndarray) -> str:
    """SHA-256 of an array's dtype, shape and bytes (to name large inputs in ``params``)."""
    a = np.ascontiguousarray(a)
    h = hashlib.sha256(f"{a.dtype.str}{a.shape}".encode())
    h.update(a.data)
    return h.hexdigest()


def _atomic_write(path: Path, write) -> None:
    """Call ``write(file)`` on a temporary file beside ``path``, then rename it to ``path``."""
    tmp = path.with_name(f".{path.name}.{os.getpid()}.tmp")
    try:
        with open(tmp, "wb") as f:
            write(f)
            f.flush()
            os.fsync(f.fileno())
        os.replace(tmp, path)
    finally:
        if tmp.exists():
            tmp.unlink()


class ChunkStore:
    """Folder of finished chunks of one run.

    Parameters
    ----------
    folder : str or Path
        Output folder (created if missing).
    params : dict
        JSON-serialisable description of everything the chunk results depend on.

    Raises
    ------
    InputError
        If the folder cannot be created or already holds chunks of a run with other parameters.
    """

    def __init__(self, folder, params: dict):
        self.folder = Path(folder)
        try:
            self.folder.mkdir(parents=True, exist_ok=True)
        except OSError as exc:
            raise InputError(f"out: cannot create folder {self.folder} ({exc.strerror})") from None
        digest = fingerprint(params)
        manifest = self.folder / MANIFEST
        if manifest.exists():
            old = self._read_manifest(manifest)
            if old.get("sha256") != digest:
                differ = sorted(k for k in set(params) | set(old.get("params", {}))
                                if params.get(k) != old.get("params", {}).get(k))
                raise InputError(
                    f"out: {self.folder} holds results of a different run (differs in "
                    f"{', '.join(differ) or 'format'}); use another folder or empty this one")
        else:
            text = json.dumps({"format": _FORMAT, "sha256": digest, "params": params}, indent=1)
            _atomic_write(manifest, lambda f: f.write(text.encode()))

    @staticmethod
    def _read_manifest(path: Path) -> dict:
        try:
            data = json.loads(path.read_text())
        except (OSError, ValueError) as exc:
            raise InputError(f"out: cannot read {path} ({exc})") from None
        if not isinstance(data, dict) or data.get("format") != _FORMAT:
            raise InputError(f"out: {path} is not a rocking chunk manifest")
        return data

    def path(self, key: str) -> Path:
        """File of chunk ``key``."""
        return self.folder / f"chunk-{key}.npz"

    def save(self, key: str, **arrays) -> None:
        """Write chunk ``key`` (arrays by name) atomically."""
        _atomic_write(self.path(key), lambda f: np.savez(f, **arrays))

    def load_all(self):
        """Yield (key, dict of arrays) for every complete chunk in the folder, in key order.

        A file that cannot be read (not written by :meth:`save`, e.g. copied in half) is skipped:
        its chunk counts as missing and is computed again.
        """
        for path in sorted(self.folder.glob("chunk-*.npz")):
            try:
                with np.load(path) as data:
                    arrays = {name: data[name] for name in data.files}
            except (OSError, ValueError, zipfile.BadZipFile, EOFError):
                continue
            yield path.name[len("chunk-"):-len(".npz")], arrays
