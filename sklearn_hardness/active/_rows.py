"""The active learner's reservoir: rows of any container (arrays, tensors, sparse, videos) appended and subsampled."""

from __future__ import annotations

import numpy as np
import scipy.sparse as sp
import torch
from sklearn.utils import _safe_indexing

from ..datasets import LazyVideoSequence

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


def training_subset(X, y, max_size, rng):
    """The reservoir, or ``max_size`` of its rows drawn without replacement when it holds more.

    Parameters
    ----------
    X : rows of any container :func:`concat_rows` builds
    y : ndarray of shape (n,)
    max_size : int or None
        None: no cap.
    rng : numpy.random.RandomState

    Returns
    -------
    X_train, y_train
    """
    size = y.shape[0]
    if max_size is None or size <= max_size:
        return X, y
    subset = rng.choice(size, max_size, replace=False)
    return _safe_indexing(X, subset), y[subset]
