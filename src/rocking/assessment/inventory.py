"""Inventories of free-standing equipment: what stands where, read from CSV or TOML.

An item is a rigid rectangular block (height and width [m], or R [m] and γ [-]) standing on the
ground or on floor N of a shear frame, with an optional coefficient of restitution e [-] and
friction coefficients μ (static) and μ_k (kinetic) [-].

CSV (header row, then one item per row; header names are case-insensitive and may carry a unit in
brackets, e.g. ``height [m]``; blank lines and lines starting with ``#`` are skipped; other
columns, e.g. notes, are ignored; a column given twice, e.g. ``h`` and ``height``, is an error)::

    name,height,width,location,frame,mu
    battery rack,2.2,0.6,floor 3,paper-2.0,0.35
    statue,1.8,0.45,ground,,

Columns: ``name``; ``height`` and ``width`` [m], or ``R`` [m] and ``gamma`` [-], or, for equipment
whose mass is not uniform, ``h_cg`` (height of the centre of mass), ``b`` (horizontal distance
from the centre of mass to each pivot edge) and ``r_g`` (radius of gyration about the centre of
mass), all [m] (:meth:`rocking.Block.from_mass_properties`); ``location``:
``ground`` or ``floor N`` (N = 1 … number of stories; ``floor 0`` is read as the ground, with a
warning); ``frame``
(optional): a preset (``paper-2.0`` …), a frame defined in a TOML inventory, or a frame TOML file
(relative to the inventory; see :meth:`rocking.structures.frames.ShearFrame.from_toml`); empty: the
default
frame. ``e`` (optional): a number in (0, 1] or ``housner`` (1 − 1.5·sin²α); empty: 0.925, the
paper's value. ``mu`` (optional): the static friction coefficient μ_s > 0 between the base and
the floor; empty: infinite friction (the item rocks but never slides, the paper's model).
``mu_k`` (optional): the kinetic friction coefficient, 0 < μ_k ≤ μ_s; empty: μ_s. With μ the
item may rest, slide, rock, slide-rock and fly (issue 45, :mod:`rocking.dynamics.modes`).

TOML: the same fields in ``[[items]]`` tables, an optional top-level ``frame = "NAME"`` (the
default frame) and frames defined in ``[frames.NAME]`` tables with the keys of a frame TOML file
(``masses_kg`` + ``stiffnesses_N_per_m``, or ``weights_kN_per_g`` + ``stiffness_kN_per_cm``;
optional ``damping``).

Rows are numbered as in a spreadsheet (the header is row 1); TOML items as ``item N``. Every
malformed row is reported, all of them in one :class:`rocking.errors.InputError`.
"""

from __future__ import annotations

import csv
import os
import re
import warnings
from collections.abc import Iterator
from dataclasses import dataclass
from pathlib import Path

from ..core.checks import kinetic_friction, positive, read_toml
from ..defaults import DEFAULT_E
from ..dynamics.body import Block, resolve_e
from ..errors import InputError
from ..structures.frames import PRESETS, ShearFrame

_FIELDS = (
    *("name", "height", "width", "r", "gamma", "h_cg", "b", "r_g"),
    *("location", "frame", "e", "mu", "mu_k"),
)
_ALIASES = {
    "h": "height",
    "b": "width",
    "slenderness": "gamma",
    "friction": "mu",
    "restitution": "e",
}


class _NoFrame(InputError):
    """An item on a floor without a frame (the way out follows the list of rows, once)."""


_LOCATION = re.compile(r"\s*(?:(ground)|floor\s*(\d+))\s*", re.IGNORECASE)


@dataclass(frozen=True)
class Item:
    """One item of an inventory.

    Attributes
    ----------
    name : str
        Unique name.
    block : Block
        Geometry (R [m], γ [-]).
    floor : int
        0 for the ground, else the floor of ``frame`` (1 … n_stories).
    frame : ShearFrame or None
        The building (None on the ground).
    e : float
        Coefficient of restitution [-].
    mu : float or None
        Static friction coefficient μ_s [-] (None: not given, infinite friction).
    mu_k : float or None
        Kinetic friction coefficient μ_k ≤ μ_s [-] (None: μ_s).
    source : str
        File and row it came from.
    """

    name: str
    block: Block
    floor: int
    frame: ShearFrame | None
    e: float
    mu: float | None
    source: str
    mu_k: float | None = None

    @property
    def location(self) -> str:
        """ "ground" or "floor N of FRAME" (as a floor ensemble's ``meta["location"]``)."""
        if self.floor == 0 or self.frame is None:  # (an item on a floor always has its frame)
            return "ground"
        return f"floor {self.floor} of {self.frame.name}"


@dataclass(frozen=True)
class Inventory:
    """Items read by :func:`read_inventory` (in file order) and the file they came from."""

    items: tuple[Item, ...]
    path: Path | None = None

    def __len__(self) -> int:
        return len(self.items)

    def __iter__(self) -> Iterator[Item]:
        return iter(self.items)


class _Frames:
    """Resolves frame names of one inventory: its own frames, presets, then frame TOML files."""

    def __init__(self, defined: dict, base_dir: Path):
        self.defined = dict(defined)
        self.base_dir = base_dir
        self.files: dict[str, ShearFrame] = {}

    def get(self, name: str) -> ShearFrame:
        if name in self.defined:
            return self.defined[name]
        if name in PRESETS:
            return ShearFrame.preset(name)
        path = Path(name) if Path(name).is_absolute() else self.base_dir / name
        if name.lower().endswith(".toml") and path.is_file():
            if name not in self.files:
                self.files[name] = ShearFrame.from_toml(path)
            return self.files[name]
        known = [*self.defined, *PRESETS]
        raise InputError(
            f"unknown frame {name!r} (known: {', '.join(known)}, or a frame TOML file)"
        )


def read_inventory(
    path: str | os.PathLike[str], *, frame: str | ShearFrame | None = None
) -> Inventory:
    """Read an inventory from a CSV or TOML file (see the module notes for the format).

    Parameters
    ----------
    path : str or Path
        ``.toml`` file, or CSV (any other suffix).
    frame : str or ShearFrame, optional
        Default frame of ``floor N`` items without a frame of their own (a preset name, a frame
        defined in the file or a frame TOML file); overrides a TOML file's ``frame`` key.

    Returns
    -------
    Inventory

    Raises
    ------
    InputError
        Naming the file and every malformed row (missing field, text where a number belongs,
        non-positive size, unknown floor or frame, repeated name, μ_k without μ or above it).
    """
    path = Path(path)
    if not path.is_file():
        raise InputError(f"{path}: no such inventory file")
    if path.suffix.lower() == ".toml":
        rows, defined, default = _toml_rows(path)
    else:
        rows, defined, default = _csv_rows(path), {}, None
    frames = _Frames(defined, path.parent)
    named = frame if frame is not None else default
    default_frame = (
        _frame_or_error(frames, named, f"{path}: default frame")
        if isinstance(named, str)
        else named
    )
    items: list[Item] = []
    errors: list[str] = []
    seen: dict[str, str] = {}
    no_frame = False
    for where, fields in rows:
        try:
            item = _item(fields, f"{path}: {where}", frames, default_frame)
            if item.name in seen:
                raise InputError(f"name {item.name!r} repeats that of {seen[item.name]}")
            seen[item.name] = where
            items.append(item)
        except InputError as exc:
            no_frame = no_frame or isinstance(exc, _NoFrame)
            msg = str(exc).removeprefix(f"{path}: ")  # the file is named once, below
            errors.append(msg if msg.startswith(where) else f"{where}: {msg}")
    if errors:
        n = len(errors)
        s = "" if n == 1 else "s"
        if no_frame:  # the way out, said once
            errors.append(
                "an item on a floor needs a frame: fill the frame column or give a default "
                "frame (--frame NAME on the command line, frame= in Python)"
            )
        raise InputError(f"{n} malformed item{s} in {path}:\n" + ";\n".join(errors))
    if not items:
        raise InputError(f"{path}: no items")
    _check_frame_names(items, path)
    return Inventory(tuple(items), path)


def _frame_or_error(frames: _Frames, name: str, where: str) -> ShearFrame:
    try:
        return frames.get(name)
    except InputError as exc:
        raise type(exc)(f"{where}: {exc}") from None


def _check_frame_names(items: list[Item], path: Path) -> None:
    by_name: dict[str, ShearFrame] = {}
    for it in items:
        if it.frame is not None and by_name.setdefault(it.frame.name, it.frame) != it.frame:
            raise InputError(
                f"{path}: two different frames are named {it.frame.name!r}; give "
                "them distinct names"
            )


def _key(header: str) -> str:
    """Normalised column name: lower case, unit in brackets dropped, aliases resolved."""
    h = re.sub(r"[\[(].*?[\])]", "", str(header)).strip().lower()
    return _ALIASES.get(h, h)


def _keys(headers) -> list[str]:
    """:func:`_key` of every header; beside ``h_cg``, ``b`` is the distance from the centre of
    mass to the pivot edge (a general body), not the width."""
    plain = [re.sub(r"[\[(].*?[\])]", "", str(h)).strip().lower() for h in headers]
    general = "h_cg" in plain
    return ["b" if general and p == "b" else _key(h) for p, h in zip(plain, headers)]


def _repeated(keys: list[str]) -> str | None:
    """The first field of :data:`_FIELDS` that ``keys`` name twice (e.g. ``h`` and ``height``),
    or None."""
    fields = [k for k in keys if k in _FIELDS]
    return next((k for i, k in enumerate(fields) if k in fields[:i]), None)


def _csv_rows(path: Path) -> list[tuple[str, dict]]:
    try:
        with open(path, newline="", encoding="utf-8-sig") as fh:
            reader = csv.reader(fh)
            lines = [(reader.line_num, [c.strip() for c in cells]) for cells in reader]
    except UnicodeDecodeError as exc:
        raise InputError(f"{path}: not a text (UTF-8) CSV file ({exc.reason})") from None
    lines = [(n, cells) for n, cells in lines if any(cells) and not cells[0].startswith("#")]
    if not lines:
        raise InputError(f"{path}: empty inventory file")
    head_row, head = lines[0]
    keys = _keys(head)
    twice = _repeated(keys)
    if twice:
        raise InputError(
            f"{path}: row {head_row}: two columns are {twice!r} ({','.join(head)!r}): which "
            "one holds the values is not clear"
        )
    if "name" not in keys or "location" not in keys:
        raise InputError(
            f"{path}: row {head_row}: the header must name the columns name, "
            f"height, width (or R, gamma) and location; got {','.join(head)!r}"
        )
    rows = []
    for n, cells in lines[1:]:
        if len(cells) > len(keys) and any(cells[len(keys) :]):
            rows.append((f"row {n}", {"_error": f"{len(cells)} values for {len(keys)} columns"}))
            continue
        rows.append((f"row {n}", {k: v for k, v in zip(keys, cells) if k in _FIELDS and v}))
    return rows


def _toml_rows(path: Path) -> tuple[list[tuple[str, dict]], dict, str | None]:
    data = read_toml(path)
    unknown = set(data) - {"items", "frames", "frame"}
    if unknown:
        raise InputError(
            f"{path}: unknown key(s) {', '.join(sorted(unknown))}; expected "
            "[[items]], [frames.NAME] and frame"
        )
    items = data.get("items")
    if not isinstance(items, list) or not all(isinstance(it, dict) for it in items):
        raise InputError(f"{path}: give the items as [[items]] tables")
    tables = data.get("frames", {})
    if not isinstance(tables, dict) or not all(isinstance(t, dict) for t in tables.values()):
        raise InputError(f"{path}: give frames as [frames.NAME] tables")
    defined = {
        name: ShearFrame.from_mapping(table, name, f"{path}: [frames.{name}]")
        for name, table in tables.items()
    }
    default = data.get("frame")
    if default is not None and not isinstance(default, str):
        raise InputError(f"{path}: frame must be the name of a frame, got {default!r}")
    rows = [(f"item {i}", dict(zip(_keys(it), it.values()))) for i, it in enumerate(items, start=1)]
    for (_where, fields), item in zip(rows, items):
        extra = set(fields) - set(_FIELDS)
        twice = _repeated(_keys(item))
        if extra:
            fields["_error"] = f"unknown key(s) {', '.join(sorted(extra))}"
        elif twice:
            fields["_error"] = f"two keys are {twice!r} (e.g. h and height): give it once"
    return rows, defined, default


def _item(fields: dict, where: str, frames: _Frames, default: ShearFrame | None) -> Item:
    """One item from a row's fields (column -> str or number); raises InputError."""
    if "_error" in fields:
        raise InputError(fields["_error"])
    name = str(fields.get("name", "")).strip()
    if not name:
        raise InputError("missing name")
    problems: list[InputError] = []

    def check(fn, *args):
        try:
            return fn(*args)
        except InputError as exc:
            problems.append(exc)
            return None

    block = check(_block, fields)
    floor, frame = check(_location, fields, frames, default, where) or (None, None)
    e = check(_restitution, fields.get("e"), block) if block is not None else None
    mu = check(_optional_positive, "mu", fields.get("mu"))
    mu_k = check(_optional_positive, "mu_k", fields.get("mu_k"))
    if mu is not None or "mu" not in fields:  # (a bad mu is a problem already)
        check(kinetic_friction, mu, mu_k)
    if problems or block is None or floor is None or e is None:
        kind = _NoFrame if any(isinstance(p, _NoFrame) for p in problems) else InputError
        raise kind(f"item {name!r}: " + "; ".join(map(str, problems)))
    return Item(name, block, floor, frame, e, mu, where, mu_k)


def _block(fields: dict) -> Block:
    dims = [k for k in ("height", "width") if k in fields]
    shape = [k for k in ("r", "gamma") if k in fields]
    mass = [k for k in ("h_cg", "b", "r_g") if k in fields]
    if sum(map(bool, (dims, shape, mass))) > 1:
        raise InputError("give height and width, or R and gamma, or h_cg, b and r_g: one of them")
    if mass:
        missing = [k for k in ("h_cg", "b", "r_g") if k not in fields]
        if missing:
            raise InputError(f"missing {' and '.join(missing)} (a general body needs h_cg, b, r_g)")
        return Block.from_mass_properties(
            positive("h_cg", fields["h_cg"], "m"),
            positive("b", fields["b"], "m"),
            radius_of_gyration=positive("r_g", fields["r_g"], "m"),
        )
    if len(dims) == 2:
        return Block.from_dimensions(
            positive("height", fields["height"], "m"), positive("width", fields["width"], "m")
        )
    if len(shape) == 2:
        return Block(positive("R", fields["r"], "m"), positive("gamma", fields["gamma"], "-"))
    missing = (
        [k for k in ("height", "width") if k not in fields]
        if dims or not shape
        else [k.replace("r", "R") for k in ("r", "gamma") if k not in fields]
    )
    raise InputError(f"missing {' and '.join(missing)}")


def _location(fields: dict, frames: _Frames, default: ShearFrame | None, where: str):
    text = str(fields.get("location", "")).strip()
    if not text:
        raise InputError("missing location ('ground' or 'floor N')")
    match = _LOCATION.fullmatch(text)
    if match is None:
        raise InputError(f"location must be 'ground' or 'floor N', got {text!r}")
    frame_name = str(fields.get("frame", "")).strip()
    frame = frames.get(frame_name) if frame_name else default
    floor = 0 if match.group(1) else int(match.group(2))
    if floor == 0 and not match.group(1):
        warnings.warn(
            f"{where}: location {text!r} is read as the ground, the base of the frame (its "
            "floors count from 1); write 'ground' if that is meant",
            stacklevel=2,
        )
    if floor == 0:
        return 0, None
    if frame is None:
        raise _NoFrame(f"location {text!r} needs a frame")
    if floor > frame.n_stories:
        raise InputError(f"unknown floor {floor}: {frame.name} has floors 1 to {frame.n_stories}")
    return floor, frame


def _restitution(value, block: Block) -> float:
    if value is None or str(value).strip() == "":
        return DEFAULT_E
    return resolve_e(value, block)


def _optional_positive(name: str, value) -> float | None:
    if value is None or str(value).strip() == "":
        return None
    return positive(name, value, "-")
