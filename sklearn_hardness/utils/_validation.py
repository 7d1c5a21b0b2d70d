"""Data validation for press videos and selected-frame arrays.

Every public estimator validates its *data* through these helpers so that bad
input gets the same clear message everywhere: what is wrong, and with which
video (by index). Parameters are validated by scikit-learn's machinery
(``_parameter_constraints`` and ``validate_params``), not here.
"""

from __future__ import annotations

import numbers
import re

import numpy as np

__all__ = ["check_video", "check_video_sequence", "check_frames_array", "check_roi", "roi_slices",
           "check_force_position", "names_a_video", "rename_videos"]

#: How these helpers name a video in their messages: by its index in the sequence given, ``X[i]``.
_VIDEO_NAME = re.compile(r"\bX\[(\d+)\]")


def names_a_video(message):
    """Whether ``message`` names a video the way these helpers do (``X[i]``)."""
    return _VIDEO_NAME.search(message) is not None


def rename_videos(message, name):
    """``message`` with each ``X[i]`` replaced by ``name(i)``.

    The helpers name a video by its index in the sequence they were given;
    where that sequence was a chunk or one press of a dataset, ``name`` says
    which press of the dataset it is (and its file).
    """
    return _VIDEO_NAME.sub(lambda m: name(int(m.group(1))), message)


def check_video(video, *, name="video", min_frames=1, allow_float=True):
    """Validate one press video and return it as a (T, H, W, C) array.

    Parameters
    ----------
    video : array-like of shape (T, H, W, C) or (T, H, W)
        Frames of one press. Grey-scale videos of shape (T, H, W) get a
        trailing channel axis of size 1. ``C`` must be 1 or 3.
    name : str, default="video"
        How the video is called in error messages (e.g. ``"X[3]"``).
    min_frames : int, default=1
        Fewest frames accepted.
    allow_float : bool, default=True
        Whether floating point frames are accepted. Integer frames must be
        ``uint8`` or ``uint16``; float frames must be finite.

    Returns
    -------
    video : ndarray of shape (T, H, W, C)
        The validated video, not copied where possible.

    Raises
    ------
    TypeError
        If the video is not numeric or has an unsupported dtype.
    ValueError
        If the shape is wrong, there are too few frames, or frames contain
        NaN or infinite values.

    Examples
    --------
    >>> import numpy as np
    >>> from sklearn_hardness.utils._validation import check_video
    >>> check_video(np.zeros((4, 8, 8), dtype=np.uint8)).shape
    (4, 8, 8, 1)
    """
    if isinstance(video, (str, bytes)) or video is None:
        raise TypeError(
            f"{name} must be an array of frames (T, H, W, C), got {type(video).__name__}; "
            "read files with sklearn_hardness.io.read_video first."
        )
    if hasattr(video, "tocsr") or hasattr(video, "toarray"):
        raise TypeError(f"{name}: sparse input is not supported; pass dense frames.")
    arr = np.asarray(video)
    if np.iscomplexobj(arr):
        raise ValueError(f"{name}: Complex data not supported; frames must be real.")
    if arr.dtype == object or not (
        np.issubdtype(arr.dtype, np.integer)
        or np.issubdtype(arr.dtype, np.floating)
    ):
        raise TypeError(
            f"{name} must have a numeric dtype (uint8, uint16 or float), got {arr.dtype}."
        )
    if np.issubdtype(arr.dtype, np.integer) and arr.dtype not in (np.uint8, np.uint16):
        if arr.size and (arr.min() < 0 or arr.max() > 255):
            raise TypeError(
                f"{name} has integer dtype {arr.dtype} with values outside [0, 255]; "
                "pass uint8 frames or scale them to floats."
            )
        arr = arr.astype(np.uint8)
    if np.issubdtype(arr.dtype, np.floating) and not allow_float:
        raise TypeError(f"{name} must be uint8, got {arr.dtype}.")
    if arr.ndim == 3:
        arr = arr[..., np.newaxis]
    if arr.ndim != 4:
        raise ValueError(
            f"{name} must have shape (T, H, W, C) or (T, H, W), got an array with "
            f"{arr.ndim} dimension(s) and shape {arr.shape}."
        )
    if arr.shape[-1] not in (1, 3):
        raise ValueError(
            f"{name} must have 1 or 3 colour channels in its last axis, got shape {arr.shape}."
        )
    if arr.shape[1] < 2 or arr.shape[2] < 2:
        raise ValueError(f"{name} has frames of size {arr.shape[1]}x{arr.shape[2]}; need at least 2x2.")
    if arr.shape[0] < min_frames:
        raise ValueError(
            f"{name} has {arr.shape[0]} frame(s); at least {min_frames} are needed."
        )
    if np.issubdtype(arr.dtype, np.floating) and not np.isfinite(arr).all():
        bad = np.unique(np.nonzero(~np.isfinite(arr.reshape(arr.shape[0], -1)))[0])
        raise ValueError(
            f"{name} contains NaN or infinite values in frame(s) {bad[:10].tolist()}"
            f"{' ...' if bad.size > 10 else ''}."
        )
    return arr


def check_video_sequence(X, *, name="X"):
    """Check that ``X`` is a sequence of videos and return it unchanged.

    ``X`` may be a list or tuple of arrays, a lazy sequence (anything with
    ``__len__`` and integer ``__getitem__``, such as the ``videos`` of
    :func:`sklearn_hardness.datasets.load_press_videos`), or a 5-D array
    (n, T, H, W, C) of equal-length videos. Individual videos are validated
    lazily by :func:`check_video` when they are used.

    Parameters
    ----------
    X : sequence of array-like
        The videos.
    name : str, default="X"
        How the input is called in error messages.

    Returns
    -------
    X : sequence
        The same object.

    Raises
    ------
    TypeError
        If ``X`` is not a sequence of videos.
    ValueError
        If ``X`` is empty, or a 4-D array (ambiguous: one video or many
        grey-scale ones).
    """
    if isinstance(X, (str, bytes)) or X is None:
        raise TypeError(f"{name} must be a sequence of videos, got {type(X).__name__}.")
    if hasattr(X, "tocsr") or hasattr(X, "toarray"):
        raise TypeError(f"{name}: sparse input is not supported; pass a sequence of videos.")
    if np.iscomplexobj(X) if isinstance(X, np.ndarray) else False:
        raise ValueError(f"{name}: Complex data not supported; frames must be real.")
    if isinstance(X, np.ndarray):
        if X.dtype != object and X.ndim != 5:
            raise ValueError(
                f"{name} must be a sequence of videos: a list of (T, H, W, C) arrays or a "
                f"5-D array (n, T, H, W, C); got an array of shape {X.shape}. "
                "For a single video, pass [video]."
            )
    elif not (hasattr(X, "__len__") and hasattr(X, "__getitem__")):
        raise TypeError(
            f"{name} must be a sequence of videos supporting len() and indexing, "
            f"got {type(X).__name__}."
        )
    if len(X) == 0:
        raise ValueError(f"{name} contains no videos.")
    return X


def check_frames_array(X, *, name="X", n_frames=None, frame_shape=None, dtype=np.float32):
    """Validate selected frames of shape (n, k, H, W, C).

    This is the input of the feature transformers and classifiers, i.e. the
    output of :class:`~sklearn_hardness.preprocessing.ContactFrameSelector`.

    Parameters
    ----------
    X : array-like of shape (n, k, H, W, C)
        Selected frames.
    name : str, default="X"
        How the input is called in error messages.
    n_frames : int or None, default=None
        If given, the number of frames ``k`` each sample must have (e.g. as
        seen during ``fit``).
    frame_shape : tuple of int or None, default=None
        If given, the required (H, W, C).
    dtype : numpy dtype, default=np.float32
        Output dtype.

    Returns
    -------
    X : ndarray of shape (n, k, H, W, C)

    Raises
    ------
    TypeError
        If ``X`` is not numeric.
    ValueError
        If the shape differs from what is required or values are not finite.
    """
    arr = np.asarray(X)
    if arr.dtype == object or not (
        np.issubdtype(arr.dtype, np.number) or arr.dtype == bool
    ):
        raise TypeError(f"{name} must be a numeric array of selected frames, got dtype {arr.dtype}.")
    if arr.ndim != 5:
        raise ValueError(
            f"{name} must have shape (n_samples, n_frames, height, width, channels) as produced "
            f"by ContactFrameSelector; got {arr.ndim} dimension(s) with shape {arr.shape}."
        )
    if arr.shape[0] == 0:
        raise ValueError(f"{name} contains no samples (shape {arr.shape}).")
    if 0 in arr.shape[1:]:
        raise ValueError(
            f"{name} has empty samples (shape {arr.shape}): each needs at least one frame of at least "
            "one pixel and channel."
        )
    if n_frames is not None and arr.shape[1] != n_frames:
        raise ValueError(
            f"{name} has {arr.shape[1]} frames per sample but {n_frames} were seen during fit."
        )
    if frame_shape is not None and tuple(arr.shape[2:]) != tuple(frame_shape):
        raise ValueError(
            f"{name} has frames of shape {tuple(arr.shape[2:])} but {tuple(frame_shape)} were "
            "seen during fit."
        )
    arr = arr.astype(dtype, copy=False)
    if np.issubdtype(arr.dtype, np.floating):
        # one sample at a time: a whole-array isfinite would allocate a mask as large as X
        bad = [i for i in range(arr.shape[0]) if not np.isfinite(arr[i]).all()]
        if bad:
            raise ValueError(f"{name} contains NaN or infinite values in sample(s) {bad[:10]}.")
    return arr


def check_positive_int(value, name, *, minimum=1):
    """Check that ``value`` is an integer >= ``minimum`` and return it as int.

    Deprecated for parameters: declare ``Interval(Integral, minimum, None,
    closed="left")`` in ``_parameter_constraints`` instead. Kept only while
    ``models/`` still imports it.
    """
    if isinstance(value, bool) or not isinstance(value, numbers.Integral):
        raise TypeError(f"{name} must be an integer, got {value!r}.")
    if value < minimum:
        raise ValueError(f"{name} must be >= {minimum}, got {value}.")
    return int(value)


def check_roi(roi):
    """Check a region of interest and return it as a tuple of four floats, or None.

    ``roi`` is ``(top, bottom, left, right)``: fractions of the frame's height
    and width in [0, 1], ``top < bottom`` and ``left < right``. The one check
    of every ``roi`` parameter (:class:`~sklearn_hardness.preprocessing.ContactFrameSelector`,
    :class:`~sklearn_hardness.features.ContactProfileFeatures`,
    :func:`~sklearn_hardness.models.peak_contact_change`, ...), so a bad
    region gets the same message everywhere.
    """
    if roi is None:
        return None
    values = tuple(roi) if isinstance(roi, (tuple, list, np.ndarray)) else ()
    if (len(values) != 4
            or not all(isinstance(v, numbers.Real) and not isinstance(v, bool) and 0 <= v <= 1 for v in values)
            or not (values[0] < values[1] and values[2] < values[3])):
        raise ValueError("roi must be None or (top, bottom, left, right) fractions in [0, 1] with "
                         f"top < bottom and left < right, got {roi!r}.")
    return tuple(float(v) for v in values)


def roi_slices(shape, roi, name):
    """Row and column slices of a checked ``roi`` in frames of ``shape`` (height, width).

    ``None`` gives the whole frame. A region smaller than 2x2 pixels raises a
    ``ValueError`` that names ``name`` (the video).
    """
    if roi is None:
        return slice(None), slice(None)
    h, w = shape
    y0, y1, x0, x1 = roi
    rows = slice(int(round(y0 * h)), int(round(y1 * h)))
    cols = slice(int(round(x0 * w)), int(round(x1 * w)))
    if rows.stop - rows.start < 2 or cols.stop - cols.start < 2:
        raise ValueError(f"roi={roi} leaves fewer than 2x2 pixels of the {h}x{w} frames of {name}.")
    return rows, cols


def check_force_position(X, *, name="X"):
    """Validate presses given as force and position per frame; return a list of (T_i, 2) float arrays.

    Parameters
    ----------
    X : sequence of array-like of shape (T_i, 2), or array of shape (n, T, 2)
        Per press and frame: the force (N) and the position (mm), in that
        order. Lengths may differ between presses.
    name : str, default="X"
        How the input is called in error messages.

    Returns
    -------
    presses : list of ndarray of shape (T_i, 2), float64

    Raises
    ------
    TypeError
        If ``X`` is not a sequence of arrays, or a press is not numeric.
    ValueError
        If ``X`` is empty, or a press is not (T, 2) with ``T >= 1``, or has
        a value that is not finite. The message names the press by index.
    """
    if isinstance(X, (str, bytes)) or X is None or not hasattr(X, "__len__") or hasattr(X, "toarray"):
        raise TypeError(f"{name} must be a sequence of (T, 2) arrays of force (N) and position (mm) per frame, "
                        f"got {type(X).__name__}.")
    if isinstance(X, np.ndarray) and X.dtype != object and X.ndim != 3:
        raise ValueError(f"{name} must be a sequence of (T, 2) arrays of force (N) and position (mm) per frame, "
                         f"or an (n, T, 2) array; got an array of shape {X.shape}. For one press, pass [press].")
    if len(X) == 0:
        raise ValueError(f"{name} holds no presses.")
    presses = []
    for i in range(len(X)):
        press = np.asarray(X[i])
        if press.dtype.kind not in "biuf":
            raise TypeError(f"{name}[{i}] must be numeric (force in N, position in mm), got dtype {press.dtype}.")
        if press.ndim != 2 or press.shape[1] != 2 or press.shape[0] < 1:
            raise ValueError(f"{name}[{i}] must have shape (T, 2): force (N) and position (mm) per frame, "
                             f"with T >= 1; got shape {press.shape}. Build it with "
                             "np.column_stack([force, position]).")
        if not np.isfinite(press).all():
            raise ValueError(f"{name}[{i}] has values that are not finite (NaN or inf) in its force or position.")
        presses.append(press.astype(np.float64))
    return presses
