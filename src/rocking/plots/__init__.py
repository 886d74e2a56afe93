"""Figures. Every plotting function here builds and returns a ``matplotlib.figure.Figure`` (no
pyplot, no global state, no display); callers save it. One module per topic; here the figure
itself (:func:`new_figure`) and a legend placed off the data (:func:`legend_beside`).

Matplotlib is imported when the first figure is built, not with these modules (about 0.6 s):
a process whose figures are built by drawing workers (:meth:`rocking.report.Report.plot`) need
not import it.
"""

from __future__ import annotations

from typing import TYPE_CHECKING, Any

if TYPE_CHECKING:
    from matplotlib.axes import Axes
    from matplotlib.figure import Figure


def new_figure(**kwargs: Any) -> Figure:
    """A new ``matplotlib.figure.Figure(**kwargs)`` (figsize in inches)."""
    from matplotlib.figure import Figure

    return Figure(**kwargs)


def legend_beside(ax: Axes, title: str = "", **kwargs: Any) -> None:
    """The legend of ``ax`` beside it, right of its top corner, where it covers no data
    (``kwargs``: other options of ``Axes.legend``, or these, e.g. ``fontsize``)."""
    options = {"fontsize": "small", "title_fontsize": "small"} | kwargs
    ax.legend(loc="upper left", bbox_to_anchor=(1.01, 1.0), title=title or None, **options)
