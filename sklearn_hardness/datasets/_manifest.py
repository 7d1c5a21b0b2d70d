"""Loading real press recordings listed in a CSV manifest."""

from __future__ import annotations

import csv
import os
import warnings
from numbers import Integral
from pathlib import Path

import numpy as np
from sklearn.utils import Bunch

from ..io import read_video
from ..utils._lazy import LazyVideoSequence
from ..utils._param_validation import Interval, validate_params
from ..utils._warnings import external_stacklevel

__all__ = ["load_press_videos"]

_REQUIRED = ("path", "label")
_KNOWN = _REQUIRED + ("hardness", "hardness_unit", "object_id", "force_path", "timestamps_path", "position_path",
                      "fps")


def _read_series(path):
    """Read one per-frame series (.npy, or one number per line / comma separated)."""
    if path.suffix.lower() == ".npy":
        arr = np.load(path, allow_pickle=False)
    else:
        try:
            arr = np.loadtxt(path, delimiter="," if path.suffix.lower() == ".csv" else None, ndmin=1)
        except ValueError as exc:
            raise ValueError(f"Could not parse numbers in '{path}': {exc}") from None
    arr = np.asarray(arr, dtype=float)
    if arr.ndim > 1 and sum(n > 1 for n in arr.shape) > 1:  # a table, not one column or one row
        raise ValueError(
            f"'{path}' holds a table of shape {arr.shape}; a per-frame series is one number per frame (one "
            "column or one row): save that column alone (a (time, value) export's time goes to "
            "timestamps_path; of a multi-axis force, the component normal to the gel)."
        )
    arr = arr.ravel()
    if not np.isfinite(arr).all():
        raise ValueError(f"'{path}' contains NaN or infinite values.")
    return arr


def _sort_labels(labels):
    try:
        return sorted(labels, key=float)
    except ValueError:
        return sorted(labels)


def _warn_labels_alike(target_names, manifest):
    """Warn where labels differ only in case (``Soft`` and ``soft``): each is a class of its own."""
    spellings = {}
    for name in target_names:
        spellings.setdefault(name.casefold(), []).append(name)
    alike = [names for names in spellings.values() if len(names) > 1]
    if alike:
        warnings.warn(
            f"Manifest '{manifest}': labels {', '.join(' and '.join(map(repr, names)) for names in alike)} "
            "differ only in case, so each is a class of its own; if they are one class, write its label "
            "one way on every row.",
            UserWarning,
            stacklevel=external_stacklevel(),
        )


def _float_or_raise(value, column, row_number, manifest):
    try:
        out = float(value)
    except ValueError:
        raise ValueError(
            f"{manifest}: line {row_number}: column '{column}' must be a number, got {value!r}."
        ) from None
    if not np.isfinite(out):
        raise ValueError(f"{manifest}: line {row_number}: column '{column}' is not finite ({value!r}).")
    return out


def _positive_or_raise(value, column, row_number, manifest):
    out = _float_or_raise(value, column, row_number, manifest)
    if out <= 0:
        raise ValueError(f"{manifest}: line {row_number}: column '{column}' must be positive, got {value!r}.")
    return out


def _object_ids(rows, lines, manifest):
    """The object of every row: its ``object_id``, or its label where the manifest names no object.

    An ``object_id`` names one physical object, so all its presses have one
    label; where some rows give an id, every row must (a blank id would put
    the presses of unknown objects together as one object per label).
    """
    ids = [row.get("object_id", "") for row in rows]
    if not any(ids):
        return np.array([row["label"] for row in rows])
    blank = [n for n, i in zip(lines, ids) if not i]
    if blank:
        shown = ", ".join(map(str, blank[:5])) + (f" and {len(blank) - 5} more" if len(blank) > 5 else "")
        raise ValueError(
            f"{manifest}: 'object_id' is empty on line(s) {shown} while other rows give it; give the "
            "object of every press or of none (without object ids, every label counts as one object)."
        )
    labels = {}  # object_id -> {label: first line}
    for n, i, row in zip(lines, ids, rows):
        labels.setdefault(i, {}).setdefault(row["label"], n)
    shared = [(i, seen) for i, seen in labels.items() if len(seen) > 1]
    if shared:
        i, seen = shared[0]
        where = ", ".join(f"{label!r} (line {n})" for label, n in seen.items())
        more = f" (and {len(shared) - 1} other object_id(s) likewise)" if len(shared) > 1 else ""
        raise ValueError(
            f"{manifest}: object_id {i!r} has presses labelled {where}{more}; an object_id names one "
            "physical object, which has one label. Where objects are numbered within each label, make "
            f"the ids unique across labels (e.g. '{next(iter(seen))}-{i}')."
        )
    return np.array(ids)


@validate_params(
    {
        "manifest": [str, os.PathLike],
        "cache_size": [Interval(Integral, 0, None, closed="left")],
    },
    prefer_skip_nested_validation=True,
)
def load_press_videos(manifest, *, cache_size=0):
    """Load press recordings listed in a CSV manifest.

    Videos are not read here: ``videos`` is a lazy sequence that decodes a
    video when it is indexed, so datasets larger than memory can be used
    with :func:`~sklearn.model_selection.train_test_split` and pipelines.
    Every file the manifest names is checked up front; all missing files are
    listed in one error.

    Parameters
    ----------
    manifest : str or path-like
        A CSV file with a header row. Required columns:

        ``path``
            The video (any format :func:`sklearn_hardness.io.read_video`
            reads), relative to the manifest's folder or absolute.
        ``label``
            The reference object's class label (any string; numbers sort
            numerically).

        Optional columns: ``hardness`` (the class's hardness value, equal
        for all rows of a label), ``hardness_unit`` (e.g. ``mm/N`` or
        ``Shore 00``), ``object_id`` (which physical object was pressed: one
        label per object; given on every row or on none),
        ``force_path``, ``timestamps_path`` and ``position_path`` (per-frame
        force in N, time in s and the sensor's position in mm, growing as it
        moves into the object: a robot's encoders, a gripper's closing; as
        ``.npy`` or text files with one number per line; force and position
        are the input of
        :class:`~sklearn_hardness.features.LoadingCompliance`), ``fps``.
        Other columns are returned in ``metadata``. Empty cells
        mean "not known".
    cache_size : int, default=0
        How many decoded videos to keep in memory (least recently used).

    Returns
    -------
    data : :class:`~sklearn.utils.Bunch`
        ``videos``
            Lazy sequence (``len``, integer and array indexing; videos are
            read when indexed) of ``(T, H, W, 3)`` ``uint8`` arrays.
        ``target``
            ndarray of int, the class index of each video.
        ``target_names``
            ndarray of str, the labels in class-index order.
        ``hardness``
            ndarray of float per class, or None if the manifest has none.
        ``hardness_unit``
            str or None.
        ``force``, ``timestamps``, ``position``
            list with a float array per video (None for a video without
            one), or None where the manifest has no such column.
        ``object_id``
            ndarray of str per video: which physical object it presses
            (its label on every row where the manifest names no object).
        ``fps``
            ndarray of float per video (NaN where not given).
        ``paths``
            list of resolved video paths.
        ``metadata``
            dict of any extra columns.
        ``manifest``
            the manifest's path.

    Raises
    ------
    FileNotFoundError
        If the manifest or any file it names is missing (all are listed).
    ValueError
        If required columns are missing, the manifest has no rows, a cell
        is malformed, or a label has conflicting hardness values.

    Warns
    -----
    UserWarning
        If labels differ only in case (``Soft`` and ``soft``): each is a
        class of its own.

    Examples
    --------
    >>> import os, tempfile
    >>> import numpy as np
    >>> from sklearn_hardness.io import write_video
    >>> from sklearn_hardness.datasets import load_press_videos
    >>> root = tempfile.mkdtemp()
    >>> write_video(os.path.join(root, "a.avi"), np.zeros((4, 16, 16, 3), np.uint8))
    >>> with open(os.path.join(root, "manifest.csv"), "w") as f:
    ...     _ = f.write("path,label,hardness\\na.avi,soft,1.13\\n")
    >>> data = load_press_videos(os.path.join(root, "manifest.csv"))
    >>> data.target_names.tolist(), data.videos[0].shape
    (['soft'], (4, 16, 16, 3))
    """
    manifest = Path(os.fspath(manifest))
    if not manifest.is_file():
        raise FileNotFoundError(f"Manifest not found: '{manifest}'.")
    root = manifest.parent
    try:
        with open(manifest, newline="", encoding="utf-8-sig") as f:
            reader = csv.DictReader(f)
            columns = [c.strip() for c in (reader.fieldnames or [])]
            # each row with the file's line it ends on, so that errors name that line
            read = []
            for row in reader:
                extra = [v for v in row.get(None, []) if v.strip()]  # cells beyond the header's columns
                if extra:
                    raise ValueError(
                        f"{manifest}: line {reader.line_num} has more cells than the header's {len(columns)} "
                        f"columns ({extra} left over): quote a cell that holds a comma, or name the column "
                        "in the header."
                    )
                read.append(({k.strip(): (v or "").strip() for k, v in row.items() if k is not None},
                             reader.line_num))
    except UnicodeDecodeError as exc:
        raise ValueError(
            f"Manifest '{manifest}' is not UTF-8 text (byte {exc.start}: {exc.reason}); save it as "
            "\"CSV UTF-8\" (a spreadsheet's export), or convert it, e.g. `iconv -f cp1252 -t utf-8`."
        ) from None
    missing_cols = [c for c in _REQUIRED if c not in columns]
    if missing_cols:
        raise ValueError(
            f"Manifest '{manifest}' lacks required column(s) {missing_cols}; found {columns}."
        )
    lines = [n for r, n in read if any(r.values())]  # rows of empty cells (",,") are no presses
    rows = [r for r, _ in read if any(r.values())]
    if not rows:
        raise ValueError(f"Manifest '{manifest}' lists no videos.")

    def resolve(cell):
        p = Path(cell).expanduser()
        return p if p.is_absolute() else root / p

    paths, missing = [], []
    for i, row in zip(lines, rows):
        if not row["path"]:
            raise ValueError(f"{manifest}: line {i}: empty 'path'.")
        if not row["label"]:
            raise ValueError(f"{manifest}: line {i}: empty 'label'.")
        p = resolve(row["path"])
        paths.append(p)
        for col in ("path", "force_path", "timestamps_path", "position_path"):
            if row.get(col) and not resolve(row[col]).exists():
                missing.append(str(resolve(row[col])))
    if missing:
        raise FileNotFoundError(
            f"Manifest '{manifest}' names {len(missing)} missing file(s):\n  " + "\n  ".join(missing)
        )

    labels = [row["label"] for row in rows]
    target_names = _sort_labels(set(labels))
    _warn_labels_alike(target_names, manifest)
    index = {name: i for i, name in enumerate(target_names)}
    target = np.array([index[label] for label in labels], dtype=int)

    hardness = None
    if "hardness" in columns and any(row["hardness"] for row in rows):
        per_class = {}
        for i, row in zip(lines, rows):
            if not row["hardness"]:
                raise ValueError(
                    f"{manifest}: line {i}: 'hardness' is empty while other rows give it; give the "
                    "hardness of every row or of none."
                )
            value = _float_or_raise(row["hardness"], "hardness", i, manifest)
            prev = per_class.setdefault(row["label"], value)
            if not np.isclose(prev, value):
                raise ValueError(
                    f"{manifest}: line {i}: label {row['label']!r} has hardness {value} here but "
                    f"{prev} in an earlier row; a class has one hardness value."
                )
        hardness = np.array([per_class[name] for name in target_names], dtype=float)
    units = {row.get("hardness_unit", "") for row in rows} - {""}
    if len(units) > 1:
        raise ValueError(f"Manifest '{manifest}' mixes hardness units {sorted(units)}.")
    hardness_unit = units.pop() if units else None

    def series(col):
        if col not in columns or not any(row[col] for row in rows):
            return None
        return [_read_series(resolve(row[col])) if row[col] else None for row in rows]

    fps = np.array(
        [
            _positive_or_raise(row["fps"], "fps", i, manifest) if row.get("fps") else np.nan
            for i, row in zip(lines, rows)
        ]
    )
    object_id = _object_ids(rows, lines, manifest)
    extra = [c for c in columns if c not in _KNOWN]
    return Bunch(
        videos=LazyVideoSequence(read_video, paths, cache_size=cache_size),
        target=target,
        target_names=np.array(target_names),
        hardness=hardness,
        hardness_unit=hardness_unit,
        force=series("force_path"),
        timestamps=series("timestamps_path"),
        position=series("position_path"),
        object_id=object_id,
        fps=fps,
        paths=paths,
        metadata={c: [row[c] for row in rows] for c in extra},
        manifest=manifest,
        DESCR=f"Press videos listed in {manifest} ({len(rows)} videos, {len(target_names)} classes).",
    )
