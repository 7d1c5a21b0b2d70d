"""The public real GelSight Wedge grasps of ``GelSight-lab/EstimateModulus`` for the study scripts.

The repository's ``example_data/`` (45 MJPG grasp videos of 15 objects, 480x640
at 30 fps) has no license: it is never committed here. Bring it locally (e.g.
``git show HEAD:example_data/...`` from a clone) and pass its folder as
``--data``. The ``.avi`` files are read as videos; the ``.pkl`` gripper force
(N) and width (m) per frame next to them are pickled NumPy arrays, read by
:func:`load_grasp_forces` through an unpickler that builds NumPy arrays and
nothing else (a pickle can run any code it names).

The file names give relative softness within two object families, from
hardest to softest:

- balls: ``golf_ball``, ``purple_ball_hardest``, ``green_ball_softer``,
  ``orange_ball_softest``;
- foam bricks: ``blue_foam_brick_harder``, ``red_foam_brick_softer``,
  ``yellow_foam_brick_softest``.

Videos of one object (``golf_ball_1``, ``golf_ball__t=0``, ... over the
recording days) are one object here.
"""

import csv
import pickle
import re
import tempfile
from itertools import combinations
from pathlib import Path

import numpy as np

#: Object families, hardest first.
FAMILIES = {
    "balls": ("golf_ball", "purple_ball_hardest", "green_ball_softer", "orange_ball_softest"),
    "foam bricks": ("blue_foam_brick_harder", "red_foam_brick_softer", "yellow_foam_brick_softest"),
}

#: Region of the 480x640 Wedge frame that shows the gel (top, bottom, left, right fractions); the
#: rest is the sensor housing and the second finger's gel seen at an angle.
GEL_ROI = (0.18, 0.88, 0.08, 0.70)


def object_name(path):
    """``golf_ball_2.avi`` and ``golf_ball__t=1.avi`` -> ``golf_ball``."""
    stem = Path(path).stem
    return re.sub(r"(__t=\d+|_\d+)$", "", stem)


class CroppedVideos:
    """A lazy sequence: each video cropped to ``roi`` (fractions) and strided by ``stride``."""

    def __init__(self, videos, roi=None, stride=1):
        self.videos, self.roi, self.stride = videos, roi, stride

    def __len__(self):
        return len(self.videos)

    def __getitem__(self, i):
        if not isinstance(i, (int, np.integer)):
            return [self[j] for j in np.arange(len(self))[i]]
        v = self.videos[int(i)]
        if self.roi is not None:
            h, w = v.shape[1:3]
            y0, y1, x0, x1 = self.roi
            v = v[:, int(round(y0 * h)):int(round(y1 * h)), int(round(x0 * w)):int(round(x1 * w))]
        return np.ascontiguousarray(v[:, ::self.stride, ::self.stride])


def load_estimate_modulus(data, roi=None, stride=1):
    """The grasp videos under ``data`` as a Bunch (lazy ``videos``, ``object_name``, ``paths``).

    Read through :func:`sklearn_hardness.datasets.load_press_videos` with a
    manifest written to a temporary folder (label = object name).
    """
    from sklearn_hardness.datasets import load_press_videos

    paths = sorted(Path(data).rglob("*.avi"))
    if not paths:
        raise FileNotFoundError(f"no .avi videos under {data!r}: pass the example_data folder of "
                                "GelSight-lab/EstimateModulus.")
    with tempfile.TemporaryDirectory() as tmp:
        manifest = Path(tmp) / "manifest.csv"
        with open(manifest, "w", newline="") as f:
            writer = csv.writer(f)
            writer.writerow(["path", "label", "object_id"])
            for p in paths:
                writer.writerow([str(p.resolve()), object_name(p), object_name(p)])
        bunch = load_press_videos(manifest)
    bunch.object_name = np.array([object_name(p) for p in paths])
    bunch.videos = CroppedVideos(bunch.videos, roi=roi, stride=stride)
    return bunch


def expected_rank(proba, classes, hardness):
    """Expected hardness from class probabilities (``hardness[c]`` per class index ``c``)."""
    return np.asarray(proba) @ np.asarray(hardness, dtype=float)[np.asarray(classes)]


def family_pairs(object_names, scores):
    """Per family: (right, total, per-object mean score) of the within-family pairs.

    A pair is right when the harder object's mean score is strictly higher.
    """
    object_names = np.asarray(object_names)
    out = {}
    for family, members in FAMILIES.items():
        present = [m for m in members if (object_names == m).any()]
        mean = {m: float(np.mean(np.asarray(scores)[object_names == m])) for m in present}
        pairs = list(combinations(present, 2))  # (harder, softer): members are hardest first
        right = sum(mean[a] > mean[b] for a, b in pairs)
        out[family] = (right, len(pairs), mean)
    return out


class _ArrayUnpickler(pickle.Unpickler):
    """Builds NumPy arrays and nothing else ("Restricting Globals", Python's pickle documentation)."""

    ALLOWED = {("numpy.core.multiarray", "_reconstruct"), ("numpy._core.multiarray", "_reconstruct"),
               ("numpy", "ndarray"), ("numpy", "dtype")}

    def find_class(self, module, name):
        if (module, name) not in self.ALLOWED:
            raise pickle.UnpicklingError(f"{module}.{name} is not a NumPy array part: refused")
        return super().find_class(module, name)


def load_grasp_forces(data):
    """Per grasp video under ``data``: (object name, force in N, gripper width in m), per frame.

    From the ``<video>_forces.pkl`` and ``<video>_widths.pkl`` files next to each
    ``.avi`` (sorted by path, as :func:`load_estimate_modulus`).
    """
    out = []
    for video in sorted(Path(data).rglob("*.avi")):
        arrays = []
        for kind in ("forces", "widths"):
            with open(video.with_name(f"{video.stem}_{kind}.pkl"), "rb") as f:
                arrays.append(np.asarray(_ArrayUnpickler(f).load(), dtype=float).ravel())
        out.append((object_name(video), *arrays))
    return out
