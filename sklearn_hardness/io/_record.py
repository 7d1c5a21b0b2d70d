"""Recording presses from a tactile camera (GelSight Mini, DIGIT, any UVC camera) with OpenCV."""

from __future__ import annotations

import numbers
import os
import warnings
from pathlib import Path

import cv2
import numpy as np

from ..utils._param_validation import FRAME_SIZE, HasMethods, Interval, validate_params
from ..utils._warnings import external_stacklevel
from ._video import _to_rgb, write_video

__all__ = ["record_video"]


def _open_capture(source):
    """An opened ``cv2.VideoCapture`` for a device index, a file or a URL, or a clear error."""
    if isinstance(source, numbers.Integral):
        cap = cv2.VideoCapture(int(source))
        what = (
            f"camera {int(source)} (device index; on Linux /dev/video{int(source)}). Check that the "
            "sensor is plugged in, not open in another program, and that you may read it"
        )
    else:
        source = os.fspath(source)
        if "://" not in source and not Path(source).exists():
            raise FileNotFoundError(f"Capture source not found: '{source}' (not a file, and not a URL).")
        cap = cv2.VideoCapture(source)
        what = f"'{source}': OpenCV cannot decode it (unsupported codec, corrupt file or unreachable URL)"
    if not cap.isOpened():
        cap.release()
        raise OSError(f"Could not open capture source {what}.")
    return cap


@validate_params(
    {
        "source": [Interval(numbers.Integral, 0, None, closed="left"), str, os.PathLike,
                   HasMethods(["read", "isOpened"])],
        "n_frames": [Interval(numbers.Integral, 1, None, closed="left"), None],
        "duration": [Interval(numbers.Real, 0, None, closed="neither"), None],
        "fps": [Interval(numbers.Real, 0, None, closed="neither"), None],
        "image_size": [tuple, list, None],
        "path": [str, os.PathLike, None],
        "warmup": [Interval(numbers.Integral, 0, None, closed="left")],
    },
    prefer_skip_nested_validation=True,
)
def record_video(source, *, n_frames=None, duration=None, fps=None, image_size=None, path=None, warmup=0):
    """Record one press from a camera, a video file or a stream URL.

    Frames are read with OpenCV's :class:`cv2.VideoCapture`, converted to
    RGB and, with ``path``, written with :func:`write_video`.

    Parameters
    ----------
    source : int, str, path-like or capture object
        A camera's device index (``0`` is the first camera; a GelSight Mini
        is a UVC camera), a video file, a stream URL (``rtsp://...``), or an
        opened capture object with ``read()`` and ``isOpened()`` (a
        :class:`cv2.VideoCapture` you keep open between presses, or a
        :class:`~sklearn_hardness.datasets.SimulatedSensor`); such an object
        is read from and left open.
    n_frames : int or None, default=None
        Frames to record. Give this or ``duration``.
    duration : float or None, default=None
        Seconds to record: ``round(duration * fps)`` frames.
    fps : float or None, default=None
        Frame rate asked of the camera and stored in the written file.
        ``None`` uses the rate the source reports (25 if it reports none).
        Cameras may ignore the request.
    image_size : (height, width) or None, default=None
        Frame size asked of the camera; frames that arrive in another size
        are resized to it (``cv2.INTER_AREA``). ``None`` keeps the source's
        size (GelSight Mini streams 240x320). The same name as the size of
        :func:`~sklearn_hardness.datasets.make_presses`'s frames.
    path : str, path-like or None, default=None
        Also write the frames here (any format :func:`write_video` writes;
        ``.avi`` is lossless).
    warmup : int, default=0
        Frames read and dropped first, while the camera's exposure settles.

    Returns
    -------
    frames : ndarray of shape (T, H, W, 3), dtype uint8
        The recorded frames, RGB. ``T`` is ``n_frames`` unless the source
        ended first (a file), which gives a warning.

    Raises
    ------
    FileNotFoundError
        If ``source`` is a path that does not exist.
    OSError
        If the camera, file or URL cannot be opened.
    ValueError
        If neither or both of ``n_frames`` and ``duration`` are given, if
        ``image_size`` is malformed, or if the source gives no frame at all.

    See Also
    --------
    read_video, write_video

    Examples
    --------
    A video file stands in for the camera here:

    >>> import numpy as np, tempfile, os
    >>> from sklearn_hardness.io import record_video, write_video
    >>> source = os.path.join(tempfile.mkdtemp(), "camera.avi")
    >>> write_video(source, np.full((10, 24, 32, 3), 120, np.uint8))
    >>> record_video(source, n_frames=6, image_size=(12, 16)).shape
    (6, 12, 16, 3)
    """
    if (n_frames is None) == (duration is None):
        raise ValueError("Pass exactly one of n_frames and duration (how long to record).")
    if image_size is not None and not FRAME_SIZE.is_satisfied_by(image_size):
        raise ValueError(f"image_size must be None or (height, width) with ints >= 2, got {image_size!r}.")
    owned = not hasattr(source, "read")
    cap = _open_capture(source) if owned else source
    if not owned and not cap.isOpened():
        raise OSError(f"The capture object {source!r} is not opened.")
    try:
        if fps is not None:
            cap.set(cv2.CAP_PROP_FPS, float(fps))
        if image_size is not None:
            cap.set(cv2.CAP_PROP_FRAME_HEIGHT, int(image_size[0]))
            cap.set(cv2.CAP_PROP_FRAME_WIDTH, int(image_size[1]))
        rate = float(fps) if fps is not None else (cap.get(cv2.CAP_PROP_FPS) or 25.0)
        n = int(n_frames) if n_frames is not None else max(1, int(round(duration * rate)))
        for _ in range(warmup):
            if not cap.read()[0]:
                break
        frames = []
        while len(frames) < n:
            ok, frame = cap.read()
            if not ok:
                break
            frame = _to_rgb(frame, source)
            if image_size is not None and frame.shape[:2] != tuple(image_size):
                frame = cv2.resize(frame, (int(image_size[1]), int(image_size[0])), interpolation=cv2.INTER_AREA)
            frames.append(frame)
    finally:
        if owned:
            cap.release()
    if not frames:
        raise ValueError(f"Capture source {source!r} gave no frames (after {warmup} warm-up frames).")
    if len(frames) < n:
        warnings.warn(
            f"Capture source {source!r} ended after {len(frames)} of {n} frames; returning those.",
            UserWarning,
            stacklevel=external_stacklevel(),
        )
    video = np.stack(frames)
    if path is not None:
        write_video(path, video, fps=rate)
    return video
