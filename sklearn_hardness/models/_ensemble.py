"""Uncertainty from an ensemble of independently seeded classifiers: :class:`EnsembleClassifier`."""

from __future__ import annotations

import numbers

import numpy as np
from joblib import Parallel, delayed
from sklearn.base import BaseEstimator, ClassifierMixin, _fit_context, clone
from sklearn.utils._param_validation import HasMethods, Interval, validate_parameter_constraints
from sklearn.utils.validation import check_is_fitted

from ..utils._random import draw_seeds, set_random_states

__all__ = ["EnsembleClassifier"]


def _fit_member(est, X, y, fit_params):
    return est.fit(X, y, **fit_params)


def _partial_fit_member(est, X, y, kwargs):
    return est.partial_fit(X, y, **kwargs)


class EnsembleClassifier(ClassifierMixin, BaseEstimator):
    """Several copies of a classifier with different seeds; their spread is the uncertainty.

    An alternative to Monte-Carlo dropout as the source of
    ``predict_proba_samples``: each member is a clone of ``estimator`` whose
    ``random_state`` parameters (its own and any nested ``*__random_state``)
    are set to a seed of its own, so the members differ in initial weights,
    batch order and dropout masks during training. A "sample" is one
    member's (deterministic) ``predict_proba``, so every strategy of
    :mod:`sklearn_hardness.active` works unchanged. Deep ensembles are often
    better calibrated than MC dropout in active learning (Beluch et al.,
    CVPR 2018), at ``n_estimators`` times the training cost; on frozen
    features (OFNN, DINOv2NN) the members are small heads on the same cached
    features, so that cost is small.

    Parameters
    ----------
    estimator : classifier
        The member to copy, e.g. :class:`OFNNClassifier`. It needs
        ``predict_proba``.
    n_estimators : int, default=5
        Number of members.
    random_state : int, RandomState instance or None, default=None
        Draws the members' seeds.
    n_jobs : int or None, default=None
        Members trained in parallel (:class:`joblib.Parallel`).

    Attributes
    ----------
    estimators_ : list of estimators
        The trained members.
    seeds_ : ndarray of shape (n_estimators,)
        The seed given to each member.
    classes_ : ndarray of shape (n_classes,)
    n_features_in_ : int
        Only when the members have it.

    See Also
    --------
    MCDropoutClassifierBase.predict_proba_samples : MC dropout, one net.

    Notes
    -----
    :class:`~sklearn_hardness.active.ActiveLearner` trains an ensemble of
    skorch nets like one net: ``partial_fit(X, y, classes=..., epochs=...)``
    continues every member from its current weights.

    Examples
    --------
    >>> from sklearn.datasets import make_blobs
    >>> from sklearn_hardness.models import EnsembleClassifier, OFNNClassifier
    >>> X, y = make_blobs(60, n_features=4, centers=3, random_state=0)
    >>> ens = EnsembleClassifier(OFNNClassifier(hidden_units=8, max_epochs=20, lr=0.05),
    ...                          n_estimators=3, random_state=0).fit(X.astype("float32"), y)
    >>> ens.predict_proba_samples(X[:2].astype("float32")).shape  # (members, presses, classes)
    (3, 2, 3)
    """

    _parameter_constraints = {
        "estimator": [HasMethods(["fit", "predict_proba"])],
        "n_estimators": [Interval(numbers.Integral, 1, None, closed="left")],
        "random_state": ["random_state"],
        "n_jobs": [numbers.Integral, None],
    }

    def __init__(self, estimator, *, n_estimators=5, random_state=None, n_jobs=None):
        self.estimator = estimator
        self.n_estimators = n_estimators
        self.random_state = random_state
        self.n_jobs = n_jobs

    def _new_members(self):
        self.seeds_ = np.array(draw_seeds(self.random_state, self.n_estimators))
        return [set_random_states(clone(self.estimator), s) for s in self.seeds_]

    def _set_classes(self):
        classes = [np.asarray(m.classes_) for m in self.estimators_]
        if any(c.shape != classes[0].shape or np.any(c != classes[0]) for c in classes[1:]):
            raise ValueError(
                "the members learned different classes; pass classes=[...] to the estimator so "
                "that every member knows all of them."
            )
        self.classes_ = classes[0]
        if hasattr(self.estimators_[0], "n_features_in_"):
            self.n_features_in_ = self.estimators_[0].n_features_in_

    @_fit_context(prefer_skip_nested_validation=False)
    def fit(self, X, y, **fit_params):
        """Train every member from scratch on ``(X, y)``.

        Parameters
        ----------
        X : array-like
            Input of ``estimator``.
        y : array-like of shape (n_samples,)
        **fit_params
            Passed to each member's ``fit``.

        Returns
        -------
        self
        """
        members = self._new_members()
        self.estimators_ = Parallel(n_jobs=self.n_jobs, prefer="threads")(
            delayed(_fit_member)(m, X, y, fit_params) for m in members
        )
        self._set_classes()
        return self

    def partial_fit(self, X, y, classes=None, **kwargs):
        """Continue training every member (the first call creates them).

        For members that are skorch nets, ``epochs=`` gives the number of
        epochs, as in :meth:`skorch.NeuralNet.partial_fit`.

        Returns
        -------
        self
        """
        if not hasattr(self, "estimators_"):
            self._validate_params()
            self.estimators_ = self._new_members()
        if not all(hasattr(m, "partial_fit") for m in self.estimators_):
            raise TypeError(f"{type(self.estimator).__name__} has no partial_fit; use fit.")
        if classes is not None:
            kwargs["classes"] = classes
        self.estimators_ = Parallel(n_jobs=self.n_jobs, prefer="threads")(
            delayed(_partial_fit_member)(m, X, y, kwargs) for m in self.estimators_
        )
        self._set_classes()
        return self

    @property
    def history_(self):
        """The first member's training history (skorch members), for loss reports."""
        check_is_fitted(self, "estimators_")
        return self.estimators_[0].history_

    def predict_proba_samples(self, X, n_samples=None, random_state=None):
        """Each member's class probabilities: one "sample" per member.

        Parameters
        ----------
        X : array-like
        n_samples : int or None, default=None
            ``None`` returns one row per member. An int returns that many
            rows, cycling through the members (row ``j`` is member
            ``j % n_estimators``), so callers that ask for a fixed number of
            MC passes work unchanged; with a multiple of ``n_estimators`` the
            mean and variance over rows equal those over the members.
        random_state : ignored
            The members are deterministic at prediction time; accepted for
            the interface of the MC-dropout nets.

        Returns
        -------
        proba : ndarray of shape (n_samples or n_estimators, n_X, n_classes)
        """
        check_is_fitted(self, "estimators_")
        validate_parameter_constraints(
            {"n_samples": [Interval(numbers.Integral, 1, None, closed="left"), None]},
            {"n_samples": n_samples},
            caller_name=f"{type(self).__name__}.predict_proba_samples",
        )
        members = np.stack([np.asarray(m.predict_proba(X), dtype=np.float32) for m in self.estimators_])
        if n_samples is None:
            return members
        return members[np.arange(n_samples) % len(self.estimators_)]

    def predict_proba(self, X):
        """Mean of the members' class probabilities."""
        return self.predict_proba_samples(X).mean(axis=0)

    def predict(self, X):
        """The class with the highest mean probability."""
        proba = self.predict_proba(X)
        return self.classes_[np.argmax(proba, axis=1)]
