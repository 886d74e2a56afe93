"""Figures. Every function here builds and returns a ``matplotlib.figure.Figure`` (no pyplot, no
global state, no display); callers save it. One module per topic.

Matplotlib is imported when the first figure is built, not with these modules (about 0.6 s):
a process whose figures are built by drawing workers (:meth:`rocking.report.Report.plot`) need
not import it.
"""

from __future__ import annotations

from typing import TYPE_CHECKING, Any

if TYPE_CHECKING:
    from matplotlib.figure import Figure


def new_figure(**kwargs: Any) -> Figure:
    """A new ``matplotlib.figure.Figure(**kwargs)`` (figsize in inches)."""
    from matplotlib.figure import Figure

    return Figure(**kwargs)
