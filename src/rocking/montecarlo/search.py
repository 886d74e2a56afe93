"""The adaptive grid search of :func:`rocking.agx_50`, as a pure state machine (no simulation).

Levels are integers k = 1 … K of a grid (A_gx = k·resolution in :func:`rocking.agx_50`); the
caller evaluates, round after round, the levels that :meth:`CrossingSearch.pending` asks for
(one level per item still searching) and reports for each whether the probability there is at
least 50 %.  Each item's search:

1. bracket: ``coarse`` evenly spread levels (the last is K) in increasing order until one is at
   or above 50 %; the bracket is (the previous coarse level or 0, that level).  If none is, the
   item has no crossing;
2. bisection on the integer levels inside the bracket, keeping P(lo) < 0.5 ≤ P(hi), until
   hi = lo + 1.

The result ``hi`` is an upward crossing of 50 % on the grid: P(hi) ≥ 0.5 and P(hi − 1) < 0.5
(P(0) = 0).  Where P is monotone on the grid it is the smallest level with P ≥ 0.5.
"""

from __future__ import annotations

import dataclasses
import math
from collections.abc import Hashable, Iterable, Mapping
from typing import Generic, TypeVar

from ..errors import InputError

Item = TypeVar("Item", bound=Hashable)


@dataclasses.dataclass(frozen=True)
class Agx50Search:
    """The settings of the search for the A_gx of 50 % overturning probability
    (:func:`rocking.agx_50`, :func:`rocking.screen`).

    Parameters
    ----------
    resolution : float
        Grid step of A_gx [g] (the paper reads A_gx to 0.01 g).
    agx_max : float
        Largest A_gx searched [g], ≥ resolution; A_gx50 is NaN above it.
    coarse : int
        Levels of the bracketing round (≥ 1).
    exhaustive : bool
        Simulate every motion at every level the search visits (the same result, with more
        simulations; a chunk folder then holds every count).
    same_motions : bool
        The ensembles of a dict are the same motions in other forms (e.g. sampled at other time
        steps): the cases are searched one after the other, in the dict's order, and each
        simulates first the motions whose outcome at a level another case already knows
        decides the comparison with n/2 (the same result, with fewer simulations when the
        outcomes mostly agree).  Needs ensembles of the same number of motions.
    """

    resolution: float = 0.01
    agx_max: float = 5.0
    coarse: int = 10
    exhaustive: bool = False
    same_motions: bool = False


def motions_to_decide(n: int, overturned: int, safe: int) -> int:
    """Fewest further motions whose outcomes could decide whether at least half of ``n`` motions
    overturn the body (2·count ≥ n), when ``overturned`` motions are known to overturn it and
    ``safe`` known not to; 0 when it is decided.

    It is decided above once 2·overturned ≥ n, below once even every motion not yet known
    overturning leaves 2·(n − safe) < n.  Asking for exactly this many never simulates a motion
    beyond the first point, in a fixed order of the motions, where the answer is decided.
    """
    if overturned < 0 or safe < 0 or overturned + safe > n:
        raise InputError(
            f"overturned ({overturned}) and safe ({safe}) must be >= 0 with a sum <= n ({n})"
        )
    if 2 * overturned >= n or 2 * safe > n:
        return 0
    return min(-(-n // 2) - overturned, n // 2 + 1 - safe)


class CrossingSearch(Generic[Item]):
    """Search, for every item, an upward crossing of 50 % on the integer levels 1 … ``K``.

    Parameters
    ----------
    items : iterable of hashable
        What is searched (in :func:`rocking.agx_50`: (case, body) pairs).
    K : int
        Highest level (≥ 1).
    coarse : int
        Levels of the bracketing round (≥ 1).
    """

    def __init__(self, items: Iterable[Item], K: int, coarse: int):
        if not (isinstance(K, int) and K >= 1):
            raise InputError(f"K must be an integer >= 1, got {K!r}")
        if not (isinstance(coarse, int) and coarse >= 1):
            raise InputError(f"coarse must be an integer >= 1, got {coarse!r}")
        #: The bracketing levels, increasing, the last K.
        self.grid = sorted({math.ceil(K * i / coarse) for i in range(1, coarse + 1)})
        self._scan = dict.fromkeys(items, 0)  # bracketing: index in grid of the next level
        self._lo: dict[Item, int] = {}  # bisection: P(lo) < 0.5 <= P(hi)
        self._hi: dict[Item, int] = {}

    @property
    def widest_bracket(self) -> int:
        """Largest distance between two successive bracketing levels (from 0)."""
        return max(b - a for a, b in zip([0, *self.grid], self.grid))

    @property
    def max_levels(self) -> int:
        """Most levels one item can need: all bracketing levels, then the bisection."""
        return len(self.grid) + math.ceil(math.log2(self.widest_bracket)) + 1

    @property
    def typical_rounds(self) -> int:
        """Rounds of a typical item (half the bracketing levels, then the bisection): an
        estimate for progress displays."""
        return len(self.grid) // 2 + math.ceil(math.log2(self.widest_bracket))

    def pending(self) -> dict[Item, int]:
        """The level to evaluate next for every item still searching (empty: done)."""
        level = {item: self.grid[i] for item, i in self._scan.items()}
        for item, hi in self._hi.items():
            if hi - self._lo[item] > 1:
                level[item] = (self._lo[item] + hi) // 2
        return level

    def update(self, above: Mapping[Item, bool]) -> None:
        """Take the outcomes of the levels of :meth:`pending`: ``above[item]`` is True where the
        probability at that item's pending level is at least 50 %."""
        for item, k in self.pending().items():
            if item not in above:
                raise InputError(f"no outcome for {item!r} at level {k}")
            if item in self._scan:
                if above[item]:
                    i = self._scan.pop(item)
                    self._lo[item], self._hi[item] = (self.grid[i - 1] if i else 0), k
                elif self._scan[item] + 1 < len(self.grid):
                    self._scan[item] += 1
                else:
                    del self._scan[item]  # below 50 % at every bracketing level: no crossing
            elif above[item]:
                self._hi[item] = k
            else:
                self._lo[item] = k

    def crossings(self) -> dict[Item, int]:
        """Item → its crossing level ``hi`` (items without a crossing are absent); final once
        :meth:`pending` is empty."""
        return dict(self._hi)
