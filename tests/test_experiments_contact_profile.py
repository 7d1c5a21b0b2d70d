"""The experiments' ``contact_profile_nn`` and ``contact_profile`` models (issue 20): active sampling on the
features that carry over.

ContactProfileFeatures of the whole press video (no frame selection), an
MC-dropout MLP (``contact_profile_nn``) or a logistic regression sampled from
its Laplace posterior (``contact_profile``), and a per-feature
standardisation fitted on each run's initial training presses only.
"""

import numpy as np
import pytest

from sklearn_hardness.datasets import make_presses
from sklearn_hardness.experiments import get_config, run_active_sampling
from sklearn_hardness.experiments._config import check_config, config_hash
from sklearn_hardness.experiments._data import prepare_inputs
from sklearn_hardness.experiments._run import _input_scaler, _rows

from ._presets import EVERYDAY_BEFORE

SMALL = dict(n_initial=1, n_per_query=1, n_iterations=2, n_test=1, initial_epochs=20, epochs_per_query=5,
             n_samples=5)


@pytest.fixture(scope="module")
def everyday():
    return make_presses("everyday", n_per_class=2, n_objects=9, class_ratio=[1, 1, 1], image_size=(32, 40),
                        codec=None, random_state=0, **EVERYDAY_BEFORE)  # test objects named by their kind


def test_inputs_are_the_contact_profile_features_of_whole_videos(everyday):
    cfg = check_config(get_config("silicone5", model="contact_profile_nn"))
    assert cfg["frame_size"] is None  # no frame selection, and the hash says so
    inputs = prepare_inputs(everyday, cfg, "contact_profile_nn", memory=False, verbose=0)
    assert inputs.X.shape == (len(everyday.target), 12) and inputs.X.dtype == np.float32
    from sklearn_hardness.features import ContactProfileFeatures

    expected = ContactProfileFeatures().fit_transform(everyday.videos)
    np.testing.assert_allclose(inputs.X, expected, rtol=1e-6)
    assert config_hash(cfg) != config_hash(check_config(get_config("silicone5", model="ofnn")))


def test_standardisation_is_fitted_on_the_run_s_training_presses_only():
    rng = np.random.default_rng(0)
    X = (rng.normal(size=(40, 10)) * np.logspace(-2, 2, 10) + 5).astype(np.float32)
    train, test = np.arange(30), np.arange(30, 40)
    scale = _input_scaler(X[train], get_config("silicone5"), "contact_profile_nn")
    Z = _rows(X, train, scale)
    np.testing.assert_allclose(Z.mean(axis=0), 0, atol=1e-4)
    np.testing.assert_allclose(Z.std(axis=0), 1, rtol=1e-4)
    # test presses get the training presses' statistics, not their own
    X64 = X.astype(np.float64)
    expected = (X64[test] - X64[train].mean(0)) / X64[train].std(0)
    np.testing.assert_allclose(_rows(X, test, scale), expected, rtol=1e-4, atol=2e-4)
    assert not np.allclose(_rows(X, test, scale), (X64[test] - X64[test].mean(0)) / X64[test].std(0), atol=0.1)
    assert _input_scaler(X[train], get_config("silicone5"), "ofnn") is None


@pytest.mark.parametrize("model", ["contact_profile_nn", "contact_profile"])
def test_object_disjoint_runs_with_the_contact_profile_models_repeat(everyday, tmp_path, model):
    kw = dict(strategies=("entropy", "random"), model=model, n_runs=1, memory=tmp_path, verbose=0,
              test_objects=["everyday-00-marble", "everyday-01-mug"], **SMALL)
    first = run_active_sampling(everyday, **kw)
    records = first.records
    assert len(records) == 4 and all(r["converged"] for r in records)
    assert {r["test_object"] for r in records} == {"everyday-00-marble", "everyday-01-mug"}
    for r in records:  # the test object is never trained on
        assert r["test_object"] not in r["initial_objects"]
        assert all(r["test_object"] not in drawn for drawn in r["drawn_objects"])
        assert len(r["accuracy"]) == SMALL["n_iterations"] + 1
    again = run_active_sampling(everyday, **kw)
    assert [r["accuracy"] for r in again.records] == [r["accuracy"] for r in records]
    assert [r["queried"] for r in again.records] == [r["queried"] for r in records]


@pytest.mark.parametrize("model", ["contact_profile_nn", "contact_profile"])
def test_frame_settings_are_refused_for_the_contact_profile_models(model):
    with pytest.raises(ValueError, match=f"{model} does not use"):
        check_config(get_config("silicone5", model=model, frame_size=(12, 16)))
    with pytest.raises(ValueError, match=f"{model} does not use"):
        check_config(get_config("silicone5", model=model, crop_contact=0.5))


def test_contact_profile_is_the_laplace_logistic_head_without_net_settings():
    from sklearn_hardness.experiments._models import make_estimator
    from sklearn_hardness.models import LaplaceLogisticRegression

    cfg = check_config(get_config("silicone5", model="contact_profile"))
    est = make_estimator("contact_profile", cfg, seed=7, n_classes=3)
    assert type(est) is LaplaceLogisticRegression
    # the experiments weigh every class alike, as for the nets; the seed reaches the estimator
    assert (est.class_weight, est.random_state, est.max_iter) == (None, 7, 2000)
    with pytest.raises(ValueError, match="n_ensemble applies to the nets"):
        check_config(get_config("silicone5", model="contact_profile", n_ensemble=3))
    # the same cached features as contact_profile_nn: one feature file serves both
    from sklearn_hardness.experiments._models import feature_params

    assert feature_params(cfg, "contact_profile") == feature_params(cfg, "contact_profile_nn")


@pytest.mark.slow
def test_features_of_a_preset_are_cached_on_disk(tmp_path, monkeypatch):
    from sklearn_hardness.features import ContactProfileFeatures
    from sklearn_hardness.utils._per_press import cache_size

    cfg = check_config(get_config("silicone5", model="contact_profile_nn", image_size=(32, 40)))
    first = prepare_inputs("everyday", cfg, "contact_profile_nn", memory=str(tmp_path), verbose=0)
    assert cache_size(tmp_path)[0] == len(first.y)  # one row per press
    computed, original = [], ContactProfileFeatures._transform_presses
    monkeypatch.setattr(ContactProfileFeatures, "_transform_presses",
                        lambda self, X: computed.append(len(X)) or original(self, X))
    again = prepare_inputs("everyday", cfg, "contact_profile_nn", memory=str(tmp_path), verbose=0)
    assert computed == []  # every press read from the disk
    np.testing.assert_array_equal(again.X, first.X)
    assert first.object_id is not None and len(set(first.object_id)) == 42
