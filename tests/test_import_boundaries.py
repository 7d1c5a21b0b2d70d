"""Import boundaries, read from the source with :mod:`ast` (tests/test_package_boundary.py keeps the lab out).

1. The package uses only public names of scikit-learn, skorch and torch, so a new release
   that reorganises their private code cannot break it, and ``pyproject.toml`` needs no upper
   bound. The one compatibility module, ``sklearn_hardness/utils/_param_validation.py``, holds a
   vendored copy of scikit-learn's parameter validation instead of importing it.
2. Subpackages meet through each other's public names (their ``__init__``) or through
   ``sklearn_hardness.utils``, never through another subpackage's private module or name, nor
   through a private module at the package's top level (the named pipelines' table is reached
   through ``sklearn_hardness.models`` alone; the command line, ``_cli``, imports public names too).
"""

from __future__ import annotations

import ast
import pathlib

import pytest

ROOT = pathlib.Path(__file__).resolve().parents[1]
PACKAGE = ROOT / "sklearn_hardness"

#: The one module allowed to reach scikit-learn's private code (it does not, today).
COMPAT_MODULE = "sklearn_hardness/utils/_param_validation.py"

#: Third-party libraries whose private code the package must not use.
GUARDED = ("sklearn", "skorch", "torch")

#: Modules without a leading underscore that are still implementation detail: torch documents
#: its layers on ``torch.nn``, not on ``torch.nn.modules.<file>``.
INTERNAL_MODULES = ("torch.nn.modules",)

#: Names with a leading underscore that their library documents in its public API reference:
#: public despite the underscore (scikit-learn's reference lists ``sklearn.utils._safe_indexing``
#: under its utilities, and its newer releases put it in ``sklearn.utils.__all__``).
PUBLIC_UNDERSCORE_NAMES = {("sklearn.utils", "_safe_indexing")}

def _private(part):
    return part.startswith("_") and not (part.startswith("__") and part.endswith("__"))


def _modules():
    return sorted(PACKAGE.rglob("*.py"))


def _imports(source, where):
    """``(module parts, imported name or None, line)`` of every import in ``source``, relative ones
    resolved from ``where`` (the module's path below the repository, e.g. ``sklearn_hardness/io/_video.py``)."""
    package = list(pathlib.PurePosixPath(where).parts[:-1])
    out = []
    for node in ast.walk(ast.parse(source, where)):
        if isinstance(node, ast.Import):
            out.extend((alias.name.split("."), None, node.lineno) for alias in node.names)
        elif isinstance(node, ast.ImportFrom):
            base = package[: len(package) - node.level + 1] if node.level else []
            module = base + (node.module.split(".") if node.module else [])
            out.extend((module, alias.name, node.lineno) for alias in node.names)
    return out


def _attribute_chains(source):
    """Dotted names like ``torch.nn.modules.dropout._DropoutNd`` used in ``source``."""
    chains = []
    nodes = list(ast.walk(ast.parse(source)))
    inner = {id(n.value) for n in nodes if isinstance(n, ast.Attribute)}  # only the whole chain
    for node in nodes:
        if isinstance(node, ast.Attribute) and id(node) not in inner:
            parts, cur = [], node
            while isinstance(cur, ast.Attribute):
                parts.append(cur.attr)
                cur = cur.value
            if isinstance(cur, ast.Name):
                chains.append(([cur.id, *reversed(parts)], node.lineno))
    return chains


def _third_party_violations(source, where):
    found = set()
    for module, name, line in _imports(source, where):
        if module[0] not in GUARDED:
            continue
        full = module + ([name] if name and name != "*" else [])
        if (".".join(module), name) in PUBLIC_UNDERSCORE_NAMES:
            continue
        dotted = ".".join(full)
        if any(_private(p) for p in full) or any(dotted.startswith(m + ".") or dotted == m for m in INTERNAL_MODULES):
            found.add((dotted, line))
    for chain, line in _attribute_chains(source):
        if chain[0] not in GUARDED:
            continue
        dotted = ".".join(chain)
        if any(_private(p) for p in chain[1:]) or any(dotted.startswith(m + ".") for m in INTERNAL_MODULES):
            found.add((dotted, line))
    return found


def _cross_subpackage_violations(source, where):
    parts = pathlib.PurePosixPath(where).parts  # ("sklearn_hardness", subpackage, ..., file)
    own = parts[1] if len(parts) > 2 else None
    found = set()
    for module, name, line in _imports(source, where):
        full = module + ([name] if name and name != "*" else [])
        if full[0] != "sklearn_hardness" or len(full) < 2:
            continue
        other = full[1]
        if other in (own, "utils"):
            continue
        # a private top-level module or package (sklearn_hardness._registry, ._cli), or another
        # subpackage's private module or name (sklearn_hardness.<other>.<...private...>)
        if _private(other) or any(_private(p) for p in full[2:]):
            found.add((".".join(full), line))
    return found


def _rel(path):
    return path.relative_to(ROOT).as_posix()


def test_no_private_scikit_learn_skorch_or_torch_outside_the_compat_module():
    offenders = [
        f"{_rel(path)}:{line}: {dotted}"
        for path in _modules() if _rel(path) != COMPAT_MODULE
        for dotted, line in sorted(_third_party_violations(path.read_text(), _rel(path)))
    ]
    assert offenders == [], (
        "private scikit-learn/skorch/torch code used; take the public name, or add what is missing "
        f"to {COMPAT_MODULE}:\n" + "\n".join(offenders))


def test_public_underscore_names_are_still_public():
    import importlib

    import sklearn
    from packaging.version import Version  # a dependency of pytest

    for module, name in PUBLIC_UNDERSCORE_NAMES:
        assert hasattr(importlib.import_module(module), name), (module, name)
    if Version(sklearn.__version__) >= Version("1.9"):
        assert "_safe_indexing" in importlib.import_module("sklearn.utils").__all__


def test_subpackages_meet_through_public_or_utils_names():
    offenders = [
        f"{_rel(path)}:{line}: {dotted}"
        for path in _modules()
        for dotted, line in sorted(_cross_subpackage_violations(path.read_text(), _rel(path)))
    ]
    assert offenders == [], (
        "a subpackage imports another subpackage's private module or name; import the public name "
        "from its __init__, or move a shared helper to sklearn_hardness/utils/:\n" + "\n".join(offenders))


@pytest.mark.parametrize("source, expected", [
    ("from sklearn.utils._param_validation import Interval", {"sklearn.utils._param_validation.Interval"}),
    ("from sklearn.base import _fit_context", {"sklearn.base._fit_context"}),
    ("from sklearn.utils.validation import _is_arraylike", {"sklearn.utils.validation._is_arraylike"}),
    ("import torch\nx = torch.nn.modules.dropout._DropoutNd", {"torch.nn.modules.dropout._DropoutNd"}),
    ("import torch._dynamo", {"torch._dynamo"}),
    ("from skorch._version import x", {"skorch._version.x"}),
    ("from torch.nn.modules.dropout import Dropout", {"torch.nn.modules.dropout.Dropout"}),
    ("from sklearn.utils import _safe_indexing, check_array\nimport torch\nv = torch.__version__", set()),
    ("from .._private import x\nimport numpy._core", set()),
])
def test_the_third_party_check_sees_each_kind_of_private_use(source, expected):
    found = _third_party_violations(source, "sklearn_hardness/models/_probe.py")
    assert {dotted for dotted, _ in found} == expected


@pytest.mark.parametrize("where, source, expected", [
    ("features/_x.py", "from ..preprocessing._contact_curve import curve",
     {"sklearn_hardness.preprocessing._contact_curve.curve"}),
    ("features/_x.py", "from ..models import _pipelines", {"sklearn_hardness.models._pipelines"}),
    ("features/_x.py", "from sklearn_hardness.datasets._lazy import L", {"sklearn_hardness.datasets._lazy.L"}),
    ("features/_x.py",
     "from ..preprocessing import contact_curve\nfrom ..utils._torch import t\nfrom ._common import c", set()),
    ("_cli/_x.py", "from ..experiments import get_config", set()),
    # private top-level modules are private too: the registry is reached through models alone
    ("model_selection/_x.py", "from .._registry import make_named_pipeline",
     {"sklearn_hardness._registry.make_named_pipeline"}),
    ("_cli/_x.py", "from .._experiment_names import KEY_HELP", {"sklearn_hardness._experiment_names.KEY_HELP"}),
    ("experiments/_x.py", "from .. import _cli", {"sklearn_hardness._cli"}),
    ("models/_x.py", "from ._registry import pipeline_names\nfrom .. import models", set()),
])
def test_the_cross_subpackage_check_sees_private_imports(where, source, expected):
    found = _cross_subpackage_violations(source, f"sklearn_hardness/{where}")
    assert {dotted for dotted, _ in found} == expected
