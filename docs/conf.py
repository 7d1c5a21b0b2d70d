"""Sphinx configuration: user guide, API reference (autosummary + numpydoc), gallery (sphinx-gallery).

Build (offline, warnings as errors, gallery executed)::

    pip install -e ".[docs]"
    sphinx-build -W --keep-going -b html docs docs/_build/html

``-D plot_gallery=0`` skips running the examples. Links to the Python, NumPy,
scikit-learn and skorch docs (intersphinx) are made only when
``SKLEARN_HARDNESS_INTERSPHINX`` is set: to ``online`` to fetch the inventories,
or to a directory holding ``python.inv``, ``numpy.inv``, ``sklearn.inv``,
``skorch.inv`` (any subset). Unset, the build needs no network and
cross-project references render as plain text.
"""

import os
import re
from pathlib import Path

import sklearn_hardness

project = "sklearn-hardness"
author = "sklearn-hardness developers"
copyright = "sklearn-hardness developers"
release = sklearn_hardness.__version__
version = release

extensions = [
    "sphinx.ext.autodoc",
    "sphinx.ext.autosummary",
    "sphinx.ext.intersphinx",
    "sphinx.ext.mathjax",
    "sphinx-mathjax-offline",  # ships MathJax with the pages: equations render without network
    "numpydoc",
    "sphinx_gallery.gen_gallery",
    "myst_parser",
]
templates_path = ["_templates"]
exclude_patterns = ["_build", "**.ipynb_checkpoints", "auto_examples/*.ipynb", "auto_examples/*.py"]
source_suffix = {".rst": "restructuredtext", ".md": "markdown"}
myst_enable_extensions = ["dollarmath", "amsmath"]

autosummary_generate = True
autodoc_default_options = {"members": True, "inherited-members": False}
numpydoc_show_class_members = False
numpydoc_class_members_toctree = False

html_theme = "pydata_sphinx_theme"
html_title = f"sklearn-hardness {release}"
html_theme_options = {
    "show_toc_level": 2,
    "navigation_with_keys": False,
}
html_sidebars = {"index": [], "getting_started": []}
html_static_path = []

# Cross-project links only when the inventories can be had without surprises (see module docstring).
_INVENTORY_URLS = {
    "python": "https://docs.python.org/3",
    "numpy": "https://numpy.org/doc/stable",
    "sklearn": "https://scikit-learn.org/stable",
    "skorch": "https://skorch.readthedocs.io/en/stable",
}
_inventories = os.environ.get("SKLEARN_HARDNESS_INTERSPHINX", "")
if _inventories == "online":
    intersphinx_mapping = {name: (url, None) for name, url in _INVENTORY_URLS.items()}
elif _inventories:
    _inv_dir = Path(_inventories)
    if not _inv_dir.is_dir():
        raise RuntimeError(f"SKLEARN_HARDNESS_INTERSPHINX={_inventories!r} is neither 'online' nor a directory")
    intersphinx_mapping = {
        name: (url, str(_inv_dir / f"{name}.inv"))
        for name, url in _INVENTORY_URLS.items()
        if (_inv_dir / f"{name}.inv").is_file()
    }
else:
    intersphinx_mapping = {}

sphinx_gallery_conf = {
    "examples_dirs": "../examples",
    "gallery_dirs": "auto_examples",
    "filename_pattern": r"/plot_",
    "abort_on_example_error": True,
    "doc_module": ("sklearn_hardness",),
    "backreferences_dir": "generated/backreferences",
    "matplotlib_animations": False,
    "remove_config_comments": True,
}


# Shapes like "(n_samples, n_features_out_)" in numpydoc type lines would be read as rst link
# targets ("name_"); escape the underscore inside such shapes only.
_SHAPE = re.compile(r"shape \(([^()]*)\)")
_TRAILING_UNDERSCORE = re.compile(r"\b(\w*[A-Za-z0-9])_(?=[,)\s]|$)")


def _escape_shape_names(app, what, name, obj, options, lines):
    for i, line in enumerate(lines):
        lines[i] = _SHAPE.sub(lambda m: "shape (" + _TRAILING_UNDERSCORE.sub(r"\1\\_", m.group(1)) + ")", line)


# set_<method>_request are scikit-learn's metadata-routing setters added to every estimator
# class; their docstrings link into scikit-learn's own user guide and add nothing here.
_ROUTING_SETTER = re.compile(r"^set_\w+_request$")


def _skip_routing_setters(app, what, name, obj, skip, options):
    if _ROUTING_SETTER.match(name):
        return True
    return None


def _drop_type_docstring(app, what, name, obj, options, lines):
    # A constant without its own doc comment would show its type's docstring ("Built-in immutable sequence").
    type_doc = " ".join((type(obj).__doc__ or "").split())
    if what == "data" and type_doc and " ".join(" ".join(lines).split()) == type_doc:
        lines[:] = []


def setup(app):
    app.connect("autodoc-process-docstring", _escape_shape_names, priority=100)
    app.connect("autodoc-process-docstring", _drop_type_docstring, priority=100)  # before numpydoc
    app.connect("autodoc-skip-member", _skip_routing_setters)
