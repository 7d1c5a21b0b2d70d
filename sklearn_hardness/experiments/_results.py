"""A resumable, append-only results file (JSON Lines) and the result container.

Every finished run is one line: a JSON object with a ``"key"`` (what was run:
experiment, strategy or model, test class, seed, config hash) and its
metrics. A line is written with a single ``write`` of the whole line, then
flushed and ``fsync``-ed, so after a crash or ``kill -9`` the file holds every
run that finished, plus at most one torn last line (no final newline, or not
valid JSON). :class:`ResultsStore` detects that line, warns, and truncates it
before appending, so a rerun of the same command skips the finished keys and
computes only the missing ones.
"""

from __future__ import annotations

import contextlib
import json
import os
import warnings

import numpy as np

from ..utils._json import to_json
from ..utils._warnings import external_stacklevel

__all__ = ["ResultsStore", "ExperimentResult", "key_id"]


def key_id(key):
    """A string id of a run key (dict): ``"name=value|..."`` in sorted order."""
    return "|".join(f"{k}={key[k]}" for k in sorted(key))


class ResultsStore:
    """Append-only JSON Lines file of finished runs, safe against crashes.

    Parameters
    ----------
    path : str or path-like or None
        The file; created (with its folder) if missing. ``None`` keeps the
        records in memory only (nothing is resumed).

    Attributes
    ----------
    records : list of dict
        The runs read from the file plus those appended since.
    n_torn : int
        Torn lines found (and removed) when the file was opened.

    Notes
    -----
    Only one process may write a file at a time: while an experiment runs
    it holds an exclusive ``fcntl`` lock on ``path + ".lock"`` (POSIX), and a
    second process trying to write the same file gets a clear error instead
    of duplicating runs.
    """

    def __init__(self, path):
        self.path = None if path is None else os.fspath(path)
        self.records = []
        self.n_torn = 0
        self._ids = set()
        self._lock_file = None
        if self.path is not None:
            self._load()

    def _load(self):
        self.records, self._ids, self.n_torn = [], set(), 0
        self._needs_newline = False
        if not os.path.exists(self.path):
            return
        with open(self.path, "rb") as f:
            data = f.read()
        good_end = 0  # byte offset after the last complete, valid line
        pos = 0
        lines = data.split(b"\n")
        for i, raw in enumerate(lines):
            last = i == len(lines) - 1
            end = pos + len(raw) + (0 if last else 1)
            if raw.strip():
                try:
                    rec = json.loads(raw)
                except ValueError:
                    rec = None
                if isinstance(rec, dict) and "key" in rec and not isinstance(rec["key"], dict):
                    # complete JSON, so not a torn write: a line some other program wrote
                    raise ValueError(
                        f"{self.path}: line {i + 1} is a record whose 'key' is a "
                        f"{type(rec['key']).__name__}, not a dict of what was run; the file was not "
                        "written by this library alone. Fix or remove that line."
                    )
                if not isinstance(rec, dict) or "key" not in rec:
                    if last or all(not rest.strip() for rest in lines[i + 1 :]):
                        # the torn tail of an interrupted write
                        self.n_torn += 1
                        break
                    raise ValueError(
                        f"{self.path}: line {i + 1} is not a valid run record and is followed "
                        "by more lines; the file was not written by this library alone. Fix or "
                        "remove that line."
                    ) from None
                if last:  # valid JSON but no final newline: written completely, keep it
                    self._add(rec)
                    good_end = end
                    self._needs_newline = True
                    break
                self._add(rec)
            good_end = end
            pos = end
        if self.n_torn:
            warnings.warn(
                f"{self.path}: ignoring a torn last line (an interrupted write); "
                f"{len(self.records)} complete runs kept, the torn line is removed.",
                UserWarning,
                stacklevel=external_stacklevel(),
            )
            with open(self.path, "r+b") as f:
                f.truncate(good_end)
                f.flush()
                os.fsync(f.fileno())

    def _add(self, rec):
        kid = key_id(rec["key"])
        if kid in self._ids:
            warnings.warn(
                f"{self.path}: duplicate run {kid}; the first one is kept.", UserWarning,
                stacklevel=external_stacklevel(),
            )
            return
        self._ids.add(kid)
        self.records.append(rec)

    def __contains__(self, key):
        return key_id(key) in self._ids

    def __len__(self):
        return len(self.records)

    @contextlib.contextmanager
    def writing(self):
        """Hold the writer lock for the duration of an experiment."""
        if self.path is None:
            yield self
            return
        folder = os.path.dirname(os.path.abspath(self.path))
        os.makedirs(folder, exist_ok=True)
        try:
            import fcntl
        except ImportError:  # pragma: no cover - not POSIX
            yield self
            return
        lock = open(self.path + ".lock", "a")
        try:
            fcntl.flock(lock, fcntl.LOCK_EX | fcntl.LOCK_NB)
        except OSError:
            lock.close()
            raise RuntimeError(
                f"another process is writing {self.path} (lock {self.path}.lock is held); "
                "wait for it to finish or use another results path."
            ) from None
        try:
            self._load()  # what other processes wrote before we got the lock
            yield self
        finally:
            fcntl.flock(lock, fcntl.LOCK_UN)
            lock.close()

    def append(self, record):
        """Add a finished run; with a file, write it durably (one line, fsync)."""
        record = to_json(record)
        if record["key"] in self:
            raise ValueError(f"run {key_id(record['key'])} is already in the results.")
        if self.path is not None:
            line = json.dumps(record, separators=(",", ":"), allow_nan=False) + "\n"
            if getattr(self, "_needs_newline", False):
                line = "\n" + line
                self._needs_newline = False
            fd = os.open(self.path, os.O_WRONLY | os.O_APPEND | os.O_CREAT, 0o644)
            try:
                buf = line.encode()
                while buf:  # os.write may write less than asked
                    n = os.write(fd, buf)
                    buf = buf[n:]
                os.fsync(fd)
            finally:
                os.close(fd)
        self._ids.add(key_id(record["key"]))
        self.records.append(record)


class ExperimentResult:
    """Records of an experiment's runs, with helpers to aggregate them.

    Parameters
    ----------
    records : list of dict
        One dict per run (the lines of the results file).
    config : dict or None
        The configuration the runs were made with.
    path : str or None
        The results file, if any.

    Attributes
    ----------
    records : list of dict
        Tidy: one dict per run, per-iteration metrics as lists.
        ``pandas.DataFrame(result.records)`` gives a table.

    Examples
    --------
    >>> from sklearn_hardness.experiments import ExperimentResult
    >>> runs = [{"key": {"strategy": s, "seed": 0}, "accuracy": [0.4, a], "converged": True}
    ...         for s, a in [("variance", 0.8), ("random", 0.6)]]
    >>> res = ExperimentResult(runs)
    >>> res.groups("strategy"), res.curves("accuracy", strategy="variance").tolist()
    (['variance', 'random'], [[0.4, 0.8]])
    """

    def __init__(self, records, config=None, path=None):
        self.records = list(records)
        self.config = config
        self.path = path

    def __len__(self):
        return len(self.records)

    def __iter__(self):
        return iter(self.records)

    def __repr__(self):
        return f"ExperimentResult(n_runs={len(self.records)}, path={self.path!r})"

    def groups(self, field):
        """Distinct values of ``record["key"][field]`` in first-seen order."""
        out = []
        for r in self.records:
            v = r["key"].get(field)
            if v not in out:
                out.append(v)
        return out

    def select(self, converged_only=True, **key_values):
        """Records whose key matches ``key_values`` (and that converged)."""
        out = []
        for r in self.records:
            if converged_only and not r.get("converged", True):
                continue
            if all(r["key"].get(k) == v for k, v in key_values.items()):
                out.append(r)
        return out

    def curves(self, metric, converged_only=True, **key_values):
        """Stack a per-iteration metric: array (n_runs, n_iterations + 1).

        Runs that stopped early (not converged) are left out when
        ``converged_only``; otherwise their missing iterations are NaN.
        """
        rows = [r[metric] for r in self.select(converged_only, **key_values)]
        if not rows:
            return np.empty((0, 0))
        width = max(len(np.atleast_1d(r)) for r in rows)
        out = np.full((len(rows), width), np.nan)
        for i, r in enumerate(rows):
            r = np.atleast_1d(np.asarray(r, dtype=float))
            out[i, : len(r)] = r
        return out

    def converged_fraction(self, **key_values):
        """Fraction of runs (matching ``key_values``) that converged."""
        rows = self.select(False, **key_values)
        if not rows:
            return float("nan")
        return float(np.mean([bool(r.get("converged", True)) for r in rows]))

    def to_frame(self):
        """The records as a ``pandas.DataFrame`` (pandas is optional)."""
        try:
            import pandas as pd
        except ImportError as exc:  # pragma: no cover
            raise ImportError("to_frame() needs pandas: pip install pandas") from exc
        rows = []
        for r in self.records:
            row = dict(r["key"])
            row.update({k: v for k, v in r.items() if k != "key"})
            rows.append(row)
        return pd.DataFrame(rows)
