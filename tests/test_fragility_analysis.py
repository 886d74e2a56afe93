"""IDA, multiple-stripe and cloud analysis (rocking.fragility_analysis) and the ranking of
intensity measures (rocking.im_efficiency).

The batched kernel is checked elsewhere against the scalar rocking.simulate and SciPy; here the
question is whether each motion is scaled as the method says.  The reference for every outcome
is an independent path: the motion scaled by hand with NumPy and integrated by rocking.simulate
(the scalar integrator, not the batched kernel the analyses use), its IM computed from the scaled
motion by rocking.intensity_measures."""

import math

import numpy as np
import pandas as pd
import pytest

import rocking
from rocking.defaults import G
from rocking.errors import InputError
from rocking.montecarlo.engine import scale_factors
from rocking.montecarlo.statistics import ExtrapolationWarning

BLOCKS = [rocking.Block(1.0, 4.0), rocking.Block(2.0, 3.0)]


@pytest.fixture(scope="module")
def ens():
    return rocking.generate(8, duration=10.0, dt=1 / 200, seed=5)


def by_hand(block, ens, factors):
    """Overturned flags of every motion scaled by ``factors`` (one per motion), by simulate."""
    return np.array(
        [rocking.simulate(block, f * a, ens.dt).overturned for f, a in zip(factors, ens.acc)]
    )


def test_ida_scales_every_motion_to_its_own_im_level(ens):
    levels = np.array([0.3, 0.6, 0.9])
    ds = rocking.fragility_analysis(
        BLOCKS, ens, im="pgv", method="ida", levels=levels, n_boot=20, progress=False
    )
    pgv = rocking.intensity_measures(ens, "pgv").iloc[:, 0].to_numpy()
    for b, block in enumerate(BLOCKS):
        for i, level in enumerate(levels):
            factors = level / pgv
            # the scaled motions have the level as their PGV (to rounding)
            scaled = rocking.Ensemble(ens.acc * factors[:, None], ens.dt)
            np.testing.assert_allclose(
                rocking.intensity_measures(scaled, "pgv").iloc[:, 0], level, rtol=1e-12
            )
            np.testing.assert_array_equal(
                ds["overturned"].values[b, i], by_hand(block, ens, factors)
            )
    assert (ds["count"].values == ds["overturned"].values.sum(axis=2)).all()
    assert ds.attrs["im"] == "pgv" and ds["level"].attrs["units"] == "m/s"


def test_arias_levels_scale_by_the_square_root(ens):
    # Arias intensity grows as the square of the scale factor: a motion scaled by
    # (level/I_A)^(1/2) has Arias intensity = level
    ia = rocking.intensity_measures(ens, "arias").iloc[:, 0].to_numpy()
    factors = scale_factors(0.5, ia, 2)
    scaled = rocking.Ensemble(ens.acc * factors[:, None], ens.dt)
    np.testing.assert_allclose(rocking.intensity_measures(scaled, "arias").iloc[:, 0], 0.5)


def test_agx_ida_is_the_papers_overturning_probability(ens):
    levels = [0.2, 0.5, 0.8]
    ds = rocking.fragility_analysis(BLOCKS, ens, method="ida", levels=levels, progress=False)
    ref = rocking.overturning_probability(BLOCKS, ens, levels, progress=False)
    np.testing.assert_array_equal(ds["count"].values, ref["count"].values)


def test_msa_uses_each_stripes_factors_and_levels(ens):
    rows = [
        {"level": 0.25 * k, "motion": ens.labels[j], "scale": 0.5 + 0.3 * k + 0.05 * j}
        for k in (1, 2, 3)
        for j in range(ens.n)
    ]
    stripes = pd.DataFrame(rows)
    ds = rocking.fragility_analysis(
        BLOCKS, ens, im="pga", method="msa", stripes=stripes, n_boot=20, progress=False
    )
    np.testing.assert_allclose(ds["level"].values, [0.25, 0.5, 0.75])
    for b, block in enumerate(BLOCKS):
        for i, (_, stripe) in enumerate(stripes.groupby("level")):
            expected = by_hand(block, ens, stripe["scale"].to_numpy())
            np.testing.assert_array_equal(ds["overturned"].values[b, i], expected)


def test_cloud_takes_the_motions_as_they_are(ens):
    strong = rocking.Ensemble(ens.acc * 3.0, ens.dt, ens.labels)  # some overturn, some not
    ds = rocking.fragility_analysis(BLOCKS, strong, im="pgv", method="cloud", progress=False)
    np.testing.assert_allclose(
        ds["im_value"].values, rocking.intensity_measures(strong, "pgv").iloc[:, 0]
    )
    for b, block in enumerate(BLOCKS):
        np.testing.assert_array_equal(
            ds["overturned_motion"].values[b], by_hand(block, strong, np.ones(strong.n))
        )
    assert ds["n"].values.sum(axis=1).tolist() == [strong.n] * len(BLOCKS)


def test_bad_requests_are_refused_with_the_reason(ens):
    with pytest.raises(InputError, match="does not change when a motion is scaled"):
        rocking.fragility_analysis(BLOCKS, ens, im="pgv/pga", levels=[1.0], progress=False)
    with pytest.raises(InputError, match="needs levels"):
        rocking.fragility_analysis(BLOCKS, ens, im="pgv", progress=False)
    with pytest.raises(InputError, match="needs stripes"):
        rocking.fragility_analysis(BLOCKS, ens, method="msa", progress=False)
    with pytest.raises(InputError, match="method must be one of"):
        rocking.fragility_analysis(BLOCKS, ens, method="bogus", levels=[1.0], progress=False)
    with pytest.raises(InputError, match="row 1: no motion 'nope'"):
        rocking.fragility_analysis(
            BLOCKS,
            ens,
            method="msa",
            stripes=pd.DataFrame({"level": [0.1], "motion": ["nope"], "scale": [1.0]}),
            progress=False,
        )
    with pytest.raises(InputError, match="same number of motions"):
        rocking.fragility_analysis(
            BLOCKS,
            ens,
            method="msa",
            stripes=pd.DataFrame({"level": [0.1, 0.2, 0.2], "motion": [0, 1, 2], "scale": 1.0}),
            progress=False,
        )
    with pytest.raises(InputError, match="pgv/pga does not change"):
        rocking.im_efficiency(BLOCKS, ens, ["pgv", "pgv/pga"], levels=[0.5], progress=False)


def test_im_efficiency_of_the_scaling_im_is_the_ida_fit(ens):
    # Two likelihoods, two code paths: binomial counts per level (fragility_analysis) and one
    # Bernoulli point per (motion, level) run (im_efficiency); they are the same function of
    # (median, beta), so the maximum-likelihood fits agree to the optimiser's tolerance.
    levels = np.round(np.arange(0.1, 1.55, 0.1), 12)
    table = rocking.im_efficiency(
        BLOCKS, ens, ["pga", "pgv"], levels=levels, n_boot=20, progress=False
    )
    ida = rocking.fragility_analysis(BLOCKS, ens, im="pga", levels=levels, n_boot=1, progress=False)
    for b in range(len(BLOCKS)):
        row = table[(table["body"] == ida["body"].values[b]) & (table["im"] == "pga")].iloc[0]
        assert row["median"] == pytest.approx(float(ida["median"][b]), rel=1e-5)
        assert row["beta"] == pytest.approx(float(ida["beta"][b]), rel=1e-4)
        assert row["beta_low"] <= row["beta"] <= row["beta_high"]
    # sorted by body, then from the most efficient IM (smallest beta)
    for _, rows in table.groupby("body", sort=False):
        assert rows["beta"].is_monotonic_increasing


def test_floor_fragility_against_the_ground_im_is_the_buildings_response(ens):
    # A floor motion of a linear frame scales with its ground motion: the IDA of the floor
    # motions with the ground motions' PGV as im_values must count what the frame gives when
    # each GROUND motion is scaled to the level first and then filtered (ShearFrame and
    # simulate, no per-motion factor on the floor).
    frame = rocking.ShearFrame.preset("paper-1.0")
    floor = frame.floor_ensemble(ens, 2)
    ground_pgv = rocking.intensity_measures(ens, "pgv").iloc[:, 0].to_numpy()
    level = 0.4
    ds = rocking.fragility_analysis(
        BLOCKS, floor, im="pgv", levels=[level], im_values=ground_pgv, n_boot=0, progress=False
    )
    scaled_ground = rocking.Ensemble(ens.acc * (level / ground_pgv)[:, None], ens.dt)
    by_frame = frame.floor_ensemble(scaled_ground, 2)
    for b, block in enumerate(BLOCKS):
        expected = [rocking.simulate(block, a, ens.dt).overturned for a in by_frame.acc]
        np.testing.assert_array_equal(ds["overturned"].values[b, 0], expected)


def test_screen_with_a_hazard_curve_gives_each_item_its_annual_rate(tmp_path):
    # Under a power-law PGV hazard, each item's rate must be Cornell's closed form for the
    # lognormal the screening fitted (Cornell et al. 2002): the hazard table spans 1e-3 to
    # 1e2 m/s, far beyond the fragility, so the tails are below 1e-9 of the rate.
    k0, k = 1e-4, 2.0
    x = np.geomspace(1e-3, 1e2, 41)
    hazard = tmp_path / "pgv.csv"
    pd.DataFrame({"pgv [m/s]": x, "annual_rate": k0 * x**-k}).to_csv(hazard, index=False)
    inventory = tmp_path / "inv.csv"
    inventory.write_text("name,R,gamma,location\nslim,0.8,5,ground\nup,0.8,4,floor 2\n")
    ds = rocking.screen(
        inventory,
        "asce7:SDS=1.0,SD1=0.6,TL=8",
        frame="paper-1.0",
        n=8,
        duration=8.0,
        dt=1 / 200,
        hazard=hazard,
        years=10.0,
        progress=False,
    )
    # The levels of the fits span the hazard table, so its extremes never overturn or always do:
    # the fits must still be finite
    assert np.isfinite(ds["fragility_median"]).all()
    for item in ds["item"].values:
        row = ds.sel(item=item)
        median, beta = float(row["fragility_median"]), float(row["fragility_beta"])
        exact = k0 * median**-k * math.exp(k**2 * beta**2 / 2)
        assert float(row["annual_rate"]) == pytest.approx(exact, rel=1e-6)
        assert float(row["p_years"]) == pytest.approx(-math.expm1(-10 * exact), rel=1e-9)
    with pytest.raises(InputError, match="floor_motions='building'"):
        rocking.screen(
            inventory,
            "asce7:SDS=1.0,SD1=0.6,TL=8",
            frame="paper-1.0",
            n=4,
            duration=4.0,
            hazard=hazard,
            floor_motions="paper",
            progress=False,
        )


def test_vertical_components_go_with_their_motions(ens):
    # Each motion's vertical component is scaled with it: the IDA counts what simulate gives
    # with (f·a_g, f·a_v) for the motion's own factor f (the batched kernel and the scalar
    # integrator, each with a_v, are compared bit for bit in tests/test_vertical.py).
    av = ens.acc[::-1]  # another motion of the ensemble as the vertical: as strong as a_g
    both = rocking.Ensemble(ens.acc, ens.dt, ens.labels, av=av)
    levels = [0.3, 0.5, 0.7]
    ds = rocking.fragility_analysis(BLOCKS, both, im="pga", levels=levels, n_boot=0, progress=False)
    for i, level in enumerate(levels):
        factors = level / both.pga
        for b, block in enumerate(BLOCKS):
            expected = [
                rocking.simulate(block, f * a, both.dt, av=f * v).overturned
                for f, a, v in zip(factors, both.acc, av)
            ]
            np.testing.assert_array_equal(ds["overturned"].values[b, i], expected)
    # and the vertical motion matters here (else the test could not tell)
    flat = rocking.fragility_analysis(
        BLOCKS, ens, im="pga", levels=levels, n_boot=0, progress=False
    )
    assert not np.array_equal(flat["overturned"].values, ds["overturned"].values)


def test_scaling_a_vertical_to_minus_g_is_refused_before_any_run(ens):
    # A constant vertical of -0.4 g scaled by more than 2.5 reaches -g (the block would lift
    # off: not modelled). IDA to a PGA of 2.5 x the weakest motion's PGA is the limit.
    av = np.full_like(ens.acc, -0.4 * G)
    both = rocking.Ensemble(ens.acc, ens.dt, ens.labels, av=av)
    weakest = int(np.argmin(both.pga))
    ok = 2.49 * both.pga[weakest]
    rocking.fragility_analysis(BLOCKS[:1], both, im="pga", levels=[ok], n_boot=0, progress=False)
    expected = rf"motion '{both.labels[weakest]}' scaled by 2.6.*-1.04 g"
    with pytest.raises(InputError, match=expected):
        rocking.fragility_analysis(
            BLOCKS[:1], both, im="pga", levels=[2.6 * both.pga[weakest]], n_boot=0, progress=False
        )
    stripes = pd.DataFrame({"level": [1.0, 1.0], "motion": [0, 1], "scale": [1.0, 2.6]})
    with pytest.raises(InputError, match=r"stripes: motion .* scaled by 2\.6"):
        rocking.fragility_analysis(
            BLOCKS[:1], both, im="pga", method="msa", stripes=stripes, n_boot=0, progress=False
        )


def test_im_efficiency_intervals_are_those_of_each_resample_fitted_alone(ens):
    # im_efficiency fits its bootstrap resamples all at once: each β must be the cloud fit of
    # that resample alone (the same NumPy draws: one resample of the motions per bootstrap
    # round, whole motions), so the interval is the quantiles of those fits, to the bit.
    levels = np.array([0.2, 0.4, 0.6, 0.8, 1.0])
    table = rocking.im_efficiency(BLOCKS[0], ens, ["pgv"], levels=levels, n_boot=30, seed=3)
    base = rocking.intensity_measures(ens, "pga").iloc[:, 0].to_numpy()
    factors = levels[:, None] / base[None, :]
    x = rocking.intensity_measures(ens, "pgv").iloc[:, 0].to_numpy()[None, :] * factors
    ida = rocking.fragility_analysis(
        BLOCKS[0], ens, im="pga", method="ida", levels=levels, n_boot=0, progress=False
    )
    y = ida["overturned"].values[0]
    rng = np.random.default_rng(3)
    betas = []
    for _ in range(30):
        j = rng.integers(0, ens.n, ens.n)
        xb, yb = x[:, j].ravel(), y[:, j].ravel()
        if yb.any() and not yb.all():
            betas.append(rocking.fit_lognormal(xb, yb.astype(int), 1).beta)
    low, high = np.quantile(betas, [(1 - 0.95) / 2, (1 + 0.95) / 2])
    assert table["beta_low"].iloc[0] == low and table["beta_high"].iloc[0] == high


def test_im_efficiency_in_blocks_of_resamples_is_the_same(ens, monkeypatch):
    # the bootstrap resamples are fitted a block at a time (memory): blocks of 4 resamples
    # must give the table that one block gives, to the bit
    from rocking.montecarlo import fragility

    levels = np.array([0.2, 0.4, 0.6, 0.8, 1.0])
    args = (BLOCKS[0], ens, ["pgv", "arias"])
    whole = rocking.im_efficiency(*args, levels=levels, n_boot=30, seed=3)
    monkeypatch.setattr(fragility, "_FIT_BLOCK_ELEMENTS", 4 * levels.size * ens.n)
    pd.testing.assert_frame_equal(
        rocking.im_efficiency(*args, levels=levels, n_boot=30, seed=3), whole, check_exact=True
    )


def test_a_median_beyond_the_levels_tested_is_flagged_and_warned(ens):
    # issue 48: a median at or beyond the highest level tested (the transformer's 1.52 m/s
    # against 1.5 m/s) was reported without a word. Up to 0.9 g the stocky block overturns
    # in at most 2 of the 8 motions (4 of 8 is first reached at 1.0 g, in the IDA to 1.5 g of
    # test_im_efficiency_of_the_scaling_im_is_the_ida_fit's levels), so its fitted median lies
    # beyond 0.9 g; the slender one reaches 4 of 8 at 0.6 g, inside the levels.
    levels = np.round(np.arange(0.1, 0.95, 0.1), 12)
    with pytest.warns(ExtrapolationWarning) as caught:
        ds = rocking.fragility_analysis(BLOCKS, ens, im="pga", levels=levels, progress=False)
    assert ds["count"].values[1].max() <= 2 and ds["count"].values[0].max() >= 4
    assert ds["median_extrapolated"].values.tolist() == [False, True]
    assert float(ds["median"][1]) > 0.9
    assert len(caught) == 1 and BLOCKS[1].label in str(caught[0].message)
    assert "0.9 g" in str(caught[0].message)


def test_one_block_is_taken_as_a_list_of_one(ens):
    # issue 48: overturning_probability(block, ...) raised "'Block' object is not iterable";
    # every function that takes bodies takes one Block as the list of that Block
    block = BLOCKS[0]
    calls = {
        "overturning_probability": lambda b: rocking.overturning_probability(
            b, ens, [0.4, 0.8], progress=False
        ),
        "member_outcomes": lambda b: rocking.member_outcomes(b, ens, [0.6], progress=False),
        "agx_50": lambda b: rocking.agx_50(
            b, ens, resolution=0.1, agx_max=1.5, coarse=3, progress=False
        ),
        "fragility_analysis": lambda b: rocking.fragility_analysis(
            b, ens, im="pgv", levels=[0.3, 0.9], n_boot=5, progress=False
        ),
        "energy_balance": lambda b: rocking.energy_balance(b, ens, [0.6]),
        "assess": lambda b: rocking.assess(b, ens),
    }
    for name, call in calls.items():
        one, listed = call(block), call([block])
        assert one.identical(listed), name
        assert one.sizes["body"] == 1, name


def test_an_ensemble_prints_a_summary_not_its_arrays(ens):
    # issue 48: repr(Ensemble) dumped the accelerations and the metadata's lists (~10 kB)
    text = repr(ens)
    assert text == (
        f"Ensemble(8 motions, dt = 0.005 s, 10 s, ground, A_gx = {ens.agx:.4g} g, simulated)"
    )
