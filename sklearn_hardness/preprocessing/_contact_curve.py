"""Contact detection on one press video (paper Sec. II-A): the contact curve and where contact starts and peaks.

:func:`contact_curve` is the per-frame mean absolute change to the first
frame; :func:`_select_one` finds contact on it (a noise-relative threshold
on the mean curve for strong contacts, a localised, smoothed curve for weak
ones) and spreads the selected frames from contact start to peak.
:class:`~sklearn_hardness.preprocessing.ContactFrameSelector` applies it to
every video.
"""

from __future__ import annotations

import cv2
import numpy as np

from ..utils._frames import as_float255, check_float_range, smooth_curve
from ..utils._validation import check_video, roi_slices

__all__ = ["contact_curve"]

# Side length (pixels) the contact curve is computed at: frames are strided down
# to about this size, which keeps the curve's cost independent of resolution.
_CURVE_SIDE = 80
# Auto threshold: baseline + max(_NOISE_FACTOR * noise, _RELATIVE * (peak - baseline)).
_NOISE_FACTOR = 6.0
_RELATIVE = 0.05
# Strong contacts (markers, uncompressed sensors such as the simulator's) rise this many
# levels over the mean curve's quiet level; weaker ones (real marker-less presses, a few levels
# at peak, near the codec noise) go to the weak-contact test, whose smoothed, localised
# curve also places their start and peak better on a compressed plateau that steps at key frames.
_STRONG_CONTRAST = 2.0
# Weak contacts (compressed, marker-less streams) are tested on a localised curve: the mean
# of the most-changed _LOCAL_TOP of a grid of _LOCAL_CELLS x _LOCAL_CELLS cells, so a small
# sharp contact is not diluted by the pad, running-median smoothed (utils._frames.smooth_curve)
# (codec key-frame dips and one-frame glitches go), against its own _BASE_QUANTILE level
# (the quiet part of the video, robust to the codec's rise over the first frames; taken over
# the frames before the maximum where a long hold would put it on the plateau: _quiet_level).
_LOCAL_CELLS = 8
_LOCAL_TOP = 0.1
_BASE_QUANTILE = 0.2
# A weak contact must lift the localised curve to this multiple of its quiet level.
_MIN_RATIO = 1.4
# Weak contact starts where the smoothed localised curve passes this fraction of its rise
# and peaks where it first comes within _WEAK_PEAK_TOLERANCE of its rise from the top.
_WEAK_START = 0.25
_WEAK_PEAK_TOLERANCE = 0.2
# The peak (maximum deformation) is the first frame within this fraction of the
# contrast (or the noise) of the maximum: on a plateau, argmax would pick a noisy frame.
_PEAK_TOLERANCE = 0.02
# Ridge (intensity levels squared) pulling the fitted illumination gain towards 1.
_RIDGE = 4.0


def _contact_window(video, indices, rows, cols, fraction, name):
    """Row and column slices of a fixed-size window centred on the change of a press."""
    last = as_float255(video[indices[-1] : indices[-1] + 1, rows, cols], name)[0]
    first = as_float255(video[:1, rows, cols], name)[0]
    change = np.abs(last - first).mean(axis=-1)
    change = cv2.blur(change, (5, 5))
    weight = np.clip(change - np.median(change), 0.0, None)  # the unchanged pad weighs nothing
    h, w = change.shape
    wh, ww = max(2, int(round(fraction * h))), max(2, int(round(fraction * w)))
    total = float(weight.sum())
    if total > 0 and np.isfinite(total):
        cy = float((weight.sum(axis=1) * np.arange(h)).sum() / total)
        cx = float((weight.sum(axis=0) * np.arange(w)).sum() / total)
    else:
        cy, cx = (h - 1) / 2, (w - 1) / 2
    top = int(np.clip(round(cy - (wh - 1) / 2), 0, h - wh))
    left = int(np.clip(round(cx - (ww - 1) / 2), 0, w - ww))
    r0, c0 = rows.start or 0, cols.start or 0
    return slice(r0 + top, r0 + top + wh), slice(c0 + left, c0 + left + ww)


def _illumination_residual(small):
    """|frame - (gain * first + offset)| per pixel, the gain/offset fitted per frame and channel.

    ``small`` is (T, h, w, C) float32 in 0..255. A first, robust pass takes a
    gain of 1 and the median change as offset (exact for uniform brightness
    changes, and unaffected by contact covering less than half the frame);
    pixels whose residual is far out (the contact region) are then left out
    and gain and offset are refitted by least squares on the rest
    (ridge-regularised towards a gain of 1 so flat frames stay well posed),
    which also removes multiplicative drift that follows the vignetting.
    """
    t, h, w, c = small.shape
    x = small[0].reshape(h * w, c)
    y = small.reshape(t, h * w, c)
    # Medians on every 4th pixel: plenty for an offset and a noise scale, 4x cheaper.
    sub = slice(None, None, 4) if h * w >= 400 else slice(None)
    offset = np.median(y[:, sub] - x[sub], axis=1)  # (t, c)
    resid = np.abs(y - x - offset[:, None, :])
    score = resid[..., 0].copy()  # (t, n): largest residual over the channels
    for ch in range(1, c):
        np.maximum(score, resid[..., ch], out=score)
    scale = 1.4826 * np.median(score[:, sub], axis=1, keepdims=True) + 0.5
    weights = (score <= 3.0 * scale).astype(np.float32)  # (t, n): 0 for contact pixels
    n = np.maximum(weights.sum(axis=1), 1.0)[:, None]  # (t, 1)
    mx = np.einsum("tn,nc->tc", weights, x) / n  # (t, c)
    my = np.einsum("tn,tnc->tc", weights, y) / n
    var = np.einsum("tn,nc->tc", weights, x * x) / n - mx * mx
    cov = np.einsum("tn,tnc->tc", weights, y * x) / n - mx * my
    gain = (cov + _RIDGE) / (np.maximum(var, 0.0) + _RIDGE)
    return np.abs(y - (gain[:, None, :] * (x - mx[:, None, :]) + my[:, None, :]))


def contact_curve(video, *, roi=None):
    """Mean absolute intensity change of each frame against the first frame.

    The change is measured after removing the frame's global illumination
    change: per frame and channel, ``gain * first_frame + offset`` is fitted
    to the frame (least squares, refitted once without the pixels that
    change most), and the curve is the mean absolute residual. Auto-exposure
    steps and slow LED drift, uniform or following the vignetting, scale
    and shift every pixel alike and cancel; the local change made by contact
    remains. Frames are strided down to about 80 pixels on their long side
    first, so the cost does not grow with resolution.

    Parameters
    ----------
    video : array-like of shape (T, H, W, C) or (T, H, W)
        One press; ``uint8``, ``uint16`` or float in [0, 1].
    roi : tuple of 4 floats or None, default=None
        ``(top, bottom, left, right)`` as fractions of the frame height and
        width; only this region is used.

    Returns
    -------
    curve : ndarray of shape (T,), float64
        In intensity levels of 0..255 per pixel and channel; ``curve[0]`` is 0.

    Examples
    --------
    >>> import numpy as np
    >>> from sklearn_hardness.preprocessing import contact_curve
    >>> video = np.full((3, 8, 8), 100, dtype=np.uint8)
    >>> video[1] += 10                   # a uniform brightness change: ignored
    >>> video[2, 2:4, 2:4] = 164         # a local change in the last frame
    >>> contact_curve(video).round(1).tolist()
    [0.0, 0.0, 4.0]
    """
    video = check_video(video, min_frames=1)
    return _curves(video, roi, "video")[0]


def _curves(video, roi, name):
    """The contact curve and the localised curve of one validated video.

    The localised curve is, per frame, the mean residual of the most-changed
    ``_LOCAL_TOP`` of a grid of cells over the (strided) frame. A float
    video is range-checked whole, before the crop and the stride.
    """
    check_float_range(video, name)
    rows, cols = roi_slices(video.shape[1:3], roi, name)
    video = video[:, rows, cols]
    h, w = video.shape[1:3]
    stride = max(1, max(h, w) // _CURVE_SIDE)
    small = as_float255(video[:, ::stride, ::stride], name)
    t, h, w = small.shape[:3]
    resid = _illumination_residual(small)
    curve = resid.mean(axis=(1, 2), dtype=np.float64)
    cell = max(1, -(-max(h, w) // _LOCAL_CELLS))  # ceil: at most _LOCAL_CELLS cells a side
    ny, nx = max(1, h // cell), max(1, w // cell)
    pixels = resid.mean(axis=2).reshape(t, h, w)[:, : ny * cell, : nx * cell]
    cells = pixels.reshape(t, ny, min(cell, h), nx, min(cell, w)).mean(axis=(2, 4)).reshape(t, -1)
    n_top = max(1, int(round(_LOCAL_TOP * cells.shape[1])))
    local = np.partition(cells, -n_top, axis=1)[:, -n_top:].mean(axis=1, dtype=np.float64)
    return curve, local


def _min_frames_auto(n_baseline):
    """Fewest frames the automatic threshold needs: the first, the baseline and two more."""
    return n_baseline + 3


def _quiet_level(smooth, top):
    """Quiet level of a smoothed curve whose maximum is at frame ``top``.

    The ``_BASE_QUANTILE`` of all frames after the first, unless that lies
    at least halfway from the same quantile of the frames before the
    maximum (``smooth[1:top]``) to the maximum: a press held for most of the
    video (about 80% of the frames after the first) puts the whole video's
    quantile on its plateau, and the frames before the maximum give the
    level instead. With fewer than two frames before the maximum, the whole
    video's quantile. (The whole video's quantile is kept otherwise: in
    compressed streams the frames before contact rise with the codec, and
    the quantile before the maximum would fall on the first, lowest ones.)
    """
    whole = float(np.quantile(smooth[1:], _BASE_QUANTILE))
    if top - 1 < 2:
        return whole
    before = float(np.quantile(smooth[1:top], _BASE_QUANTILE))
    return whole if whole - before < 0.5 * (float(smooth[top]) - before) else before


def _mean_curve_peak(curve, n_baseline):
    """Peak, baseline level, noise and contrast of the mean curve.

    The baseline is the ``n_baseline`` frames after the first, but no lower
    than the quiet level of the video (:func:`_quiet_level`) and with
    at least the video's frame-to-frame noise: a compressed stream changes
    least in its first frames (the codec copies the first frame) and
    fluctuates later. The peak is the first frame within the tolerance of
    the maximum (on a plateau, argmax would pick a noisy frame).
    """
    top = int(np.argmax(curve))
    n_base = min(n_baseline, top - 1)
    if n_base >= 1:
        base = curve[1 : n_base + 1]
        level = float(np.median(base))
        noise = float(1.4826 * np.median(np.abs(base - level))) if n_base >= 2 else 0.0
    else:
        level, noise = 0.0, 0.0
    if len(curve) > 2:
        smooth = smooth_curve(curve)
        level = max(level, _quiet_level(smooth, top))
        noise = max(noise, float(1.4826 * np.median(np.abs(curve[1:] - smooth[1:]))))
    contrast = float(curve[top]) - level
    tolerance = max(_PEAK_TOLERANCE * contrast, _NOISE_FACTOR * noise)
    peak = int(np.flatnonzero(curve[: top + 1] >= curve[top] - tolerance)[0])
    return peak, level, noise, contrast


def _locate_weak(local, min_contrast):
    """Start, peak and found on the smoothed localised curve (weak contacts in compressed video)."""
    smooth = smooth_curve(local)
    top = int(np.argmax(smooth))
    quiet = _quiet_level(smooth, top)
    rise = float(smooth[top]) - quiet
    found = top > 0 and rise >= min_contrast and smooth[top] >= _MIN_RATIO * quiet
    peak = int(np.flatnonzero(smooth[: top + 1] >= smooth[top] - _WEAK_PEAK_TOLERANCE * rise)[0])
    return _last_run_start(smooth, peak, quiet + _WEAK_START * rise), peak, found


def _last_run_start(curve, peak, tau):
    """First frame of the last run above ``tau`` that ends at ``peak``.

    An isolated noisy frame earlier does not count.
    """
    below = np.flatnonzero(curve[: peak + 1] <= tau)
    return int(below[-1] + 1) if below.size else 0


def _locate_contact(curve, local, threshold, n_baseline, min_contrast):
    """Contact start, peak, the threshold used and the outcome (one of ``_STATUSES``)."""
    if threshold == "auto" and len(curve) < _min_frames_auto(n_baseline):
        return 0, len(curve) - 1, np.nan, "too short"
    peak, level, noise, contrast = _mean_curve_peak(curve, n_baseline)
    if threshold != "auto":
        # a numeric threshold needs no baseline: contact iff the curve passes it; the peak is the
        # first frame after the reference that is within the tolerance of the maximum and above
        # the threshold (so a short video's noise estimate cannot move the peak below it)
        tau = float(threshold)
        top = int(np.argmax(curve))
        if curve[top] > tau:
            tolerance = max(_PEAK_TOLERANCE * contrast, _NOISE_FACTOR * noise)
            near = curve[1 : top + 1]
            peak = 1 + int(np.flatnonzero((near >= curve[top] - tolerance) & (near > tau))[0])
            return _last_run_start(curve, peak, tau), peak, tau, "contact"
        return 0, peak, tau, "no contact"
    # strong contacts (uncompressed sensors, markers): the mean curve against its first frames
    tau = level + max(_NOISE_FACTOR * noise, _RELATIVE * contrast)
    if peak > 0 and contrast >= _STRONG_CONTRAST and contrast > 2 * _NOISE_FACTOR * noise:
        return _last_run_start(curve, peak, tau), peak, tau, "contact"
    start, peak_weak, found = _locate_weak(local, min_contrast)
    if found:
        return start, peak_weak, np.nan, "weak contact"
    return 0, peak, tau, "no contact"


_STATUSES = ("contact", "weak contact", "no contact", "too short")


def _select_one(video, *, k, threshold, n_baseline, min_contrast, roi, name="video"):
    """Selection of one validated video: (indices, start, peak, threshold, status, curve)."""
    curve, local = _curves(video, roi, name)
    start, peak, tau, status = _locate_contact(curve, local, threshold, n_baseline, min_contrast)
    if status in ("no contact", "too short"):
        # Fallback: spread the frames from the first frame to the frame of the
        # largest change, or over the whole video if nothing changes at all.
        start, peak = 0, (peak if peak > 0 else len(curve) - 1)
    indices = np.rint(np.linspace(start, peak, k)).astype(int)
    return indices, start, peak, tau, status, curve
