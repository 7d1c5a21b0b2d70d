"""Shape- and texture-normalised features of a press's loading phase: :class:`ContactProfileFeatures`."""

from __future__ import annotations

import numbers

import cv2
import numpy as np
from sklearn.base import BaseEstimator, TransformerMixin, clone
from sklearn.utils.validation import check_is_fitted

from ..utils._frames import as_float255, check_float_range
from ..utils._param_validation import HasMethods, Interval, StrOptions, fit_context
from ..utils._per_press import PerPressTransformerMixin, map_presses, transform_presses
from ..utils._tags import videos_tags
from ..utils._validation import check_roi, check_video, check_video_sequence, roi_slices
from ._feature_names import check_feature_names, feature_columns

__all__ = ["ContactProfileFeatures"]

#: Every feature, in output order when ``features="all"`` (the last two, ``log_loading_time`` and
#: ``log_contact_spread``, were added later).
FEATURE_NAMES = (
    "log_peak_change",
    "peak_over_precontact",
    "rise_frames",
    "rise_fraction",
    "hold_fraction",
    "area_at_peak",
    "concentration",
    "area_intensity_slope",
    "texture_ratio",
    "early_late_ratio",
    "log_loading_time",
    "log_contact_spread",
)


def _grey_small(video, max_side, roi=None, name="video"):
    """Grey frames strided to about ``max_side`` pixels, in 0..255 intensity units.

    Read as the contact curve reads them (by dtype: uint8 as is, uint16 / 257,
    float in [0, 1] times 255); a float video with any value outside [0, 1]
    raises an error naming it.
    """
    video = check_video(video, min_frames=1, name=name)
    check_float_range(video, name)  # the whole video, not only the strided pixels
    rows, cols = roi_slices(video.shape[1:3], roi, name)  # the whole frame for roi=None
    video = video[:, rows, cols]
    h, w = video.shape[1:3]
    stride = max(1, max(h, w) // max_side)
    small = as_float255(video[:, ::stride, ::stride], name)
    return small.mean(axis=-1) if small.ndim == 4 else small


def _crossing(above, level, stop):
    """First time (in frames, interpolated between frames) at which ``above`` reaches ``level``, up to ``stop``."""
    a = above[:stop + 1]
    j = int(np.argmax(a >= level))
    if j == 0:
        return 0.0
    lo, hi = float(a[j - 1]), float(a[j])
    return j - 1 + (level - lo) / max(hi - lo, 1e-9)


def _spread(d_peak):
    """Log second moment of the change at peak about its centroid, as a share of the frame.

    The change is smoothed (a Gaussian of 1/40 of the frame's long side) and
    weighted by how far it lies above its median, so that the half of the
    frame below it (mostly noise) does not count; a rigid tip gives a small
    spread and a contact that grows wide a large one, whatever its strength,
    as long as the change stands well above the pixel noise (for a change of
    a few times the noise, the noise above the median pulls the spread
    towards its own, that of the whole frame).
    """
    h, w = d_peak.shape
    smooth = cv2.GaussianBlur(np.maximum(d_peak, 0).astype(np.float32), (0, 0), max(h, w) / 40.0)
    weight = np.maximum(smooth - np.median(smooth), 0.0)
    total = float(weight.sum())
    if total <= 0:
        return float(np.log(1e-4))
    yy, xx = np.mgrid[0:h, 0:w].astype(np.float32)
    cy, cx = float((weight * yy).sum()) / total, float((weight * xx).sum()) / total
    moment = float((weight * ((yy - cy) ** 2 + (xx - cx) ** 2)).sum()) / total
    return float(np.log(moment / (h * w) + 1e-4))


def _run_start(above, level):
    """First frame of the last run of ``above >= level`` that ends at the last frame (its length if none)."""
    below = np.flatnonzero(above < level)
    return int(below[-1]) + 1 if below.size else 0


def _n_precontact(curve, i_peak):
    """End (exclusive) of the pre-contact frames ``1 .. n - 1``, before the rise to the peak.

    The window is a quarter of the video (at most 25 frames, at least 2),
    unless the rise to the peak is under way inside it: where the last run
    of frames, up to the peak, at least halfway from the window's median to
    the peak starts inside the window, the window is cut at the start of the
    last run at least 20% of the way, and the median is taken again, until
    the halfway run starts at or after the window's end. Runs, not single
    frames, and halfway, so a noise spike or a codec step before contact
    does not cut it; where the rise begins after the first window, the
    window is the first one.
    """
    n = max(2, min(len(curve) // 4, 25))
    peak = float(curve[i_peak])
    head = curve[: i_peak + 1]
    while n > 2:
        base = float(np.median(curve[1:n]))
        span = peak - base
        if span <= 0 or _run_start(head - base, 0.5 * span) >= n:
            break
        n = max(2, _run_start(head - base, 0.2 * span))
    return n


def _profile(video, max_side, noise_factor, roi=None, name="video"):
    g = _grey_small(video, max_side, roi, name)
    t = len(g)
    diff = np.abs(g - g[0])  # (T, h, w)
    curve = diff.reshape(t, -1).mean(axis=1)
    if t < 3:
        # no pre-contact frames; ratios default to 1, or to 0 (as for longer videos) where nothing changes
        one = 1.0 if curve.max() > 0 else 0.0
        return np.array([np.log(0.1 + curve.max()), one, 0.0, 0.0, 0.0, 0.0, one, 0.0, one, one,
                         np.log(0.1), np.log(1e-4)])
    i_peak = int(np.argmax(curve))
    peak = float(curve[i_peak])
    # pre-contact frames: up to a quarter of the video (at most 25), ending before the rise
    n_pre = _n_precontact(curve, i_peak)
    base = float(np.median(curve[1:n_pre])) if n_pre > 1 else 0.0
    span = max(peak - base, 1e-6)
    above = curve - base
    # loading phase: from 20% to 90% of the rise above the pre-contact level
    i20 = int(np.argmax(above >= 0.2 * span))
    i90 = int(np.argmax(above >= 0.9 * span))
    rise = max(i90 - i20, 0)
    hold = float(np.mean(above >= 0.5 * span))
    # pixels that changed beyond the pre-contact noise of each pixel
    noise = np.median(diff[1:n_pre], axis=0) if n_pre > 1 else np.zeros(diff.shape[1:])
    thr = noise_factor * (float(np.median(noise)) + 0.5)
    active = (diff - noise) > thr  # (T, h, w)
    area = active.reshape(t, -1).mean(axis=1)
    d_peak = diff[i_peak] - noise
    conc = float(np.percentile(d_peak, 99) / max(np.mean(np.abs(d_peak)), 1e-6))
    # how contact area grows against intensity during loading (shape normalised by the log-log slope)
    load = np.arange(i20, max(i90, i20) + 1)
    ok = load[(area[load] > 0) & (above[load] > 0)]
    if len(ok) >= 3 and np.ptp(np.log(above[ok])) > 1e-6:
        slope = float(np.polyfit(np.log(above[ok]), np.log(area[ok]), 1)[0])
    else:
        slope = 0.0
    lap = np.abs(cv2.Laplacian(d_peak.astype(np.float32), cv2.CV_32F))
    texture = float(lap.mean() / max(np.mean(np.abs(d_peak)), 1e-6))
    # early vs late loading: soft bodies keep changing long after first contact
    mid = i20 + max(rise // 2, 1)
    early_late = float(above[min(mid, t - 1)] / span)
    # the same loading time between frames: interpolated crossings of 20% and 90% of the rise
    loading = _crossing(above, 0.9 * span, i_peak) - _crossing(above, 0.2 * span, i_peak)
    return np.array([np.log(0.1 + peak), peak / max(base, 0.05), float(rise), rise / t, hold,
                     float(area[i_peak]), conc, slope, texture, early_late, np.log(max(loading, 0.1)),
                     _spread(d_peak)])


class ContactProfileFeatures(PerPressTransformerMixin, TransformerMixin, BaseEstimator):
    """Features of a press that normalise away object shape, texture and signal strength.

    From the change of each frame to the first frame (grey, strided to about
    ``max_side`` pixels on the long side), per video: the peak mean change
    and its ratio to the video's own pre-contact level (codec and exposure
    noise), the loading time (frames from 20% to 90% of the rise; soft
    objects load slowly), the fraction of the video held above half the
    peak, the contact area at peak and how concentrated the change is, the
    log-log slope of contact area against intensity during loading (how
    contact size grows with depth, which Hertz contact ties to hardness
    whatever the object's radius), the texture ratio (Laplacian energy over
    mean change), how far the change has risen halfway through loading, and
    two later measures: the loading time between frames
    (``log_loading_time``: the crossings of 20% and 90% of the rise,
    interpolated between frames, where ``rise_frames`` counts whole frames)
    and the contact's spread (``log_contact_spread``: the second moment of
    the smoothed change at peak about its centroid, as a share of the
    frame). A gel's shading changes at the rim and slopes of a contact, not
    over its flat middle, so the share of changed pixels (``area_at_peak``)
    does not follow the contact's size; on the simulator the spread does
    (evidence: ``studies/pages/contact_profile_features.md``,
    ``studies/scripts/contact_profile_features.py``). Where the change is
    only a few times the pixel noise, the spread is pulled towards that of
    the noise (the whole frame).

    Parameters
    ----------
    features : "all" or sequence of str, default="all"
        Which features to output, in this order (names as in
        :meth:`get_feature_names_out`); ``"all"`` is the twelve, the last
        two the later ``log_loading_time`` and ``log_contact_spread``. Every feature is computed either way; a
        subset is a choice of columns that ``GridSearchCV`` can make on a
        user's own presses (``features__features`` in
        :func:`~sklearn_hardness.models.make_contact_profile_pipeline`).
    max_side : int, default=80
        Frames are strided down to about this many pixels on their long side.
    noise_factor : float, default=3.0
        A pixel is in contact when its change exceeds its own pre-contact
        change by this many times the median pre-contact change (+0.5 grey
        levels for codec quantisation).
    roi : tuple (top, bottom, left, right) or None, default=None
        Read only this region of each frame, given as fractions of its height
        and width (e.g. ``(0.18, 0.88, 0.08, 0.70)``), before striding: the
        same features as on videos cropped to it. For sensors whose frame
        shows more than the gel (a GelSight Wedge grasp shows the housing and
        the other finger), where changes outside the gel would count as
        contact. The region of
        :class:`~sklearn_hardness.preprocessing.ContactFrameSelector` and
        :func:`~sklearn_hardness.models.make_peak_change_baseline`.
    n_jobs : int or None, default=None
        Videos processed in parallel (joblib threads).
    memory : None, str or object with the joblib.Memory interface, default=None
        Cache each press's row here (a folder, or a :class:`joblib.Memory`),
        keyed by the parameters that change it and the press (a video of a
        lazy sequence by its file or seed, without decoding it; a video in
        memory by a hash of its frames), so that the folds of a
        cross-validation, a grid search or a later run that meet the press
        again read it. Validated as
        :func:`sklearn.utils.validation.check_memory` validates a
        :class:`~sklearn.pipeline.Pipeline`'s ``memory``; None: no cache.
        An entry is the row, every feature whichever ``features`` are output (under 1 kB).

    Attributes
    ----------
    features_ : tuple of str
        The output features, in order.
    n_features_out_ : int
        Their number (12 for ``features="all"``).

    See Also
    --------
    sklearn_hardness.preprocessing.contact_curve : The mean change alone.

    Notes
    -----
    The pre-contact frames (the level ``peak_over_precontact`` divides by
    and each pixel's own noise) are frames 1 to a quarter of the video, at
    most 25, ended before the rise where contact starts among them: where
    the frames from the last run at least halfway from their median to the
    peak reach into the window, it ends where that rise passes 20% of the
    way (and its median is taken again). A press touched early and held
    long so gives the features of the same press held briefly; with contact
    after the window, the window is the quarter of the video as before.

    Frames are read as :class:`~sklearn_hardness.preprocessing.ContactFrameSelector`
    reads them: ``uint8`` as is, ``uint16`` divided by 257, float in
    [0, 1] times 255; float videos with any value outside [0, 1] raise an
    error naming the video.

    Examples
    --------
    >>> import numpy as np
    >>> from sklearn_hardness.features import ContactProfileFeatures
    >>> video = np.full((20, 32, 32, 3), 120, np.uint8)
    >>> for t in range(8, 20):
    ...     video[t, 16 - t // 2:16 + t // 2, 16 - t // 2:16 + t // 2] = 140
    >>> ContactProfileFeatures().fit_transform([video]).shape
    (1, 12)
    >>> ContactProfileFeatures(features=["log_peak_change", "log_loading_time"]).fit([video]).get_feature_names_out()
    array(['log_peak_change', 'log_loading_time'], dtype=object)
    """

    _parameter_constraints: dict = {
        "features": [StrOptions({"all"}), list, tuple],
        "max_side": [Interval(numbers.Integral, 8, None, closed="left")],
        "noise_factor": [Interval(numbers.Real, 0, None, closed="neither")],
        "roi": [None, tuple, list],
        "n_jobs": [numbers.Integral, None],
        "memory": [None, str, HasMethods(["cache"])],
    }

    _per_press_ignored = ("memory", "n_jobs", "features")  # every feature is computed and cached

    def __init__(self, features="all", max_side=80, noise_factor=3.0, roi=None, n_jobs=None, memory=None):
        self.features = features
        self.max_side = max_side
        self.noise_factor = noise_factor
        self.roi = roi
        self.n_jobs = n_jobs
        self.memory = memory

    @fit_context(prefer_skip_nested_validation=True)
    def fit(self, X, y=None):
        """Check the parameters and the input (stateless otherwise).

        Parameters
        ----------
        X : sequence of array-like of shape (T, H, W, 3)
            Press videos.
        y : ignored

        Returns
        -------
        self : ContactProfileFeatures
        """
        check_roi(self.roi)
        check_video_sequence(X)
        self.features_ = check_feature_names(self.features, FEATURE_NAMES)
        self.n_features_out_ = len(self.features_)
        return self

    def transform(self, X):
        """Compute the features of each video.

        Parameters
        ----------
        X : sequence of array-like of shape (T, H, W, 3)
            Press videos (lengths may differ; one-frame videos give a
            defined row).

        Returns
        -------
        features : ndarray of shape (n_videos, n_features_out_), float64
        """
        check_is_fitted(self)
        X = check_video_sequence(X)
        rows = transform_presses(self, X)[0]
        return rows[:, feature_columns(self.features_, FEATURE_NAMES)]

    def _transform_presses(self, X):
        params = dict(max_side=self.max_side, noise_factor=self.noise_factor, roi=check_roi(self.roi))
        return map_presses(_profile, X, params, n_jobs=self.n_jobs), {}

    def _shared_pass(self):
        """All twelve features: steps that differ only in ``features`` share one pass, each taking its columns."""
        if isinstance(self.features, str):
            return None
        try:
            columns = feature_columns(self.features, FEATURE_NAMES)
        except (TypeError, ValueError):  # its own fit refuses it: the pass fails as the step would
            return None
        return clone(self).set_params(features="all"), columns

    def get_feature_names_out(self, input_features=None):
        """Names of the features.

        Parameters
        ----------
        input_features : ignored

        Returns
        -------
        names : ndarray of str
        """
        check_is_fitted(self)
        return np.array(self.features_, dtype=object)

    def __sklearn_tags__(self):
        return videos_tags(super().__sklearn_tags__())
