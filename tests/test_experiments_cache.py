"""The experiments' inputs are per-press rows in the one cache: computed once a press, shared with users' pipelines."""

import os

import numpy as np
import pytest

from sklearn_hardness.experiments import _data
from sklearn_hardness.experiments._config import check_config, get_config
from sklearn_hardness.utils import default_cache_dir
from sklearn_hardness.utils._per_press import cache_size

from ._exp_data import TINY, tiny_presses


def _manifest(tmp_path):
    from sklearn_hardness._cli import main

    main(["simulate", "--preset", "silicone5", "--out", str(tmp_path / "sim"), "--n-per-class", "2",
          "--image-size", "32", "40", "--format", "npy", "--quiet"])
    return tmp_path / "sim" / "manifest.csv"


@pytest.fixture
def computed(monkeypatch):
    """The presses whose rows a per-press step computed (those the cache lacked), by step."""
    from sklearn_hardness.utils import _per_press

    calls = []
    original = _per_press._transform_missing

    def counting(step, X, missing):
        calls.append((type(step).__name__, len(missing)))
        return original(step, X, missing)

    monkeypatch.setattr(_per_press, "_transform_missing", counting)
    return calls


def test_inputs_are_computed_once_per_press_then_read_from_disk(tmp_path, computed):
    manifest = _manifest(tmp_path)
    n = 10  # silicone5, 2 presses per object
    cfg = check_config(dict(get_config("silicone5", **TINY), model="convlstm"))
    cache = str(tmp_path / "cache")
    first = _data.prepare_inputs(manifest, cfg, "convlstm", memory=cache, verbose=0)
    assert computed == [("ContactFrameSelector", n)] and cache_size(cache)[0] == n
    again = _data.prepare_inputs(manifest, cfg, "convlstm", memory=cache, verbose=0)
    assert computed == [("ContactFrameSelector", n)]  # read from disk, not recomputed
    np.testing.assert_array_equal(first.X, again.X)
    np.testing.assert_array_equal(first.y, again.y)
    # another frame size is another entry per press
    _data.prepare_inputs(manifest, dict(cfg, frame_size=(8, 10)), "convlstm", memory=cache, verbose=0)
    assert computed[-1] == ("ContactFrameSelector", n) and cache_size(cache)[0] == 2 * n
    # memory=False: no disk cache
    _data.prepare_inputs(manifest, cfg, "convlstm", memory=False, verbose=0)
    assert len(computed) == 3 and cache_size(cache)[0] == 2 * n


def test_a_users_pipeline_and_the_experiments_share_one_cache(tmp_path, computed):
    """The same folder as a pipeline's memory and as the experiments' cache: one entry per press, read by both."""
    from sklearn_hardness.models import make_named_pipeline

    manifest = _manifest(tmp_path)
    cache = str(tmp_path / "cache")
    cfg = check_config(get_config("silicone5", model="contact_profile"))
    inputs = _data.prepare_inputs(manifest, cfg, "contact_profile", memory=cache, verbose=0)
    assert computed == [("ContactProfileFeatures", 10)]
    from sklearn_hardness.datasets import load_press_videos

    data = load_press_videos(manifest)
    pipe = make_named_pipeline("contact_profile", memory=cache)
    rows = pipe[:1].fit_transform(data.videos)
    assert computed == [("ContactProfileFeatures", 10)]  # a hit for every press
    np.testing.assert_allclose(rows, inputs.X, rtol=1e-6)


def test_a_choice_of_contact_profile_features_reads_the_rows_of_all_twelve(tmp_path, computed):
    """``contact_profile_3`` after ``contact_profile`` on the same cache: its three columns of the cached twelve."""
    manifest = _manifest(tmp_path)
    cache = str(tmp_path / "cache")
    twelve = _data.prepare_inputs(manifest, check_config(get_config("silicone5", model="contact_profile")),
                                  "contact_profile", memory=cache, verbose=0)
    three = _data.prepare_inputs(manifest, check_config(get_config("silicone5", model="contact_profile_3")),
                                 "contact_profile_3", memory=cache, verbose=0)
    assert twelve.X.shape[1] == 12 and three.X.shape[1] == 3 and len(computed) == 1
    np.testing.assert_array_equal(three.X, twelve.X[:, [0, 10, 11]])


def test_default_cache_dir_follows_the_environment(tmp_path, monkeypatch):
    monkeypatch.setenv("SKLEARN_HARDNESS_CACHE", str(tmp_path / "c"))
    assert default_cache_dir() == str(tmp_path / "c")
    monkeypatch.delenv("SKLEARN_HARDNESS_CACHE")
    assert default_cache_dir().endswith(os.path.join(".cache", "sklearn_hardness"))


def test_a_video_re_recorded_in_place_is_prepared_again(tmp_path, computed):
    from sklearn_hardness.io import read_video, write_video

    manifest = _manifest(tmp_path)
    spec = _data._dataset_spec(manifest, {})
    video = tmp_path / "sim" / "videos" / "press_0003.npy"
    manifest_stat = os.stat(manifest)
    cfg = check_config(dict(get_config("silicone5", **TINY), model="convlstm"))
    cache = str(tmp_path / "cache")
    _data.prepare_inputs(manifest, cfg, "convlstm", memory=cache, verbose=0)
    write_video(video, read_video(video)[::-1])  # same size, new content, manifest untouched
    os.utime(video, ns=(os.stat(video).st_atime_ns, os.stat(video).st_mtime_ns + 10**9))
    assert os.stat(manifest).st_mtime_ns == manifest_stat.st_mtime_ns
    assert _data._dataset_spec(manifest, {}) == spec  # the run's data id (config hash) stays
    _data.prepare_inputs(manifest, cfg, "convlstm", memory=cache, verbose=0)
    assert computed == [("ContactFrameSelector", 10), ("ContactFrameSelector", 1)]  # that press alone, again


def test_force_or_position_rewritten_in_place_is_prepared_again_for_loading_compliance(tmp_path, computed):
    """Its inputs are the force and position series: the cache follows their content, press by press."""
    manifest = _manifest(tmp_path)
    cfg = check_config(dict(get_config("silicone5", **TINY), model="loading_compliance", frame_size=None))
    cache = str(tmp_path / "cache")
    first = _data.prepare_inputs(manifest, cfg, "loading_compliance", memory=cache, verbose=0).X
    path = tmp_path / "sim" / "position" / "press_0003.npy"
    np.save(path, 2.0 * np.load(path))  # the sensor travelled twice as far: twice the compliance
    again = _data.prepare_inputs(manifest, cfg, "loading_compliance", memory=cache, verbose=0).X
    assert computed == [("LoadingCompliance", 10), ("LoadingCompliance", 1)]
    np.testing.assert_allclose(again[3], first[3] + np.log(2.0), rtol=1e-5)
    np.testing.assert_array_equal(np.delete(again, 3, axis=0), np.delete(first, 3, axis=0))


def test_cache_is_cleared_by_function_and_command(tmp_path, capsys):
    from sklearn_hardness._cli import main
    from sklearn_hardness.utils import clear_cache

    manifest = _manifest(tmp_path)
    cfg = check_config(dict(get_config("silicone5", **TINY), model="convlstm"))
    cache = tmp_path / "out" / "cache"
    _data.prepare_inputs(manifest, cfg, "convlstm", memory=str(cache), verbose=0)
    (cache / "notes.txt").write_text("not ours")
    assert main(["cache", "--out", str(tmp_path / "out")]) == 0
    assert "10 cached press row(s)" in capsys.readouterr().out
    assert main(["cache", "--out", str(tmp_path / "out"), "--clear"]) == 0
    assert "removed 10 cached press row(s)" in capsys.readouterr().out
    assert (cache / "notes.txt").exists() and cache_size(cache) == (0, 0)  # only the cache's own files go
    assert clear_cache(cache) == [] and clear_cache(tmp_path / "nowhere") == []


def test_ofnn_inputs_say_once_how_many_presses_the_flow_padded(tmp_path):
    # the paper's OFNN reads 500 corners; a small frame has fewer, padded with zeros: the one pass over
    # every press says so once, with the count, instead of nothing
    cfg = check_config(dict(get_config("silicone5", **TINY), model="ofnn"))
    data = tiny_presses()
    for _ in range(2):  # computed, then read from the cache: the same warning
        with pytest.warns(UserWarning) as record:
            inputs = _data.prepare_inputs(data, cfg, "ofnn", memory=str(tmp_path), verbose=0)
        padded = [str(w.message) for w in record if "padded" in str(w.message)]
        n = len(data.target)
        assert len(padded) == 1 and f"{n} of {n} sample(s) had fewer than n_features=500 corners" in padded[0]
        assert inputs.X.shape[0] == n
