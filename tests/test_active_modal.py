"""Our class-level strategies plug into modAL's ActiveLearner through as_modal_strategy.

modAL is not a dependency of sklearn-hardness (its latest release pins
skorch 0.9); CI installs it with ``pip install --no-deps modAL-python``.
modAL >= 0.4 calls ``query_strategy(learner, X_pool, **kwargs)`` and unpacks
``(query_result, query_metrics)``; the adapter returns
``(class_indices, scores)``.
"""

import numpy as np
import pytest
import torch
from modAL.models import ActiveLearner as ModalLearner
from sklearn.linear_model import LogisticRegression
from sklearn.pipeline import Pipeline, make_pipeline
from sklearn.preprocessing import StandardScaler

from sklearn_hardness.active import (
    as_modal_strategy,
    bald_sampling,
    entropy_sampling,
    margin_sampling,
    mc_variance_sampling,
    random_sampling,
    variance_sampling,
)
from sklearn_hardness.utils._param_validation import InvalidParameterError

from ._active_net import MCDropoutNet, make_blobs, make_net

STRATEGIES = [entropy_sampling, variance_sampling, bald_sampling, margin_sampling,
              mc_variance_sampling, random_sampling]


def _replay(random_state):
    """The two seeds the adapter draws from an int random_state: MC masks, then strategy."""
    return [int(s) for s in np.random.RandomState(random_state).randint(np.iinfo(np.int32).max, size=2)]


@pytest.fixture(scope="module")
def modal_learner():
    torch.manual_seed(0)
    X, y = make_blobs(n_per_class=10, seed=0)
    learner = ModalLearner(
        estimator=make_net(max_epochs=5), query_strategy=as_modal_strategy(entropy_sampling),
        X_training=X, y_training=y,
    )
    return learner


@pytest.mark.parametrize("strategy", STRATEGIES)
@pytest.mark.parametrize("n_instances", [1, 2])
def test_modal_query_returns_our_class_indices(strategy, n_instances, modal_learner):
    X_test, _ = make_blobs(n_per_class=3, seed=1)
    modal_learner.query_strategy = as_modal_strategy(strategy, n_samples=12)
    before = MCDropoutNet.n_mc_calls
    idx, rows = modal_learner.query(X_test, n_instances=n_instances, random_state=0)
    # modAL ran the MC passes once (no fall-back re-run after a failed unpacking)
    assert MCDropoutNet.n_mc_calls - before == 1
    mc_seed, strategy_seed = _replay(0)
    p = modal_learner.estimator.predict_proba_samples(X_test, n_samples=12, random_state=mc_seed)
    expected, scores = strategy(p, n_instances, random_state=strategy_seed)
    np.testing.assert_array_equal(idx, expected)
    assert idx.shape == (n_instances,)
    # modAL also hands back X_test[idx]: rows of X_test, meaningless for class indices
    np.testing.assert_array_equal(rows, X_test[idx])
    # return_metrics gives our per-class scores
    idx2, _, metrics = modal_learner.query(X_test, n_instances=n_instances, random_state=0,
                                           return_metrics=True)
    np.testing.assert_array_equal(idx2, expected)
    np.testing.assert_allclose(metrics, scores)
    assert metrics.shape == (3,)


def test_adapter_sees_through_modal_learner_and_pipelines():
    """The adapter receives modAL's learner and finds the net in .estimator;
    a Pipeline's feature steps run before the net's MC passes."""
    X, y = make_blobs(n_per_class=10, seed=2)
    learner = ModalLearner(estimator=make_net(max_epochs=3),
                           query_strategy=as_modal_strategy(variance_sampling, n_samples=9),
                           X_training=X, y_training=y)
    X_test, _ = make_blobs(n_per_class=2, seed=3)
    query = as_modal_strategy(variance_sampling, n_samples=9)
    a = query(learner, X_test, random_state=4)
    b = query(learner.estimator, X_test, random_state=4)
    np.testing.assert_array_equal(a[0], b[0])
    np.testing.assert_allclose(a[1], b[1])
    # (modAL 0.4.2's own ``teach`` calls ``check_X_y(force_all_finite=...)``,
    # which scikit-learn >= 1.8 no longer accepts: use our ActiveLearner to teach.)
    torch.manual_seed(0)
    pipe = make_pipeline(StandardScaler(), make_net(max_epochs=5)).fit(X * 10 + 100, y)
    Xt = pipe[:-1].transform(X_test * 10 + 100)
    mc_seed, _ = _replay(5)
    p = pipe[-1].predict_proba_samples(Xt, n_samples=9, random_state=mc_seed)
    _, scores = query(pipe, X_test * 10 + 100, random_state=5)
    np.testing.assert_allclose(scores, variance_sampling(p)[1])
    # a "passthrough" step is skipped as scikit-learn's Pipeline skips it
    passthrough = Pipeline([("nothing", "passthrough"), ("net", pipe[-1])])
    np.testing.assert_allclose(query(passthrough, Xt, random_state=5)[1], scores)


def test_adapter_bad_input():
    X, y = make_blobs(n_per_class=5, seed=0)
    lr = LogisticRegression().fit(X, y)
    query = as_modal_strategy(entropy_sampling)
    with pytest.raises(TypeError, match="no predict_proba_samples"):
        query(lr, X[:3])
    with pytest.raises(TypeError, match="no predict_proba_samples"):
        query(make_pipeline(StandardScaler(), lr).fit(X, y), X[:3])
    with pytest.raises(ValueError, match="X_test is empty"):
        query(make_net().fit(X, y), X[:0])
    with pytest.raises(InvalidParameterError, match="'n_samples' parameter"):
        as_modal_strategy(entropy_sampling, n_samples=0)
    with pytest.raises(InvalidParameterError, match="'strategy' parameter"):
        as_modal_strategy("entropy")
