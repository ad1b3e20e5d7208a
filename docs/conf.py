"""Sphinx configuration: ``make docs`` builds the site into docs/_build/html.

Sphinx + numpydoc rather than MkDocs + mkdocstrings: the docstrings are numpydoc,
which numpydoc renders natively (Parameters, Returns, Examples as tables and
doctest blocks), autodoc imports the package the way users do, myst-parser
reads the existing Markdown pages unchanged (they stay pytest doctests), and
sphinx-gallery runs the example scripts at build time. Warnings are errors
(``-W`` in the Makefile).
"""

from __future__ import annotations

import sys
from pathlib import Path

HERE = Path(__file__).resolve().parent
sys.path.insert(0, str(HERE / "_ext"))
sys.path.insert(0, str(HERE.parent / "src"))

import optri_reference  # noqa: E402

import optri  # noqa: E402  (after the path set-up above)

project = "optri"
author = "the optri developers"
copyright = "2026, the optri developers (MIT licence)"
release = version = optri.__version__

extensions = [
    "myst_parser",
    "numpydoc",
    "sphinx.ext.autodoc",
    "sphinx.ext.mathjax",
    "sphinx_gallery.gen_gallery",
]
source_suffix = {".rst": "restructuredtext", ".md": "markdown"}
exclude_patterns = ["_build", "_ext", "auto_gallery/*.ipynb", "sg_execution_times.rst"]
root_doc = "index"

# Markdown pages: ```python blocks with >>> stay plain code blocks (pytest runs them);
# headings get anchors so [text](page.md#heading) links resolve.
myst_heading_anchors = 3
myst_enable_extensions = ["colon_fence", "dollarmath"]

# numpydoc renders the sections; autodoc lists members itself (no autosummary stubs)
numpydoc_show_class_members = False
numpydoc_class_members_toctree = False
numpydoc_xref_param_type = False
autodoc_member_order = "bysource"
autodoc_typehints = "none"  # numpydoc's Parameters already state the types
autodoc_default_options = {"no-value": True}

sphinx_gallery_conf = {
    "examples_dirs": "../examples",
    "gallery_dirs": "auto_gallery",
    "filename_pattern": r"/plot_",
    "ignore_pattern": r"__init__\.py",
    "abort_on_example_error": True,
    "download_all_examples": False,
    "show_memory": False,
    "plot_gallery": "True",
    "write_computation_times": False,
    "matplotlib_animations": False,
    "within_subsection_order": "FileNameSortKey",
}

html_theme = "furo"
html_title = f"optri {version}"
html_static_path: list[str] = []
html_show_sourcelink = False


def setup(app: object) -> None:
    """Write the API reference and the command-line page before Sphinx reads the sources.

    They come from optri.__all__, each public subpackage's __all__ and the click group,
    so new names and commands appear without editing any page. Here rather than at
    import, so that importing this file (pytest's --doctest-modules does) writes nothing.
    """
    optri_reference.write_reference(HERE)
