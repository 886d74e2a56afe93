"""Ensembles of acceleration time histories with labels and metadata, saved as netCDF:
:class:`Ensemble`.

Simulated ensembles (:func:`rocking.generate`) remember how they were made and can be rebuilt
(:meth:`Ensemble.regenerate`); recorded ones (:meth:`Ensemble.from_records`) name their sources.
:meth:`Ensemble.scaled` rescales all members by one factor to a chosen A_gx (mean PGA [g], paper
Section 3).
"""

from __future__ import annotations

import json
import math
from collections.abc import Sequence
from dataclasses import dataclass, field
from pathlib import Path
from typing import Final

import numpy as np
import xarray as xr

from ..core.checks import finite_array, positive
from ..core.files import atomic_write
from ..defaults import G
from ..errors import InputError
from .records import read_record
from .targets import StoredTarget

#: xarray engine for ensemble files: "scipy" writes netCDF-3 (64-bit offset) with SciPy alone.
#: netCDF-4 (engine "h5netcdf") would add h5py and HDF5 to the install for no gain here.
NETCDF_ENGINE: Final = "scipy"
#: Meta entries that hold one value per member (kept in step by :meth:`Ensemble.subset`).
PER_MEMBER = ("members", "sources", "record_dt")


def _n_samples(duration: float, dt: float) -> int:
    """Samples t = 0, dt, … up to T (a T within 1e-9·dt of a whole step counts as whole)."""
    return math.floor(duration / dt + 1e-9) + 1


@dataclass(frozen=True, eq=False)
class Ensemble:
    """An ensemble of acceleration time histories with labels and metadata.

    Parameters
    ----------
    acc : array_like, shape (n, n_t) or (n_t,)
        Accelerations [m/s²] sampled at ``dt`` from t = 0 (stored read-only, 2-D).
    dt : float
        Time step [s], > 0.
    labels : sequence of str, optional
        One name per member (default ``"m-0000"``, ``"m-0001"``, …).
    meta : dict, optional
        JSON-serialisable description: generation parameters of simulated ensembles, record
        sources of recorded ones, ``kind`` ("simulated", "recorded", …), ``location``
        ("ground" or e.g. "floor 3 of paper-2.0") and ``scale`` (factor applied since).
    """

    acc: np.ndarray
    dt: float
    labels: Sequence[str] = ()
    meta: dict = field(default_factory=dict)

    def __post_init__(self):
        acc = finite_array("acc", self.acc, ndim=(1, 2), min_len=2)
        acc = np.array(acc, ndmin=2, copy=acc is self.acc)
        acc.setflags(write=False)
        object.__setattr__(self, "acc", acc)
        object.__setattr__(self, "dt", positive("dt", self.dt, "s"))
        labels = tuple(str(s) for s in self.labels) or tuple(f"m-{i:04d}" for i in range(len(acc)))
        if len(labels) != len(acc):
            raise InputError(f"labels has {len(labels)} names for {len(acc)} members")
        object.__setattr__(self, "labels", labels)
        object.__setattr__(self, "meta", {"location": "ground", "scale": 1.0, **self.meta})

    @property
    def n(self) -> int:
        """Number of members."""
        return self.acc.shape[0]

    @property
    def n_t(self) -> int:
        """Samples per member."""
        return self.acc.shape[1]

    @property
    def t(self) -> np.ndarray:
        """Sample times [s]."""
        return np.arange(self.n_t) * self.dt

    @property
    def duration(self) -> float:
        """Time of the last sample [s]."""
        return (self.n_t - 1) * self.dt

    @property
    def pga(self) -> np.ndarray:
        """Peak ground acceleration of each member, max |a| [g], shape (n,)."""
        return np.abs(self.acc).max(axis=1) / G

    @property
    def agx(self) -> float:
        """Ensemble intensity A_gx: mean of the members' PGA [g] (paper Section 3)."""
        return float(self.pga.mean())

    @property
    def simulated(self) -> bool:
        """True for a simulated ground-motion ensemble (``kind`` "simulated" at the ground),
        which :meth:`regenerate` can rebuild from its metadata."""
        return self.meta.get("kind") == "simulated" and self.meta.get("location") == "ground"

    def __len__(self) -> int:
        return self.n

    def scaled(self, agx: float) -> Ensemble:
        """The ensemble times one factor, so that its mean PGA is ``agx`` [g] (> 0)."""
        agx = positive("agx", agx, "g")
        if self.agx == 0.0:
            raise InputError("cannot scale an ensemble of zero motions to a given agx")
        return self.scaled_by(agx / self.agx)

    def subset(self, indices) -> Ensemble:
        """The members at positions ``indices`` (ints, in the order given)."""
        idx = np.asarray(indices)
        if idx.dtype.kind not in "iu" or idx.ndim != 1:
            raise InputError("indices must be a 1-D sequence of integers")
        if idx.size and not (-self.n <= idx.min() and idx.max() < self.n):
            raise InputError(f"indices must lie in [0, {self.n}), got {idx.tolist()}")
        meta = {k: ([v[i] for i in idx] if k in PER_MEMBER else v) for k, v in self.meta.items()}
        return Ensemble(self.acc[idx], self.dt, [self.labels[i] for i in idx], meta)

    def regenerate(self, **overrides) -> Ensemble:
        """Simulate this ensemble again from its metadata (same members, phases and scale).

        ``overrides`` replace stored generation parameters of :func:`generate` (e.g.
        ``baseline=False``); changing the frequencies needs a new ``target``.
        """
        from .synthesis import _GENERATION_KEYS, _generate  # (synthesis makes Ensembles)

        if not self.simulated:
            raise InputError(
                "only simulated ground motions can be regenerated (this ensemble "
                f"is {self.meta.get('kind', 'of unknown kind')!r} at "
                f"{self.meta['location']!r})"
            )
        unknown = set(overrides) - set(_GENERATION_KEYS) - {"target"}
        if unknown:
            raise InputError(
                f"cannot override {', '.join(sorted(unknown))}: not a parameter of generate()"
            )
        m = self.meta
        # Files written before peak limiting existed were generated without it.
        params = {"peak_limit": False, **{k: m[k] for k in _GENERATION_KEYS if k in m}}
        params["target"] = StoredTarget(
            m["target"], tuple(m["freqs_hz"]), tuple(m["target_psa"]), m["damping"]
        )
        params.update(overrides)
        ens = _generate(m["members"], **params)
        return ens.scaled_by(m["scale"]) if m["scale"] != 1.0 else ens

    def target_spectrum(self) -> StoredTarget:
        """The target a simulated ensemble was fitted to, times its ``scale`` (PSA [g]); known
        at the fitted frequencies ``meta["freqs_hz"]`` [Hz] only."""
        if not self.simulated:
            raise InputError("only a simulated ground-motion ensemble has a stored target")
        m = self.meta
        scale = m["scale"]
        name = m["target"] if scale == 1.0 else f"{m['target']} × {scale:.4g}"
        return StoredTarget(
            name, tuple(m["freqs_hz"]), tuple(v * scale for v in m["target_psa"]), m["damping"]
        )

    def scaled_by(self, factor: float) -> Ensemble:
        """The ensemble with every member multiplied by ``factor`` [-] (> 0)."""
        factor = positive("factor", factor)
        meta = {**self.meta, "scale": self.meta["scale"] * factor}
        return Ensemble(self.acc * factor, self.dt, self.labels, meta)

    def save(self, path) -> Path:
        """Write the ensemble as netCDF (xarray, engine :data:`NETCDF_ENGINE`) atomically (no
        half-written file ever has the name); return the path.

        Variable ``acc`` [m/s²] on dimensions (member, time); coordinates ``member`` (labels)
        and ``time`` [s]. The metadata go to attribute ``meta_json`` as JSON (exact, read back
        by :meth:`load`) and, for other readers of the file, to plain attributes: scalars,
        numeric lists and dictionary entries as ``<key>_<entry>`` (booleans as 0/1).
        """
        path = Path(path)
        attrs = {**_flat_attrs(self.meta), "dt": self.dt, "meta_json": json.dumps(self.meta)}
        ds = xr.Dataset(
            {
                "acc": (
                    ("member", "time"),
                    self.acc,
                    {"units": "m s-2", "long_name": "ground acceleration"},
                )
            },
            coords={"member": list(self.labels), "time": ("time", self.t, {"units": "s"})},
            attrs=attrs,
        )
        atomic_write(path, bytes(ds.to_netcdf(engine=NETCDF_ENGINE)))
        return path

    @classmethod
    def load(cls, path) -> Ensemble:
        """Read an ensemble written by :meth:`save`."""
        path = Path(path)
        try:
            with xr.open_dataset(path, engine=NETCDF_ENGINE) as ds:
                acc = ds["acc"].values
                labels = [str(s) for s in ds["member"].values]
                dt = float(ds.attrs["dt"])
                meta = json.loads(ds.attrs["meta_json"])
        except KeyError as exc:
            raise InputError(f"{path}: not an ensemble file (missing {exc})") from None
        except (OSError, ValueError, TypeError) as exc:  # TypeError: SciPy's "not netCDF"
            raise InputError(
                f"{path}: not a netCDF ensemble file ({' '.join(str(exc).split()[:12])})"
            ) from None
        return cls(acc, dt, labels, meta)

    @classmethod
    def from_records(cls, records, dt: float | None = None) -> Ensemble:
        """Ensemble of real records (``rocking.motions.records.Record`` objects or file paths).

        Records at another time step than ``dt`` (default: the smallest of the records) are
        resampled by linear interpolation over their own length (downsampling this way does not
        filter: pass a ``dt`` no larger than the records' for an alias-free result). Records
        shorter than the longest are padded with zeros at the end (ground at rest). The
        records are used as given (no baseline correction).

        Parameters
        ----------
        records : sequence of Record or path
            At least one.
        dt : float, optional
            Common time step [s], > 0.
        """
        recs = [r if hasattr(r, "acc") else read_record(r) for r in records]
        if not recs:
            raise InputError("records must name at least one record")
        step = min(r.dt for r in recs) if dt is None else positive("dt", dt, "s")
        rows = []
        for r in recs:
            t_end = (len(r.acc) - 1) * r.dt
            t = np.arange(_n_samples(t_end, step)) * step
            rows.append(
                r.acc if r.dt == step else np.interp(t, np.arange(len(r.acc)) * r.dt, r.acc)
            )
        acc = np.zeros((len(rows), max(len(x) for x in rows)))
        for i, x in enumerate(rows):
            acc[i, : len(x)] = x
        meta = {
            "kind": "recorded",
            "location": "ground",
            "sources": [str(r.source) for r in recs],
            "record_dt": [r.dt for r in recs],
        }
        return cls(acc, step, [r.name for r in recs], meta)


def _flat_attrs(meta: dict) -> dict:
    """netCDF attributes for the readable entries of ``meta`` (see :meth:`Ensemble.save`)."""
    flat = {}
    for key, value in meta.items():
        entries = value.items() if isinstance(value, dict) else [("", value)]
        for sub, v in entries:
            name = f"{key}_{sub}" if sub else key
            if isinstance(v, bool):
                v = int(v)
            numeric_list = (
                isinstance(v, list)
                and v
                and all(isinstance(x, (int, float)) and not isinstance(x, bool) for x in v)
            )
            if isinstance(v, (str, int, float)) or numeric_list:
                flat[name] = v
    return flat
