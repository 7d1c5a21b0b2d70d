"""The public checks pass good estimators and catch the faults they are named after."""

import pathlib
from numbers import Integral, Real

import numpy as np
import pytest
from sklearn.base import BaseEstimator, TransformerMixin
from sklearn.utils.validation import check_is_fitted

from sklearn_hardness.models._pipelines import FrameScaler
from sklearn_hardness.utils._param_validation import (
    Interval,
    InvalidParameterError,
    fit_context,
    validate_estimator_params,
)
from sklearn_hardness.utils._tags import frames_tags
from sklearn_hardness.utils.estimator_checks import (
    VIDEO_CHECKS,
    check_param_validation,
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


# ---------------------------------------------------------------- check_param_validation
class _Thresholder(TransformerMixin, BaseEstimator):
    """A frames transformer whose parameter validation can be broken in each way the check looks for."""

    _parameter_constraints = {"k": [Interval(Integral, 1, None, closed="left")], "fault": [str, None]}

    def __init__(self, k=1, fault=None):
        self.k = k
        self.fault = fault

    @fit_context(prefer_skip_nested_validation=True)
    def _validated_fit(self, X, y=None):
        return self

    def fit(self, X, y=None):
        if self.fault == "unvalidated":
            return self
        if self.fault == "own message" and not (isinstance(self.k, Integral) and self.k >= 1):
            raise InvalidParameterError(f"k must be positive, got {self.k!r}")
        if self.fault == "stricter" and self.k != 1:
            raise InvalidParameterError(f"The 'k' parameter of _Thresholder must be 1. Got {self.k!r} instead.")
        return self._validated_fit(X, y)

    def transform(self, X):
        return X

    def __sklearn_tags__(self):
        return frames_tags(super().__sklearn_tags__())


def _with_fault(fault):
    class Faulty(_Thresholder):
        pass

    Faulty.__name__ = "_Thresholder"
    if fault == "missing constraint":
        Faulty._parameter_constraints = {"k": _Thresholder._parameter_constraints["k"]}
    elif fault == "mixed intervals":
        Faulty._parameter_constraints = {**_Thresholder._parameter_constraints,
                                         "k": [Interval(Integral, 1, None, closed="left"),
                                               Interval(Real, 0, 1, closed="both")]}
    return Faulty(fault=None if fault in ("missing constraint", "mixed intervals") else fault)


def test_the_parameter_check_passes_a_good_estimator():
    X, y = _frames()
    check_param_validation("_Thresholder", _Thresholder(), X, y)


def test_the_parameter_check_writes_nothing_where_it_runs(tmp_path, monkeypatch):
    # memory's valid string is "": a joblib cache folder in the working directory, were the check
    # not run in a temporary one (CI's clone got a joblib/ folder, which then changed ruff's imports)
    from sklearn_hardness.preprocessing import ContactFrameSelector

    monkeypatch.chdir(tmp_path)
    videos = [np.random.default_rng(i).integers(0, 255, (8, 24, 32, 3), dtype=np.uint8) for i in range(4)]
    check_param_validation("ContactFrameSelector", ContactFrameSelector(n_between=1, frame_size=(12, 16)),
                           videos, None)
    assert list(tmp_path.iterdir()) == [] and pathlib.Path.cwd() == tmp_path


@pytest.mark.parametrize("fault, message", [
    ("missing constraint", r"parameters without constraints \['fault'\]"),
    ("mixed intervals", "mix intervals of Integral and Real"),
    ("unvalidated", "raised no InvalidParameterError"),
    ("own message", r"does not say \"The 'k' parameter of _Thresholder must be"),
    ("stricter", "a value its constraints accept, raised a parameter error"),
])
def test_the_parameter_check_catches_each_fault(fault, message):
    X, y = _frames()
    with pytest.raises(AssertionError, match=message):
        check_param_validation("_Thresholder", _with_fault(fault), X, y)


def test_the_parameter_check_needs_a_method_that_validates():
    class Mirror(BaseEstimator):  # no fit: like FrameAugmenter, its own method validates
        _parameter_constraints = {"k": [Interval(Integral, 1, None, closed="left")]}

        def __init__(self, k=1):
            self.k = k

        def apply(self, X, y=None):
            validate_estimator_params(self)
            return X[..., ::-1]

    X, y = _frames()
    with pytest.raises(AssertionError, match="pass the methods that validate its parameters"):
        check_param_validation("Mirror", Mirror(), X, y)
    check_param_validation("Mirror", Mirror(), X, y, methods=("apply",))
