"""Generated tables carry what made them; the checks hold on any CPU (no float digits compared)."""

import importlib.util
import json
import os
import platform
import re
import shlex

import pytest

from sklearn_hardness._cli import build_parser
from sklearn_hardness._cli._common import _reproduce_command
from sklearn_hardness._cli._reproduce import _README_END, _README_START, _reproduce_config_hash
from sklearn_hardness.experiments import (
    code_fingerprint,
    machine_reference,
    parse_provenance,
    planned_config_hash,
    provenance_header,
)

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
_spec = importlib.util.spec_from_file_location("regenerate_outputs",
                                               os.path.join(ROOT, "benchmarks", "regenerate_outputs.py"))
regen = importlib.util.module_from_spec(_spec)
_spec.loader.exec_module(regen)
RERUN = "python benchmarks/regenerate_outputs.py --quick"


def _command_config_hash(command):
    """What the current code computes for a recorded ``sklearn-hardness reproduce`` command."""
    words = shlex.split(command)
    assert words[:2] == ["sklearn-hardness", "reproduce"], command
    return _reproduce_config_hash(build_parser().parse_args(words[1:]))


def test_code_fingerprint_follows_code_not_docs(tmp_path):
    pkg = tmp_path / "pkg"
    (pkg / "sub").mkdir(parents=True)
    (pkg / "a.py").write_text('"""Module doc."""\n\n\ndef f(x):\n    """Doc."""\n    return x + 1  # one\n')
    (pkg / "sub" / "b.py").write_text("class C:\n    '''Doc.'''\n\n    y = 2\n")
    before = code_fingerprint(root=pkg)
    assert len(before) == 16 and code_fingerprint(root=pkg) == before
    # reworded docstrings, comments and layout: the same code
    (pkg / "a.py").write_text('"""Other words."""\ndef f(x):\n    # a comment\n    return x + 1  # two\n')
    (pkg / "sub" / "b.py").write_text("class C:\n    '''Other.'''\n    y = 2  # why\n")
    assert code_fingerprint(root=pkg) == before
    (pkg / "sub" / "b.py").write_text("class C:\n    y = 3\n")  # a changed constant
    assert code_fingerprint(root=pkg) != before
    (pkg / "sub" / "b.py").write_text("class C:\n    y = 2\n")
    assert code_fingerprint(root=pkg) == before
    (pkg / "sub" / "c.py").write_text("z = 1\n")  # a new module
    assert code_fingerprint(root=pkg) != before
    (pkg / "sub" / "c.py").unlink()
    (pkg / "sub" / "b.py").rename(pkg / "sub" / "d.py")  # a moved module
    assert code_fingerprint(root=pkg) != before
    with pytest.raises(ValueError, match="not a folder"):
        code_fingerprint(root=tmp_path / "missing")


def test_provenance_header_is_one_line_that_reads_back():
    machine = machine_reference(matmul=False)
    assert set(machine) == {"cpu", "cores", "torch_threads", "python", "torch", "numpy", "blas", "matmul_gflops",
                            "load"}
    line = provenance_header("sklearn-hardness reproduce --quick", config_hash="abc", machine=machine,
                             date="2026-01-01T00:00Z", commit="f00")
    assert "\n" not in line
    record = parse_provenance("title\n" + line + "\nbody")
    assert record == {"command": "sklearn-hardness reproduce --quick", "config_hash": "abc",
                      "code_fingerprint": code_fingerprint(), "commit": "f00", "machine": machine,
                      "date": "2026-01-01T00:00Z"}
    assert parse_provenance("no header here") is None
    with pytest.raises(ValueError, match="one-line"):
        provenance_header("a\nb")


def test_machine_reference_measures_the_matmul_rate():
    gflops = machine_reference()["matmul_gflops"]
    assert isinstance(gflops, float) and 0.1 < gflops < 1e5


def test_machine_reference_names_the_kernels_blas_runs_and_what_chose_them():
    # OpenBLAS runs the kernels it picks for the CPU or those OPENBLAS_CORETYPE names; runs that refit a
    # model between choices move in their last digits with them, so the provenance says which ran
    from threadpoolctl import threadpool_info

    from sklearn_hardness.experiments._provenance import _blas

    libraries = [lib for lib in threadpool_info() if lib.get("user_api") == "blas"]
    assert libraries, "numpy and scipy load a BLAS"
    blas = machine_reference(matmul=False)["blas"]
    for lib in libraries:
        assert f"{lib['internal_api']} {lib['version']}" in blas
        if lib.get("architecture"):
            assert f"{lib['version']} {lib['architecture']}" in blas
    # the variables that steer OpenBLAS are named where set, read from the environment given
    plain = _blas(environ={})
    assert "(" not in plain and plain.startswith(blas.split(" (")[0])
    steered = _blas(environ={"OPENBLAS_CORETYPE": "Haswell", "OPENBLAS_L2_SIZE": "512", "OTHER": "1"})
    assert steered == plain + " (OPENBLAS_CORETYPE=Haswell, OPENBLAS_L2_SIZE=512)"


def test_recorded_command_leaves_out_where_output_goes():
    argv = ["reproduce", "--quick", "--out", "o", "--n-jobs", "2", "--readme=R.md", "--quiet", "--set", "a=b c"]
    assert _reproduce_command(argv) == "sklearn-hardness reproduce --quick --n-jobs 2 --set 'a=b c'"
    assert _command_config_hash("sklearn-hardness reproduce --quick --n-jobs 2") == planned_config_hash(
        "silicone5", quick=True)
    assert _command_config_hash("sklearn-hardness reproduce --quick --set n_holdout=5") != planned_config_hash(
        "silicone5", quick=True)
    assert _command_config_hash("sklearn-hardness reproduce --protocol paper") is None


def test_output_index_lists_every_file_with_its_sha256():
    rows = regen.load_index()
    files = regen.output_files()
    listed = [r["file"] for r in rows]
    assert sorted(listed) == listed and len(set(listed)) == len(listed)
    assert set(listed) == set(files), (
        f"docs/_output and its index differ (not indexed: {sorted(set(files) - set(listed))}, "
        f"gone: {sorted(set(listed) - set(files))}); run `python benchmarks/regenerate_outputs.py`.")
    for row in rows:
        assert row["sha256"] == regen.file_sha256(os.path.join(regen.OUTPUT, row["file"])), (
            f"docs/_output/{row['file']} changed after it was indexed (hand edit?); regenerate it with "
            f"`{row['command']}` and run `python benchmarks/regenerate_outputs.py`.")
    with open(os.path.join(regen.OUTPUT, regen.INDEX_MD)) as f:
        assert f.read() == regen.render_index(rows), "INDEX.md is not index.json rendered; run the script."


def test_output_index_rows_are_current_or_say_historical():
    current = code_fingerprint()
    for row in regen.load_index():
        assert row["status"] in regen.STATUSES
        if row["status"] == "historical":
            assert row["code_fingerprint"] is None and "before provenance" in row["note"] and row["commit"]
            continue
        with open(os.path.join(regen.OUTPUT, row["file"])) as f:
            made = regen.provenance_row(row["file"], f.read())
        made.pop("status")
        extra = ("sha256", "status", "note") + (("python",) if "python" not in made else ())
        assert made == {k: v for k, v in row.items() if k not in extra}
        if row["status"] == "earlier code":
            # made by the code of its commit, not rerun since: the note says why it stands, and
            # the commit's package (where this clone has it) is the code the file names
            assert row["note"] and row["code_fingerprint"] != current
            assert "+dirty" not in row["commit"], f"{row['file']} was made by uncommitted code"
            at_commit = regen.fingerprint_at(row["commit"])
            # files made before the fingerprint ignored the Python version carry the legacy one,
            # computed by the Python that made them: checkable here only on that Python's minor version
            made_on = ".".join(row.get("python", "").split(".")[:2])
            other_python = bool(made_on) and made_on != ".".join(platform.python_version_tuple()[:2])
            assert at_commit is None or other_python or row["code_fingerprint"] in at_commit, (
                f"docs/_output/{row['file']} names commit {row['commit']}, whose code is {at_commit}, "
                f"not the {row['code_fingerprint']} that made it")
            # a legacy fingerprint with no Python recorded fails this check on every other Python
            # (seen on Python 3.12): the row must say which Python computed it
            legacy_only = at_commit is not None and row["code_fingerprint"] == at_commit[1] != at_commit[0]
            assert not legacy_only or made_on, (
                f"docs/_output/{row['file']} carries the legacy fingerprint of commit {row['commit']}, which "
                "depends on the Python that computed it; record that Python: "
                f"python benchmarks/regenerate_outputs.py --python {row['file']} X.Y")
            continue
        assert row["code_fingerprint"] == current, (
            f"docs/_output/{row['file']} was made by other code ({row['code_fingerprint']}, now {current}); "
            f"rerun `{row['command']}` (for the quick table: `{RERUN}`), or keep it with "
            f"`python benchmarks/regenerate_outputs.py --earlier-code {row['file']} \"why it stands\"`.")
        if row["config_hash"] is not None:
            assert row["config_hash"] == _command_config_hash(row["command"]), (
                f"the configuration of `{row['command']}` changed since docs/_output/{row['file']} was made; "
                f"rerun it (for the quick table: `{RERUN}`).")


def test_index_keeps_a_file_of_earlier_code_only_with_a_note(tmp_path):
    line = provenance_header("sklearn-hardness reproduce --quick", config_hash="abc",
                             machine=machine_reference(matmul=False), date="2026-01-01T00:00Z", commit="f00")
    old = line.replace(code_fingerprint(), "0123456789abcdef")
    (tmp_path / "now.txt").write_text(line + "\ntable\n")
    (tmp_path / "old.txt").write_text(old + "\ntable\n")
    with pytest.raises(SystemExit, match="old.txt: made by other code.*--earlier-code old.txt"):
        regen.build_index(tmp_path)
    with pytest.raises(SystemExit, match="no such file"):
        regen.build_index(tmp_path, earlier_code={"gone.txt": "why"})
    rows = {r["file"]: r for r in regen.build_index(tmp_path, earlier_code={"old.txt": "a refactor"})}
    assert rows["now.txt"]["status"] == "current" and "note" not in rows["now.txt"]
    assert rows["old.txt"]["status"] == "earlier code" and rows["old.txt"]["note"] == "a refactor"
    regen.write_index(list(rows.values()), tmp_path)
    # the note is kept by later rebuilds while the file is the same run
    again = {r["file"]: r for r in regen.build_index(tmp_path)}
    assert again["old.txt"] == rows["old.txt"]
    # a rerun by today's code makes it current again
    (tmp_path / "old.txt").write_text(line + "\nnew table\n")
    assert {r["file"]: r["status"] for r in regen.build_index(tmp_path)}["old.txt"] == "current"


def test_fingerprint_at_a_commit_is_that_commits_code():
    # 3f0609a9d0 made the everyday tables; its package hashed to 75910e509d7dcabe
    at = regen.fingerprint_at("3f0609a9d0")
    if at is not None:  # a shallow clone may not have it
        # the legacy fingerprint of Python 3.10 and 3.11 (3.12 and 3.13 gave others)
        assert at[1] == "75910e509d7dcabe" or platform.python_version_tuple()[:2] not in (("3", "10"), ("3", "11"))
        assert at[0] == "99ca6471feb2f688"  # the same on every Python
    assert regen.fingerprint_at("not-a-commit") is None


def test_readme_quick_table_carries_the_current_code_and_config():
    with open(os.path.join(ROOT, "README.md")) as f:
        text = f.read()
    block = text[text.index(_README_START):text.index(_README_END)]
    match = re.search(r"<!-- provenance (\{.*\}) -->", block)
    assert match, f"README's quick table has no provenance line; run `{RERUN}`."
    record = json.loads(match.group(1))
    assert record["command"] == "sklearn-hardness reproduce --quick --n-jobs 2"
    assert record["code_fingerprint"] == code_fingerprint(), (
        f"README's quick table was made by other code; run `{RERUN}` and commit README.md and docs/_output.")
    assert record["config_hash"] == _command_config_hash(record["command"]), (
        f"the --quick configuration changed since README's table was made; run `{RERUN}`.")
    # the docs' copy of the table is the same run
    with open(os.path.join(regen.OUTPUT, "reproduce_quick.txt")) as f:
        docs = parse_provenance(f.read())
    assert {k: docs[k] for k in record} == record
    fence = block.split("```")[1].strip("\n")
    assert fence in open(os.path.join(regen.OUTPUT, "reproduce_quick.txt")).read(), (
        f"README's quick table and docs/_output/reproduce_quick.txt are not one run; run `{RERUN}`.")
