"""Active sampling with the library's own MC-dropout nets (OFNNClassifier, ConvLSTMClassifier)."""

import numpy as np
import pytest
from sklearn.pipeline import make_pipeline
from sklearn.preprocessing import StandardScaler

from sklearn_hardness.active import (
    ActiveLearner,
    PressOracle,
    as_modal_strategy,
    bald_sampling,
    class_uncertainty,
    entropy_sampling,
    random_sampling,
    variance_sampling,
)
from sklearn_hardness.metrics import hardness_mae
from sklearn_hardness.models import ConvLSTMClassifier, OFNNClassifier

from ._active_net import make_blobs

NAMES = np.array(["hard", "medium", "soft"])
HARDNESS = {"hard": 0.44, "medium": 0.79, "soft": 1.13}


@pytest.fixture(scope="module")
def pool():
    X, y = make_blobs(n_per_class=30, n_features=12, spread=1.5, seed=0)
    X = X * 4 + 20  # raw scale: the pipeline's scaler matters
    oracle = PressOracle(X, NAMES[y], random_state=0)
    X_test, y_test = oracle.press(NAMES, 6)
    return oracle, X_test, y_test


@pytest.fixture(scope="module")
def pipe(pool):
    oracle, _, _ = pool
    net = OFNNClassifier(max_epochs=10, random_state=0)
    return make_pipeline(StandardScaler(), net).fit(oracle.X_pool, oracle.y_pool)


@pytest.mark.parametrize(
    "strategy", [entropy_sampling, variance_sampling, bald_sampling, random_sampling]
)
def test_strategies_on_ofnn_pipeline(strategy, pipe, pool):
    _, X_test, _ = pool
    idx, scores = as_modal_strategy(strategy, n_samples=16)(pipe, X_test, n_instances=2,
                                                             random_state=0)
    assert idx.shape == (2,) and scores.shape == (3,)
    if strategy is not random_sampling:
        Xt = pipe[:-1].transform(X_test)
        # replay the adapter's MC seed
        seed = int(np.random.RandomState(0).randint(np.iinfo(np.int32).max, size=2)[0])
        p = pipe[-1].predict_proba_samples(Xt, n_samples=16, random_state=seed)
        kind = strategy.__name__.split("_")[0]
        np.testing.assert_allclose(scores, class_uncertainty(p, kind))


def test_algorithm_1_with_ofnn(pool):
    oracle, X_test, y_test = pool
    oracle = PressOracle(oracle.X_pool, oracle.y_pool, random_state=1)
    X0, y0 = oracle.initial(5)
    learner = ActiveLearner(
        make_pipeline(StandardScaler(), OFNNClassifier(random_state=0)),
        "variance", initial_epochs=30, epochs_per_query=15, max_reservoir=20,
        n_samples=20, random_state=0,
    ).fit(X0, y0)
    np.testing.assert_array_equal(learner.classes_, ["hard", "medium", "soft"])
    net = learner.estimator_[-1]
    assert learner.initial_train_loss_ == pytest.approx(net.final_train_loss_)
    acc, mae = [learner.score(X_test, y_test)], [hardness_mae(y_test, learner.predict(X_test), HARDNESS)]
    for _ in range(3):
        idx, _ = learner.query(X_test)
        learner.teach(*oracle.press(learner.classes_[idx[0]], 5))
        acc.append(learner.score(X_test, y_test))
        mae.append(hardness_mae(y_test, learner.predict(X_test), HARDNESS))
    # warm start: the net's history runs on through the iterations
    assert len(net.history) == 30 + 3 * 15
    assert [h["train_size"] for h in learner.history_ if h["event"] == "teach"] == [20, 20, 20]
    assert learner.uncertainty_history("variance").shape == (3,)
    assert acc[-1] >= 0.8 and mae[-1] < 0.15  # separable blobs


def test_convlstm_reservoir_of_frames():
    rng = np.random.default_rng(0)
    X = rng.random((24, 3, 8, 10, 1), dtype=np.float32)
    y = np.repeat([0, 1, 2], 8)
    X[y == 1] += 0.5
    X[y == 2] -= 0.5
    oracle = PressOracle(X, y, random_state=0)
    X_test, y_test = oracle.press([0, 1, 2], 2)
    X0, y0 = oracle.initial(2)
    learner = ActiveLearner(
        ConvLSTMClassifier(filters=(2, 2), random_state=0), "entropy",
        initial_epochs=2, epochs_per_query=1, max_reservoir=8, n_samples=4,
        random_state=0,
    ).fit(X0, y0)
    idx, scores = learner.query(X_test)
    learner.teach(*oracle.press(learner.classes_[idx[0]], 3))
    assert learner.reservoir_X_.shape == (9, 3, 8, 10, 1)
    assert learner.history_[-1]["train_size"] == 8
    assert np.isfinite(learner.history_[-1]["train_loss"])
