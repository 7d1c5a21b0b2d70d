"""load_physiclear on a tiny copy of the public set's layout (dataset/*.mov, utils/constants.py)."""

import numpy as np
import pytest

from harness.smoke import write_physiclear_layout
from sklearn_hardness.datasets import load_physiclear
from sklearn_hardness.utils._lazy import LazyVideoSequence

from ._synthetic import synthetic_press

#: The variable names of the repository's utils/constants.py, with a statement that fails if the file is run.
CONSTANTS = """\
raise RuntimeError("constants.py must be parsed, never run")
TRAIN_OBJECTS = ['physiclear_toothbrush_handle', 'physiclear_avocado_1']
VAL_OBJECTS = ['physiclear_toothbrush_bristles']
TEST_OBJECTS = [
    'physiclear_eraser', 'physiclear_orange',
    # "physiclear_kiwi",
]
OBJECTS = {'physiclear_eraser': "an eraser"}
HARDNESS_RANK = {
    'physiclear_toothbrush_handle': 2, 'physiclear_toothbrush_bristles': 0, 'physiclear_eraser': 1,
    'physiclear_orange': 1, 'physiclear_pen_base': 2, 'physiclear_kiwi': 1, "physiclear_avocado_1": 2,
}
HARDNESS_MAP = {0: "soft", 1: "moderately hard", 2: "hard"}
ROUGHNESS_RANK = {
    'physiclear_toothbrush_handle': 0, 'physiclear_toothbrush_bristles': 2, 'physiclear_eraser': 0,
    'physiclear_orange': 1, 'physiclear_pen_base': 0, 'physiclear_kiwi': 1, "physiclear_avocado_1": 2,
}
ROUGHNESS_MAP = {0: "smooth", 1: "slightly rough", 2: "rough"}
TEXTURE_RANK = {'physiclear_toothbrush_handle': 1, 'physiclear_eraser': 0}
RANKS = {"hardness": HARDNESS_RANK, "roughness": ROUGHNESS_RANK, "texture": TEXTURE_RANK}
OBJECTS_PARTS = {
    "a toothbrush": {'handle': 'physiclear_toothbrush_handle', 'sides of bristles': 'physiclear_toothbrush_bristles'},
    "a Pen": {'barrel': 'physiclear_pen_base'},
}
"""

#: Videos by object: pen (no rank, its name a prefix of pen_base's) and apple (no rank) as in the real set.
VIDEOS = {"toothbrush_handle": 2, "toothbrush_bristles": 2, "eraser": 3, "orange": 1, "pen_base": 1, "pen": 1,
          "apple": 1, "avocado_1": 1}


def _layout(root, constants=CONSTANTS, videos=VIDEOS):
    presses = {obj: [synthetic_press(n_frames=6, size=(16, 16), contact_start=2, peak=4, seed=k)] * n
               for k, (obj, n) in enumerate(videos.items())}
    return write_physiclear_layout(root, constants, presses)  # the layout the lab's smoke runs read too


@pytest.fixture(scope="module")
def layout(tmp_path_factory):
    return _layout(tmp_path_factory.mktemp("physiclear"))


def test_fields_of_every_ranked_object(layout):
    data = load_physiclear(layout)
    names = [p.name for p in data.paths]
    assert names == sorted(names) and "pen_0.mov" not in names and "apple_0.mov" not in names
    assert data.object_id.tolist() == ["avocado_1", "eraser", "eraser", "eraser", "orange", "pen_base",
                                       "toothbrush_bristles", "toothbrush_bristles", "toothbrush_handle",
                                       "toothbrush_handle"]
    assert data.target.tolist() == [2, 1, 1, 1, 1, 2, 0, 0, 2, 2]
    assert data.target_names.tolist() == ["soft", "moderate", "hard"]
    np.testing.assert_array_equal(data.hardness, [0.0, 1.0, 2.0])
    assert data.hardness_unit == "rank"
    assert data.force is None and data.timestamps is None and data.position is None
    np.testing.assert_array_equal(data.ranks["hardness"], data.target)
    assert data.ranks["roughness"].tolist() == [2, 0, 0, 0, 1, 0, 2, 2, 0, 0]
    assert data.ranks["texture"].tolist() == [-1, 0, 0, 0, -1, -1, -1, -1, 1, 1]  # -1: no rank
    assert data.rank_names == {"hardness": {0: "soft", 1: "moderately hard", 2: "hard"},
                               "roughness": {0: "smooth", 1: "slightly rough", 2: "rough"}}
    assert "Left out: 2 videos of 2 objects without a hardness rank (apple, pen)" in data.DESCR


def test_family_is_the_whole_object_of_a_part(layout):
    data = load_physiclear(layout)
    family = dict(zip(data.object_id, data.family))
    assert family == {"toothbrush_handle": "toothbrush", "toothbrush_bristles": "toothbrush", "pen_base": "pen",
                      "eraser": "eraser", "orange": "orange", "avocado_1": "avocado_1"}


def test_the_sets_own_split(layout):
    data = load_physiclear(layout)
    split = dict(zip(data.object_id, data.split))
    assert split == {"toothbrush_handle": "train", "avocado_1": "train", "toothbrush_bristles": "val",
                     "eraser": "test", "orange": "test", "pen_base": ""}


def test_videos_are_lazy_and_read_back(layout, monkeypatch):
    opened = []
    import sklearn_hardness.io._video as video_mod

    read = video_mod.read_video
    monkeypatch.setattr("sklearn_hardness.datasets._physiclear.read_video", lambda p: opened.append(p) or read(p))
    data = load_physiclear(layout, cache_size=2)
    assert isinstance(data.videos, LazyVideoSequence) and opened == []
    video = data.videos[1]
    assert video.shape == (6, 16, 16, 3) and video.dtype == np.uint8 and opened == [data.paths[1]]


def test_objects_filters_what_is_listed(layout):
    data = load_physiclear(layout, objects=["physiclear_pen_base", "eraser"])  # with or without the prefix
    assert [p.name for p in data.paths] == ["eraser_0.mov", "eraser_1.mov", "eraser_2.mov", "pen_base_0.mov"]
    assert "Left out" not in data.DESCR  # pen_0.mov, of the unranked "pen", is not even listed


def test_objects_from_a_text_file(layout, tmp_path):
    listed = tmp_path / "objects.txt"
    listed.write_text("# development objects\ntoothbrush_handle\n\norange  # one video\n")
    data = load_physiclear(layout, objects=listed)
    assert sorted(set(data.object_id)) == ["orange", "toothbrush_handle"]
    assert load_physiclear(layout, objects=str(listed)).paths == data.paths


def test_unlisted_objects_are_never_opened(tmp_path):
    root = _layout(tmp_path / "set")
    (root / "dataset" / "orange_0.mov").write_bytes(b"kept aside: never to be read")
    data = load_physiclear(root, objects=["toothbrush_handle", "toothbrush_bristles", "eraser", "pen_base"])
    assert all(len(video) == 6 for video in data.videos)  # every listed video reads
    everything = load_physiclear(root)
    with pytest.raises(ValueError):
        everything.videos[everything.paths.index(root / "dataset" / "orange_0.mov")]


@pytest.mark.parametrize("remove, match", [("utils/constants.py", r"constants\.py' is missing"),
                                           ("dataset", r"dataset' is no folder")])
def test_wrong_layout_says_how_to_get_the_set(tmp_path, remove, match):
    root = _layout(tmp_path / "set", videos={"eraser": 1})
    target = root / remove
    if target.is_dir():
        for f in target.iterdir():
            f.unlink()
        target.rmdir()
    else:
        target.unlink()
    with pytest.raises(FileNotFoundError, match=match) as info:
        load_physiclear(root)
    assert "clear-nus/octopi" in str(info.value) and "git -C octopi archive HEAD dataset utils/constants.py" in str(
        info.value)


def test_missing_folder(tmp_path):
    with pytest.raises(FileNotFoundError, match="is no folder.*clear-nus/octopi"):
        load_physiclear(tmp_path / "nowhere")


@pytest.mark.parametrize("constants, match", [
    ("TRAIN_OBJECTS = ['physiclear_eraser']\n", "assigns no HARDNESS_RANK.*clear-nus/octopi"),
    ("HARDNESS_RANK = dict(physiclear_eraser=1)\n", "HARDNESS_RANK must be a dict written out as a literal"),
    ("HARDNESS_RANK = {'physiclear_eraser': 3}\n", r"0, 1 or 2; not physiclear_eraser: 3"),
    ("HARDNESS_RANK = {'physiclear_eraser': 1}\nROUGHNESS_RANK = {'physiclear_eraser': 'low'}\n",
     "ROUGHNESS_RANK maps objects to an integer; not physiclear_eraser: 'low'"),
    ("HARDNESS_RANK = {'physiclear_eraser': 1\n", "not readable Python source"),
    ("HARDNESS_RANK = {'physiclear_eraser': 1}\nTRAIN_OBJECTS = ['physiclear_eraser']\n"
     "TEST_OBJECTS = ['physiclear_eraser']\n", "'eraser' is in both TRAIN_OBJECTS and TEST_OBJECTS"),
    ("HARDNESS_RANK = {'physiclear_eraser': 1}\nOBJECTS_PARTS = {'a pen': ['physiclear_eraser']}\n",
     "OBJECTS_PARTS"),
])
def test_malformed_constants(tmp_path, constants, match):
    root = _layout(tmp_path / "set", constants=constants, videos={"eraser": 1})
    with pytest.raises(ValueError, match=match):
        load_physiclear(root)


@pytest.mark.parametrize("objects, match", [
    (["eraser", "stapler"], r"unknown object\(s\) \['stapler'\]"),
    (["eraser", "kiwi"], r"\['kiwi'\] have no video"),
    (["eraser", "pen"], r"\['pen'\] have videos .* but no HARDNESS_RANK"),
    ([], "objects is empty"),
])
def test_bad_objects(layout, objects, match):
    with pytest.raises(ValueError, match=match):
        load_physiclear(layout, objects=objects)


def test_objects_file_errors(layout, tmp_path):
    with pytest.raises(FileNotFoundError, match="is no file"):
        load_physiclear(layout, objects=tmp_path / "missing.txt")
    (tmp_path / "empty.txt").write_text("# nothing yet\n\n")
    with pytest.raises(ValueError, match="names no object"):
        load_physiclear(layout, objects=tmp_path / "empty.txt")


@pytest.mark.parametrize("videos, match", [({}, "no <object>_<i>.mov video"),
                                           ({"apple": 1}, r"only videos of unranked objects \['apple'\]")])
def test_no_ranked_video(tmp_path, videos, match):
    root = _layout(tmp_path / "set", videos=videos)
    with pytest.raises(ValueError, match=match):
        load_physiclear(root)


@pytest.mark.parametrize("name, value", [("objects", 5), ("cache_size", -1)])
def test_parameters_are_validated(layout, name, value):
    with pytest.raises(ValueError, match=f"'{name}' parameter of load_physiclear"):  # InvalidParameterError
        load_physiclear(layout, **{name: value})
