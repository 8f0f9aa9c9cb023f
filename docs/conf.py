"""Sphinx configuration of heatdata's documentation site (pydata-sphinx-theme, numpydoc, sphinx-gallery, MyST).

Build: ``.venv/bin/sphinx-build -W -b html docs docs/_build/html`` (``scripts/setup.sh --docs`` installs the tools;
``tests/test_docs.py`` runs this build with warnings as errors).
"""

import os
import sys
from pathlib import Path

DOCS = Path(__file__).resolve().parent
ROOT = DOCS.parent
sys.path.insert(0, str(ROOT))
sys.path.insert(0, str(DOCS))  # sphinx-gallery finds GalleryOrder below as conf.GalleryOrder
os.environ.setdefault("MPLBACKEND", "Agg")

from numpydoc.xref import DEFAULT_LINKS  # noqa: E402

import heatdata  # noqa: E402

project = "heatdata"
author = "The heatdata developers"
copyright = "2026, the heatdata developers (MIT); the thesis: S. D. Brandão, 2015"
release = heatdata.__version__
version = release

extensions = [
    "sphinx.ext.autodoc",
    "sphinx.ext.autosummary",
    "sphinx.ext.mathjax",
    "sphinx-mathjax-offline",  # the site carries MathJax (_static/mathjax/): maths renders without a network
    "sphinx.ext.intersphinx",
    "numpydoc",
    "myst_parser",
    "sphinx_gallery.gen_gallery",
]

source_suffix = {".rst": "restructuredtext", ".md": "markdown"}
root_doc = "index"
exclude_patterns = ["_build", "results/*.md", "gallery/*.ipynb", "gallery/*.py", "gallery/*.md5", "gallery/*.zip"]
templates_path = ["_templates"]

# MyST: the user guide pages are Markdown (as the README was); $...$ maths, heading anchors for #links
myst_enable_extensions = ["dollarmath", "colon_fence"]
myst_heading_anchors = 3

# numpydoc renders the numpy-style docstrings; autosummary writes one page per public name
autosummary_generate = True
autosummary_imported_members = True
autodoc_default_options = {"members": True, "inherited-members": False, "show-inheritance": True}
autodoc_typehints = "none"  # numpydoc's Parameters sections carry the types; signatures stay readable
numpydoc_show_class_members = False
numpydoc_class_members_toctree = False
# the types of Parameters and Returns link to heatdata's own classes (Recognition, View, ...); other words stay text
numpydoc_xref_param_type = True
numpydoc_xref_ignore = "all"
numpydoc_xref_aliases = {
    **{word: word for word in DEFAULT_LINKS},  # numpydoc's own links need Python's and numpy's inventories
    **{name: f"heatdata.{name}" for name in heatdata.__all__ if isinstance(getattr(heatdata, name), type)},
}

# no intersphinx inventories are fetched (no network at build time); links to numpy/scipy are plain text
intersphinx_mapping: dict[str, tuple[str, str | None]] = {}

GALLERY = [  # the thesis's order: views, recognition, several views, compact libraries, JASNOM
    "plot_views_temperature.py",
    "plot_recognition.py",
    "plot_particle_filter.py",
    "plot_compact_library.py",
    "plot_jasnom_stitch.py",
]


class GalleryOrder:
    """The gallery's examples in the order of :data:`GALLERY` (a new example must be listed there)."""

    def __init__(self, src_dir: str):
        self.src_dir = src_dir

    def __call__(self, filename: str) -> int:
        if filename not in GALLERY:
            raise ValueError(f"docs/conf.py: list the example {filename} in GALLERY")
        return GALLERY.index(filename)


sphinx_gallery_conf = {
    "examples_dirs": str(ROOT / "examples"),
    "gallery_dirs": "gallery",
    "filename_pattern": r"/plot_",
    "within_subsection_order": "conf.GalleryOrder",
    "download_all_examples": False,
    "remove_config_comments": True,
    "plot_gallery": "True",
    "abort_on_example_error": True,
    "reset_modules": ("matplotlib",),
    "matplotlib_animations": False,
    "show_memory": False,
    "min_reported_time": 0,
    "write_computation_times": False,  # its page loads scripts from CDNs; each example states its own time
}

html_theme = "pydata_sphinx_theme"
html_title = "heatdata"
html_static_path: list[str] = []
html_theme_options = {
    "navbar_align": "left",
    "show_toc_level": 2,
    "navigation_with_keys": False,
    "footer_start": ["copyright"],
    "footer_end": ["sphinx-version"],
    "secondary_sidebar_items": ["page-toc"],
}
html_show_sourcelink = False
