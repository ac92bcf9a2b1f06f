"""Sphinx configuration of the qmaps documentation site; `bash tools/docs` builds it."""
import pathlib
import sys

docs = pathlib.Path(__file__).resolve().parent
sys.path.insert(0, str(docs.parent / "python"))  # the package qmaps, for the API reference
sys.path.insert(0, str(docs / "_ext"))

project = "qmaps"
author = "the qmaps authors"
copyright = "the qmaps authors"

extensions = [
    "myst_parser",
    "sphinx.ext.autodoc",
    "sphinx.ext.napoleon",
    "sphinx.ext.mathjax",
    "notebook_pages",  # docs/notebooks/*.ipynb as pages
    "links_outside_docs",  # a link out of docs/ is an error
]

source_suffix = {".md": "markdown"}
root_doc = "index"
exclude_patterns = ["_ext", "gallery", "**/.ipynb_checkpoints"]

# MyST: ::: fences, $...$ and $$...$$ maths, and page.md#anchor links to headings down to ###.
myst_enable_extensions = ["colon_fence", "dollarmath"]
myst_heading_anchors = 3

# The Python API is read from the sources: neither the compiled engine nor the libraries the
# package imports need to be installed to build the documentation.
autodoc_mock_imports = ["qmaps._engine", "numpy", "h5py", "matplotlib", "pandas", "xarray", "tqdm"]
autodoc_member_order = "bysource"
autodoc_typehints = "none"
napoleon_google_docstring = True
napoleon_numpy_docstring = False
napoleon_attr_annotations = False  # the attributes' types are said in words

nitpicky = True
highlight_language = "none"

html_theme = "sphinx_rtd_theme"
html_title = "qmaps"
html_show_sourcelink = False
html_theme_options = {"navigation_depth": 3}

# The classes that qmaps makes and the caller never does: no constructor's signature.
MADE_BY_QMAPS = {"qmaps.Spec", "qmaps.Run", "qmaps.Group"}


def without_constructor(app, what, name, obj, options, signature, return_annotation):
    if what == "class" and name in MADE_BY_QMAPS:
        return None, None
    return None


def setup(app):
    app.connect("autodoc-process-signature", without_constructor)
