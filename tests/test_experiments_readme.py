"""No typed results: README's --quick table is what the command beside it prints."""

import os
import shutil

import pytest

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))


def test_readme_table_block_is_replaced_in_place(tmp_path):
    from sklearn_hardness._cli import _README_END, _README_START, _UsageError, _write_readme_table

    path = tmp_path / "R.md"
    path.write_text(f"intro\n{_README_START}\nold\n{_README_END}\nafter\n")
    assert _write_readme_table(path, "a  b\n-  -")
    assert path.read_text() == f"intro\n{_README_START}\n```\na  b\n-  -\n```\n{_README_END}\nafter\n"
    assert not _write_readme_table(path, "a  b\n-  -")  # idempotent
    path.write_text("no markers")
    with pytest.raises(_UsageError, match="no"):
        _write_readme_table(path, "x")


@pytest.mark.slow
def test_readme_quick_table_is_what_the_code_produces(tmp_path, capsys):
    """Fails when README.md's table differs from `reproduce --quick --n-jobs 2` (regenerate with --readme)."""
    from sklearn_hardness._cli import main

    readme = tmp_path / "README.md"
    shutil.copy(os.path.join(ROOT, "README.md"), readme)
    before = readme.read_text()
    assert main(["reproduce", "--quick", "--n-jobs", "2", "--out", str(tmp_path / "out"), "--quiet",
                 "--readme", str(readme)]) == 0
    assert readme.read_text() == before, (
        "README.md's --quick table is not what the code produces; run "
        "`sklearn-hardness reproduce --quick --n-jobs 2 --readme README.md` and commit the result.")
    # the same table in the docs' "Getting started" page
    docs_table = os.path.join(ROOT, "docs", "_output", "reproduce_quick.txt")
    with open(docs_table) as f, open(tmp_path / "out" / "table.txt") as g:
        assert f.read() == g.read(), (
            "docs/_output/reproduce_quick.txt is not what the code produces; copy OUT/table.txt of "
            "`sklearn-hardness reproduce --quick --n-jobs 2 --out OUT` there.")
