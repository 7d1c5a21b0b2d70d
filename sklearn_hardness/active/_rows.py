"""The active learner's reservoir: rows of any container (arrays, tensors, sparse, videos) appended and subsampled."""

from __future__ import annotations

import numpy as np
import scipy.sparse as sp
import torch
from sklearn.utils import _safe_indexing

from ..utils._lazy import LazyVideoSequence

__all__ = ["concat_rows", "n_rows", "training_subset"]


def concat_rows(a, b):
    """Concatenate two row collections of the same kind (arrays, tensors, lists)."""
    if isinstance(a, np.ndarray) and isinstance(b, np.ndarray):
        if a.shape[1:] != b.shape[1:]:
            raise ValueError(
                f"new samples have shape {b.shape[1:]} per sample, the reservoir "
                f"holds {a.shape[1:]}."
            )
        return np.concatenate([a, b], axis=0)
    if hasattr(a, "detach") and hasattr(b, "detach"):  # torch tensors
        return torch.cat([a, b], dim=0)
    if sp.issparse(a) or sp.issparse(b):
        return sp.vstack([a, b], format="csr")
    if (
        isinstance(a, LazyVideoSequence)
        and isinstance(b, LazyVideoSequence)
        and a.loader is b.loader
    ):  # stay lazy: only the keys are concatenated
        return a.concatenate(b)
    # other sequences of videos: a list of the (loaded) items
    return [a[i] for i in range(len(a))] + [b[i] for i in range(len(b))]


def n_rows(X):
    """Number of rows (samples) of an array, tensor, sparse matrix or sequence."""
    if hasattr(X, "shape") and getattr(X, "ndim", 1) >= 1:
        return X.shape[0]
    return len(X)


def training_subset(X, y, max_size, rng, *, keep_classes=True):
    """The reservoir, or ``max_size`` of its rows drawn without replacement when it holds more.

    The rows are drawn uniformly. With ``keep_classes``, if the draw leaves
    out a class that the reservoir holds (an estimator refitted from scratch
    would then lose it from ``classes_``), then, with the same ``rng`` after the draw, each
    missing class (in sorted order) gets one of its reservoir rows drawn
    uniformly, which replaces a drawn row (drawn uniformly among them) of
    the class most represented in the subset (the smallest label on ties).
    A class is only displaced while it has more than one row in the subset,
    so when ``max_size`` is smaller than the number of classes some stay
    missing. A draw that covers every class is returned unchanged and
    consumes no further random numbers.

    Parameters
    ----------
    X : rows of any container :func:`concat_rows` builds
    y : ndarray of shape (n,)
    max_size : int or None
        None: no cap.
    rng : numpy.random.RandomState
    keep_classes : bool, default=True
        Repair a draw that left out a class. False for estimators that are
        told every class when they train (skorch nets, ``partial_fit(...,
        classes=...)``): their draws stay the plain uniform ones.

    Returns
    -------
    X_train, y_train
    """
    size = y.shape[0]
    if max_size is None or size <= max_size:
        return X, y
    subset = rng.choice(size, max_size, replace=False)
    classes, y_codes = np.unique(y, return_inverse=True)
    y_codes = y_codes.reshape(-1)
    counts = np.bincount(y_codes[subset], minlength=classes.shape[0])
    missing = np.flatnonzero(counts == 0)
    if keep_classes and missing.size:  # only then: repair the draw, leaving the others untouched
        subset = subset.copy()
        for c in missing:
            most = int(np.argmax(counts))  # first (smallest label) on ties
            if counts[most] <= 1:
                break  # every class left has a single row: max_size < n_classes
            rows_c = np.flatnonzero(y_codes == c)
            new_row = rows_c[rng.randint(rows_c.shape[0])]
            slots = np.flatnonzero(y_codes[subset] == most)
            subset[slots[rng.randint(slots.shape[0])]] = new_row
            counts[most] -= 1
            counts[c] += 1
    return _safe_indexing(X, subset), y[subset]
