"""The pre-contact frames and the moments of a press's loading phase, shared by the feature transformers.

:class:`~sklearn_hardness.features.ContactGeometryFeatures` and
:class:`~sklearn_hardness.features.ImprintTextureFeatures` read the contact
at the same moments: the first frames at which the press's mean change
reaches given fractions of its rise from the pre-contact level to its peak.
"""

from __future__ import annotations

from typing import NamedTuple

import numpy as np

from ..utils._frames import smooth_curve
from ._contact_profile import _n_precontact

_EPS = 1e-6


class LoadingMoments(NamedTuple):
    """Where a press's loading phase is: ``n_pre`` reference frames, the peak and the moments' frames."""

    n_pre: int  # frames 0 .. n_pre - 1 precede the contact; their mean is the reference
    i_peak: int
    frames: list  # one frame index per fraction of the rise, in the fractions' order


def _norm(d):
    """Euclidean norm over the last (channel) axis, summed channel by channel (faster than a short-axis reduction)."""
    out = d[..., 0] * d[..., 0]
    for ch in range(1, d.shape[-1]):
        out += d[..., ch] * d[..., ch]
    return np.sqrt(out)


def _frame_medians(d):
    """Median change of each frame and channel, shape (T, 1, 1, C), on every 4th pixel (plenty for an offset)."""
    t, c = d.shape[0], d.shape[-1]
    flat = d.reshape(t, -1, c)
    sub = flat[:, ::4] if flat.shape[1] >= 400 else flat
    return np.median(sub, axis=1)[:, None, None, :]


def loading_moments(small, fractions):
    """The pre-contact frames, the peak and the frames at ``fractions`` of the rise of a press.

    Parameters
    ----------
    small : ndarray of shape (T, h, w, C)
        The press's frames, float (block-averaged: the mean change is all
        that is read).
    fractions : sequence of float in (0, 1]
        Fractions of the rise of the mean change (after a running median
        over five frames) from its pre-contact level to its peak; 1 is the
        peak.

    Returns
    -------
    moments : LoadingMoments or None
        None for videos of fewer than three frames or without any change.
    """
    t = small.shape[0]
    # change to the first frame, less each frame's median (uniform illumination drift)
    d0 = small - small[0]
    d0 -= _frame_medians(d0)
    curve = _norm(d0).reshape(t, -1).mean(axis=1, dtype=np.float64)
    if t < 3 or curve.max() <= 0:
        return None
    smooth = smooth_curve(curve)
    i_peak = int(np.argmax(smooth))
    n_pre = _n_precontact(smooth, i_peak)
    level = float(np.median(smooth[1:n_pre])) if n_pre > 1 else 0.0
    span = max(float(smooth[i_peak]) - level, _EPS)
    frames = []
    for q in fractions:
        hit = np.flatnonzero(smooth[: i_peak + 1] - level >= q * span)
        frames.append(i_peak if q >= 1.0 or not hit.size else int(hit[0]))
    return LoadingMoments(n_pre, i_peak, frames)
