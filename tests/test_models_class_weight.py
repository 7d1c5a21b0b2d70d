"""class_weight: as in scikit-learn, applied as the criterion's weight."""

import numpy as np
import pytest
from sklearn.metrics import balanced_accuracy_score
from sklearn.utils.class_weight import compute_class_weight

from sklearn_hardness.models import ConvLSTMClassifier, DINOv2NNClassifier, OFNNClassifier

pytestmark = pytest.mark.torch_threads(1)


def _imbalanced(n_major=90, n_minor=10, seed=0):
    """Two overlapping Gaussian classes, 9:1."""
    rng = np.random.default_rng(seed)
    y = np.array(["hard"] * n_major + ["soft"] * n_minor)
    X = rng.normal(size=(len(y), 4)).astype(np.float32)
    X[y == "soft", 0] += 1.5
    return X, y


@pytest.mark.parametrize("cls", [OFNNClassifier, DINOv2NNClassifier])
@pytest.mark.parametrize("class_weight", ["balanced", {"hard": 1.0, "soft": 5.0}])
def test_weights_equal_sklearns(cls, class_weight):
    X, y = _imbalanced()
    net = cls(class_weight=class_weight, max_epochs=1, random_state=0).fit(X, y)
    expected = compute_class_weight(class_weight, classes=np.unique(y), y=y)
    np.testing.assert_allclose(net.class_weight_, expected, rtol=1e-6)
    np.testing.assert_allclose(net.criterion_.weight.numpy(), expected, rtol=1e-6)
    assert cls(max_epochs=1, random_state=0).fit(X, y).criterion_.weight is None


def test_convlstm_takes_class_weight():
    rng = np.random.default_rng(0)
    X = rng.normal(size=(8, 2, 5, 6, 1)).astype(np.float32)
    y = np.array([0] * 6 + [1] * 2)
    net = ConvLSTMClassifier(class_weight="balanced", filters=(2,), max_epochs=1, random_state=0).fit(X, y)
    np.testing.assert_allclose(net.criterion_.weight.numpy(), [8 / 12, 8 / 4], rtol=1e-6)


def test_balanced_weights_raise_minority_recall():
    X, y = _imbalanced()
    X_test, y_test = _imbalanced(n_major=300, n_minor=300, seed=1)
    scores = {}
    for cw in (None, "balanced"):
        net = OFNNClassifier(class_weight=cw, hidden_units=16, lr=1e-2, max_epochs=20, random_state=0).fit(X, y)
        scores[cw] = balanced_accuracy_score(y_test, net.predict(X_test))
    assert scores["balanced"] > scores[None] + 0.1, scores
