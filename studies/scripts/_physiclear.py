"""The real PhysiCLeAR presses of the development objects, for the study scripts.

``--data`` is a local copy of the public set (the repository ``clear-nus/octopi``'s
``dataset/`` and ``utils/constants.py``, e.g. ``git -C octopi archive HEAD dataset
utils/constants.py | tar x -C DATA``), read by
:func:`sklearn_hardness.datasets.load_physiclear` with ``objects=`` the development
list ``studies/real_development_objects.txt``: the kept-aside objects are never listed,
so never read. A manifest written by ``physiclear_manifest.py`` (a ``.csv`` or a folder
holding ``manifest.csv`` but no ``dataset/``) is read with ``load_press_videos``, and
refused if it names an object outside the list.
"""

from pathlib import Path

from sklearn_hardness.datasets import load_physiclear, load_press_videos

#: One development object a line, ``#`` comments.
DEVELOPMENT_OBJECTS = Path(__file__).resolve().parents[1] / "real_development_objects.txt"


def development_objects():
    """The names of the 49 development objects, in the list's order."""
    lines = (line.split("#", 1)[0].strip() for line in DEVELOPMENT_OBJECTS.read_text().splitlines())
    return [name for name in lines if name]


def load_development(data):
    """The presses of the development objects in ``data``: a copy of the public set, or a manifest."""
    data = Path(data)
    if (data / "dataset").is_dir():
        return load_physiclear(data, objects=DEVELOPMENT_OBJECTS)
    bunch = load_press_videos(data / "manifest.csv" if data.is_dir() else data)
    others = sorted(set(bunch.object_id) - set(development_objects()))
    if others:
        raise ValueError(f"{data} holds presses of objects that are not development objects ({others}); pass "
                         "the public set's folder instead, read with the development list alone.")
    return bunch
