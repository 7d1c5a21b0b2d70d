"""Lucas-Kanade optical-flow features of selected press frames (the paper's OFNN input)."""

from __future__ import annotations

import warnings
from numbers import Integral, Real

import cv2
import numpy as np
from joblib import Parallel, delayed
from sklearn.base import BaseEstimator, TransformerMixin
from sklearn.utils import Bunch
from sklearn.utils.validation import check_is_fitted

from ..utils._param_validation import HasMethods, Interval, Pair, StrOptions, ValueRange, fit_context
from ..utils._per_press import PerPressTransformerMixin, transform_presses
from ..utils._tags import frames_tags
from ..utils._validation import check_frames_array
from ..utils._warnings import external_stacklevel
from ._common import to_uint8_grey
from ._lk_tracking import MAGNITUDE_QUANTILES as _MAGNITUDE_QUANTILES
from ._lk_tracking import hold_last as _hold_last
from ._lk_tracking import magnitude_quantiles as _magnitude_quantiles
from ._lk_tracking import track_one as _track_one

__all__ = ["OpticalFlowFeatures"]

_REFERENCES = ("first", "previous")
_FILL_LOST = ("zero", "last")
_OUTPUTS = ("tracks", "magnitude_quantiles")


class OpticalFlowFeatures(PerPressTransformerMixin, TransformerMixin, BaseEstimator):
    """Displacements of Shi-Tomasi corners tracked by pyramidal Lucas-Kanade.

    For every sample (the ``k`` selected frames of one press, as produced by
    :class:`~sklearn_hardness.preprocessing.ContactFrameSelector`), the
    ``n_features`` strongest Shi-Tomasi corners of the first frame
    (:func:`cv2.goodFeaturesToTrack`) are tracked through the following frames
    with pyramidal Lucas-Kanade (:func:`cv2.calcOpticalFlowPyrLK`, frame to
    frame), and their displacements are flattened into one fixed-length
    vector. This is the input of the OFNN model of the paper (Sec. II-B).

    Parameters
    ----------
    n_features : int, default=500
        Number of corners (tracks) per sample. The paper uses the 500
        strongest.
    quality_level : float, default=0.001
        Minimal corner quality relative to the best corner of the frame
        (``qualityLevel`` of :func:`cv2.goodFeaturesToTrack`), in (0, 1].
        The low default lets ``n_features`` decide, i.e. the strongest
        ``n_features`` corners are kept even where strong features such as
        the markers of a GelSight gel dominate (on GelSight-like 240x320
        frames 0.01 leaves only the marker corners).
    min_distance : float, default=5.0
        Minimal distance in pixels between two corners.
    block_size : int, default=7
        Size of the neighbourhood used to compute the corner quality.
    win_size : tuple of int (width, height), default=(15, 15)
        Lucas-Kanade search window at each pyramid level.
    max_level : int, default=2
        Number of pyramid levels above the original image (0: no pyramid).
    max_iter : int, default=30
        Iterations of the Lucas-Kanade solver per level.
    epsilon : float, default=0.01
        Stops the Lucas-Kanade iterations when the update is below this (px).
    reference : {"first", "previous"}, default="first"
        ``"first"``: displacement of each tracked corner relative to its
        position in the first frame (cumulative); ``"previous"``: relative to
        the previous frame (increments). Tracking is frame to frame either way.
    include_positions : bool, default=False
        Whether to prepend each corner's start position ``(x0, y0)`` in pixels
        to its displacements.
    include_valid : bool, default=False
        Whether to add, for each corner and frame, a column that is 1.0 where
        the corner was found and tracked and 0.0 where the value is padding.
    fill_lost : {"zero", "last"}, default="zero"
        What a track that is lost (Lucas-Kanade status 0, or the point left the
        image) gives in that and all later frames: ``"zero"`` displacement, or
        the ``"last"`` displacement measured before it was lost (with
        ``reference="previous"``, the increments are zero either way from the
        frame where the track is lost on).
    output : {"tracks", "magnitude_quantiles"}, default="tracks"
        ``"tracks"``: every corner's displacements, flattened in corner order
        (the paper's OFNN input; layout in the Notes). ``"magnitude_quantiles"``:
        per frame ``t = 1 .. k-1``, the median, 75th, 90th and 99th
        percentile, the maximum and the mean of the displacement magnitudes
        of the corners found in the first frame (a lost track counts as
        ``fill_lost`` says), each as ``log(0.01 + pixels)`` (6 values per
        frame). This summary does not depend on
        which corner is which, so it carries over between objects whose
        shape and texture put the corners in different places (see the
        Notes); ``include_positions`` and ``include_valid`` do not apply.
    value_range : None or tuple of float (low, high), default=None
        How frames are turned into the 8-bit grey images OpenCV tracks on.
        RGB frames become grey first (ITU-R BT.601 weights, RGB order). With
        ``None``, each sample is scaled by its own minimum and maximum over all
        its ``k`` frames (one scaling per sample, so brightness changes between
        its frames are kept); this handles raw frames in [0, 1] and
        differences to the first frame in [-1, 1] alike. With ``(low, high)``
        every sample is mapped by the same linear map ``low -> 0, high -> 255``
        (values outside are clipped), e.g. ``(0, 1)`` or ``(-1, 1)``.
    n_jobs : int or None, default=None
        Number of joblib workers over samples (``None``: 1 unless in a
        :func:`joblib.parallel_config` context; ``-1``: all cores). Threads
        are preferred, as OpenCV releases the GIL.
    memory : None, str or object with the joblib.Memory interface, default=None
        Cache each sample's row here (a folder, or a :class:`joblib.Memory`),
        keyed by the parameters that change it and a hash of the sample's
        frames, so that a later fit or transform on the same frames reads it.
        Validated as :func:`sklearn.utils.validation.check_memory` validates
        a :class:`~sklearn.pipeline.Pipeline`'s ``memory``. An entry holds
        the row (``4 n_features_out_`` bytes) and the sample's corner counts.

    Attributes
    ----------
    n_frames_in_ : int
        Number of frames ``k`` per sample seen during :meth:`fit`.
    frame_shape_in_ : tuple of int
        Frame shape ``(H, W, C)`` seen during :meth:`fit`.
    n_features_out_ : int
        Length of the output vector.

    See Also
    --------
    DINOv2Features : Frozen DINOv2 embeddings of the same frames.
    sklearn_hardness.preprocessing.ContactFrameSelector : Produces the input.

    Notes
    -----
    **Output layout.** Corners are ordered by decreasing corner quality
    (minimal eigenvalue of the gradient covariance), ties broken by ``y``
    then ``x`` position, so the order is stable for a given input. The row
    of one sample is the concatenation over corners ``j = 0 .. n_features-1``
    of the block::

        [x0_j, y0_j]                         (if include_positions)
        for t = 1 .. k-1: [dx_jt, dy_jt]     (+ [valid_jt] if include_valid)

    so without options its length is ``n_features * (k - 1) * 2`` and
    ``X_out.reshape(n, n_features, k - 1, 2)`` gives the displacements in
    pixels (x to the right, y down). :meth:`get_feature_names_out` names
    every column (``"c0_t1_dx"``, ...).

    **Magnitude quantiles.** The corners of one sample are ordered by
    quality, and on a marker-less gel what makes a strong corner is the
    object's shape and texture: column ``j`` of one press and of another
    object's press then hold unrelated points, and a classifier on the
    flattened tracks learns the objects it was trained on. The distribution
    of how far the corners moved does not depend on that order.
    Object-disjoint on the ``everyday`` preset an OFNN on this summary ranks
    unseen objects above one on the tracks (evidence:
    ``studies/pages/net_inputs.md``).

    **Which frames.** Corners are found in the first selected frame. With
    ``ContactFrameSelector(subtract_first=True)`` the frames are differences
    to the pre-contact frame, so the corners come from what has changed by
    the start of contact; to track the gel's markers themselves, select raw
    frames (``subtract_first=False``).

    **Padding.** Nothing is ever NaN. If a sample has fewer than
    ``n_features`` corners (small or smooth frames, or a flat sample where
    all frames are constant: no corners at all), the missing corners are
    padded with zeros (position and displacements, ``valid = 0``). Lost
    tracks follow ``fill_lost``. A :class:`UserWarning` gives the number of
    samples padded and of lost tracks. :meth:`track` returns the raw tracks
    with a validity mask for closer inspection.

    Examples
    --------
    >>> import numpy as np
    >>> from sklearn_hardness.features import OpticalFlowFeatures
    >>> rng = np.random.default_rng(0)
    >>> texture = rng.random((40, 48)).astype(np.float32)
    >>> frames = np.stack([np.roll(texture, s, axis=1) for s in range(3)])  # moves right
    >>> X = frames[np.newaxis, ..., np.newaxis]          # (1 sample, 3 frames, 40, 48, 1)
    >>> of = OpticalFlowFeatures(n_features=20, min_distance=3).fit(X)
    >>> Xt = of.transform(X)
    >>> Xt.shape
    (1, 80)
    >>> dx = Xt.reshape(1, 20, 2, 2)[0, :, -1, 0]        # x-displacement at the last frame
    >>> float(np.round(np.median(dx), 1))
    2.0
    """

    _per_press_input = "frames"

    _parameter_constraints: dict = {
        "n_features": [Interval(Integral, 1, None, closed="left")],
        "quality_level": [Interval(Real, 0, 1, closed="right")],
        "min_distance": [Interval(Real, 0, None, closed="left")],
        "block_size": [Interval(Integral, 1, None, closed="left")],
        "win_size": [Pair(Interval(Integral, 3, None, closed="left"), "(width, height)")],
        "max_level": [Interval(Integral, 0, None, closed="left")],
        "max_iter": [Interval(Integral, 1, None, closed="left")],
        "epsilon": [Interval(Real, 0, None, closed="neither")],
        "reference": [StrOptions(set(_REFERENCES))],
        "include_positions": ["boolean"],
        "include_valid": ["boolean"],
        "fill_lost": [StrOptions(set(_FILL_LOST))],
        "output": [StrOptions(set(_OUTPUTS))],
        "value_range": [None, ValueRange()],
        "n_jobs": [Integral, None],
        "memory": [None, str, HasMethods(["cache"])],
    }

    def __init__(
        self,
        n_features=500,
        *,
        quality_level=0.001,
        min_distance=5.0,
        block_size=7,
        win_size=(15, 15),
        max_level=2,
        max_iter=30,
        epsilon=0.01,
        reference="first",
        include_positions=False,
        include_valid=False,
        fill_lost="zero",
        output="tracks",
        value_range=None,
        n_jobs=None,
        memory=None,
    ):
        self.n_features = n_features
        self.quality_level = quality_level
        self.min_distance = min_distance
        self.block_size = block_size
        self.win_size = win_size
        self.max_level = max_level
        self.max_iter = max_iter
        self.epsilon = epsilon
        self.reference = reference
        self.include_positions = include_positions
        self.include_valid = include_valid
        self.fill_lost = fill_lost
        self.output = output
        self.value_range = value_range
        self.n_jobs = n_jobs
        self.memory = memory

    # --------------------------------------------------------------- sklearn API
    @fit_context(prefer_skip_nested_validation=True)
    def fit(self, X, y=None):
        """Check the parameters and remember the number and shape of frames.

        Parameters
        ----------
        X : array-like of shape (n_samples, k, H, W, C)
            Selected frames, ``k >= 2``, ``C`` in {1, 3}.
        y : None
            Ignored.

        Returns
        -------
        self : OpticalFlowFeatures
        """
        X = _check_X(X)
        if self.output == "magnitude_quantiles" and (self.include_positions or self.include_valid):
            raise ValueError(
                "include_positions and include_valid describe single corners and do not apply to "
                "output='magnitude_quantiles'; set them to False or use output='tracks'."
            )
        self.n_frames_in_ = int(X.shape[1])
        self.frame_shape_in_ = tuple(int(s) for s in X.shape[2:])
        self.n_features_out_ = self._row_length(self.n_frames_in_)
        return self

    def track(self, X):
        """Detect and track the corners of each sample.

        Parameters
        ----------
        X : array-like of shape (n_samples, k, H, W, C)
            Selected frames with the ``k`` and frame shape seen in :meth:`fit`.

        Returns
        -------
        tracks : :class:`~sklearn.utils.Bunch`
            ``points`` (n_samples, n_features, k, 2) float32 ``(x, y)`` pixel
            positions, zero where ``valid`` is False; ``valid`` (n_samples,
            n_features, k) bool, True where the corner exists and was tracked
            up to that frame; ``quality`` (n_samples, n_features) float32
            corner quality (0 for padding); ``n_corners`` (n_samples,) int,
            corners found in the first frame; ``n_lost`` (n_samples,) int, of
            those, the tracks lost before the last frame.
        """
        check_is_fitted(self)
        X = _check_X(X, n_frames=self.n_frames_in_, frame_shape=self.frame_shape_in_)
        grey = to_uint8_grey(X, self.value_range)
        kwargs = dict(
            n_features=int(self.n_features),
            quality_level=float(self.quality_level),
            min_distance=float(self.min_distance),
            block_size=int(self.block_size),
            win_size=tuple(int(v) for v in self.win_size),
            max_level=int(self.max_level),
            criteria=(cv2.TERM_CRITERIA_EPS | cv2.TERM_CRITERIA_COUNT, int(self.max_iter), float(self.epsilon)),
        )
        if self.n_jobs is None or self.n_jobs == 1:
            results = [_track_one(g, **kwargs) for g in grey]
        else:
            # OpenCV releases the GIL: threads parallelise without copying frames
            # (a joblib.parallel_config backend overrides this preference).
            results = Parallel(n_jobs=self.n_jobs, prefer="threads")(
                delayed(_track_one)(g, **kwargs) for g in grey
            )
        points, valid, quality, n_corners = zip(*results)
        valid = np.stack(valid)
        return Bunch(
            points=np.stack(points),
            valid=valid,
            quality=np.stack(quality),
            n_corners=np.asarray(n_corners, dtype=np.intp),
            n_lost=np.sum(valid[:, :, 0] & ~valid[:, :, -1], axis=1),
        )

    def transform(self, X):
        """Compute the flattened displacement vector of each sample.

        Parameters
        ----------
        X : array-like of shape (n_samples, k, H, W, C)
            Selected frames with the ``k`` and frame shape seen in :meth:`fit`.

        Returns
        -------
        X_out : ndarray of shape (n_samples, n_features_out_), float32
            See the Notes of the class for the layout. Never NaN.

        Warns
        -----
        UserWarning
            If some samples have fewer corners than ``n_features`` (padded
            with zeros) or tracks were lost.
        """
        return self._transform_and_info(X)[0]

    def _transform_and_info(self, X):
        check_is_fitted(self)
        X = _check_X(X, n_frames=self.n_frames_in_, frame_shape=self.frame_shape_in_)
        out, info = transform_presses(self, X)
        self._warn_tracks(info["n_corners"], info["n_lost"])
        return out, info

    def _transform_presses(self, X):
        tracks = self.track(X)
        return self._rows_of(tracks), {"n_corners": tracks.n_corners, "n_lost": tracks.n_lost}

    def _rows_of(self, tr):
        """:meth:`transform`'s rows from :meth:`track`'s result ``tr``."""
        n, m, k = tr.valid.shape
        points, valid = tr.points, tr.valid
        # Displacement relative to the first frame, zeros where not valid.
        disp = np.where(valid[..., None], points - points[:, :, :1], 0.0).astype(np.float32)
        if self.fill_lost == "last":
            disp = _hold_last(disp, valid)
        if self.reference == "previous":
            disp = np.diff(disp, axis=2, prepend=disp[:, :, :1])
            # Zero the increments after differencing: with fill_lost="zero" the cumulative
            # displacement drops to 0 where a track is lost, and its difference would be a
            # fake jump back by the whole travel. Where valid, nothing changes (a track is
            # valid in every frame before one where it is valid).
            disp = np.where(valid[..., None], disp, np.float32(0.0))
        if self.output == "magnitude_quantiles":
            return _magnitude_quantiles(disp[:, :, 1:], valid[:, :, 0])
        blocks = []
        if self.include_positions:
            blocks.append(points[:, :, 0, :])  # zero for padded corners
        steps = disp[:, :, 1:, :]
        if self.include_valid:
            steps = np.concatenate([steps, valid[:, :, 1:, None].astype(np.float32)], axis=-1)
        blocks.append(steps.reshape(n, m, -1))
        return np.concatenate(blocks, axis=-1).reshape(n, -1).astype(np.float32, copy=False)

    def _warn_tracks(self, n_corners, n_lost):
        """Warn about the padded samples and lost tracks (corners found and tracks lost per sample)."""
        n_corners, n_lost = np.asarray(n_corners), np.asarray(n_lost)
        n, m = len(n_corners), int(self.n_features)
        n_padded = int(np.sum(n_corners < m))
        lost = int(n_lost.sum())
        tracks = self.output == "tracks"
        if n_padded or lost:
            parts = []
            if n_padded:
                parts.append(
                    f"{n_padded} of {n} sample(s) had fewer than n_features={m} corners "
                    f"(fewest: {int(n_corners.min())}); "
                    + ("the missing corners are padded with zeros" if tracks
                       else "the quantiles are taken over the corners found")
                )
            if lost:
                parts.append(
                    f"{lost} of {int(n_corners.sum())} track(s) were lost before the last frame; "
                    f"fill_lost={self.fill_lost!r} applies"
                )
            warnings.warn(
                "OpticalFlowFeatures: " + "; ".join(parts)
                + (". Use include_valid=True to give the mask to the classifier." if tracks
                   else ". The magnitude quantiles use the corners found in the first frame."),
                UserWarning,
                stacklevel=external_stacklevel(),
            )

    def _press_note(self, info, users):
        """Corners per press, presses without any, tracks lost (the folds' warnings say it per fold)."""
        corners, lost = np.asarray(info["n_corners"]), np.asarray(info["n_lost"])
        text = (f"optical flow ({', '.join(users)}): corners in a press's first frame {int(np.median(corners))} "
                f"(median; fewest {int(corners.min())}, most {int(corners.max())}, at most "
                f"n_features={int(self.n_features)})")
        none = int(np.sum(corners == 0))
        if none:
            text += f"; none on {none} of {len(corners)} presses: their rows are those of a press without motion"
        if corners.sum():
            text += (f"; {lost.sum() / corners.sum():.0%} of the tracks lost before the last frame "
                     f"(on {int(np.sum(lost > 0))} of {len(corners)} presses)")
        return text

    def get_feature_names_out(self, input_features=None):
        """Names of the output columns, e.g. ``"c0_t1_dx"``.

        Parameters
        ----------
        input_features : None
            Ignored (the input is not tabular).

        Returns
        -------
        names : ndarray of str of shape (n_features_out_,)
        """
        check_is_fitted(self)
        names = []
        if self.output == "magnitude_quantiles":
            stats = [_quantile_name(q) for q in _MAGNITUDE_QUANTILES] + ["mean"]
            return np.asarray([f"t{t}_mag_{s}" for t in range(1, self.n_frames_in_) for s in stats], dtype=object)
        for j in range(self.n_features):
            if self.include_positions:
                names += [f"c{j}_x0", f"c{j}_y0"]
            for t in range(1, self.n_frames_in_):
                names += [f"c{j}_t{t}_dx", f"c{j}_t{t}_dy"]
                if self.include_valid:
                    names.append(f"c{j}_t{t}_valid")
        return np.asarray(names, dtype=object)

    def __sklearn_tags__(self):
        tags = frames_tags(super().__sklearn_tags__())
        return tags

    def _row_length(self, k):
        if self.output == "magnitude_quantiles":
            return (k - 1) * (len(_MAGNITUDE_QUANTILES) + 1)
        per_corner = 2 * int(self.include_positions) + (k - 1) * (2 + int(self.include_valid))
        return int(self.n_features) * per_corner


def _quantile_name(q):
    return "max" if q == 1.0 else f"q{int(round(100 * q))}"


def _check_X(X, n_frames=None, frame_shape=None):
    X = check_frames_array(X, name="X", n_frames=n_frames, frame_shape=frame_shape)
    if X.shape[1] < 2:
        raise ValueError(
            f"OpticalFlowFeatures needs at least 2 frames per sample to measure motion; "
            f"X has shape {X.shape}."
        )
    return X
