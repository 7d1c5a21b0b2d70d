"""Hardness-aware metrics: how far off is a misclassification, in hardness units."""

from __future__ import annotations

from collections.abc import Mapping

import numpy as np
from sklearn.metrics import make_scorer

from ..utils._param_validation import validate_params

__all__ = ["hardness_mae", "make_hardness_mae_scorer"]


def _hardness_lookup(hardness, classes):
    """Return (labels, values): class labels and their hardness, validated."""
    if isinstance(hardness, Mapping):
        if classes is not None:
            raise ValueError(
                "pass either hardness as a mapping label -> hardness, or hardness "
                "as an array with classes=..., not both."
            )
        labels = np.asarray(list(hardness.keys()))
        values = np.asarray(list(hardness.values()), dtype=np.float64)
    else:
        values = np.asarray(hardness, dtype=np.float64)
        if values.ndim != 1:
            raise ValueError(
                f"hardness must be 1-D (one value per class), got shape {values.shape}."
            )
        if classes is None:
            labels = np.arange(values.shape[0])
        else:
            labels = np.asarray(classes)
            if labels.ndim != 1 or labels.shape[0] != values.shape[0]:
                raise ValueError(
                    f"classes has {labels.size} entries but hardness has "
                    f"{values.shape[0]} values; give one hardness per class."
                )
    if values.size == 0:
        raise ValueError("hardness is empty.")
    if not np.all(np.isfinite(values)):
        raise ValueError("hardness contains NaN or infinite values.")
    if np.unique(labels).size != labels.size:
        raise ValueError(f"classes has duplicate labels: {labels.tolist()}.")
    return labels, values


def _to_hardness(y, labels, values, name):
    y = np.asarray(y)
    if y.ndim != 1:
        raise ValueError(f"{name} must be 1-D, got shape {y.shape}.")
    order = np.argsort(labels, kind="stable")
    sorted_labels = labels[order]
    try:
        pos = np.searchsorted(sorted_labels, y)
    except TypeError:
        raise TypeError(
            f"{name} labels ({y.dtype}) cannot be compared with the hardness "
            f"classes ({labels.dtype})."
        ) from None
    pos = np.clip(pos, 0, sorted_labels.size - 1)
    found = sorted_labels[pos] == y
    if not np.all(found):
        unknown = np.unique(y[~found])
        raise ValueError(
            f"{name} has labels {unknown.tolist()} with no hardness value; known "
            f"labels are {labels.tolist()}."
        )
    return values[order[pos]]


@validate_params(
    {
        "y_true": ["array-like"],
        "y_pred": ["array-like"],
        "hardness": ["array-like", Mapping],
        "classes": ["array-like", None],
        "sample_weight": ["array-like", None],
    },
    prefer_skip_nested_validation=True,
)
def hardness_mae(y_true, y_pred, hardness, *, classes=None, sample_weight=None):
    """Mean absolute error between true and predicted hardness values.

    The classifier predicts a reference object; this metric measures how far
    the predicted object's hardness is from the true one's (the paper's MAE,
    Sec. III-D), so confusing two similar objects costs less than confusing
    the softest with the hardest.

    Parameters
    ----------
    y_true : array-like of shape (n_samples,)
        True class labels.
    y_pred : array-like of shape (n_samples,)
        Predicted class labels.
    hardness : array-like of shape (n_classes,) or mapping
        Hardness of every class, in any unit (e.g. ``Bunch.hardness`` with
        ``Bunch.hardness_unit``). An array is indexed by class: by the
        integer label ``0 .. n_classes - 1``, or by position in ``classes``.
        A mapping goes from label to hardness.
    classes : array-like of shape (n_classes,), default=None
        Labels of the entries of an array ``hardness``.
    sample_weight : array-like of shape (n_samples,), default=None
        Weights of the samples.

    Returns
    -------
    mae : float
        In the unit of ``hardness``.

    Raises
    ------
    ValueError
        If a label has no hardness value, lengths differ, or ``hardness``
        is empty or not finite.

    See Also
    --------
    make_hardness_mae_scorer : the same as a scorer for ``cross_val_score``.

    Examples
    --------
    >>> from sklearn_hardness.metrics import hardness_mae
    >>> round(hardness_mae([0, 1, 2], [0, 2, 2], hardness=[1.13, 1.02, 0.79]), 4)
    0.0767
    >>> hardness_mae(["soft", "hard"], ["hard", "hard"], {"soft": 8.0, "hard": 95.0})
    43.5
    """
    labels, values = _hardness_lookup(hardness, classes)
    h_true = _to_hardness(y_true, labels, values, "y_true")
    h_pred = _to_hardness(y_pred, labels, values, "y_pred")
    if h_true.shape[0] != h_pred.shape[0]:
        raise ValueError(
            f"y_true has {h_true.shape[0]} samples but y_pred has {h_pred.shape[0]}."
        )
    if h_true.shape[0] == 0:
        raise ValueError("y_true and y_pred are empty.")
    if sample_weight is not None:
        sample_weight = np.asarray(sample_weight, dtype=np.float64)
        if sample_weight.shape != h_true.shape:
            raise ValueError(
                f"sample_weight has shape {sample_weight.shape}, expected {h_true.shape}."
            )
    return float(np.average(np.abs(h_true - h_pred), weights=sample_weight))


@validate_params(
    {"hardness": ["array-like", Mapping], "classes": ["array-like", None]},
    prefer_skip_nested_validation=True,
)
def make_hardness_mae_scorer(hardness, *, classes=None):
    """A scorer for :func:`hardness_mae`, for ``cross_val_score`` and ``GridSearchCV``.

    As for scikit-learn's ``"neg_mean_absolute_error"``, the scorer returns
    the *negative* MAE (greater is better).

    Parameters
    ----------
    hardness : array-like of shape (n_classes,) or mapping
        As in :func:`hardness_mae`.
    classes : array-like of shape (n_classes,), default=None
        As in :func:`hardness_mae`.

    Returns
    -------
    scorer : callable
        ``scorer(estimator, X, y)`` returning ``-hardness_mae(y, estimator.predict(X))``.

    Examples
    --------
    >>> from sklearn.model_selection import cross_val_score
    >>> from sklearn.tree import DecisionTreeClassifier
    >>> from sklearn_hardness.metrics import make_hardness_mae_scorer
    >>> X = [[0], [1], [2], [3], [4], [5]]; y = [0, 0, 1, 1, 2, 2]
    >>> scorer = make_hardness_mae_scorer([1.13, 1.02, 0.79])
    >>> cross_val_score(DecisionTreeClassifier(), X, y, cv=2, scoring=scorer).shape
    (2,)
    """
    _hardness_lookup(hardness, classes)  # validate now, not in the middle of a search
    return make_scorer(
        hardness_mae, greater_is_better=False, hardness=hardness, classes=classes
    )
