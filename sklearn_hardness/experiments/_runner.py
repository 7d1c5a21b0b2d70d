"""Run independent tasks through joblib, appending each result as it ends."""

from __future__ import annotations

import os
import socket
import time

import joblib
from joblib import Parallel, delayed

__all__ = ["run_tasks"]


def _call(func, n_threads, common, task):
    import torch

    old = torch.get_num_threads()
    if n_threads is not None:
        torch.set_num_threads(n_threads)
    started = time.time()
    try:
        record = func(**common, **task)
    finally:
        if n_threads is not None:
            torch.set_num_threads(old)
    record["key"] = task["key"]
    record["wall_time"] = time.time() - started
    record["finished_at"] = time.time()
    record["pid"] = os.getpid()
    record["host"] = socket.gethostname()
    return record


def _worker_threads(n_jobs):
    """1 torch thread per worker when runs go in parallel; untouched otherwise."""
    try:
        effective = joblib.effective_n_jobs(n_jobs)
    except Exception:  # pragma: no cover - odd backends
        effective = 2
    backend = joblib.parallel.get_active_backend()[0]
    sequential = type(backend).__name__ == "SequentialBackend"
    return None if (effective == 1 or sequential) else 1


def run_tasks(func, tasks, common, store, *, n_jobs=None, verbose=1, desc="runs"):
    """Run ``func(**common, **task)`` for every task whose key is not in ``store``.

    Results are appended to ``store`` (durably, if it has a file) in the
    parent process as each run ends, in completion order; a rerun skips the
    keys already stored. Runs go through :class:`joblib.Parallel`, so
    ``joblib.parallel_config(backend="dask")`` moves them to a Dask cluster.
    """
    from tqdm.auto import tqdm

    with store.writing():
        todo = [t for t in tasks if t["key"] not in store]
        n_threads = _worker_threads(n_jobs)
        calls = (delayed(_call)(func, n_threads, common, t) for t in todo)
        with tqdm(total=len(tasks), initial=len(tasks) - len(todo), desc=desc, unit="run",
                  disable=True if not verbose else None) as bar:
            if todo:
                for record in Parallel(n_jobs=n_jobs, return_as="generator_unordered")(calls):
                    store.append(record)
                    bar.update(1)
    return store
