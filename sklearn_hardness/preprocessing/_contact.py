"""Contact-frame selection (paper Sec. II-A) as a scikit-learn transformer."""

from __future__ import annotations

import numbers
import warnings

import cv2
import numpy as np
from joblib import Parallel, delayed
from sklearn.base import BaseEstimator, TransformerMixin
from sklearn.utils import Bunch
from sklearn.utils.validation import check_is_fitted

from ..utils._validation import check_video, check_video_sequence

__all__ = ["ContactFrameSelector", "ContactNotFoundWarning", "contact_curve"]

# Side length (pixels) the contact curve is computed at: frames are strided down
# to about this size, which keeps the curve's cost independent of resolution.
_CURVE_SIDE = 80
# Auto threshold: baseline + max(_NOISE_FACTOR * noise, _RELATIVE * (peak - baseline)).
_NOISE_FACTOR = 6.0
_RELATIVE = 0.05
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
    rows, cols = _roi_slices(video.shape[1:3], roi, "video")
    video = video[:, rows, cols]
    h, w = video.shape[1:3]
    stride = max(1, max(h, w) // _CURVE_SIDE)
    small = _as_float255(video[:, ::stride, ::stride], "video")
    resid = _illumination_residual(small)
    return resid.mean(axis=(1, 2), dtype=np.float64)


def _locate_contact(curve, threshold, n_baseline, min_contrast):
    """Contact start, peak, the threshold used and whether contact was found."""
    top = int(np.argmax(curve))
    n_base = min(n_baseline, top - 1)
    if n_base >= 1:
        base = curve[1 : n_base + 1]
        level = float(np.median(base))
        noise = float(1.4826 * np.median(np.abs(base - level))) if n_base >= 2 else 0.0
    else:
        level, noise = 0.0, 0.0
    contrast = float(curve[top]) - level
    tolerance = max(_PEAK_TOLERANCE * contrast, _NOISE_FACTOR * noise)
    peak = int(np.flatnonzero(curve[: top + 1] >= curve[top] - tolerance)[0])
    if threshold == "auto":
        tau = level + max(_NOISE_FACTOR * noise, _RELATIVE * contrast)
        found = peak > 0 and contrast >= min_contrast and contrast > 2 * _NOISE_FACTOR * noise
    else:
        tau = float(threshold)
        found = peak > 0 and curve[peak] > tau
    if not found:
        return 0, peak, tau, False
    # Contact starts at the first frame of the last run above the threshold that
    # ends at the peak: an isolated noisy frame earlier does not count.
    below = np.flatnonzero(curve[: peak + 1] <= tau)
    start = int(below[-1] + 1) if below.size else 0
    return start, peak, tau, True


def _select_one(video, *, k, threshold, n_baseline, min_contrast, roi):
    """Selection of one validated video: (indices, start, peak, threshold, found, curve)."""
    curve = contact_curve(video, roi=roi)
    start, peak, tau, found = _locate_contact(curve, threshold, n_baseline, min_contrast)
    if not found:
        # Fallback: spread the frames from the first frame to the frame of the
        # largest change, or over the whole video if nothing changes at all.
        start, peak = 0, (peak if peak > 0 else len(curve) - 1)
    indices = np.rint(np.linspace(start, peak, k)).astype(int)
    return indices, start, peak, tau, found, curve


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
        needs no tuning on any sensor: with ``b`` the median and ``s`` the
        robust spread (1.4826 MAD) of the curve over the ``n_baseline``
        frames after the first, and ``p`` the peak change, the threshold is
        ``b + max(6 s, 0.1 (p - b))``: well above the sensor's noise and
        above slow drift, at one tenth of the press's own contrast. The
        paper's value (1400) is in its own units and does not carry over.
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
        ``threshold="auto"``; they must precede contact.
    min_contrast : float, default=1.0
        With ``threshold="auto"``, a peak change smaller than this (0..255
        levels) above the baseline counts as no contact.
    n_jobs : int or None, default=None
        Videos processed in parallel (joblib threads; OpenCV and NumPy
        release the GIL). ``None`` means 1, ``-1`` all cores.

    Attributes
    ----------
    selection_ : :class:`~sklearn.utils.Bunch`
        What :meth:`select` found on the videos given to :meth:`fit`
        (``indices``, ``contact_start``, ``contact_peak``, ``contact_found``,
        ``threshold``, ``curves``).
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
    - *Never reaches contact*: see ``on_no_contact``.
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
        color="rgb",
        on_no_contact="fallback",
        n_baseline=5,
        min_contrast=1.0,
        n_jobs=None,
    ):
        self.n_between = n_between
        self.threshold = threshold
        self.subtract_first = subtract_first
        self.output_size = output_size
        self.roi = roi
        self.color = color
        self.on_no_contact = on_no_contact
        self.n_baseline = n_baseline
        self.min_contrast = min_contrast
        self.n_jobs = n_jobs

    # ------------------------------------------------------------------ params
    def _validate_params(self):
        if isinstance(self.n_between, bool) or not isinstance(self.n_between, numbers.Integral) or self.n_between < 0:
            raise ValueError(f"n_between must be an integer >= 0, got {self.n_between!r}.")
        if isinstance(self.threshold, str):
            if self.threshold != "auto":
                raise ValueError(f"threshold must be 'auto' or a number, got {self.threshold!r}.")
        elif (
            isinstance(self.threshold, bool)
            or not isinstance(self.threshold, numbers.Real)
            or not np.isfinite(self.threshold)
            or self.threshold < 0
        ):
            raise ValueError(f"threshold must be 'auto' or a number >= 0, got {self.threshold!r}.")
        if self.output_size is not None:
            size = self.output_size
            if (
                not isinstance(size, (tuple, list))
                or len(size) != 2
                or not all(isinstance(s, numbers.Integral) and not isinstance(s, bool) and s >= 2 for s in size)
            ):
                raise ValueError(f"output_size must be None or (height, width) with ints >= 2, got {size!r}.")
        if self.roi is not None:
            roi = self.roi
            if (
                not isinstance(roi, (tuple, list))
                or len(roi) != 4
                or not all(isinstance(v, numbers.Real) and 0 <= v <= 1 for v in roi)
                or not (roi[0] < roi[1] and roi[2] < roi[3])
            ):
                raise ValueError(
                    "roi must be None or (top, bottom, left, right) fractions in [0, 1] with "
                    f"top < bottom and left < right, got {roi!r}."
                )
        if self.color not in ("rgb", "gray"):
            raise ValueError(f"color must be 'rgb' or 'gray', got {self.color!r}.")
        if self.on_no_contact not in ("fallback", "raise"):
            raise ValueError(f"on_no_contact must be 'fallback' or 'raise', got {self.on_no_contact!r}.")
        if isinstance(self.n_baseline, bool) or not isinstance(self.n_baseline, numbers.Integral) or self.n_baseline < 1:
            raise ValueError(f"n_baseline must be an integer >= 1, got {self.n_baseline!r}.")
        if not isinstance(self.min_contrast, numbers.Real) or not self.min_contrast >= 0:
            raise ValueError(f"min_contrast must be a number >= 0, got {self.min_contrast!r}.")

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
            ``contact_found`` (n,) bool; ``threshold`` (n,) float (the
            threshold used, in curve units); ``curves`` list of (T,) float
            arrays (see :func:`contact_curve`).

        Raises
        ------
        ValueError
            With ``on_no_contact="raise"``, if any video never reaches
            contact; or if a video is invalid.
        """
        return self._run(X, extract=False)[1]

    def _run(self, X, extract):
        """Select (and with ``extract``, cut out) the frames of every video.

        Each video is loaded, validated and scanned once: with a lazy sequence,
        loading (decoding or rendering) is the expensive part. Extracted frames
        go straight into one preallocated array, whose shape the first video
        fixes. Returns ``(frames or None, selection)``.
        """
        self._validate_params()
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
            results[i] = _select_one(video, **kwargs)
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
        selection = Bunch(
            indices=np.stack([r[0] for r in results]),
            contact_start=np.array([r[1] for r in results], dtype=int),
            contact_peak=np.array([r[2] for r in results], dtype=int),
            threshold=np.array([r[3] for r in results], dtype=float),
            contact_found=np.array([r[4] for r in results], dtype=bool),
            curves=[r[5] for r in results],
        )
        missing = np.flatnonzero(~selection.contact_found)
        if missing.size:
            listed = missing[:20].tolist()
            more = " ..." if missing.size > 20 else ""
            if self.on_no_contact == "raise":
                raise ValueError(
                    f"{missing.size} of {n} video(s) never reach contact: X{listed}{more}. "
                    "Lower `threshold`, check the videos, or set on_no_contact='fallback'."
                )
            warnings.warn(
                f"{missing.size} of {n} video(s) never reach contact (X{listed}{more}); their "
                "frames were spread from the first frame to the frame of largest change.",
                ContactNotFoundWarning,
                stacklevel=3,
            )
        return out, selection

    def _extract(self, video, indices, name):
        """The selected frames of one validated video, scaled, cropped, converted, resized."""
        rows, cols = _roi_slices(video.shape[1:3], self.roi, name)
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
        tags = super().__sklearn_tags__()
        tags.requires_fit = True
        tags.input_tags.two_d_array = True  # keep sklearn's common checks running (see tests)
        return tags
