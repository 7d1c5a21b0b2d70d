"""Run independent tasks through joblib, appending each result as it ends."""

from __future__ import annotations

import os
import socket
import sys
import time

import joblib
import torch
from joblib import Parallel, delayed

__all__ = ["run_tasks", "ProgressLog"]


def _call(func, n_threads, common, task):
    old = torch.get_num_threads()
    if n_threads is not None:
        torch.set_num_threads(n_threads)
    started = time.time()
    try:
        out = func(**common, **task)
    finally:
        if n_threads is not None:
            torch.set_num_threads(old)
    # a task either yields one record ("key") or one per key of a group ("keys")
    records = [out] if "key" in task else list(out)
    keys = [task["key"]] if "key" in task else task["keys"]
    if len(records) != len(keys):
        raise RuntimeError(f"a task returned {len(records)} records for {len(keys)} keys.")
    wall = (time.time() - started) / len(records)
    for record, key in zip(records, keys):
        record["key"] = key
        record["wall_time"] = wall
        record["finished_at"] = time.time()
        record["pid"] = os.getpid()
        record["host"] = socket.gethostname()
    return records


def _worker_threads(n_jobs):
    """1 torch thread per worker when runs go in parallel; untouched otherwise."""
    try:
        effective = joblib.effective_n_jobs(n_jobs)
    except Exception:  # pragma: no cover - odd backends
        effective = 2
    backend = joblib.parallel.get_active_backend()[0]
    sequential = type(backend).__name__ == "SequentialBackend"
    return None if (effective == 1 or sequential) else 1


def _fmt_seconds(s):
    s = int(round(s))
    return f"{s // 3600}h{s % 3600 // 60:02d}m{s % 60:02d}s" if s >= 3600 else (
        f"{s // 60}m{s % 60:02d}s" if s >= 60 else f"{s}s")


class ProgressLog:
    """One line per finished run: done/total, elapsed time and an estimate of the rest.

    Unlike a progress bar it also reports when the output is a file or a
    pipe (a batch job's log); ``verbose=0`` silences it. The estimate is the
    mean time per run finished in this call times the runs left, unless the
    caller, who may know the runs differ, passes its own to :meth:`update`.

    Parameters
    ----------
    total : int
        Runs in all (those already in the results file included).
    done : int, default=0
        Runs already finished before this call (resumed).
    desc : str, default="runs"
    verbose : int, default=1
    stream : file-like or None, default=None
        Where to write (``sys.stderr`` if None).
    unit : str, default="runs"
        What is counted, as printed.
    """

    def __init__(self, total, done=0, desc="runs", verbose=1, stream=None, unit="runs"):
        self.total, self.done, self.desc, self.verbose = int(total), int(done), desc, verbose
        self.stream, self.unit = stream, unit
        self._start = time.perf_counter()
        self._new = 0

    def update(self, n=1, seconds_left=None, note=None):
        """Count ``n`` finished runs and print a line.

        ``seconds_left``, where given, is printed as the estimate instead of
        the mean time per run times the runs left; ``note``, where given,
        follows the estimate after a comma.
        """
        self.done += n
        self._new += n
        if not self.verbose:
            return
        elapsed = time.perf_counter() - self._start
        left = self.total - self.done
        if seconds_left is not None:
            eta = seconds_left
        else:
            eta = elapsed / self._new * left if self._new else float("nan")
        self.write(f"{self.done}/{self.total} {self.unit}, {_fmt_seconds(elapsed)} elapsed, "
                   f"about {_fmt_seconds(eta)} left" + (f", {note}" if note else ""))

    def write(self, message):
        """Print ``"desc: message"`` (unless ``verbose=0``)."""
        if self.verbose:
            stream = sys.stderr if self.stream is None else self.stream
            print(f"{self.desc}: {message}", file=stream, flush=True)


def run_tasks(func, tasks, common, store, *, n_jobs=None, verbose=1, desc="runs", group_field=None):
    """Run ``func(**common, **task)`` for every task whose key is not in ``store``.

    A task has a ``"key"`` (``func`` returns one record) or, to share work
    between runs, a list ``"keys"`` and an equally long list
    ``task[group_field]`` (``func`` returns one record per key, in order);
    keys already stored are dropped from the group before it runs.
    Results are appended to ``store`` (durably, if it has a file) in the
    parent process as each task ends, in completion order; a rerun skips the
    keys already stored. Runs go through :class:`joblib.Parallel`, so
    ``joblib.parallel_config(backend="dask")`` moves them to a Dask cluster.
    A line per finished run goes to stderr (:class:`ProgressLog`) unless
    ``verbose=0``.
    """
    with store.writing():
        todo, total, n_todo = [], 0, 0
        for t in tasks:
            if "key" in t:
                total += 1
                if t["key"] not in store:
                    todo.append(t)
                    n_todo += 1
                continue
            keep = [i for i, k in enumerate(t["keys"]) if k not in store]
            total += len(t["keys"])
            if keep:
                todo.append(dict(t, keys=[t["keys"][i] for i in keep],
                                 **{group_field: [t[group_field][i] for i in keep]}))
                n_todo += len(keep)
        n_threads = _worker_threads(n_jobs)
        calls = (delayed(_call)(func, n_threads, common, t) for t in todo)
        progress = ProgressLog(total, total - n_todo, desc=desc, verbose=verbose)
        if todo:
            for records in Parallel(n_jobs=n_jobs, return_as="generator_unordered")(calls):
                for record in records:
                    store.append(record)
                    progress.update(1)
    return store
