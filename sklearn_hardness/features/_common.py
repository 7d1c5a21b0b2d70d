"""Helpers shared by the feature transformers: per-sample intensity scaling (named output columns: utils)."""

from __future__ import annotations

import numpy as np

_GREY_WEIGHTS = np.array([0.299, 0.587, 0.114], dtype=np.float32)  # ITU-R BT.601, RGB order


def sample_range(X, value_range):
    """Low and high intensity of each sample, shape (n,) each.

    With ``value_range=None`` these are the minimum and maximum over all
    frames, pixels and channels of the sample; flat samples get ``high =
    low + 1`` so they map to a constant image instead of dividing by zero.
    """
    n = X.shape[0]
    if value_range is not None:
        lo, hi = float(value_range[0]), float(value_range[1])  # validated by the estimator's constraints
        return np.full(n, lo, np.float32), np.full(n, hi, np.float32)
    flat = X.reshape(n, -1)
    lo = flat.min(axis=1).astype(np.float32)
    hi = flat.max(axis=1).astype(np.float32)
    hi = np.where(hi - lo > 0, hi, lo + 1.0).astype(np.float32)
    return lo, hi


def to_grey(X):
    """(n, k, H, W, C) float -> new (n, k, H, W) float32 grey array (BT.601 weights for RGB)."""
    if X.shape[-1] == 1:
        return X[..., 0].astype(np.float32, copy=True)
    return np.tensordot(X, _GREY_WEIGHTS, axes=([-1], [0])).astype(np.float32, copy=False)


def to_uint8_grey(X, value_range):
    """(n, k, H, W, C) float -> (n, k, H, W) uint8 grey with one scaling per sample.

    Works one sample at a time, so the only large allocation is the uint8
    output (a quarter of one channel of the input).
    """
    fixed = value_range
    out = np.empty(X.shape[:4], dtype=np.uint8)
    for i in range(X.shape[0]):
        g = to_grey(X[i : i + 1])[0]  # a new array: scaled in place below
        lo, hi = sample_range(g[np.newaxis], fixed)
        g -= lo[0]
        g *= 255.0 / (hi[0] - lo[0])
        np.clip(np.rint(g, out=g), 0, 255, out=g)
        out[i] = g
    return out
