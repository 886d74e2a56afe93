"""The paper's studies: configuration, conclusions logic, published values and end-to-end runs
of ``rocking reproduce all --fidelity quick``."""

import json
import re
from itertools import pairwise

import numpy as np
import pandas as pd
import pytest
import xarray as xr
from click.testing import CliRunner

import rocking
from rocking.cli import main
from rocking.dynamics.body import Block, housner_sv
from rocking.errors import InputError
from rocking.montecarlo.statistics import wilson_interval
from rocking.plots.studies import plot_responses
from rocking.studies import conclusions as C
from rocking.studies import reproduce, sec4_baseline
from rocking.studies.config import PRESETS, load_config, to_toml
from rocking.studies.paper import paper_values
from rocking.studies.sec5_sensitivity import reversals

# --------------------------------------------------------------------------- configuration


def test_presets_follow_the_paper():
    paper = PRESETS["paper"]
    assert paper["common"]["dt"] == 1 / 400  # paper Section 2
    assert paper["sec6"]["n"] == 500 and paper["sec7"]["n"] == 500  # Sections 6, 7
    assert paper["sec8"]["n"] == 200 and paper["sec8"]["bodies"] == "paper"  # Section 8
    assert paper["sec4"]["R"] == pytest.approx(3.048)  # "3.05 m" is 10 ft


def test_config_file_and_set_override_the_preset(tmp_path):
    path = tmp_path / "c.toml"
    path.write_text('[sec8]\nn = 12\nbodies = [[1.0, 3]]\n[common]\nenvelope = "boxcar"\n')
    cfg = load_config("quick", path, ["sec8.n=20", 'sec7.frames=["paper-0.5"]'])
    assert cfg["sec8"]["n"] == 20  # --set wins over the file
    assert cfg["sec8"]["bodies"] == [[1.0, 3]] and cfg["common"]["envelope"] == "boxcar"
    assert cfg["sec7"]["frames"] == ["paper-0.5"]
    assert cfg["sec6"] == PRESETS["quick"]["sec6"]  # untouched keys keep the preset
    assert PRESETS["quick"]["sec8"]["n"] == 40  # the preset itself is not modified


@pytest.mark.parametrize(
    "text, message",
    [
        ("[sec9]\nn = 1\n", r"unknown section \[sec9\]"),
        ("[sec8]\nmotions = 1\n", r"unknown key 'motions' in \[sec8\]"),
        ("[sec8]\nn = 1.5\n", r"\[sec8\] n must be an integer"),
        ("[sec6]\nagx = []\n", r"\[sec6\] agx must be a non-empty list of a numbers"),
        ("[sec8]\nbodies = [[1.0]]\n", r"list of \[R, gamma\] pairs"),
        ("sec8 = 3\n", r"must be a \[section\] table"),
        ("[sec8\n", "not valid TOML"),
    ],
)
def test_config_errors_name_file_section_and_key(tmp_path, text, message):
    path = tmp_path / "bad.toml"
    path.write_text(text)
    with pytest.raises(InputError, match=message) as info:
        load_config("quick", path)
    assert "bad.toml" in str(info.value)


def test_show_config_round_trips(tmp_path):
    cfg = load_config("paper", sets=["common.envelope_params={t1 = 2.0, c = 0.25}"])
    path = tmp_path / "shown.toml"
    path.write_text(to_toml(cfg))
    assert load_config("paper", path) == cfg
    result = CliRunner().invoke(main, ["reproduce", "all", "--show-config", "--set", "sec8.n=7"])
    assert result.exit_code == 0 and "[sec8]\nseed = 8\nn = 7\n" in result.output


def test_set_errors():
    with pytest.raises(InputError, match="section.key=VALUE"):
        load_config("quick", sets=["n=3"])
    with pytest.raises(InputError, match="TOML syntax"):
        load_config("quick", sets=["sec8.frame=paper-2.0"])  # a string needs quotes
    with pytest.raises(InputError, match="unknown fidelity"):
        load_config("medium")


# --------------------------------------------------------------------------- published values


def test_paper_tables_are_transcribed_consistently():
    t = paper_values()["tables"]
    t1, t2, t3 = (np.array(t[k]) for k in ("table1_sv_required", "table2_sv1", "table3_ratio"))
    assert t1.shape == t2.shape == t3.shape == (8, 9)
    # Table 3 is Table 2 / Table 1 as printed; both are rounded to 0.01 cm/s and the ratio to
    # 0.001, so they agree to 0.0005 plus the rounding of the velocities (< 1e-4 here).
    assert np.abs(t2 / t1 - t3).max() < 6e-4
    assert len(paper_values()["conclusions"]["statements"]) == 9


# --------------------------------------------------------------------------- conclusions logic


def _prob(count, n, dims, coords):
    """A probability dataset as rocking.montecarlo.probability returns it, from counts."""
    count = np.asarray(count)
    lo, hi = wilson_interval(count, np.full(count.shape, n))
    return xr.Dataset(
        {
            "probability": (dims, count / n),
            "ci_low": (dims, lo),
            "ci_high": (dims, hi),
            "n": (dims, np.full(count.shape, n)),
        },
        coords=coords,
    )


def _floors(ground, floor, t1=0.5):
    """Section 7 result: one frame, ground and two floors, one body, three A_gx."""
    counts = np.array([ground, floor, floor])[None, :, None, None] * np.ones((1, 1, 1, 3), int)
    return _prob(
        counts,
        100,
        ("frame", "location", "body", "agx"),
        {
            "frame": ["stiff"],
            "location": ["ground", "floor 1", "floor 2"],
            "body": ["b"],
            "agx": [0.3, 0.5, 0.8],
            "T1": ("frame", [t1]),
        },
    )


def test_conclusion_8_follows_the_data():
    assert C.conclusion_8(_floors(ground=60, floor=20)).verdict == C.REPRODUCED
    assert C.conclusion_8(_floors(ground=20, floor=60)).verdict == C.NOT_REPRODUCED
    assert C.conclusion_8(_floors(60, 20, t1=2.0)).verdict == C.NOT_EVALUATED  # no stiff frame


def test_conclusion_7_needs_both_directions():
    both = xr.concat([_floors(60, 20), _floors(20, 60).assign_coords(frame=["soft"])], "frame")
    assert C.conclusion_7(both).verdict == C.REPRODUCED
    assert C.conclusion_7(_floors(60, 20)).verdict == C.NOT_REPRODUCED  # a clear rule


def _durations(counts, envelopes=("boxcar",)):
    """Section 6 result from counts per duration 10, 20, 25, 30 s (out of 100)."""
    c = np.array(counts)[None, :, None, None] * np.ones((len(envelopes), 1, 1, 2), int)
    return _prob(
        c,
        100,
        ("envelope", "duration", "body", "agx"),
        {
            "envelope": list(envelopes),
            "duration": [10.0, 20.0, 25.0, 30.0],
            "body": ["b"],
            "agx": [0.5, 1.0],
        },
    )


def test_conclusions_4_and_5_on_durations():
    saturating = _durations([20, 50, 60, 61])
    assert C.conclusion_4(saturating).verdict == C.REPRODUCED
    assert C.conclusion_5(saturating).verdict == C.REPRODUCED
    linear = _durations([20, 50, 65, 80])  # keeps growing at 3 % per second beyond 25 s
    assert C.conclusion_5(linear).verdict == C.NOT_REPRODUCED
    falling = _durations([60, 40, 30, 20])
    assert C.conclusion_4(falling).verdict == C.NOT_REPRODUCED


def test_conclusion_6_on_intensity_functions():
    same = _durations([20, 50, 60, 61], envelopes=("boxcar", "compound"))
    assert C.conclusion_6(same).verdict == C.REPRODUCED
    other = same.copy(deep=True)
    other["probability"].loc[{"envelope": "compound"}] += 0.3
    assert C.conclusion_6(other).verdict == C.NOT_REPRODUCED


def test_conclusion_3_detects_a_significant_drop():
    rising = _prob([[5, 40, 90]], 100, ("body", "agx"), {"body": ["b"], "agx": [0.2, 0.5, 0.8]})
    falling = _prob([[5, 90, 10]], 100, ("body", "agx"), {"body": ["b"], "agx": [0.2, 0.5, 0.8]})
    assert C.conclusion_3({"6": rising}).verdict == C.REPRODUCED
    assert C.conclusion_3({"6": falling}).verdict == C.NOT_REPRODUCED


def _balance(ground_ratio, floor_ratio):
    blocks = [Block(r, g) for r in (1.2, 2.4) for g in (2.0, 4.0)]
    sv = np.array([housner_sv(b) for b in blocks])
    agx50 = sv / 2.0  # any positive values: A_gx50 [g] proportional to S_v
    ratio = np.array([np.full(4, ground_ratio), np.full(4, floor_ratio)])
    return xr.Dataset(
        {
            "ratio": (("location", "body"), ratio),
            "sv_required": (("location", "body"), np.array([sv, sv])),
            "agx50": (("location", "body"), np.array([agx50, agx50])),
        },
        coords={"location": ["ground", "floor 1"], "body": [b.label for b in blocks]},
    )


def test_conclusion_9_on_ratios():
    assert C.conclusion_9(_balance(1.03, 1.2)).verdict == C.REPRODUCED
    assert C.conclusion_9(_balance(1.03, 2.2)).verdict == C.PARTLY  # floors off only
    assert C.conclusion_9(_balance(1.6, 2.2)).verdict == C.NOT_REPRODUCED


def test_conclusion_1_counts_changed_outcomes():
    flags = np.zeros((2, 1, 10), bool)
    flags[0, 0, :3] = True  # uncorrected overturns 3 motions, corrected none
    check = xr.Dataset(
        {
            "overturned": (("correction", "body", "motion"), flags),
            "peak": (("correction", "body", "motion"), np.ones((2, 1, 10))),
        },
        coords={"correction": ["uncorrected", "corrected"]},
    )
    assert C.conclusion_1(check).verdict == C.REPRODUCED
    assert "3/10" in C.conclusion_1(check).evidence
    check["overturned"][:] = False
    assert C.conclusion_1(check).verdict == C.NOT_REPRODUCED


def test_known_disagreements_find_the_frame_that_matches_the_paper():
    # Two frames; "stiff" has the paper's floor-1 S_v (114.30 cm/s) and its 1 Hz order
    # (ground, 1, 2, 5, 3, 4), "soft" neither. Spectra are flat, so the order holds everywhere.
    locations = ["ground", "floor 1", "floor 2", "floor 3", "floor 4", "floor 5"]
    level = {"stiff": [1.0, 1.143, 1.2, 1.5, 1.6, 1.4], "soft": [1.0, 2.6, 2.5, 2.4, 2.3, 2.2]}
    freqs = np.geomspace(0.04, 30.0, 20)
    psv = xr.DataArray(
        np.array([[np.full(20, v) for v in level[f]] for f in level]),
        dims=("frame", "location", "freq"),
        coords={
            "frame": list(level),
            "location": locations,
            "freq": freqs,
            "T1": ("frame", [1.0, 2.0]),
        },
        attrs={"agx": 0.6},
    )

    class R7:
        pass

    r7 = R7()
    r7.psv = psv
    text = C.known_disagreements({"7": r7})[-1]
    assert "Matching both (S_v within 15%): stiff;" in text and "soft (T1 = 2.00 s)" in text
    assert "floor-1 S_v 114.3 cm/s" in text


def test_reversals_of_a_sweep():
    # Three motions, PGA 0.4/0.6/0.8: motion 1 monotone, motion 2 overturns at 0.6 but not at
    # 0.8 (the paper's Fig. 6 situation), motion 3 peaks lower at 0.8 (by 50 %).
    ov = np.array([[False, False, False], [False, True, False], [False, False, False]])
    pk = np.array([[0.1, 0.2, 0.5], [0.2, 9.0, 0.4], [0.3, 0.3, 0.25]])
    sweep = xr.Dataset(
        {"overturned": (("value", "motion"), ov), "peak": (("value", "motion"), pk)},
        coords={"value": [0.4, 0.6, 0.8]},
        attrs={"direction": +1},
    )
    assert reversals(sweep) == {"outcome": 1, "peak": 2, "n": 3}


@pytest.mark.parametrize("title", ["", "R = 1.00 m, motion No. 3"])
def test_response_panels_fit_their_fixed_margins(title):
    # plot_responses has fixed margins, no layout engine: its widest tick labels ("−12.5",
    # "−1000") stay inside the figure and no panel's title reaches the panel above.
    t = np.linspace(0.0, 19.05, 400)
    wave = np.sin(t)
    fig = plot_responses(
        t,
        [wave, -12.3 * wave, -999.0 * wave],
        ["γ = 4", "γ = 5", "γ = 50"],
        overturned=[np.nan, 12.0, 3.0],
        title=title,
    )
    fig.draw_without_rendering()
    inside = fig.get_tightbbox()
    width, height = fig.get_size_inches()
    assert inside.x0 >= 0 and inside.y0 >= 0 and inside.x1 <= width and inside.y1 <= height
    boxes = [ax.get_tightbbox() for ax in fig.axes]
    assert not any(upper.overlaps(lower) for upper, lower in pairwise(boxes))


# --------------------------------------------------------------------------- end to end


@pytest.fixture(scope="module")
def quick_run(tmp_path_factory):
    # The quick fidelity itself, as CI must run it (issue 7): about 15 s on 2 cores.
    out = tmp_path_factory.mktemp("reproduce") / "out"
    result = CliRunner().invoke(
        main, ["reproduce", "all", "--fidelity", "quick", "--out", str(out), "--quiet"]
    )
    return result, out


def test_reproduce_all_quick(quick_run):
    result, out = quick_run
    assert result.exit_code == 0, result.output
    md = (out / "report.md").read_text()
    page = (out / "report.html").read_text()
    for k in range(1, 10):  # all nine conclusions, each with a verdict
        assert any(
            f"**{k}. {v}.**" in md
            for v in (C.REPRODUCED, C.PARTLY, C.NOT_REPRODUCED, C.NOT_EVALUATED)
        ), k
    # key numbers: Table 1 misprint by Eq. (11), the paper's floor S_v, the fidelity note
    for text in ("324.33", "316.71", "114.30", "quick fidelity"):
        assert text in md
    for fig in (
        "fig3",
        "fig4",
        "fig5",
        "fig8",
        "fig9a",
        "fig11-paper-0.5",
        "fig12-paper-2.0",
        "fig13",
        "fig14",
        "fig15",
        "fig16",
        "friction",
    ):
        assert (out / "figures" / f"{fig}.png").exists(), fig
    assert page.count("data:image/png;base64,") == len(list((out / "figures").iterdir()))
    run = json.loads((out / "run.json").read_text())
    assert run["status"] == "completed" and run["version"] == rocking.__version__
    assert set(run["wall_time_s"]) >= {"4", "5", "6", "7", "8", "friction", "total"}
    assert run["parameters"] == PRESETS["quick"] and not run["modified"]


def test_reproduce_report_writes_gamma_as_gamma(quick_run):
    # Body names, table headers and legends used to write γ as "g" ("R=1.22m g=4").
    _result, out = quick_run
    md = (out / "report.md").read_text()
    assert "R=1.22 m, γ=4" in md
    assert not re.search(r"\bg=", md)
    for table in (out / "tables").iterdir():
        assert not re.search(r"\bg=", table.read_text()), table.name
    floor = pd.read_csv(out / "tables" / "table3-floor_1.csv")
    assert list(floor.columns) == ["R [m]", "γ=2", "γ=4", "γ=6"]  # were 2.0, 4.0, 6.0
    reversals_table = pd.read_csv(out / "tables" / "sec5-reversals.csv")
    assert "γ" in set(reversals_table["factor"]) and "gamma" not in set(reversals_table["factor"])


#: Sizes of the small run below (each section's ensemble differs from the preset's).
SMALL_SETS = ["sec4.n_check=3", "sec6.n=6", "sec7.n=5", "sec8.n=12"]


def _titles(fig) -> list[str]:
    """Every title of a figure (its suptitle and each panel's three titles), whitespace
    normalised."""
    texts = [fig.get_suptitle()] + [
        ax.get_title(loc) for ax in fig.axes for loc in ("left", "center", "right")
    ]
    return [" ".join(t.split()) for t in texts if t.strip()]


@pytest.fixture(scope="module")
def small_run(tmp_path_factory):
    """All sections with smaller ensembles than the quick preset (SMALL_SETS); records the
    titles and caption of every figure the report receives."""
    from rocking.report import Report

    out = tmp_path_factory.mktemp("small") / "out"
    shown = []
    figure, plot = Report.figure, Report.plot

    def recording_figure(self, fig, name, caption):
        shown.append((name, caption, _titles(fig)))
        return figure(self, fig, name, caption)

    def recording_plot(self, func, /, *args, name, caption, **kwargs):
        # the studies' figures are built by the drawing workers: built here too, to read them
        shown.append((name, caption, _titles(func(*args, **kwargs))))
        return plot(self, func, *args, name=name, caption=caption, **kwargs)

    with pytest.MonkeyPatch.context() as mp:
        mp.setattr(Report, "figure", recording_figure)
        mp.setattr(Report, "plot", recording_plot)
        reproduce(list("45678"), fidelity="quick", out_dir=out, sets=SMALL_SETS)
    return out, shown


def test_figure_titles_do_not_repeat_their_captions(small_run):
    # Every study figure used to carry its caption, wrapped, as its title; the report shows the
    # caption under it, so the sentence appeared twice.
    _, shown = small_run
    assert len(shown) >= 20
    for name, caption, titles in shown:
        sentence = " ".join(caption.split(" [")[0].split())
        for title in titles:
            assert sentence not in title and title not in caption, (name, title)


def test_report_quotes_the_ensemble_sizes_of_the_run(small_run):
    # Every "N motions", "n=N" or "motions=N" in the report is a size this run used (Section 5
    # keeps the preset's 25); the Table 3 note used to say "n = 200" whatever the run.
    out, _ = small_run
    md = (out / "report.md").read_text()
    quoted = {
        int(n)
        for match in re.findall(r"(\d+) motions\b|\bn ?= ?(\d+)|motions=(\d+)", md)
        for n in match
        if n
    }
    assert quoted == {3, 25, 6, 5, 12}
    assert "with the 12 motions of this run" in md


def test_worked_examples_say_where_eq11_and_the_simulation_disagree(small_run):
    # The quick run's γ = 2 example is judged "overturn>50%" by Eq. (11) beside a simulated
    # P of about 0.05: the table now says so, and the report explains why they can differ.
    out, _ = small_run
    table = pd.read_csv(out / "tables" / "worked-examples.csv")
    said = table["Eq. (11) vs Monte Carlo"]
    same_side = (table["verdict by Eq. (11), ours"] == "safe") == (
        table["P(overturn) simulated [-]"] < 0.5
    )
    assert (said.str.startswith("agree") == same_side).all()
    md = (out / "report.md").read_text()
    assert "Why Eq. (11) and the Monte Carlo probability can disagree" in md


def test_reproduce_bad_input_is_one_line(tmp_path):
    bad = tmp_path / "bad.toml"
    bad.write_text("[sec8]\nn = -\n")
    result = CliRunner().invoke(
        main, ["reproduce", "8", "--out", str(tmp_path / "o"), "--config", str(bad)]
    )
    assert result.exit_code == 1
    assert result.output.startswith("Error: config") and "Traceback" not in result.output
    result = CliRunner().invoke(main, ["reproduce", "9", "--out", str(tmp_path / "o")])
    # click's usage error for an unknown SECTION: one line, exit status 1 as every input error
    assert result.exit_code == 1 and len(result.output.strip().splitlines()) == 1


@pytest.mark.parametrize(
    "setting, message",
    [
        ('sec7.frames=["paper-3.0"]', "sec7.frames: unknown frame preset 'paper-3.0'"),
        ("sec6.bodies=[[1.0, -2]]", "sec6.bodies: gamma must be"),
        ("common.envelope_params={t2 = 50.0}", "common.envelope_params: t2 must lie in"),
        ("sec5.motions=[1, 30]", "sec5: motion numbers must lie in 1..n = 25"),
        ("friction.mu=[0.3, 0.3]", "friction.mu must hold at least one friction coefficient, each"),
        ("friction.mu=[0.0]", "friction.mu must be a finite number > 0"),
        ("friction.kinetic_ratio=1.5", "friction.kinetic_ratio must lie in (0, 1], got 1.5"),
    ],
)
def test_bad_values_stop_the_run_before_it_writes(tmp_path, setting, message):
    out = tmp_path / "out"
    result = CliRunner().invoke(main, ["reproduce", "4", "--out", str(out), "--set", setting])
    assert result.exit_code == 1 and message in result.output
    assert not out.exists()  # nothing computed, nothing written


def test_failed_run_leaves_no_report(tmp_path, monkeypatch):
    (tmp_path / "report.html").write_text("old report")

    def broken(ctx):
        raise RuntimeError("worker lost")

    monkeypatch.setattr(sec4_baseline, "run", broken)
    with pytest.raises(RuntimeError):
        reproduce(["4"], out_dir=tmp_path)
    assert not (tmp_path / "report.html").exists()
    assert json.loads((tmp_path / "run.json").read_text())["status"] == "failed"


SIGTERM_SCRIPT = """
import sys, threading
import rocking.montecarlo.backends
from rocking.montecarlo.backends import LocalBackend
from rocking.cli import main

class WaitAfterFirstChunk(LocalBackend):
    # The engine writes a chunk file before it asks for the next result: from then on the run
    # waits, in the middle of its Monte Carlo, for the test's SIGTERM.
    def map(self, func, handle, tasks):
        results = super().map(func, handle, tasks)
        yield next(results)
        threading.Event().wait(600)  # bounded: never an orphan

rocking.montecarlo.backends.get_backend = lambda scheduler=None, timeout=None: WaitAfterFirstChunk()
main(sys.argv[1:], prog_name="rocking")
"""


def test_sigterm_marks_the_run_failed(tmp_path):
    # A batch system stops a job with SIGTERM: the run must not be left looking "running" (or
    # complete). The command runs in a process whose backend (above) waits once the first
    # Monte Carlo chunk is on disk; the signal is sent on that event, so it always arrives
    # while the section works (run.json says "running" and the handler is installed by then).
    import os
    import signal
    import subprocess
    import sys
    import time

    out = tmp_path / "out"
    proc = subprocess.Popen(
        [sys.executable, "-c", SIGTERM_SCRIPT, "reproduce", "6", "--quiet", "--out", str(out)]
    )
    try:
        deadline = time.monotonic() + 120
        while not list(out.rglob("chunk-*.npz")):
            assert proc.poll() is None, "the run ended before writing a chunk"
            assert time.monotonic() < deadline, "no chunk written in 120 s"
            time.sleep(0.01)
        assert json.loads((out / "run.json").read_text())["status"] == "running"
        proc.send_signal(signal.SIGTERM)
        assert proc.wait(timeout=120) == 128 + signal.SIGTERM
    finally:
        if proc.poll() is None:
            os.kill(proc.pid, signal.SIGKILL)
    assert json.loads((out / "run.json").read_text())["status"] == "failed"
    assert not (out / "report.html").exists()


def test_sections_and_conclusions_not_run_read_as_english():
    # Issue 48: a run of Section 8 was titled "sections 8" and listed 8 conclusions as "not
    # evaluated"; now one section is "section 8", several "sections 4, 5 and 8", and the
    # conclusions whose sections were not run share one line.
    assert C.sections_phrase(["8"]) == "section 8"
    assert C.sections_phrase(["4", "8"]) == "sections 4 and 8"
    assert C.sections_phrase(["4", "5", "8"]) == "sections 4, 5 and 8"
    verdicts = [C.not_evaluated(1, "4"), C.not_evaluated(4, "6"), C.not_evaluated(5, "6")]
    assert C.not_run_line(verdicts) == (
        "Not evaluated by this run, as their sections were not run: conclusions 1 (section 4); "
        "4 and 5 (section 6)."
    )
    assert C.not_run_line([C.not_evaluated(9, "8")]).endswith("conclusion 9 (section 8).")
    assert C.not_run_line([]) == ""
