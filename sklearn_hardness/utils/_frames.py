"""Frame intensities and curve smoothing shared by ``preprocessing`` and ``features``."""

from __future__ import annotations

import numpy as np
from scipy.ndimage import median_filter

__all__ = ["check_float_range", "as_float255", "smooth_curve"]

#: Frames in the running median of :func:`smooth_curve`.
_SMOOTH = 5


def check_float_range(video, name):
    """Raise if a float video has values outside [0, 1]; integer videos are not looked at.

    Called on the whole video before any striding or cropping, so a value
    out of range anywhere is found, not only in the pixels that are read.
    """
    if video.dtype.kind != "f" or video.size == 0:
        return
    vmin, vmax = float(video.min()), float(video.max())
    if vmin < 0.0 or vmax > 1.0:
        raise ValueError(
            f"{name} has float frames with values in [{vmin:g}, {vmax:g}]; float videos must be "
            "scaled to [0, 1] (or pass uint8 frames)."
        )


def as_float255(video, name):
    """Frames as float32 in 0..255 intensity units (uint8 as is, uint16 / 257, float in [0, 1] * 255)."""
    if video.dtype == np.uint8:
        return video.astype(np.float32)
    if video.dtype == np.uint16:
        return video.astype(np.float32) / 257.0
    check_float_range(video, name)
    return video.astype(np.float32) * 255.0


def smooth_curve(curve):
    """Running median over ``_SMOOTH`` frames of all but the first (reference) frame."""
    out = curve.copy()
    if len(curve) > 2:
        out[1:] = median_filter(curve[1:], size=min(_SMOOTH, len(curve) - 1), mode="nearest")
    return out
