"""The adaptive search of rocking.agx_50 on its own (rocking.montecarlo.search.CrossingSearch):
checked against brute force on given probability functions, no simulation."""

import numpy as np
import pytest

from rocking.errors import InputError
from rocking.montecarlo.search import CrossingSearch


def run(search, prob):
    """Drive ``search`` with ``prob[item](k)``; return the crossings and the levels each item
    asked for."""
    asked: dict = {}
    while level := search.pending():
        for item, k in level.items():
            asked.setdefault(item, []).append(k)
        search.update({item: prob[item](k) >= 0.5 for item, k in level.items()})
    return search.crossings(), asked


@pytest.mark.parametrize("coarse", [1, 3, 10, 500])
def test_monotone_probability_gives_the_first_level_at_or_above_half(coarse):
    # brute force: for a step at k0 (P = 0 below, 1 from k0 on) the answer is k0, for every k0
    K = 500
    items = list(range(1, K + 1))
    search = CrossingSearch(items, K, coarse)
    found, asked = run(search, {k0: (lambda k, k0=k0: float(k >= k0)) for k0 in items})
    assert found == {k0: k0 for k0 in items}
    # and no item asks for more levels than the bound used to size the memory
    assert max(len(levels) for levels in asked.values()) <= search.max_levels


def test_never_half_has_no_crossing_and_non_monotone_is_an_upward_crossing():
    rng = np.random.default_rng(3)
    K = 200
    tables = {i: rng.random(K + 1) for i in range(300)}  # P(k) random: far from monotone
    tables[-1] = np.zeros(K + 1)  # never reaches 50 %
    prob = {i: (lambda k, t=t: t[k] if k > 0 else 0.0) for i, t in tables.items()}
    found, _ = run(CrossingSearch(list(tables), K, 7), prob)
    assert -1 not in found
    for i, k in found.items():  # the definition of the result: P(hi) >= 0.5 > P(hi - 1)
        assert prob[i](k) >= 0.5 > prob[i](k - 1)
    assert len(found) > 250  # (a random table crosses 50 % in the first bracket almost surely)


def test_bad_arguments_are_named():
    with pytest.raises(InputError, match="coarse"):
        CrossingSearch([0], 10, 0)
    with pytest.raises(InputError, match="K must"):
        CrossingSearch([0], 0, 3)
