"""Logistic regression with posterior samples: :class:`LaplaceLogisticRegression`."""

from __future__ import annotations

import inspect
import numbers

import numpy as np
from scipy.special import expit, softmax
from sklearn.linear_model import LogisticRegression
from sklearn.utils import check_random_state
from sklearn.utils.validation import check_is_fitted, validate_data

from ..utils._param_validation import Interval, validate_parameter_constraints

__all__ = ["LaplaceLogisticRegression"]

#: Solvers that fit one multinomial model with an unpenalised intercept (liblinear fits
#: one-vs-rest models and penalises the intercept: not the posterior written here).
_SOLVERS = ("lbfgs", "newton-cg", "newton-cholesky", "sag", "saga")


class LaplaceLogisticRegression(LogisticRegression):
    """Logistic regression whose class probabilities can be sampled from a Laplace posterior.

    Fits exactly as :class:`~sklearn.linear_model.LogisticRegression` (same
    parameters, coefficients, ``predict`` and ``predict_proba``) and then
    reads its L2-penalised objective as a negative log posterior: a Gaussian
    prior :math:`\\mathcal N(0, C\\,I)` on the coefficients, a flat one on
    the intercepts, and the (class- and sample-weighted) log-likelihood of
    the training data. The Laplace approximation is the Gaussian at the
    fitted coefficients whose precision is the objective's Hessian there
    (``posterior_covariance_`` is its inverse).
    :meth:`predict_proba_samples` draws coefficients from it and returns
    their class probabilities, so the model drives active sampling
    (:class:`~sklearn_hardness.active.ActiveLearner`): its samples are the
    model's own uncertainty about the decision boundary, wide far from the
    training data and narrowing as presses are added, where a Monte-Carlo
    dropout net's spread depends on the dropout rate.

    Only pure L2 penalties with a finite ``C`` (the prior) and the solvers
    that fit one multinomial model with an unpenalised intercept (``lbfgs``,
    ``newton-cg``, ``newton-cholesky``, ``sag``, ``saga``) are accepted.

    Parameters
    ----------
    C, class_weight, solver, max_iter, tol, fit_intercept, random_state, ...
        As in :class:`~sklearn.linear_model.LogisticRegression`; ``C`` is
        also the prior variance of each coefficient.

    Attributes
    ----------
    coef_, intercept_, classes_, n_features_in_, n_iter_
        As in :class:`~sklearn.linear_model.LogisticRegression`.
    posterior_covariance_ : ndarray of shape (n_params, n_params)
        Covariance of the Laplace posterior over the parameters, ordered per
        row of ``coef_`` as that row's coefficients followed by its intercept
        (when fitted). With more than two classes the intercepts' common
        shift, which changes no probability and has no prior, is left out
        (the covariance is the pseudo-inverse of the Hessian).

    See Also
    --------
    ContactProfileNNClassifier : an MLP head whose samples come from MC dropout.
    EnsembleClassifier : samples from differently seeded nets.

    Notes
    -----
    The posterior treats the training rows as independent. Presses of one
    object are not (they share its shape and texture), so with several
    presses per object the samples understate the uncertainty about a new
    object; their spread still ranks which objects the model is least sure
    of, which is what the active-sampling strategies use.

    Examples
    --------
    >>> import numpy as np
    >>> from sklearn_hardness.models import LaplaceLogisticRegression
    >>> rng = np.random.default_rng(0)
    >>> X = rng.normal(size=(60, 2))
    >>> y = (X[:, 0] + 0.5 * rng.normal(size=60) > 0).astype(int)
    >>> clf = LaplaceLogisticRegression().fit(X, y)
    >>> samples = clf.predict_proba_samples([[0.0, 0.0], [4.0, 0.0]], n_samples=200, random_state=0)
    >>> samples.shape
    (200, 2, 2)
    >>> bool(samples[:, 0, 1].std() > samples[:, 1, 1].std())  # less sure at the boundary
    True
    """

    _predict_proba_samples_constraints = {
        "n_samples": [Interval(numbers.Integral, 1, None, closed="left")],
        "random_state": ["random_state"],
    }

    def fit(self, X, y, sample_weight=None):
        """Fit the logistic regression, then the Laplace posterior at its coefficients.

        Parameters
        ----------
        X : array-like of shape (n_samples, n_features)
            Training data (dense; sparse input is refused).
        y : array-like of shape (n_samples,)
            Target labels.
        sample_weight : array-like of shape (n_samples,), default=None
            Weights of the rows, in the fit and in the posterior.

        Returns
        -------
        self : LaplaceLogisticRegression
        """
        X = validate_data(self, X, dtype=np.float64)  # dense: the Hessian is a dense matrix anyway
        # LogisticRegression.fit first: scikit-learn's own messages for a bad C, solver, ... come
        # before ours (a value it accepts but that is no Gaussian prior is refused right after)
        super().fit(X, y, sample_weight=sample_weight)
        self._check_gaussian_prior()
        weights = self._row_weights(y, sample_weight)
        self.posterior_covariance_ = self._covariance(X, weights)
        return self

    def __sklearn_tags__(self):
        tags = super().__sklearn_tags__()
        tags.input_tags.sparse = False
        tags.array_api_support = False  # the posterior and its samples are computed with numpy
        return tags

    def _check_gaussian_prior(self):
        penalty = getattr(self, "penalty", "l2")
        l1_ratio = getattr(self, "l1_ratio", None)
        # penalty="deprecated" (newer scikit-learn): the penalty is l1_ratio's
        pure_l2 = penalty in ("l2", "deprecated") and l1_ratio in (None, 0, 0.0)
        if not pure_l2 or not np.isfinite(self.C):
            raise ValueError(
                f"{type(self).__name__} needs a pure L2 penalty with a finite C (its Gaussian prior); got "
                f"penalty={penalty!r}, l1_ratio={l1_ratio!r}, C={self.C!r}.")
        if self.solver not in _SOLVERS:
            raise ValueError(
                f"{type(self).__name__} needs a solver that fits one multinomial model with an unpenalised "
                f"intercept, one of {list(_SOLVERS)}; got solver={self.solver!r}.")
        if getattr(self, "multi_class", "auto") == "ovr":  # scikit-learn < 1.8 only
            raise ValueError(f"{type(self).__name__} needs the multinomial model, got multi_class='ovr'.")

    def _row_weights(self, y, sample_weight):
        """Per-row weight of the log-likelihood: ``sample_weight`` times ``class_weight``."""
        from sklearn.utils.class_weight import compute_class_weight

        y = np.asarray(y)
        n = len(y)
        weights = np.ones(n) if sample_weight is None else np.asarray(sample_weight, dtype=np.float64).copy()
        if self.class_weight is not None:
            # as LogisticRegression weighs its rows: where compute_class_weight takes sample_weight
            # (newer scikit-learn), "balanced" counts the classes by sample weight
            extra = {}
            if "sample_weight" in inspect.signature(compute_class_weight).parameters:
                extra["sample_weight"] = sample_weight
            per_class = compute_class_weight(self.class_weight, classes=self.classes_, y=y, **extra)
            weights *= per_class[np.searchsorted(self.classes_, y)]
        return weights

    def _design(self, X):
        return np.hstack([X, np.ones((len(X), 1))]) if self.fit_intercept else X

    def _is_penalised(self, n_features):
        """Which entries of one row's parameters (coefficients, then the intercept) have the prior."""
        return np.r_[np.ones(n_features, bool), np.zeros(int(self.fit_intercept), bool)]

    def _covariance(self, X, weights):
        Z = self._design(X)
        p = Z.shape[1]
        penalised = self._is_penalised(X.shape[1])
        logits = Z @ self._parameters().T  # (n, rows)
        if len(self.classes_) == 2:
            q = expit(logits[:, 0])
            H = (Z * (weights * q * (1 - q))[:, None]).T @ Z
            H += np.diag(penalised / self.C)
        else:
            P = softmax(logits, axis=1)
            k = P.shape[1]
            H = np.zeros((k * p, k * p))
            for a in range(k):
                for b in range(a, k):
                    w = weights * (P[:, a] * ((a == b) - P[:, b]))
                    block = (Z * w[:, None]).T @ Z
                    H[a * p:(a + 1) * p, b * p:(b + 1) * p] = block
                    H[b * p:(b + 1) * p, a * p:(a + 1) * p] = block.T
            H += np.diag(np.tile(penalised, k) / self.C)
        values, vectors = np.linalg.eigh(H)
        # the intercepts' common shift (multinomial) has a zero eigenvalue: no probability depends on it
        keep = values > values.max() * 1e-10
        return (vectors[:, keep] / values[keep]) @ vectors[:, keep].T

    def _parameters(self):
        """The fitted parameters, one row per row of ``coef_``: coefficients then intercept."""
        if self.fit_intercept:
            return np.hstack([self.coef_, np.asarray(self.intercept_).reshape(-1, 1)])
        return np.asarray(self.coef_)

    def predict_proba_samples(self, X, n_samples=50, random_state=None):
        """Class probabilities under coefficients drawn from the Laplace posterior.

        Parameters
        ----------
        X : array-like of shape (n_X, n_features)
            Input of the shape seen during fit.
        n_samples : int, default=50
            Number of posterior draws.
        random_state : int, RandomState instance or None, default=None
            Seed of the draws; the same seed gives identical samples.

        Returns
        -------
        proba : ndarray of shape (n_samples, n_X, n_classes)
            Class probabilities under each draw (rows sum to 1).
        """
        validate_parameter_constraints(
            self._predict_proba_samples_constraints, {"n_samples": n_samples, "random_state": random_state},
            caller_name=f"{type(self).__name__}.predict_proba_samples")
        check_is_fitted(self, "posterior_covariance_")
        X = validate_data(self, X, reset=False, dtype=np.float64)
        rng = check_random_state(random_state)
        theta = self._parameters()
        values, vectors = np.linalg.eigh(self.posterior_covariance_)
        factor = vectors * np.sqrt(np.clip(values, 0, None))  # factor @ factor.T == the covariance
        draws = theta.ravel() + rng.standard_normal((n_samples, len(values))) @ factor.T
        draws = draws.reshape((n_samples,) + theta.shape)  # (S, rows, p)
        logits = np.einsum("np,srp->snr", self._design(X), draws)
        if len(self.classes_) == 2:
            q = expit(logits[..., 0])
            return np.stack([1 - q, q], axis=-1)
        return softmax(logits, axis=-1)
