"""The paper's published numbers (``rocking/data/paper_values.toml``) as Python objects."""

from __future__ import annotations

import tomllib
from functools import cache
from importlib.resources import files

import pandas as pd

from ..dynamics.body import FOOT

_TABLES = {1: "table1_sv_required", 2: "table2_sv1", 3: "table3_ratio"}


@cache
def paper_values() -> dict:
    """All of ``paper_values.toml`` (tables, misprints, readings of Sections 5, 7, 8, and the
    nine conclusions)."""
    with files("rocking").joinpath("data/paper_values.toml").open("rb") as fh:
        return tomllib.load(fh)


def paper_table(number: int) -> pd.DataFrame:
    """Table 1 (S_v [cm/s]), 2 (S_v1 [cm/s]) or 3 (ratio) as printed: rows R [m] = whole feet
    rounded as :func:`rocking.assessment.energy.grid_table` labels them, columns γ [-]."""
    t = paper_values()["tables"]
    index = pd.Index([round(f * FOOT, 7) for f in t["R_ft"]], name="R [m]")
    columns = pd.Index(t["gamma"], name="gamma [-]")
    return pd.DataFrame(t[_TABLES[number]], index=index, columns=columns)
