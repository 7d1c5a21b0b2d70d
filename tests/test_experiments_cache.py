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
