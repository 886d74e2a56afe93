"""Ensembles of acceleration time histories with labels and metadata, saved as netCDF:
:class:`Ensemble`.

Simulated ensembles (:func:`rocking.generate`) remember how they were made and can be rebuilt
(:func:`rocking.regenerate`); recorded ones (:meth:`Ensemble.from_records`) name their sources
(file, event, station, component, original time step and units of each member).
:meth:`Ensemble.scaled` rescales all members by one factor to a chosen A_gx (mean PGA [g], paper
Section 3). A member may have a vertical component ``av`` [m/s², up positive], scaled with it.
"""

from __future__ import annotations

import io
import json
import math
import os
import re
from collections.abc import Sequence
from dataclasses import dataclass, field, replace
from functools import cached_property
from pathlib import Path
from typing import Any, Final

import numpy as np
from numpy.typing import ArrayLike

from ..core.checks import finite_array, positive
from ..core.files import atomic_write
from ..core.reuse import array_digest, digest
from ..defaults import G
from ..errors import InputError
from .records import (
    _NETCDF_MAGIC,
    MAX_DT,
    RATIO_RTOL,
    RECORD_SUFFIXES,
    RESAMPLING,
    Record,
    _refuse_shared_step,
    read_manifest,
    read_record,
    record_path,
    record_paths,
    resample,
)
from .targets import StoredTarget
from .units import MAX_PEAK_G

#: xarray engine for ensemble files: "scipy" writes netCDF-3 (64-bit offset) with SciPy alone.
#: netCDF-4 (engine "h5netcdf") would add h5py and HDF5 to the install for no gain here.
NETCDF_ENGINE: Final = "scipy"
#: Meta entries of :meth:`Ensemble.from_records` that hold one value per member, with the value
#: given to members of an ensemble file that has none (its generated motions): file, vertical
#: file, kind, header fields, original time step [s], samples, units and format, import scale
#: [-].
RECORD_ENTRIES = {
    "sources": "",
    "vertical_sources": "",
    "kinds": "",
    "events": "",
    "dates": "",
    "stations": "",
    "components": "",
    "record_dt": 0.0,
    "record_npts": 0,
    "record_units": "m/s2",
    "record_formats": "",
    "record_scale": 1.0,
}
#: Meta entries that hold one value per member (kept in step by :meth:`Ensemble.subset`).
PER_MEMBER = ("members", *RECORD_ENTRIES)
#: Suffixes of the files :meth:`Ensemble.from_records` takes from a folder: records and
#: ensemble files.
IMPORT_SUFFIXES = (*RECORD_SUFFIXES, ".nc")


#: Where motions act: the ground, or floor N (N ≥ 1) of a building, optionally "of FRAME" (as
#: :meth:`rocking.structures.frames.ShearFrame.floor_motions` names its floor ensembles).
_LOCATION = re.compile(r"(ground)|floor\s+([1-9]\d*)(?:\s+of\s+(\S.*))?", re.IGNORECASE)
#: The locations understood, for messages.
LOCATIONS_TEXT = "ground, floor N (N = 1, 2, … counted from the ground) or floor N of FRAME"


def location_name(text: str) -> str:
    """Where motions act, as written by a user, in the form the package uses: "ground",
    "floor N" or "floor N of FRAME" (N ≥ 1; any case and spacing). Anything else (e.g. "roof
    garden", "floor 0") is an InputError that lists what is understood."""
    m = _LOCATION.fullmatch(str(text).strip())
    if m is None:
        raise InputError(f"location {str(text).strip()!r} is not understood; give {LOCATIONS_TEXT}")
    if m[1]:
        return "ground"
    return f"floor {int(m[2])}" + (f" of {m[3].strip()}" if m[3] else "")


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
    av : array_like, shape (n, n_t) or (n_t,), optional
        Vertical accelerations [m/s², up positive] of the members, same shape as ``acc``
        (stored read-only, 2-D); None (default) when the motions have no vertical component.
    """

    acc: np.ndarray
    dt: float
    labels: Sequence[str] = ()
    meta: dict = field(default_factory=dict)
    av: np.ndarray | None = None

    def __post_init__(self):
        object.__setattr__(self, "acc", _read_only("acc", self.acc))
        if self.av is not None:
            av = _read_only("av", self.av)
            if av.shape != self.acc.shape:
                raise InputError(
                    f"av has shape {av.shape}, acc {self.acc.shape}: one vertical "
                    "acceleration per horizontal one, sample for sample"
                )
            object.__setattr__(self, "av", av)
        object.__setattr__(self, "dt", positive("dt", self.dt, "s"))
        n = len(self.acc)
        labels = tuple(str(s) for s in self.labels) or tuple(f"m-{i:04d}" for i in range(n))
        if len(labels) != n:
            raise InputError(f"labels has {len(labels)} names for {n} members")
        object.__setattr__(self, "labels", labels)
        object.__setattr__(self, "meta", {"location": "ground", "scale": 1.0, **self.meta})

    def __repr__(self) -> str:
        """A summary, not the arrays: e.g. ``Ensemble(20 motions, dt = 0.0025 s, 20 s,
        ground, A_gx = 1.203 g, simulated)``."""
        kind = self.meta.get("kind")
        more = (f", {kind}" if kind else "") + (", with verticals" if self.av is not None else "")
        agx = f"{self.agx:.4g} g" if self.n else "-"
        return (
            f"Ensemble({self.n} motions, dt = {self.dt:g} s, {self.duration:g} s, "
            f"{self.meta.get('location', 'ground')}, A_gx = {agx}{more})"
        )

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

    @cached_property
    def digests(self) -> tuple[str, str | None]:
        """SHA-256 of ``acc`` and of ``av`` (None without vertical motions), as
        :func:`rocking.core.reuse.array_digest` gives them.  Computed once (the arrays cannot
        change): the Monte Carlo engines name the motions by them in their chunk stores and in
        :attr:`sha256`."""
        return array_digest(self.acc), None if self.av is None else array_digest(self.av)

    @cached_property
    def sha256(self) -> str:
        """SHA-256 of the motions' contents, ``acc``, ``av`` and ``dt`` (:func:`digest` of
        :attr:`digests` and ``dt``): the Monte Carlo engines of one run share the outcomes of the
        motions by it."""
        return digest((*self.digests, self.dt))

    @cached_property
    def pga(self) -> np.ndarray:
        """Peak ground acceleration of each member, max abs(a) [g], shape (n,), read-only.

        Computed once (``acc`` cannot change): the engine asks for it, through :attr:`agx`,
        in every Monte Carlo call."""
        pga = np.abs(self.acc).max(axis=1) / G
        pga.setflags(write=False)
        return pga

    @property
    def agx(self) -> float:
        """Ensemble intensity A_gx: mean of the members' PGA [g] (paper Section 3).

        An ensemble whose every member is zero has none (InputError, naming the members): it
        cannot be scaled to a level."""
        if not self.pga.any():
            raise InputError(
                f"every member of the ensemble is zero ({_listed(self.labels)}): it has no "
                "A_gx and cannot be scaled to a level"
            )
        return float(self.pga.mean())

    @property
    def simulated(self) -> bool:
        """True for a simulated ground-motion ensemble (``kind`` "simulated" at the ground),
        which :func:`rocking.regenerate` can rebuild from its metadata."""
        return self.meta.get("kind") == "simulated" and self.meta.get("location") == "ground"

    def __len__(self) -> int:
        return self.n

    def scaled(self, agx: float) -> Ensemble:
        """The ensemble times one factor, so that its mean PGA is ``agx`` [g] (> 0)."""
        agx = positive("agx", agx, "g")
        return self.scaled_by(agx / self.agx)

    def subset(self, indices: ArrayLike) -> Ensemble:
        """The members at positions ``indices`` (ints, in the order given)."""
        idx = np.asarray(indices)
        if idx.dtype.kind not in "iu" or idx.ndim != 1:
            raise InputError("indices must be a 1-D sequence of integers")
        if idx.size and not (-self.n <= idx.min() and idx.max() < self.n):
            raise InputError(f"indices must lie in [0, {self.n}), got {idx.tolist()}")
        meta = {k: ([v[i] for i in idx] if k in PER_MEMBER else v) for k, v in self.meta.items()}
        av = None if self.av is None else self.av[idx]
        return Ensemble(self.acc[idx], self.dt, [self.labels[i] for i in idx], meta, av)

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
        """The ensemble with every member multiplied by ``factor`` [-] (> 0), its vertical
        component too (the components of a record are scaled together)."""
        factor = positive("factor", factor)
        meta = {**self.meta, "scale": self.meta["scale"] * factor}
        av = None if self.av is None else self.av * factor
        return Ensemble(self.acc * factor, self.dt, self.labels, meta, av)

    def save(self, path: str | os.PathLike[str]) -> Path:
        """Write the ensemble as a netCDF-3 file atomically (no half-written file ever has the
        name); return the path.

        Variable ``acc`` [m/s²] on dimensions (member, time), and ``av`` [m/s², up positive]
        when the ensemble has vertical components; coordinates ``member`` (labels, UTF-8
        characters) and ``time`` [s]. The metadata go to attribute ``meta_json`` as JSON (exact,
        read back by :meth:`load`) and, for other readers of the file, to plain attributes:
        scalars, numeric lists and dictionary entries as ``<key>_<entry>`` (booleans as 0/1).
        The layout is the one xarray gives such a Dataset (``xarray.open_dataset`` reads it);
        it is written with :class:`scipy.io.netcdf_file` directly, which spares every command
        that writes or reads motions the import of xarray and of the Dask modules xarray looks
        for.
        """
        atomic_write(path, self._netcdf_bytes())
        return Path(path)

    def _netcdf_bytes(self) -> bytes:
        from scipy.io import netcdf_file

        labels = [str(x).encode("utf-8") for x in self.labels]
        width = max(1, *(len(x) for x in labels))
        buf = io.BytesIO()
        nc = netcdf_file(buf, "w", version=2)
        nc.createDimension("member", len(labels))
        nc.createDimension("time", self.n_t)
        nc.createDimension(f"string{width}", width)
        _netcdf_variable(nc, "time", ("time",), self.t, {"units": "s"})
        _netcdf_variable(
            nc, "acc", ("member", "time"), self.acc, {"units": "m s-2", "long_name": _ACC_NAME}
        )
        if self.av is not None:
            _netcdf_variable(
                nc, "av", ("member", "time"), self.av, {"units": "m s-2", "long_name": _AV_NAME}
            )
        member = nc.createVariable("member", "c", ("member", f"string{width}"))
        chars = b"".join(x.ljust(width, b"\0") for x in labels)
        member[:] = np.frombuffer(chars, dtype="S1").reshape(len(labels), width)
        member._Encoding = "utf-8"
        attrs = {**_flat_attrs(self.meta), "dt": self.dt, "meta_json": json.dumps(self.meta)}
        for key, value in attrs.items():
            setattr(nc, key, _netcdf_attr(value))
        nc.flush()
        data = buf.getvalue()
        nc.close()
        return data

    @classmethod
    def load(cls, path: str | os.PathLike[str]) -> Ensemble:
        """Read an ensemble written by :meth:`save`.

        Refused, naming the file: a file that is no such ensemble; attribute ``dt`` that
        disagrees with the step of the time axis (to :data:`~rocking.motions.records.RATIO_RTOL`);
        a non-finite sample; a member that is zero everywhere; a member whose peak exceeds
        :data:`~rocking.motions.units.MAX_PEAK_G` (certainly other units than m/s²).
        """
        from scipy.io import netcdf_file

        path = Path(path)
        try:
            with netcdf_file(path, "r", mmap=False) as nc:
                time = np.array(nc.variables["time"][:], dtype=np.float64)
                acc = np.array(nc.variables["acc"][:], dtype=np.float64)
                av = (
                    np.array(nc.variables["av"][:], dtype=np.float64)
                    if "av" in nc.variables
                    else None
                )
                chars = np.asarray(nc.variables["member"][:]).reshape(acc.shape[0], -1)
                labels = [b"".join(row).rstrip(b"\0").decode("utf-8") for row in chars]
                dt = float(nc._attributes["dt"])
                meta = json.loads(_text(nc._attributes["meta_json"]))
        except KeyError as exc:
            raise InputError(f"{path}: not an ensemble file (missing {exc})") from None
        except (OSError, ValueError, TypeError) as exc:  # TypeError: SciPy's "not netCDF"
            raise InputError(
                f"{path}: not a netCDF ensemble file ({' '.join(str(exc).split()[:12])})"
            ) from None
        if time.size >= 2:
            step = float(time[-1] - time[0]) / (time.size - 1)
            if not math.isclose(step, dt, rel_tol=RATIO_RTOL):
                raise InputError(
                    f"{path}: its attribute dt = {dt:g} s disagrees with its time axis, whose "
                    f"step is {step:g} s; the file is inconsistent (written by another program?)"
                )
        try:
            ens = cls(acc, dt, labels, meta, av)
        except InputError as exc:
            raise InputError(f"{path}: {exc}") from None
        ens._check_motions(str(path))
        return ens

    def _check_motions(self, where: str = "ensemble") -> None:
        """Refuse (InputError starting with ``where``) members that are zero everywhere (no
        motion: it has no A_gx, and scaled with the others it never moves), or whose
        horizontal or vertical peak exceeds :data:`~rocking.motions.units.MAX_PEAK_G` [g]
        (certainly not an acceleration in m/s²)."""
        zero = [label for label, p in zip(self.labels, self.pga) if p == 0.0]
        if zero:
            every = "every member is" if len(zero) == self.n else f"{len(zero)} member(s) are"
            raise InputError(f"{where}: {every} zero everywhere ({_listed(zero)}): no motion")
        peaks = self.pga if self.av is None else np.maximum(self.pga, np.abs(self.av).max(1) / G)
        huge = np.flatnonzero(peaks > MAX_PEAK_G)
        if huge.size:
            i = huge[0]
            raise InputError(
                f"{where}: member {self.labels[i]} peaks at {peaks[i]:.4g} g, above "
                f"{MAX_PEAK_G:g} g: certainly not a ground or floor acceleration "
                f"({huge.size} such member(s))"
            )

    @classmethod
    def from_records(
        cls,
        records: Sequence[Record | Ensemble | str | Path] = (),
        dt: float | None = None,
        *,
        vertical: Sequence[Record | str | Path | None] | None = None,
        scale: float | Sequence[float] | None = None,
        units: str | None = None,
        calibration: float | None = None,
        manifest: str | Path | None = None,
        location: str = "ground",
        record_dt: float | None = None,
        horizontal_only: bool = False,
    ) -> Ensemble:
        """Ensemble of recorded motions: record files, folders of them, ensemble files and a
        manifest (``rocking motions import`` on the command line).

        Every member is used as recorded (no baseline correction). Members at another time
        step than ``dt`` are resampled to it with :func:`rocking.motions.records.resample`
        (:func:`scipy.signal.resample_poly`, a Kaiser-window FIR anti-alias filter; meta
        ``resampling`` says so). Without ``dt`` the members must share one step: records at
        different steps are refused with a message listing them, so that choosing the step
        (and the cost of the simulations, which grows with 1/dt) stays the user's decision.
        Members shorter than the longest are padded with zeros at the end (the ground at
        rest; meta ``record_npts`` keeps each one's own length).

        Parameters
        ----------
        records : sequence of Record, Ensemble, str or Path
            Records (:class:`~rocking.motions.records.Record`), record files (PEER .AT2, text
            or CSV, see :func:`~rocking.motions.records.read_record`), folders (their .AT2,
            .txt, .csv and .nc files sorted by name), ensembles or ensemble files (.nc, written
            by :meth:`save`: their members are appended, with their vertical components and
            metadata). The word ``example`` stands for the shipped record.
        dt : float, optional
            Common time step [s], > 0 and at most :data:`~rocking.motions.records.MAX_DT`
            (0.05 s).
        vertical : sequence of Record, str, Path or None, optional
            One per entry of ``records``: the vertical record [up positive] of the same motion,
            or None. Members without one get a zero vertical acceleration when others have one.
        scale : float or sequence of float, optional
            Factor [-] (> 0) applied to both components: one for all or one per entry of
            ``records`` (default 1).
        units : str, optional
            Units of the values in record files that state none (g, m/s2, cm/s2 or gal,
            mm/s2, in/s2, ft/s2; :func:`~rocking.motions.records.read_record`): a file that
            states other units is refused. Required for SAC and miniSEED files.
        calibration : float, optional
            ``units`` per count of SAC and miniSEED files (default 1;
            :func:`~rocking.motions.records.read_record`).
        manifest : str or Path, optional
            A CSV with one row per motion (columns ``horizontal``, ``vertical``, ``scale``,
            ``dt``;
            :func:`~rocking.motions.records.read_manifest`), its members after ``records``.
            Errors in its records name the row.
        location : str, optional
            Where the motions act: "ground" (default), "floor N" (e.g. "floor 3" for floor
            acceleration histories exported from a structural model) or "floor N of FRAME"
            (:func:`location_name`; meta ``location``). Appended ensembles must be at the same
            location.
        record_dt : float, optional
            Time step [s] of a one-column text file (which does not state it); checked against
            the step of the others. It gives the step of one such file only: several are
            refused (their rates may differ) unless each has its own in a manifest's ``dt``
            column.
        horizontal_only : bool, optional
            Drop every vertical component (given, in the manifest or in appended ensembles):
            e.g. for an IDA that scales records far enough that their verticals would reach −g.

        Returns
        -------
        Ensemble
            ``meta``: ``kind`` ("recorded", or "mixed" when generated members were appended),
            ``location``, ``resampling`` (method and filter, or method "none" when no
            component was resampled), ``padding``, and per member (in step with the members
            through :meth:`subset`): ``sources`` and ``vertical_sources`` (files), ``kinds``,
            ``events``, ``dates``, ``stations``, ``components``, ``record_dt`` [s],
            ``record_npts``, ``record_units`` and ``record_formats`` (of the horizontal record:
            "PEER", "K-NET", "ESM", …, :attr:`~rocking.motions.records.Record.format`) and
            ``record_scale`` [-]. Labels are the file names without suffix (a repeated label
            gets "-2", "-3", …).
        """
        location = location_name(location)
        read = {
            "units": units,
            "calibration": calibration,
            "dt": None if record_dt is None else positive("record_dt", record_dt, "s"),
        }
        members = _members(records, vertical, scale, read, location)
        if manifest is not None:
            members += _manifest_members(Path(manifest), read)
        if not members:
            raise InputError("no motions: give records (files, folders, ensembles) or a manifest")
        if horizontal_only:
            members = [
                replace(m, v=None, dt_v=m.dt_h, info={**m.info, "vertical_sources": ""})
                for m in members
            ]
        shared = [m.label for m in members if m.shared_step]
        if len(shared) > 1 and record_dt is not None:
            remedy = "give each its own step: list them in a manifest with a dt column"
            _refuse_shared_step(shared, record_dt, remedy)
        step = _common_step(members) if dt is None else positive("dt", dt, "s")
        if step > MAX_DT:
            given = f"dt = {step:g} s" if dt is not None else f"the records' step {step:g} s"
            raise InputError(
                f"{given} is coarser than {MAX_DT:g} s: motions must carry frequencies up to "
                f"{0.5 / MAX_DT:g} Hz (the Nyquist frequency of {MAX_DT:g} s), the amplified "
                "region of design spectra (to 9 Hz, RG 1.60's point B) that sets their peaks "
                "and A_gx"
            )
        rows_h = [_resampled(m.h, m.dt_h, step, m) for m in members]
        rows_v = [None if m.v is None else _resampled(m.v, m.dt_v, step, m) for m in members]
        n_t = max(len(x) for x in rows_h + rows_v if x is not None)
        acc = np.zeros((len(members), n_t))
        av = None if all(x is None for x in rows_v) else np.zeros((len(members), n_t))
        for i, (m, h, v) in enumerate(zip(members, rows_h, rows_v)):
            acc[i, : len(h)] = h * m.scale
            if v is not None and av is not None:
                av[i, : len(v)] = v * m.scale
        entries = {key: [m.info[key] for m in members] for key in RECORD_ENTRIES}
        own_steps = [*entries["record_dt"], *(m.dt_v for m in members)]
        resampled = any(not math.isclose(d, step, rel_tol=RATIO_RTOL) for d in own_steps)
        meta = {
            "kind": "recorded" if set(entries["kinds"]) == {"recorded"} else "mixed",
            "location": location,
            "resampling": ({"dt": step, **RESAMPLING} if resampled else {"method": "none"}),
            "padding": "zeros at the end, to the longest member",
            **entries,
        }
        ens = cls(acc, step, _unique([m.label for m in members]), meta, av)
        ens._check_motions("the records")
        return ens


@dataclass(frozen=True)
class _Member:
    """One motion on its way into :meth:`Ensemble.from_records`: horizontal and vertical
    accelerations [m/s²] at their own steps [s], the factor still to apply, its label and its
    per-member metadata (:data:`RECORD_ENTRIES`)."""

    h: np.ndarray
    dt_h: float
    v: np.ndarray | None
    dt_v: float
    scale: float
    label: str
    info: dict
    shared_step: bool = False


def _record_member(h: Record, v: Record | None, scale: float, shared: bool = False) -> _Member:
    """``shared``: the records were read with the ``record_dt`` of every one-column file."""
    info = {
        **RECORD_ENTRIES,
        "sources": h.source,
        "vertical_sources": "" if v is None else v.source,
        "kinds": "recorded",
        "events": h.event,
        "dates": h.date,
        "stations": h.station,
        "components": h.component,
        "record_dt": h.dt,
        "record_npts": int(h.acc.size),
        "record_units": h.units,
        "record_formats": h.format,
        "record_scale": scale,
    }
    dt_v = h.dt if v is None else v.dt
    v_acc = None if v is None else v.acc
    return _Member(h.acc, h.dt, v_acc, dt_v, scale, h.name, info, shared and h.dt_given)


def _ensemble_members(ens: Ensemble, source: str, scale: float, location: str) -> list[_Member]:
    """The members of an ensemble appended by :meth:`Ensemble.from_records` (from the file
    ``source``), with their stored per-member metadata or, for generated members, defaults."""
    if ens.meta["location"] != location:
        raise InputError(
            f"{source or 'ensemble'}: its motions are at {ens.meta['location']!r}, not at "
            f"{location!r} (location)"
        )
    defaults = {
        **RECORD_ENTRIES,
        "sources": source,
        "kinds": ens.meta.get("kind", ""),
        "record_dt": ens.dt,
        "record_npts": ens.n_t,
    }
    stored: dict[str, list] = {}
    for key, value in defaults.items():
        given = ens.meta.get(key)
        stored[key] = given if isinstance(given, list) and len(given) == ens.n else [value] * ens.n
    factor = ens.meta["scale"] * scale
    return [
        _Member(
            ens.acc[i],
            ens.dt,
            None if ens.av is None else ens.av[i],
            ens.dt,
            scale,
            ens.labels[i],
            {
                **{key: stored[key][i] for key in RECORD_ENTRIES},
                "record_scale": stored["record_scale"][i] * factor,
            },
        )
        for i in range(ens.n)
    ]


def _per_entry(name: str, values, n: int, default) -> list:
    """``values`` as one value per entry of ``records`` (a scalar repeated)."""
    if values is None or isinstance(values, (int, float, str, Path, Record)):
        return [default if values is None else values] * n
    values = list(values)
    if len(values) != n:
        raise InputError(f"{name} has {len(values)} entries for {n} entries of records")
    return values


def _members(records, vertical, scale, read: dict, location: str) -> list[_Member]:
    """The motions of the ``records`` argument of :meth:`Ensemble.from_records`."""
    if isinstance(records, (str, Path, Record, Ensemble)):
        records = [records]
    records = list(records)
    verticals = _per_entry("vertical", vertical, len(records), None)
    scales = [positive("scale", f) for f in _per_entry("scale", scale, len(records), 1.0)]
    out: list[_Member] = []
    for entry, v, f in zip(records, verticals, scales):
        if isinstance(entry, (Ensemble, Record)):
            items: list[tuple[Ensemble | Record, str]] = [(entry, "")]
        else:
            items = [(_read_path(p, read), str(p)) for p in _import_paths(entry)]
        if v is not None and (len(items) != 1 or isinstance(items[0][0], Ensemble)):
            raise InputError(f"{entry}: a vertical record goes with one horizontal record")
        for item, source in items:
            if isinstance(item, Ensemble):
                out += _ensemble_members(item, source, f, location)
            else:
                vert = None if v is None else _read_one(v, read)
                out.append(_record_member(item, vert, f, shared=bool(source)))
    return out


def _import_paths(entry: str | Path) -> list[Path]:
    """The files of one path argument: itself, a folder's records and ensemble files, or the
    shipped record for ``example``."""
    paths = record_paths(entry, IMPORT_SUFFIXES)
    for p in paths:
        if not p.exists():
            raise InputError(f"{p}: no such file or folder")
    return paths


def _is_netcdf(path: Path) -> bool:
    with path.open("rb") as f:
        return f.read(8).startswith(_NETCDF_MAGIC)


def _read_path(path: Path, read: dict) -> Ensemble | Record:
    """An ensemble file or a record file."""
    return Ensemble.load(path) if _is_netcdf(path) else read_record(path, **read)


def _read_one(spec: Record | str | Path, read: dict) -> Record:
    """A vertical record given to :meth:`Ensemble.from_records`."""
    if isinstance(spec, Record):
        return spec
    path = record_path(spec)
    if not path.is_file():
        raise InputError(f"vertical record {path}: no such file")
    return read_record(path, **read)


def _manifest_members(manifest: Path, read: dict) -> list[_Member]:
    """The motions of a manifest; errors name its row."""
    out = []
    for row in read_manifest(manifest):
        own = read if row.dt is None else {**read, "dt": row.dt}
        try:
            h = read_record(row.horizontal, **own)
            v = None if row.vertical is None else read_record(row.vertical, **own)
        except InputError as exc:
            raise InputError(f"{manifest}: row {row.row} (line {row.line}): {exc}") from None
        out.append(_record_member(h, v, row.scale, shared=row.dt is None))
    return out


def _common_step(members: list[_Member]) -> float:
    """The one time step [s] of every component, or an InputError listing the steps."""
    steps: dict[float, list[str]] = {}
    for m in members:
        for d in (m.dt_h, m.dt_v):
            known = next((s for s in steps if math.isclose(s, d, rel_tol=RATIO_RTOL)), d)
            names = steps.setdefault(known, [])
            if m.label not in names:
                names.append(m.label)
    if len(steps) == 1:
        return next(iter(steps))
    listed = "; ".join(
        f"{d:g} s: {', '.join(names[:3])}{', …' if len(names) > 3 else ''}"
        for d, names in sorted(steps.items())
    )
    raise InputError(
        f"the records have different time steps ({listed}); give the common step dt [s] "
        f"(--dt), e.g. {min(steps):g} to upsample all without loss"
    )


def _resampled(x: np.ndarray, dt: float, step: float, member: _Member) -> np.ndarray:
    """One component of ``member`` at ``step`` [s]; errors name the member."""
    try:
        return resample(x, dt, step)
    except InputError as exc:
        raise InputError(f"{member.info['sources'] or member.label}: {exc}") from None


def _listed(labels: Sequence[str], most: int = 3) -> str:
    """The first ``most`` labels, then how many more."""
    more = f" and {len(labels) - most} more" if len(labels) > most else ""
    return ", ".join(labels[:most]) + more


def _unique(labels: list[str]) -> tuple[str, ...]:
    """``labels`` with repeated ones numbered: a, a → a, a-2."""
    seen: set[str] = set()
    out = []
    for label in labels:
        name, k = label, 1
        while name in seen:
            k += 1
            name = f"{label}-{k}"
        seen.add(name)
        out.append(name)
    return tuple(out)


def _read_only(name: str, values) -> np.ndarray:
    """``values`` as a finite 2-D float array that cannot be written (a copy unless it is one
    already)."""
    a = finite_array(name, values, ndim=(1, 2), min_len=2)
    a = np.array(a, ndmin=2, copy=a is values)
    a.setflags(write=False)
    return a


_ACC_NAME = "ground acceleration"
_AV_NAME = "vertical ground acceleration, up positive"


def _netcdf_variable(nc: Any, name: str, dims: tuple[str, ...], values: np.ndarray, attrs: dict):
    """A float64 variable of ``nc`` with ``attrs`` and a NaN fill value (as xarray writes it)."""
    var = nc.createVariable(name, "d", dims)
    var[:] = values
    var._FillValue = np.float64(np.nan)
    for key, value in attrs.items():
        setattr(var, key, value)


def _netcdf_attr(value: Any) -> Any:
    """An attribute as netCDF-3 stores it: int32 for integers (no 64-bit integers), float64 for
    floats, arrays for numeric lists, text as it is."""
    if isinstance(value, list):
        arr = np.asarray(value)
        return arr.astype(np.int32) if arr.dtype.kind in "iu" else arr.astype(np.float64)
    if isinstance(value, int):
        return np.int32(value)
    if isinstance(value, float):
        return np.float64(value)
    return value


def _text(value: Any) -> str:
    """A text attribute as read by scipy.io.netcdf_file (bytes) as str."""
    return value.decode("utf-8") if isinstance(value, bytes) else str(value)


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
