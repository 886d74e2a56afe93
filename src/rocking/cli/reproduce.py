"""``rocking reproduce``: run the paper's studies (Sections 4–8) and write the report."""

from __future__ import annotations

import click

from ..defaults import STUDY_SECTIONS
from ._options import connect_timeout_option, overwrite_option, quiet_option, reporter


@click.command("reproduce")
@click.argument("section", type=click.Choice([*STUDY_SECTIONS, "all"]), metavar="SECTION|all")
@click.option(
    "--fidelity",
    type=click.Choice(["quick", "paper"]),
    default="quick",
    show_default=True,
    help="quick: small ensembles, dt = 1/200 s, 9 bodies (a fast check of every section); "
    "paper: the paper's sizes (200/500 motions, 72 bodies, dt = 1/400 s).",
)
@click.option(
    "--out",
    "out_dir",
    type=click.Path(file_okay=False, writable=True),
    help="Output folder for report.md, report.html, run.json, figures/, tables/ and "
    "chunks/ (finished work: a rerun with the same parameters resumes). A folder of another "
    "run (other sections or parameters) is refused (see --overwrite).",
)
@overwrite_option
@click.option(
    "--scheduler",
    default=None,
    metavar="ADDRESS",
    help="'local' (default), 'dask-local' or a Dask scheduler address (tcp://host:8786).",
)
@connect_timeout_option
@click.option(
    "--config",
    "config_path",
    type=click.Path(exists=True, dir_okay=False),
    help="TOML file overriding parameters of the fidelity preset ([common], [sec4] "
    "... [sec8] tables; keys in `python -m pydoc rocking.studies.config`).",
)
@click.option(
    "--set",
    "sets",
    multiple=True,
    metavar="SECTION.KEY=VALUE",
    help="Override one parameter (VALUE in TOML syntax), e.g. --set sec8.n=100 "
    "--set 'sec7.frames=[\"paper-0.5\"]'. Repeatable; wins over --config.",
)
@click.option(
    "--show-config",
    is_flag=True,
    help="Print the parameters (preset + --config + --set) as TOML and exit: a "
    "starting point for a --config file.",
)
@quiet_option
def reproduce_command(
    section: str,
    fidelity: str,
    out_dir: str | None,
    overwrite: bool,
    scheduler: str | None,
    connect_timeout: float | None,
    config_path: str | None,
    sets: tuple[str, ...],
    show_config: bool,
    quiet: bool,
) -> None:
    """Reproduce SECTION (4-8) of the paper, or all of them, into a report in --out.

    \b
    4  baseline correction (Figs. 3-4)
    5  sensitivity to motion, intensity, size, slenderness, e (Figs. 5-8)
    6  duration and intensity function (Figs. 9-10)
    7  floors of shear frames (Figs. 11-12)
    8  Housner's energy balance (Figs. 13-16, Tables 1-3, worked examples)
    soundness  time step, ensemble size and strength, the Section 8 floor
    friction   beyond the paper: A_gx50 and Table 3 with friction mu = 0.3-0.8

    The report lists the paper's nine conclusions as reproduced / partly / not reproduced
    with the evidence in numbers.
    """
    from ..studies.config import load_config, to_toml, validate

    cfg = load_config(fidelity, config_path, sets)
    validate(cfg)  # before anything is printed or written (and --show-config prints a valid one)
    if show_config:
        click.echo(to_toml(cfg), nl=False)
        return
    if out_dir is None:
        raise click.UsageError("Missing option '--out'.")
    sections = list(STUDY_SECTIONS) if section == "all" else [section]
    progress = reporter(quiet)
    progress.write(
        f"reproducing section{'s' if len(sections) > 1 else ''} "
        f"{', '.join(sections)} at {fidelity} fidelity into {out_dir}"
    )
    from ..studies import reproduce

    echo = (lambda _msg: None) if quiet else click.echo
    reproduce(
        sections,
        fidelity=fidelity,
        out_dir=out_dir,
        overwrite=overwrite,
        scheduler=scheduler,
        connect_timeout=connect_timeout,
        config=config_path,
        sets=sets,
        progress=progress,
        echo=echo,
    )


COMMANDS = [reproduce_command]
