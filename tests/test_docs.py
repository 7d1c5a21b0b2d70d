"""The API reference lists every public name, and the docs build works offline."""

import importlib
import re
import runpy
from pathlib import Path

import pytest

import sklearn_hardness

from ._references import dangling_references

DOCS = Path(__file__).resolve().parents[1] / "docs"
SUBPACKAGES = [name for name in sklearn_hardness.__all__ if not name.startswith("_")]
#: Public modules below a subpackage, documented by their dotted path.
PUBLIC_MODULES = ["utils.estimator_checks"]


def _api_entries(text=None):
    """``subpackage.name`` entries of the autosummary blocks in docs/api.rst (or in ``text``)."""
    entries, in_block = [], False
    text = (DOCS / "api.rst").read_text() if text is None else text
    for line in text.splitlines():
        if line.startswith(".. autosummary::"):
            in_block = True
        elif in_block and line and not line[0].isspace():
            in_block = False
        elif in_block and (m := re.fullmatch(r"\s+(\w+(?:\.\w+)?)\.(\w+)\s*", line)):
            entries.append((m.group(1), m.group(2)))
    return entries


def _public_names():
    return {(sub, name) for sub in SUBPACKAGES + PUBLIC_MODULES
            for name in importlib.import_module(f"sklearn_hardness.{sub}").__all__}


def test_every_public_name_is_in_the_api_reference():
    missing = sorted(f"{sub}.{name}" for sub, name in _public_names() - set(_api_entries()))
    assert not missing, f"public names missing from docs/api.rst (add them to an autosummary block): {missing}"


def test_api_reference_lists_only_public_names_once():
    entries = _api_entries()
    assert len(entries) >= 50  # the parser found the blocks
    unknown = sorted(f"{sub}.{name}" for sub, name in set(entries) - _public_names())
    assert not unknown, f"docs/api.rst lists names that are not in their subpackage's __all__: {unknown}"
    duplicated = sorted({f"{s}.{n}" for s, n in entries if entries.count((s, n)) > 1})
    assert not duplicated, f"listed twice in docs/api.rst: {duplicated}"


def test_the_parser_sees_a_removed_entry():
    # Guard against a parser that misreads the file and so passes the completeness test vacuously.
    text = (DOCS / "api.rst").read_text()
    assert "   active.bald_sampling\n" in text
    entries = set(_api_entries(text.replace("   active.bald_sampling\n", "")))
    assert ("active", "bald_sampling") not in entries
    assert ("active", "bald_sampling") in _public_names() - entries
    # a name outside an autosummary block does not count
    assert ("io", "read_video") not in set(_api_entries("Text\n\n   io.read_video\n"))


def _conf(monkeypatch, value):
    if value is None:
        monkeypatch.delenv("SKLEARN_HARDNESS_INTERSPHINX", raising=False)
    else:
        monkeypatch.setenv("SKLEARN_HARDNESS_INTERSPHINX", str(value))
    return runpy.run_path(str(DOCS / "conf.py"))


def test_docs_build_needs_no_network_by_default(monkeypatch):
    conf = _conf(monkeypatch, None)
    assert conf["intersphinx_mapping"] == {}
    assert conf["release"] == sklearn_hardness.__version__


def test_intersphinx_from_a_local_inventory_dir(monkeypatch, tmp_path):
    (tmp_path / "numpy.inv").write_bytes(b"# Sphinx inventory version 2\n")
    conf = _conf(monkeypatch, tmp_path)
    assert conf["intersphinx_mapping"] == {"numpy": ("https://numpy.org/doc/stable", str(tmp_path / "numpy.inv"))}
    assert set(_conf(monkeypatch, "online")["intersphinx_mapping"]) == {"python", "numpy", "sklearn", "skorch"}
    with pytest.raises(RuntimeError, match="neither 'online' nor a directory"):
        _conf(monkeypatch, tmp_path / "missing")


def test_shape_names_with_trailing_underscore_are_escaped(monkeypatch):
    conf = _conf(monkeypatch, None)
    lines = ["X_out : ndarray of shape (n_samples, n_features_out_), float32", "see ``n_features_out_``"]
    conf["_escape_shape_names"](None, "method", "f", None, {}, lines)
    assert lines == ["X_out : ndarray of shape (n_samples, n_features_out\\_), float32", "see ``n_features_out_``"]


def test_every_user_guide_page_is_in_the_toctree():
    index = (DOCS / "user_guide" / "index.rst").read_text()
    pages = {p.stem for p in (DOCS / "user_guide").glob("*.rst")} - {"index"}
    missing = sorted(p for p in pages if not re.search(rf"^\s+{p}\s*$", index, flags=re.M))
    assert not missing, f"user guide pages not in docs/user_guide/index.rst: {missing}"


def _prose():
    """(path, line number, line) of README, the docs' pages and the examples' comments."""
    root = DOCS.parent
    pages = [root / "README.md", *DOCS.glob("*.md"), *DOCS.glob("*.rst"), *(DOCS / "user_guide").glob("*.rst")]
    for path in pages + sorted((root / "examples").glob("*.py")):
        for number, line in enumerate(path.read_text().splitlines(), 1):
            if path.suffix != ".py" or line.lstrip().startswith("#"):
                yield path.relative_to(root), number, line


def test_prose_cites_only_public_names():
    # Sphinx checks the roles (nitpicky); this checks plain-text and literal names, and README
    dangling = [f"{path}:{number}: {ref}" for path, number, line in _prose() for ref in dangling_references(line)]
    assert not dangling, f"references to names that are not public: {dangling}"


def test_the_docs_build_fails_on_a_dangling_reference(monkeypatch):
    conf = _conf(monkeypatch, None)
    assert conf["nitpicky"] is True
    assert "-W" in (DOCS / "build_docs.sh").read_text().split()
    # the only exceptions are other projects' names, not ours
    for _, target in conf["nitpick_ignore_regex"]:
        assert not re.fullmatch(target, "sklearn_hardness.models.is_converged")
        assert not re.fullmatch(target, "is_converged")


def test_api_pages_link_public_bases_and_qualify_bare_names(monkeypatch):
    from skorch import NeuralNetClassifier

    from sklearn_hardness.models import OFNNClassifier

    conf = _conf(monkeypatch, None)
    bases = list(OFNNClassifier.__bases__)  # the private _MLPClassifier
    conf["_public_bases"](None, "OFNNClassifier", OFNNClassifier, {}, bases)
    assert bases == [NeuralNetClassifier]
    # a bare name of the docstring's own subpackage is qualified (it resolves in api.rst too);
    # a private one is left as it is, to fail the nitpicky build
    lines = [":func:`run_active_sampling` of :data:`PAIRED_METRICS`"]
    conf["_qualify_bare_references"](None, "method", "sklearn_hardness.experiments.ExperimentResult.paired_table",
                                     None, {}, lines)
    assert lines == [":func:`~sklearn_hardness.experiments.run_active_sampling` of :data:`PAIRED_METRICS`"]
    assert conf["_skip_members"](None, "class", "fit", NeuralNetClassifier.fit, False, {}) is True
    assert conf["_skip_members"](None, "class", "predict_proba_samples",
                                 OFNNClassifier.predict_proba_samples, False, {}) is None
