"""Sphinx configuration of the wheelrail documentation.

Build (warnings are errors, the gallery is executed)::

    python -m sphinx -W --keep-going -b html docs docs/_build/html
"""

import os
from pathlib import Path

import matplotlib

matplotlib.use("Agg")  # the gallery draws off-screen


project = "wheelrail"
author = "the wheelrail developers"
copyright = "2026, the wheelrail developers"

extensions = [
    "sphinx.ext.autodoc",
    "sphinx.ext.autosummary",
    "sphinx.ext.mathjax",
    "numpydoc",
    "sphinx_gallery.gen_gallery",
    "myst_parser",
]

source_suffix = {".rst": "restructuredtext", ".md": "markdown"}
root_doc = "index"
exclude_patterns = ["_build", "examples"]
myst_heading_anchors = 3

# API reference: numpydoc reads the NumPy-style docstrings; class members are listed by autodoc, not by
# numpydoc's autosummary tables (which would need a stub page per member).
autosummary_generate = False
autodoc_member_order = "bysource"
autodoc_typehints = "none"
numpydoc_show_class_members = False
numpydoc_class_members_toctree = False
numpydoc_xref_param_type = False

# Gallery: every script in docs/examples is run at build time, so a broken example breaks the build.
sphinx_gallery_conf = {
    "examples_dirs": "examples",
    "gallery_dirs": "auto_examples",
    "filename_pattern": r"/plot_",
    "abort_on_example_error": True,
    "download_all_examples": False,
    "remove_config_comments": True,
    "within_subsection_order": "FileNameSortKey",
    "matplotlib_animations": False,
    "show_memory": False,
    "reset_modules": ("matplotlib",),
}

html_theme = "alabaster"
html_title = "wheelrail"
html_static_path = []
html_theme_options = {
    "description": "vertical wheel/rail interaction and the dynamic contact filter",
    "page_width": "1240px",  # the physics and validation tables are wide
}

# The examples write their files (tables, recordings) into a scratch folder inside the build.
os.environ.setdefault("WHEELRAIL_GALLERY_OUT", str(Path(__file__).parent / "_build" / "gallery-output"))
