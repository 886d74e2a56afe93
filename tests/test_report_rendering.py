"""Every report, rendered from small fast inputs, checked for what reads badly (issue 48): tables
that run off the page, column headers without units, raw True/False cells, overlapping labels
and legends over the data in the figures; and what each report must say.

The reports: ``screen`` (with a hazard curve), ``fragility`` (with IM efficiency), ``risk`` and
a reproduction of one section. No browser is needed: the page's layout is checked in its HTML
(each table in a box that scrolls sideways, ``div.table`` with ``overflow-x: auto`` and
``max-width: 100%``), the figures' layout with Matplotlib's text extents after a draw.
"""

import re
from html.parser import HTMLParser
from itertools import combinations

import numpy as np
import pandas as pd
import pytest
import xarray as xr
from click.testing import CliRunner
from matplotlib.backends.backend_agg import FigureCanvasAgg
from matplotlib.transforms import Bbox

from rocking import generate
from rocking.assessment.screen import RESPONSES, screen
from rocking.cli import main
from rocking.motions.design import parse_spectrum
from rocking.motions.records import example_record_path
from rocking.plots.fragility import plot_fragility, plot_im_efficiency
from rocking.plots.screen import plot_screen
from rocking.studies import reproduce

#: Headers that need no unit: names, words, counts and keys. Any other header carries
#: "[unit]" ("[-]" for a ratio or probability).
UNITLESS = {
    "#",
    "limit state",
    "overturns above",
    "item",
    "body",
    "location",
    "verdict",
    "response (most frequent)",
    "Eq. (11) screen (conservative)",
    "no.",
    "sections",
    "conclusion (paper, Section 9)",
    "robust to integrator and ensemble size?",
    "Eq. (11) vs Monte Carlo",
    "verdict by Eq. (11), ours",
    "verdict, paper",
    "ratio S_v1/S_v",  # row labels of the Table 3 summary
    "n",  # a count of bodies
    "note",  # text: the IM efficiency's note on a per-body dimensionless IM
    "refitted not to cross",  # yes/no: the limit-state fits refitted together (fragility)
}
#: Columns keyed by γ of an R × γ grid (paper Tables 1–3): the quantity and its unit are in the
#: caption.
GRID_KEY = re.compile(r"^((ours|paper|ours - paper) )?γ=\S+$")
UNIT = re.compile(r"\[[^\]]+\]")

# Two identical items at one location (one point: one label "2, 3" must not overprint), one
# stocky and one slender on the ground, one upstairs; two with friction (issue 45: the stocky
# block slides, the cabinet may slide-rock), the others without (infinite friction).
INVENTORY = """name,height,width,location,frame,mu,mu_k
cabinet,2.0,0.5,ground,,0.35,0.3
rack A,2.0,0.6,ground,,,
rack B,2.0,0.6,ground,,,
stocky block,1.5,1.0,ground,,0.3,
shelf,2.2,0.35,floor 2,paper-2.0,,
"""


def _run(args):
    return CliRunner().invoke(main, [str(a) for a in args])


class _Page(HTMLParser):
    """The tables of an HTML page: for each, its parent element (tag, class), header cells
    and body cells."""

    def __init__(self):
        super().__init__()
        self.stack, self.tables, self.cell = [], [], None

    def handle_starttag(self, tag, attrs):
        attrs = dict(attrs)
        if tag == "table":
            parent = self.stack[-1] if self.stack else ("", "")
            self.tables.append({"parent": parent, "th": [], "td": []})
        if tag in ("th", "td") and self.tables:
            self.cell = (tag, [])
        if tag not in ("br", "img", "meta", "hr", "input"):
            self.stack.append((tag, attrs.get("class", "")))

    def handle_endtag(self, tag):
        if tag in ("th", "td") and self.cell is not None:
            self.tables[-1][tag].append("".join(self.cell[1]).strip())
            self.cell = None
        if self.stack and self.stack[-1][0] == tag:
            self.stack.pop()

    def handle_data(self, data):
        if self.cell is not None:
            self.cell[1].append(data)


def _tables(page: str) -> list[dict]:
    parser = _Page()
    parser.feed(page)
    return parser.tables


def _check_page(out):
    """What every report's page must satisfy; returns its tables."""
    page = (out / "report.html").read_text()
    tables = _tables(page)
    assert tables
    # no table wider than the page: each sits in a box as wide as the text that scrolls
    # sideways (the tables used to run off the page at 1400 px)
    assert re.search(r"div\.table \{[^}]*max-width: 100%[^}]*overflow-x: auto", page)
    for t in tables:
        assert t["parent"] == ("div", "table"), t["th"]
        # units in every column header, or a header that needs none
        for h in t["th"]:
            assert UNIT.search(h) or h in UNITLESS or GRID_KEY.match(h), h
        # booleans read yes/no, not Python's True/False
        assert not {"True", "False"} & set(t["td"]), t["th"]
    return tables


def _no_overlaps(boxes, what):
    for (i, a), (j, b) in combinations(enumerate(boxes), 2):
        assert not a.overlaps(b), f"{what} {i} and {j} overlap"


def _legend_outside(fig):
    """Draw ``fig``; its axes' legends lie outside the axes (they covered the curves)."""
    renderer = FigureCanvasAgg(fig).get_renderer()
    fig.draw(renderer)  # the layout solved, as in the PNG file
    legends = [ax.get_legend() for ax in fig.axes if ax.get_legend() is not None]
    assert legends
    for ax in fig.axes:
        if ax.get_legend() is not None:
            frame = ax.get_window_extent(renderer)
            assert not ax.get_legend().get_window_extent(renderer).overlaps(frame)
    return renderer


# --------------------------------------------------------------------------- screen


@pytest.fixture(scope="module")
def screened(tmp_path_factory):
    folder = tmp_path_factory.mktemp("screen")
    inventory = folder / "inv.csv"
    inventory.write_text(INVENTORY)
    out = folder / "out"
    args = ["screen", inventory, "--spectrum", "asce7:SDS=1.5,SD1=0.9,TL=8", "--out", out]
    args += ["--n", 8, "--duration", 5, "--resolution", 0.05, "--agx-max", 3]
    result = _run([*args, "--hazard", "example", "--max-slip", 0.05, "--quiet"])
    assert result.exit_code == 0, result.output
    spectrum = parse_spectrum("asce7:SDS=1.5,SD1=0.9,TL=8")
    motions = generate(8, duration=5.0, target=spectrum, seed=0)
    ds = screen(inventory, spectrum, ensemble=motions, resolution=0.05, agx_max=3.0)
    return out, ds


def test_screen_report_reads_at_a_glance(screened):
    out, _ = screened
    (table,) = _check_page(out)
    # the page shows the verdict and Eq. (11) as the conservative screen, with yes/no cells
    assert table["th"][:5] == ["#", "item", "location", "H × B [m]", "verdict"]
    assert "Eq. (11) screen (conservative)" in table["th"]
    # the response at the design level: a word, μ as a number or ∞ (infinite friction), the
    # slip in mm
    n_cols, k = len(table["th"]), table["th"].index("response (most frequent)")
    assert set(table["td"][k::n_cols]) <= set(RESPONSES)
    mu = table["td"][table["th"].index("μ [-]") :: n_cols]
    assert sorted(mu) == sorted(["0.35 / 0.3", "∞", "∞", "0.3", "∞"])
    assert "slip if standing, median / largest [mm]" in table["th"]
    assert any(h.startswith("P(overturn or slip >= 0.05 m)") for h in table["th"])
    md = (out / "report.md").read_text()
    assert "illustrative" in md and "not the hazard of any real site" in md


def test_screen_labels_neither_overlap_nor_overprint(screened):
    _, ds = screened
    fig = plot_screen(ds)
    renderer = _legend_outside(fig)
    ax = fig.axes[0]
    labels = [t for t in ax.texts if t.get_text()]
    # rack A and rack B are one point: one label names both (by their rows in the table)
    rows = {str(item): k + 1 for k, item in enumerate(ds["item"].values)}
    both = f"{min(rows['rack A'], rows['rack B'])}, {max(rows['rack A'], rows['rack B'])}"
    assert both in [t.get_text() for t in labels]
    assert len(labels) == ds.sizes["item"] - 1
    boxes = [t.get_window_extent(renderer) for t in labels]
    _no_overlaps(boxes, "labels")
    frame = ax.get_window_extent(renderer)
    for box in boxes:
        assert frame.contains(box.x0, box.y0) and frame.contains(box.x1, box.y1)


def test_screen_rings_the_items_that_slide(screened):
    _, ds = screened
    # the stocky block (B/H = 1/1.5 = 0.67 > mu = 0.3) slips before it can tip (Shenton 1996):
    # at the design level it mostly slides, which the figure must show (a ring about its point,
    # named in the legend) and no label may hide
    items = [str(i) for i in ds["item"].values]
    modes = ds["mode"].values.astype(str)
    assert modes[items.index("stocky block")] in ("slide", "slide-rock")
    moving = np.isin(modes, ["slide", "slide-rock"])
    fig = plot_screen(ds)
    renderer = _legend_outside(fig)
    ax = fig.axes[0]
    rings = [line for line in ax.get_lines() if line.get_markerfacecolor() == "none"]
    ringed = sorted((float(x), float(y)) for r in rings for x, y in zip(*r.get_data()))
    agx50 = np.where(np.isfinite(ds["agx50"]), ds["agx50"], ds.attrs["agx_max"])
    sv = 100.0 * ds["sv_required"].values  # the figure's cm/s
    assert ringed == sorted(zip(agx50[moving].tolist(), sv[moving].tolist()))
    legend = [t.get_text() for t in ax.get_legend().get_texts()]
    assert {f"{m}s at design A_gx (most motions)" for m in modes[moving]} <= set(legend)
    labels = [t.get_window_extent(renderer) for t in ax.texts if t.get_text()]
    for r in rings:
        for x, y in zip(*r.get_data()):
            cx, cy = ax.transData.transform((x, y))
            half = r.get_markersize() / 2 * fig.dpi / 72  # [pixels]
            ring = Bbox([[cx - half, cy - half], [cx + half, cy + half]])
            assert not any(box.overlaps(ring) for box in labels), (x, y)


# --------------------------------------------------------------------------- fragility, risk


@pytest.fixture(scope="module")
def fragility(tmp_path_factory):
    """A fragility run against PGV of two bodies on a small suite (one real record and 7
    generated motions) with its IM ranking, and the risk run on it with the example hazard."""
    folder = tmp_path_factory.mktemp("frag")
    generate(7, duration=8.0, dt=1 / 200, seed=4).save(folder / "gen.nc")
    suite = folder / "suite.nc"
    args = ["motions", "import", example_record_path(), folder / "gen.nc", "--dt", 0.01]
    result = _run([*args, "--out", suite])
    assert result.exit_code == 0, result.output
    bodies = folder / "bodies.csv"
    bodies.write_text("name,R,gamma\nslim,0.5,5\nsquat,1.5,3\n")
    out = folder / "frag"
    args = ["fragility", "--bodies", bodies, "--motions", suite, "--im", "pgv"]
    args += ["--levels", "0.05:0.8:0.05", "--n-boot", 20, "--out", out, "--quiet"]
    result = _run([*args, "--im-efficiency", "pga,pgv"])
    assert result.exit_code == 0, result.output
    risk = folder / "risk"
    result = _run(["risk", "--fragility", out, "--hazard", "example", "--out", risk, "--quiet"])
    assert result.exit_code == 0, result.output
    return out, risk


def test_fragility_report_reads_at_a_glance(fragility):
    out, _ = fragility
    tables = _check_page(out)
    assert len(tables) == 2  # the fits and the IM ranking
    page = (out / "report.html").read_text()
    # the IM ranking is a figure, its table folded under it
    assert (out / "figures" / "im-efficiency.png").is_file()
    assert re.search(r"<details>.*IMs ranked by β per body", page)
    fits = pd.read_csv(out / "lognormal.csv")
    top = 0.8  # the highest level tested (--levels 0.05:0.8:0.05)
    beyond = fits[fits["median"] >= top]
    md = (out / "report.md").read_text()
    # a median at or beyond the highest level tested is an extrapolation, said so (squat, a
    # stocky 1.5 m body, overturns under 3 of these 8 motions at 0.8 m/s of PGV: its median
    # lies above; slim's, at about 0.37 m/s, below)
    assert list(beyond["body"]) == ["squat"]
    assert "> **Warning.** The fitted median of squat" in md
    assert "slim (" not in md.split("**Warning.**")[1].split("\n\n")[0]


def test_fragility_figures_keep_legends_off_the_data(fragility):
    out, _ = fragility
    ds = xr.open_dataset(out / "probabilities.nc").rename(level="agx")
    _legend_outside(plot_fragility(ds, xlabel="PGV [m/s]"))
    fig = plot_im_efficiency(pd.read_csv(out / "im_efficiency.csv"))
    renderer = _legend_outside(fig)
    ticks = [t.get_window_extent(renderer) for t in fig.axes[0].get_yticklabels()]
    _no_overlaps(ticks, "body names")


def test_risk_report_says_the_result_in_words_with_units(fragility):
    _, risk = fragility
    (rates, tails, _ranking) = _check_page(risk)
    for header in rates["th"] + tails["th"]:
        assert "_" not in header or header.startswith("P_f"), header  # no code names
    md = (risk / "report.md").read_text()
    table = pd.read_csv(risk / "risk.csv")
    for _, row in table.iterrows():  # one sentence per body, its numbers as in risk.csv
        period = f"{float(format(1 / row['annual_rate'], '.2g')):,.0f}"  # 2 digits, e.g. 24,000
        assert f"**{row['body']}** overturns on average once in {period} years" in md
        assert f"{100 * row['p_in_50_yr']:.2g} % of overturning at least once in 50 years" in md
    assert "illustrative" in md and "not the hazard of any real site" in md
    # squat's median is extrapolated beyond the fragility's levels (above): the risk resting
    # on it says so too
    assert "> **Warning.** The fitted median of squat" in md


def test_limit_states_report_reads_at_a_glance(fragility, tmp_path):
    # issue 44's report (a figure per body, one curve per limit state) meets the same rules
    out, _ = fragility
    suite = out.parent / "suite.nc"
    bodies = out.parent / "bodies.csv"
    args = ["fragility", "--bodies", bodies, "--motions", suite, "--agx", "0.1:1.0:0.3"]
    args += ["--limit-states", "uplift, theta/alpha>=0.5, overturn", "--n-boot", 0]
    result = _run([*args, "--out", tmp_path / "states", "--quiet"])
    assert result.exit_code == 0, result.output
    _check_page(tmp_path / "states")


def test_pulse_spectrum_report_reads_at_a_glance(tmp_path):
    # issue 46's report meets the same rules
    args = ["pulse-spectrum", "--R", 1, "--gamma", 4, "--shape", "one-sine"]
    result = _run([*args, "--periods", "0.5:2:0.5", "--out", tmp_path / "pulse", "--quiet"])
    assert result.exit_code == 0, result.output
    _check_page(tmp_path / "pulse")


# --------------------------------------------------------------------------- reproduction


def test_single_section_reproduction(tmp_path):
    out = tmp_path / "sec8"
    reproduce(["8"], fidelity="quick", out_dir=out, sets=["sec8.n=12"], progress=False)
    _check_page(out)
    md = (out / "report.md").read_text()
    assert md.startswith("# Reproduction of the rocking paper: section 8 (quick fidelity)")
    assert "sections 8" not in md
    # only what the run evaluated is listed (conclusions 3 and 9 rest on Section 8), the rest
    # named in one line
    listed = re.findall(r"^- \*\*(\d)\. ", md, flags=re.M)
    assert listed == ["3", "9"]
    assert "not evaluated" not in md.split("## Section 8")[0].replace("Not evaluated", "")
    assert (
        "Not evaluated by this run, as their sections were not run: conclusions 1 (section 4); "
        "2 (section 5); 4, 5 and 6 (section 6); 7 and 8 (section 7)."
    ) in md
    assert len(pd.read_csv(out / "tables" / "conclusions.csv")) == 9  # the CSV keeps all
    page = (out / "report.html").read_text()
    assert "index" not in [h for t in _tables(page) for h in t["th"]]


def test_friction_reproduction_sits_beside_the_conclusions(tmp_path):
    # the study beyond the paper (issue 45): its table, figure and summary in words come right
    # after the conclusions, the summary's numbers those of its table
    out = tmp_path / "friction"
    sets = ["friction.n=6", "friction.resolution=0.1", "friction.mu=[0.3, 0.6]"]
    reproduce(["8", "friction"], fidelity="quick", out_dir=out, sets=["sec8.n=6", *sets])
    tables = _check_page(out)
    assert any("μ [-]" in t["th"] for t in tables)
    md = (out / "report.md").read_text()
    # the heading names the run's μ (friction.mu), not the default 0.3–0.8
    title = "## Beyond the paper: friction (A_gx50 and Table 3 for μ = 0.3–0.6, issue 45)"
    beyond, section8 = md.index(title), md.index("## Section 8")
    assert md.index("The paper's conclusions") < beyond < section8
    assert "**What the paper's assumption of sufficient friction hides.**" in md
    assert (out / "figures" / "friction.png").exists()
    table = pd.read_csv(out / "tables" / "friction-agx50.csv")
    assert sorted(set(table["μ [-]"])) == [0.3, 0.6, float("inf")]
    change = table["change [-]"].dropna()
    if len(change):
        assert f"{100 * change.min():+.1f} % to {100 * change.max():+.1f} %" in md
