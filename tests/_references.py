"""Dotted references in prose and help texts (``models.is_converged``) and whether they are public."""

import importlib
import importlib.util
import re

import sklearn_hardness

SUBPACKAGES = [name for name in sklearn_hardness.__all__ if not name.startswith("_")]
#: ``subpackage.name`` or ``sklearn_hardness.subpackage.name``: what a user would look up
#: (not part of a longer dotted name such as ``modAL.models.ActiveLearner``).
_DOTTED = re.compile(r"(?<![\w.])(?:sklearn_hardness\.)?(" + "|".join(SUBPACKAGES) + r")\.([A-Za-z_]\w*)")


def dangling_references(text):
    """The ``subpackage.name`` references in ``text`` that are not public names."""
    out = []
    for sub, name in _DOTTED.findall(text):
        module = importlib.import_module(f"sklearn_hardness.{sub}")
        public = name in getattr(module, "__all__", ()) or (
            # a public module below the subpackage (utils.estimator_checks)
            not name.startswith("_") and importlib.util.find_spec(f"sklearn_hardness.{sub}.{name}") is not None)
        if not public:
            out.append(f"{sub}.{name}")
    return out
