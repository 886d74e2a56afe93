"""Dimensionless intensity measures of rocking (issue 46): PGA/(g·tan α), PGV·p/(g·tan α) and
Ω = ω_p/p, and whether they predict overturning better than PGA and PGV (β)."""

from __future__ import annotations

import math

import numpy as np
import pytest

import rocking
from rocking.defaults import G
from rocking.montecarlo.dimensionless import dimensionless_efficiency, dimensionless_intensities

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


def test_pooled_sizes_pgv_p_over_g_tan_alpha_predicts_better_than_pgv(ensemble):
    # Housner's size effect: at one slenderness, a larger block needs a larger PGV to overturn,
    # about in proportion to 1/p; PGV·p/(g·tan α) removes it, so one fragility fitted to blocks
    # of R = 0.3, 1 and 3 m has a much smaller β against it than against PGV or PGA
    blocks = [rocking.Block(R, 4.0) for R in (0.3, 1.0, 3.0)]
    table = dimensionless_efficiency(blocks, ensemble, levels=LEVELS).set_index("im")
    beta = table["beta"]
    assert beta["pgv p/(g tan alpha)"] < 0.75 * min(beta["pgv"], beta["pga"])
    # one body: the dimensionless measures are PGA and PGV times a constant, the same β
    one = dimensionless_efficiency(blocks[1], ensemble, levels=LEVELS).set_index("im")
    assert one.loc["pga/(g tan alpha)", "beta"] == pytest.approx(one.loc["pga", "beta"], rel=1e-6)
    assert one.loc["pgv p/(g tan alpha)", "beta"] == pytest.approx(one.loc["pgv", "beta"], rel=1e-6)
    # and the medians by that constant: g·tan α = G/4 for γ = 4
    assert one.loc["pga/(g tan alpha)", "median"] == pytest.approx(
        4.0 * one.loc["pga", "median"], rel=1e-6
    )
