"""Video reading and writing with OpenCV."""

from __future__ import annotations

import os
import re
from numbers import Integral, Real
from pathlib import Path

import cv2
import numpy as np

from ..utils._param_validation import Interval, validate_params
from ..utils._validation import check_video

__all__ = ["read_video", "write_video", "VIDEO_EXTENSIONS", "IMAGE_EXTENSIONS"]

#: File extensions read as video containers.
VIDEO_EXTENSIONS = (".mp4", ".avi", ".mov", ".mkv", ".m4v")
#: File extensions read as frames when a folder is given.
IMAGE_EXTENSIONS = (".png", ".jpg", ".jpeg", ".bmp", ".tif", ".tiff")

# Codec per container used by write_video. FFV1 is lossless, so .avi and .mkv
# round-trip exactly; mp4v (MPEG-4 Part 2) is lossy but plays everywhere.
_DEFAULT_FOURCC = {".avi": "FFV1", ".mkv": "FFV1", ".mp4": "mp4v", ".mov": "mp4v", ".m4v": "mp4v"}


def _natural_key(name):
    return [int(tok) if tok.isdigit() else tok.lower() for tok in re.split(r"(\d+)", name)]


def _to_rgb(frame, path):
    if frame.ndim == 2:
        return cv2.cvtColor(frame, cv2.COLOR_GRAY2RGB)
    if frame.shape[2] == 4:
        return cv2.cvtColor(frame, cv2.COLOR_BGRA2RGB)
    if frame.shape[2] == 3:
        return cv2.cvtColor(frame, cv2.COLOR_BGR2RGB)
    raise ValueError(f"Unsupported number of channels ({frame.shape[2]}) in '{path}'.")


def _read_image_folder(path, max_frames):
    files = sorted(
        (f for f in os.listdir(path) if f.lower().endswith(IMAGE_EXTENSIONS)), key=_natural_key
    )
    if not files:
        raise ValueError(
            f"Folder '{path}' contains no image files (looked for {', '.join(IMAGE_EXTENSIONS)})."
        )
    if max_frames is not None:
        files = files[:max_frames]
    frames = []
    for f in files:
        img = cv2.imread(str(path / f), cv2.IMREAD_UNCHANGED)
        if img is None:
            raise ValueError(f"Could not decode image '{path / f}'.")
        if img.dtype != np.uint8:
            if img.dtype == np.uint16:
                img = (img >> 8).astype(np.uint8)
            else:
                raise ValueError(f"Image '{path / f}' has unsupported dtype {img.dtype}.")
        img = _to_rgb(img, path / f)
        if frames and img.shape != frames[0].shape:
            raise ValueError(
                f"Image '{path / f}' has shape {img.shape} but the first image of '{path}' has "
                f"{frames[0].shape}; all frames of a video must have the same size."
            )
        frames.append(img)
    return np.stack(frames)


def _read_container(path, max_frames):
    cap = cv2.VideoCapture(str(path))
    try:
        if not cap.isOpened():
            raise ValueError(
                f"Could not open video file '{path}': OpenCV cannot decode it (unsupported codec "
                "or corrupt file)."
            )
        n_hint = int(cap.get(cv2.CAP_PROP_FRAME_COUNT) or 0)
        frames = []
        while max_frames is None or len(frames) < max_frames:
            ok, frame = cap.read()
            if not ok:
                break
            frames.append(_to_rgb(frame, path))
    finally:
        cap.release()
    if not frames:
        raise ValueError(
            f"Video file '{path}' has zero decodable frames"
            + (f" (its header claims {n_hint})." if n_hint else ".")
        )
    # a file cut short (an interrupted recording or copy) decodes as a shorter video; a header's count
    # can be off by a frame or two where it is estimated, so only a larger shortfall is an error
    if max_frames is None and n_hint - len(frames) > max(2, n_hint // 20):
        raise ValueError(
            f"Video file '{path}' decodes {len(frames)} of the {n_hint} frames its header claims: it "
            "looks cut short (an interrupted recording or copy). Record or copy it again, or remove it."
        )
    return np.stack(frames)


@validate_params(
    {
        "path": [str, os.PathLike],
        "max_frames": [Interval(Integral, 1, None, closed="left"), None],
    },
    prefer_skip_nested_validation=True,
)
def read_video(path, *, max_frames=None):
    """Read a press video as a ``(T, H, W, 3)`` ``uint8`` RGB array.

    Parameters
    ----------
    path : str or path-like
        A video file (``.mp4``, ``.avi``, ``.mov``, ``.mkv``, ``.m4v``), a
        ``.npy`` file holding a ``(T, H, W, 3)`` ``uint8`` array (``uint16``
        is converted to ``uint8`` by its high byte, as 16-bit images are), or a folder
        of numbered images (``frame_1.png``, ``frame_2.png``, ...; sorted by
        the numbers in their names, so ``10`` comes after ``9``).
    max_frames : int or None, default=None
        Read at most this many frames from the start.

    Returns
    -------
    frames : ndarray of shape (T, H, W, 3), dtype uint8
        The frames in RGB order (OpenCV's BGR is converted).

    Raises
    ------
    FileNotFoundError
        If ``path`` does not exist.
    ValueError
        If the file cannot be decoded or holds no frames, or if a video
        file decodes fewer frames than its header claims (more than two and
        more than 5% fewer: a file cut short).

    See Also
    --------
    write_video : The inverse operation.

    Examples
    --------
    >>> import numpy as np, tempfile, os
    >>> from sklearn_hardness.io import read_video, write_video
    >>> frames = np.zeros((5, 32, 48, 3), dtype=np.uint8)
    >>> path = os.path.join(tempfile.mkdtemp(), "press.avi")
    >>> write_video(path, frames, fps=25)
    >>> read_video(path).shape
    (5, 32, 48, 3)
    """
    path = Path(os.fspath(path))
    if not path.exists():
        raise FileNotFoundError(f"Video not found: '{path}'.")
    if path.is_dir():
        return _read_image_folder(path, max_frames)
    if path.suffix.lower() == ".npy":
        try:
            arr = np.load(path, allow_pickle=False, mmap_mode="r")
        except (ValueError, EOFError, OSError) as exc:  # truncated or empty files raise EOFError
            raise ValueError(
                f"Could not read '{path}' as a .npy video (corrupt or truncated file): "
                f"{type(exc).__name__}: {exc}"
            ) from None
        arr = check_video(arr, name=f"'{path}'", allow_float=False)
        if arr.dtype == np.uint16:  # as 16-bit images are read: the high byte
            arr = (arr >> 8).astype(np.uint8)
        if arr.shape[-1] == 1:
            arr = np.repeat(arr, 3, axis=-1)
        return np.ascontiguousarray(arr[:max_frames])
    return _read_container(path, max_frames)


@validate_params(
    {
        "path": [str, os.PathLike],
        "frames": ["array-like"],
        "fps": [Interval(Real, 0, None, closed="neither")],
        "fourcc": [str, None],
    },
    prefer_skip_nested_validation=True,
)
def write_video(path, frames, fps=25.0, *, fourcc=None):
    """Write frames to a video file or a folder of PNG images.

    Parameters
    ----------
    path : str or path-like
        Destination. The extension chooses the container: ``.avi`` and
        ``.mkv`` use the lossless FFV1 codec (frames read back bit-exact),
        ``.mp4``, ``.mov`` and ``.m4v`` use the lossy MPEG-4 ``mp4v`` codec,
        ``.npy`` saves the raw array, and a path without extension becomes a
        folder of ``frame_00000.png`` files (lossless).
    frames : array-like of shape (T, H, W, 3) or (T, H, W)
        RGB ``uint8`` frames (grey-scale frames are written as RGB).
    fps : float, default=25.0
        Frame rate stored in the container.
    fourcc : str or None, default=None
        Four-character codec code overriding the default for the extension.

    Raises
    ------
    ValueError
        If the frames are invalid, the extension unknown, or OpenCV cannot
        open a writer for the codec.

    See Also
    --------
    read_video

    Examples
    --------
    >>> import tempfile
    >>> from pathlib import Path
    >>> import numpy as np
    >>> from sklearn_hardness.io import read_video, write_video
    >>> frames = np.random.default_rng(0).integers(0, 255, size=(5, 24, 32, 3), dtype=np.uint8)
    >>> path = Path(tempfile.mkdtemp()) / "press.avi"
    >>> write_video(path, frames)
    >>> np.array_equal(read_video(path), frames)   # FFV1: lossless
    True
    """
    path = Path(os.fspath(path))
    frames = check_video(frames, name="frames", allow_float=False)
    if frames.dtype != np.uint8:
        raise TypeError(f"frames must be uint8 to be written, got {frames.dtype}.")
    if frames.shape[-1] == 1:
        frames = np.repeat(frames, 3, axis=-1)
    suffix = path.suffix.lower()
    if suffix == ".npy":
        path.parent.mkdir(parents=True, exist_ok=True)
        np.save(path, np.ascontiguousarray(frames))
        return
    if suffix == "":
        path.mkdir(parents=True, exist_ok=True)
        for t, frame in enumerate(frames):
            if not cv2.imwrite(str(path / f"frame_{t:05d}.png"), cv2.cvtColor(frame, cv2.COLOR_RGB2BGR)):
                raise ValueError(f"OpenCV could not write '{path / f'frame_{t:05d}.png'}'.")
        return
    if suffix not in _DEFAULT_FOURCC:
        raise ValueError(
            f"Unknown video extension '{suffix}' for '{path}'; use one of "
            f"{', '.join(_DEFAULT_FOURCC)}, '.npy', or no extension for a PNG folder."
        )
    code = fourcc or _DEFAULT_FOURCC[suffix]
    if len(code) != 4:
        raise ValueError(f"fourcc must have 4 characters, got {code!r}.")
    path.parent.mkdir(parents=True, exist_ok=True)
    height, width = frames.shape[1:3]
    writer = cv2.VideoWriter(str(path), cv2.VideoWriter_fourcc(*code), float(fps), (width, height))
    if not writer.isOpened():
        raise ValueError(f"OpenCV could not open a '{code}' writer for '{path}'.")
    try:
        for frame in frames:
            writer.write(cv2.cvtColor(np.ascontiguousarray(frame), cv2.COLOR_RGB2BGR))
    finally:
        writer.release()
