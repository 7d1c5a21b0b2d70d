"""A tiny simulated dataset shared by the experiment tests."""

import csv
import functools

from sklearn_hardness.datasets import make_presses
from sklearn_hardness.io import write_video

# Small enough that frame selection takes about a second, large enough for
# s0 + N * s + l presses per class with the tiny settings below.
TINY = dict(
    initial_epochs=4,
    epochs_per_query=2,
    n_iterations=2,
    n_initial=2,
    n_per_query=2,
    n_test=2,
    n_samples=4,
    max_reservoir=8,
    frame_size=(16, 20),
)


@functools.lru_cache(maxsize=2)
def tiny_presses(n_per_class=8):
    return make_presses("silicone5", n_per_class=n_per_class, image_size=(32, 40), random_state=0)


def write_object_manifest(folder, data, presses_per_object, paths=None):
    """Write ``data``'s videos as ``press_NNN.npy`` and a manifest of objects ``object{class}-{k}``.

    Each class's presses are grouped, in order, into objects of
    ``presses_per_object``. ``paths`` maps a press index to the file its row
    names instead of its own (a file the caller writes). Returns the manifest.
    """
    paths, seen = paths or {}, {}
    with open(folder / "manifest.csv", "w", newline="") as f:
        w = csv.writer(f)
        w.writerow(["path", "label", "object_id"])
        for i in range(len(data.videos)):
            c = int(data.target[i])
            k = seen[c] = seen.get(c, -1) + 1
            write_video(folder / f"press_{i:03d}.npy", data.videos[i])
            w.writerow([paths.get(i, f"press_{i:03d}.npy"), data.target_names[c],
                        f"object{c}-{k // presses_per_object}"])
    return folder / "manifest.csv"
