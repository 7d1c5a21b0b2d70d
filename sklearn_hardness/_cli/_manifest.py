"""A manifest's file, and writing its rows: the command line's ``record`` and ``select``
(:func:`~sklearn_hardness.datasets.load_press_videos` reads manifests)."""

from __future__ import annotations

import csv
import os
from pathlib import Path

__all__ = ["MANIFEST_COLUMNS", "append_manifest_row", "complete_manifest_row", "manifest_file", "read_manifest_rows"]


def manifest_file(path):
    """``path``, or the ``manifest.csv`` in it where ``path`` is a folder (as ``record`` writes one)."""
    path = Path(os.fspath(path))
    return path / "manifest.csv" if path.is_dir() else path


# ---------------------------------------------------------------- writing (the CLI's record)
MANIFEST_COLUMNS = ["path", "label", "hardness", "hardness_unit", "object_id", "fps"]


def read_manifest_rows(manifest):
    """Columns and rows of an existing manifest (empty lists when there is none)."""
    if not manifest.exists() or manifest.stat().st_size == 0:
        return [], []
    with open(manifest, newline="", encoding="utf-8-sig") as f:
        reader = csv.DictReader(f)
        rows = [{k.strip(): (v or "").strip() for k, v in r.items() if k is not None} for r in reader]
        return [c.strip() for c in reader.fieldnames or []], rows


def complete_manifest_row(manifest, row):
    """``row`` completed and checked against the manifest, before anything is recorded.

    The hardness of a label is the same on all its rows, and given on all rows or on
    none (as load_press_videos requires): an omitted value is taken from the label's
    earlier rows; a conflicting or missing one is an error. An object_id already
    recorded with another label is an error too (an object has one label).
    """
    columns, rows = read_manifest_rows(manifest)
    same = [r for r in rows if r.get("label") == row["label"]]
    for key in ("hardness", "hardness_unit"):
        known = {r.get(key, "") for r in same} - {""}
        if not row[key] and known:
            row[key] = known.pop()
        elif row[key] and known and known != {row[key]}:
            raise ValueError(f"{manifest}: label '{row['label']}' has {key} {sorted(known)}, not '{row[key]}'.")
    if rows and not row["hardness"] and any(r.get("hardness") for r in rows):
        raise ValueError(f"{manifest} gives the hardness of its other labels: pass --hardness for "
                         f"'{row['label']}' too.")
    if rows and row["hardness"] and any(not r.get("hardness") for r in rows):
        raise ValueError(f"{manifest} has rows without hardness: record without --hardness, or add it there.")
    other = sorted({r.get("label", "") for r in rows if r.get("object_id") == row.get("object_id")} - {row["label"]})
    if row.get("object_id") and other:
        raise ValueError(f"{manifest}: object_id '{row['object_id']}' is recorded with label {other[0]!r}, not "
                         f"'{row['label']}'; an object has one label: pass another --object-id "
                         f"(e.g. '{row['label']}-{row['object_id']}').")
    missing = [k for k, v in row.items() if v and columns and k not in columns]
    if missing:
        raise ValueError(f"{manifest} has no column(s) {missing} for this recording; "
                         f"its columns are {columns}. Add them or record into another folder.")
    return columns or MANIFEST_COLUMNS, row


def append_manifest_row(manifest, columns, row):
    """Append ``row`` to ``manifest``, writing the header first when the file is new."""
    new = not manifest.exists() or manifest.stat().st_size == 0
    if not new:
        with open(manifest, "rb") as f:
            f.seek(-1, 2)
            new_line = f.read(1) not in (b"\n", b"\r")
    with open(manifest, "a", newline="", encoding="utf-8") as f:
        writer = csv.DictWriter(f, columns, restval="", extrasaction="ignore")
        if new:
            writer.writeheader()
        elif new_line:
            f.write("\n")
        writer.writerow(row)
