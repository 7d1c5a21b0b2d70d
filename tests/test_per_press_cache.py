"""The per-press mark and the one cache (``memory=``): folds of any CV, grid searches and the experiments share
each press's rows."""

import os

import joblib
import numpy as np
import pytest
from sklearn.base import clone
from sklearn.model_selection import GroupKFold, cross_val_score

from sklearn_hardness.features import (
    ContactGeometryFeatures,
    ContactProfileFeatures,
    DINOv2Features,
    ImprintTextureFeatures,
    LoadingCompliance,
    OpticalFlowFeatures,
    PeakContactChange,
)
from sklearn_hardness.features._contact_geometry import FEATURE_NAMES as GEOMETRY_FEATURES
from sklearn_hardness.models import make_named_pipeline, pipeline_names
from sklearn_hardness.preprocessing import ContactFrameSelector
from sklearn_hardness.utils import PerPressTransformerMixin, clear_cache
from sklearn_hardness.utils._lazy import LazyVideoSequence
from sklearn_hardness.utils._per_press import cache_size, is_per_press

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
    """Counts the presses whose rows ContactGeometryFeatures computes (those its cache lacks)."""
    calls = []
    original = ContactGeometryFeatures._transform_presses

    def counting(self, X):
        calls.extend([1] * len(X))
        return original(self, X)

    monkeypatch.setattr(ContactGeometryFeatures, "_transform_presses", counting)
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
    pipe = make_named_pipeline("contact_geometry", memory=str(tmp_path))
    _cv(pipe, videos, y, groups, GroupKFold(2))
    assert len(counted_rows) == N_PRESSES
    np.testing.assert_allclose(_cv(pipe, videos, y, groups, GroupKFold(3)), plain)
    assert len(counted_rows) == N_PRESSES
    videos[0] = videos[0].copy()
    videos[0][-1] += 1  # other frames: another press
    ContactGeometryFeatures(memory=str(tmp_path)).fit_transform(videos)
    assert len(counted_rows) == N_PRESSES + 1


def test_a_changed_parameter_misses_and_a_column_choice_hits(presses, counted_rows, tmp_path):
    _, videos, _, _ = presses
    memory = str(tmp_path)
    full = ContactGeometryFeatures(memory=memory).fit_transform(videos)
    assert len(counted_rows) == N_PRESSES
    two = ContactGeometryFeatures(features=["log_depth", "eccentricity"], memory=memory).fit_transform(videos)
    assert len(counted_rows) == N_PRESSES  # every row holds every feature
    names = list(GEOMETRY_FEATURES)
    np.testing.assert_array_equal(two, full[:, [names.index("log_depth"), names.index("eccentricity")]])
    ContactGeometryFeatures(max_side=16, memory=memory).fit_transform(videos)
    assert len(counted_rows) == 2 * N_PRESSES
    ContactGeometryFeatures(sigma=0.5, memory=memory).fit_transform(videos)
    assert len(counted_rows) == 3 * N_PRESSES
    ContactGeometryFeatures(n_jobs=2, memory=memory).fit_transform(videos)  # parallelism changes no row
    assert len(counted_rows) == 3 * N_PRESSES


@pytest.mark.parametrize("Features", [ContactProfileFeatures, ImprintTextureFeatures])
def test_other_feature_steps_read_cached_rows_without_decoding(Features, presses, tmp_path):
    loader, videos, _, _ = presses
    expected = Features().fit_transform(videos)
    first = Features(memory=str(tmp_path)).fit_transform(videos)
    loader.n_loads = 0
    again = Features(memory=str(tmp_path)).fit_transform(videos[np.arange(N_PRESSES)[::-1]])
    assert loader.n_loads == 0
    np.testing.assert_array_equal(first, expected)
    np.testing.assert_array_equal(again, expected[::-1])


def test_peak_change_baseline_caches_per_press(presses, tmp_path):
    loader, videos, y, groups = presses
    plain = _cv(make_named_pipeline("peak_change"), videos, y, groups, GroupKFold(3))
    pipe = make_named_pipeline("peak_change", memory=str(tmp_path))
    assert pipe.named_steps["peakcontactchange"].memory == str(tmp_path)
    _cv(pipe, videos, y, groups, GroupKFold(2))
    loader.n_loads = 0
    np.testing.assert_allclose(_cv(pipe, videos, y, groups, GroupKFold(3)), plain)
    assert loader.n_loads == 0


def test_memory_is_a_parameter_of_every_per_press_step_and_means_one_thing(tmp_path):
    pipe = make_named_pipeline("contact_geometry", memory=str(tmp_path), with_profile=True)
    assert pipe.memory is None  # the steps cache per press; the Pipeline caches nothing on top
    assert pipe.get_params()["features__geometry__memory"] == str(tmp_path)
    assert pipe.get_params()["features__profile__memory"] == str(tmp_path)
    assert clone(pipe).get_params()["features__geometry__memory"] == str(tmp_path)
    # every named pipeline: memory goes to its per-press steps (the nets' frame selection too), never the Pipeline
    for name in pipeline_names():
        pipe = make_named_pipeline(name, memory=str(tmp_path))
        steps = [key for key, value in pipe.get_params().items() if isinstance(value, PerPressTransformerMixin)]
        assert steps and pipe.memory is None, name
        assert all(pipe.get_params()[f"{key}__memory"] == str(tmp_path) for key in steps), name
    # check_memory's semantics, as a scikit-learn Pipeline's memory: None, a folder or a Memory-like object
    with pytest.raises(ValueError, match="'memory' should be None, a string or have the same interface"):
        make_named_pipeline("contact_geometry", memory=3)
    with pytest.raises(ValueError, match="memory"):
        ContactGeometryFeatures(memory=3).fit([np.zeros((3, 8, 8, 3), np.uint8)])
    from sklearn.pipeline import Pipeline

    # a path object is refused as scikit-learn's Pipeline refuses it (give str(path))
    refused = "must be None, an instance of 'str' or an object implementing 'cache'"
    with pytest.raises(ValueError, match=f"'memory' parameter of Pipeline {refused}"):
        Pipeline([("f", ContactGeometryFeatures())], memory=tmp_path).fit([np.zeros((3, 8, 8, 3), np.uint8)])
    with pytest.raises(ValueError, match=f"'memory' parameter of ContactGeometryFeatures {refused}"):
        ContactGeometryFeatures(memory=tmp_path).fit([np.zeros((3, 8, 8, 3), np.uint8)])
    # a Memory without a location caches nothing and computes every row
    X = [np.zeros((3, 8, 8, 3), np.uint8)]
    assert ContactGeometryFeatures(memory=joblib.Memory(None)).fit_transform(X).shape == (1, 17)


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


#: Every per-press step of the package: each carries the one mark that the machinery reads.
PER_PRESS_STEPS = [ContactFrameSelector, OpticalFlowFeatures, DINOv2Features, ContactProfileFeatures,
                   ContactGeometryFeatures, ImprintTextureFeatures, PeakContactChange, LoadingCompliance]


def test_every_per_press_step_carries_the_mark_and_nothing_else_does():
    import importlib
    import inspect
    import pkgutil

    import sklearn_hardness

    marked = set()
    for module in pkgutil.walk_packages(sklearn_hardness.__path__, "sklearn_hardness."):
        if module.name.endswith("__main__"):
            continue
        for _, cls in inspect.getmembers(importlib.import_module(module.name), inspect.isclass):
            if issubclass(cls, PerPressTransformerMixin) and cls is not PerPressTransformerMixin:
                marked.add(cls)
    assert marked == set(PER_PRESS_STEPS)
    for step in PER_PRESS_STEPS:
        assert "memory" in step().get_params() and is_per_press(step())
    from sklearn.pipeline import FeatureUnion, make_pipeline
    from sklearn.preprocessing import StandardScaler

    assert is_per_press(FeatureUnion([("a", ContactProfileFeatures()), ("b", PeakContactChange())]))
    assert is_per_press(make_pipeline(ContactFrameSelector(), OpticalFlowFeatures()))
    assert not is_per_press(FeatureUnion([("a", ContactProfileFeatures()), ("s", StandardScaler())]))
    assert not is_per_press(StandardScaler())


@pytest.mark.parametrize("make", [
    lambda memory: make_named_pipeline("convlstm", memory=memory)[:1],  # the selected frames
    lambda memory: make_named_pipeline("ofnn", frame_size=(24, 32), memory=memory)[:2],  # frames, then flow
    lambda memory: PeakContactChange(memory=memory),
], ids=["frames", "flow", "peak"])
def test_a_cached_press_gives_the_rows_and_the_warnings_of_a_computed_one(make, presses, tmp_path):
    import warnings

    loader, videos, _, _ = presses
    videos = list(videos)
    videos[4] = np.full_like(videos[4], 100)  # a press without contact: the selector and the flow warn
    with warnings.catch_warnings(record=True) as plain_warnings:
        warnings.simplefilter("always")
        plain = make(None).fit_transform(videos)
    with warnings.catch_warnings(record=True):
        warnings.simplefilter("always")
        make(str(tmp_path)).fit_transform(videos)
    with warnings.catch_warnings(record=True) as hit_warnings:
        warnings.simplefilter("always")
        hit = make(str(tmp_path)).fit_transform(videos)
    np.testing.assert_array_equal(hit, plain)
    assert sorted(str(w.message) for w in hit_warnings) == sorted(str(w.message) for w in plain_warnings)
    n_rows, n_bytes = cache_size(str(tmp_path))
    assert n_rows >= N_PRESSES and n_bytes > 0


def test_a_change_to_the_code_that_computes_rows_invalidates_them(presses, counted_rows, tmp_path, monkeypatch):
    from sklearn_hardness.utils import _per_press

    _, videos, _, _ = presses
    ContactGeometryFeatures(memory=str(tmp_path)).fit_transform(videos)
    ContactGeometryFeatures(memory=str(tmp_path)).fit_transform(videos)
    assert len(counted_rows) == N_PRESSES
    monkeypatch.setattr(_per_press, "_package_fingerprint", lambda: "other code")
    ContactGeometryFeatures(memory=str(tmp_path)).fit_transform(videos)
    assert len(counted_rows) == 2 * N_PRESSES


def test_an_error_names_the_press_by_its_index_in_the_whole_sequence(presses, tmp_path):
    _, videos, _, _ = presses
    videos = list(videos)
    ContactGeometryFeatures(memory=str(tmp_path)).fit_transform(videos[:5])  # presses 0-4 cached
    videos[7] = np.zeros((4, 8), np.uint8)  # not a video; computed with the other presses the cache lacks
    with pytest.raises(ValueError, match=r"^video 7 must have shape"):
        ContactGeometryFeatures(memory=str(tmp_path)).fit_transform(videos)


def test_clear_cache_removes_the_rows_of_every_step_and_nothing_else(presses, tmp_path):
    _, videos, y, _ = presses
    folder = str(tmp_path)
    make_named_pipeline("contact_profile", memory=folder).fit(videos, y)
    PeakContactChange(memory=folder).fit_transform(videos)
    (tmp_path / "notes.txt").write_text("not ours")
    assert cache_size(folder)[0] == 2 * N_PRESSES
    assert len(clear_cache(folder)) == 1 and cache_size(folder) == (0, 0)
    assert (tmp_path / "notes.txt").read_text() == "not ours"
    assert clear_cache(folder) == [] and clear_cache(tmp_path / "nowhere") == []

