"""Confidence intervals of cross-validated scores and of paired differences: the package's one t-interval.

Every interval the package prints comes from ``sklearn_hardness.utils._intervals``: the
evaluation's fold scores (corrected for the folds' overlapping training
sets) and the experiments' paired comparisons of runs (no correction:
``test_train_ratio=0``). Each is clipped to the range its quantity can take
(an accuracy within [0, 1], a difference of accuracies within [-1, 1],
presses within the budget), and the tables say in words when
too few values stand behind it.
"""

from __future__ import annotations

import numbers

import numpy as np

from ..utils._intervals import _interval
from ..utils._param_validation import Interval, validate_params

__all__ = ["corrected_interval"]


@validate_params(
    {
        "scores": ["array-like"],
        "test_train_ratio": [Interval(numbers.Real, 0, None, closed="left")],
        "baseline": ["array-like", None],
        "df": [Interval(numbers.Integral, 1, None, closed="left"), None],
        "bounds": [tuple, None],
        "level": [Interval(numbers.Real, 0, 1, closed="neither")],
    },
    prefer_skip_nested_validation=True,
)
def corrected_interval(scores, test_train_ratio=0.0, *, baseline=None, df=None, bounds=None, level=0.95):
    """Mean of fold scores and its t-interval, corrected for overlapping training sets.

    The folds of a cross-validation share most of their training presses,
    so their scores are not independent and the plain t-interval over folds
    is too narrow. Nadeau and Bengio's correction widens it: the variance of
    the mean is ``var(scores, ddof=1) * (1 / n + n_test / n_train)`` instead
    of ``var(scores, ddof=1) / n`` (as in scikit-learn's example
    "Statistical comparison of models using grid search"). With
    ``baseline``, the interval is that of the paired difference
    ``scores - baseline`` (the same folds). ``test_train_ratio=0`` gives
    the plain t-interval of independent values (paired runs). See
    ``docs/user_guide/recording.rst``; evidence that it keeps its level:
    ``studies/pages/evaluate_intervals.md``.

    Parameters
    ----------
    scores : array-like of shape (n_folds,)
        One score per fold; non-finite scores (a failed fold) are left out.
    test_train_ratio : float, default=0.0
        ``n_test / n_train`` of the folds (their mean); 0 for independent
        values.
    baseline : array-like of shape (n_folds,) or None, default=None
        Another pipeline's scores on the same folds: the interval is then
        that of the difference.
    df : int or None, default=None
        Degrees of freedom of the t quantile: ``n - 1`` over ``n`` finite
        scores, or ``df`` where fewer (repeated folds: those of one
        repetition).
    bounds : (float, float) or None, default=None
        The range the score (or the difference) can take; the mean and the
        interval are clipped to it (a symmetric t-interval can reach past a
        bound). None: unbounded.
    level : float in (0, 1), default=0.95
        Confidence level.

    Returns
    -------
    mean : float
        Mean of the finite scores (or differences).
    interval : (float, float)
        ``(nan, nan)`` with fewer than two finite values: one fold carries
        no interval. With fewer than ``MIN_VALUES_FOR_INTERVAL`` (5) degrees
        of freedom + 1 the interval is computed but the reports
        (``str(result)`` of an :class:`EvaluationResult`) print words instead.

    Examples
    --------
    >>> from sklearn_hardness.model_selection import corrected_interval
    >>> mean, (low, high) = corrected_interval([0.6, 0.7, 0.65, 0.8, 0.75], 0.25, bounds=(0, 1))
    >>> round(mean, 2), round(low, 2), round(high, 2)
    (0.7, 0.55, 0.85)
    """
    values = np.asarray(scores, dtype=float).ravel()
    if baseline is not None:
        base = np.asarray(baseline, dtype=float).ravel()
        if base.shape != values.shape:
            raise ValueError(f"baseline has {base.size} scores, scores {values.size}: they must be of the same folds.")
        values = values - base
    lo, hi = (-np.inf, np.inf) if bounds is None else bounds
    return _interval(values, test_train_ratio, np.inf if df is None else df, bounds=(lo, hi), level=level)


def paired_difference(scores, base, test_train_ratio, df):
    """Mean over folds of ``scores - base`` and its corrected 95% interval, clipped to [-1, 1].

    (None, None) without a base.
    """
    if base is None:
        return None, None
    return _interval(np.asarray(scores, dtype=float) - np.asarray(base, dtype=float), test_train_ratio, df,
                     bounds=(-1.0, 1.0))
