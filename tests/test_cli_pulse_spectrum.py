"""``rocking pulse-spectrum`` (issue 46): the folder it writes and its refusals."""

from __future__ import annotations

import json
import math

import numpy as np
import pandas as pd
import pytest
from click.testing import CliRunner

from rocking.cli import main
from rocking.defaults import G


def test_pulse_spectrum_writes_tables_report_and_run_json(tmp_path):
    out = tmp_path / "ps"
    args = ["pulse-spectrum", "--R", "1", "--gamma", "4", "--shape", "one-sine"]
    args += ["--periods", "0.3:0.9:0.3", "--n-scan", "64", "--e", "0.9", "--out", str(out)]
    result = CliRunner().invoke(main, args)
    assert result.exit_code == 0, result.output
    run = json.loads((out / "run.json").read_text())
    assert run["status"] == "completed" and run["command"] == "pulse-spectrum"
    for name in ("spectrum.csv", "switches.csv", "report.html", "figures/kappa-omega.png"):
        assert name in run["outputs"] and (out / name).is_file()
    spectrum = pd.read_csv(out / "spectrum.csv")
    assert list(spectrum["period_s"]) == [0.3, 0.6, 0.9]
    # Ω = 2π/(T_p·p) with p = sqrt(3g/4) for R = 1 m; κ and a_p consistent with tan α = 1/4
    p = (3 * G / 4) ** 0.5
    assert spectrum["omega_ratio"].tolist() == pytest.approx(
        [2 * math.pi / (t * p) for t in (0.3, 0.6, 0.9)]
    )
    np.testing.assert_allclose(
        spectrum["overturning_amplitude_g"], spectrum["kappa"] / 4, rtol=1e-11
    )
    # a longer pulse overturns the block with a smaller amplitude (Ω falls, κ with it)
    assert spectrum["kappa"].is_monotonic_decreasing and spectrum["kappa"].iloc[-1] > 1.0
    switches = pd.read_csv(out / "switches.csv")
    assert set(switches["period_s"]) == {0.3, 0.6, 0.9}
    first = switches[switches["switch"] == 0]
    assert first["kappa"].tolist() == pytest.approx(spectrum["kappa"].tolist())
    assert first["overturns_above"].all()


def test_pulse_spectrum_refuses_bad_input_in_one_line_before_any_work(tmp_path):
    out = tmp_path / "bad"
    for extra, word in [
        (["--shape", "triangle", "--periods", "1"], "pulse shape"),
        (["--shape", "one-sine", "--periods", "2:1:0.5"], "--periods"),
    ]:
        args = ["pulse-spectrum", "--R", "1", "--gamma", "4", *extra, "--out", str(out)]
        result = CliRunner().invoke(main, args)
        assert result.exit_code == 1 and word in result.output
        assert "Traceback" not in result.output and len(result.output.strip().splitlines()) == 1
        assert not out.exists()
