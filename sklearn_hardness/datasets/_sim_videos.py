"""Simulated press videos rendered on access: the simulation objects behind ``make_presses``.

A simulated dataset stores each press's mechanics and seeds; its videos are
rendered when indexed (:class:`SimulatedPressVideos`), so they cost no memory
until used and pickle without frames for joblib's process backends.
"""

from __future__ import annotations

import threading

import numpy as np

from ..utils._lazy import LazyVideoSequence
from ._sim_everyday import apply_codec, render_everyday_press
from ._sim_optics import SensorOptics, render_press


class _Simulation:
    """Everything needed to render any press of one simulated dataset."""

    def __init__(self, params, image_size, markers, sensor_seeds, sensor_idx, mechanics,
                 centers, render_seeds):
        self.params = params
        self.image_size = image_size
        self.markers = markers
        self.sensor_seeds = sensor_seeds
        self.sensor_idx = sensor_idx
        self.mechanics = mechanics
        self.centers = centers
        self.render_seeds = render_seeds
        self._sensors = {}
        self._lock = threading.Lock()

    def __getstate__(self):
        # Sensors (background, noise bank) are rebuilt from their seeds.
        state = self.__dict__.copy()
        state["_sensors"] = {}
        del state["_lock"]
        return state

    def __setstate__(self, state):
        self.__dict__.update(state)
        self._lock = threading.Lock()

    def sensor(self, k):
        with self._lock:
            if k not in self._sensors:
                rng = np.random.default_rng(self.sensor_seeds[k])
                self._sensors[k] = SensorOptics(rng, self.image_size, self.params, self.markers)
            return self._sensors[k]

    def render(self, i):
        rng = np.random.default_rng(self.render_seeds[i])
        return render_press(
            self.sensor(int(self.sensor_idx[i])), self.mechanics[i], self.centers[i], rng,
            self.params["drift_amplitude"],
        )


class _EverydaySimulation(_Simulation):
    """An ``everyday`` dataset: per-press objects of many shapes, optional codec."""

    def __init__(self, params, image_size, markers, sensor_seeds, sensor_idx, mechanics, centers,
                 render_seeds, objects, object_idx, codec):
        super().__init__(params, image_size, markers, sensor_seeds, sensor_idx, mechanics, centers,
                         render_seeds)
        self.objects = objects
        self.object_idx = object_idx
        self.codec = codec

    def render(self, i):
        rng = np.random.default_rng(self.render_seeds[i])
        video = render_everyday_press(
            self.sensor(int(self.sensor_idx[i])), self.objects[int(self.object_idx[i])],
            self.mechanics[i], self.centers[i], rng, self.params,
        )
        return video if self.codec is None else apply_codec(video, self.codec, self.params["fps"])


class SimulatedPressVideos(LazyVideoSequence):
    """Lazy sequence of simulated press videos.

    Each video is rendered when accessed, from the stored press parameters
    and a per-press seed, so indexing in any order gives the same frames. It
    behaves like a read-only list of ``(T, H, W, 3)`` ``uint8`` arrays:
    ``len``, iteration, an integer index (returns the video), and a slice,
    integer array or boolean mask (returns a new lazy sequence). It has a
    ``shape`` of ``(n_videos,)`` so that :func:`sklearn.utils._safe_indexing`,
    :func:`~sklearn.model_selection.train_test_split` and
    :func:`~sklearn.model_selection.cross_val_score` keep it lazy. It
    pickles without its rendered frames (for joblib's process backends).

    Parameters
    ----------
    loader : callable
        Renders the press of a key (internal: the simulated dataset).
    keys : sequence of int
        Which presses of the dataset this sequence holds.
    cache_size : int, default=0
        Number of most recently rendered videos kept in memory.

    See Also
    --------
    LazyVideoSequence : The generic lazy sequence (used for recordings).

    Examples
    --------
    >>> from sklearn_hardness.datasets import make_presses
    >>> data = make_presses(n_per_class=2, image_size=(48, 64), random_state=0)
    >>> videos = data.videos
    >>> len(videos), videos[0].dtype, videos[0].shape[1:]
    (10, dtype('uint8'), (48, 64, 3))
    >>> len(videos[[0, 3, 4]])
    3
    """

    @property
    def indices(self):
        """Indices of these videos in the dataset made by :func:`make_presses`."""
        return np.asarray(self.keys, dtype=int)

    def __repr__(self):
        h, w = self.loader.__self__.image_size
        return f"SimulatedPressVideos(n_videos={len(self)}, image_size=({h}, {w}))"


class _CodecSimulation:
    """A flat-preset simulation whose videos pass through a lossy codec."""

    def __init__(self, sim, codec):
        self.sim = sim
        self.codec = codec
        self.image_size = sim.image_size

    def render(self, i):
        return apply_codec(self.sim.render(i), self.codec, self.sim.params["fps"])
