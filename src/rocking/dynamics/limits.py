"""Limit states on the response (issue 44, part 1): :class:`LimitState` and its text form.

A limit state is exceeded in a case when a response quantity that the batched kernel records
(:class:`rocking.dynamics.batch.Outcome`: ``overturned``, ``peak_theta_ratio`` = max abs(θ)/α,
``uplift``, and with friction ``peak_slip``, ``residual_slip``, ``peak_lift`` [m]) reaches a
threshold.  Loss assessment grades damage this way (FEMA P-58's damage
states of unanchored equipment), and the rocking literature grades the response by the peak
rotation ratio: uplift, large rocking (θ/α ≥ 0.5, say), overturning.

The default of every analysis is overturning alone (:data:`OVERTURN`).  Standard library only,
so that the command line parses ``--limit-states`` before it imports anything heavy.
"""

from __future__ import annotations

import math
import re
from collections.abc import Iterable
from dataclasses import dataclass
from typing import Any

from ..defaults import LIMIT_STATE_SYNTAX, QUANTITY_ALIASES, RESPONSE_QUANTITIES
from ..errors import InputError

#: Quantities that are yes/no: their only threshold is 1 (True).
_FLAGS = ("overturned", "uplift")


@dataclass(frozen=True)
class LimitState:
    """A limit state: exceeded where the response quantity ``quantity`` ≥ ``threshold``.

    Parameters
    ----------
    name : str
        Its name in tables and figures (e.g. ``"theta/alpha>=0.5"``).
    quantity : str
        One of :data:`rocking.defaults.RESPONSE_QUANTITIES`: ``"overturned"``,
        ``"peak_theta_ratio"`` (max abs(θ)/α [-]; θ_ov/α once overturned, so an overturned
        block exceeds every threshold up to θ_ov/α), ``"uplift"`` (the block left rest),
        ``"peak_slip"``, ``"residual_slip"`` (max and final abs(slip) [m]) or ``"peak_lift"``
        (max lift of the base [m]); 0 without friction (issue 45).
    threshold : float
        The threshold, > 0, in the quantity's unit; 1 (True) for a yes/no quantity.
    """

    name: str
    quantity: str
    threshold: float = 1.0

    def __post_init__(self) -> None:
        name = str(self.name).strip()
        if not name or "," in name:
            raise InputError(
                f"limit state name must be non-empty text without commas, got {name!r}"
            )
        quantity = QUANTITY_ALIASES.get(str(self.quantity).strip(), str(self.quantity).strip())
        if quantity not in RESPONSE_QUANTITIES:
            raise InputError(
                f"limit state {name!r}: quantity must be one of "
                f"{', '.join(RESPONSE_QUANTITIES)}, got {self.quantity!r}"
            )
        try:
            threshold = float(self.threshold)
        except (TypeError, ValueError):
            threshold = math.nan
        if not (math.isfinite(threshold) and threshold > 0.0):
            raise InputError(
                f"limit state {name!r}: threshold must be a number > 0, got {self.threshold!r}"
            )
        if quantity in _FLAGS and threshold != 1.0:
            raise InputError(
                f"limit state {name!r}: {quantity} is yes/no; its threshold is 1, got {threshold:g}"
            )
        object.__setattr__(self, "name", name)
        object.__setattr__(self, "quantity", quantity)
        object.__setattr__(self, "threshold", threshold)

    def exceeded(self, outcome: Any) -> Any:
        """Where the limit state is exceeded (bool array) in ``outcome`` (an
        :class:`~rocking.dynamics.batch.Outcome`, or anything with the quantity as attribute)."""
        return getattr(outcome, self.quantity) >= self.threshold


#: Overturning: the limit state of every analysis by default.
OVERTURN = LimitState("overturn", "overturned")

_ITEM = re.compile(r"^(?:(?P<name>[^=<>]+)=)?\s*(?P<quantity>[\w/]+)\s*(?:>=\s*(?P<value>\S+))?$")


def parse_limit_state(text: str) -> LimitState:
    """One limit state of the text form: ``uplift``, ``overturn``, ``theta/alpha>=0.5``,
    ``QUANTITY>=X``, optionally ``NAME=`` before it (:data:`LIMIT_STATE_SYNTAX`)."""
    item = str(text).strip()
    match = _ITEM.match(item)
    if match is None:
        raise InputError(f"limit states: cannot read {item!r}; give {LIMIT_STATE_SYNTAX}")
    quantity = match["quantity"]
    key = QUANTITY_ALIASES.get(quantity, quantity)
    if key not in RESPONSE_QUANTITIES:
        raise InputError(
            f"limit states: unknown quantity {quantity!r} in {item!r}; give {LIMIT_STATE_SYNTAX}"
        )
    if match["value"] is None and key not in _FLAGS:
        raise InputError(f"limit states: {item!r} needs a threshold, e.g. {quantity}>=0.5")
    try:
        value = 1.0 if match["value"] is None else float(match["value"])
    except ValueError:
        raise InputError(f"limit states: {item!r}: {match['value']!r} is not a number") from None
    name = match["name"] or (quantity if match["value"] is None else f"{quantity}>={value:g}")
    try:
        return LimitState(name.strip(), key, value)
    except InputError as exc:
        raise InputError(f"limit states: {exc}") from None


def parse_limit_states(
    limit_states: str | LimitState | Iterable[str | LimitState] | None,
) -> tuple[LimitState, ...]:
    """The limit states of an analysis: None gives (:data:`OVERTURN`,); text is split at commas
    (``"uplift, theta/alpha>=0.5, overturn"``); a sequence may mix text and
    :class:`LimitState`.  Names must differ.  Errors are one line, naming the item."""
    if limit_states is None:
        return (OVERTURN,)
    if isinstance(limit_states, (str, LimitState)):
        limit_states = [limit_states]
    parsed: list[LimitState] = []
    for item in limit_states:
        if isinstance(item, LimitState):
            parsed.append(item)
        elif isinstance(item, str):
            parsed.extend(parse_limit_state(part) for part in item.split(",") if part.strip())
        else:
            raise InputError(
                f"limit states must be text or rocking.LimitState, got {type(item).__name__}"
            )
    if not parsed:
        raise InputError(f"limit states: none given; give {LIMIT_STATE_SYNTAX}")
    names = [ls.name for ls in parsed]
    twice = sorted({n for n in names if names.count(n) > 1})
    if twice:
        raise InputError(f"limit states: the name {twice[0]!r} is given twice")
    return tuple(parsed)


def limit_state_coords(states: Iterable[LimitState]) -> dict[str, tuple]:
    """The coordinates of a ``limit_state`` dimension (xarray form): the names, and on them
    each one's ``quantity`` and ``threshold``."""
    states = list(states)
    return {
        "limit_state": ("limit_state", [ls.name for ls in states]),
        "quantity": ("limit_state", [ls.quantity for ls in states]),
        "threshold": ("limit_state", [ls.threshold for ls in states]),
    }
