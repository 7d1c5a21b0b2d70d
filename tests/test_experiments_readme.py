"""No typed results: README's --quick table is what the command beside it prints, with its provenance."""

import json
import os
import re
import shutil

import pytest

from sklearn_hardness._cli._common import _UsageError
from sklearn_hardness._cli._reproduce import _README_END, _README_START, _write_readme_table

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))


def test_readme_table_block_is_replaced_in_place(tmp_path):
    path = tmp_path / "R.md"
    path.write_text(f"intro\n{_README_START}\nold\n{_README_END}\nafter\n")
    assert _write_readme_table(path, "a  b\n-  -")
    assert path.read_text() == f"intro\n{_README_START}\n```\na  b\n-  -\n```\n{_README_END}\nafter\n"
    assert not _write_readme_table(path, "a  b\n-  -")  # idempotent
    path.write_text("no markers")
    with pytest.raises(_UsageError, match="no"):
        _write_readme_table(path, "x")


def test_readme_block_carries_provenance_and_stays_idempotent(tmp_path):
    path = tmp_path / "R.md"
    path.write_text(f"{_README_START}\nold\n{_README_END}\n")
    prov = {"command": "sklearn-hardness reproduce --quick", "config_hash": "c", "code_fingerprint": "f"}
    assert _write_readme_table(path, "t", prov)
    assert path.read_text() == (f'{_README_START}\n<!-- provenance {json.dumps(prov)} -->\n```\nt\n```\n'
                                f"{_README_END}\n")
    assert not _write_readme_table(path, "t", prov)
    assert _write_readme_table(path, "t", dict(prov, code_fingerprint="g"))  # other code: rewritten


@pytest.mark.slow
def test_reproduce_quick_writes_a_well_formed_table_with_current_provenance(tmp_path):
    """The quick run's table: structure, ranges and run counts, and the provenance of this code.

    The digits are not compared with README's: they are one CPU's floats. README's block is
    checked against the current code's fingerprint and config hash in tests/test_experiments_provenance.py.
    """
    from sklearn_hardness._cli import main
    from sklearn_hardness.experiments import (
        HUMAN_ACCURACY,
        STRATEGIES,
        code_fingerprint,
        parse_provenance,
        planned_config_hash,
    )

    readme = tmp_path / "README.md"
    shutil.copy(os.path.join(ROOT, "README.md"), readme)
    assert main(["reproduce", "--quick", "--n-jobs", "2", "--out", str(tmp_path / "out"), "--quiet",
                 "--readme", str(readme)]) == 0
    text = (tmp_path / "out" / "table.txt").read_text()
    record = parse_provenance(text)
    assert text.splitlines()[0].startswith("# provenance ")
    assert record["command"] == "sklearn-hardness reproduce --quick --n-jobs 2"
    assert record["code_fingerprint"] == code_fingerprint()
    assert record["config_hash"] == planned_config_hash("silicone5", quick=True)
    assert record["machine"]["matmul_gflops"] > 0 and re.fullmatch(r"\d{4}-\d\d-\d\dT\d\d:\d\dZ", record["date"])
    rows = {}
    for line in text.splitlines():
        m = re.match(r"(no resampling|\w+(?: \(paper\))?)\s+(\d+\.\d\d)% \+- +(\d+\.\d\d)%\s+(.*)$", line)
        if m:
            rows[m.group(1)] = (float(m.group(2)), float(m.group(3)), m.group(4))
    assert list(rows) == ["no resampling", *STRATEGIES, "humans (paper)"]
    assert rows["humans (paper)"][:2] == (round(100 * HUMAN_ACCURACY[0], 2), round(100 * HUMAN_ACCURACY[1], 2))
    for name in ["no resampling", *STRATEGIES]:
        acc, sd, rest = rows[name]
        assert 0 <= acc <= 100 and 0 <= sd <= 100
        mae, runs, share = re.fullmatch(r"(\d\.\d{3}) \+- \d\.\d{3}\s+(\d)/5\s+(\d+)%", rest).groups()
        assert 0 <= float(mae) < 1 and int(share) == 20 * int(runs)  # 1 seed x 5 test objects
    # README's block: this run's table under this code's provenance line
    block = readme.read_text().split(_README_START)[1].split(_README_END)[0]
    assert json.loads(re.search(r"<!-- provenance (\{.*\}) -->", block).group(1)) == {
        k: record[k] for k in ("command", "config_hash", "code_fingerprint")}
    assert block.split("```")[1].strip("\n") in text
