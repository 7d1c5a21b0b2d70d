"""The public video checks pass good estimators and catch the faults they are named after."""

import numpy as np
import pytest
from sklearn.base import BaseEstimator, TransformerMixin
from sklearn.utils.validation import check_is_fitted

from sklearn_hardness.models._pipelines import FrameScaler
from sklearn_hardness.utils._tags import frames_tags
from sklearn_hardness.utils.estimator_checks import (
    VIDEO_CHECKS,
    check_tags_match_input,
    check_video_estimator,
    check_video_input_unchanged,
    check_video_refit_idempotent,
    check_video_sample_order_invariance,
)


def _frames(n=6, seed=0):
    return np.random.default_rng(seed).random((n, 3, 8, 8, 1), dtype=np.float32), np.arange(n) % 2


class _Scaler(TransformerMixin, BaseEstimator):
    """A frames transformer with switchable faults."""

    def __init__(self, fault=None):
        self.fault = fault

    def fit(self, X, y=None):
        if self.fault == "stateful" and hasattr(self, "scale_"):
            self.scale_ = self.scale_ + float(np.std(X))  # remembers earlier fits
        else:
            self.scale_ = float(np.std(X))
        return self

    def transform(self, X):
        check_is_fitted(self, "scale_")
        if self.fault == "inplace":
            X /= self.scale_
            return X
        out = X / self.scale_
        if self.fault == "order":
            out = out + np.arange(len(X), dtype=np.float32).reshape(-1, 1, 1, 1, 1)
        return out

    def __sklearn_tags__(self):
        tags = super().__sklearn_tags__()
        return tags if self.fault == "tags" else frames_tags(tags)


def test_a_good_estimator_passes_every_check():
    X, y = _frames()
    assert check_video_estimator(FrameScaler(), X, y) == [c.__name__ for c in VIDEO_CHECKS]
    assert check_video_estimator(_Scaler(), X, y) == [c.__name__ for c in VIDEO_CHECKS]


@pytest.mark.parametrize(
    "fault, check",
    [
        ("inplace", check_video_input_unchanged),
        ("stateful", check_video_refit_idempotent),
        ("order", check_video_sample_order_invariance),
        ("tags", check_tags_match_input),
    ],
)
def test_each_check_catches_its_fault(fault, check):
    X, y = _frames()
    check("good", _Scaler(), X.copy(), y)  # the same check passes without the fault
    with pytest.raises(AssertionError):
        check("faulty", _Scaler(fault=fault), X.copy(), y)
    with pytest.raises(AssertionError, match=check.__name__):
        check_video_estimator(_Scaler(fault=fault), X.copy(), y)


def test_expected_failures_are_not_run():
    X, y = _frames()
    passed = check_video_estimator(_Scaler(fault="tags"), X, y,
                                   expected_failed_checks={"check_tags_match_input": "known"})
    assert "check_tags_match_input" not in passed and len(passed) == len(VIDEO_CHECKS) - 1
