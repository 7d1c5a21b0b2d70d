"""The paper's convergence rule."""

import warnings

import numpy as np
import pytest
import torch
from sklearn.exceptions import ConvergenceWarning

from sklearn_hardness.models import OFNNClassifier, check_convergence, is_converged


def test_rule_on_values():
    assert is_converged(0.99) and is_converged(1.0)
    assert not is_converged(1.01)
    assert not is_converged(float("nan")) and not is_converged(float("inf"))
    assert is_converged(1.5, threshold=2.0)


def test_rule_on_nets():
    torch.set_num_threads(1)
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
