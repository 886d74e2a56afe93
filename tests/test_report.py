"""Reports: Markdown + self-contained HTML, atomic writing, provenance (rocking.report)."""

import base64
import io
import json
import os
import stat
import subprocess
import sys
import time
from concurrent.futures import Executor, Future
from concurrent.futures.process import BrokenProcessPool

import numpy as np
import pandas as pd
import pytest
import xarray as xr
from matplotlib.figure import Figure
from PIL import Image

import rocking
from rocking.core.files import figure_png
from rocking.core.runs import provenance
from rocking.dynamics.body import FOOT, Block
from rocking.errors import InputError
from rocking.report import Report, drawing_pool, markdown_to_html, remove_report, slug


def _figure():
    fig = Figure(figsize=(2, 2))
    fig.add_subplot().plot([0, 1], [0, 1])
    return fig


def test_report_writes_markdown_html_png_and_csv(tmp_path):
    rep = Report("Study", tmp_path)
    rep.heading("Section 4")
    rep.text("We find **3** overturned & `x < 1`.\n\n- first\n- second *item*")
    rep.figure(_figure(), "fig-3", "Fig. 3: θ(t) [quick fidelity: n=1]")
    df = pd.DataFrame(
        {"ours": [1.0, np.nan], "paper": [2.0, 3.0]}, index=pd.Index([1.22, 1.52], name="R [m]")
    )
    rep.table(df, "Table 1 beside the paper", name="table-1", floatfmt=".2f")
    md_path, html_path = rep.write()

    md = md_path.read_text()
    assert md.startswith("# Study\n")
    assert "![Fig. 3: θ(t) (quick fidelity: n=1)](figures/fig-3.png)" in md
    assert "| R [m] | ours | paper |" in md and "| 1.22 | 1.00 | 2.00 |" in md
    assert "| 1.52 |  | 3.00 |" in md  # NaN shown as an empty cell

    page = html_path.read_text()
    assert "figures/" not in page  # self-contained: no link to the PNG file
    b64 = page.split('src="data:image/png;base64,')[1].split('"')[0]
    png = base64.b64decode(b64)
    assert png[:8] == b"\x89PNG\r\n\x1a\n"
    assert png == (tmp_path / "figures" / "fig-3.png").read_bytes()
    assert "<strong>3</strong>" in page and "&amp;" in page and "<code>x &lt; 1</code>" in page
    assert "<li>second <em>item</em></li>" in page
    assert "<td>1.22</td><td>1.00</td><td>2.00</td>" in page

    csv = pd.read_csv(tmp_path / "tables" / "table-1.csv")
    assert list(csv.columns) == ["R [m]", "ours", "paper"]
    assert csv["paper"].tolist() == [2.0, 3.0]


def test_figures_drawn_by_worker_processes_are_the_same_files(tmp_path):
    # A report whose figures are drawn by a pool of worker processes (each Figure pickled and
    # drawn there) writes the same bytes, pages and files as one drawn here: same Matplotlib,
    # same figure, so the same pixels; every figure is written by write() at the latest.
    def build(out, drawer):
        rep = Report("Study", out, drawer)
        rep.text("before")
        for i in range(3):
            fig = Figure(figsize=(3, 2), layout="constrained")
            ax = fig.add_subplot()
            ax.semilogy([1, 2, 3], [1.0, 10.0 ** (i + 1), 5.0], label=f"curve {i}")
            ax.set_title(f"θ(t), figure {i}")
            ax.legend()
            rep.figure(fig, f"f{i}", f"Figure {i}.")
        rep.text("after")
        rep.write()
        return rep.files

    files_here = build(tmp_path / "here", None)
    with drawing_pool(2) as pool:
        assert pool is not None
        files_pool = build(tmp_path / "pool", pool)
    assert (
        files_here
        == files_pool
        == [f"figures/f{i}.png" for i in range(3)]
        + [
            "report.md",
            "report.html",
        ]
    )
    for name in files_here:
        assert (tmp_path / "pool" / name).read_bytes() == (tmp_path / "here" / name).read_bytes()
    with drawing_pool(0) as pool:
        assert pool is None  # no workers: drawn in this process


def _responses(n):
    """Data for rocking.plots.studies.plot_responses: n panels of θ/α against t."""
    t = np.linspace(0.0, 2.0, 201)
    theta = np.array([np.sin((k + 1) * np.pi * t) * (k + 1) / 2 for k in range(n)])
    return t, theta, [f"γ = {k + 4}" for k in range(n)]


def test_a_plot_built_by_a_worker_is_the_figure_built_here(tmp_path):
    # Report.plot sends the plotting function and its data to a worker, which builds the
    # figure and draws it: the same bytes as the figure built and drawn here (Report.figure),
    # with a pool, without one, and where the pool broke after the plot was submitted.
    from rocking.plots.fragility import plot_sv_agx
    from rocking.plots.studies import plot_responses

    t, theta, labels = _responses(2)
    sv = xr.Dataset(
        {
            "agx50": ("body", [0.2, 0.3, 0.5]),
            "sv_required": ("body", [0.1, 0.2, 0.3]),
            "sv1": ("body", [0.08, 0.12, 0.2]),
        }
    )

    def build(out, drawer, plot, plot_here=False):
        rep = Report("Study", out, drawer, plot_here=plot_here)
        if plot:
            rep.plot(
                plot_responses, t, theta, labels, overturned=[np.nan, 1.5], name="a", caption="A."
            )
            rep.plot(plot_sv_agx, sv, title="B", name="b", caption="B.")
        else:
            rep.figure(plot_responses(t, theta, labels, overturned=[np.nan, 1.5]), "a", "A.")
            rep.figure(plot_sv_agx(sv, title="B"), "b", "B.")
        rep.write()
        return {name: (out / name).read_bytes() for name in rep.files}

    here = build(tmp_path / "here", None, plot=False)
    assert sorted(here) == ["figures/a.png", "figures/b.png", "report.html", "report.md"]
    with drawing_pool(1) as pool:
        assert pool is not None
        assert build(tmp_path / "pool", pool, plot=True) == here
        # plot_here: built here, drawn by the worker (a run's last section)
        assert build(tmp_path / "plot-here", pool, plot=True, plot_here=True) == here
    assert build(tmp_path / "no-pool", None, plot=True) == here
    assert build(tmp_path / "died", _DiedAfterSubmit(), plot=True) == here
    # what the worker receives: the plot (function and data), or with plot_here the figure
    for plot_here in (False, True):
        pending = _Pending()
        assert build(tmp_path / f"pending-{plot_here}", pending, True, plot_here) == here
        assert [isinstance(what, Figure) for what in pending.sent] == [plot_here] * 2


def test_figures_no_worker_has_started_are_drawn_here_when_the_report_is_written(tmp_path):
    # Report.write would only wait for the workers: the drawings they have not started (the
    # last ones sent, e.g. those of a run's last section) are taken back and drawn here, the
    # same bytes; those already drawn are the workers'.
    def build(out, drawer):
        rep = Report("Study", out, drawer)
        for i in range(3):
            rep.figure(_figure(), f"f{i}", f"Figure {i}.")
        rep.write()
        return {name: (out / name).read_bytes() for name in rep.files}

    here = build(tmp_path / "here", None)
    pending = _Pending()
    assert build(tmp_path / "pending", pending) == here
    assert len(pending.sent) == 3 and all(f.cancelled() for f in pending.futures)
    with drawing_pool(1) as pool:
        assert build(tmp_path / "pool", pool) == here


def test_figures_plotted_by_workers_keep_matplotlib_out_of_this_process():
    # The point of Report.plot: a process whose figures are built by the drawing workers
    # neither imports Matplotlib (0.6 s) nor builds figures; rocking.plots imports it on first
    # use.  (A figure no worker has started when the report is written is drawn here: not this
    # one, which the worker has drawn by then.)
    code = (
        "import sys, tempfile\n"
        "import numpy as np\n"
        "from rocking.plots.studies import plot_responses\n"
        "from rocking.report import Report, drawing_pool\n"
        "print('imported', 'matplotlib' in sys.modules)\n"
        "t = np.linspace(0.0, 1.0, 11)\n"
        "with tempfile.TemporaryDirectory() as out, drawing_pool(1) as pool:\n"
        "    rep = Report('Study', out, pool)\n"
        "    rep.plot(plot_responses, t, np.array([t]), ['γ = 4'], name='f', caption='F.')\n"
        "    print('plotted', 'matplotlib' in sys.modules)\n"
        "    rep._blocks[-1].png.result()\n"
        "    rep.write()\n"
        "    print('written', 'matplotlib' in sys.modules, sorted(rep.files))\n"
    )
    out = subprocess.run(
        [sys.executable, "-c", code], capture_output=True, text=True, check=True
    ).stdout.splitlines()
    assert out == [
        "imported False",
        "plotted False",
        "written False ['figures/f.png', 'report.html', 'report.md']",
    ]


def test_the_default_pool_leaves_one_processor_to_the_computation(monkeypatch):
    # one processor: no pool; two: one worker (measured faster than two on a 2-vCPU VM, and
    # ~100 MB less memory); many: at most four
    import rocking.report as report_module

    for cpus, expected in ((1, None), (2, 1), (3, 2), (16, 4)):
        monkeypatch.setattr(
            report_module.os,
            "sched_getaffinity",
            lambda _pid, n=cpus: set(range(n)),
            raising=False,  # not on every platform (macOS): drawing_pool then asks cpu_count
        )
        made = []
        monkeypatch.setattr(
            report_module,
            "ProcessPoolExecutor",
            lambda n, made=made, **kw: made.append(n) or _NoPool(),
        )
        with drawing_pool() as pool:
            assert (pool is None) == (expected is None)
        assert made == ([] if expected is None else [expected])


class _DiedAfterSubmit(Executor):
    """A pool whose worker died after a drawing was submitted."""

    def submit(self, fn, /, *args, **kwargs):
        future = Future()
        future.set_exception(BrokenProcessPool("a worker died"))
        return future


class _Pending(Executor):
    """A pool whose workers never start a drawing (every future stays pending)."""

    def __init__(self):
        self.sent, self.futures = [], []

    def submit(self, fn, /, *args, **kwargs):
        self.sent.append(args[0])
        self.futures.append(Future())
        return self.futures[-1]


class _NoPool(Executor):
    """Stands for a ProcessPoolExecutor whose workers are never started."""

    def submit(self, fn, /, *args, **kwargs):
        future = Future()
        future.set_result(None)
        return future


def test_a_figure_drawn_by_a_worker_is_let_go_before_the_report_is_written(tmp_path):
    # A run's figures used to stay in memory until its report was written, while its later
    # sections computed (quick's 23 figures hold 24 MB); once a worker has drawn one, the report
    # needs only its PNG.  A failed drawing keeps its figure (drawn here: the test below).
    import gc
    import weakref

    with drawing_pool(2) as pool:
        rep = Report("Study", tmp_path, pool)
        fig = _figure()
        alive = weakref.ref(fig)
        rep.figure(fig, "f", "Figure.")
        del fig
        rep._blocks[-1].png.result()
        for _ in range(500):  # the future's callbacks run just after its result is set
            gc.collect()
            if alive() is None:
                break
            time.sleep(0.01)
        assert alive() is None
        rep.write()
    assert (tmp_path / "figures" / "f.png").read_bytes()[:8] == b"\x89PNG\r\n\x1a\n"


def test_a_part_filled_earlier_reads_as_if_written_in_place(tmp_path):
    # rocking.studies.reproduce fills each section's part as the section ends (its figures drawn
    # meanwhile) and appends the parts after the introduction and conclusions: the pages and
    # files must be those of one report written in that order.
    def content(rep, k):
        rep.heading(f"Section {k}")
        rep.figure(_figure(), f"fig-{k}", f"Figure {k}.")
        rep.table(pd.DataFrame({"x": [float(k)]}), f"Table {k}.", name=f"tab-{k}")

    def intro(rep):
        rep.text("Conclusions first.")
        rep.table(pd.DataFrame({"verdict": ["yes"]}), "Verdicts.", name="conclusions")

    whole = Report("Study", tmp_path / "whole")
    intro(whole)
    for k in (4, 5):
        content(whole, k)
    whole.write()
    with drawing_pool(2) as pool:
        parts = []
        for k in (4, 5):
            parts.append(Report(f"part {k}", tmp_path / "parts", pool))
            content(parts[-1], k)
        rep = Report("Study", tmp_path / "parts", pool)
        intro(rep)
        for part in parts:
            rep.extend(part)
        rep.write()
    assert sorted(rep.files) == sorted(whole.files)
    for name in whole.files:
        assert (tmp_path / "parts" / name).read_bytes() == (tmp_path / "whole" / name).read_bytes()
    with pytest.raises(InputError, match="'tab-4' is used twice"):
        again = Report("again", tmp_path / "parts")
        again.table(pd.DataFrame({"x": [1.0]}), "Again.", name="tab-4")
        rep.extend(again)
    with pytest.raises(ValueError, match="same folder"):
        rep.extend(Report("elsewhere", tmp_path / "other"))


def test_figures_are_drawn_here_where_worker_processes_fail(tmp_path, monkeypatch):
    # No processes or semaphores (some sandboxes: OSError when the pool is made): no pool. A
    # worker that died (BrokenProcessPool, before or after the figure was submitted): the
    # figure is drawn in this process, the same bytes as a report without workers.
    import rocking.report as report_module

    def no_pool(*args, **kwargs):
        raise OSError(38, "Function not implemented")

    with monkeypatch.context() as m:
        m.setattr(report_module, "ProcessPoolExecutor", no_pool)
        with drawing_pool(2) as pool:
            assert pool is None

    class DiedBefore(Executor):
        def submit(self, fn, /, *args, **kwargs):
            raise BrokenProcessPool("a worker died")

    pngs = []
    for name, drawer in (("here", None), ("after", _DiedAfterSubmit()), ("before", DiedBefore())):
        rep = Report("Study", tmp_path / name, drawer)
        rep.figure(_figure(), "f", "Figure.")
        rep.write()
        pngs.append((tmp_path / name / "figures" / "f.png").read_bytes())
    assert pngs[0][:8] == b"\x89PNG\r\n\x1a\n"
    assert pngs[1] == pngs[0] and pngs[2] == pngs[0]


def test_figure_png_draws_what_savefig_draws():
    # One draw instead of savefig's two (a layout engine's figure), the same pixels; RGB when
    # opaque, RGBA otherwise; the resolution recorded, the figure's canvas and dpi kept.
    fig = Figure(figsize=(4, 3), layout="constrained")
    ax = fig.add_subplot()
    ax.loglog([0.1, 1.0, 10.0], [1.0, 30.0, 2.0], label="curve")
    ax.set_title("title")
    ax.legend()
    saved = io.BytesIO()
    fig.savefig(saved, format="png", dpi=110)
    canvas, dpi = fig.canvas, fig.dpi
    png = Image.open(io.BytesIO(figure_png(fig, 110)))
    assert png.mode == "RGB" and png.info["dpi"] == pytest.approx((110, 110), abs=0.01)
    assert np.array_equal(np.asarray(png), np.asarray(Image.open(saved).convert("RGB")))
    assert fig.canvas is canvas and fig.dpi == dpi
    fig.patch.set_alpha(0.0)
    assert Image.open(io.BytesIO(figure_png(fig, 110))).mode == "RGBA"


def test_text_columns_are_left_aligned_and_numbers_right_aligned(tmp_path):
    # Alignment follows each column's dtype (every cell used to be right-aligned); the index
    # (row labels, here numbers) is shown with "g", not with the values' floatfmt.
    rep = Report("Study", tmp_path)
    df = pd.DataFrame(
        {
            "body": ["a", "b"],
            "n": [3, 40],
            "P": [0.5, 0.25],
            "at risk": [True, False],
            "verdict": ["safe", "overturn>50%"],
        },
        index=pd.Index([1.22, 3.05], name="R [m]"),
    )
    rep.table(df, "mixed", name="mixed", floatfmt=".3f")
    md_path, html_path = rep.write()
    md = md_path.read_text()
    assert "| R [m] | body | n | P | at risk | verdict |\n|---:|:---|---:|---:|:---|:---|" in md
    assert "| 3.05 | b | 40 | 0.250 | no | overturn>50% |" in md  # booleans as yes/no (issue 48)
    page = html_path.read_text()
    assert (
        '<th>R [m]</th><th class="text">body</th><th>n</th><th>P</th>'
        '<th class="text">at risk</th><th class="text">verdict</th>'
    ) in page
    assert (
        '<td>1.22</td><td class="text">a</td><td>3</td><td>0.500</td>'
        '<td class="text">yes</td><td class="text">safe</td>'
    ) in page
    assert "td.text { text-align: left; }" in page


def test_csv_tables_carry_no_float_noise(tmp_path):
    # 0.23000000000046314: an A_gx50 of 0.23 g found on a grid of 0.01·r g and divided by r
    # (screening of a floor item); 6 * 0.3048 = 1.8288000000000002 (6 ft in metres). Both used to
    # reach the CSV as written here; 12 significant digits drop the noise and keep real values
    # (1/3, a Wilson bound) to a relative 5e-12, far below any sampling error.
    rep = Report("Study", tmp_path)
    df = pd.DataFrame(
        {
            "Agx50 [g]": [0.23000000000046314, 0.1 + 0.2],
            "R [m]": [6 * 0.3048, 0.5],
            "P": [1 / 3, 0.9568342712073097],
            "count": [7, 200],
        }
    )
    path = rep.table(df, "noisy", name="noisy")
    lines = path.read_text().splitlines()
    assert lines[1].startswith("0.23,1.8288,0.333333333333,") and lines[1].endswith(",7")
    assert lines[2].startswith("0.3,0.5,")
    back = pd.read_csv(path)
    np.testing.assert_allclose(back["P"], df["P"], rtol=5e-12)  # half a unit in the 12th digit
    assert back["count"].tolist() == [7, 200]


def test_interrupted_write_leaves_no_report(tmp_path, monkeypatch):
    rep = Report("Study", tmp_path)
    rep.text("partial")

    def broken_html(self):
        raise RuntimeError("disk full while rendering")

    monkeypatch.setattr(Report, "html", broken_html)
    with pytest.raises(RuntimeError):
        rep.write()
    # Neither page, nor a leftover temporary file, exists after the failure.
    assert sorted(p.name for p in tmp_path.iterdir()) == []


def test_stale_report_is_removed_before_a_new_run(tmp_path):
    rep = Report("Old", tmp_path)
    rep.write()
    remove_report(tmp_path)
    assert not (tmp_path / "report.html").exists() and not (tmp_path / "report.md").exists()


def test_names_are_checked(tmp_path):
    rep = Report("Study", tmp_path)
    rep.figure(_figure(), "a", "first")
    with pytest.raises(InputError, match="used twice"):
        rep.figure(_figure(), "a", "again")
    with pytest.raises(InputError, match="file name"):
        rep.table(pd.DataFrame({"x": [1]}), "bad", name="../escape")
    with pytest.raises(InputError, match="level"):
        rep.heading("h", level=7)


def test_slug_makes_file_names():
    assert slug("frames/my frame.toml") == "frames_my_frame.toml"
    assert slug("floor 1") == "floor_1" and slug("///") == "unnamed"


def test_slug_of_a_body_label_is_a_valid_distinct_name(tmp_path):
    # Body labels carry "γ", a comma and spaces; the slug spells γ out rather than dropping it.
    labels = [Block(4 * FOOT, g).label for g in (2.0, 2.5)]
    names = [slug(label) for label in labels]
    assert names == ["R_1.22_m_gamma_2", "R_1.22_m_gamma_2.5"]
    rep = Report("Study", tmp_path)
    for name in names:  # accepted as figure names (file names)
        assert rep.figure(_figure(), name, "caption").name == f"{name}.png"


def test_markdown_renders_lists_and_links():
    html = markdown_to_html("a\nb\n\n* x\n  y")
    assert html.startswith("<p>a") and "<ul>" in html and "<li>x" in html
    assert markdown_to_html("[doc](run.json)") == '<p><a href="run.json">doc</a></p>'


def test_provenance_records_versions_and_parameters(tmp_path):
    path = provenance(
        tmp_path,
        seeds={"ground": np.int64(7)},
        agx=np.array([0.3, 0.6]),
        wall_time_s={"4": 1.25},
        backend="local",
    )
    run = json.loads(path.read_text())
    assert run["version"] == rocking.__version__
    assert run["seeds"] == {"ground": 7} and run["agx"] == [0.3, 0.6]
    assert run["numpy"] == np.__version__ and {"python", "numba", "command_line"} <= set(run)
    with pytest.raises(TypeError, match="run.json"):
        provenance(tmp_path, thing=object())
    assert json.loads(path.read_text())["backend"] == "local"  # the failed write left it intact


@pytest.mark.skipif(os.name != "posix", reason="file modes and umask are POSIX")
@pytest.mark.parametrize("umask", [0o022, 0o027, 0o077])
def test_written_files_get_the_mode_open_would_give(tmp_path, umask):
    # Reference: a file made by open(..., "w") under the same umask (0666 & ~umask). The old
    # writer went through tempfile.mkstemp, so every report file came out 0600; the shared
    # writer then read the umask once per process, so 0o027 and 0o077 after 0o022 failed.
    old = os.umask(umask)
    try:
        with open(tmp_path / "reference.txt", "w") as fh:
            fh.write("x")
        rep = Report("Study", tmp_path / "out")
        rep.figure(_figure(), "fig", "a figure")
        rep.table(pd.DataFrame({"x": [1.0]}), "a table", name="tab")
        rep.write()
        provenance(tmp_path / "out", status="complete")
    finally:
        os.umask(old)
    expected = stat.S_IMODE((tmp_path / "reference.txt").stat().st_mode)
    assert expected == 0o666 & ~umask
    out = tmp_path / "out"
    for name in ("report.md", "report.html", "figures/fig.png", "tables/tab.csv", "run.json"):
        assert stat.S_IMODE((out / name).stat().st_mode) == expected, name


def test_failed_html_write_leaves_no_page(tmp_path, monkeypatch):
    # The pages are now written one after the other by the package's one atomic writer: if the
    # second (report.html) fails on disk, the first must not stay behind looking like a result.
    import rocking.core.files
    import rocking.report

    rep = Report("Study", tmp_path)
    rep.text("partial")
    real = rocking.core.files.atomic_write

    def full_disk(path, data):
        if path.name == "report.html":
            raise OSError("no space left on device")
        return real(path, data)

    monkeypatch.setattr(rocking.report, "atomic_write", full_disk)
    with pytest.raises(OSError, match="no space"):
        rep.write()
    assert sorted(p.name for p in tmp_path.iterdir()) == []
