"""Per-press caching of the rows of a stateless feature step, through a :class:`joblib.Memory`.

A feature transformer whose ``fit`` learns nothing turns each press into its
row by that press alone, so a press's row depends only on the press and the
transformer's parameters. :func:`press_rows` computes the rows press by press
through a memory keyed by those two, so that any fold of any cross-validation
(or grid search, or later run) that meets a press again reads its row instead
of reading the video and extracting the features again. A press is keyed
without loading it where its sequence can name it (the ``cache_keys`` of a
lazy sequence: the loader and the key, e.g. the file), by a hash of its
frames otherwise.
"""

from __future__ import annotations

import functools
import os
from pathlib import Path

import joblib
import numpy as np
from joblib import Parallel, delayed

__all__ = ["as_memory", "press_rows", "press_tokens"]


def as_memory(memory):
    """``memory`` as a :class:`joblib.Memory`, or None where it caches nothing.

    Parameters
    ----------
    memory : None, str, path-like or object with a ``cache`` method
        A folder (made on first use) or a memory.

    Returns
    -------
    memory : joblib.Memory-like or None
        None for None and for a :class:`joblib.Memory` without a location.
    """
    if memory is None:
        return None
    if isinstance(memory, (str, os.PathLike)):
        return joblib.Memory(location=os.fspath(memory), verbose=0)
    if not callable(getattr(memory, "cache", None)):
        raise TypeError("memory must be None, a folder (str or path) or an object with a joblib.Memory "
                        f"interface (a `cache` method); got {type(memory).__name__}.")
    if isinstance(memory, joblib.Memory) and memory.location is None:
        return None
    return memory


@functools.lru_cache(maxsize=1)
def _code_fingerprint():
    """Hash of the package's source files: a change to the code that computes rows invalidates them."""
    root = Path(__file__).resolve().parent.parent
    return joblib.hash(sorted((str(p.relative_to(root)), p.read_bytes()) for p in root.rglob("*.py")))


def press_tokens(X):
    """One string per press of ``X`` that identifies its frames, as cheaply as it can.

    Parameters
    ----------
    X : sequence of videos
        A sequence with a ``cache_keys()`` method (the lazy sequences of
        :mod:`sklearn_hardness.datasets`: nothing is loaded) or any other
        sequence of videos (each video is hashed, frame bytes included).

    Returns
    -------
    tokens : list of str
    """
    keys = getattr(X, "cache_keys", None)
    if callable(keys):
        tokens = keys()
        if tokens is not None:
            return list(tokens)
    return [joblib.hash(np.asarray(X[i])) for i in range(len(X))]


def _cached_row(function, params, code, token, load, name):
    """``function(load(), name=name, **params)``: the cached call (``load`` and ``name`` are not in its key)."""
    return function(load(), name=name, **params)


def _load(X, i):
    return X[i]


def press_rows(function, X, params, *, memory=None, n_jobs=None):
    """``function(X[i], name=f"video {i}", **params)`` for every press, stacked, through ``memory`` per press.

    Parameters
    ----------
    function : callable
        A module-level function of one video (keyword ``name``: how errors
        call it) and ``params`` that returns its row; it must depend on the
        video and ``params`` alone.
    X : sequence of videos
    params : dict
        The keyword arguments of ``function`` that change the row (part of
        each press's key).
    memory : None, str, path-like or joblib.Memory, default=None
        Where rows are cached (:func:`as_memory`); None computes every row.
        Keys: ``function``, ``params``, the package's code and the press
        (:func:`press_tokens`); a hit loads no video.
    n_jobs : int or None, default=None
        Presses processed in parallel (joblib threads).

    Returns
    -------
    rows : ndarray of shape (n_presses, n_columns)
    """
    memory = as_memory(memory)
    if memory is None:
        rows = Parallel(n_jobs=n_jobs, prefer="threads")(
            delayed(function)(X[i], name=f"video {i}", **params) for i in range(len(X)))
        return np.vstack(rows)
    cached = memory.cache(_cached_row, ignore=["load", "name"], verbose=0)
    tokens, code = press_tokens(X), _code_fingerprint()
    rows = Parallel(n_jobs=n_jobs, prefer="threads")(
        delayed(cached)(function, params, code, token, functools.partial(_load, X, i), f"video {i}")
        for i, token in enumerate(tokens))
    return np.vstack(rows)
