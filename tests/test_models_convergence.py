"""The paper's convergence rule."""

import warnings

import numpy as np
import pytest
from sklearn.exceptions import ConvergenceWarning

from sklearn_hardness.models import OFNNClassifier, is_converged
from sklearn_hardness.models._convergence import check_convergence


def test_rule_on_values():
    assert is_converged(0.99) and is_converged(1.0)
    assert not is_converged(1.01)
    assert not is_converged(float("nan")) and not is_converged(float("inf"))
    assert is_converged(1.5, threshold=2.0)


@pytest.mark.torch_threads(1)
def test_rule_on_nets():
    rng = np.random.default_rng(0)
    X = rng.normal(size=(30, 5)).astype(np.float32)
    y = np.arange(30) % 3
    X[:, 0] += 3 * y
    good = OFNNClassifier(max_epochs=40, lr=1e-2, random_state=0).fit(X, y)
    assert good.final_train_loss_ == good.history[-1, "train_loss"]
    assert is_converged(good)
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        assert check_convergence(good)
    # one epoch at a tiny learning rate on 3 classes stays near log(3) > 1
    bad = OFNNClassifier(max_epochs=1, lr=1e-6, random_state=0).fit(X * 10, y)
    assert bad.final_train_loss_ > 1
    assert not is_converged(bad)
    with pytest.warns(ConvergenceWarning, match="did not converge"):
        assert not check_convergence(bad)


def test_rule_rejects_unfitted():
    with pytest.raises(TypeError, match="trained classifier"):
        is_converged(OFNNClassifier())
    with pytest.raises(TypeError):
        is_converged("1.0")


def test_chance_scaled_threshold_keeps_the_papers_fraction_of_chance_loss():
    from sklearn_hardness.utils._chance_threshold import chance_scaled_threshold

    assert chance_scaled_threshold(5) == 1.0  # exactly the paper's rule at its 5 classes
    assert chance_scaled_threshold(9) == pytest.approx(np.log(9) / np.log(5))
    assert chance_scaled_threshold(3) == pytest.approx(np.log(3) / np.log(5))
    for k in (2, 3, 9, 30):  # the same fraction of chance loss ln K at every K
        assert chance_scaled_threshold(k) / np.log(k) == pytest.approx(1 / np.log(5))
    assert chance_scaled_threshold(10, reference_classes=10, reference_threshold=0.7) == 0.7
    assert chance_scaled_threshold(4, reference_classes=2, reference_threshold=0.5) == pytest.approx(1.0)
    for bad in ({"n_classes": 1}, {"n_classes": 2.5}, {"n_classes": 3, "reference_classes": 1},
                {"n_classes": 3, "reference_threshold": 0}):
        with pytest.raises(ValueError):
            chance_scaled_threshold(**bad)


def test_chance_threshold_in_the_rule():
    # a loss of 1.3: not converged by the paper's fixed rule, converged at 9 classes (1.365), not at 3
    assert not is_converged(1.3)
    assert is_converged(1.3, "chance", n_classes=9)
    assert not is_converged(0.9, "chance", n_classes=3) and is_converged(0.6, "chance", n_classes=3)
    assert is_converged(1.0, "chance", n_classes=5) and not is_converged(1.01, "chance", n_classes=5)
    with pytest.warns(ConvergenceWarning, match="1.3 > 0.6826"):
        assert not check_convergence(1.3, "chance", n_classes=3)
    with pytest.raises(ValueError, match="number of classes"):
        is_converged(1.3, "chance")
    with pytest.raises(ValueError, match="only with threshold"):
        is_converged(1.3, 1.0, n_classes=9)
    with pytest.raises(ValueError, match='"chance"'):
        is_converged(1.3, "auto")


def test_chance_threshold_reads_the_classes_of_a_net():
    class Fitted:  # what the rule reads of a fitted classifier
        final_train_loss_ = 1.3

        def __init__(self, n_classes):
            self.classes_ = np.arange(n_classes)

    assert is_converged(Fitted(9), "chance") and not is_converged(Fitted(5), "chance")
    assert not is_converged(Fitted(9), "chance", n_classes=5)  # an explicit n_classes wins
