"""Saving a trained net or pipeline and running it elsewhere ("train here, run on the robot")."""

import pickle

import numpy as np
import pytest
import torch

from sklearn_hardness.models import ConvLSTMClassifier, OFNNClassifier, make_convlstm_pipeline

from ._exp_data import tiny_presses

pytestmark = pytest.mark.torch_threads(1)


def _frames(n=12, seed=0):
    rng = np.random.default_rng(seed)
    y = np.array(["soft", "hard", "medium"])[np.arange(n) % 3]
    X = rng.normal(loc=5.0, scale=2.0, size=(n, 3, 6, 8, 1)).astype(np.float32)
    return X, y


def test_convlstm_save_params_carries_input_standardisation(tmp_path):
    X, y = _frames()
    net = ConvLSTMClassifier(max_epochs=2, random_state=0).fit(X, y)
    # statistics of the training input, kept in the module's buffers
    np.testing.assert_allclose(net.input_mean_, [X.mean()], rtol=1e-4)
    np.testing.assert_allclose(net.module_.input_scale.numpy(), [X.std()], rtol=1e-4)
    f = tmp_path / "params.pt"
    net.save_params(f_params=str(f))
    fresh = ConvLSTMClassifier(classes=net.classes_).initialize()  # initialize, then load
    fresh.load_params(f_params=str(f))
    np.testing.assert_array_equal(fresh.input_mean_, net.input_mean_)
    np.testing.assert_array_equal(fresh.predict_proba(X), net.predict_proba(X))
    np.testing.assert_array_equal(
        fresh.predict_proba_samples(X, n_samples=5, random_state=1),
        net.predict_proba_samples(X, n_samples=5, random_state=1),
    )
    np.testing.assert_array_equal(fresh.predict(X), net.predict(X))
    # the stored statistics survive warm-start training on other data
    fresh.partial_fit(X * 10, y, epochs=1)
    np.testing.assert_array_equal(fresh.input_mean_, net.input_mean_)


def test_torch_load_is_weights_only(tmp_path, monkeypatch):
    X, y = _frames()
    net = OFNNClassifier(max_epochs=1, random_state=0).fit(X.reshape(len(X), -1), y)
    f = tmp_path / "params.pt"
    net.save_params(f_params=str(f))
    calls = []
    real_load = torch.load

    def spy(*args, **kwargs):
        calls.append(kwargs.get("weights_only"))
        return real_load(*args, **kwargs)

    monkeypatch.setattr(torch, "load", spy)
    OFNNClassifier(classes=net.classes_).load_params(f_params=str(f))
    assert calls and all(w is True for w in calls)


def test_fitted_pipeline_pickles_with_identical_predictions():
    data = tiny_presses()
    videos = data.videos[:20]
    pipe = make_convlstm_pipeline(frame_size=(8, 10), max_epochs=2, random_state=0).fit(videos, data.target[:20])
    restored = pickle.loads(pickle.dumps(pipe))
    np.testing.assert_array_equal(restored.predict_proba(videos), pipe.predict_proba(videos))
    np.testing.assert_array_equal(
        restored.predict_proba_samples(videos[:4], n_samples=6, random_state=3),
        pipe.predict_proba_samples(videos[:4], n_samples=6, random_state=3),
    )


def test_user_guide_code_runs():
    import doctest
    from pathlib import Path

    page = Path(__file__).resolve().parents[1] / "docs" / "user_guide" / "persistence.rst"
    result = doctest.testfile(str(page), module_relative=False, optionflags=doctest.ELLIPSIS)
    assert result.attempted > 10 and result.failed == 0
