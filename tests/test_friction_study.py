"""The friction study beyond the paper (``rocking reproduce friction``, issue 45): its numbers
against direct calls of the library, its limits (μ large: the paper's results; μ below every
body's B/H: sliding only) and its summary written from the results."""

import math

import numpy as np
import pytest
import xarray as xr

from rocking import Block, Physics, agx_50, generate, simulate
from rocking.assessment.energy import energy_balance
from rocking.assessment.screen import RESPONSES
from rocking.errors import InputError
from rocking.montecarlo.probability import member_outcomes
from rocking.montecarlo.search import Agx50Search
from rocking.studies import friction
from rocking.studies.friction import LEVELS, friction_study, summary

#: A small configuration: a stocky (B/H = 1/2) and a slender body (B/H = 1/6), six short
#: compound motions, a coarse A_gx grid.
BODIES = [Block(1.0, 2.0), Block(1.0, 6.0)]
SEARCH = Agx50Search(resolution=0.1, agx_max=2.0)


@pytest.fixture(scope="module")
def motions():
    return generate(6, duration=6.0, dt=1 / 200, seed=3)


#: The calls of member_outcomes and of energy_balance made by the study of the fixture ``study``.
CALLS: list[str] = []


@pytest.fixture(scope="module")
def study(motions):
    def counted(f):
        def call(*args, **kwargs):
            CALLS.append(f.__name__)
            return f(*args, **kwargs)

        return call

    with pytest.MonkeyPatch.context() as mp:
        for f in (member_outcomes, energy_balance):
            mp.setattr(friction, f.__name__, counted(f))
        return friction_study(BODIES, motions, [0.3, 0.6], search=SEARCH)


def test_agx50_is_that_of_agx_50_with_the_friction(study, motions):
    for mu in (0.3, 0.6, math.inf):
        physics = Physics() if math.isinf(mu) else Physics(mu=mu)
        direct = agx_50(BODIES, motions, search=SEARCH, physics=physics)["agx50"].values
        np.testing.assert_array_equal(study["agx50"].sel(mu=mu).values, direct)
    paper = study["agx50"].sel(mu=math.inf).values
    # Table 3 at μ: energy_balance at the row's A_gx50, bit for bit (S_v1 = sv1_per_g · A_gx50)
    for mu in (0.3, 0.6, math.inf):
        table3 = energy_balance(BODIES, motions, study["agx50"].sel(mu=mu).values)
        np.testing.assert_array_equal(study["ratio"].sel(mu=mu).values, table3["ratio"].values)
    # so S_v1 scales with A_gx50, S_v does not (to rounding: rtol 1e-12)
    np.testing.assert_allclose(
        study["ratio"].sel(mu=0.3).values,
        study["ratio"].sel(mu=math.inf).values * study["agx50"].sel(mu=0.3).values / paper,
        rtol=1e-12,
    )


def test_shares_count_the_modes_of_single_simulations(study, motions):
    # the shares at each body's A_gx50 equal a count over rocking.simulate with the friction
    for mu in (0.3, 0.6):
        for level in LEVELS:
            at = study.sel(mu=mu, level=level)
            # the level: A_gx50 with this μ, or with infinite friction
            agx50 = at["agx50"] if level == LEVELS[0] else study["agx50"].sel(mu=math.inf)
            for b, block in enumerate(BODIES):
                agx = float(agx50[b])
                if not math.isfinite(agx):
                    assert np.isnan(at["share"][b]).all()
                    continue
                acc = motions.scaled(agx).acc
                runs = [simulate(block, a, motions.dt, mu=mu) for a in acc]
                ov = np.array([r.overturned for r in runs])
                slid = np.array([r.max_abs_slip > 0.0 for r in runs]) & ~ov
                up = np.array([r.uplift for r in runs]) & ~ov
                expected = [~slid & ~up & ~ov, slid & ~up, ~slid & up, slid & up, ov]
                got = at["share"].isel(body=b).sel(mode=list(RESPONSES)).values
                np.testing.assert_array_equal(got, [m.mean() for m in expected])
                slips = [r.max_abs_slip for r, o in zip(runs, ov) if not o]
                if slips:  # the batched kernel's peak slip is simulate's (same model)
                    assert float(at["max_slip"][b]) == pytest.approx(
                        max(slips), rel=1e-9, abs=1e-12
                    )


def test_each_row_simulated_once_and_the_spectrum_computed_once(study, motions):
    # both levels of a row (A_gx50 with μ and with infinite friction) in one member_outcomes
    # call: its chunk folder opened and read once per row (was twice); the ensemble's mean
    # spectrum, the same for every row, in one energy_balance call (was one per row)
    assert CALLS.count("member_outcomes") == study["mu"].size == 3
    assert CALLS.count("energy_balance") == 1
    with pytest.raises(InputError, match=r"agx must hold one intensity or one row .* \(2 bodies\)"):
        friction.mode_shares(BODIES, motions, [1.0])
    with pytest.raises(InputError, match=r"agx must hold one intensity .* got shape \(\)"):
        friction.mode_shares(BODIES, motions, 1.0)


def test_kinetic_ratio_sets_mu_k_of_every_row(motions):
    # kinetic_ratio = μ_k/μ: each finite row is agx_50 with Physics(mu=μ, mu_k=ratio·μ), the
    # infinite row the paper's; the shares too come from simulations with that μ_k
    ds = friction_study(BODIES, motions, [0.6], search=SEARCH, kinetic_ratio=0.5)
    assert ds.attrs["kinetic_ratio"] == 0.5
    direct = agx_50(BODIES, motions, search=SEARCH, physics=Physics(mu=0.6, mu_k=0.3))
    np.testing.assert_array_equal(ds["agx50"].sel(mu=0.6).values, direct["agx50"].values)
    paper = agx_50(BODIES, motions, search=SEARCH)["agx50"].values
    np.testing.assert_array_equal(ds["agx50"].sel(mu=math.inf).values, paper)
    at = ds.sel(mu=0.6, level=LEVELS[1]).isel(body=0)  # the stocky body at the paper's A_gx50
    acc = motions.scaled(float(paper[0])).acc
    runs = [simulate(BODIES[0], a, motions.dt, mu=0.6, mu_k=0.3) for a in acc]
    fell = np.mean([r.overturned for r in runs])
    assert float(at["share"].sel(mode="overturn")) == fell
    with pytest.raises(InputError, match=r"kinetic_ratio must lie in \(0, 1\]"):
        friction_study(BODIES, motions, [0.6], search=SEARCH, kinetic_ratio=1.2)
    for mus in ([], [0.6, 0.6]):  # refused before any search (the summary needs a μ)
        with pytest.raises(InputError, match="mus must hold at least one friction coefficient"):
            friction_study(BODIES, motions, mus, search=SEARCH)
    # one chunk folder per row, infinite friction's too: fewer would leave rows out unseen
    with pytest.raises(InputError, match="stores must hold 2 folders"):
        friction_study(BODIES, motions, [0.6], search=SEARCH, stores=[None])


def test_large_friction_gives_the_papers_results_bit_for_bit(motions):
    # μ = 1000 exceeds any friction demand of these motions while the body stands: it only
    # rocks, as in the paper's model (issue 45: "μ → ∞ gives today's results bit for bit");
    # only as it falls does it slip, and overturned motions are counted apart
    ds = friction_study(BODIES, motions, [1000.0], search=SEARCH)
    big, inf = ds.sel(mu=1000.0), ds.sel(mu=math.inf)
    for name in ("agx50", "ratio", "share", "max_slip"):
        np.testing.assert_array_equal(big[name].values, inf[name].values, err_msg=name)
    assert (inf["share"].sel(mode=["slide", "slide-rock"]) == 0).all()


def test_friction_below_every_b_over_h_makes_every_moving_case_slide(motions):
    # μ < B/H: the base slips before the body can tip (|a_g| > μg comes before g·tan α), and
    # sliding with μ < tan α cannot tip it onto a corner (Shenton 1996): it slides, never rocks
    bodies = [Block(1.0, 2.0), Block(1.0, 3.0)]  # B/H = 1/2 and 1/3
    ds = friction_study(bodies, motions, [0.2], search=SEARCH)
    at_paper = ds.sel(mu=0.2, level=LEVELS[1])
    assert np.isnan(ds["agx50"].sel(mu=0.2)).all()  # never overturns: 50 % not reached
    assert (at_paper["share"].sel(mode=["rock", "slide-rock"]) == 0).all()
    assert (at_paper["share"].sel(mode="overturn") == 0).all()
    assert (at_paper["share"].sel(mode="slide") > 0).all()  # the paper's A_gx50 moves them
    assert (at_paper["max_slip"] > 0).all()


def _synthetic(agx50_mu, agx50_inf, shares, max_slip=0.12, b_over_h=(0.5, 0.2)) -> xr.Dataset:
    """A friction_study result for one μ (0.4) and two bodies, from given numbers."""
    mus = [0.4, math.inf]
    agx50 = np.array([agx50_mu, agx50_inf])
    share = np.zeros((2, 2, 2, len(RESPONSES)))
    share[0, :, 0, :] = shares
    share[0, :, 1, :] = [0.0, 0.6, 0.0, 0.3, 0.1]  # at the paper's A_gx50
    share[1, :, :, 2] = 1.0
    return xr.Dataset(
        {
            "agx50": (("mu", "body"), agx50),
            "change": (("mu", "body"), agx50 / agx50[-1] - 1.0),
            "ratio": (("mu", "body"), agx50),
            "share": (("mu", "body", "level", "mode"), share),
            "max_slip": (("mu", "body", "level"), np.full((2, 2, 2), max_slip)),
        },
        coords={
            "mu": mus,
            "body": ["stocky", "slender"],
            "level": list(LEVELS),
            "mode": list(RESPONSES),
            "b_over_h": ("body", list(b_over_h)),
        },
        attrs={"agx_max": 3.0},
    )


def test_summary_reports_friction_raising_agx50_and_bodies_that_stop_overturning():
    # rest, slide, rock, slide-rock, overturned
    shares = [[0.0, 0.0, 0.3, 0.2, 0.5], [0.0, 0.3, 0.0, 0.5, 0.2]]
    text = summary(_synthetic([np.nan, 0.9], [1.0, 0.75], shares))
    # slender body: 0.9 / 0.75 − 1 = +20 %, raised by friction; the stocky one slides instead
    assert "+20.0 %" in text and "higher in 1" in text
    assert "raises A_gx50 most for slender (B/H = 0.2) at μ = 0.4 (+20.0 %), presumably" in text
    # the same rise at μ = B/H is named as the boundary between slipping and tipping first
    edge = summary(_synthetic([np.nan, 0.9], [1.0, 0.75], shares, b_over_h=(0.5, 0.4)))
    assert "(+20.0 %), at μ = B/H, the boundary between slipping first" in edge
    assert "In 1 pair the body no longer overturns" in text
    # the stocky body at the paper's A_gx50 (level 1 of the synthetic data: overturned 0.1)
    assert "stocky (B/H = 0.5) at μ = 0.4: at the paper's A_gx50 it overturns in 10 %" in text
    assert "and 90 % slide it, by up to 0.12 m" in text
    assert (
        "up to 80 % of the motions make a body slide or slide-rock without overturning it " in text
    )
    assert "(slender at μ = 0.4), with slips up to 0.12 m" in text
    assert "overturning probability with friction is 0.10–0.10" in text
    lowered = summary(_synthetic([0.8, 0.6], [1.0, 0.75], shares))
    assert "−" not in lowered and "-20.0 % to -20.0 %" in lowered and "higher in 0" in lowered
    assert "raises" not in lowered and "no longer overturns" not in lowered
