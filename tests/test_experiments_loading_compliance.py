"""The experiments' ``loading_compliance`` model: active sampling on each press's force and position.

The log Hertz compliance of every press is computed once per dataset (no
video is read); the median imputer and the scaler are fitted on each run's
initial training presses only; the head is the logistic regression sampled
from its Laplace posterior, refitted per iteration.
"""

import warnings

import numpy as np
import pytest
from sklearn.utils import Bunch

from sklearn_hardness._cli import main
from sklearn_hardness.datasets import make_presses
from sklearn_hardness.experiments import get_config, run_active_sampling
from sklearn_hardness.experiments._config import check_config, config_hash
from sklearn_hardness.experiments._data import prepare_inputs
from sklearn_hardness.experiments._run import _input_scaler, _rows
from sklearn_hardness.features import LoadingCompliance

SMALL = dict(n_initial=1, n_per_query=1, n_iterations=2, n_test=1, n_samples=5)


@pytest.fixture(scope="module")
def everyday():
    return make_presses("everyday", n_per_class=2, n_objects=9, class_ratio=[1, 1, 1], image_size=(32, 40),
                        codec=None, random_state=0)


def _never_rendered(data):
    """``data`` whose videos raise when read: the model must not need them."""
    class NoVideos:
        def __len__(self):
            return len(data.target)

        def __getitem__(self, i):
            raise AssertionError("loading_compliance read a video")

    return Bunch(**{**data, "videos": NoVideos()})


def test_inputs_are_the_log_hertz_compliance_of_force_and_position_without_any_video(everyday):
    cfg = check_config(get_config("silicone5", model="loading_compliance"))
    assert cfg["frame_size"] is None
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", UserWarning)
        inputs = prepare_inputs(_never_rendered(everyday), cfg, "loading_compliance", memory=False, verbose=0)
        expected = LoadingCompliance(features=["hertz_compliance"]).fit_transform(
            [np.column_stack([f, z]) for f, z in zip(everyday.force, everyday.position)])
    assert inputs.X.shape == (len(everyday.target), 1) and inputs.X.dtype == np.float32
    np.testing.assert_allclose(inputs.X, np.log(np.maximum(expected, 1e-3)), rtol=1e-6)
    assert config_hash(cfg) != config_hash(check_config(get_config("silicone5", model="contact_profile")))


def test_imputer_and_scaler_are_fitted_on_the_run_s_training_presses_only():
    X = np.array([[0.0], [1.0], [2.0], [np.nan], [10.0], [np.nan]], dtype=np.float32)
    train, test = np.arange(4), np.arange(4, 6)
    scale = _input_scaler(X[train], get_config("silicone5"), "loading_compliance")
    Z = _rows(X, train, scale)
    assert np.isfinite(Z).all()  # the short press of the training set gets the training median (1.0)
    np.testing.assert_allclose(Z.mean(), 0, atol=1e-6)
    mean, std = np.mean([0, 1, 2, 1]), np.std([0, 1, 2, 1])
    np.testing.assert_allclose(_rows(X, test, scale).ravel(), [(10 - mean) / std, (1 - mean) / std], rtol=1e-5)


def test_object_disjoint_runs_repeat_and_never_train_on_the_test_object(everyday):
    kw = dict(strategies=("thompson", "random"), model="loading_compliance", n_runs=1, memory=False, verbose=0,
              test_objects=["everyday-00-marble", "everyday-03-rubber-ball"], **SMALL)
    data = _never_rendered(everyday)
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", UserWarning)
        first = run_active_sampling(data, **kw)
        again = run_active_sampling(data, **kw)
    records = first.records
    assert len(records) == 4 and all(r["converged"] for r in records)
    for r in records:
        assert r["test_object"] not in r["initial_objects"]
        assert all(r["test_object"] not in drawn for drawn in r["drawn_objects"])
        assert len(r["accuracy"]) == SMALL["n_iterations"] + 1
    assert [r["accuracy"] for r in again.records] == [r["accuracy"] for r in records]
    assert [r["queried"] for r in again.records] == [r["queried"] for r in records]


def test_frames_and_ensembles_are_refused_and_quick_keeps_no_frames():
    with pytest.raises(ValueError, match="loading_compliance does not use .*force and position"):
        check_config(get_config("silicone5", model="loading_compliance", frame_size=(12, 16)))
    with pytest.raises(ValueError, match="loading_compliance's samples come from the Laplace posterior"):
        check_config(get_config("silicone5", model="loading_compliance", n_ensemble=3))
    assert check_config(get_config("silicone5", quick=True, model="loading_compliance"))["frame_size"] is None
    assert check_config(get_config("silicone5", quick=True, model="contact_profile"))["frame_size"] is None
    assert check_config(get_config("silicone5", quick=True))["frame_size"] == (12, 16)  # the ConvLSTM's


def test_a_dataset_without_position_is_an_error_that_says_what_to_give(everyday):
    no_position = Bunch(**{k: v for k, v in everyday.items() if k != "position"})
    with pytest.raises(ValueError, match="force_path and position_path"):
        prepare_inputs(no_position, check_config(get_config("silicone5", model="loading_compliance")),
                       "loading_compliance", memory=False, verbose=0)


def test_reproduce_runs_it_quick_on_the_everyday_preset(tmp_path, capsys):
    with pytest.warns(UserWarning, match="presses .* their figures are NaN"):  # the preset's cut-short videos
        assert main(["reproduce", "--dataset", "everyday", "--model", "loading_compliance", "--quick", "--n-runs",
                     "1", "--strategies", "thompson", "random", "--test-objects", "everyday-00-marble",
                     "--out", str(tmp_path / "out"), "--quiet"]) == 0
    text = capsys.readouterr().out
    assert "loading_compliance" in text and "refitted per iteration" in text and "thompson" in text


def test_model_baselines_run_quick_beside_a_video_model_each_with_its_own_frames(everyday):
    """``quick``'s frame size is the ConvLSTM's: a model that selects no frames keeps none, in the same call.

    Before, the baselines applied the quick frame size to every model and
    ``loading_compliance`` (or ``contact_profile``) failed in ``check_config``.
    """
    from sklearn_hardness.experiments import run_model_baselines

    with warnings.catch_warnings():
        warnings.simplefilter("ignore", UserWarning)
        result = run_model_baselines(everyday, models=("loading_compliance", "ofnn"), n_train_per_class=2,
                                     n_test_per_class=1, n_runs=1, quick=True, initial_epochs=2, memory=False,
                                     verbose=0)
    by_model = {r["key"]["model"]: r for r in result.records}
    assert set(by_model) == {"loading_compliance", "ofnn"}
    assert by_model["loading_compliance"]["train_loss"] is None  # a logistic head, no epochs
    assert len(by_model["ofnn"]["train_loss_curve"]) == 2
    assert result.config["frame_size"] == (12, 16)  # the runs' shared settings keep quick's frames
