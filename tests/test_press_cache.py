"""Per-press caching of the stateless feature steps (``memory=``): folds of any CV share each press's row."""

import functools
import os

import joblib
import numpy as np
import pytest
from sklearn.base import clone
from sklearn.model_selection import GroupKFold, cross_val_score

from sklearn_hardness.datasets._lazy import LazyVideoSequence
from sklearn_hardness.features import (
    ContactGeometryFeatures,
    ContactProfileFeatures,
    ImprintTextureFeatures,
    _contact_geometry,
)
from sklearn_hardness.models import make_named_pipeline

from ._synthetic import synthetic_press

N_PRESSES = 12


class CountingLoader:
    """Renders the press of a seed (amplitude by class) and counts the videos it made (outside its state,
    which the cache keys hash)."""

    counts = {}

    def __init__(self, name="loader"):
        self.name = name
        self.n_loads = 0

    @property
    def n_loads(self):
        return self.counts[self.name]

    @n_loads.setter
    def n_loads(self, value):
        self.counts[self.name] = value

    def __getstate__(self):
        return {"name": self.name}

    def __call__(self, seed):
        self.n_loads += 1
        return synthetic_press(n_frames=16, size=(24, 32), contact_start=5, peak=10,
                               amplitude=20.0 + 25.0 * (seed % 3), radius=5 + 2 * (seed % 3), seed=seed)


@pytest.fixture
def presses():
    loader = CountingLoader()
    videos = LazyVideoSequence(loader, list(range(N_PRESSES)))
    y = np.arange(N_PRESSES) % 3
    groups = np.arange(N_PRESSES) // 2  # six objects of two presses
    return loader, videos, y, groups


@pytest.fixture
def counted_rows(monkeypatch):
    """Counts the rows ContactGeometryFeatures computes (its per-press function, same name for the cache)."""
    calls = []
    original = _contact_geometry._press_row

    @functools.wraps(original)
    def counting(*args, **kwargs):
        calls.append(1)
        return original(*args, **kwargs)

    monkeypatch.setattr(_contact_geometry, "_press_row", counting)
    return calls


def _cv(pipe, videos, y, groups, cv):
    return cross_val_score(pipe, videos, y, groups=groups, cv=cv, scoring="balanced_accuracy")


def test_second_cv_over_other_folds_decodes_and_computes_nothing(presses, counted_rows, tmp_path):
    loader, videos, y, groups = presses
    plain = _cv(make_named_pipeline("contact_geometry"), videos, y, groups, GroupKFold(2))
    assert loader.n_loads == len(counted_rows) > 0

    memory = str(tmp_path / "cache")
    _cv(make_named_pipeline("contact_geometry", memory=memory), videos, y, groups, GroupKFold(3))
    assert len(counted_rows) - loader.n_loads == 0  # cold: one row per decoded video
    loader.n_loads, counted_rows[:] = 0, []
    cached = _cv(make_named_pipeline("contact_geometry", memory=memory), videos, y, groups, GroupKFold(2))
    assert loader.n_loads == 0 and counted_rows == []
    np.testing.assert_allclose(cached, plain)


def test_cold_cache_computes_each_press_once_across_folds(presses, counted_rows, tmp_path):
    _, videos, y, groups = presses
    _cv(make_named_pipeline("contact_geometry", memory=joblib.Memory(tmp_path, verbose=0)), videos, y, groups,
        GroupKFold(3))
    assert len(counted_rows) == N_PRESSES  # without memory: 2 * N_PRESSES (fit and score of each fold)


def test_videos_in_memory_are_keyed_by_their_frames(presses, counted_rows, tmp_path):
    loader, lazy, y, groups = presses
    videos = [lazy[i] for i in range(N_PRESSES)]
    plain = _cv(make_named_pipeline("contact_geometry"), videos, y, groups, GroupKFold(3))
    counted_rows[:] = []
    pipe = make_named_pipeline("contact_geometry", memory=tmp_path)
    _cv(pipe, videos, y, groups, GroupKFold(2))
    assert len(counted_rows) == N_PRESSES
    np.testing.assert_allclose(_cv(pipe, videos, y, groups, GroupKFold(3)), plain)
    assert len(counted_rows) == N_PRESSES
    videos[0] = videos[0].copy()
    videos[0][-1] += 1  # other frames: another press
    ContactGeometryFeatures(memory=tmp_path).fit_transform(videos)
    assert len(counted_rows) == N_PRESSES + 1


def test_a_changed_parameter_misses_and_a_column_choice_hits(presses, counted_rows, tmp_path):
    _, videos, _, _ = presses
    full = ContactGeometryFeatures(memory=tmp_path).fit_transform(videos)
    assert len(counted_rows) == N_PRESSES
    two = ContactGeometryFeatures(features=["log_depth", "eccentricity"], memory=tmp_path).fit_transform(videos)
    assert len(counted_rows) == N_PRESSES  # every row holds every feature
    names = list(_contact_geometry.FEATURE_NAMES)
    np.testing.assert_array_equal(two, full[:, [names.index("log_depth"), names.index("eccentricity")]])
    ContactGeometryFeatures(max_side=16, memory=tmp_path).fit_transform(videos)
    assert len(counted_rows) == 2 * N_PRESSES
    ContactGeometryFeatures(sigma=0.5, memory=tmp_path).fit_transform(videos)
    assert len(counted_rows) == 3 * N_PRESSES


@pytest.mark.parametrize("Features", [ContactProfileFeatures, ImprintTextureFeatures])
def test_other_feature_steps_read_cached_rows_without_decoding(Features, presses, tmp_path):
    loader, videos, _, _ = presses
    expected = Features().fit_transform(videos)
    first = Features(memory=tmp_path).fit_transform(videos)
    loader.n_loads = 0
    again = Features(memory=tmp_path).fit_transform(videos[np.arange(N_PRESSES)[::-1]])
    assert loader.n_loads == 0
    np.testing.assert_array_equal(first, expected)
    np.testing.assert_array_equal(again, expected[::-1])


def test_peak_change_baseline_caches_per_press(presses, tmp_path):
    loader, videos, y, groups = presses
    plain = _cv(make_named_pipeline("peak_change"), videos, y, groups, GroupKFold(3))
    pipe = make_named_pipeline("peak_change", memory=tmp_path)
    assert pipe.named_steps["functiontransformer"].kw_args == {"memory": tmp_path}
    _cv(pipe, videos, y, groups, GroupKFold(2))
    loader.n_loads = 0
    np.testing.assert_allclose(_cv(pipe, videos, y, groups, GroupKFold(3)), plain)
    assert loader.n_loads == 0


def test_memory_is_a_parameter_of_the_step(tmp_path):
    pipe = make_named_pipeline("contact_geometry", memory=str(tmp_path), with_profile=True)
    assert pipe.memory is None  # the steps cache per press; the Pipeline caches nothing on top
    assert pipe.get_params()["features__geometry__memory"] == str(tmp_path)
    assert pipe.get_params()["features__profile__memory"] == str(tmp_path)
    assert clone(pipe).get_params()["features__geometry__memory"] == str(tmp_path)
    assert ContactGeometryFeatures(memory=tmp_path).memory is tmp_path  # stored as given
    assert make_named_pipeline("convlstm", memory=str(tmp_path)).memory == str(tmp_path)  # no per-press step
    with pytest.raises(ValueError, match="memory"):
        ContactGeometryFeatures(memory=3).fit([np.zeros((3, 8, 8, 3), np.uint8)])


def test_cache_keys_name_videos_without_loading(tmp_path):
    loader = CountingLoader()
    videos = LazyVideoSequence(loader, [3, 5, 7])
    keys = videos.cache_keys()
    assert loader.n_loads == 0 and len(set(keys)) == 3
    assert videos[np.array([2, 0])].cache_keys() == [keys[2], keys[0]]
    assert LazyVideoSequence(CountingLoader(), [3]).cache_keys() == keys[:1]  # an equal loader, another run
    assert LazyVideoSequence(lambda key: key, [3]).cache_keys() is None  # a lambda names nothing stable

    path = tmp_path / "press.bin"
    path.write_bytes(b"one")
    files = LazyVideoSequence(np.load, [str(path)])
    before = files.cache_keys()
    path.write_bytes(b"other")
    os.utime(path, ns=(1, 1))
    assert LazyVideoSequence(np.load, [str(path)]).cache_keys() != before  # the file was written again
