"""Dimensionless intensity measures of rocking (issue 46): PGA/(g·tan α), PGV·p/(g·tan α) and
Ω = ω_p/p, and whether they predict overturning better than PGA and PGV (β)."""

from __future__ import annotations

import math

import numpy as np
import pytest

import rocking
from rocking.defaults import G
from rocking.montecarlo.dimensionless import dimensionless_efficiency, dimensionless_intensities
from rocking.montecarlo.fragility import POOLED

LEVELS = np.geomspace(0.05, 3.0, 16)  # [g], spanning the fragility of R = 0.3–3 m


@pytest.fixture(scope="module")
def ensemble():
    return rocking.generate(16, duration=10.0, seed=46)


def test_dimensionless_values_follow_their_definitions(ensemble):
    block = rocking.Block(1.0, 4.0)  # tan α = 1/4, p = sqrt(3g/4)
    table = dimensionless_intensities(block, ensemble)
    ims = rocking.intensity_measures(ensemble, ["pga", "pgv"])
    np.testing.assert_allclose(table["pga_over_uplift"], 4.0 * ims["pga [g]"], rtol=1e-12)
    p = math.sqrt(3 * G / 4)
    np.testing.assert_allclose(
        table["pgv_p_over_uplift"], ims["pgv [m/s]"] * p * 4.0 / G, rtol=1e-12
    )
    np.testing.assert_allclose(table["omega_ratio"], 2 * np.pi / (table["pulse_period"] * p))


@pytest.fixture(scope="module")
def ranking(ensemble):
    """im_efficiency of three blocks of one slenderness and sizes R = 0.3, 1 and 3 m."""
    blocks = [rocking.Block(R, 4.0) for R in (0.3, 1.0, 3.0)]
    return rocking.im_efficiency(
        blocks, ensemble, ["pga", "pgv", "pga/gtana", "pgv*p/gtana"], levels=LEVELS, n_boot=20
    )


def test_pooled_sizes_pgv_p_over_g_tan_alpha_predicts_better_than_pgv(ranking):
    # Similarity (Makris & Konstantinidis 2003, "The rocking spectrum and the limitations of
    # practical design methodologies", EESD 32; Dimitrakopoulos & DeJong 2012, "Revisiting the
    # rocking block: closed-form solutions and similarity laws", Proc. R. Soc. A 468): at one
    # slenderness the response depends on the motion through a_g/(g tan α) and p·t, so a larger
    # block needs a PGV larger about in proportion to 1/p (Housner's size effect).
    # PGV·p/(g·tan α) removes it, so one fragility fitted to blocks of R = 0.3, 1 and 3 m has a
    # much smaller β against it than against PGV or PGA (0.28 against 0.52 and 0.53 with these
    # 16 motions; 0.75 leaves room for other motions without admitting a tie)
    pooled = ranking[ranking["body"] == POOLED].set_index("im")
    beta = pooled["beta"]
    assert beta["pgv*p/gtana"] < 0.75 * min(beta["pgv"], beta["pga"])
    assert (pooled["beta_low"] <= beta).all() and (beta <= pooled["beta_high"]).all()
    # one slenderness: PGA/(g tan α) is 4·PGA for all three, the same pooled fit
    assert beta["pga/gtana"] == pytest.approx(beta["pga"], rel=1e-6)


def test_per_body_beta_of_a_dimensionless_im_is_that_of_its_dimensional_im(ranking):
    # For one body, PGA/(g tan α) = PGA·(G/(g tan α)) and PGV·p/(g tan α) = PGV·p/(g tan α):
    # a constant factor c shifts ln IM by ln c, which moves the lognormal's median by c and
    # leaves β unchanged (an invariant of the maximum-likelihood fit; equal to the optimiser's
    # tolerance, 1e-6); the bootstrap draws the same motions, so the intervals agree too.
    for body, rows in ranking[ranking["body"] != POOLED].groupby("body"):
        one = rows.set_index("im")
        for dimensionless, im in (("pga/gtana", "pga"), ("pgv*p/gtana", "pgv")):
            for col in ("beta", "beta_low", "beta_high"):
                assert one.loc[dimensionless, col] == pytest.approx(one.loc[im, col], rel=1e-6)
            assert f"the β of {im}" in one.loc[dimensionless, "note"], body
        # the medians differ by that constant: g·tan α = G/4 for γ = 4
        assert one.loc["pga/gtana", "median"] == pytest.approx(
            4.0 * one.loc["pga", "median"], rel=1e-6
        )


def test_dimensionless_efficiency_of_one_body_has_the_betas_of_pga_and_pgv(ensemble):
    one = dimensionless_efficiency(rocking.Block(1.0, 4.0), ensemble, levels=LEVELS)
    one = one.set_index("im")
    # one body: a constant factor leaves β unchanged, to the fit optimiser's tolerance (1e-6)
    assert one.loc["pga/gtana", "beta"] == pytest.approx(one.loc["pga", "beta"], rel=1e-6)
    assert one.loc["pgv*p/gtana", "beta"] == pytest.approx(one.loc["pgv", "beta"], rel=1e-6)
    assert (one.loc["pga", "unit"], one.loc["pga/gtana", "unit"]) == ("g", "-")


def test_im_efficiency_refuses_an_im_that_scaling_does_not_change(ensemble):
    with pytest.raises(rocking.InputError, match="omega does not change when a motion is scaled"):
        rocking.im_efficiency(rocking.Block(1.0, 4.0), ensemble, ["pgv", "omega"], levels=LEVELS)
