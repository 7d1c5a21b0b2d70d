"""A simulated tactile sensor: a stand-in for a camera that streams presses of chosen objects."""

from __future__ import annotations

import numpy as np
from sklearn.utils import check_random_state

__all__ = ["SimulatedSensor"]

# cv2.CAP_PROP_* numbers (OpenCV's stable enum) answered by get()
_PROP_FPS, _PROP_FRAME_WIDTH, _PROP_FRAME_HEIGHT, _PROP_FRAME_COUNT = 5, 3, 4, 7


class SimulatedSensor:
    """A tactile camera that streams presses of the objects of a dataset, for sessions without hardware.

    It has the part of :class:`cv2.VideoCapture`'s interface that
    :func:`~sklearn_hardness.io.record_video` uses (``read``, ``isOpened``,
    ``get``, ``set``, ``release``), so a robot session written for a camera
    runs unchanged in CI: :meth:`press` stands for the robot pressing an
    object, then ``record_video(sensor, n_frames=sensor.n_frames)`` reads that
    press's frames. Each object's presses in ``data`` are handed out in a
    seeded random order, and again in a new order once all were pressed.

    Parameters
    ----------
    data : Bunch
        Presses with ``videos`` and ``object_id`` (e.g. from
        :func:`make_presses` or :func:`load_press_videos`).
    random_state : int, RandomState instance or None, default=None
        Seeds the order of each object's presses.

    Attributes
    ----------
    n_frames : int
        Frames of the current press not read yet (0 before the first press).
    pressed_ : list of (object_id, int)
        Each press so far: the object and the index of its video in ``data``.

    Examples
    --------
    >>> from sklearn_hardness.datasets import SimulatedSensor, make_presses
    >>> from sklearn_hardness.io import record_video
    >>> data = make_presses("silicone5", n_per_class=2, image_size=(24, 32), random_state=0)
    >>> sensor = SimulatedSensor(data, random_state=0)
    >>> sensor.press("silicone5-object3")
    >>> video = record_video(sensor, n_frames=sensor.n_frames)
    >>> video.shape[1:], sensor.n_frames
    ((24, 32, 3), 0)
    """

    def __init__(self, data, *, random_state=None):
        self.data = data
        self.random_state = random_state
        for field in ("videos", "object_id"):
            if field not in data:
                raise ValueError(f"data has no {field!r} field; pass a Bunch of make_presses or load_press_videos.")
        self._objects = np.asarray(data["object_id"]).astype(str)
        if self._objects.shape[0] != len(data["videos"]):
            raise ValueError(f"data has {len(data['videos'])} videos but {self._objects.shape[0]} object ids.")
        self._rng = check_random_state(random_state)
        self._queue = {}
        self._frames = np.empty((0, 1, 1, 3), np.uint8)
        self._pos = 0
        self.pressed_ = []

    @property
    def n_frames(self):
        return len(self._frames) - self._pos

    @property
    def objects(self):
        """The object ids this sensor can press, sorted."""
        return np.unique(self._objects)

    def press(self, object_id):
        """Press ``object_id``: its next press's frames are what :meth:`read` returns now."""
        object_id = str(object_id)
        members = np.flatnonzero(self._objects == object_id)
        if members.size == 0:
            raise ValueError(f"unknown object {object_id!r}; the sensor can press {self.objects.tolist()}.")
        if not self._queue.get(object_id):
            self._queue[object_id] = self._rng.permutation(members).tolist()
        i = self._queue[object_id].pop(0)
        self._frames = np.asarray(self.data["videos"][i])
        self._pos = 0
        self.pressed_.append((object_id, int(i)))

    def read(self):
        """``(True, frame)`` with the next frame in BGR, as OpenCV gives it; ``(False, None)`` after the press."""
        if self._pos >= len(self._frames):
            return False, None
        frame = self._frames[self._pos][..., ::-1]
        self._pos += 1
        return True, np.ascontiguousarray(frame)

    def isOpened(self):  # noqa: N802 - OpenCV's name
        """Always True: a simulated sensor is always connected."""
        return True

    def get(self, prop):
        """Frame rate, frame size or frames left (OpenCV property numbers); 0 for others."""
        shape = self._frames.shape
        fps = self.data.get("fps") if hasattr(self.data, "get") else None
        fps = float(np.nanmean(fps)) if fps is not None and np.size(fps) else 0.0
        return {_PROP_FPS: fps if np.isfinite(fps) else 0.0, _PROP_FRAME_WIDTH: float(shape[2]),
                _PROP_FRAME_HEIGHT: float(shape[1]), _PROP_FRAME_COUNT: float(self.n_frames)}.get(int(prop), 0.0)

    def set(self, prop, value):
        """Ignored (a camera may ignore requests too); returns False."""
        return False

    def release(self):
        """Nothing to release."""
