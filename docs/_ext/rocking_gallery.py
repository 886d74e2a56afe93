"""The gallery's order of examples, and its image scraper: the figures an example keeps in its
variables.

The functions of :mod:`rocking.plots` build ``matplotlib.figure.Figure`` objects that pyplot does
not know of, so sphinx-gallery's own matplotlib scraper (which asks pyplot for its figures) does
not see them. This scraper shows, after each code block, every figure held by a variable of the
example that was not shown before, made by pyplot or not (a documented extension point of
sphinx-gallery: "image_scrapers").
"""

from __future__ import annotations

from typing import Any

from matplotlib.figure import Figure
from sphinx_gallery.scrapers import figure_rst

#: Example file → ids of the figures already shown from it.
_shown: dict[str, set[int]] = {}


def scraper(block: Any, block_vars: dict, gallery_conf: dict) -> str:
    """Save the new figures of the example's namespace and return the reST that shows them."""
    shown = _shown.setdefault(str(block_vars["src_file"]), set())
    figures = [
        value
        for value in block_vars["example_globals"].values()
        if isinstance(value, Figure) and id(value) not in shown
    ]
    paths = []
    for figure in figures:
        path = next(block_vars["image_path_iterator"])
        figure.savefig(path, dpi=100)
        shown.add(id(figure))
        paths.append(path)
    return figure_rst(paths, gallery_conf["src_dir"])


class ExampleOrder:
    """Sort key of the gallery (``within_subsection_order``): the examples in the order of the
    tutorials, from one block to an inventory; an example not listed comes last, by name."""

    ORDER = (
        "plot_block_el_centro.py",
        "plot_response_modes.py",
        "plot_motions_fit.py",
        "plot_floor_spectra.py",
        "plot_fragility.py",
        "plot_table1.py",
        "plot_sv_agx.py",
        "plot_screen_inventory.py",
    )

    def __init__(self, src_dir: str) -> None:
        self.src_dir = src_dir

    def __call__(self, filename: str) -> tuple[int, str]:
        rank = self.ORDER.index(filename) if filename in self.ORDER else len(self.ORDER)
        return rank, filename
