"""README's quick table is made by its command: the command's table has the right form and plausible figures.

The digits are one CPU's floats: they are not compared with README's, and README is not read.
"""

import json
import re

import pytest

from sklearn_hardness._cli._common import _UsageError
from sklearn_hardness._cli._reproduce import _README_END, _README_START, _write_readme_table


def test_readme_table_block_is_replaced_in_place(tmp_path):
    path = tmp_path / "R.md"
    path.write_text(f"intro\n{_README_START}\nold\n{_README_END}\nafter\n")
    assert _write_readme_table(path, "a  b\n-  -")
    assert path.read_text() == f"intro\n{_README_START}\n```\na  b\n-  -\n```\n{_README_END}\nafter\n"
    assert not _write_readme_table(path, "a  b\n-  -")  # idempotent
    path.write_text("no markers")
    with pytest.raises(_UsageError, match="no"):
        _write_readme_table(path, "x")


def test_readme_block_carries_its_header(tmp_path):
    path = tmp_path / "R.md"
    path.write_text(f"{_README_START}\nold\n{_README_END}\n")
    prov = {"command": "sklearn-hardness reproduce --quick", "commit": "f00", "date": "2026-01-01T00:00Z",
            "machine": "cpu, 2 cores, matmul 80.0 GFLOP/s"}
    assert _write_readme_table(path, "t", prov)
    assert path.read_text() == (f'{_README_START}\n<!-- provenance {json.dumps(prov)} -->\n```\nt\n```\n'
                                f"{_README_END}\n")
    assert not _write_readme_table(path, "t", prov)


@pytest.mark.slow
def test_reproduce_quick_writes_a_table_of_the_right_form_with_plausible_figures(tmp_path):
    """``reproduce --quick --n-jobs 2 --readme``: rows, columns, ranges and run counts; a header, no fingerprint."""
    from sklearn_hardness._cli import main
    from sklearn_hardness.experiments._active import STRATEGIES
    from sklearn_hardness.experiments._provenance import parse_provenance
    from sklearn_hardness.experiments._tables import HUMAN_ACCURACY

    readme = tmp_path / "README.md"
    readme.write_text(f"# title\n\n{_README_START}\nold table\n{_README_END}\n\nafter\n")
    assert main(["reproduce", "--quick", "--n-jobs", "2", "--out", str(tmp_path / "out"), "--quiet",
                 "--readme", str(readme)]) == 0
    text = (tmp_path / "out" / "table.txt").read_text()
    record = parse_provenance(text)
    assert text.splitlines()[0].startswith("# provenance ")
    assert record["command"] == "sklearn-hardness reproduce --quick --n-jobs 2"
    assert "code_fingerprint" not in record
    assert record["machine"]["matmul_gflops"] > 0 and re.fullmatch(r"\d{4}-\d\d-\d\dT\d\d:\d\dZ", record["date"])
    lines = text.splitlines()
    header = next(line for line in lines if line.lstrip().startswith("accuracy"))
    assert header.split() == ["accuracy", "MAE", "(mm/N)", "runs", "converged"]
    rows = {}
    for line in lines:
        m = re.match(r"(no resampling|\w+(?: \(paper\))?)\s+(\d+\.\d\d)% \+- +(\d+\.\d\d)%\s+(.*)$", line)
        if m:
            rows[m.group(1)] = (float(m.group(2)), float(m.group(3)), m.group(4))
    assert list(rows) == ["no resampling", *STRATEGIES, "humans (paper)"]
    assert list(rows) == ["no resampling", "variance", "entropy", "random", "bald", "humans (paper)"]
    assert rows["humans (paper)"][:2] == (round(100 * HUMAN_ACCURACY[0], 2), round(100 * HUMAN_ACCURACY[1], 2))
    assert rows["humans (paper)"][2].strip() == "n/a"
    for name in ["no resampling", *STRATEGIES]:
        acc, sd, rest = rows[name]
        assert 0 <= acc <= 100 and 0 <= sd <= 100
        mae, mae_sd, runs, share = re.fullmatch(r"(\d+\.\d{3}) \+- (\d+\.\d{3})\s+(\d)/5\s+(\d+)%", rest).groups()
        assert float(mae) >= 0 and float(mae_sd) >= 0
        assert 1 <= int(runs) <= 5 and int(share) == 20 * int(runs)  # 1 seed x 5 test objects
    # the README block: this run's table under a header of command, commit, date and machine
    block = readme.read_text().split(_README_START)[1].split(_README_END)[0]
    header = json.loads(re.search(r"<!-- provenance (\{.*\}) -->", block).group(1))
    assert set(header) == {"command", "commit", "date", "machine"}
    assert header["command"] == record["command"] and "GFLOP/s" in header["machine"]
    table = block.split("```")[1].strip("\n")
    assert table in text and "old table" not in block
    assert readme.read_text().startswith("# title\n") and readme.read_text().endswith("\nafter\n")
