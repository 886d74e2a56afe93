"""Overturning probability, A_gx(50 %), Wilson intervals, lognormal fit, resumable runs."""

import json
import os
import signal
import subprocess
import sys
import time

import numpy as np
import pytest
import xarray as xr

from rocking.core import portable
from rocking.core.progress import Reporter
from rocking.dynamics.body import Block
from rocking.dynamics.simulate import simulate
from rocking.errors import InputError
from rocking.montecarlo.probability import agx_50, member_outcomes, overturning_probability
from rocking.montecarlo.statistics import LognormalFit, fit_lognormal, wilson_interval
from rocking.motions.ensemble import Ensemble
from rocking.motions.synthesis import generate

RUN_STATS = ("chunks_computed", "chunks_loaded")


@pytest.fixture(scope="module")
def ensemble():
    return generate(8, duration=6.0, dt=1 / 200, seed=7)


def _science(ds):
    """The dataset without the attributes that describe how it was computed."""
    out = ds.copy()
    out.attrs = {k: v for k, v in ds.attrs.items() if k not in RUN_STATS}
    return out


def test_probability_is_the_fraction_of_motions_that_overturn(ensemble):
    blocks = [Block(1.22, 4.0), Block(0.6, 3.0)]
    agx = [0.3, 0.7, 1.2]
    ds = overturning_probability(blocks, ensemble, agx)
    for b, blk in enumerate(blocks):
        for j, a in enumerate(agx):
            scaled = ensemble.scaled(a)  # the paper's definition of a motion set at A_gx
            count = sum(simulate(blk, row, scaled.dt).overturned for row in scaled.acc)
            assert ds["count"].values[b, j] == count
            assert ds["probability"].values[b, j] == count / ensemble.n
    assert (ds["n"] == ensemble.n).all()
    assert ds["count"].values.max() > 0 and ds["count"].values.min() < ensemble.n
    assert list(ds["body"].values) == [b.label for b in blocks]
    assert ds["agx"].attrs["units"] == "g" and ds["R"].attrs["units"] == "m"


def test_member_outcomes_are_each_bodys_own_simulations(ensemble):
    # each body at intensities of its own, in one batch: every flag and peak must be the one
    # simulate gives for that motion scaled to that body's A_gx (the paper's definition), and
    # the bits of overturning_probability(members=True) for that body alone
    blocks = [Block(1.22, 4.0), Block(0.6, 3.0)]
    agx = np.array([[0.3, 0.7, 1.2], [0.25, 0.55, 0.95]])
    ds = member_outcomes(blocks, ensemble, agx)
    assert ds["overturned"].dims == ("body", "level", "member")
    assert ds["overturned"].values.any() and not ds["overturned"].values.all()
    for b, blk in enumerate(blocks):
        alone = overturning_probability([blk], ensemble, agx[b], members=True)
        assert ds["agx"].values[b].tobytes() == alone["agx"].values.tobytes()
        for name in ("overturned", "peak", "uplift", "peak_slip", "residual_slip", "peak_lift"):
            assert ds[name].values[b].tobytes() == alone[name].values[0].tobytes()
        for j, a in enumerate(agx[b]):
            scaled = ensemble.scaled(a)
            for m, row in enumerate(scaled.acc):
                assert ds["overturned"].values[b, j, m] == simulate(blk, row, scaled.dt).overturned
    # one level per body, and a dict of ensembles: a leading case axis
    one = member_outcomes(blocks, {"x": ensemble, "y": ensemble}, agx[:, 1])
    assert one["overturned"].dims == ("case", "body", "level", "member")
    for c in range(2):
        assert (
            one["overturned"].values[c, :, 0].tobytes() == ds["overturned"].values[:, 1].tobytes()
        )
    with pytest.raises(InputError, match="one row of levels per body"):
        member_outcomes(blocks, ensemble, [0.3, 0.5, 0.7])
    with pytest.raises(InputError, match="agx"):
        member_outcomes(blocks, ensemble, [0.3, np.nan])


def test_member_outcomes_of_some_bodies_load_a_run_of_all(ensemble, tmp_path):
    # bodies=: only the bodies named are simulated (e.g. those whose A_gx50 a search found),
    # their outcomes the bits of a call with every body, and a chunk folder of a run of all
    # the blocks serves (the fingerprint holds every block): nothing is simulated again
    blocks = [Block(1.22, 4.0), Block(0.6, 3.0), Block(1.0, 2.0)]
    agx = np.array([0.3, 0.7, 0.9])
    full = member_outcomes(blocks, ensemble, agx, out=tmp_path)
    some = member_outcomes(blocks, ensemble, agx[[2, 0]], bodies=[2, 0], out=tmp_path)
    assert some.attrs["chunks_computed"] == 0 and some.attrs["chunks_loaded"] > 0
    assert _science(some).identical(_science(full).isel(body=[2, 0]))
    for bad in ([3], [0, 0], [-1], []):
        with pytest.raises(InputError, match=r"bodies must hold indices of the blocks \(0 to 2\)"):
            member_outcomes(blocks, ensemble, agx[: len(bad)], bodies=bad)


def test_member_outcomes_with_friction_are_simulates_slip_lift_and_uplift(ensemble):
    # with friction (issue 45) each motion's uplift, peak and residual slip and peak lift must
    # be those of rocking.simulate(mu=) for that motion at that A_gx, bit for bit (the batched
    # kernel and simulate integrate the same steps: tests/test_batch_modes.py); B/H = 0.25 and
    # mu = 0.3 slightly above it, so that at 0.4 g some motions slide and some rock
    blk, mu = Block(1.22, 4.0), 0.3
    ds = member_outcomes([blk], ensemble, [0.4], mu=mu)
    assert ds["peak_slip"].attrs["units"] == "m" and ds["peak_lift"].attrs["units"] == "m"
    scaled = ensemble.scaled(float(ds["agx"].values[0, 0]))
    for m, row in enumerate(scaled.acc):
        r = simulate(blk, row, scaled.dt, mu=mu)
        one = ds.isel(body=0, level=0, member=m)
        assert bool(one["overturned"]) == r.overturned
        assert bool(one["uplift"]) == r.uplift
        assert float(one["peak_slip"]) == r.max_abs_slip
        assert float(one["residual_slip"]) == abs(r.residual_slip)
        assert float(one["peak_lift"]) == r.max_lift
    standing = ~ds["overturned"].values
    assert (ds["peak_slip"].values[standing] > 0).any(), "no motion slid the body: no check"
    assert ds["uplift"].values.any(), "no motion rocked the body: no check"
    # without friction (the paper's model) nothing slips or lifts
    rigid = member_outcomes([blk], ensemble, [0.4])
    for name in ("peak_slip", "residual_slip", "peak_lift"):
        assert not rigid[name].values.any()


def test_wilson_interval_published_values():
    # Newcombe, R. G. (1998), Two-sided confidence intervals for the single proportion:
    # comparison of seven methods, Stat. Med. 17, 857-872, Table II, method 3 (Wilson score
    # interval without continuity correction), printed to 4 decimals (hence abs=5e-5).
    cases = {
        (81, 263): (0.2553, 0.3662),
        (15, 148): (0.0624, 0.1605),
        (0, 20): (0.0, 0.1611),
        (1, 29): (0.0061, 0.1718),
    }
    k, n = np.array(list(cases)).T
    low, high = wilson_interval(k, n, 0.95)
    expected = np.array(list(cases.values()))
    np.testing.assert_allclose(low, expected[:, 0], atol=5e-5)
    np.testing.assert_allclose(high, expected[:, 1], atol=5e-5)


def test_wilson_interval_is_scipys_bit_for_bit():
    # Independent implementation: scipy.stats.binomtest(k, n).proportion_ci(method="wilson").
    # wilson_interval evaluates the same formula in the same operations (vectorized, without
    # the exact test SciPy also computes), so the bounds must be equal, not merely close.
    import scipy.stats

    for confidence in (0.5, 0.9, 0.95, 0.99):
        for n in (1, 2, 7, 20, 199, 1000):
            k = np.arange(n + 1)
            low, high = wilson_interval(k, np.full(k.shape, n), confidence)
            ref = [scipy.stats.binomtest(int(i), n).proportion_ci(confidence, "wilson") for i in k]
            np.testing.assert_array_equal(low, [c.low for c in ref])
            np.testing.assert_array_equal(high, [c.high for c in ref])


def test_lognormal_probability_is_the_normal_cdf():
    # Reference: scipy.stats.norm.cdf of ln(IM/median)/beta, the definition of the curve; Φ by
    # scipy.special.ndtr is what norm.cdf evaluates, so the values are equal, not merely close.
    import scipy.stats

    fit = LognormalFit(0.3, 0.4)
    agx = np.geomspace(1e-3, 10.0, 200)
    expected = scipy.stats.norm.cdf(portable.log(agx / 0.3) / 0.4)
    np.testing.assert_array_equal(fit.probability(agx), expected)


def test_interval_in_dataset_brackets_probability(ensemble):
    ds = overturning_probability([Block(1.0, 4.0)], ensemble, [0.4, 0.9, 2.0], confidence=0.9)
    assert ((ds.ci_low <= ds.probability) & (ds.probability <= ds.ci_high)).all()
    low, high = wilson_interval(ds["count"].values, ds["n"].values, 0.9)
    np.testing.assert_array_equal(ds.ci_low.values, low)
    np.testing.assert_array_equal(ds.ci_high.values, high)


def test_agx50_is_an_upward_crossing_of_one_half(ensemble):
    blocks = [Block(0.8, 3.0), Block(1.22, 4.0), Block(2.5, 2.5)]
    res = 0.02
    ds = agx_50(blocks, ensemble, resolution=res, agx_max=4.0, members=True)
    a50 = ds["agx50"].values
    assert np.all(np.isfinite(a50))
    # recomputed independently, at agx50 and one grid step below; members=True gives the
    # outcomes of every motion at agx50, as member_outcomes simulates them there
    for b, blk in enumerate(blocks):
        check = overturning_probability(
            [blk], ensemble, [a50[b], round(a50[b] - res, 12)], members=True
        )
        p_at, p_below = check["probability"].values[0]
        assert p_at >= 0.5 > p_below
        assert ds["probability"].values[b] == p_at
        assert ds["probability_below"].values[b] == p_below
        assert ds["overturned"].values[b].tobytes() == check["overturned"].values[0, 0].tobytes()
    assert ds["overturned"].dims == ("body", "member")


def test_agx50_not_reached_is_nan_and_cases_stack(ensemble):
    big, small = Block(3.0, 2.0), Block(0.5, 4.0)
    ds = agx_50(
        [big, small],
        {"all": ensemble, "half": ensemble.subset(range(4))},
        resolution=0.05,
        agx_max=0.5,
    )
    assert ds["agx50"].dims == ("case", "body")
    assert list(ds["case"].values) == ["all", "half"]
    # a 3 m block with gamma 2 needs far more than 0.5 g (paper Table 2: A_gx(50 %) > 1 g for
    # R = 1.22 m, gamma = 2 already); the small slender block overturns below 0.5 g
    assert np.isnan(ds["agx50"].sel(body=big.label)).all()
    assert np.isfinite(ds["agx50"].sel(body=small.label)).all()
    # no agx50, no outcomes there: all False
    one = agx_50([big, small], ensemble, resolution=0.05, agx_max=0.5, members=True)
    assert not one["overturned"].values[0].any() and one["overturned"].values[1].any()
    # the outcomes at agx50 need one member axis: refused for ensembles of other sizes
    with pytest.raises(InputError, match="same number of motions"):
        agx_50([small], {"all": ensemble, "half": ensemble.subset(range(4))}, members=True)


def test_lognormal_fit_recovers_known_parameters():
    rng = np.random.default_rng(2024)
    true = LognormalFit(median=0.65, beta=0.35)
    agx = np.arange(0.1, 1.55, 0.05)
    n = 400
    count = rng.binomial(n, true.probability(agx))
    fit = fit_lognormal(agx, count, n)
    # With 29 levels × 400 trials the standard errors are about 0.006 on ln(median) and 0.01 on
    # beta (Fisher information of the probit model); 4 % / 12 % are > 4 standard errors.
    assert fit.median == pytest.approx(true.median, rel=0.04)
    assert fit.beta == pytest.approx(true.beta, rel=0.12)
    with pytest.raises(InputError, match="not all 0"):
        fit_lognormal(agx, np.zeros_like(count), n)


def test_bad_input_is_named(ensemble):
    blk = [Block(1.0, 3.0)]
    with pytest.raises(InputError, match="agx"):
        overturning_probability(blk, ensemble, [])
    with pytest.raises(InputError, match="agx"):
        overturning_probability(blk, ensemble, [0.5, -0.1])
    with pytest.raises(InputError, match="ensemble"):
        overturning_probability(blk, ensemble.acc, [0.5])
    with pytest.raises(InputError, match="agx_max"):
        agx_50(blk, ensemble, resolution=0.1, agx_max=0.05)


def test_resume_loads_chunks_and_refuses_another_run(ensemble, tmp_path):
    blocks = [Block(1.0, 3.0), Block(2.0, 4.0)]
    agx = [0.3, 0.6, 0.9]
    first = overturning_probability(blocks, ensemble, agx, out=tmp_path, chunk_size=8)
    assert first.attrs["chunks_computed"] == 6 and first.attrs["chunks_loaded"] == 0  # 1 pair each
    again = overturning_probability(blocks, ensemble, agx, out=tmp_path, chunk_size=48)
    assert again.attrs["chunks_computed"] == 0 and again.attrs["chunks_loaded"] == 6
    xr.testing.assert_identical(_science(first), _science(again))
    with pytest.raises(InputError, match="different run.*e"):
        overturning_probability(blocks, ensemble, agx, out=tmp_path, e=0.8)
    # the adaptive search resumes the same way (its rounds are determined by earlier results)
    a50 = agx_50(blocks, ensemble, resolution=0.05, out=tmp_path / "a50")
    again = agx_50(blocks, ensemble, resolution=0.05, out=tmp_path / "a50")
    assert again.attrs["chunks_computed"] == 0
    assert again.attrs["chunks_loaded"] == a50.attrs["chunks_computed"] > 0
    xr.testing.assert_identical(_science(a50), _science(again))


def test_progress_bar_reports_simulations(ensemble, capsys):
    # a reporter writing lines (as off a terminal) from the first instant (stages shorter than
    # 2 s show nothing by default): the last line counts every simulation
    reporter = Reporter(tty=False, delay=0.0)
    overturning_probability([Block(1.0, 3.0)], ensemble, [0.5, 1.0], progress=reporter)
    err = capsys.readouterr().err
    assert "P(overturn)" in err and f"{2 * ensemble.n}/{2 * ensemble.n}" in err
    assert "\r" not in err  # lines, not a bar redrawn in place
    overturning_probability([Block(1.0, 3.0)], ensemble, [0.5, 1.0], progress=False)
    assert capsys.readouterr().err == ""


KILL_SCRIPT = """
import json, sys, threading
from rocking.montecarlo.backends import LocalBackend
from rocking.dynamics.body import Block
from rocking.motions.ensemble import Ensemble
from rocking.montecarlo.probability import overturning_probability

class WaitAfterFirstChunk(LocalBackend):
    # The engine writes a chunk file before it asks for the next result: from then on this
    # process only waits, so it is killed with exactly one chunk on disk.
    def map(self, func, handle, tasks):
        results = super().map(func, handle, tasks)
        yield next(results)
        threading.Event().wait(600)  # until the test's kill -9 (bounded: never an orphan)

sizes, agx = json.loads(sys.argv[3])
overturning_probability([Block(*rg) for rg in sizes], Ensemble.load(sys.argv[1]), agx,
                        out=sys.argv[2], chunk_size=64, progress=False,
                        backend=WaitAfterFirstChunk())
"""


def test_killed_run_resumes_to_the_same_result(tmp_path):
    ens_path = tmp_path / "motions.nc"
    generate(8, duration=10.0, dt=1 / 200, seed=5).save(ens_path)
    ens = Ensemble.load(ens_path)
    # 45 chunks of 64 simulations of blocks that mostly keep rocking
    sizes = [[R, g] for R in np.linspace(1.5, 3.5, 8).tolist() for g in (2.5, 3.5, 4.5, 5.5, 6.0)]
    agx = np.linspace(0.2, 0.6, 9).tolist()
    blocks = [Block(*rg) for rg in sizes]
    reference = overturning_probability(blocks, ens, agx, out=tmp_path / "ref", chunk_size=64)
    n_chunks = reference.attrs["chunks_computed"]

    out = tmp_path / "run"
    # The run's backend (above) stops after its first chunk is written; the kill follows that
    # event, not a guess of how long the run takes.
    proc = subprocess.Popen(
        [sys.executable, "-c", KILL_SCRIPT, str(ens_path), str(out), json.dumps([sizes, agx])]
    )
    try:
        deadline = time.monotonic() + 120
        while not list(out.glob("chunk-*.npz")):
            assert proc.poll() is None, "the run ended before writing a chunk"
            assert time.monotonic() < deadline, "no chunk written in 120 s"
            time.sleep(0.005)
        os.kill(proc.pid, signal.SIGKILL)
    finally:
        if proc.poll() is None:
            os.kill(proc.pid, signal.SIGKILL)
        proc.wait()
    finished = {p.name: p.stat().st_mtime_ns for p in out.glob("chunk-*.npz")}
    assert 0 < len(finished) < n_chunks, "kill -9 came too late to test resuming"
    assert len(finished) == 1

    resumed = overturning_probability(blocks, ens, agx, out=out, chunk_size=64)
    assert resumed.attrs["chunks_loaded"] == len(finished)
    assert resumed.attrs["chunks_computed"] == n_chunks - len(finished)
    assert all(out.joinpath(name).stat().st_mtime_ns == t for name, t in finished.items())
    xr.testing.assert_identical(_science(resumed), _science(reference))


def _curves_dataset(blocks, n=40):
    """A probability dataset shaped like overturning_probability's: lognormal curves with the
    median A_gx growing with R and falling with γ, Wilson intervals of n motions."""
    agx = np.round(np.arange(1, 16) * 0.1, 12)
    median = np.array([[0.4 * b.R / b.gamma**0.5] for b in blocks])
    count = np.round(n * LognormalFit(1.0, 0.3).probability(agx[None, :] / median)).astype(int)
    lo, hi = wilson_interval(count, n)
    dims = ("body", "agx")
    return xr.Dataset(
        {"probability": (dims, count / n), "ci_low": (dims, lo), "ci_high": (dims, hi)},
        coords={
            "body": [b.label for b in blocks],
            "agx": agx,
            "R": ("body", [b.R for b in blocks]),
            "gamma": ("body", [b.gamma for b in blocks]),
        },
        attrs={"confidence": 0.95},
    )


def _marked_lines(ax):
    return [line for line in ax.get_lines() if line.get_marker() == "o"]


def test_many_bodies_are_drawn_one_panel_per_size():
    # The paper's 72 bodies were 72 curves on one axis (12 named in the legend, the rest not);
    # now one panel per R with one curve per γ, coloured alike in every panel, γ named once.
    from rocking.dynamics.body import PAPER_GAMMAS, PAPER_R_FT, paper_bodies
    from rocking.plots.fragility import plot_fragility

    blocks = paper_bodies()
    ds = _curves_dataset(blocks)
    fits = {b.label: LognormalFit(0.4 * b.R / b.gamma**0.5, 0.3) for b in blocks}
    fig = plot_fragility(ds, fits=fits, title="72 bodies")
    assert [ax.get_title() for ax in fig.axes] == [
        f"R = {Block(f * 0.3048, 2).R:.2f} m" for f in PAPER_R_FT
    ]
    colours = None
    for ax, r_ft in zip(fig.axes, PAPER_R_FT):
        lines = _marked_lines(ax)
        assert len(lines) == len(PAPER_GAMMAS)  # one curve per γ
        mine = ds.sel(body=[Block(r_ft * 0.3048, g).label for g in PAPER_GAMMAS])
        for line, p in zip(lines, mine["probability"].values):
            np.testing.assert_array_equal(line.get_ydata(), p)
        assert len([li for li in ax.get_lines() if li.get_linestyle() == "--"]) == 9  # fits
        same = [line.get_color() for line in lines]
        assert colours is None or same == colours  # γ has one colour in every panel
        colours = same
    labels = [t.get_text() for t in fig.legends[0].get_texts()]
    assert labels == [f"γ = {g:g}" for g in PAPER_GAMMAS]


def test_few_bodies_share_one_axis_and_many_gammas_get_a_colour_bar():
    from rocking.plots.fragility import MAX_LEGEND, plot_fragility

    few = [Block(1.0, g) for g in (3.0, 4.0, 5.0)]
    fig = plot_fragility(_curves_dataset(few))
    assert len(fig.axes) == 1 and len(_marked_lines(fig.axes[0])) == 3
    assert [t.get_text() for t in fig.axes[0].get_legend().get_texts()] == [b.label for b in few]
    # 2 sizes x 14 slenderness values: two panels and a colour bar instead of 14 legend entries
    many = [Block(r, 2.0 + 0.25 * k) for r in (1.0, 2.0) for k in range(MAX_LEGEND + 2)]
    fig = plot_fragility(_curves_dataset(many))
    panels = [ax for ax in fig.axes if ax.get_title()]
    assert len(panels) == 2 and all(len(_marked_lines(ax)) == MAX_LEGEND + 2 for ax in panels)
    assert len(fig.axes) == 3 and not fig.legends  # the third axis is the colour bar
