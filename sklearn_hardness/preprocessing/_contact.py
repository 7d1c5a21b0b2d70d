"""Contact-frame selection (paper Sec. II-A) as a scikit-learn transformer; detection is in :mod:`._contact_curve`."""

from __future__ import annotations

import numbers
import warnings
from collections import Counter

import cv2
import numpy as np
from joblib import Parallel, delayed
from sklearn.base import BaseEstimator, TransformerMixin
from sklearn.utils import Bunch
from sklearn.utils.validation import check_is_fitted

from ..utils._frames import as_float255
from ..utils._param_validation import (
    FRAME_SIZE,
    HasMethods,
    Hidden,
    Interval,
    StrOptions,
    fit_context,
    validate_estimator_params,
)
from ..utils._per_press import PerPressTransformerMixin, transform_presses
from ..utils._tags import videos_tags
from ..utils._validation import check_roi, check_video, check_video_sequence, roi_slices
from ..utils._warnings import external_stacklevel
from ._contact_curve import _contact_window, _min_frames_auto, _select_one

__all__ = ["ContactFrameSelector", "ContactNotFoundWarning"]

class ContactNotFoundWarning(UserWarning):
    """Some videos never reached contact; their frames were chosen by the fallback rule.

    Examples
    --------
    >>> import warnings
    >>> import numpy as np
    >>> from sklearn_hardness.preprocessing import ContactFrameSelector, ContactNotFoundWarning
    >>> still = np.full((12, 16, 16, 3), 100, np.uint8)   # a press that never touches
    >>> with warnings.catch_warnings(record=True) as caught:
    ...     warnings.simplefilter("always")
    ...     ContactFrameSelector().fit([still]).selection_.status.tolist()
    ['no contact']
    >>> [w.category is ContactNotFoundWarning for w in caught]
    [True]
    """


class ContactFrameSelector(PerPressTransformerMixin, TransformerMixin, BaseEstimator):
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
        frames does not bias as it does the first frames; where it lies at
        least halfway up to the maximum, as when the press is held for most
        of the video, the 20th percentile of the frames before the maximum;
        the same level of the mean curve bounds ``b`` from below): contact
        is found
        when its peak ``m`` is at least ``1.4 q`` and ``m - q >=
        min_contrast``; it starts where the smoothed curve passes
        ``q + 0.25 (m - q)`` and peaks where it first comes within 20% of
        ``m - q`` of ``m``. The paper's value (1400) is in its own units and
        does not carry over.
    subtract_first : bool, default=True
        Output the selected frames minus the first frame of the video (in
        [-1, 1]), as the paper does; if False, output the raw frames (in
        [0, 1]).
    frame_size : tuple (height, width) or None, default=None
        Resize the selected frames (``cv2.INTER_AREA``). Needed when videos
        of different sizes are mixed; ``None`` keeps the input size. The same
        name as the ``frame_size`` of the model factories and the
        experiments' configuration.

        .. versionchanged:: 0.1
           Renamed from ``output_size``, the name it had before.
    roi : tuple (top, bottom, left, right) or None, default=None
        Crop each frame to this region, given as fractions of the height
        and width (e.g. ``(0.1, 0.9, 0.1, 0.9)``), before everything else.
        The contact curve is computed on the region too.
    crop_contact : float in (0, 1) or None, default=None
        Cut every press to a window of this fraction of the frame's height
        and width (after ``roi``), centred on where the press changed the
        image (the centroid of the change from the first to the last
        selected frame), before resizing: at the same ``frame_size`` the
        net sees the contact at ``1 / crop_contact`` times the resolution,
        or the same detail at a smaller ``frame_size``. The window has the
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
    memory : None, str or object with the joblib.Memory interface, default=None
        Cache each press's frames and selection here (a folder, or a
        :class:`joblib.Memory`), keyed by the parameters that change them and
        the press (a video of a lazy sequence by its file or seed, without
        decoding it), so that the folds of a cross-validation, a grid search
        or a later run that meet the press again read them. Validated as
        :func:`sklearn.utils.validation.check_memory` validates a
        :class:`~sklearn.pipeline.Pipeline`'s ``memory``. A press's entry
        holds its ``k`` frames as float32: ``4 k H' W' C`` bytes (12 kB at
        ``frame_size=(18, 24)``, 3.7 MB for 4 full 240x320 RGB frames).
    output_size : tuple (height, width) or None, default="deprecated"
        The former name of ``frame_size``.

        .. deprecated:: 0.1
           Use ``frame_size``; ``output_size`` will be removed in 0.2.

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
      quiet level is a percentile over the video, or over the frames before
      the peak where a press held for most of the video would put it on the
      plateau: a long hold does not hide a contact.
    - *Too short* (fewer than ``n_baseline + 3`` frames, e.g. truncated
      recordings of 3-7 frames) with ``threshold="auto"``: there is no
      baseline to measure noise against, so the status is ``"too short"``,
      the frames are spread over the whole video and the video counts like
      one that never reaches contact (warning or error, ``on_no_contact``).
      A numeric ``threshold`` needs no baseline and still applies: contact
      is found when the curve passes it, and the peak is the first frame
      within the noise tolerance of the maximum that is above it.
    - *Videos of different lengths* are fine; different frame sizes need
      ``frame_size``.
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
        frame_size=None,
        roi=None,
        crop_contact=None,
        color="rgb",
        on_no_contact="fallback",
        n_baseline=5,
        min_contrast=0.3,
        n_jobs=None,
        memory=None,
        output_size="deprecated",
    ):
        self.n_between = n_between
        self.threshold = threshold
        self.subtract_first = subtract_first
        self.frame_size = frame_size
        self.roi = roi
        self.crop_contact = crop_contact
        self.color = color
        self.on_no_contact = on_no_contact
        self.n_baseline = n_baseline
        self.min_contrast = min_contrast
        self.n_jobs = n_jobs
        self.memory = memory
        self.output_size = output_size

    _parameter_constraints: dict = {
        "n_between": [Interval(numbers.Integral, 0, None, closed="left")],
        "threshold": [StrOptions({"auto"}), Interval(numbers.Real, 0, None, closed="left")],
        "subtract_first": ["boolean"],
        "frame_size": [None, FRAME_SIZE],
        "output_size": [Hidden(StrOptions({"deprecated"})), None, FRAME_SIZE],
        "roi": [None, tuple, list],
        "crop_contact": [None, Interval(numbers.Real, 0, 1, closed="neither")],
        "color": [StrOptions({"rgb", "gray"})],
        "on_no_contact": [StrOptions({"fallback", "raise"})],
        "n_baseline": [Interval(numbers.Integral, 1, None, closed="left")],
        "min_contrast": [Interval(numbers.Real, 0, None, closed="left")],
        "n_jobs": [numbers.Integral, None],
        "memory": [None, str, HasMethods(["cache"])],
    }

    def _check_sizes(self):
        """What the constraint table cannot say: the contents of ``roi``; not both size names."""
        if self.output_size != "deprecated" and self.frame_size is not None:
            raise ValueError(
                "Both frame_size and output_size are set; output_size is the deprecated name of "
                "frame_size: set frame_size only."
            )
        check_roi(self.roi)

    def _resolved_frame_size(self):
        """``frame_size``, or the deprecated ``output_size`` where that was set (checked in ``_check_sizes``)."""
        return self.frame_size if self.output_size == "deprecated" else self.output_size

    def _warn_output_size(self):
        if self.output_size != "deprecated":
            warnings.warn(
                "`output_size` was renamed `frame_size` in 0.1 and will be removed in 0.2; "
                "use frame_size=(height, width).",
                FutureWarning,
                stacklevel=external_stacklevel(),
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
        validate_estimator_params(self)  # select may be called without fit
        self._warn_output_size()
        selection = self._run(X, extract=False)[1]
        self._check_contacts(selection.status)
        return selection

    def _run(self, X, extract):
        """Select (and with ``extract``, cut out) the frames of every video.

        Each video is loaded, validated and scanned once: with a lazy sequence,
        loading (decoding or rendering) is the expensive part. Extracted frames
        go straight into one preallocated array, whose shape the first video
        fixes. Returns ``(frames or None, selection)``.
        """
        self._check_sizes()
        frame_size = self._resolved_frame_size()
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
            frames = self._extract(video, results[i][0], name, frame_size)
            if out is None:
                return frames
            if frames.shape != out.shape[1:]:
                raise ValueError(
                    f"Videos have different frame sizes (X[0]: {out.shape[2:4]}, {name}: "
                    f"{frames.shape[1:3]}); set frame_size=(height, width) to resize them."
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
        selection = _selection(
            indices=np.stack([r[0] for r in results]),
            contact_start=np.array([r[1] for r in results], dtype=int),
            contact_peak=np.array([r[2] for r in results], dtype=int),
            threshold=np.array([r[3] for r in results], dtype=float),
            status=status.astype(str),
            curves=[r[5] for r in results],
        )
        return out, selection

    def _check_contacts(self, status):
        """Warn (or, with ``on_no_contact="raise"``, raise) about the presses without contact, by index."""
        status = np.asarray(status)
        n = len(status)
        problems = []
        for what, outcome in [("never reach contact", "no contact"), ("are too short to detect contact "
                              f"(fewer than {_min_frames_auto(self.n_baseline)} frames)", "too short")]:
            idx = np.flatnonzero(status == outcome)
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
                stacklevel=external_stacklevel(),
            )

    def _extract(self, video, indices, name, frame_size):
        """The selected frames of one validated video, scaled, cropped, converted, resized."""
        # a float video's range was checked whole by _select_one (_curves) before this
        rows, cols = roi_slices(video.shape[1:3], self.roi, name)
        if self.crop_contact is not None:
            rows, cols = _contact_window(video, indices, rows, cols, self.crop_contact, name)
        frames = as_float255(video[indices][:, rows, cols], name)
        if self.subtract_first:
            frames -= as_float255(video[:1, rows, cols], name)
        frames /= 255.0
        if self.color == "gray" and frames.shape[-1] == 3:
            frames = frames @ np.array([0.299, 0.587, 0.114], dtype=np.float32)
            frames = frames[..., np.newaxis]
        elif self.color == "rgb" and frames.shape[-1] == 1:
            frames = np.repeat(frames, 3, axis=-1)
        if frame_size is not None:
            h, w = frame_size
            if frames.shape[1:3] != (h, w):
                resized = [cv2.resize(f, (w, h), interpolation=cv2.INTER_AREA) for f in frames]
                frames = np.stack([r if r.ndim == 3 else r[..., np.newaxis] for r in resized])
        return np.ascontiguousarray(frames, dtype=np.float32)

    # ------------------------------------------------------------- estimator
    @fit_context(prefer_skip_nested_validation=True)
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

    @fit_context(prefer_skip_nested_validation=True)
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
        self._warn_output_size()
        self._check_sizes()
        check_video_sequence(X)
        out, info = transform_presses(self, X)
        self.selection_ = _selection(**info)
        self._press_info = info
        self._check_contacts(info["status"])
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
        return self._transform_and_info(X)[0]

    def _transform_and_info(self, X):
        check_is_fitted(self, "selection_")
        self._check_sizes()
        check_video_sequence(X)
        out, info = transform_presses(self, X)
        self._check_contacts(info["status"])
        if tuple(out.shape[2:]) != self.frame_shape_:
            raise ValueError(
                f"X gives frames of shape {tuple(out.shape[2:])} but the videos seen in fit gave "
                f"{self.frame_shape_}; set frame_size to make them equal."
            )
        return out, info

    def _transform_presses(self, X):
        out, selection = self._run(X, extract=True)
        info = {key: selection[key] for key in _PRESS_INFO}
        return out, info

    def _press_note(self, info, users):
        """How many presses the selection found contact on (the folds' warnings say it per fold)."""
        status = np.asarray(info["status"])
        n, count = len(status), Counter(status.tolist())  # 0 for a status not found
        found = count["contact"] + count["weak contact"]
        text = f"contact ({', '.join(users)}): found on {found} of {n} presses ({count['weak contact']} weak)"
        missing = [f"{what} {count[what]}" for what in ("no contact", "too short") if count[what]]
        if missing:
            text += (f"; {', '.join(missing)}: their frames are spread from the first frame to the frame of "
                     "largest change (`sklearn-hardness select` lists them)")
        return text

    def __sklearn_tags__(self):
        return videos_tags(super().__sklearn_tags__())


#: What the selection keeps of each press, beside its frames (``selection_`` less ``contact_found``).
_PRESS_INFO = ("indices", "contact_start", "contact_peak", "threshold", "status", "curves")


def _selection(indices, contact_start, contact_peak, threshold, status, curves):
    """The ``selection_`` Bunch of the presses' selections, one entry per press in each field."""
    status = np.asarray(status).astype(str)
    return Bunch(
        indices=np.stack(list(indices)) if len(indices) else np.empty((0, 0), dtype=int),
        contact_start=np.asarray(contact_start, dtype=int),
        contact_peak=np.asarray(contact_peak, dtype=int),
        threshold=np.asarray(threshold, dtype=float),
        contact_found=np.isin(status, ["contact", "weak contact"]),
        status=status,
        curves=list(curves),
    )
