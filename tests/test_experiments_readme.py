"""README's quick table is made by its command, through the harness (``python -m harness.readme_table``).

The command's table has the right form and plausible figures. The digits are one
CPU's floats: they are not compared with README's.
"""

import json
import os
import re

import pytest

from harness import ROOT
from harness.readme_table import COMMAND, END, START, main, table_of, write_readme_table


def test_readme_table_block_is_replaced_in_place(tmp_path):
    path = tmp_path / "R.md"
    path.write_text(f"intro\n{START}\nold\n{END}\nafter\n")
    assert write_readme_table(path, "a  b\n-  -")
    assert path.read_text() == f"intro\n{START}\n```\na  b\n-  -\n```\n{END}\nafter\n"
    assert not write_readme_table(path, "a  b\n-  -")  # idempotent
    path.write_text("no markers")
    with pytest.raises(ValueError, match="no"):
        write_readme_table(path, "x")


def test_readme_block_carries_its_header(tmp_path):
    path = tmp_path / "R.md"
    path.write_text(f"{START}\nold\n{END}\n")
    prov = {"command": COMMAND, "commit": "f00", "date": "2026-01-01T00:00Z",
            "machine": "cpu, 2 cores, matmul 80 GFLOP/s (one thread)"}
    assert write_readme_table(path, "t", prov)
    assert path.read_text() == f'{START}\n<!-- provenance {json.dumps(prov)} -->\n```\nt\n```\n{END}\n'
    assert not write_readme_table(path, "t", prov)


def test_readme_has_the_block_the_harness_writes():
    with open(os.path.join(ROOT, "README.md")) as f:
        text = f.read()
    assert text.count(START) == 1 and text.count(END) == 1 and text.index(START) < text.index(END)
    block = text.split(START)[1].split(END)[0]
    assert json.loads(re.search(r"<!-- provenance (\{.*\}) -->", block).group(1))["command"] == COMMAND
    assert f"```bash\n{COMMAND}\n```" in text  # README's main command is the table's


def test_table_of_needs_the_note_after_the_table():
    with pytest.raises(ValueError, match="no comparison table"):
        table_of("# provenance {}\nheader\nrows without a note")


@pytest.mark.slow
def test_readme_command_writes_a_table_of_the_right_form_with_plausible_figures(tmp_path):
    """``python -m harness.readme_table``: rows, columns, ranges and run counts; a header of command, commit, date,
    machine."""
    from sklearn_hardness._cli._header import read_header
    from sklearn_hardness.experiments._active import STRATEGIES
    from sklearn_hardness.experiments._tables import HUMAN_ACCURACY

    readme = tmp_path / "README.md"
    readme.write_text(f"# title\n\n{START}\nold table\n{END}\n\nafter\n")
    main(["--readme", str(readme), "--out", str(tmp_path / "out")])
    text = (tmp_path / "out" / "table.txt").read_text()
    record = read_header(text)
    assert text.splitlines()[0].startswith("# provenance ")
    assert record["command"] == COMMAND == "sklearn-hardness reproduce --quick --n-jobs 2"
    assert re.fullmatch(r"\d{4}-\d\d-\d\dT\d\d:\d\dZ", record["date"])
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
    block = readme.read_text().split(START)[1].split(END)[0]
    prov = json.loads(re.search(r"<!-- provenance (\{.*\}) -->", block).group(1))
    assert set(prov) == {"command", "commit", "date", "machine"}
    assert prov["command"] == COMMAND and prov["date"] == record["date"] and "GFLOP/s" in prov["machine"]
    table = block.split("```")[1].strip("\n")
    assert table == table_of(text) and table in text and "old table" not in block
    assert readme.read_text().startswith("# title\n") and readme.read_text().endswith("\nafter\n")
