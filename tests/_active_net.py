"""A small, real Monte-Carlo-dropout classifier for the active-sampling tests.

A skorch ``NeuralNetClassifier`` around an MLP with dropout whose
``predict_proba_samples`` runs the module with dropout on, as the library's
nets do. It is trained for real in the tests (a few epochs on blobs).
``CentroidMC`` is a much cheaper stand-in for tests that run many learners.
"""

import numpy as np
import torch
from sklearn.base import BaseEstimator, ClassifierMixin
from skorch import NeuralNetClassifier
from torch import nn


class MLP(nn.Module):
    def __init__(self, n_features=4, n_hidden=32, n_classes=3, dropout=0.3):
        super().__init__()
        self.net = nn.Sequential(
            nn.Linear(n_features, n_hidden),
            nn.ReLU(),
            nn.Dropout(dropout),
            nn.Linear(n_hidden, n_classes),
        )

    def forward(self, X):
        return self.net(X)


class MCDropoutNet(NeuralNetClassifier):
    """NeuralNetClassifier with MC-dropout sampling; counts its MC calls."""

    n_mc_calls = 0

    def predict_proba_samples(self, X, n_samples=50, random_state=None):
        type(self).n_mc_calls += 1
        X = torch.as_tensor(np.asarray(X, dtype=np.float32))
        module = self.module_
        with torch.random.fork_rng(devices=[]):
            if random_state is not None:
                torch.manual_seed(int(random_state))
            module.train()  # dropout on
            try:
                with torch.no_grad():
                    Xr = X.repeat(n_samples, *([1] * (X.ndim - 1)))  # batch the passes
                    p = torch.softmax(module(Xr), dim=-1)
            finally:
                module.eval()
        return p.reshape(n_samples, X.shape[0], -1).numpy()


def make_net(n_features=4, n_classes=3, dropout=0.3, max_epochs=5, **kwargs):
    params = dict(
        module__n_features=n_features,
        module__n_classes=n_classes,
        module__dropout=dropout,
        criterion=nn.CrossEntropyLoss,
        optimizer=torch.optim.Adam,
        lr=0.02,
        batch_size=16,
        max_epochs=max_epochs,
        train_split=None,
        iterator_train__shuffle=True,
        verbose=0,
    )
    params.update(kwargs)
    return MCDropoutNet(MLP, **params)


def make_blobs(n_per_class=30, n_classes=3, n_features=4, spread=1.0, seed=0):
    """Gaussian blobs: class c centred at 3*e_c (so classes are separable)."""
    rng = np.random.default_rng(seed)
    X, y = [], []
    for c in range(n_classes):
        centre = np.zeros(n_features)
        centre[c % n_features] = 3.0
        X.append(centre + spread * rng.standard_normal((n_per_class, n_features)))
        y.append(np.full(n_per_class, c))
    return np.concatenate(X).astype(np.float32), np.concatenate(y)


class CentroidMC(ClassifierMixin, BaseEstimator):
    """A cheap MC classifier: softmax of minus squared distances to class centroids,
    with seeded Gaussian noise on the logits standing in for dropout."""

    def __init__(self, noise=0.5):
        self.noise = noise

    def fit(self, X, y):
        self.classes_ = np.unique(y)
        self.centroids_ = np.stack([X[y == c].mean(axis=0) for c in self.classes_])
        self.n_train_ = len(y)
        return self

    def _logits(self, X):
        return -((X[:, None, :] - self.centroids_[None]) ** 2).sum(-1)

    def predict_proba(self, X):
        z = self._logits(X)
        e = np.exp(z - z.max(axis=1, keepdims=True))
        return e / e.sum(axis=1, keepdims=True)

    def predict_proba_samples(self, X, n_samples=50, random_state=None):
        z = self._logits(X)[None] + self.noise * np.random.default_rng(random_state).normal(
            size=(n_samples, len(X), len(self.classes_)))
        e = np.exp(z - z.max(axis=2, keepdims=True))
        return e / e.sum(axis=2, keepdims=True)
