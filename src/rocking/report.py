"""Reports of studies: Markdown plus a self-contained HTML page.

A :class:`Report` collects headings, Markdown text, figures and tables in order and writes them
with :meth:`Report.write` as ``report.md`` (figures as PNG files beside it, tables also as CSV) and
``report.html`` (one file: figures embedded as base64 PNG, so it can be mailed or archived alone).
Figures can be drawn by worker processes (``drawer``: a pool in which Matplotlib draws each
pickled ``Figure``, the same pixels as in this process), while this process goes on; with
:meth:`Report.plot` a worker also builds the figure, from its plotting function and data, so that
this process needs neither the time nor the import of Matplotlib.

Every file is written atomically by :func:`rocking.core.files.atomic_write` (a temporary file in
the same folder renamed over the final name; mode 0666 less the umask, as ``open`` gives). Both
pages are rendered before either is written and ``report.html`` is written last, so an interrupted
run never leaves a page that looks finished. The provenance of a run (``run.json``) is written by
:func:`rocking.core.runs.provenance`.

Text is Markdown, rendered to HTML by Python-Markdown; figures and tables are rendered here.
"""

from __future__ import annotations

import base64
import html
import multiprocessing
import os
import re
import signal
import unicodedata
from collections.abc import Callable, Iterator
from concurrent.futures import BrokenExecutor, Executor, Future, ProcessPoolExecutor
from contextlib import contextmanager
from dataclasses import dataclass
from pathlib import Path
from typing import TYPE_CHECKING, Any, NamedTuple

import markdown as _markdown
import numpy as np

from .core.files import atomic_write, figure_png
from .defaults import CSV_FLOAT_FORMAT
from .errors import InputError

if TYPE_CHECKING:
    import pandas as pd
    from matplotlib.figure import Figure

#: Resolution of the PNG figures [dots per inch].
DPI = 110
#: Name pattern of figures and tables (used as file names).
_NAME = re.compile(r"^[A-Za-z0-9][A-Za-z0-9_.-]*$")

_CSS = """
body { font-family: system-ui, sans-serif; max-width: 70rem; margin: 2rem auto; padding: 0 1rem;
       line-height: 1.45; color: #222; }
h1, h2, h3 { line-height: 1.2; }
div.table { max-width: 100%; overflow-x: auto; margin: 0.5rem 0 1.5rem; }
table { border-collapse: collapse; font-size: 0.85rem; }
th, td { border: 1px solid #bbb; padding: 0.15rem 0.45rem; text-align: right; }
th { vertical-align: bottom; }
td { white-space: nowrap; }
th.text, td.text { text-align: left; }
td.text { white-space: normal; }
td.text:first-child { min-width: 9rem; }
details { margin: 0.5rem 0 1.5rem; }
summary { cursor: pointer; color: #444; }
.warning { border-left: 4px solid #c60; background: #fff6ec; padding: 0.3rem 0.8rem; }
th { background: #f0f0f0; }
figure { margin: 1rem 0 1.5rem; }
figure img { max-width: 100%; }
figcaption, .caption { font-size: 0.9rem; color: #444; text-align: left; padding: 0.3rem 0; }
code { background: #f4f4f4; padding: 0 0.2rem; }
"""


@dataclass(frozen=True)
class _Block:
    """One element of a report, rendered for both pages."""

    md: str
    html: str


class _Plot(NamedTuple):
    """A figure still to be built: ``func(*args, **kwargs)`` (pickled to a drawing worker)."""

    func: Callable[..., Figure]
    args: tuple
    kwargs: dict[str, Any]


def _png(what: Figure | _Plot, dpi: float) -> bytes:
    """The PNG file of a figure, or of the figure that a :class:`_Plot` builds (in a drawing
    worker, or here)."""
    fig = what.func(*what.args, **what.kwargs) if isinstance(what, _Plot) else what
    return figure_png(fig, dpi)


@dataclass
class _Drawing:
    """A figure being drawn by a worker of the report's ``drawer``: its PNG comes from ``png``
    (``what``, the figure or the plot that builds it, is kept to draw it here if the pool breaks,
    and let go once it is drawn: a run's figures would otherwise stay in memory while its later
    sections compute)."""

    name: str
    caption: str
    what: Figure | _Plot | None
    png: Future

    def __post_init__(self) -> None:
        self.png.add_done_callback(self._let_go)

    def _let_go(self, png: Future) -> None:
        if not png.cancelled() and png.exception() is None:
            self.what = None


class Report:
    """An ordered report written to ``out_dir`` as report.md and a self-contained report.html.

    Parameters
    ----------
    title : str
        Title of the report (the page's first heading).
    out_dir : str or Path
        Output folder; created if missing. Figures go to ``out_dir/figures/<name>.png`` and
        tables to ``out_dir/tables/<name>.csv`` as they are added; the two pages only on
        :meth:`write`.
    drawer : concurrent.futures.Executor, optional
        A pool of worker processes that draws the figures (:func:`rocking.core.files.figure_png`
        of the pickled ``Figure``) while the caller goes on; their PNG files are then written
        as they are needed, at the latest by :meth:`write`. None: each figure is drawn and
        written when it is added.
    plot_here : bool
        Build the figures of :meth:`plot` in this process, the ``drawer`` only drawing them:
        for a report after which this process has nothing else to do but wait for the workers
        (a run of one section), where building and drawing every figure in the worker would
        leave this process idle.
    """

    def __init__(
        self,
        title: str,
        out_dir: str | os.PathLike[str],
        drawer: Executor | None = None,
        *,
        plot_here: bool = False,
    ) -> None:
        self.title = str(title)
        self.out_dir = Path(out_dir)
        self.out_dir.mkdir(parents=True, exist_ok=True)
        self.drawer = drawer
        self.plot_here = plot_here
        self._blocks: list[_Block | _Drawing] = []
        self._names: set[str] = set()
        self._n_tables = 0
        #: Files written so far, relative to ``out_dir`` ('/'-separated).
        self.files: list[str] = []

    # ---- content -------------------------------------------------------------------------------
    def heading(self, text: str, level: int = 2) -> None:
        """Add a heading of ``level`` 1–6."""
        if isinstance(level, bool) or level not in range(1, 7):
            raise InputError(f"heading level must be an integer 1-6, got {level!r}")
        text = " ".join(str(text).split())
        self._blocks.append(
            _Block(f"{'#' * level} {text}", f"<h{level}>{_inline(text)}</h{level}>")
        )

    def text(self, markdown: str) -> None:
        """Add Markdown text (paragraphs, ``-`` lists, bold, italic, code, links)."""
        markdown = str(markdown).strip("\n")
        self._blocks.append(_Block(markdown, markdown_to_html(markdown)))

    def figure(self, fig: Figure, name: str, caption: str) -> Path:
        """Add a matplotlib ``Figure``, saved as ``figures/<name>.png``; returns that path (with
        a ``drawer``, the file is written once drawn: by :meth:`write` at the latest)."""
        return self._add_figure(fig, name, caption)

    def plot(
        self, func: Callable[..., Figure], /, *args: Any, name: str, caption: str, **kwargs: Any
    ) -> Path:
        """Add the figure ``func(*args, **kwargs)`` (a module-level function that returns a
        matplotlib ``Figure``, e.g. one of :mod:`rocking.plots`), saved as
        ``figures/<name>.png``; returns that path.

        As :meth:`figure`, but with a ``drawer`` (and not ``plot_here``) the figure is built
        where it is drawn: a worker receives the function and its (pickled) arguments, so this
        process spends nothing on the figure and need not import Matplotlib.  The same PNG as
        ``figure(func(*args, **kwargs), name, caption)``.
        """
        if self.plot_here:
            return self._add_figure(func(*args, **kwargs), name, caption)
        return self._add_figure(_Plot(func, args, kwargs), name, caption)

    def _add_figure(self, what: Figure | _Plot, name: str, caption: str) -> Path:
        name = self._claim(name)
        cap = " ".join(str(caption).split())
        if self.drawer is not None:
            try:
                self._blocks.append(_Drawing(name, cap, what, self.drawer.submit(_png, what, DPI)))
                return self.out_dir / "figures" / f"{name}.png"
            except BrokenExecutor:  # a worker died (e.g. out of memory): draw here from now on
                self.drawer = None
        self._blocks.append(self._figure_block(name, cap, _png(what, DPI)))
        return self.out_dir / "figures" / f"{name}.png"

    def _figure_block(self, name: str, cap: str, png: bytes) -> _Block:
        """Write a figure's PNG file; its block."""
        path = self.out_dir / "figures" / f"{name}.png"
        path.parent.mkdir(exist_ok=True)
        atomic_write(path, png)
        self.files.append(f"figures/{name}.png")
        b64 = base64.b64encode(png).decode("ascii")
        return _Block(
            f"![{_md_alt(cap)}](figures/{name}.png)\n\n*{cap}*",
            f'<figure><img alt="{html.escape(cap)}" src="data:image/png;base64,{b64}">'
            f"<figcaption>{_inline(cap)}</figcaption></figure>",
        )

    def _drawn(self) -> list[_Block]:
        """The blocks, every figure drawn by the ``drawer`` waited for and written (in order).

        The figures no worker has started yet (the last ones sent: those of a run's last
        section) are taken back and drawn here, while the workers finish theirs: this process
        would otherwise only wait (``reproduce 8 --fidelity quick``: its report phase took 1.5–2 s
        instead of 0.7–0.9 s once the workers built the figures too).
        """
        drawings = [b for b in self._blocks if isinstance(b, _Drawing)]
        taken = [d for d in reversed(drawings) if d.png.cancel()]  # the last ones first
        here = {}
        for d in reversed(taken):
            assert d.what is not None  # kept: not drawn
            here[id(d)] = _png(d.what, DPI)
        for i, b in enumerate(self._blocks):
            if isinstance(b, _Drawing):
                if id(b) in here:
                    png = here[id(b)]
                else:
                    try:
                        png = b.png.result()
                    except BrokenExecutor:  # its worker died: drawn here instead
                        assert b.what is not None  # kept: the drawing failed
                        png = _png(b.what, DPI)
                self._blocks[i] = self._figure_block(b.name, b.caption, png)
        return [b for b in self._blocks if isinstance(b, _Block)]  # all of them now

    def table(
        self,
        dataframe: pd.DataFrame,
        caption: str,
        name: str | None = None,
        *,
        floatfmt: str = ".4g",
        csv: pd.DataFrame | None = None,
        collapsed: bool = False,
    ) -> Path:
        """Add a table (a ``pandas.DataFrame``; its index is shown when it is named or not a
        plain range); also written as ``tables/<name>.csv`` (floats to 12 significant digits,
        :data:`CSV_FLOAT_FORMAT`).

        ``floatfmt`` is the format of floats on the pages (e.g. ``".2f"``); index values are
        row labels, shown with ``"g"``; booleans are shown as yes/no. Numeric columns are
        right-aligned, the others (text, booleans) left-aligned. On the HTML page the table
        scrolls sideways inside a box as wide as the text, never off the page. ``csv``: a
        fuller table written as the CSV file instead (e.g. every column, where the page shows
        a few). ``collapsed``: on the HTML page, the table is folded under its caption (a
        ``<details>`` element), for tables that a figure above already shows. Returns the CSV
        path.
        """
        self._n_tables += 1
        name = self._claim(name or f"table-{self._n_tables}")
        df = dataframe
        show_index = (
            df.index.name is not None
            or any(df.index.names[1:])
            or not (df.index.dtype.kind in "iu" and np.array_equal(df.index, np.arange(len(df))))
        )
        n_index = df.index.nlevels if show_index else 0
        if show_index:
            df = df.reset_index()
        path = self.out_dir / "tables" / f"{name}.csv"
        path.parent.mkdir(exist_ok=True)
        full = df if csv is None else csv
        atomic_write(path, full.to_csv(index=False, float_format=CSV_FLOAT_FORMAT).encode())
        self.files.append(f"tables/{name}.csv")
        header = [str(c) for c in df.columns]
        numeric = [dtype.kind in "iufc" for dtype in df.dtypes]
        formats = ["g"] * n_index + [floatfmt] * (len(header) - n_index)
        rows = [[_cell(v, f) for v, f in zip(row, formats)] for row in df.itertuples(index=False)]
        cap = " ".join(str(caption).split())
        md = [
            f"*{cap}*",
            "",
            "| " + " | ".join(h.replace("|", "\\|") for h in header) + " |",
            "|" + "|".join("---:" if num else ":---" for num in numeric) + "|",
        ]
        md += ["| " + " | ".join(c.replace("|", "\\|") for c in row) + " |" for row in rows]
        cls = ["" if num else ' class="text"' for num in numeric]
        body = "".join(
            "<tr>" + "".join(f"<td{k}>{html.escape(c)}</td>" for k, c in zip(cls, row)) + "</tr>"
            for row in rows
        )
        head = "".join(f"<th{k}>{html.escape(h)}</th>" for k, h in zip(cls, header))
        table = f"<table><thead><tr>{head}</tr></thead><tbody>{body}</tbody></table>"
        if collapsed:
            page = (
                f'<details><summary class="caption">{_inline(cap)} (click to show)</summary>'
                f'<div class="table">{table}</div></details>'
            )
        else:
            page = f'<p class="caption">{_inline(cap)}</p><div class="table">{table}</div>'
        self._blocks.append(_Block("\n".join(md) + f"\n\n(CSV: `tables/{name}.csv`)", page))
        return path

    def warning(self, markdown: str) -> None:
        """Add a warning (Markdown text, shown boxed on the HTML page, quoted in Markdown)."""
        markdown = str(markdown).strip("\n")
        self._blocks.append(
            _Block(
                "\n".join("> " + line for line in f"**Warning.** {markdown}".splitlines()),
                f'<div class="warning">{markdown_to_html(f"**Warning.** {markdown}")}</div>',
            )
        )

    def extend(self, other: Report) -> None:
        """Append the content of ``other``, a report into the same folder filled earlier (its
        figures drawn by the ``drawer`` meanwhile, its tables written), in order; its figure and
        table names become this report's, which must not use them already."""
        if other is self or other.out_dir != self.out_dir:
            raise ValueError("extend() takes another report into the same folder")
        for name in sorted(other._names):
            self._claim(name)
        self._blocks += other._blocks
        self.files += other.files
        self._n_tables += other._n_tables
        other._blocks, other.files = [], []

    def _claim(self, name: str) -> str:
        name = str(name)
        if not _NAME.match(name):
            raise InputError(
                f"figure/table name {name!r} must be letters, digits, '_', '-' or "
                "'.', starting with a letter or digit (it becomes a file name)"
            )
        if name in self._names:
            raise InputError(f"figure/table name {name!r} is used twice in this report")
        self._names.add(name)
        return name

    # ---- output --------------------------------------------------------------------------------
    def markdown(self) -> str:
        """The report as Markdown (figures linked as ``figures/<name>.png``)."""
        return "\n\n".join([f"# {self.title}"] + [b.md for b in self._drawn()]) + "\n"

    def html(self) -> str:
        """The report as one self-contained HTML page (figures embedded)."""
        title = html.escape(self.title)
        body = "\n".join(b.html for b in self._drawn())
        return (
            f'<!DOCTYPE html>\n<html lang="en"><head><meta charset="utf-8">'
            f"<title>{title}</title><style>{_CSS}</style></head>\n<body>\n<h1>{title}</h1>\n"
            f"{body}\n</body></html>\n"
        )

    def write(self) -> tuple[Path, Path]:
        """Write ``report.md`` and ``report.html`` atomically; return their paths.

        Both are rendered first, then written, ``report.html`` last; if writing it fails, the new
        ``report.md`` is removed again, so an error part-way leaves no new page behind.
        """
        md_path = self.out_dir / "report.md"
        html_path = self.out_dir / "report.html"
        md, page = self.markdown(), self.html()
        atomic_write(md_path, md)
        try:
            atomic_write(html_path, page)
        except BaseException:
            md_path.unlink(missing_ok=True)
            raise
        self.files += ["report.md", "report.html"]
        return md_path, html_path


@contextmanager
def drawing_pool(workers: int | None = None) -> Iterator[Executor | None]:
    """A pool of worker processes to draw a :class:`Report`'s figures (its ``drawer``), or None
    (draw in this process) on a machine with one processor, or where processes cannot be
    started (some sandboxes have no semaphores; :class:`Report` also draws in its own process
    from the moment a worker dies).

    ``workers`` (0: None) defaults to the processors this process may use less one, the one
    this process computes on, at most 4: one worker on two processors, where the figures are
    drawn while the sections compute (2026-11-27, Zen 3: ``reproduce all --fidelity quick``
    0.90–0.93× the time of two workers in four interleaved pairs, and ~100 MB less memory).
    The workers are started at once and import Matplotlib in the background (about 1 s each),
    so that a pool opened before the figures' data are computed is ready when they are; they
    ignore Ctrl-C (this process stops them).  They are fresh interpreters ("spawn"), never a
    fork of this process and its threads.  Leaving the context waits for the drawings still
    running; on an error, those not started are dropped.
    """
    if workers is None:
        cpus = len(os.sched_getaffinity(0)) if hasattr(os, "sched_getaffinity") else os.cpu_count()
        workers = min(4, (cpus or 1) - 1)
    if workers < 1:
        yield None
        return
    pool = None
    try:
        pool = ProcessPoolExecutor(
            workers,
            mp_context=multiprocessing.get_context("spawn"),
            initializer=_drawing_worker,
            initargs=(os.getpid(),),
        )
        for _ in range(workers):  # each task starts a worker while none is idle
            pool.submit(os.getpid)
    except OSError:
        if pool is not None:
            pool.shutdown(wait=False, cancel_futures=True)
        pool = None
    if pool is None:
        yield None
        return
    try:
        yield pool
    except BaseException:
        pool.shutdown(wait=True, cancel_futures=True)
        raise
    pool.shutdown(wait=True)


def _drawing_worker(parent: int) -> None:
    """Start of a worker of :func:`drawing_pool`: it dies with the process ``parent`` that owns
    the pool (also when that one is killed outright) and leaves Ctrl-C to it (it stops the
    worker), makes rocking's process settings and imports what drawing a figure needs."""
    from .core.process import configure_process, die_with_parent

    die_with_parent(parent)
    signal.signal(signal.SIGINT, signal.SIG_IGN)
    configure_process(thresholds=False)  # each figure drawn is cyclic garbage: collect it soon
    import matplotlib.backends.backend_agg
    import matplotlib.figure  # noqa: F401
    import PIL.PngImagePlugin  # noqa: F401


def slug(text: str) -> str:
    """``text`` made usable as a figure or table name: Greek letters spelled out (a body's
    ``"R=1.22 m, γ=4"`` gives ``"R_1.22_m_gamma_4"``), other characters than letters, digits,
    ``_``, ``.`` and ``-`` replaced by ``_``."""
    spelled = "".join(_greek_name(ch) for ch in str(text))
    name = re.sub(r"[^A-Za-z0-9_.-]+", "_", spelled).strip("_.-")
    return name or "unnamed"


def _greek_name(ch: str) -> str:
    """The name of a Greek letter (``"γ"`` -> ``"gamma"``), any other character as it is."""
    name = unicodedata.name(ch, "")  # e.g. "GREEK SMALL LETTER GAMMA"
    if name.startswith("GREEK ") and " LETTER " in name:
        return name.split(" LETTER ", 1)[1].split()[0].lower()
    return ch


def remove_report(out_dir: str | os.PathLike[str]) -> None:
    """Delete ``report.md`` and ``report.html`` of an earlier run in ``out_dir`` (if any), so
    that a run which then fails does not leave the old pages looking like its result."""
    for name in ("report.md", "report.html"):
        (Path(out_dir) / name).unlink(missing_ok=True)


# --------------------------------------------------------------------------- helpers


def _cell(value, floatfmt: str) -> str:
    if isinstance(value, (bool, np.bool_)):
        return "yes" if value else "no"
    if isinstance(value, (float, np.floating)):
        return "" if np.isnan(value) else format(float(value), floatfmt)
    return str(value)


def _md_alt(text: str) -> str:
    return text.replace("[", "(").replace("]", ")")


def _inline(text: str) -> str:
    """``text`` (one line of Markdown) as inline HTML, without the paragraph around it."""
    out = markdown_to_html(text)
    return out[3:-4] if out.startswith("<p>") and out.endswith("</p>") else out


def markdown_to_html(text: str) -> str:
    """HTML of Markdown ``text`` (Python-Markdown)."""
    return _markdown.markdown(text)
