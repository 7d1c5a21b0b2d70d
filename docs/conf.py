"""Sphinx configuration: user guide, API reference (autosummary + numpydoc), gallery (sphinx-gallery).

Build (offline, warnings as errors, every reference checked, gallery executed)::

    pip install -e ".[docs]"
    bash docs/build_docs.sh

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

# Every cross-reference must resolve: a name that is no longer public fails the build
# (build_docs.sh passes -W). The exceptions are other projects' names (the standard library's
# among them), which resolve only through intersphinx inventories, not fetched offline (the
# default, see above); torch, OpenCV, SciPy, matplotlib and pandas have no inventory at all.
nitpicky = True
nitpick_ignore_regex = [
    (r"py:.*", r"(numpy|sklearn|skorch|torch|cv2|scipy|matplotlib|pandas|joblib|transformers|pickle)(\..*)?"),
]

autosummary_generate = True
# Inherited members are documented when they are this package's (predict_proba_samples of the
# nets comes from a private base); scikit-learn's, skorch's and torch's are not (_skip_members).
autodoc_default_options = {"members": True, "inherited-members": True}
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


def _defined_here(obj):
    """Whether a class member (function, property, classmethod) is defined in this package."""
    target = obj.fget if isinstance(obj, property) else getattr(obj, "__func__", obj)
    return (getattr(target, "__module__", None) or "").startswith("sklearn_hardness")


def _skip_members(app, what, name, obj, skip, options):
    if _ROUTING_SETTER.match(name):
        return True
    if what in ("class", "exception") and not _defined_here(obj):
        return True  # inherited from scikit-learn, skorch, torch or the standard library
    return None


def _public_classes():
    import importlib

    return {id(obj) for sub in sklearn_hardness.__all__ if not sub.startswith("_")
            for obj in vars(importlib.import_module(f"sklearn_hardness.{sub}")).values() if isinstance(obj, type)}


def _public_bases(app, name, obj, options, bases):
    # "Bases:" would link a private class (models._mlp._MLPClassifier) that has no page: show
    # the nearest public ancestors instead, ours or another project's.
    public, todo, out = _public_classes(), list(bases), []
    while todo:
        base = todo.pop(0)
        if base.__module__.startswith("sklearn_hardness") and id(base) not in public:
            todo[:0] = [b for b in base.__bases__ if b is not object]
        elif base not in out:
            out.append(base)
    bases[:] = out or [object]


# A docstring's bare :func:`name` means a name of its own subpackage, which is how it resolves on
# the object's page; in the API table of api.rst it is read in the package's context instead.
# Qualify it where the subpackage exports that name (anything else still fails the nitpicky build).
_BARE_REFERENCE = re.compile(r":(func|class|meth|attr|data|obj|exc):`(\w+)`")


def _qualify_bare_references(app, what, name, obj, options, lines):
    import importlib

    parts = name.split(".")
    for n in range(len(parts) - 1, 1, -1):  # the longest public module that holds the object
        try:
            module = importlib.import_module(".".join(parts[:n]))
        except ImportError:
            continue
        public, package = set(getattr(module, "__all__", ())), module.__name__
        lines[:] = [_BARE_REFERENCE.sub(
            lambda m: f":{m[1]}:`~{package}.{m[2]}`" if m[2] in public else m[0], line) for line in lines]
        return


def _drop_type_docstring(app, what, name, obj, options, lines):
    # A constant without its own doc comment would show its type's docstring ("Built-in immutable sequence").
    type_doc = " ".join((type(obj).__doc__ or "").split())
    if what == "data" and type_doc and " ".join(" ".join(lines).split()) == type_doc:
        lines[:] = []


def setup(app):
    app.connect("autodoc-process-docstring", _escape_shape_names, priority=100)
    app.connect("autodoc-process-docstring", _drop_type_docstring, priority=100)  # before numpydoc
    app.connect("autodoc-process-docstring", _qualify_bare_references, priority=100)
    app.connect("autodoc-skip-member", _skip_members)
    app.connect("autodoc-process-bases", _public_bases)
