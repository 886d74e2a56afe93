"""The paper's studies (Sections 4–8), the checks of their soundness and, beyond the paper, the
friction study (issue 45), each a small module composing the library, and the runner that
reproduces them into a report.

Every study module has ``TITLE``, ``run(ctx) -> result`` (computation only) and
``report(result, rep, ctx)`` (figures and tables into a :class:`rocking.report.Report`).
:func:`reproduce` runs the chosen sections, judges the paper's nine conclusions
(:mod:`.conclusions`) and writes ``report.md``, ``report.html`` and ``run.json``.
"""

from __future__ import annotations

import importlib
import os
import time
from collections.abc import Callable, Iterable, Sequence
from pathlib import Path
from types import ModuleType
from typing import TYPE_CHECKING

from ..defaults import STUDY_SECTIONS
from ..errors import InputError

if TYPE_CHECKING:
    from concurrent.futures import Executor

    from ..core.progress import Reporter
    from ..report import Report
    from .conclusions import Verdict
    from .config import RunContext

#: Study modules by section number (imported when a section runs: they load Matplotlib).
STUDIES = {
    "4": "sec4_baseline",
    "5": "sec5_sensitivity",
    "6": "sec6_duration",
    "7": "sec7_floors",
    "8": "sec8_energy",
    "soundness": "soundness",
    "friction": "friction",
}


def study(section: str) -> ModuleType:
    """The module of the study of ``section`` ("4"–"8", "soundness" or "friction")."""
    return importlib.import_module(f".{STUDIES[section]}", __name__)


def reproduce(
    sections: Iterable[str],
    *,
    fidelity: str = "quick",
    out_dir: str | os.PathLike[str],
    overwrite: bool = False,
    scheduler: str | None = None,
    connect_timeout: float | None = None,
    config: str | os.PathLike[str] | None = None,
    sets: Sequence[str] = (),
    progress: bool | Reporter | None = False,
    echo: Callable[[str], object] | None = None,
) -> Path:
    """Run ``sections`` (e.g. ``["8"]`` or all of :data:`STUDIES`) and write the report.

    Parameters
    ----------
    sections : iterable of str
        Section numbers "4"–"8", "soundness" (:mod:`.soundness`) or "friction" (beyond the
        paper: :mod:`.friction`, reported beside the conclusions).
    fidelity : str
        "quick" or "paper" (:data:`rocking.studies.config.PRESETS`).
    out_dir : str or Path
        Output folder (a :class:`rocking.core.runs.RunFolder`): report.md, report.html, run.json,
        figures/, tables/, and chunks/ (finished Monte Carlo chunks: a rerun with the same
        parameters resumes from them). A folder of another run (other sections or parameters)
        is refused, unless ``overwrite``.
    overwrite : bool
        Replace the results of another run in ``out_dir`` (:class:`rocking.core.runs.RunFolder`).
    scheduler : str, optional
        Backend (:func:`rocking.montecarlo.backends.get_backend`): None/"local", "dask-local" or a
        Dask scheduler address.
    connect_timeout : float, optional
        Seconds to wait for a scheduler address (:func:`rocking.montecarlo.backends.get_backend`).
    config : str or Path, optional
        TOML file of parameter overrides (:func:`rocking.studies.config.load_config`).
    sets : sequence of str
        ``section.key=VALUE`` overrides.
    progress : bool, None or rocking.core.progress.Reporter
        Progress of each section (:func:`rocking.core.progress.resolve`).
    echo : callable, optional
        Called with one line of text per finished step.

    Returns
    -------
    Path
        The report.html written.
    """
    from ..core.progress import resolve
    from ..core.reuse import reusing
    from ..core.runs import RunFolder
    from ..montecarlo.backends import get_backend
    from ..report import Report, drawing_pool, remove_report
    from .config import PRESETS, RunContext, load_config, validate

    echo = echo or (lambda _msg: None)
    sections = list(dict.fromkeys(str(s) for s in sections))
    unknown = [s for s in sections if s not in STUDIES]
    if unknown or not sections:
        raise InputError(
            f"unknown section(s) {', '.join(unknown) or '(none)'}; choose from "
            f"{', '.join(STUDIES)} or all"
        )
    cfg = load_config(fidelity, config, sets)
    validate(cfg)
    backend = get_backend(scheduler, connect_timeout)  # checks the address before any writing
    reporter = resolve(progress)
    out = Path(out_dir)
    modified = cfg != PRESETS[fidelity]
    run_info = {
        "sections": sections,
        "fidelity": fidelity,
        "config_file": None if config is None else str(config),
        "sets": list(sets),
        "modified": modified,
        "scheduler": scheduler or "local",
        "seeds": {s: cfg[s]["seed"] for s in cfg if "seed" in cfg[s]},
        "backend": repr(backend),
    }
    with (
        RunFolder(
            out,
            command="reproduce",
            params={"parameters": cfg, "sections": sections},
            overwrite=overwrite,
            reads={"--config": config},
        ) as run,
        reporter,
        drawing_pool() as drawer,  # started now: ready when the figures are
    ):
        # the pages of an earlier run must not look like this run's result if it fails
        remove_report(out)
        run.update(**run_info)
        ctx = RunContext(cfg, fidelity, modified, backend, reporter, run.chunks)
        start = time.perf_counter()
        results, parts, wall = {}, {}, {}
        # a run of one section builds its figures here, the worker only drawing them: else this
        # process would wait while the worker built and drew every one after the section
        # (`reproduce 8 --fidelity quick` took 1.18x the time: median of six interleaved pairs)
        plot_here = len(sections) == 1
        # the same spectra recur across sections (e.g. the mean PSV of Section 8's ground
        # motions in the soundness checks): computed once (rocking.core.reuse)
        with backend, reusing():
            for s in sections:
                t0 = time.perf_counter()
                reporter.write(f"section {s}: {STUDY_SECTIONS[s]}")
                with reporter.stage(f"section {s}", unit="sim"):
                    results[s] = study(s).run(ctx)
                # its part of the report at once: the drawer builds and draws its figures while
                # the next sections run (on two cores the processor has room for them beside the
                # sections, not after them)
                parts[s] = Report(STUDY_SECTIONS[s], out, drawer, plot_here=plot_here)
                study(s).report(results[s], parts[s], ctx)
                for name in parts[s].files:
                    run.file(name)
                wall[s] = round(time.perf_counter() - t0, 2)
                run.update(wall_time_s=wall)
                echo(f"section {s}: {wall[s]:.1f} s")
        t0 = time.perf_counter()
        with reporter.stage("report", unit="sections"):
            for name in _write_report(out, ctx, results, parts, drawer):
                run.file(name)
        wall["report"] = round(time.perf_counter() - t0, 2)
        wall["total"] = round(time.perf_counter() - start, 2)
        run.info["wall_time_s"] = wall
    echo(f"report: {out / 'report.html'} ({wall['total']:.1f} s in all)")
    return out / "report.html"


def _write_report(
    out: Path,
    ctx: RunContext,
    results: dict,
    parts: dict[str, Report],
    drawer: Executor | None = None,
) -> list[str]:
    """Report of the studies in ``results`` (by section): the introduction and the conclusions,
    then each section's ``parts`` (filled as the section ended), figures drawn by ``drawer``
    (:class:`rocking.report.Report`); returns the files written (relative to ``out``), the
    parts' included."""
    from ..report import Report
    from . import conclusions

    sections = list(results)
    rep = Report(
        f"Reproduction of the rocking paper: {conclusions.sections_phrase(sections)} "
        f"({ctx.fidelity} fidelity)",
        out,
        drawer,
    )
    _introduction(rep, ctx, sections, ctx.fidelity, ctx.modified)
    _conclusions(rep, conclusions.evaluate(results), conclusions.robustness(results), ctx.label())
    # beyond the paper, beside its conclusions: what its assumption of sufficient friction hides
    for s in sorted(sections, key=lambda s: s != "friction"):
        rep.extend(parts[s])
    rep.heading("Known disagreements with the paper and likely reasons")
    rep.text("\n".join(f"- {item}" for item in conclusions.known_disagreements(results)))
    rep.write()
    return rep.files


def _introduction(
    rep: Report, ctx: RunContext, sections: list[str], fidelity: str, modified: bool
) -> None:
    from .conclusions import sections_phrase

    c = ctx.cfg["common"]
    rep.text(
        f"Fidelity **{fidelity}**{' (modified by --config/--set)' if modified else ''}; "
        f"{sections_phrase(sections)}; time step {c['dt']:g} s; e = {c['e']:g}; motions "
        f"simulated from the RG 1.60 spectrum with the {c['envelope']} intensity function, "
        f"{c['duration']:g} s, unless a section says otherwise. Every parameter, seed, version "
        "and wall time is in [run.json](run.json); tables are also in `tables/` as CSV. "
        + (
            "The quick fidelity uses small ensembles: its probabilities carry wide sampling "
            "intervals (shown), so verdicts may differ from a paper-fidelity run."
            if fidelity == "quick"
            else ""
        )
    )


def _conclusions(rep: Report, verdicts: list[Verdict], robust: list[str], label: str) -> None:
    import pandas as pd

    from .conclusions import not_run_line

    table = pd.DataFrame(
        {
            "no.": [v.number for v in verdicts],
            "verdict": [v.verdict for v in verdicts],
            "sections": [v.sections for v in verdicts],
            "conclusion (paper, Section 9)": [v.statement for v in verdicts],
            "robust to integrator and ensemble size?": robust,
        }
    )
    # the page lists what this run judged (and what section soundness assessed), the rest in
    # one line; the CSV keeps all nine
    shown = [v.ran or not r.startswith("not assessed") for v, r in zip(verdicts, robust)]
    n_ran = sum(v.ran for v in verdicts)
    rep.heading(
        "The paper's nine conclusions"
        if n_ran == len(verdicts)
        else f"The paper's conclusions: {n_ran} of {len(verdicts)} evaluated by this run"
    )
    if any(shown):
        rep.table(
            table[shown].reset_index(drop=True),
            f"Verdicts on the paper's conclusions, evidence below [{label}; "
            "sizes per section in the figure captions]",
            name="conclusions",
            csv=table,
        )
    lines = [f"- **{v.number}. {v.verdict}.** {v.evidence}" for v, ok in zip(verdicts, shown) if ok]
    rep.text("\n".join(lines + ([""] if lines else []) + [not_run_line(verdicts)]))
