"""Sphinx configuration of the user documentation: Markdown pages (MyST), the API reference generated from
the docstrings of ``linkage`` (autodoc with Google-style sections). Build: ``sphinx-build -W -b html docs
docs/_build``."""

import os
import sys

sys.path.insert(0, os.path.abspath(".."))

project = "linkage"
author = "the linkage developers"
extensions = ["myst_parser", "sphinx.ext.autodoc", "sphinx.ext.napoleon"]
source_suffix = {".md": "markdown"}
root_doc = "index"
exclude_patterns = ["_build", "notebooks", "**.ipynb_checkpoints"]
myst_heading_anchors = 3
autodoc_member_order = "bysource"
autodoc_typehints = "none"
napoleon_google_docstring = True
napoleon_numpy_docstring = False
html_theme = "alabaster"
html_static_path = []
suppress_warnings = ["myst.xref_missing"]
