"""Sphinx extension: ``|x|`` in a docstring is an absolute value, not a substitution.

The docstrings are physics and write absolute values as ``|θ|`` or ``|a_g|``; reStructuredText
reads a word between two bars as a substitution reference and fails the build on it.  Every bar
of a docstring is escaped before numpydoc and autodoc parse it (the docstrings hold no
reStructuredText tables or line blocks, the only constructs that need a bare bar).
"""

from __future__ import annotations

import re

from sphinx.application import Sphinx

_BAR = re.compile(r"(?<!\\)\|")


def escape_bars(app, what, name, obj, options, lines: list[str]) -> None:
    """Escape, in place, every bar of a docstring's ``lines`` not already escaped."""
    lines[:] = [_BAR.sub(r"\\|", line) for line in lines]


def setup(app: Sphinx) -> dict:
    # before numpydoc (priority 500), which turns the docstring's sections into reST
    app.connect("autodoc-process-docstring", escape_bars, priority=400)
    return {"parallel_read_safe": True, "parallel_write_safe": True}
