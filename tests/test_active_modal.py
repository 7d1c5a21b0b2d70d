"""Our class-level strategies plug into modAL's ActiveLearner.

modAL is not a dependency of sklearn-hardness (its latest release pins
skorch 0.9); CI installs it with ``pip install --no-deps modAL-python``.
modAL >= 0.4 calls ``query_strategy(learner, X_pool, **kwargs)`` and unpacks
``(query_result, query_metrics)``; our strategies return
``(class_indices, scores)``.
"""

import numpy as np
import pytest
import torch
from modAL.models import ActiveLearner as ModalLearner

from sklearn_hardness.active import (
    bald_sampling,
    entropy_sampling,
    random_sampling,
    variance_sampling,
)

from ._active_net import MCDropoutNet, make_blobs, make_net


@pytest.fixture(scope="module")
def modal_learner():
    torch.manual_seed(0)
    X, y = make_blobs(n_per_class=10, seed=0)
    learner = ModalLearner(
        estimator=make_net(max_epochs=5), query_strategy=entropy_sampling,
        X_training=X, y_training=y,
    )
    return learner


@pytest.mark.parametrize(
    "strategy", [entropy_sampling, variance_sampling, bald_sampling, random_sampling]
)
@pytest.mark.parametrize("n_instances", [1, 2])
def test_modal_query_returns_our_class_indices(strategy, n_instances, modal_learner):
    X_test, _ = make_blobs(n_per_class=3, seed=1)
    modal_learner.query_strategy = strategy
    before = MCDropoutNet.n_mc_calls
    idx, rows = modal_learner.query(X_test, n_instances=n_instances, random_state=0)
    # modAL ran the strategy once (no fall-back re-run after a failed unpacking)
    assert MCDropoutNet.n_mc_calls - before == (0 if strategy is random_sampling else 1)
    expected, scores = strategy(modal_learner.estimator, X_test, n_instances=n_instances,
                                random_state=0)
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


def test_strategy_sees_through_modal_learner():
    """The strategy receives modAL's learner and finds the net in .estimator."""
    X, y = make_blobs(n_per_class=10, seed=2)
    learner = ModalLearner(estimator=make_net(max_epochs=3), query_strategy=variance_sampling,
                           X_training=X, y_training=y)
    X_test, _ = make_blobs(n_per_class=2, seed=3)
    a = variance_sampling(learner, X_test, n_samples=9, random_state=4)
    b = variance_sampling(learner.estimator, X_test, n_samples=9, random_state=4)
    np.testing.assert_array_equal(a[0], b[0])
    np.testing.assert_allclose(a[1], b[1])
    # (modAL 0.4.2's own ``teach`` calls ``check_X_y(force_all_finite=...)``,
    # which scikit-learn >= 1.8 no longer accepts: use our ActiveLearner to teach.)
