"""Sphinx configuration of the rocking documentation.

Build (from the repository root, with the ``dev`` extra installed)::

    .venv/bin/sphinx-build -W --keep-going -b html docs docs/_build/html

The API pages are generated from the numpydoc docstrings (autosummary, one page per public
object), the command-line reference from the click commands (sphinx-click) and the gallery by
running the scripts of ``examples/`` (sphinx-gallery). No inventory of another project is fetched
(intersphinx is not used): the build works offline.
"""

from __future__ import annotations

import sys
from pathlib import Path

import rocking

DOCS = Path(__file__).resolve().parent
sys.path.insert(0, str(DOCS / "_ext"))  # local extensions and the gallery's figure scraper

project = "rocking"
author = "the rocking developers"
copyright = "the rocking developers, MIT licence"
release = rocking.__version__
version = ".".join(release.split(".")[:2])

extensions = [
    "sphinx.ext.autodoc",
    "sphinx.ext.autosummary",
    "numpydoc",
    "myst_parser",
    "sphinx_click",
    "sphinx_gallery.gen_gallery",
    "public_api",
    "absolute_values",
]

source_suffix = {".rst": "restructuredtext", ".md": "markdown"}
root_doc = "index"
exclude_patterns = ["_build"]
templates_path = ["_templates"]
smartquotes = False  # options are written --out, never with an en dash

# -- API reference ------------------------------------------------------------------------------
autosummary_generate = True
autosummary_ignore_module_all = True  # members are what each module defines, private excluded
autodoc_member_order = "bysource"
autodoc_typehints = "none"  # the numpydoc sections state types and units; signatures stay short
autodoc_default_options = {"show-inheritance": True}
numpydoc_show_class_members = False  # the class template lists methods and attributes itself
numpydoc_class_members_toctree = False
numpydoc_attributes_as_param_list = False
numpydoc_xref_param_type = False

# -- Markdown pages -----------------------------------------------------------------------------
myst_enable_extensions = ["colon_fence"]
myst_heading_anchors = 3

# -- Gallery ------------------------------------------------------------------------------------
sphinx_gallery_conf = {
    "examples_dirs": str(DOCS.parent / "examples"),
    "gallery_dirs": "auto_examples",
    "filename_pattern": r"/plot_",
    "image_scrapers": ("rocking_gallery.scraper",),
    "within_subsection_order": "rocking_gallery.ExampleOrder",
    "download_all_examples": False,
    "remove_config_comments": True,
    "abort_on_example_error": False,  # every failing example is reported, then the build fails
    "min_reported_time": 1,
    "show_memory": False,
    "write_computation_times": True,
}

# -- HTML ---------------------------------------------------------------------------------------
html_theme = "pydata_sphinx_theme"
html_title = f"rocking {release}"
html_theme_options = {
    "navigation_with_keys": False,
    "show_toc_level": 2,
    "footer_start": ["copyright"],
    "footer_end": ["sphinx-version"],
}
html_show_sourcelink = False
