"""Progress reports: a line every few seconds off a terminal, one stage per section, and a word
when the kernels compile (issue 14: "a first run that talks")."""

from __future__ import annotations

import io
import time

import numba
import numpy as np
from click.testing import CliRunner

from rocking.cli import main
from rocking.core import progress
from rocking.core.progress import COMPILING, Reporter


def test_a_silent_stage_still_writes_a_line_every_interval():
    # one long piece of work without updates (like the first compilation inside the first
    # chunk) must not leave the log silent: a heartbeat writes the elapsed time
    out = io.StringIO()
    with Reporter(out, tty=False, interval=0.2, delay=0.0).stage("work", unit="sim") as stage:
        time.sleep(1.1)
        stage.expect(10)
        stage.update(10)
    lines = out.getvalue().splitlines()
    assert len(lines) >= 4  # about one per 0.2 s, and the last one
    assert all(line.startswith("work: ") for line in lines)
    assert lines[-1].startswith("work: 100% (10/10 sim")
    assert "\r" not in out.getvalue()


def test_short_stages_show_nothing():
    out = io.StringIO()
    with Reporter(out, tty=False, interval=0.1, delay=1.0).stage("quick") as stage:
        stage.update(5)
    assert out.getvalue() == ""


def test_nested_stages_report_into_the_outer_one():
    out = io.StringIO()
    reporter = Reporter(out, tty=False, interval=0.2, delay=0.0)
    with reporter.stage("section 6"):
        for _ in range(3):  # three Monte Carlo calls of one section
            with reporter.stage("P(overturn)", total=100) as inner:
                inner.expect(100)
                inner.update(100)
        time.sleep(0.3)
    text = out.getvalue()
    assert "P(overturn)" not in text  # no bar per call
    assert text.splitlines()[-1].startswith("section 6: 300 sim")


def test_the_first_compilation_is_announced_once():
    progress._said_compiling.clear()

    @numba.njit  # not cached: it compiles in this process whatever ran before
    def twice(x):
        return 2.0 * x

    @numba.njit
    def thrice(x):
        return 3.0 * x

    out = io.StringIO()
    with Reporter(out, tty=False):
        twice(1.0)
        thrice(1.0)
    assert out.getvalue().splitlines() == [COMPILING]


def test_the_stage_line_says_what_is_compiling_then_counts():
    # issue 48: on the first run the line read "section 8: 0 sim (00:02 elapsed)" for 27 s
    # while the kernels compiled (the notice, printed once above it, scrolled away): the
    # stage's line names what is compiling until the compilation ends, then counts again
    progress._said_compiling.clear()

    @numba.njit  # not cached: it compiles in this process whatever ran before
    def busy(x):
        total = 0.0
        for i in range(x.size):
            if x[i] > 0.5:
                total += np.sin(x[i]) * np.exp(-x[i])
            else:
                total -= np.cos(x[i]) ** 2
        return total

    out = io.StringIO()
    # heartbeat every 10 ms: the compilation (~0.3 s or more) spans many lines
    with Reporter(out, tty=False, interval=0.01, delay=0.0).stage("work", unit="sim") as stage:
        busy(np.linspace(0.0, 1.0, 5))
        stage.expect(10)
        stage.update(10)
    lines = out.getvalue().splitlines()
    assert lines.count(COMPILING) == 1  # the notice, once, naming what compiles
    assert any(line.startswith("work [compiling the numerical kernels]: 0 sim") for line in lines)
    assert lines[-1].startswith("work: 100% (10/10 sim")  # counting again, named as before


def test_the_package_kernels_are_named_by_their_module():
    from types import SimpleNamespace

    from rocking.dynamics import batch_lanes as batch  # the lane machine: the kernels
    from rocking.motions import response

    def named(func):
        return progress._kernel_of(SimpleNamespace(data={"dispatcher": func}))[0]

    kernels = [getattr(m, n) for m in (batch, response) for n in dir(m)]
    kernels = [k for k in kernels if isinstance(k, numba.core.dispatcher.Dispatcher)]
    assert {named(k) for k in kernels if k.py_func.__module__ == batch.__name__} == {
        "the rocking kernel"
    }
    assert {named(k) for k in kernels if k.py_func.__module__ == response.__name__} == {
        "the response-spectrum kernel"
    }


def test_reproduce_off_a_terminal_writes_lines_per_section_not_a_bar_per_call(tmp_path):
    # the defect: `reproduce` printed ~20 lines of "P(overturn): 0sim", one bar per call
    result = CliRunner().invoke(
        main,
        [
            "reproduce",
            "6",
            "--set",
            "sec6.n=8",
            "--set",
            "sec6.durations=[10.0, 20.0]",
            "--set",
            "sec6.fig10_durations=[20.0]",
            "--out",
            str(tmp_path),
        ],
    )
    assert result.exit_code == 0, result.output
    assert "P(overturn)" not in result.output and "\r" not in result.output
    assert "section 6: duration and intensity function" in result.output
