"""Inputs are prepared once per dataset and configuration: a disk cache safe under concurrent runs."""

import os

import numpy as np
import pytest

from sklearn_hardness.experiments import _data
from sklearn_hardness.experiments._config import check_config, get_config

from ._exp_data import TINY, tiny_presses


def _manifest(tmp_path):
    from sklearn_hardness._cli import main

    main(["simulate", "--preset", "silicone5", "--out", str(tmp_path / "sim"), "--n-per-class", "2",
          "--image-size", "32", "40", "--format", "npy"])
    return tmp_path / "sim" / "manifest.csv"


def test_inputs_are_computed_once_then_read_from_disk(tmp_path, monkeypatch):
    manifest = _manifest(tmp_path)
    cfg = check_config(dict(get_config("silicone5", **TINY), model="convlstm"))
    calls = []
    compute = _data._compute
    monkeypatch.setattr(_data, "_compute", lambda *a: calls.append(1) or compute(*a))
    cache = tmp_path / "cache"
    first = _data.prepare_inputs(manifest, cfg, "convlstm", memory=cache, verbose=0)
    assert calls == [1]
    files = os.listdir(cache)
    assert len(files) == 1 and files[0].startswith("inputs-") and files[0].endswith(".npz")  # no temp left
    _data._MEMO.clear()  # a new process
    again = _data.prepare_inputs(manifest, cfg, "convlstm", memory=cache, verbose=0)
    assert calls == [1]  # read from disk, not recomputed
    np.testing.assert_array_equal(first.X, again.X)
    np.testing.assert_array_equal(first.y, again.y)
    # another frame size is another entry
    _data.prepare_inputs(manifest, dict(cfg, frame_size=(8, 10)), "convlstm", memory=cache, verbose=0)
    assert calls == [1, 1] and len(os.listdir(cache)) == 2
    # a corrupt file (e.g. the disk filled up) is recomputed, not trusted
    path = cache / files[0]
    path.write_bytes(b"not an npz")
    _data._MEMO.clear()
    third = _data.prepare_inputs(manifest, cfg, "convlstm", memory=cache, verbose=0)
    assert calls == [1, 1, 1]
    np.testing.assert_array_equal(first.X, third.X)
    # memory=False: no disk cache
    _data._MEMO.clear()
    _data.prepare_inputs(manifest, cfg, "convlstm", memory=False, verbose=0)
    assert calls == [1, 1, 1, 1] and len(os.listdir(cache)) == 2


def test_a_choice_of_contact_profile_features_is_its_own_cache_entry(tmp_path):
    """``contact_profile_3`` after ``contact_profile`` on the same cache: three columns, not the cached twelve."""
    manifest = _manifest(tmp_path)
    cache = tmp_path / "cache"
    _data._MEMO.clear()
    twelve = _data.prepare_inputs(manifest, check_config(get_config("silicone5", model="contact_profile")),
                                  "contact_profile", memory=cache, verbose=0)
    _data._MEMO.clear()  # a new process: only the disk cache is left
    three = _data.prepare_inputs(manifest, check_config(get_config("silicone5", model="contact_profile_3")),
                                 "contact_profile_3", memory=cache, verbose=0)
    assert twelve.X.shape[1] == 12 and three.X.shape[1] == 3 and len(os.listdir(cache)) == 2
    np.testing.assert_array_equal(three.X, twelve.X[:, [0, 10, 11]])


def test_default_cache_dir_follows_the_environment(tmp_path, monkeypatch):
    monkeypatch.setenv("SKLEARN_HARDNESS_CACHE", str(tmp_path / "c"))
    assert _data.default_cache_dir() == str(tmp_path / "c")
    monkeypatch.delenv("SKLEARN_HARDNESS_CACHE")
    assert _data.default_cache_dir().endswith(os.path.join(".cache", "sklearn_hardness"))


def test_a_failed_write_leaves_no_file(tmp_path, monkeypatch):
    cfg = check_config(dict(get_config("silicone5", **TINY), model="convlstm"))

    def boom(*a, **k):
        raise OSError("disk full")

    monkeypatch.setattr(_data.np, "savez", boom)
    with pytest.raises(OSError, match="disk full"):
        _data._cached_compute(str(tmp_path), ("make_presses", "x"), tiny_presses(), cfg,
                              _data._frame_params(cfg, "convlstm"), None, 0)
    assert os.listdir(tmp_path) == []


def test_a_video_re_recorded_in_place_is_prepared_again(tmp_path, monkeypatch):
    from sklearn_hardness.io import read_video, write_video

    manifest = _manifest(tmp_path)
    spec = _data._dataset_spec(manifest, {})
    key = _data._cache_spec(spec)
    assert _data._cache_spec(spec) == key  # stable while nothing changes
    video = tmp_path / "sim" / "videos" / "press_0003.npy"
    manifest_stat = os.stat(manifest)
    write_video(video, read_video(video)[::-1])  # same size, new content, manifest untouched
    os.utime(video, ns=(os.stat(video).st_atime_ns, os.stat(video).st_mtime_ns + 10**9))
    assert os.stat(manifest).st_mtime_ns == manifest_stat.st_mtime_ns
    assert _data._dataset_spec(manifest, {}) == spec  # the run's data id (config hash) stays
    assert _data._cache_spec(spec) != key
    # and prepare_inputs computes again instead of returning the old frames
    cfg = check_config(dict(get_config("silicone5", **TINY), model="convlstm"))
    calls = []
    compute = _data._compute
    monkeypatch.setattr(_data, "_compute", lambda *a: calls.append(1) or compute(*a))
    _data.prepare_inputs(manifest, cfg, "convlstm", memory=tmp_path / "cache", verbose=0)
    write_video(video, read_video(video)[::-1])
    os.utime(video, ns=(os.stat(video).st_atime_ns, os.stat(video).st_mtime_ns + 2 * 10**9))
    _data.prepare_inputs(manifest, cfg, "convlstm", memory=tmp_path / "cache", verbose=0)
    assert calls == [1, 1]


def test_force_or_position_rewritten_in_place_is_prepared_again_for_loading_compliance(tmp_path):
    """Its inputs are the force and position series: the cache follows their content, the videos' keys stay."""
    manifest = _manifest(tmp_path)
    spec = _data._dataset_spec(manifest, {})
    cfg = check_config(dict(get_config("silicone5", **TINY), model="loading_compliance", frame_size=None))
    features = _data._feature_params(cfg, "loading_compliance")
    key = _data._cache_spec(spec, features)
    assert _data._cache_spec(spec, features) == key and _data._cache_spec(spec) != key
    first = _data.prepare_inputs(manifest, cfg, "loading_compliance", memory=tmp_path / "cache", verbose=0).X
    path = tmp_path / "sim" / "position" / "press_0003.npy"
    np.save(path, 2.0 * np.load(path))  # the sensor travelled twice as far: twice the compliance
    assert _data._cache_spec(spec, features) != key
    assert _data._cache_spec(spec) == _data._cache_spec(spec, None)  # the video models' keys do not change
    _data._MEMO.clear()
    again = _data.prepare_inputs(manifest, cfg, "loading_compliance", memory=tmp_path / "cache", verbose=0).X
    np.testing.assert_allclose(again[3], first[3] + np.log(2.0), rtol=1e-5)
    np.testing.assert_array_equal(np.delete(again, 3, axis=0), np.delete(first, 3, axis=0))


def test_cache_is_cleared_by_function_and_command(tmp_path, capsys):
    from sklearn_hardness._cli import main

    manifest = _manifest(tmp_path)
    cfg = check_config(dict(get_config("silicone5", **TINY), model="convlstm"))
    cache = tmp_path / "out" / "cache"
    _data.prepare_inputs(manifest, cfg, "convlstm", memory=cache, verbose=0)
    (cache / "notes.txt").write_text("not ours")
    assert main(["cache", "--out", str(tmp_path / "out")]) == 0
    assert "1 cached input file(s)" in capsys.readouterr().out
    assert main(["cache", "--out", str(tmp_path / "out"), "--clear"]) == 0
    assert "removed 1 cached input file(s)" in capsys.readouterr().out
    assert os.listdir(cache) == ["notes.txt"]  # only the cache's own files go
    assert _data.clear_cache(cache) == [] and _data.clear_cache(tmp_path / "nowhere") == []


def test_ofnn_inputs_say_once_how_many_presses_the_flow_padded(tmp_path):
    # the paper's OFNN reads 500 corners; a small frame has fewer, padded with zeros: the one pass over
    # every press says so once, with the count, instead of nothing
    cfg = check_config(dict(get_config("silicone5", **TINY), model="ofnn"))
    data = tiny_presses()
    with pytest.warns(UserWarning) as record:
        inputs = _data.prepare_inputs(data, cfg, "ofnn", memory=tmp_path, verbose=0)
    padded = [str(w.message) for w in record if "padded" in str(w.message)]
    n = len(data.target)
    assert len(padded) == 1 and f"{n} of {n} sample(s) had fewer than n_features=500 corners" in padded[0]
    assert inputs.X.shape[0] == n
