"""``rocking simulate``: one-line errors for bad input, physics through the command line (no uplift
below g·tan α, overturning under a constant acceleration at the time of the energy integral), the
JSON equal to :func:`rocking.simulate` on the same input, and the plot."""

import json
import math
import re

import numpy as np
import pytest
from click.testing import CliRunner
from matplotlib.image import imread
from scipy.integrate import quad

from rocking.cli import main
from rocking.cli.simulate import SIMULATED_SPEC
from rocking.dynamics.body import Block, G
from rocking.dynamics.simulate import simulate
from rocking.motions.records import example_record_path, read_record
from rocking.motions.synthesis import generate

#: The block of the tests: uplift at g·tan α = g/γ = 0.25 g.
BLOCK = Block(1.22, 4.0)
BLOCK_ARGS = ["--R", "1.22", "--gamma", "4"]


def _run(args):
    return CliRunner().invoke(main, ["simulate", *[str(a) for a in args]])


def _write_motion(path, acc_g, dt):
    """Two-column text file: time [s], acceleration [g] (17 digits, so nothing is lost)."""
    t = np.arange(len(acc_g)) * dt
    np.savetxt(path, np.column_stack([t, acc_g]), fmt="%.17g", header="t [s], a [g]")
    return path


@pytest.fixture(scope="module")
def simulated_acc():
    """The built-in simulated motion (``--motion simulated``) [m/s²] and its step [s]."""
    ens = generate(1, **SIMULATED_SPEC)
    return ens.acc[0], ens.dt


@pytest.fixture(scope="module")
def simulated_file(tmp_path_factory, simulated_acc):
    acc, dt = simulated_acc
    return _write_motion(tmp_path_factory.mktemp("motion") / "simulated.txt", acc / G, dt)


def _library(path, peak_g, **kwargs):
    """rocking.simulate on the file read by rocking.read_record, scaled to a peak of peak_g."""
    rec = read_record(path)
    ag = rec.acc * (peak_g * G / np.abs(rec.acc).max())
    return simulate(BLOCK, ag, rec.dt, **kwargs), ag


# ----------------------------------------------------------------------------- bad input


def _assert_one_line_error(result, message):
    """The command failed with exit status 1 and one line ``Error: ...`` matching ``message``."""
    assert result.exit_code == 1
    assert "Traceback" not in result.output
    lines = result.output.strip().splitlines()
    assert len(lines) == 1 and lines[0].startswith("Error: "), result.output
    assert re.search(message, lines[0]), lines[0]


@pytest.mark.parametrize(
    "content, extra, message",
    [
        ("0 0\n0.01 0.1\n0.02 nan\n0.03 0\n", [], r"bad\.txt: line 3: not a finite number: 'nan'"),
        ("", [], r"bad\.txt: empty file"),
        ("0 0\n0.01 0.1\n", ["--dt", "0"], r"--dt must be a finite number > 0 \[s\], got 0"),
        ("0 0\n0.01 0.1\n", ["--dt", "-0.01"], r"--dt must be a finite number > 0 \[s\]"),
        ("0 0\n0.01 0.1\n", ["--e", "0"], r"--e must be a number in \(0, 1\] or 'housner'"),
        ("0 0\n0.01 0.1\n", ["--e", "1.01"], r"--e must be a number in \(0, 1\] or 'housner'"),
        ("0 0\n0.01 0.1\n", ["--R", "-1.22"], r"R must be a finite number > 0 \[m\], got -1.22"),
        ("0 0\n0.01 0.1\n", ["--gamma", "-4"], r"gamma must be a finite number > 0"),
        ("0 0\n0.01 0.1\n", ["--scale-g", "-0.5"], r"--scale-g must be a finite number > 0 \[g\]"),
        ("0 0\n0.01 0\n", ["--scale-g", "0.5"], r"--scale-g: the motion is zero everywhere"),
    ],
)
def test_bad_input_gives_one_line_and_exit_1(tmp_path, content, extra, message):
    path = tmp_path / "bad.txt"
    path.write_text(content)
    result = _run([*BLOCK_ARGS, "--motion", path, *extra])
    _assert_one_line_error(result, message)


def test_missing_file_gives_one_line_and_exit_1(tmp_path):
    result = _run([*BLOCK_ARGS, "--motion", tmp_path / "nowhere.txt"])
    _assert_one_line_error(result, r"--motion .*nowhere\.txt: no such file")


# ----------------------------------------------------------------------------- physics


def test_below_the_uplift_acceleration_the_block_never_moves(simulated_file):
    # Housner (1963): from rest the block uplifts only if |a_g| > g·tan α = 0.25 g here; the
    # simulated motion scaled to a peak of 0.2 g never gets there, so θ stays exactly 0.
    result = _run([*BLOCK_ARGS, "--motion", simulated_file, "--scale-g", "0.2", "--json"])
    assert result.exit_code == 0, result.output
    out = json.loads(result.stdout)
    assert out["motion"]["pga_g"] == pytest.approx(0.2, rel=1e-12)
    assert out["block"]["uplift_acceleration_g"] == pytest.approx(0.25, rel=1e-12)
    r = out["response"]
    assert (r["overturned"], r["n_impacts"], r["max_abs_theta_rad"]) == (False, 0, 0.0)
    assert r["t_overturn_s"] is None


@pytest.mark.parametrize("angle", ["pi2", "alpha"])
def test_constant_acceleration_overturns_at_the_energy_integral_time(tmp_path, angle):
    # A constant a_g = −u·g with u = 0.5 > tan α = 0.25 (twice the uplift acceleration) tips the
    # block at t = 0 and, since θ'' = p²·[u·cos(α − θ) − sin(α − θ)] > 0 for 0 ≤ θ ≤ π/2, drives
    # it over without an impact. Energy: ½θ'² = p²·E(θ), with
    # E(θ) = u·(sin α − sin(α − θ)) − (cos(α − θ) − cos α)
    #      = 2·sin(θ/2)·[u·cos(α − θ/2) − sin(α − θ/2)],
    # so t(θ_ov) = ∫₀^θ_ov dθ / sqrt(2p²E(θ)); with θ = s² the integrand is regular.
    # The file holds a = −1 g and --scale-g 0.5 scales it (sign kept) to u = 0.5.
    u, a, p2 = 0.5, BLOCK.alpha, BLOCK.p**2
    theta_ov = math.pi / 2 if angle == "pi2" else a

    def integrand(s):
        th = s * s
        return (
            2.0
            * s
            / math.sqrt(
                4.0 * p2 * math.sin(th / 2) * (u * math.cos(a - th / 2) - math.sin(a - th / 2))
            )
        )

    t_exact = quad(integrand, 0.0, math.sqrt(theta_ov), epsabs=1e-14, epsrel=1e-13)[0]
    path = _write_motion(tmp_path / "step.txt", np.full(1601, -1.0), 0.0025)  # 4 s
    result = _run(
        [*BLOCK_ARGS, "--motion", path, "--scale-g", "0.5", "--overturn-angle", angle, "--json"]
    )
    assert result.exit_code == 0, result.output
    r = json.loads(result.stdout)["response"]
    assert r["overturned"] and r["n_impacts"] == 0
    assert r["overturn_angle_rad"] == pytest.approx(theta_ov, rel=1e-15)
    assert r["max_abs_theta_rad"] == pytest.approx(theta_ov, rel=1e-15)
    # RK4 at dt = 1/400 s: global error ∝ dt⁴, measured 2.8e-9 s at dt = 0.01 s, so ~1e-11 s here;
    # 1e-8 s leaves room for the rounding of the times read back from the file.
    assert r["t_overturn_s"] == pytest.approx(t_exact, abs=1e-8)


@pytest.mark.parametrize("peak_g, overturns", [(0.5, False), (5.0, True)])
def test_json_is_rocking_simulate_on_the_same_input(tmp_path, simulated_file, peak_g, overturns):
    # At 20 times the uplift acceleration the block overturns; at twice it, it rocks and stays.
    png = tmp_path / "out.png"
    result = _run(
        [
            *BLOCK_ARGS,
            "--motion",
            simulated_file,
            "--scale-g",
            peak_g,
            "--e",
            "housner",
            "--json",
            "--plot",
            png,
        ]
    )
    assert result.exit_code == 0, result.output
    out = json.loads(result.stdout)  # pure JSON: the "wrote" line goes to stderr
    assert result.stderr == f"wrote {png}\n" and png.stat().st_size > 0
    lib, ag = _library(simulated_file, peak_g, e="housner")
    # Housner (1963) restitution of a rectangle: e = 1 − 1.5·sin²α.
    assert out["response"]["e"] == pytest.approx(1.0 - 1.5 * math.sin(BLOCK.alpha) ** 2, rel=1e-15)
    assert out["response"] == json.loads(
        json.dumps({**lib.summary(), "overturn_angle_rad": lib.overturn_angle})
    )
    assert out["response"]["overturned"] is overturns
    m = out["motion"]
    assert (m["n_samples"], m["dt_s"], m["pga_g"]) == (
        ag.size,
        read_record(simulated_file).dt,
        pytest.approx(peak_g, rel=1e-12),
    )
    assert m["duration_s"] == pytest.approx(20.0, rel=1e-12)
    b = out["block"]
    assert (b["R_m"], b["gamma"], b["H_m"], b["B_m"], b["p_rad_s"]) == pytest.approx(
        (BLOCK.R, BLOCK.gamma, BLOCK.H, BLOCK.B, BLOCK.p), rel=1e-15
    )


def test_simulated_motion_summary_and_plot(tmp_path, simulated_acc):
    png = tmp_path / "out.png"
    result = _run([*BLOCK_ARGS, "--motion", "simulated", "--scale-g", "1", "--plot", png])
    assert result.exit_code == 0, result.output
    acc, dt = simulated_acc
    lib = simulate(BLOCK, acc * (G / np.abs(acc).max()), dt)
    assert lib.overturned
    lines = result.output.splitlines()
    assert [line.split(":")[0] for line in lines] == [
        "block",
        "motion",
        "settings",
        "result",
        f"wrote {png}",
    ]
    assert "alpha = 0.2450 rad (14.04 deg)" in lines[0] and "g*tan(alpha) = 0.25 g" in lines[0]
    assert "8001 samples at dt = 0.0025 s, duration 20 s, PGA 1 g" in lines[1]
    assert lines[3] == (
        f"result:   OVERTURNED at t = {lib.t_overturn:.4f} s; {lib.n_impacts} "
        f"impacts; max |theta|/alpha = {math.pi / 2 / BLOCK.alpha:.4g} "
        f"(max |theta| = {math.pi / 2:.4g} rad)"
    )
    assert png.read_bytes()[:8] == b"\x89PNG\r\n\x1a\n"
    image = imread(png)
    assert image.ndim == 3 and image.shape[0] > 500 and image.shape[1] > 800
    assert image[..., :3].std() > 0.05  # not a blank canvas


def test_example_motion_is_the_shipped_el_centro_record():
    # 'example' is El Centro 1940 NS as shipped (src/rocking/data/records/README.md: 1559 points
    # at 0.02 s, largest |value| 0.31882 g), unscaled, and the response is rocking.simulate on it.
    result = _run([*BLOCK_ARGS, "--motion", "example", "--json"])
    assert result.exit_code == 0, result.output
    out = json.loads(result.stdout)
    m = out["motion"]
    assert m["source"] == "example (ElCentro1940_NS.AT2)"
    assert (m["n_samples"], m["dt_s"], m["scale_factor"]) == (1559, 0.02, 1.0)
    assert m["pga_g"] == pytest.approx(0.31882, rel=1e-12)
    rec = read_record(example_record_path())
    lib = simulate(BLOCK, rec.acc, rec.dt)
    assert out["response"] == json.loads(
        json.dumps({**lib.summary(), "overturn_angle_rad": lib.overturn_angle})
    )


# ------------------------------------------------------------------------ friction (issue 45)


def test_with_mu_the_summary_gives_slip_lift_and_modes_as_rocking_simulate(tmp_path):
    # A slender block (R = 2 m, γ = 3.5) on μ_s = 0.32, μ_k = 0.27 under El Centro scaled to
    # 0.7 g slides and slide-rocks for a while, then rocks to the end without overturning (the
    # README's figure): the JSON's slip, lift and shares of the modes are those of
    # rocking.simulate on the same input; the text gives them in mm.
    block = Block(2.0, 3.5)
    rec = read_record(example_record_path())
    ag = rec.acc * (0.7 * G / np.abs(rec.acc).max())
    expected = simulate(block, ag, rec.dt, mu=0.32, mu_k=0.27)
    assert not expected.overturned  # so the modes' times add up to the whole record
    args = ["--R", 2.0, "--gamma", 3.5, "--motion", "example", "--scale-g", 0.7]
    args += ["--mu", 0.32, "--mu-k", 0.27]
    res = _run([*args, "--json"])
    assert res.exit_code == 0, res.output
    got = json.loads(res.output)["response"]
    assert got["max_abs_slip_m"] == expected.max_abs_slip > 0.0
    assert got["max_lift_m"] == expected.max_lift
    times = got["time_in_mode_s"]
    # each sample counts dt in its mode: the sum is n·dt, up to the rounding of the sums (1e-12)
    assert sum(times.values()) == pytest.approx(expected.t[-1] + rec.dt, rel=1e-12)
    assert times["slide-rock"] == np.count_nonzero(expected.mode == 3) * rec.dt > 0.0
    plot = tmp_path / "slide-rock.png"
    res = _run([*args, "--plot", plot])
    assert res.exit_code == 0, res.output
    assert f"max |slip| = {expected.max_abs_slip:.4g} m" in res.output
    assert "slide-rock" in res.output and plot.is_file()
    # the figure has a panel more than without friction: the slip
    assert imread(plot).shape[0] > imread(_plain_plot(tmp_path)).shape[0]


def test_with_mu_a_block_that_cannot_rock_rests_until_the_ground_exceeds_mu_g():
    # A square block (B/H = 1: no rocking below g·tan α = 1 g) on μ = 0.6 under El Centro:
    # Coulomb friction holds it while |a_g| ≤ μ g (a_g is linear between samples, so its peak
    # is the PGA). At a PGA of 0.55 g it rests throughout, without slip; at 0.9 g it slides.
    args = ["--R", 1.0, "--gamma", 1.0, "--motion", "example", "--mu", 0.6, "--json"]
    rests = json.loads(_run([*args, "--scale-g", 0.55]).output)["response"]
    assert {m for m, t in rests["time_in_mode_s"].items() if t > 0} == {"rest"}
    assert rests["max_abs_slip_m"] == 0.0
    slides = json.loads(_run([*args, "--scale-g", 0.9]).output)["response"]
    assert {m for m, t in slides["time_in_mode_s"].items() if t > 0} == {"rest", "slide"}
    assert slides["max_abs_slip_m"] > 0.0


def _plain_plot(folder):
    """The figure of `rocking simulate` without friction (R = 1.5 m, γ = 3.5, El Centro)."""
    plot = folder / "rock.png"
    args = ["--R", 1.5, "--gamma", 3.5, "--motion", "example", "--scale-g", 0.8, "--plot", plot]
    assert _run(args).exit_code == 0
    return plot
