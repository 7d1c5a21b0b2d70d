"""Lucas-Kanade tracking of one press's corners, and summaries of the tracks (OpenCV).

The algorithm behind :class:`~sklearn_hardness.features.OpticalFlowFeatures`,
apart from the transformer (its parameters, validation and output layout).
"""

from __future__ import annotations

import cv2
import numpy as np

#: Quantiles of the displacement magnitudes that ``output="magnitude_quantiles"`` keeps per frame.
MAGNITUDE_QUANTILES = (0.5, 0.75, 0.9, 0.99, 1.0)
#: Offset (pixels) inside the log of the magnitude summary: about the precision of Lucas-Kanade.
MAGNITUDE_FLOOR = 0.01


def track_one(grey, *, n_features, quality_level, min_distance, block_size, win_size, max_level, criteria):
    """Track the corners of one sample: grey (k, H, W) uint8 -> padded arrays."""
    k, H, W = grey.shape
    points = np.zeros((n_features, k, 2), dtype=np.float32)
    valid = np.zeros((n_features, k), dtype=bool)
    quality = np.zeros(n_features, dtype=np.float32)
    corners, q = cv2.goodFeaturesToTrackWithQuality(
        grey[0], n_features, quality_level, min_distance, None, blockSize=block_size
    )
    if corners is None or len(corners) == 0:
        return points, valid, quality, 0
    corners = corners.reshape(-1, 2).astype(np.float32)
    q = q.reshape(-1).astype(np.float32)
    # Stable order: strongest first, then by row (y), then by column (x).
    order = np.lexsort((corners[:, 0], corners[:, 1], -q))
    corners, q = corners[order], q[order]
    m = len(corners)
    points[:m, 0] = corners
    valid[:m, 0] = True
    quality[:m] = q
    alive = np.ones(m, dtype=bool)
    prev = corners
    for t in range(1, k):
        idx = np.flatnonzero(alive)
        if idx.size == 0:
            break
        nxt, status, _ = cv2.calcOpticalFlowPyrLK(
            grey[t - 1],
            grey[t],
            prev[idx].reshape(-1, 1, 2),
            None,
            winSize=win_size,
            maxLevel=max_level,
            criteria=criteria,
        )
        nxt = nxt.reshape(-1, 2)
        ok = (
            (status.reshape(-1) == 1)
            & np.isfinite(nxt).all(axis=1)
            & (nxt[:, 0] >= 0) & (nxt[:, 0] <= W - 1)
            & (nxt[:, 1] >= 0) & (nxt[:, 1] <= H - 1)
        )
        alive[idx[~ok]] = False
        good = idx[ok]
        prev = prev.copy()
        prev[good] = nxt[ok]
        points[good, t] = nxt[ok]
        valid[good, t] = True
    return points, valid, quality, m


def hold_last(disp, valid):
    """Carry the last valid displacement of each track forward over lost frames."""
    n, m, k, _ = disp.shape
    t_idx = np.arange(k)
    last = np.where(valid, t_idx, 0)
    last = np.maximum.accumulate(last, axis=2)
    return np.take_along_axis(disp, last[..., None].repeat(2, axis=-1), axis=2)


def magnitude_quantiles(steps, exists):
    """Per sample and frame, log(floor + quantiles and mean) of the corners' displacement magnitudes.

    ``steps`` (n, m, k-1, 2) displacements (zero for padding), ``exists`` (n, m)
    the corners found in the first frame. A sample without corners gives
    ``log(floor)`` everywhere (no motion seen).
    """
    n, _, k1, _ = steps.shape
    mag = np.linalg.norm(steps, axis=-1)  # (n, m, k-1)
    out = np.full((n, k1, len(MAGNITUDE_QUANTILES) + 1), np.log(MAGNITUDE_FLOOR), dtype=np.float64)
    for i in range(n):
        corners = mag[i, exists[i]]
        if corners.size:
            out[i, :, :-1] = np.log(MAGNITUDE_FLOOR + np.quantile(corners, MAGNITUDE_QUANTILES, axis=0).T)
            out[i, :, -1] = np.log(MAGNITUDE_FLOOR + corners.mean(axis=0))
    return out.reshape(n, -1).astype(np.float32)
