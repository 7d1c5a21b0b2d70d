"""Common checks for estimators that take press videos or selected frames.

scikit-learn's :func:`~sklearn.utils.estimator_checks.parametrize_with_checks`
feeds 2-D tables; an estimator whose tags say its input is not 2-D
(:func:`~sklearn.utils.get_tags`, ``input_tags.two_d_array=False``) gets only
scikit-learn's data-free checks. These are the video versions of the checks
that matter for such an estimator, in the way imbalanced-learn ships its own
checks: each takes ``(name, estimator, X, y)`` with the estimator's own kind
of input (a list of ``(T, H, W, C)`` videos, an ``(n, k, H, W, C)`` frames
array, or a 2-D table) and raises ``AssertionError`` when the estimator
misbehaves.

- :func:`check_video_unfitted_raises`: every output method raises
  ``NotFittedError`` before ``fit``;
- :func:`check_video_pickle`: a fitted estimator pickles and gives the same
  output after loading;
- :func:`check_video_refit_idempotent`: ``fit(A); fit(B); fit(A)`` gives the
  output of the first ``fit(A)``;
- :func:`check_video_clone_is_unfitted`: a clone keeps the parameters and
  none of the fitted state;
- :func:`check_video_n_jobs_invariance`: ``n_jobs=2`` gives exactly the
  output of ``n_jobs=1``;
- :func:`check_video_sample_order_invariance`: permuting the input permutes
  the output;
- :func:`check_video_input_unchanged`: ``fit`` and the output methods leave
  ``X`` untouched;
- :func:`check_tags_match_input`: the tags say 2-D input exactly when ``X``
  is a 2-D table.

:func:`check_video_estimator` runs them all; :func:`parametrize_with_video_checks`
turns them into pytest parameters, with expected failures as strict xfails.
"""

from __future__ import annotations

import pickle
import warnings

import numpy as np
from sklearn.base import clone
from sklearn.exceptions import NotFittedError
from sklearn.utils import get_tags

__all__ = [
    "VIDEO_CHECKS",
    "check_video_estimator",
    "parametrize_with_video_checks",
    "check_video_unfitted_raises",
    "check_video_pickle",
    "check_video_refit_idempotent",
    "check_video_clone_is_unfitted",
    "check_video_n_jobs_invariance",
    "check_video_sample_order_invariance",
    "check_video_input_unchanged",
    "check_tags_match_input",
]

_OUTPUT_METHODS = ("transform", "predict", "predict_proba")


def _output(estimator, X, method=None):
    method = method or ("transform" if hasattr(estimator, "transform") else "predict_proba")
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", UserWarning)  # padding/contact warnings on tiny inputs
        return np.asarray(getattr(estimator, method)(X))


def _fit(estimator, X, y):
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", UserWarning)
        return estimator.fit(X, y)


def _take(X, idx):
    return [X[i] for i in idx] if isinstance(X, list) else X[idx]


def _copy_input(X):
    return [np.array(v, copy=True) for v in X] if isinstance(X, list) else np.array(X, copy=True)


def check_video_unfitted_raises(name, estimator, X, y):
    """Every output method (transform, predict, predict_proba) raises ``NotFittedError`` before fit.

    Parameters
    ----------
    name : str
        The estimator's name, for messages.
    estimator : estimator
        An unfitted estimator.
    X : list of ndarray, ndarray
        Its kind of input: videos, selected frames or a 2-D table.
    y : ndarray of shape (n_samples,)
        Labels (ignored by transformers).
    """
    for method in _OUTPUT_METHODS:
        if not hasattr(estimator, method):
            continue
        try:
            _output(estimator, X, method)
        except NotFittedError:
            continue
        raise AssertionError(f"{name}.{method} before fit did not raise NotFittedError.")


def check_video_pickle(name, estimator, X, y):
    """A fitted estimator pickles and gives the same output after loading.

    Parameters
    ----------
    name, estimator, X, y
        See :func:`check_video_unfitted_raises`.
    """
    _fit(estimator, X, y)
    expected = _output(estimator, X)
    loaded = pickle.loads(pickle.dumps(estimator))
    np.testing.assert_allclose(_output(loaded, X), expected, rtol=1e-6, atol=1e-6,
                               err_msg=f"{name}: output changed through pickling")


def check_video_refit_idempotent(name, estimator, X, y):
    """``fit(A); fit(B); fit(A)`` gives the output of the first ``fit(A)``.

    ``B`` is ``A`` in reverse order (other data for anything order-dependent
    such as a net's batches), so refitting must reset every fitted state.

    Parameters
    ----------
    name, estimator, X, y
        See :func:`check_video_unfitted_raises`.
    """
    _fit(estimator, X, y)
    first = _output(estimator, X)
    rev = np.arange(len(X))[::-1]
    _fit(estimator, _take(X, rev), np.asarray(y)[rev])
    _fit(estimator, X, y)
    np.testing.assert_allclose(_output(estimator, X), first, rtol=1e-5, atol=1e-6,
                               err_msg=f"{name}: a second fit on the same data gave other output")


def check_video_clone_is_unfitted(name, estimator, X, y):
    """A clone of a fitted estimator has its parameters and none of its fitted state.

    Parameters
    ----------
    name, estimator, X, y
        See :func:`check_video_unfitted_raises`.
    """
    _fit(estimator, X, y)
    cloned = clone(estimator)
    assert set(cloned.get_params(deep=False)) == set(estimator.get_params(deep=False)), (
        f"{name}: the clone has other parameters")
    check_video_unfitted_raises(name, cloned, X, y)


def check_video_n_jobs_invariance(name, estimator, X, y):
    """``n_jobs=2`` gives exactly the output of ``n_jobs=1`` (no-op without ``n_jobs``).

    Parameters
    ----------
    name, estimator, X, y
        See :func:`check_video_unfitted_raises`.
    """
    if "n_jobs" not in estimator.get_params():
        return
    one = _output(_fit(clone(estimator).set_params(n_jobs=1), X, y), X)
    two = _output(_fit(clone(estimator).set_params(n_jobs=2), X, y), X)
    np.testing.assert_array_equal(two, one, err_msg=f"{name}: n_jobs=2 changed the output")


def check_video_sample_order_invariance(name, estimator, X, y):
    """The output of a permuted input is the permuted output.

    Parameters
    ----------
    name, estimator, X, y
        See :func:`check_video_unfitted_raises`.
    """
    _fit(estimator, X, y)
    perm = np.random.default_rng(0).permutation(len(X))
    np.testing.assert_allclose(_output(estimator, _take(X, perm)), _output(estimator, X)[perm],
                               rtol=1e-5, atol=1e-6, err_msg=f"{name}: output depends on sample order")


def check_video_input_unchanged(name, estimator, X, y):
    """``fit`` and the output methods leave ``X`` untouched.

    Parameters
    ----------
    name, estimator, X, y
        See :func:`check_video_unfitted_raises`.
    """
    before = _copy_input(X)
    _fit(estimator, X, y)
    _output(estimator, X)
    if isinstance(X, list):
        assert len(X) == len(before), f"{name} changed the number of videos"
        for a, b in zip(X, before):
            np.testing.assert_array_equal(a, b, err_msg=f"{name} modified its input")
    else:
        np.testing.assert_array_equal(X, before, err_msg=f"{name} modified its input")


def check_tags_match_input(name, estimator, X, y):
    """The tags say 2-D input (``input_tags.two_d_array``) exactly when ``X`` is a 2-D table.

    Parameters
    ----------
    name, estimator, X, y
        See :func:`check_video_unfitted_raises`.
    """
    takes_table = isinstance(X, np.ndarray) and X.ndim == 2
    says_table = get_tags(estimator).input_tags.two_d_array
    assert says_table == takes_table, (
        f"{name}'s tags say two_d_array={says_table} but it takes "
        f"{'a 2-D table' if takes_table else 'videos or frames'}; set input_tags.two_d_array="
        f"{takes_table} in __sklearn_tags__ (sklearn_hardness.utils._tags has helpers).")


#: The video checks, in the order :func:`check_video_estimator` runs them.
VIDEO_CHECKS = (
    check_video_unfitted_raises,
    check_video_pickle,
    check_video_refit_idempotent,
    check_video_clone_is_unfitted,
    check_video_n_jobs_invariance,
    check_video_sample_order_invariance,
    check_video_input_unchanged,
    check_tags_match_input,
)


def check_video_estimator(estimator, X, y, *, expected_failed_checks=None):
    """Run every check of :data:`VIDEO_CHECKS` on a fresh clone of ``estimator``.

    Parameters
    ----------
    estimator : estimator
        The estimator to check (not modified: each check gets a clone, and
        a copy of ``X`` and ``y``, so a fault in one check cannot hide in
        another's data).
    X : list of ndarray, ndarray
        A small input of the estimator's kind: a list of ``(T, H, W, C)``
        videos, an ``(n, k, H, W, C)`` frames array, or a 2-D table.
    y : array-like of shape (n_samples,)
        Labels with at least two classes.
    expected_failed_checks : dict or None, default=None
        Check name -> reason, for checks known to fail; they are not run.

    Returns
    -------
    passed : list of str
        The names of the checks that ran and passed.

    Raises
    ------
    AssertionError
        The first check that failed, with its name.

    Examples
    --------
    >>> import numpy as np
    >>> from sklearn_hardness.models._pipelines import FrameScaler
    >>> from sklearn_hardness.utils.estimator_checks import check_video_estimator
    >>> X = np.random.default_rng(0).random((6, 3, 8, 8, 1), dtype=np.float32)
    >>> len(check_video_estimator(FrameScaler(), X, np.arange(6) % 2))
    8
    """
    expected = dict(expected_failed_checks or {})
    name = type(estimator).__name__
    passed = []
    for check in VIDEO_CHECKS:
        if check.__name__ in expected:
            continue
        try:
            check(name, clone(estimator), _copy_input(X), np.array(y, copy=True))
        except AssertionError as exc:
            raise AssertionError(f"{check.__name__} failed for {name}: {exc}") from exc
        passed.append(check.__name__)
    return passed


def parametrize_with_video_checks(estimators, *, expected_failed_checks=None):
    """A pytest ``parametrize`` decorator over (estimator, data, check).

    The decorated test gets ``name, factory, data, check`` and calls
    ``check(name, factory(), *data())``. Expected failures become strict xfails:
    once the estimator is fixed the test reports XPASS as a failure, so the
    table cannot go stale.

    Parameters
    ----------
    estimators : dict
        Name -> ``(factory, data)``: ``factory()`` builds a small, fast
        instance and ``data()`` returns ``(X, y)`` of its input kind.
    expected_failed_checks : callable or None, default=None
        ``expected_failed_checks(name)`` -> dict of check name -> reason.

    Returns
    -------
    decorator : callable
        A ``pytest.mark.parametrize`` over every estimator and check.
    """
    import pytest  # a test-time dependency, as in scikit-learn's parametrize_with_checks

    params = []
    for name, (factory, data) in estimators.items():
        failing = {} if expected_failed_checks is None else dict(expected_failed_checks(name) or {})
        for check in VIDEO_CHECKS:
            marks = ()
            if check.__name__ in failing:
                marks = (pytest.mark.xfail(reason=failing[check.__name__], strict=True),)
            params.append(pytest.param(name, factory, data, check, marks=marks,
                                       id=f"{name}-{check.__name__}"))
    return pytest.mark.parametrize("name, factory, data, check", params)
