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

:func:`check_param_validation`, scikit-learn's check of the same name on the
estimator's own kind of input, is not among them: it is for estimators that
validate their parameters with this package's ``_parameter_constraints``.
"""

from __future__ import annotations

import contextlib
import os
import pickle
import re
import tempfile
import warnings
from numbers import Integral, Real

import numpy as np
from sklearn.base import clone
from sklearn.exceptions import NotFittedError
from sklearn.utils import get_tags

from ._param_validation import (
    Interval,
    InvalidParameterError,
    generate_invalid_param_val,
    generate_valid_param,
    make_constraint,
)

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
    "check_param_validation",
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


# ------------------------------------------------------------------ parameter validation
_FIT_METHODS = ("fit", "partial_fit", "fit_transform", "fit_predict")


class _BadType:
    """An object of a type no constraint accepts."""


def _own_parameters(estimator):
    """``get_params(deep=False)`` less what is not the estimator's own parameter: names with a leading
    underscore (skorch lists its private attributes) or a ``__`` (keyword arguments skorch passes on to the
    module, optimizer or iterators: theirs, not the net's)."""
    return [p for p in estimator.get_params(deep=False) if not p.startswith("_") and "__" not in p]


def _invalid_values(caller, param, constraints):
    """Values of ``param`` that none of its ``constraints`` accepts: an object of no accepted type, and for
    each constraint the value :func:`generate_invalid_param_val` makes, where there is one."""
    intervals = {c.type for c in constraints if isinstance(c, Interval)}
    assert not {Integral, Real} <= intervals, (
        f"The constraints of {caller}'s {param!r} mix intervals of Integral and Real: use RealNotInt instead "
        "of Real, so that an invalid value of one is not a valid value of the other.")
    yield _BadType()
    for constraint in (make_constraint(c) for c in constraints):
        try:
            yield generate_invalid_param_val(constraint)
        except NotImplementedError:  # every value of its type satisfies it
            continue


def _valid_values(constraints):
    """For each of ``constraints``, the value :func:`generate_valid_param` makes, where it can make one (a
    type whose constructor needs arguments has none)."""
    for constraint in (make_constraint(c) for c in constraints):
        try:
            yield generate_valid_param(constraint)
        except (TypeError, ValueError):
            continue


def _parameter_error_message(param, caller):
    return re.compile(rf"The {param!r} parameter of {re.escape(caller)} must be .* Got .* instead\.", re.S)


@contextlib.contextmanager
def _in_temporary_directory():
    """Run in a fresh working directory, removed afterwards (``contextlib.chdir`` is Python 3.11+)."""
    here = os.getcwd()
    with tempfile.TemporaryDirectory() as folder:
        os.chdir(folder)
        try:
            yield folder
        finally:
            os.chdir(here)


def check_param_validation(name, estimator, X, y, *, methods=None):
    """Each constrained parameter rejects an invalid value with an error naming it, and takes a valid one.

    scikit-learn's ``check_param_validation`` for estimators that declare
    ``_parameter_constraints`` with this package's validation, on the
    estimator's own kind of input:

    1. ``_parameter_constraints`` names exactly the parameters of
       ``get_params(deep=False)``, less those with a leading underscore or a
       ``__`` (skorch lists its private attributes, and the keyword
       arguments it passes on to the module, optimizer or iterators);
    2. for each constrained parameter, an object of no accepted type and,
       for each of its constraints, the value
       ``generate_invalid_param_val`` makes: every method of ``methods``
       raises ``InvalidParameterError`` (a ``ValueError`` and a
       ``TypeError``) saying ``"The '<param>' parameter of <name> must be
       ... Got ... instead."``;
    3. for each constraint, the value ``generate_valid_param`` makes: the
       first method of ``methods`` raises no ``InvalidParameterError``
       (another error may still come: a valid value need not suit the data,
       e.g. ``classes`` that ``y`` does not hold).

    The calls run in a temporary working directory: a valid string can be a
    path (``memory=""`` is a cache folder where the check is called), and
    nothing is left behind.

    Parameters
    ----------
    name : str
        The estimator's class name, as its error messages say it.
    estimator : estimator
        The estimator (not modified: each parameter is set on a clone).
    X : list of ndarray, ndarray
        A small input of the estimator's kind.
    y : array-like of shape (n_samples,) or None
        Labels with at least two classes, or None.
    methods : tuple of str or None, default=None
        The methods that validate the parameters, each called as
        ``method(X, y)``. None: those of ``fit``, ``partial_fit``,
        ``fit_transform`` and ``fit_predict`` the estimator has.

    Raises
    ------
    AssertionError
        If a table and the parameters differ, an invalid value passes, its
        error does not name the parameter, or a valid value is rejected.

    Examples
    --------
    >>> from numbers import Integral
    >>> import numpy as np
    >>> from sklearn.base import BaseEstimator, TransformerMixin
    >>> from sklearn_hardness.utils._param_validation import Interval, fit_context
    >>> from sklearn_hardness.utils.estimator_checks import check_param_validation
    >>> class Clipper(TransformerMixin, BaseEstimator):
    ...     _parameter_constraints = {"k": [Interval(Integral, 1, None, closed="left")]}
    ...     def __init__(self, k=1):
    ...         self.k = k
    ...     @fit_context(prefer_skip_nested_validation=True)
    ...     def fit(self, X, y=None):
    ...         return self
    ...     def transform(self, X):
    ...         return np.minimum(X, self.k)
    >>> X = np.zeros((4, 3, 8, 8, 1), np.float32)
    >>> check_param_validation("Clipper", Clipper(), X, None)
    """
    methods = [m for m in _FIT_METHODS if hasattr(estimator, m)] if methods is None else list(methods)
    assert methods, f"{name} has none of {_FIT_METHODS}: pass the methods that validate its parameters."
    params = _own_parameters(estimator)
    constraints = getattr(estimator, "_parameter_constraints", {}) if params else {}
    unexpected, missing = sorted(set(constraints) - set(params)), sorted(set(params) - set(constraints))
    assert not unexpected and not missing, (
        f"Mismatch between _parameter_constraints and the parameters of {name}: constraints of no parameter "
        f"{unexpected}, parameters without constraints {missing}.")

    def call(est, method):
        with warnings.catch_warnings(), _in_temporary_directory():
            warnings.simplefilter("ignore")
            return getattr(est, method)(X, y)

    for param in params:
        if constraints[param] == "no_validation":
            continue
        expected = _parameter_error_message(param, name)
        for bad in _invalid_values(name, param, constraints[param]):
            est = clone(estimator).set_params(**{param: bad})
            for method in methods:
                try:
                    call(est, method)
                except InvalidParameterError as exc:
                    assert expected.search(str(exc)), (
                        f"{name}.{method} with {param}={bad!r} raised a parameter error that does not say "
                        f"\"The {param!r} parameter of {name} must be ... Got ... instead.\": {exc}")
                else:
                    raise AssertionError(
                        f"{name}.{method} with {param}={bad!r} raised no InvalidParameterError: add or tighten "
                        f"the constraint of {param!r} in _parameter_constraints (constraints must be disjoint, "
                        f"[StrOptions({{'a'}}), str] accepts every string), or validate it in {method}.")
        for good in _valid_values(constraints[param]):
            est = clone(estimator).set_params(**{param: good})
            try:
                call(est, methods[0])
            except InvalidParameterError as exc:
                raise AssertionError(
                    f"{name}.{methods[0]} with {param}={good!r}, a value its constraints accept, raised a "
                    f"parameter error: {exc}") from exc
            except Exception:  # noqa: BLE001 - a valid value need not suit the data; not a parameter error
                pass

