"""LaplaceLogisticRegression: the posterior is the objective's, and its samples behave like a posterior.

The checks that would fail if the Laplace approximation were wrong: the fitted
coefficients are the mode of the documented negative log posterior (its
gradient vanishes there, with class and sample weights), the inverse of
``posterior_covariance_`` is that objective's Hessian (finite differences),
the samples' spread shrinks roughly as one over the square root of the presses, and
the samples average to the fitted probabilities.
"""

import numpy as np
import pytest
from scipy.special import expit, softmax
from sklearn.linear_model import LogisticRegression

from sklearn_hardness.models import LaplaceLogisticRegression


def _data(n, k, rng, d=3):
    X = rng.normal(size=(n, d))
    W = rng.normal(size=(k, d))
    y = np.array([rng.choice(k, p=p) for p in softmax(1.5 * X @ W.T, axis=1)])
    return X, y


def _objective(clf, X, y, weights):
    """The documented negative log posterior: weighted log loss + ||coef||^2 / (2 C) (intercepts free)."""
    Z = clf._design(X)
    rows = clf._parameters().shape
    penalised = clf._is_penalised(X.shape[1])
    index = np.searchsorted(clf.classes_, y)

    def f(theta):
        theta = theta.reshape(rows)
        logits = Z @ theta.T
        if rows[0] == 1:
            q = expit(logits[:, 0])
            loglik = np.where(index == 1, np.log(q), np.log(1 - q))
        else:
            loglik = np.log(softmax(logits, axis=1)[np.arange(len(y)), index])
        return -(weights * loglik).sum() + (theta[:, penalised] ** 2).sum() / (2 * clf.C)

    return f


def _gradient(f, theta, eps=1e-6):
    return np.array([(f(theta + eps * e) - f(theta - eps * e)) / (2 * eps) for e in np.eye(len(theta))])


@pytest.mark.parametrize("n_classes", [2, 3])
@pytest.mark.parametrize("class_weight", [None, "balanced"])
@pytest.mark.parametrize("weighted_rows", [False, True])
def test_the_fit_is_the_mode_and_the_precision_the_hessian(n_classes, class_weight, weighted_rows):
    rng = np.random.default_rng(n_classes)
    X, y = _data(90, n_classes, rng)
    y[:30] = 0  # unequal classes: the class weights matter
    sample_weight = rng.uniform(0.5, 2.0, len(y)) if weighted_rows else None
    clf = LaplaceLogisticRegression(C=0.7, class_weight=class_weight, tol=1e-12, max_iter=10_000)
    clf.fit(X, y, sample_weight=sample_weight)
    f = _objective(clf, X, y, clf._row_weights(y, sample_weight))
    theta = clf._parameters().ravel()
    g = _gradient(f, theta)
    assert np.abs(g).max() < 1e-4 * max(1.0, np.abs(theta).max() * len(y))
    hessian = np.array([(_gradient(f, theta + 1e-4 * e) - _gradient(f, theta - 1e-4 * e)) / 2e-4
                        for e in np.eye(len(theta))])
    precision = np.linalg.pinv(clf.posterior_covariance_)
    np.testing.assert_allclose(precision, hessian, atol=1e-3 * np.abs(hessian).max())
    if n_classes > 2:  # the intercepts' common shift is the one direction left out
        rows, p = clf._parameters().shape
        shift = np.zeros((rows, p))
        shift[:, -1] = 1.0
        np.testing.assert_allclose(clf.posterior_covariance_ @ shift.ravel(), 0.0, atol=1e-8)
        assert np.linalg.matrix_rank(clf.posterior_covariance_) == rows * p - 1


def test_predictions_are_logistic_regressions():
    rng = np.random.default_rng(0)
    X, y = _data(60, 3, rng)
    laplace = LaplaceLogisticRegression(C=2.0, class_weight="balanced").fit(X, y)
    plain = LogisticRegression(C=2.0, class_weight="balanced").fit(X, y)
    np.testing.assert_array_equal(laplace.coef_, plain.coef_)
    np.testing.assert_array_equal(laplace.predict(X), plain.predict(X))
    np.testing.assert_allclose(laplace.predict_proba(X), plain.predict_proba(X))


@pytest.mark.parametrize("n_classes", [2, 3])
def test_samples_are_probabilities_reproducible_and_centred_on_the_fit(n_classes):
    rng = np.random.default_rng(1)
    X, y = _data(200, n_classes, rng)
    clf = LaplaceLogisticRegression().fit(X, y)
    samples = clf.predict_proba_samples(X[:7], n_samples=3000, random_state=0)
    assert samples.shape == (3000, 7, n_classes)
    np.testing.assert_allclose(samples.sum(axis=-1), 1.0)
    np.testing.assert_array_equal(samples, clf.predict_proba_samples(X[:7], n_samples=3000, random_state=0))
    assert not np.array_equal(samples, clf.predict_proba_samples(X[:7], n_samples=3000, random_state=1))
    # with 200 rows the posterior is narrow: its mean probability is the fitted one, up to curvature
    np.testing.assert_allclose(samples.mean(axis=0), clf.predict_proba(X[:7]), atol=0.02)


def test_the_spread_shrinks_as_one_over_root_n_with_more_presses():
    """Sixteen times the training rows of the same distribution: 1/sqrt(n) predicts 4x less spread (5.3x here)."""
    rng = np.random.default_rng(2)
    X_test = rng.normal(size=(50, 3))
    spreads = []
    for n in (100, 1600):
        X, y = _data(n, 3, np.random.default_rng(3))
        clf = LaplaceLogisticRegression(C=100.0).fit(X, y)
        spreads.append(clf.predict_proba_samples(X_test, n_samples=400, random_state=0).std(axis=0).mean())
    assert 2.5 < spreads[0] / spreads[1] < 6.0


def test_more_uncertain_where_the_training_data_say_less():
    """A region the training rows never reached gets a wider spread than the one they covered."""
    rng = np.random.default_rng(4)
    X = rng.normal(size=(120, 2)) * [1.0, 0.1]  # the second feature barely varies in training
    y = (X[:, 0] + 0.3 * rng.normal(size=120) > 0).astype(int)
    clf = LaplaceLogisticRegression(C=10.0).fit(X, y)
    seen = clf.predict_proba_samples([[0.0, 0.0]], n_samples=500, random_state=0)[:, 0, 1].std()
    unseen = clf.predict_proba_samples([[0.0, 3.0]], n_samples=500, random_state=0)[:, 0, 1].std()
    assert unseen > 3 * seen


@pytest.mark.parametrize("params, match", [
    ({"C": np.inf}, "pure L2 penalty with a finite C"),
    ({"l1_ratio": 0.5, "solver": "saga"}, "pure L2 penalty"),
    ({"solver": "liblinear"}, "unpenalised intercept"),
])
def test_what_is_not_a_gaussian_posterior_is_refused(params, match):
    X, y = _data(30, 2, np.random.default_rng(0))
    with pytest.raises(ValueError, match=match):
        LaplaceLogisticRegression(**params).fit(X, y)


def test_invalid_parameters_get_scikit_learn_s_message_first():
    # LogisticRegression's own validation (scikit-learn's InvalidParameterError, a ValueError)
    X, y = _data(30, 2, np.random.default_rng(0))
    with pytest.raises(ValueError, match="The 'C' parameter of LaplaceLogisticRegression must be"):
        LaplaceLogisticRegression(C="one").fit(X, y)
    with pytest.raises(ValueError, match="The 'solver' parameter of LaplaceLogisticRegression must be"):
        LaplaceLogisticRegression(solver="bogus").fit(X, y)


def test_sampling_checks_its_arguments_and_the_fit():
    X, y = _data(30, 2, np.random.default_rng(0))
    from sklearn.exceptions import NotFittedError

    with pytest.raises(NotFittedError):
        LaplaceLogisticRegression().predict_proba_samples(X)
    clf = LaplaceLogisticRegression().fit(X, y)
    with pytest.raises(ValueError, match="n_samples"):
        clf.predict_proba_samples(X, n_samples=0)
    with pytest.raises(ValueError, match="features"):
        clf.predict_proba_samples(X[:, :2])
