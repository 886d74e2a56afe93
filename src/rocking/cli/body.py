"""``rocking table1``: the paper's Table 1, the pseudo-velocity S_v [cm/s] that overturns each of
its 72 bodies with 50 % probability by Eq. (11), compared cell by cell with the printed values."""

from __future__ import annotations

from typing import TYPE_CHECKING

import click

from ..defaults import G
from ._options import writable_file

if TYPE_CHECKING:
    import pandas as pd

#: A cell differs from the paper when |Eq. (11) − printed| exceeds this [cm/s]: the paper prints
#: two decimals (±0.005) and rounded its intermediate values; its 70 agreeing cells scatter with
#: both signs by up to 0.023 cm/s, its two misprints by 0.76 and 7.6 cm/s (tests/test_body.py).
TOLERANCE_CM_S = 0.03


def table1(g: float = G) -> pd.DataFrame:
    """Eq. (11) for the paper's 72 bodies as Table 1 (a pandas DataFrame): S_v [cm/s], rows R [ft]
    (whole feet, as the paper's sizes are), columns γ [-]; gravity ``g`` [m/s²]."""
    import numpy as np
    import pandas as pd

    from ..dynamics.body import PAPER_GAMMAS, PAPER_R_FT, housner_sv, paper_bodies

    sv = np.array([100.0 * housner_sv(b, g) for b in paper_bodies()])
    return pd.DataFrame(
        sv.reshape(len(PAPER_R_FT), len(PAPER_GAMMAS)),
        index=pd.Index(PAPER_R_FT, name="R [ft]"),
        columns=pd.Index(PAPER_GAMMAS, name="gamma [-]"),
    )


def printed_table1() -> pd.DataFrame:
    """Table 1 as printed in the paper [cm/s], laid out as :func:`table1`."""
    import pandas as pd

    from ..studies.paper import paper_values

    t = paper_values()["tables"]
    return pd.DataFrame(
        t["table1_sv_required"],
        index=pd.Index(t["R_ft"], name="R [ft]"),
        columns=pd.Index(t["gamma"], name="gamma [-]"),
    )


@click.command("table1")
@click.option("--g", "g", type=float, default=G, show_default=True, help="Gravity [m/s^2].")
@click.option(
    "--compare/--no-compare",
    default=True,
    show_default=True,
    help=f"Mark (*) and list the cells that differ from the paper's printed value by "
    f"more than {TOLERANCE_CM_S} cm/s, with both numbers.",
)
@click.option(
    "--csv",
    "csv_path",
    type=click.Path(dir_okay=False, writable=True),
    help="Save the grid (R [ft], R [m], then one column per gamma; cm/s) to a CSV file.",
)
def table1_cmd(g: float, compare: bool, csv_path: str | None) -> None:
    """Print the paper's Table 1: required S_v [cm/s] by Eq. (11) for R = 4-11 ft, gamma = 2-6.

    By default each cell is compared with the value printed in the paper, and every cell that
    differs by more than the tolerance is marked and listed with both numbers.
    """
    writable_file(csv_path, "--csv")
    import numpy as np

    from ..core.files import atomic_write
    from ..dynamics.body import FOOT

    ours = table1(g)
    paper = printed_table1()
    diff = ours - paper
    off = (diff.abs() > TOLERANCE_CM_S).to_numpy() if compare else np.zeros(ours.shape, bool)
    click.echo(
        f"Table 1: required S_v [cm/s] to overturn with 50 % probability, Eq. (11), g = {g:g} m/s^2"
    )
    click.echo(f"{'':15}gamma [-]")
    click.echo(f"{'R [ft]':>6} {'R [m]':>7} " + "".join(f"{x:>9.1f}" for x in ours.columns))
    for i, r_ft in enumerate(ours.index):
        cells = "".join(f"{v:>8.2f}{'*' if o else ' '}" for v, o in zip(ours.iloc[i], off[i]))
        click.echo(f"{r_ft:>6d} {r_ft * FOOT:>7.4f} {cells}".rstrip())
    if compare:
        click.echo(f"* differs from the paper's printed value by more than {TOLERANCE_CM_S} cm/s:")
        cells_ours, cells_paper = ours.to_numpy(), paper.to_numpy()
        for i, j in zip(*np.nonzero(off)):
            click.echo(
                f"  R = {ours.index[i]} ft ({ours.index[i] * FOOT:.4f} m), "
                f"gamma = {ours.columns[j]:.1f}: Eq. (11) {cells_ours[i, j]:.2f} cm/s, "
                f"paper {cells_paper[i, j]:.2f} cm/s "
                f"(difference {cells_ours[i, j] - cells_paper[i, j]:+.2f})"
            )
        agree = np.abs(diff.to_numpy()[~off])
        largest = f" (largest difference {agree.max():.3f} cm/s)" if agree.size else ""
        click.echo(f"{agree.size} of {off.size} cells agree within {TOLERANCE_CM_S} cm/s{largest}.")
    if csv_path:
        out = ours.copy()
        out.insert(0, "R [m]", ours.index * FOOT)
        atomic_write(csv_path, out.to_csv(float_format="%.4f"))
        click.echo(f"wrote {csv_path}")


COMMANDS = [table1_cmd]
