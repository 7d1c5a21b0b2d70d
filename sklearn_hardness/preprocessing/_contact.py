"""Contact-frame selection (paper Sec. II-A) as a scikit-learn transformer."""

from __future__ import annotations

import numbers
import warnings

import cv2
import numpy as np
from joblib import Parallel, delayed
from scipy.ndimage import median_filter
from sklearn.base import BaseEstimator, TransformerMixin, _fit_context
from sklearn.utils import Bunch
from sklearn.utils._param_validation import Interval, StrOptions
from sklearn.utils.validation import check_is_fitted

from ..utils._tags import videos_tags
from ..utils._validation import check_video, check_video_sequence

__all__ = ["ContactFrameSelector", "ContactNotFoundWarning", "contact_curve"]

# Side length (pixels) the contact curve is computed at: frames are strided down
# to about this size, which keeps the curve's cost independent of resolution.
_CURVE_SIDE = 80
# Auto threshold: baseline + max(_NOISE_FACTOR * noise, _RELATIVE * (peak - baseline)).
_NOISE_FACTOR = 6.0
_RELATIVE = 0.05
# Strong contacts (markers, uncompressed sensors: the simulator's 18-21 levels) rise this many
# levels over the mean curve's quiet level; weaker ones (real marker-less presses, 1.5-3 levels
# at peak over ~0.75-1 of codec noise) go to the weak-contact test, whose smoothed, localised
# curve also places their start and peak better on a compressed plateau that steps at key frames.
_STRONG_CONTRAST = 2.0
# Weak contacts (compressed, marker-less streams) are tested on a localised curve: the mean
# of the most-changed _LOCAL_TOP of a grid of _LOCAL_CELLS x _LOCAL_CELLS cells, so a small
# sharp contact is not diluted by the pad, running-median smoothed over _SMOOTH frames
# (codec key-frame dips and one-frame glitches go), against its own _BASE_QUANTILE level
# (the quiet part of the video, robust to the codec's rise over the first frames).
_LOCAL_CELLS = 8
_LOCAL_TOP = 0.1
_SMOOTH = 5
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


class ContactNotFoundWarning(UserWarning):
    """Some videos never reached contact; their frames were chosen by the fallback rule."""


def _as_float255(video, name):
    """Frames as float32 in 0..255 intensity units."""
    if video.dtype == np.uint8:
        return video.astype(np.float32)
    if video.dtype == np.uint16:
        return video.astype(np.float32) / 257.0
    vmin, vmax = float(video.min()), float(video.max())
    if vmin < 0.0 or vmax > 1.0:
        raise ValueError(
            f"{name} has float frames with values in [{vmin:g}, {vmax:g}]; float videos must be "
            "scaled to [0, 1] (or pass uint8 frames)."
        )
    return video.astype(np.float32) * 255.0


def _roi_slices(shape, roi, name):
    if roi is None:
        return slice(None), slice(None)
    h, w = shape
    y0, y1, x0, x1 = roi
    rows = slice(int(round(y0 * h)), int(round(y1 * h)))
    cols = slice(int(round(x0 * w)), int(round(x1 * w)))
    if rows.stop - rows.start < 2 or cols.stop - cols.start < 2:
        raise ValueError(f"roi={roi} leaves fewer than 2x2 pixels of the {h}x{w} frames of {name}.")
    return rows, cols


def _contact_window(video, indices, rows, cols, fraction, name):
    """Row and column slices of a fixed-size window centred on the change of a press."""
    last = _as_float255(video[indices[-1] : indices[-1] + 1, rows, cols], name)[0]
    first = _as_float255(video[:1, rows, cols], name)[0]
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
    ``_LOCAL_TOP`` of a grid of cells over the (strided) frame.
    """
    rows, cols = _roi_slices(video.shape[1:3], roi, name)
    video = video[:, rows, cols]
    h, w = video.shape[1:3]
    stride = max(1, max(h, w) // _CURVE_SIDE)
    small = _as_float255(video[:, ::stride, ::stride], name)
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


def _smooth(curve):
    """Running median over ``_SMOOTH`` frames of all but the first (reference) frame."""
    out = curve.copy()
    if len(curve) > 2:
        out[1:] = median_filter(curve[1:], size=min(_SMOOTH, len(curve) - 1), mode="nearest")
    return out


def _mean_curve_peak(curve, n_baseline):
    """Peak, baseline level, noise and contrast of the mean curve.

    The baseline is the ``n_baseline`` frames after the first, but no lower
    than the quiet level of the whole video and with at least the video's
    frame-to-frame noise: a compressed stream changes least in its first
    frames (the codec copies the first frame) and fluctuates later. The peak
    is the first frame within the tolerance of the maximum (on a plateau,
    argmax would pick a noisy frame).
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
        smooth = _smooth(curve)
        level = max(level, float(np.quantile(smooth[1:], _BASE_QUANTILE)))
        noise = max(noise, float(1.4826 * np.median(np.abs(curve[1:] - smooth[1:]))))
    contrast = float(curve[top]) - level
    tolerance = max(_PEAK_TOLERANCE * contrast, _NOISE_FACTOR * noise)
    peak = int(np.flatnonzero(curve[: top + 1] >= curve[top] - tolerance)[0])
    return peak, level, noise, contrast


def _locate_weak(local, min_contrast):
    """Start, peak and found on the smoothed localised curve (weak contacts in compressed video)."""
    smooth = _smooth(local)
    quiet = float(np.quantile(smooth[1:], _BASE_QUANTILE))
    top = int(np.argmax(smooth))
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
        tau = float(threshold)
        if peak > 0 and curve[peak] > tau:
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


class ContactFrameSelector(TransformerMixin, BaseEstimator):
    """Select the frames of the loading period of each press (paper Sec. II-A).

    For each video, the first frame is subtracted from all frames and the
    contact curve (:func:`contact_curve`: mean absolute intensity change,
    with global brightness changes removed) is computed. Contact starts at
    the first frame whose change passes ``threshold``, and ends at the frame
    of peak change (maximum deformation). The first and last of these frames
    plus ``n_between`` frames at equal spacing between them are kept, so each
    video gives ``k = n_between + 2`` frames.

    Parameters
    ----------
    n_between : int, default=2
        Frames kept between the first and the last contact frame (the paper
        uses 2 for its robot data and 1 for Yuan's).
    threshold : "auto" or float, default="auto"
        Change (in 0..255 intensity levels per pixel, as returned by
        :func:`contact_curve`) that marks the start of contact. ``"auto"``
        needs no tuning on any sensor and takes two steps. First, strong
        contacts: with ``b`` the median and ``s`` the robust spread (1.4826
        MAD) of the curve over the ``n_baseline`` frames after the first,
        and ``p`` the peak change, contact is found when ``p - b`` is at
        least 2 levels and more than ``12 s``, and starts where the curve
        passes ``b + max(6 s, 0.05 (p - b))``: well above the sensor's noise
        and above slow drift, at 5% of the press's own contrast. Second,
        weak contacts (compressed, marker-less streams, soft objects): the
        most-changed tenth of an 8x8 grid of cells is averaged per frame, so
        a small sharp contact is not diluted by the pad, smoothed by a
        running median of 5 frames (codec key-frame dips and one-frame
        glitches go), and compared with its own 20th percentile ``q`` (the
        quiet part of the video, which the codec's slow rise over the first
        frames does not bias as it does the first frames): contact is found
        when its peak ``m`` is at least ``1.4 q`` and ``m - q >=
        min_contrast``; it starts where the smoothed curve passes
        ``q + 0.25 (m - q)`` and peaks where it first comes within 20% of
        ``m - q`` of ``m``. The paper's value (1400) is in its own units and
        does not carry over.
    subtract_first : bool, default=True
        Output the selected frames minus the first frame of the video (in
        [-1, 1]), as the paper does; if False, output the raw frames (in
        [0, 1]).
    output_size : tuple (height, width) or None, default=None
        Resize the selected frames (``cv2.INTER_AREA``). Needed when videos
        of different sizes are mixed; ``None`` keeps the input size.
    roi : tuple (top, bottom, left, right) or None, default=None
        Crop each frame to this region, given as fractions of the height
        and width (e.g. ``(0.1, 0.9, 0.1, 0.9)``), before everything else.
        The contact curve is computed on the region too.
    crop_contact : float in (0, 1) or None, default=None
        Cut every press to a window of this fraction of the frame's height
        and width (after ``roi``), centred on where the press changed the
        image (the centroid of the change from the first to the last
        selected frame), before resizing: at the same ``output_size`` the
        net sees the contact at ``1 / crop_contact`` times the resolution,
        or the same detail at a smaller ``output_size``. The window has the
        same size for every press, so the size of the contact, a cue of
        hardness, is kept (a box fitted to each contact would scale it
        away). A press with no change keeps the centre of the frame.
    color : {"rgb", "gray"}, default="rgb"
        Output three colour channels or one grey channel.
    on_no_contact : {"fallback", "raise"}, default="fallback"
        What happens to a video whose change never passes the threshold
        (or whose auto contrast is below ``min_contrast``): ``"fallback"``
        keeps frames spread evenly from the first frame to the frame of
        largest change and emits one :class:`ContactNotFoundWarning` that
        counts such videos; ``"raise"`` raises a ``ValueError`` listing
        them.
    n_baseline : int, default=5
        Frames after the first used to measure the noise level for
        ``threshold="auto"``; they must precede contact. With
        ``threshold="auto"``, videos of fewer than ``n_baseline + 3`` frames
        are reported as too short (see Notes).
    min_contrast : float, default=0.3
        With ``threshold="auto"``, the smallest rise (0..255 levels) of the
        weak-contact curve over its quiet level that counts as contact; it
        keeps videos that barely change (a constant picture, quantisation
        noise) from being reported as contact.
    n_jobs : int or None, default=None
        Videos processed in parallel (joblib threads; OpenCV and NumPy
        release the GIL). ``None`` means 1, ``-1`` all cores.

    Attributes
    ----------
    selection_ : :class:`~sklearn.utils.Bunch`
        What :meth:`select` found on the videos given to :meth:`fit`
        (``indices``, ``contact_start``, ``contact_peak``, ``contact_found``,
        ``status``, ``threshold``, ``curves``).
    n_frames_out_ : int
        ``n_between + 2``.
    frame_shape_ : tuple of int
        ``(H', W', C)`` of the output frames.

    See Also
    --------
    contact_curve : The per-frame change the selection is based on.
    plot_contact_selection : Plot curves with the selected frames.

    Notes
    -----
    Defined outcomes for awkward presses:

    - *Slow illumination drift before contact*: uniform drift cancels in the
      curve; what remains is slow and stays under the relative threshold.
    - *A press that peaks within one frame* (or fewer frames than ``k``
      between start and peak): indices repeat (``np.rint(np.linspace(start,
      peak, k))``), so the output still has ``k`` frames.
    - *Never reaches contact*: see ``on_no_contact``. A video of noise,
      drift and codec artefacts only is reported as no contact.
    - *Weak contact in a compressed stream* (peak only about twice the
      pre-contact level): found by the second step of ``threshold="auto"``;
      its ``status`` is ``"weak contact"`` and its ``threshold`` NaN (the
      test ran on the localised curve, not on :func:`contact_curve`). The
      quiet level is a percentile over the video, so at least a fifth of
      the frames must be free of contact (before it, or after release).
    - *Too short* (fewer than ``n_baseline + 3`` frames, e.g. truncated
      recordings of 3-7 frames) with ``threshold="auto"``: there is no
      baseline to measure noise against, so the status is ``"too short"``,
      the frames are spread over the whole video and the video counts like
      one that never reaches contact (warning or error, ``on_no_contact``).
      A numeric ``threshold`` needs no baseline and still applies.
    - *Videos of different lengths* are fine; different frame sizes need
      ``output_size``.
    - A single-frame video, NaN/inf frames, float frames outside [0, 1] and
      non-numeric input raise errors naming the video.

    Examples
    --------
    >>> import numpy as np
    >>> from sklearn_hardness.preprocessing import ContactFrameSelector
    >>> rng = np.random.default_rng(0)
    >>> video = rng.integers(100, 104, size=(20, 32, 32, 3)).astype(np.uint8)
    >>> for t in range(8, 20):           # a blob that grows from frame 8
    ...     r = min(t - 7, 8)
    ...     video[t, 16 - r:16 + r, 16 - r:16 + r] = 200
    >>> selector = ContactFrameSelector(n_between=2).fit([video])
    >>> selector.selection_.indices.tolist()
    [[9, 11, 13, 15]]
    >>> selector.transform([video]).shape
    (1, 4, 32, 32, 3)
    """

    def __init__(
        self,
        n_between=2,
        *,
        threshold="auto",
        subtract_first=True,
        output_size=None,
        roi=None,
        crop_contact=None,
        color="rgb",
        on_no_contact="fallback",
        n_baseline=5,
        min_contrast=0.3,
        n_jobs=None,
    ):
        self.n_between = n_between
        self.threshold = threshold
        self.subtract_first = subtract_first
        self.output_size = output_size
        self.roi = roi
        self.crop_contact = crop_contact
        self.color = color
        self.on_no_contact = on_no_contact
        self.n_baseline = n_baseline
        self.min_contrast = min_contrast
        self.n_jobs = n_jobs

    _parameter_constraints: dict = {
        "n_between": [Interval(numbers.Integral, 0, None, closed="left")],
        "threshold": [StrOptions({"auto"}), Interval(numbers.Real, 0, None, closed="left")],
        "subtract_first": ["boolean"],
        "output_size": [None, tuple, list],
        "roi": [None, tuple, list],
        "crop_contact": [None, Interval(numbers.Real, 0, 1, closed="neither")],
        "color": [StrOptions({"rgb", "gray"})],
        "on_no_contact": [StrOptions({"fallback", "raise"})],
        "n_baseline": [Interval(numbers.Integral, 1, None, closed="left")],
        "min_contrast": [Interval(numbers.Real, 0, None, closed="left")],
        "n_jobs": [numbers.Integral, None],
    }

    def _check_sizes(self):
        """What the constraint table cannot say: the contents of ``output_size`` and ``roi``."""
        size = self.output_size
        if size is not None and (
            len(size) != 2
            or not all(isinstance(v, numbers.Integral) and not isinstance(v, bool) and v >= 2 for v in size)
        ):
            raise ValueError(f"output_size must be None or (height, width) with ints >= 2, got {size!r}.")
        roi = self.roi
        if roi is not None and (
            len(roi) != 4
            or not all(isinstance(v, numbers.Real) and not isinstance(v, bool) and 0 <= v <= 1 for v in roi)
            or not (roi[0] < roi[1] and roi[2] < roi[3])
        ):
            raise ValueError(
                "roi must be None or (top, bottom, left, right) fractions in [0, 1] with "
                f"top < bottom and left < right, got {roi!r}."
            )

    # --------------------------------------------------------------- selection
    def select(self, X):
        """Find the contact frames of each video without extracting them.

        Parameters
        ----------
        X : sequence of array-like of shape (T, H, W, C)
            The press videos (lengths may differ).

        Returns
        -------
        selection : :class:`~sklearn.utils.Bunch`
            ``indices`` (n, k) int array of selected frame indices;
            ``contact_start``, ``contact_peak`` (n,) int;
            ``contact_found`` (n,) bool; ``status`` (n,) str, one of
            ``"contact"``, ``"weak contact"``, ``"no contact"``, ``"too
            short"`` (see Notes); ``threshold`` (n,) float (the threshold
            used, in :func:`contact_curve` units; NaN for weak and too-short
            videos); ``curves`` list of (T,) float arrays (see
            :func:`contact_curve`).

        Raises
        ------
        ValueError
            With ``on_no_contact="raise"``, if any video never reaches
            contact; or if a video is invalid.
        """
        self._validate_params()  # select may be called without fit
        return self._run(X, extract=False)[1]

    def _run(self, X, extract):
        """Select (and with ``extract``, cut out) the frames of every video.

        Each video is loaded, validated and scanned once: with a lazy sequence,
        loading (decoding or rendering) is the expensive part. Extracted frames
        go straight into one preallocated array, whose shape the first video
        fixes. Returns ``(frames or None, selection)``.
        """
        self._check_sizes()
        check_video_sequence(X)
        kwargs = dict(
            k=self.n_between + 2,
            threshold=self.threshold,
            n_baseline=self.n_baseline,
            min_contrast=self.min_contrast,
            roi=self.roi,
        )
        n = len(X)
        results = [None] * n
        out = None

        def one(i):
            name = f"X[{i}]"
            video = check_video(X[i], name=name, min_frames=2)
            results[i] = _select_one(video, name=name, **kwargs)
            if not extract:
                return
            frames = self._extract(video, results[i][0], name)
            if out is None:
                return frames
            if frames.shape != out.shape[1:]:
                raise ValueError(
                    f"Videos have different frame sizes (X[0]: {out.shape[2:4]}, {name}: "
                    f"{frames.shape[1:3]}); set output_size=(height, width) to resize them."
                )
            out[i] = frames

        first = one(0)
        if extract:
            out = np.empty((n,) + first.shape, dtype=np.float32)
            out[0] = first
        # the jobs write into results and out: they must share this process's memory, also
        # when joblib.parallel_config(backend="dask"|"loky") is active around the call
        Parallel(n_jobs=self.n_jobs, require="sharedmem")(delayed(one)(i) for i in range(1, n))
        status = np.array([r[4] for r in results], dtype=object)
        selection = Bunch(
            indices=np.stack([r[0] for r in results]),
            contact_start=np.array([r[1] for r in results], dtype=int),
            contact_peak=np.array([r[2] for r in results], dtype=int),
            threshold=np.array([r[3] for r in results], dtype=float),
            contact_found=np.isin(status, ["contact", "weak contact"]),
            status=status.astype(str),
            curves=[r[5] for r in results],
        )
        problems = []
        for what, outcome in [("never reach contact", "no contact"), ("are too short to detect contact "
                              f"(fewer than {_min_frames_auto(self.n_baseline)} frames)", "too short")]:
            idx = np.flatnonzero(selection.status == outcome)
            if idx.size:
                more = " ..." if idx.size > 20 else ""
                problems.append((f"{idx.size} of {n} video(s) {what}", f"X{idx[:20].tolist()}{more}"))
        if problems and self.on_no_contact == "raise":
            raise ValueError(
                "; ".join(f"{head}: {which}" for head, which in problems)
                + ". Lower `threshold`, check the videos, or set on_no_contact='fallback'."
            )
        if problems:
            warnings.warn(
                "; ".join(f"{head} ({which})" for head, which in problems)
                + "; their frames were spread from the first frame to the frame of largest change.",
                ContactNotFoundWarning,
                stacklevel=3,
            )
        return out, selection

    def _extract(self, video, indices, name):
        """The selected frames of one validated video, scaled, cropped, converted, resized."""
        rows, cols = _roi_slices(video.shape[1:3], self.roi, name)
        if self.crop_contact is not None:
            rows, cols = _contact_window(video, indices, rows, cols, self.crop_contact, name)
        frames = _as_float255(video[indices][:, rows, cols], name)
        if self.subtract_first:
            frames -= _as_float255(video[:1, rows, cols], name)
        frames /= 255.0
        if self.color == "gray" and frames.shape[-1] == 3:
            frames = frames @ np.array([0.299, 0.587, 0.114], dtype=np.float32)
            frames = frames[..., np.newaxis]
        elif self.color == "rgb" and frames.shape[-1] == 1:
            frames = np.repeat(frames, 3, axis=-1)
        if self.output_size is not None:
            h, w = self.output_size
            if frames.shape[1:3] != (h, w):
                resized = [cv2.resize(f, (w, h), interpolation=cv2.INTER_AREA) for f in frames]
                frames = np.stack([r if r.ndim == 3 else r[..., np.newaxis] for r in resized])
        return np.ascontiguousarray(frames, dtype=np.float32)

    # ------------------------------------------------------------- estimator
    @_fit_context(prefer_skip_nested_validation=True)
    def fit(self, X, y=None):
        """Check the parameters and find the contact frames of ``X``.

        Parameters
        ----------
        X : sequence of array-like of shape (T, H, W, C)
            The press videos.
        y : ignored

        Returns
        -------
        self : ContactFrameSelector
        """
        self.fit_transform(X, y)
        return self

    @_fit_context(prefer_skip_nested_validation=True)
    def fit_transform(self, X, y=None):
        """Fit to ``X`` and return its selected frames, in one pass over the videos.

        Parameters
        ----------
        X : sequence of array-like of shape (T, H, W, C)
            The press videos.
        y : ignored

        Returns
        -------
        frames : ndarray of shape (n, n_between + 2, H', W', C'), float32
        """
        out, selection = self._run(X, extract=True)
        self.selection_ = selection
        self.n_frames_out_ = self.n_between + 2
        self.frame_shape_ = tuple(out.shape[2:])
        return out

    def transform(self, X):
        """Return the selected frames of each video.

        Parameters
        ----------
        X : sequence of array-like of shape (T, H, W, C)
            The press videos.

        Returns
        -------
        frames : ndarray of shape (n, n_between + 2, H', W', C'), float32
            Differences to the first frame in [-1, 1] (``subtract_first``)
            or raw frames in [0, 1].
        """
        check_is_fitted(self, "selection_")
        out, _ = self._run(X, extract=True)
        if tuple(out.shape[2:]) != self.frame_shape_:
            raise ValueError(
                f"X gives frames of shape {tuple(out.shape[2:])} but the videos seen in fit gave "
                f"{self.frame_shape_}; set output_size to make them equal."
            )
        return out

    def __sklearn_tags__(self):
        return videos_tags(super().__sklearn_tags__())
