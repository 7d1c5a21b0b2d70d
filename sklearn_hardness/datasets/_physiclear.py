"""Loading a local copy of the public PhysiCLeAR press videos (repository ``clear-nus/octopi``)."""

from __future__ import annotations

import ast
import glob
import os
import re
from numbers import Integral
from pathlib import Path

import numpy as np
from sklearn.utils import Bunch

from ..io import read_video
from ..utils._lazy import LazyVideoSequence
from ..utils._param_validation import Interval, validate_params

__all__ = ["load_physiclear"]

#: How constants.py names an object; the videos' names drop it.
_PREFIX = "physiclear_"
#: The hardness ranks 0, 1, 2 (constants.py's HARDNESS_MAP says "moderately hard" for 1).
_TARGET_NAMES = ("soft", "moderate", "hard")
#: The set's own split: which list of constants.py names the objects of each part.
_SPLITS = {"train": "TRAIN_OBJECTS", "val": "VAL_OBJECTS", "test": "TEST_OBJECTS"}
_HOW_TO_GET = (
    "The folder must hold a copy of the public PhysiCLeAR set as the repository clear-nus/octopi lays it out: "
    "dataset/ (the press videos, <object>_<i>.mov) and utils/constants.py (each object's ranks and the set's "
    "split). Get both with `git clone https://github.com/clear-nus/octopi && git -C octopi archive HEAD dataset "
    "utils/constants.py | tar x -C FOLDER`."
)


def _object_of(video):
    """``dataset/hairbrush_handle_3.mov`` -> ``hairbrush_handle``."""
    return re.sub(r"_\d+$", "", Path(video).stem)


def _bare(name):
    """An object's name without constants.py's ``physiclear_`` prefix."""
    return name[len(_PREFIX):] if name.startswith(_PREFIX) else name


def _literals(constants):
    """The top-level assignments of ``constants`` (a constants.py), as syntax trees, never run."""
    try:
        tree = ast.parse(constants.read_text(encoding="utf-8"), filename=str(constants))
    except (SyntaxError, ValueError, UnicodeDecodeError) as exc:
        raise ValueError(f"'{constants}' is not readable Python source ({exc}). {_HOW_TO_GET}") from None
    nodes = {}
    for node in tree.body:
        targets = node.targets if isinstance(node, ast.Assign) else [node.target] if (
            isinstance(node, ast.AnnAssign) and node.value is not None) else []
        nodes.update({t.id: node.value for t in targets if isinstance(t, ast.Name)})
    return nodes


def _literal(nodes, name, kind, constants):
    """The value of ``name`` in constants.py (None where it is not assigned); a ``kind`` literal."""
    if name not in nodes:
        return None
    try:
        value = ast.literal_eval(nodes[name])
    except ValueError:
        value = None
    if not isinstance(value, kind):
        what = " or ".join(k.__name__ for k in (kind if isinstance(kind, tuple) else (kind,)))
        raise ValueError(f"'{constants}': {name} must be a {what} written out as a literal; it is read "
                         "without running the file.")
    return value


def _ranks(nodes, constants):
    """``{property: {object: rank}}`` from every ``<PROPERTY>_RANK`` dict, hardness first."""
    names = ["HARDNESS_RANK"] + [n for n in nodes if n.endswith("_RANK") and n != "HARDNESS_RANK"]
    ranks = {}
    for name in names:
        table = _literal(nodes, name, dict, constants)
        if table is None:
            raise ValueError(f"'{constants}' assigns no HARDNESS_RANK (object -> 0 soft, 1 moderate, 2 hard). "
                             + _HOW_TO_GET)
        bad = [f"{obj}: {r!r}" for obj, r in table.items() if not isinstance(obj, str) or isinstance(r, bool)
               or not isinstance(r, int) or (name == "HARDNESS_RANK" and r not in (0, 1, 2))]
        if bad:
            allowed = "0, 1 or 2" if name == "HARDNESS_RANK" else "an integer"
            raise ValueError(f"'{constants}': {name} maps objects to {allowed}; not {', '.join(bad[:5])}.")
        ranks[name[: -len("_RANK")].lower()] = {_bare(obj): r for obj, r in table.items()}
    return ranks


def _rank_names(nodes, prop, constants):
    """The names of the ranks of ``prop`` from its ``<PROPERTY>_MAP`` ({rank: name}), or None."""
    names = _literal(nodes, f"{prop.upper()}_MAP", dict, constants)
    return None if names is None else {int(k): str(v) for k, v in names.items() if isinstance(k, int)}


def _splits(nodes, constants):
    """``{object: "train" | "val" | "test"}`` from the set's own lists."""
    split = {}
    for part, name in _SPLITS.items():
        for obj in map(_bare, _literal(nodes, name, (list, tuple), constants) or []):
            if split.setdefault(obj, part) != part:
                raise ValueError(f"'{constants}': object {obj!r} is in both {_SPLITS[split[obj]]} and {name}.")
    return split


def _families(nodes, constants):
    """``{part: whole}`` from OBJECTS_PARTS (``'a toothbrush': {'handle': ...}`` -> ``toothbrush``)."""
    parts = _literal(nodes, "OBJECTS_PARTS", dict, constants) or {}
    family = {}
    for whole, members in parts.items():
        if not isinstance(members, dict):
            raise ValueError(f"'{constants}': OBJECTS_PARTS[{whole!r}] must map part names to objects.")
        name = str(whole).removeprefix("a ").removeprefix("an ").replace(" ", "_").lower()
        family.update({_bare(str(obj)): name for obj in members.values()})
    return family


def _object_list(objects):
    """The object names of ``objects``: a list, or a text file with one a line (``#`` starts a comment)."""
    if isinstance(objects, (str, os.PathLike)):
        source = Path(os.fspath(objects))
        if not source.is_file():
            raise FileNotFoundError(f"objects={str(objects)!r} is no file; pass a list of object names or a "
                                    "text file with one name a line.")
        names = [line.split("#", 1)[0].strip() for line in source.read_text(encoding="utf-8").splitlines()]
        names = [n for n in names if n]
        if not names:
            raise ValueError(f"'{source}' names no object (one name a line; '#' starts a comment).")
    else:
        names = [str(n).strip() for n in np.asarray(objects, dtype=object).ravel()]
        if not names:
            raise ValueError("objects is empty; pass the names of the objects to load, or None for all.")
    return list(dict.fromkeys(map(_bare, names)))


def _videos(folder, objects):
    """``{object: [video paths]}``: every video, or only the videos of ``objects`` (no other name is listed)."""
    if objects is None:
        found = sorted(folder.glob("*.mov"))
    else:
        found = [p for obj in objects for p in folder.glob(glob.escape(obj) + "_*.mov") if _object_of(p) == obj]
    videos = {}
    for path in found:
        videos.setdefault(_object_of(path), []).append(path)
    return videos


@validate_params(
    {
        "path": [str, os.PathLike],
        "objects": ["array-like", str, os.PathLike, None],
        "cache_size": [Interval(Integral, 0, None, closed="left")],
    },
    prefer_skip_nested_validation=True,
)
def load_physiclear(path, *, objects=None, cache_size=0):
    """Load a local copy of the public PhysiCLeAR presses, GelSight Mini videos of everyday objects.

    The set (repository ``clear-nus/octopi``) holds hand presses of 74
    ranked objects in ``dataset/<object>_<i>.mov``; its ``utils/constants.py``
    ranks every object's hardness (and roughness and texture), groups the
    parts of one object (a toothbrush's handle and bristles) and splits the
    objects into train, validation and test. constants.py is parsed, never
    run. Videos are not read here: ``videos`` is a lazy sequence, as in
    :func:`load_press_videos`.

    Parameters
    ----------
    path : str or path-like
        The folder holding ``dataset/`` and ``utils/constants.py`` (e.g.
        ``git -C octopi archive HEAD dataset utils/constants.py | tar x -C
        path`` from a clone of the repository).
    objects : list of str, str, path-like or None, default=None
        The objects to load (with or without the ``physiclear_`` prefix),
        or a text file naming one a line (``#`` starts a comment). Only
        these objects' videos are listed and can be read, so objects kept
        aside for a final test are never touched. Each must have a hardness
        rank and at least one video. None loads every object with a hardness
        rank; videos of objects constants.py does not rank (the repository
        holds a few) are left out, and ``DESCR`` names them.
    cache_size : int, default=0
        How many decoded videos to keep in memory (least recently used).

    Returns
    -------
    data : :class:`~sklearn.utils.Bunch`
        ``videos``
            Lazy sequence (``len``, integer and array indexing) of
            ``(T, H, W, 3)`` ``uint8`` arrays, in the order of their file
            names; a video is decoded when it is indexed.
        ``target``
            ndarray of int per video: the hardness rank, 0 soft, 1 moderate,
            2 hard.
        ``target_names``
            ``["soft", "moderate", "hard"]``.
        ``hardness``, ``hardness_unit``
            ``[0., 1., 2.]`` per class, ``"rank"`` (for the MAE in ranks).
        ``force``, ``timestamps``, ``position``
            None: the set records none of them.
        ``object_id``
            ndarray of str per video: the object, without the prefix.
        ``family``
            ndarray of str per video: the whole object a part belongs to
            (``hairbrush`` for ``hairbrush_handle``; constants.py's
            ``OBJECTS_PARTS``), else the object itself. Folds that keep a
            family on one side keep sibling parts apart.
        ``ranks``
            dict ``{property: ndarray of int per video}`` for every
            ``<PROPERTY>_RANK`` of constants.py (``hardness``,
            ``roughness``, ``texture``); -1 where an object has no rank.
        ``rank_names``
            dict ``{property: {rank: name}}`` from constants.py's
            ``<PROPERTY>_MAP`` (e.g. ``{0: "smooth", ...}``), where given.
        ``split``
            ndarray of str per video: ``"train"``, ``"val"`` or ``"test"``
            (constants.py's ``TRAIN_OBJECTS``, ``VAL_OBJECTS``,
            ``TEST_OBJECTS``), ``""`` for an object in none of them.
        ``paths``
            list of the video paths.
        ``DESCR``
            str, what was loaded.

    Raises
    ------
    FileNotFoundError
        If ``path``, ``dataset/``, ``utils/constants.py`` or the file
        ``objects`` names is missing.
    ValueError
        If constants.py assigns no HARDNESS_RANK (or not as a literal), an
        object of ``objects`` is unknown, has no video or no hardness rank,
        or no video is found.

    See Also
    --------
    load_press_videos : Press videos listed in a CSV manifest.

    Examples
    --------
    >>> import os, tempfile
    >>> import numpy as np
    >>> from sklearn_hardness.io import write_video
    >>> from sklearn_hardness.datasets import load_physiclear
    >>> root = tempfile.mkdtemp()
    >>> os.makedirs(os.path.join(root, "utils"))
    >>> with open(os.path.join(root, "utils", "constants.py"), "w") as f:
    ...     _ = f.write("HARDNESS_RANK = {'physiclear_sponge': 0, 'physiclear_pen': 2}\\n"
    ...                 "TEST_OBJECTS = ['physiclear_pen']\\n")
    >>> for name in ["sponge_0", "sponge_1", "pen_0"]:
    ...     write_video(os.path.join(root, "dataset", name + ".mov"), np.zeros((4, 16, 16, 3), np.uint8))
    >>> data = load_physiclear(root, objects=["pen", "sponge"])
    >>> data.object_id.tolist(), data.target.tolist(), data.split.tolist()
    (['pen', 'sponge', 'sponge'], [2, 0, 0], ['test', '', ''])
    """
    root = Path(os.fspath(path))
    folder, constants = root / "dataset", root / "utils" / "constants.py"
    for needed in (root, folder):
        if not needed.is_dir():
            raise FileNotFoundError(f"'{needed}' is no folder. {_HOW_TO_GET}")
    if not constants.is_file():
        raise FileNotFoundError(f"'{constants}' is missing. {_HOW_TO_GET}")
    nodes = _literals(constants)
    ranks = _ranks(nodes, constants)
    split, family = _splits(nodes, constants), _families(nodes, constants)
    hardness = ranks["hardness"]

    wanted = None if objects is None else _object_list(objects)
    videos = _videos(folder, wanted)
    unranked = sorted(set(videos) - set(hardness))
    if wanted is not None:
        unknown = [o for o in wanted if o not in hardness and o not in videos]
        if unknown:
            raise ValueError(f"unknown object(s) {unknown}: constants.py ranks no such object and dataset/ holds "
                             "no video of it (names as in dataset/<object>_<i>.mov, e.g. 'hairbrush_handle').")
        if unranked:
            raise ValueError(f"object(s) {unranked} have videos in '{folder}' but no HARDNESS_RANK in "
                             f"'{constants}'; leave them out of objects.")
        without = [o for o in wanted if o not in videos]
        if without:
            raise ValueError(f"object(s) {without} have no video in '{folder}' (<object>_<i>.mov). {_HOW_TO_GET}")
    paths = sorted((p for obj, found in videos.items() if obj in hardness for p in found), key=lambda p: p.name)
    if not paths:
        found = f"only videos of unranked objects {unranked}" if unranked else "no <object>_<i>.mov video"
        raise ValueError(f"'{folder}' holds {found}; a video's object needs a HARDNESS_RANK in "
                         f"'{constants}'. {_HOW_TO_GET}")

    object_id = np.array([_object_of(p) for p in paths])
    target = np.array([hardness[o] for o in object_id], dtype=int)
    left_out = (f" Left out: {sum(len(videos[o]) for o in unranked)} videos of {len(unranked)} objects without a "
                f"hardness rank ({', '.join(unranked)})." if unranked else "")
    return Bunch(
        videos=LazyVideoSequence(read_video, paths, cache_size=cache_size),
        target=target,
        target_names=np.array(_TARGET_NAMES),
        hardness=np.arange(len(_TARGET_NAMES), dtype=float),
        hardness_unit="rank",
        force=None,
        timestamps=None,
        position=None,
        object_id=object_id,
        family=np.array([family.get(o, o) for o in object_id]),
        ranks={prop: np.array([table.get(o, -1) for o in object_id], dtype=int) for prop, table in ranks.items()},
        rank_names={prop: names for prop in ranks if (names := _rank_names(nodes, prop, constants)) is not None},
        split=np.array([split.get(o, "") for o in object_id]),
        paths=paths,
        DESCR=(f"PhysiCLeAR presses in {root}: {len(paths)} videos of {len(set(object_id))} objects, "
               f"hardness ranks {np.bincount(target, minlength=3).tolist()} (soft, moderate, hard).{left_out}"),
    )
