"""Sphinx extension: the public names of ``rocking`` in the API reference.

* Tells the autosummary templates which members of each module are also public names of
  ``rocking`` (so that a module page links to ``rocking.simulate`` instead of documenting the
  same function a second time under ``rocking.dynamics.simulate.simulate``).
* Warns (so ``-W`` fails the build) when a name of ``rocking.__all__`` is missing from
  ``api/index.rst``: the reference lists every public name.
"""

from __future__ import annotations

import re
from pathlib import Path

from sphinx.application import Sphinx
from sphinx.config import Config
from sphinx.util import logging

import rocking

logger = logging.getLogger(__name__)


def exported_by_module() -> dict[str, list[str]]:
    """Module → names it defines that ``rocking`` exports (classes and functions)."""
    found: dict[str, list[str]] = {}
    for name in rocking.__all__:
        module = getattr(getattr(rocking, name), "__module__", None)
        if module is not None and module.startswith("rocking"):
            found.setdefault(module, []).append(name)
    return found


def _add_context(app: Sphinx, config: Config) -> None:
    config.autosummary_context = {
        **config.autosummary_context,
        "exported": exported_by_module(),
    }


def _check_index(app: Sphinx) -> None:
    index = Path(app.srcdir) / "api" / "index.rst"
    words = set(re.findall(r"[\w.]+", index.read_text(encoding="utf-8")))
    listed = {w.rsplit(".", 1)[-1] for w in words}
    for name in rocking.__all__:
        if name not in listed:
            logger.warning(
                "public name rocking.%s is missing from the API reference", name, location=index
            )


def setup(app: Sphinx) -> dict:
    app.connect("config-inited", _add_context)
    app.connect("builder-inited", _check_index)
    return {"parallel_read_safe": True, "parallel_write_safe": True}
