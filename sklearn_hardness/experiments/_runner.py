"""Run independent tasks through joblib, appending each result as it ends."""

from __future__ import annotations

import os
import socket
import time

import joblib
import torch
from joblib import Parallel, delayed

from ..utils._progress import ProgressLog

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
