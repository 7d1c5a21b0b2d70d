"""Regenerate the quick artefacts and the index of ``docs/_output`` (what made each file).

``--quick`` reruns ``sklearn-hardness reproduce --quick --n-jobs 2 --readme README.md``
(README's table block and its provenance line) and copies its ``table.txt``, which
starts with a provenance line, to ``docs/_output/reproduce_quick.txt``. Always, the
index is rebuilt: ``docs/_output/index.json`` (one row per file: command, config
hash, code fingerprint, commit, machine with its matmul GFLOP/s, date, sha256) and
``docs/_output/INDEX.md`` rendered from it. Rows of files that carry a provenance
line are read from that line: "current" when the code fingerprint in it is
today's, "earlier code" when it is not and its row says why the result still
stands (``--earlier-code FILE NOTE`` writes that note; the test then checks the
fingerprint against the package at the named commit); files made before
provenance existed keep their hand-written "historical" rows. The script stops
if a historical file changed, a file has no row, or a file made by other code
has no note (rerun its command, or record why its result stands). Idempotent: on unchanged code
README's block stays as it is unless the rerun gives other digits (another CPU);
``reproduce_quick.txt`` gets this run's provenance line (machine, date) and its
index row follows it.

    python benchmarks/regenerate_outputs.py --quick   # about 1-2 min on 2 cores
    python benchmarks/regenerate_outputs.py           # the index only
    python benchmarks/regenerate_outputs.py --earlier-code FILE "why it stands"
    python benchmarks/regenerate_outputs.py --earlier-code FILE "why" --python FILE 3.12
"""

import argparse
import hashlib
import io
import json
import os
import shutil
import subprocess
import sys
import tarfile
import tempfile

from sklearn_hardness._cli import main as cli
from sklearn_hardness.experiments import code_fingerprint, parse_provenance

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
OUTPUT = os.path.join(ROOT, "docs", "_output")
INDEX_JSON, INDEX_MD = "index.json", "INDEX.md"
QUICK = ["reproduce", "--quick", "--n-jobs", "2"]
STATUSES = ("current", "earlier code", "historical")
COLUMNS = ("file", "status", "command", "config_hash", "code_fingerprint", "commit", "machine",
           "matmul_gflops", "date", "sha256")


def file_sha256(path):
    with open(path, "rb") as f:
        return hashlib.sha256(f.read()).hexdigest()


def machine_text(machine):
    """One phrase for a provenance's machine dict."""
    python = f", Python {machine['python']}" if machine.get("python") else ""
    blas = f", {machine['blas']}" if machine.get("blas") else ""  # older records have none
    return (f"{machine['cpu']}, {machine['cores']} cores, {machine['torch_threads']} torch threads, "
            f"torch {machine['torch']}, numpy {machine['numpy']}{python}{blas}, load {machine.get('load')}")


def provenance_row(name, text):
    """The index row of a file whose text starts with a provenance line (None without one)."""
    record = parse_provenance(text)
    if record is None:
        return None
    return {"file": name, "status": "current", "command": record["command"],
            "config_hash": record["config_hash"], "code_fingerprint": record["code_fingerprint"],
            "commit": record["commit"], "machine": machine_text(record["machine"]),
            "matmul_gflops": record["machine"]["matmul_gflops"], "date": record["date"],
            **({"python": record["machine"]["python"]} if record["machine"].get("python") else {})}


def fingerprint_at(commit, root=ROOT):
    """:func:`code_fingerprint` of the package as committed at ``commit`` (None without that commit).

    Reads the commit's ``sklearn_hardness`` tree with ``git archive``, so a
    file made by earlier code can be checked against the code it names.
    Returns the pair (fingerprint, legacy fingerprint on this Python): files
    made before 2026-11-24 carry the legacy one, which depends on the Python
    version that computed it.
    """
    commit = commit.split("+")[0]
    try:
        tar = subprocess.run(["git", "archive", "--format=tar", commit, "sklearn_hardness"], cwd=root,
                             capture_output=True, timeout=60, check=True).stdout
    except (OSError, subprocess.SubprocessError):
        return None
    with tempfile.TemporaryDirectory() as tmp:
        with tarfile.open(fileobj=io.BytesIO(tar)) as archive:
            # the "data" filter (no links out, no absolute paths) where this Python has it
            archive.extractall(tmp, **({"filter": "data"} if hasattr(tarfile, "data_filter") else {}))
        root = os.path.join(tmp, "sklearn_hardness")
        return code_fingerprint(root=root), code_fingerprint(root=root, legacy=True)


def output_files(folder=OUTPUT):
    return sorted(f for f in os.listdir(folder) if f not in (INDEX_JSON, INDEX_MD)
                  and os.path.isfile(os.path.join(folder, f)))


def load_index(folder=OUTPUT):
    path = os.path.join(folder, INDEX_JSON)
    if not os.path.exists(path):
        return []
    with open(path) as f:
        return json.load(f)


def build_index(folder=OUTPUT, earlier_code=None, python=None):
    """Rows for every file of ``folder``: from its provenance line, else its historical row.

    ``earlier_code`` maps file names to the note that says why a file made by
    other code than today's still stands (it replaces the note in the index).
    ``python`` maps file names to the Python version that made them, for files
    whose provenance line predates its ``python`` field (their legacy code
    fingerprint depends on it).
    """
    old = {row["file"]: row for row in load_index(folder)}
    earlier_code = dict(earlier_code or {})
    python = dict(python or {})
    unknown = (set(earlier_code) | set(python)) - set(output_files(folder))
    if unknown:
        raise SystemExit(f"--earlier-code/--python: no such file in docs/_output: {sorted(unknown)}")
    today = code_fingerprint()
    rows, problems = [], []
    for name in output_files(folder):
        path = os.path.join(folder, name)
        try:
            with open(path, encoding="utf-8") as f:
                row = provenance_row(name, f.read())
        except UnicodeDecodeError:  # images
            row = None
        if row is not None and row["code_fingerprint"] != today:
            before = old.get(name, {})
            note = earlier_code.get(name)
            if note is None and before.get("status") == "earlier code" \
                    and before.get("code_fingerprint") == row["code_fingerprint"]:
                note = before.get("note")
            if not note:
                problems.append(f"{name}: made by other code ({row['code_fingerprint']}, today {today}); "
                                f"rerun `{row['command']}`, or say why its result stands: "
                                f"--earlier-code {name} \"WHY\"")
                continue
            row = dict(row, status="earlier code", note=note)
            made_with = python.get(name) or before.get("python")
            if made_with and "python" not in row:
                row["python"] = made_with
        if row is None:
            row = old.get(name)
            if row is None or row.get("status") != "historical":
                problems.append(f"{name}: no provenance line and no historical row in {INDEX_JSON}")
                continue
            if row["sha256"] != file_sha256(path):
                problems.append(f"{name}: changed since its historical row was written; regenerate it "
                                "with a command that writes provenance, or say in its row how it was made")
                continue
        rows.append(dict(row, sha256=file_sha256(path)))
    if problems:
        raise SystemExit("cannot index docs/_output:\n  " + "\n  ".join(problems))
    return rows


def _cell(value):
    return "" if value is None else str(value).replace("|", "\\|").replace("\n", " ")


def render_index(rows):
    """INDEX.md: a markdown table of the rows (index.json is the source)."""
    lines = [
        "# What made each file in docs/_output",
        "",
        "Generated by `python benchmarks/regenerate_outputs.py` from `index.json`; do not edit by hand.",
        "`tests/test_experiments_provenance.py` checks that every file is listed with its sha256, and that the code",
        "fingerprint and config hash of each current row are what the code computes today (rerun the",
        "row's command when they are not). \"earlier code\" rows were made by the code at their commit",
        "(the test checks the fingerprint against it) and not rerun since; their note says why they stand.",
        "Historical rows were made before provenance existed: their",
        "command and commit come from the commit history and the docs, their code fingerprint is unknown.",
        "matmul GFLOP/s: the machine's one-thread float32 2048^3 product (`experiments.matmul_gflops`),",
        "the reference for any time measured with the file.",
        "",
        "| " + " | ".join(COLUMNS) + " | note |",
        "|" + "---|" * (len(COLUMNS) + 1),
    ]
    for row in rows:
        lines.append("| " + " | ".join(_cell(row.get(c)) for c in COLUMNS) + f" | {_cell(row.get('note'))} |")
    return "\n".join(lines) + "\n"


def write_index(rows, folder=OUTPUT):
    with open(os.path.join(folder, INDEX_JSON), "w") as f:
        json.dump(rows, f, indent=1)
        f.write("\n")
    with open(os.path.join(folder, INDEX_MD), "w") as f:
        f.write(render_index(rows))


def regenerate_quick():
    with tempfile.TemporaryDirectory() as tmp:
        out = os.path.join(tmp, "out")
        rc = cli([*QUICK, "--out", out, "--quiet", "--readme", os.path.join(ROOT, "README.md")])
        if rc != 0:
            raise SystemExit(f"reproduce --quick failed with exit status {rc}")
        shutil.copyfile(os.path.join(out, "table.txt"), os.path.join(OUTPUT, "reproduce_quick.txt"))


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--quick", action="store_true",
                    help="rerun reproduce --quick --n-jobs 2 (README block, docs/_output/reproduce_quick.txt)")
    ap.add_argument("--earlier-code", nargs=2, action="append", default=[], metavar=("FILE", "NOTE"),
                    help="keep FILE (made by other code than today's) with NOTE saying why its result stands")
    ap.add_argument("--python", nargs=2, action="append", default=[], metavar=("FILE", "X.Y"),
                    help="the Python version that made FILE, where its provenance line does not say it")
    args = ap.parse_args(argv)
    if args.quick:
        regenerate_quick()
    rows = build_index(earlier_code=dict(args.earlier_code), python=dict(args.python))
    write_index(rows)
    print(f"indexed {len(rows)} files in {os.path.relpath(OUTPUT, ROOT)} "
          f"({sum(r['status'] == 'current' for r in rows)} current, "
          f"{sum(r['status'] == 'earlier code' for r in rows)} made by earlier code)")
    return 0


if __name__ == "__main__":
    sys.exit(main())
