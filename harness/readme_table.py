"""README's quick table, remade by its command.

Runs ``sklearn-hardness reproduce --quick --n-jobs 2`` and writes its comparison
table between README's markers, under an HTML comment naming the command, the
commit, the date and the machine with its one-thread matmul rate:

    python -m harness.readme_table                 # README.md of this repository
    python -m harness.readme_table --readme R.md --out results

The digits are one machine's floats; the test of this module checks the table's
form and plausibility, not README's digits.
"""

from __future__ import annotations

import argparse
import json
import os
import shlex
import tempfile

from . import ROOT
from .cli import run_sklearn_hardness
from .machine import describe, machine_reference
from .provenance import git_commit, provenance_record

__all__ = ["COMMAND", "START", "END", "write_readme_table", "table_of", "main"]

#: README's main command: the table under it is this command's.
COMMAND = "sklearn-hardness reproduce --quick --n-jobs 2"
START = "<!-- reproduce-quick-table: start -->"
END = "<!-- reproduce-quick-table: end -->"
#: The line after the table in ``table.txt``.
_NOTE = "Accuracy and MAE after"


def _block(text, path):
    start, end = text.find(START), text.find(END)
    if start < 0 or end < start:
        raise ValueError(f"{path} has no '{START}' ... '{END}' block to write the table into.")
    return start, end


def write_readme_table(path, table, provenance=None):
    """Replace the block between README's markers by ``table`` (in a code fence).

    Parameters
    ----------
    path : str or path-like
        The README.
    table : str
        The table's lines.
    provenance : dict or None, default=None
        What made the table (command, commit, date, machine): an HTML comment
        line above the fence.

    Returns
    -------
    changed : bool
        Whether the file was rewritten.
    """
    with open(path) as f:
        text = f.read()
    start, end = _block(text, path)
    comment = f"\n<!-- provenance {json.dumps(provenance)} -->" if provenance else ""
    new = text[: start + len(START)] + comment + "\n```\n" + table + "\n```\n" + text[end:]
    if new != text:
        with open(path, "w") as f:
            f.write(new)
    return new != text


def table_of(text):
    """The comparison table of a ``table.txt``: the lines between its two header lines and the note.

    Examples
    --------
    >>> from harness.readme_table import table_of
    >>> table_of("# provenance {}\\nsilicone5 ...\\n  accuracy\\n--\\nAccuracy and MAE after 5 iterations")
    '  accuracy\\n--'
    """
    lines = text.splitlines()
    note = next((i for i, line in enumerate(lines) if line.startswith(_NOTE)), None)
    if note is None or note < 3:
        raise ValueError(f"no comparison table followed by '{_NOTE} ...' in this text.")
    return "\n".join(lines[2:note])


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--readme", default=os.path.join(ROOT, "README.md"), help="the README (default: this repository's)")
    ap.add_argument("--out", default=None, help="reproduce's --out (default: a temporary folder)")
    args = ap.parse_args(argv)
    with open(args.readme) as f:
        _block(f.read(), args.readme)  # before minutes of runs
    commit, machine = git_commit() or "unknown", machine_reference()  # the code that runs, the idle machine
    with tempfile.TemporaryDirectory() as tmp:
        out = args.out or tmp
        words = shlex.split(COMMAND)[1:]
        run_sklearn_hardness([*words, "--out", out, "--quiet"])
        with open(os.path.join(out, "table.txt")) as f:
            text = f.read()
    record = provenance_record(text)
    provenance = {"command": record["command"], "commit": commit, "date": record["date"],
                  "machine": describe(machine)}
    changed = write_readme_table(args.readme, table_of(text), provenance)
    print(f"{'updated' if changed else 'unchanged'}: the table in {args.readme}")


if __name__ == "__main__":
    main()
