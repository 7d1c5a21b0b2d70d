"""Utilities for users' own estimators: :mod:`sklearn_hardness.utils.estimator_checks`, the video versions
of scikit-learn's common checks. Input validation and random-state helpers are private."""

__all__ = []
