"""Lists of bodies read from CSV files.

Format: a header row, then one body per row. Either columns ``R`` [m] and ``gamma`` [-], or
``H`` [m] and ``B`` [m] (height and width), or, for a body whose mass is not uniform, ``h_cg``
[m] (height of the centre of mass), ``b`` [m] (horizontal distance from the centre of mass to
each pivot edge: in a file with ``h_cg``, ``b`` is that distance, not the width) and ``r_g``
[m] (radius of gyration about the centre of mass; :meth:`rocking.Block.from_mass_properties`);
an optional ``name`` column; optional ``mu`` and ``mu_k`` columns [-], the static and kinetic
friction coefficients of each body's base (issue 45; an empty cell: not given, the command's
``--mu``/``--mu-k`` or infinite friction). Headers are matched
without regard to case or spaces and may carry a unit in brackets (``R [m]``, ``H (m)``);
``γ`` is accepted for ``gamma``. Blank lines and lines starting with ``#`` are skipped. Example::

    name,R,gamma
    cabinet,1.22,4
    tank,2.44,2.5

Errors name the file, the data row (1 = first body) with its line in the file, and the problem.
The package ships an example, :func:`example_bodies_path` (``--bodies example`` on the command
line).
"""

from __future__ import annotations

import dataclasses
import math
import os
import re
from collections.abc import Sequence
from dataclasses import dataclass
from importlib.resources import files
from pathlib import Path
from typing import Protocol

from ..core.checks import kinetic_friction
from ..core.files import csv_rows
from ..dynamics.body import Block
from ..dynamics.physics import Physics
from ..errors import InputError

#: Accepted column names (lower case, without units) and the canonical name they stand for.
_ALIASES = {
    "r": "R",
    "gamma": "gamma",
    "γ": "gamma",
    "h": "H",
    "b": "B",
    "h_cg": "h_cg",
    "r_g": "r_g",
    "radius_of_gyration": "r_g",
    "name": "name",
    "mu": "mu",
    "μ": "mu",
    "mu_k": "mu_k",
    "μ_k": "mu_k",
}
#: The unit of each numeric column.
_UNITS = {
    **{"R": "m", "gamma": "-", "H": "m", "B": "m", "h_cg": "m", "b": "m", "r_g": "m"},
    **{"mu": "-", "mu_k": "-"},
}
#: The optional columns other than the size: the name and the friction coefficients.
_OPTIONAL = ("name", "mu", "mu_k")
#: The sets of size columns, one of which a file gives.
_SIZES = ({"R", "gamma"}, {"H", "B"}, {"h_cg", "b", "r_g"})


@dataclass(frozen=True)
class NamedBody:
    """A body from a bodies file: its ``name`` (the Block label when the file gives none), its
    :class:`~rocking.dynamics.body.Block` and the friction coefficients of its base, static
    ``mu`` and kinetic ``mu_k`` [-] (None: not given)."""

    name: str
    block: Block
    mu: float | None = None
    mu_k: float | None = None


class _Friction(Protocol):
    """A body with friction coefficients of its own (:class:`NamedBody`, an inventory's
    :class:`~rocking.assessment.inventory.Item`)."""

    @property
    def mu(self) -> float | None: ...
    @property
    def mu_k(self) -> float | None: ...


def with_body_friction(physics: Physics, bodies: Sequence[_Friction]) -> Physics:
    """``physics`` with the friction of each body that gives one (its ``mu``, ``mu_k`` [-]) in
    place of ``physics``' own (one value each: the command's --mu, --mu-k), one value per body;
    ``physics`` itself when no body gives one.  Where a body gives one, a ``physics`` with one
    value per block (a sequence) is refused (:class:`InputError`): a body's friction would
    come from two lists."""
    if all(b.mu is None and b.mu_k is None for b in bodies):
        return physics
    for name in ("mu", "mu_k"):
        if isinstance(getattr(physics, name), tuple):
            raise InputError(
                f"physics.{name} must be one value for all the bodies when some give their own "
                f"friction (mu, mu_k), got one per block: {getattr(physics, name)}"
            )
    mu = [physics.mu if b.mu is None else b.mu for b in bodies]
    mu_k = [(physics.mu_k if b.mu is None else None) if b.mu_k is None else b.mu_k for b in bodies]
    return dataclasses.replace(physics, mu=tuple(mu), mu_k=tuple(mu_k))


def example_bodies_path() -> Path:
    """Path of the shipped example bodies file: the paper's two Section 8 blocks and five
    pieces of equipment, columns name, H [m], B [m]."""
    return Path(str(files("rocking") / "data" / "example_bodies.csv"))


def read_bodies(path: str | os.PathLike[str]) -> list[Block]:
    """Blocks listed in a CSV file (format in the module notes), in file order.

    Parameters
    ----------
    path : str or Path
        CSV file with columns R [m] and gamma [-], or H [m] and B [m].
    """
    return [body.block for body in read_bodies_table(path)]


def read_bodies_table(path: str | os.PathLike[str]) -> list[NamedBody]:
    """Named bodies listed in a CSV file (format in the module notes), in file order.

    Names must be distinct; a row without a name is named by its Block label.

    Parameters
    ----------
    path : str or Path
        CSV file with columns R [m] and gamma [-], or H [m] and B [m], and optionally name,
        mu [-] and mu_k [-].
    """
    path = Path(path)
    lines = csv_rows(path, "bodies file")
    if not lines:
        raise InputError(
            f"{path}: empty bodies file (need a header row R,gamma or H,B and one row per body)"
        )
    columns = _columns(path, *lines[0])
    if len(lines) == 1:
        raise InputError(f"{path}: no bodies below the header (line {lines[0][0]})")
    bodies = []
    seen: dict[str, int] = {}
    for row, (lineno, cells) in enumerate(lines[1:], start=1):
        where = f"{path}: row {row} (line {lineno})"
        if len(cells) != len(columns):
            raise InputError(
                f"{where}: {len(cells)} value(s) for {len(columns)} columns ({', '.join(columns)})"
            )
        values = dict(zip(columns, cells))
        size = {k: _number(where, k, v) for k, v in values.items() if k not in _OPTIONAL}
        mu, mu_k = (_friction(where, k, values.get(k, "")) for k in ("mu", "mu_k"))
        try:
            kinetic_friction(mu, mu_k)
        except InputError as exc:
            raise InputError(f"{where}: {exc}") from None
        if "R" in size:
            block = Block(size["R"], size["gamma"])
        elif "h_cg" in size:
            block = Block.from_mass_properties(
                size["h_cg"], size["b"], radius_of_gyration=size["r_g"]
            )
        else:
            block = Block.from_dimensions(size["H"], size["B"])
        name = values.get("name") or block.label
        if name in seen:
            raise InputError(f"{where}: name {name!r} repeats that of row {seen[name]}")
        seen[name] = row
        bodies.append(NamedBody(name, block, mu, mu_k))
    return bodies


def _columns(path: Path, lineno: int, header: list[str]) -> list[str]:
    """Canonical names of the header's columns; raises unless exactly one size pair is there."""
    columns = []
    for cell in header:
        key = re.sub(r"\s*[\[(].*[\])]\s*$", "", cell).strip().lower()
        if key not in _ALIASES:
            raise InputError(
                f"{path}: line {lineno}: unknown column {cell!r} (expected R and "
                "gamma, or H and B, or h_cg, b and r_g, and optionally name, mu and mu_k)"
            )
        if _ALIASES[key] in columns:
            raise InputError(f"{path}: line {lineno}: column {cell!r} appears twice")
        columns.append(_ALIASES[key])
    if "h_cg" in columns:  # with h_cg, b is the distance to the pivot edge, not the width
        columns = ["b" if c == "B" else c for c in columns]
    sizes = {c for c in columns if c not in _OPTIONAL}
    if sizes not in _SIZES:
        # fewer columns than one whole set and none of another: a set is incomplete
        whole = "R and gamma, or H and B, or h_cg, b and r_g"
        if len(sizes) < 3 and not any(sizes > s for s in _SIZES):
            problem = f"missing column: need {whole}"
        else:
            problem = f"give {whole}, one of them, not a mix"
        raise InputError(f"{path}: line {lineno}: {problem} (got {', '.join(header)})")
    return columns


def _friction(where: str, column: str, text: str) -> float | None:
    """A friction coefficient of ``column`` [-]: None for an empty cell, else a finite number
    > 0 (an error naming the row otherwise)."""
    return _number(where, column, text) if text.strip() else None


def _number(where: str, column: str, text: str) -> float:
    """``text`` as a finite number > 0 in ``column``, or an error naming the row."""
    unit = _UNITS[column]
    try:
        x = float(text)
    except ValueError:
        what = "an empty cell" if not text else repr(text)
        raise InputError(f"{where}: {column} must be a number [{unit}], got {what}") from None
    if not math.isfinite(x) or x <= 0.0:
        raise InputError(f"{where}: {column} must be a finite number > 0 [{unit}], got {text}")
    return x
