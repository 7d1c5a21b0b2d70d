"""Common checks for every public estimator, in one place.

As in imbalanced-learn's ``tests/test_common.py`` and scikit-learn's
``utils/_test_common/instance_generator.py`` there are two tables:

- ``ESTIMATORS``: how to build each public estimator for the checks (small
  and fast) and which input it takes (``"videos"``, selected ``"frames"``
  (n, k, H, W, C) or a 2-D ``"table"``);
- ``EXPECTED_FAILED_CHECKS``: every check an estimator is known to fail
  today, each with its reason.

Three families of checks run:

1. scikit-learn's ``parametrize_with_checks`` on every estimator. Its tags
   decide what runs: for 2-D estimators (the OFNN and DINOv2NN heads) the
   full set; for video/frame estimators with honest tags
   (``two_d_array=False``) scikit-learn yields only ``check_estimator_cloneable``.
2. ``DATA_FREE_CHECKS``: scikit-learn's checks that never touch data, for the
   estimators scikit-learn skips because their input is not 2-D.
3. Video-input versions of the checks that matter for video estimators
   (``VIDEO_CHECKS``): not-fitted error, pickling, refit idempotence, clone,
   n_jobs invariance, sample-order invariance, input left unchanged, tags
   matching the input. They run on every estimator with its own input.

Expected failures of family 3 are strict: once an estimator is fixed the
test reports XPASS as a failure, so the table cannot silently go stale.
"""

from __future__ import annotations

import importlib
import inspect
import pickle
import warnings

import numpy as np
import pytest
import torch
from sklearn.base import BaseEstimator, clone
from sklearn.datasets import make_blobs
from sklearn.exceptions import NotFittedError
from sklearn.utils import get_tags
from sklearn.utils import estimator_checks as ec

from sklearn_hardness.active import ActiveLearner
from sklearn_hardness.features import ContactProfileFeatures, DINOv2Features, OpticalFlowFeatures
from sklearn_hardness.models import (
    ConvLSTMClassifier,
    DINOv2NNClassifier,
    EnsembleClassifier,
    FrameScaler,
    IntensityChannels,
    OFNNClassifier,
)
from sklearn_hardness.preprocessing import ContactFrameSelector

from ._synthetic import synthetic_press


def _tiny_dinov2_backbone():
    import transformers  # the [dinov2] extra; CI installs it

    torch.manual_seed(0)
    cfg = transformers.Dinov2Config(
        hidden_size=16, num_hidden_layers=1, num_attention_heads=2, intermediate_size=32,
        image_size=28, patch_size=14,
    )
    return transformers.Dinov2Model(cfg).eval()


def _ofnn(**kw):
    return OFNNClassifier(hidden_units=16, lr=3e-2, max_epochs=5, batch_size=64, random_state=0, **kw)


# ------------------------------------------------------------------ table 1
#: name -> (factory of a small, fast instance, kind of input it takes)
ESTIMATORS = {
    "ContactFrameSelector": (lambda: ContactFrameSelector(n_between=1, output_size=(12, 16)), "videos"),
    "OpticalFlowFeatures": (lambda: OpticalFlowFeatures(n_features=8, min_distance=3), "frames"),
    "DINOv2Features": (
        lambda: DINOv2Features(model=_tiny_dinov2_backbone(), image_size=28, batch_size=4), "frames"
    ),
    "FrameScaler": (FrameScaler, "frames"),
    "IntensityChannels": (IntensityChannels, "frames"),
    "ContactProfileFeatures": (lambda: ContactProfileFeatures(), "videos"),
    "OFNNClassifier": (_ofnn, "table"),
    "DINOv2NNClassifier": (
        lambda: DINOv2NNClassifier(hidden_units=16, lr=3e-2, max_epochs=5, batch_size=64, random_state=0),
        "table",
    ),
    "ConvLSTMClassifier": (lambda: ConvLSTMClassifier(filters=(2,), max_epochs=2, random_state=0), "frames"),
    "EnsembleClassifier": (lambda: EnsembleClassifier(_ofnn(), n_estimators=2, random_state=0), "table"),
    "ActiveLearner": (
        lambda: ActiveLearner(_ofnn(), initial_epochs=5, epochs_per_query=2, n_mc_samples=4, random_state=0),
        "table",
    ),
}

#: Public estimator-like classes deliberately not in ESTIMATORS, with the reason.
NOT_CHECKED = {
    "MCDropoutClassifierBase": "abstract base of the nets (no module); checked through its subclasses",
    "MCDropoutPipeline": "a sklearn Pipeline (meta-estimator); its steps are checked one by one",
}

# ------------------------------------------------------------------ table 2
_TAGS_SAY_2D = (
    "its __sklearn_tags__ claim 2-D input (input_tags.two_d_array=True) but X is {input}; "
    "scikit-learn's 2-D data checks get a clear 'X must be ...' error. Fix: two_d_array=False "
    "in its tags ({owner}); the video versions of these checks run below"
)
# scikit-learn's data checks an estimator with 5-D/video input fails when its tags say 2-D
_CHECKS_ON_2D_DATA = [
    "check_fit_score_takes_y",
    "check_estimators_overwrite_params",
    "check_dont_overwrite_parameters",
    "check_estimators_fit_returns_self",
    "check_readonly_memmap_input",
    "check_n_features_in_after_fitting",
    "check_positive_only_tag_during_fit",
    "check_estimators_dtypes",
    "check_complex_data",
    "check_dtype_object",
    "check_estimators_empty_data_messages",
    "check_pipeline_consistency",
    "check_estimators_nan_inf",
    "check_estimator_sparse_tag",
    "check_estimator_sparse_array",
    "check_estimator_sparse_matrix",
    "check_estimators_pickle",
    "check_f_contiguous_array_estimator",
    "check_transformer_data_not_an_array",
    "check_transformer_general",
    "check_transformer_preserve_dtypes",
    "check_classifier_data_not_an_array",
    "check_classifiers_one_label_sample_weights",
    "check_classifiers_classes",
    "check_estimators_partial_fit_n_features",
    "check_classifiers_train",
    "check_supervised_y_2d",
    "check_methods_sample_order_invariance",
    "check_methods_subset_invariance",
    "check_fit2d_1sample",
    "check_fit2d_1feature",
    "check_dict_unchanged",
    "check_fit_idempotent",
    "check_fit_check_is_fitted",
    "check_n_features_in",
    "check_fit2d_predict1d",
]


def _on_2d_data(input_, owner, passing=()):
    reason = _TAGS_SAY_2D.format(input=input_, owner=owner)
    return {name: reason for name in _CHECKS_ON_2D_DATA if name not in passing}


_SKORCH_INIT = (
    "skorch's NeuralNet.__init__ sets history_, initialized_, virtual_params_ (skorch design, "
    "not ours to change)"
)
_NET_2D_MESSAGES = {
    "check_no_attributes_set_in_init": _SKORCH_INIT,
    "check_n_features_in_after_fitting": (
        "the n_features mismatch message says 'was fitted with', sklearn expects 'is expecting'"
    ),
    "check_classifier_data_not_an_array": "the 2-D shape test calls np.ndim on an array-like before check_array",
    "check_classifiers_regression_target": "a continuous y is not rejected with 'Unknown label type'",
    "check_supervised_y_2d": "a column-vector y gives no DataConversionWarning",
    "check_fit2d_1sample": "the one-sample error says 'needs at least 2 classes' (sklearn wants '1 class')",
    "check_set_params": "skorch's set_params fails on the check's arbitrary values ('float' has no 'add')",
    "check_fit2d_predict1d": "the 1-D input error does not say 'Reshape your data'",
    "check_requires_y_none": "fit(X, None) fails inside skorch without saying 'requires y to be passed'",
}
_LEARNER_INT_LABELS = (
    "without classes=, integer labels are class indices 0..K-1 and every class must be in the "
    "initial set (design: the learner must name the classes it has not seen)"
)

EXPECTED_FAILED_CHECKS = {
    "ContactFrameSelector": {
        **_on_2d_data(
            "a sequence of videos",
            "preprocessing, sensors branch",
            # its own input check rejects complex and sparse X with the words sklearn looks for
            passing=(
                "check_complex_data",
                "check_estimator_sparse_tag",
                "check_estimator_sparse_array",
                "check_estimator_sparse_matrix",
            ),
        ),
        "check_tags_match_input": _TAGS_SAY_2D.format(
            input="a sequence of videos", owner="preprocessing, sensors branch"
        ),
    },
    "FrameScaler": {
        **_on_2d_data("selected frames (n, k, H, W, C)", "models branch"),
        "check_tags_match_input": _TAGS_SAY_2D.format(
            input="selected frames (n, k, H, W, C)", owner="models branch"
        ),
    },
    "ConvLSTMClassifier": {
        **_on_2d_data("selected frames (n, k, H, W, C)", "models branch"),
        "check_tags_match_input": _TAGS_SAY_2D.format(
            input="selected frames (n, k, H, W, C)", owner="models branch"
        ),
        "check_no_attributes_set_in_init": _SKORCH_INIT,
        "check_classifiers_one_label": "one-label y fails in the frames check before the label check",
        "check_classifiers_regression_target": _NET_2D_MESSAGES["check_classifiers_regression_target"],
        "check_set_params": _NET_2D_MESSAGES["check_set_params"],
        "check_requires_y_none": _NET_2D_MESSAGES["check_requires_y_none"],
        "check_class_weight_classifiers": _TAGS_SAY_2D.format(
            input="selected frames (n, k, H, W, C)", owner="models branch"
        ),
    },
    "OFNNClassifier": {
        **_NET_2D_MESSAGES,
    },
    "DINOv2NNClassifier": {
        **_NET_2D_MESSAGES,
    },
    "EnsembleClassifier": {
        name: "fit and predict pass X and y to its OFNN members unchanged, so it fails as they do: "
        + _NET_2D_MESSAGES[name]
        for name in (
            "check_n_features_in_after_fitting",
            "check_classifier_data_not_an_array",
            "check_classifiers_regression_target",
            "check_supervised_y_2d",
            "check_fit2d_1sample",
            "check_fit2d_predict1d",
            "check_requires_y_none",
        )
    },
    "ActiveLearner": {
        "check_n_features_in_after_fitting": "does not set n_features_in_ (delegates to its estimator)",
        "check_n_features_in": "does not set n_features_in_ (delegates to its estimator)",
        "check_estimators_dtypes": _LEARNER_INT_LABELS,
        "check_classifiers_classes": _LEARNER_INT_LABELS,
        "check_fit2d_1sample": _LEARNER_INT_LABELS,
        "check_fit2d_1feature": _LEARNER_INT_LABELS,
        "check_classifier_data_not_an_array": "rejects sklearn's _NotAnArray wrapper ('X must be an array or a sequence')",
        "check_classifiers_regression_target": "a continuous y is not rejected with 'Unknown label type'",
        "check_supervised_y_2d": "a column-vector y is an error ('y must be 1-D'), not a DataConversionWarning",
        "check_fit2d_predict1d": _NET_2D_MESSAGES["check_fit2d_predict1d"],
        "check_requires_y_none": _NET_2D_MESSAGES["check_requires_y_none"],
    },
}


# Under load on 2 cores, 2 torch threads made check_classifiers_train 4-15x slower than 1.
pytestmark = pytest.mark.torch_threads(1)


def _build(name):
    return ESTIMATORS[name][0]()


def _expected_failed_checks(estimator):
    return EXPECTED_FAILED_CHECKS.get(type(estimator).__name__, {})


# ----------------------------------------------------------- completeness
def _public_estimator_classes():
    found = {}
    for sub in ("preprocessing", "features", "models", "active", "datasets", "metrics", "io", "experiments"):
        mod = importlib.import_module(f"sklearn_hardness.{sub}")
        for name in getattr(mod, "__all__", []):
            obj = getattr(mod, name)
            if inspect.isclass(obj) and issubclass(obj, BaseEstimator):
                found[name] = obj
    return found


def test_every_public_estimator_is_in_the_tables():
    public = set(_public_estimator_classes())
    assert public - set(NOT_CHECKED) == set(ESTIMATORS), (
        "add new public estimators to ESTIMATORS (or NOT_CHECKED with a reason)"
    )
    for name, failures in EXPECTED_FAILED_CHECKS.items():
        assert name in ESTIMATORS
        assert all(isinstance(reason, str) and reason for reason in failures.values())


# ------------------------------------------------------ 1. scikit-learn checks
with warnings.catch_warnings():
    # scikit-learn warns (at collection) that it skips the 2-D checks for 5-D estimators
    warnings.simplefilter("ignore", ec.SkipTestWarning)
    _sklearn_checks = ec.parametrize_with_checks(
        [_build(name) for name in ESTIMATORS], expected_failed_checks=_expected_failed_checks
    )


@_sklearn_checks
def test_sklearn_checks(estimator, check):
    check(estimator)


# ------------------------------------------- 2. data-free scikit-learn checks
#: scikit-learn's checks that do not touch data, which it skips for non-2-D estimators.
DATA_FREE_CHECKS = [
    ec.check_estimator_tags_renamed,
    ec.check_valid_tag_types,
    ec.check_estimator_repr,
    ec.check_no_attributes_set_in_init,
    ec.check_do_not_raise_errors_in_init_or_set_params,
    ec.check_mixin_order,
    ec.check_parameters_default_constructible,
    ec.check_get_params_invariance,
    ec.check_set_params,
]

_NOT_2D = [name for name in ESTIMATORS if not get_tags(_build(name)).input_tags.two_d_array]


@pytest.mark.parametrize("check", DATA_FREE_CHECKS, ids=lambda c: c.__name__)
@pytest.mark.parametrize("name", _NOT_2D)
def test_data_free_checks(name, check, request):
    _mark_expected_failure(request, name, check.__name__)
    check(name, _build(name))


# ------------------------------------------------------ 3. video-input checks
def _videos(n=6, seed=0):
    videos = [
        synthetic_press(n_frames=14, size=(24, 32), contact_start=4, peak=8, radius=6, seed=seed + i)
        for i in range(n)
    ]
    return videos, np.arange(n) % 2


def _frames(n=6, seed=0):
    rng = np.random.default_rng(seed)
    out = np.empty((n, 3, 24, 28, 1), np.float32)
    for i in range(n):
        tex = rng.random((24, 28 + 6)).astype(np.float32)
        shift = i % 3
        out[i, :, :, :, 0] = np.stack([tex[:, s * shift : s * shift + 28] for s in range(3)])
    return out, np.arange(n) % 2


def _table(n=30, seed=0):
    X, y = make_blobs(n_samples=n, centers=3, n_features=4, cluster_std=0.5, random_state=seed)
    return X.astype(np.float32), y


_DATA = {"videos": _videos, "frames": _frames, "table": _table}


def _data(name, seed=0):
    return _DATA[ESTIMATORS[name][1]](seed=seed)


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


def _copy_input(X):
    return [np.array(v, copy=True) for v in X] if isinstance(X, list) else np.array(X, copy=True)


def _assert_same_input(X, X_before):
    if isinstance(X, list):
        assert len(X) == len(X_before)
        for a, b in zip(X, X_before):
            np.testing.assert_array_equal(a, b)
    else:
        np.testing.assert_array_equal(X, X_before)


def _take(X, idx):
    return [X[i] for i in idx] if isinstance(X, list) else X[idx]


def check_video_unfitted_raises(name, estimator, X, y):
    """Every output method before fit raises NotFittedError."""
    for method in _OUTPUT_METHODS:
        if hasattr(estimator, method):
            with pytest.raises(NotFittedError):
                _output(estimator, X, method)


def check_video_pickle(name, estimator, X, y):
    """A fitted estimator pickles and gives the same output after loading."""
    _fit(estimator, X, y)
    expected = _output(estimator, X)
    loaded = pickle.loads(pickle.dumps(estimator))
    np.testing.assert_allclose(_output(loaded, X), expected, rtol=1e-6, atol=1e-6)


def check_video_refit_idempotent(name, estimator, X, y):
    """fit(A); fit(B); fit(A) gives the output of the first fit(A)."""
    _fit(estimator, X, y)
    first = _output(estimator, X)
    X_other, y_other = _data(name, seed=1)
    _fit(estimator, X_other, y_other)
    _fit(estimator, X, y)
    np.testing.assert_allclose(_output(estimator, X), first, rtol=1e-5, atol=1e-6)


def check_video_clone_is_unfitted(name, estimator, X, y):
    """clone of a fitted estimator has its parameters and none of its fitted state."""
    _fit(estimator, X, y)
    cloned = clone(estimator)
    assert set(cloned.get_params(deep=False)) == set(estimator.get_params(deep=False))
    check_video_unfitted_raises(name, cloned, X, y)


def check_video_n_jobs_invariance(name, estimator, X, y):
    """n_jobs=2 gives exactly the output of n_jobs=1."""
    if "n_jobs" not in estimator.get_params():
        return
    one = _output(_fit(clone(estimator).set_params(n_jobs=1), X, y), X)
    two = _output(_fit(clone(estimator).set_params(n_jobs=2), X, y), X)
    np.testing.assert_array_equal(two, one)


def check_video_sample_order_invariance(name, estimator, X, y):
    """The output of a permuted input is the permuted output."""
    _fit(estimator, X, y)
    perm = np.random.default_rng(0).permutation(len(X))
    np.testing.assert_allclose(_output(estimator, _take(X, perm)), _output(estimator, X)[perm], rtol=1e-5, atol=1e-6)


def check_video_input_unchanged(name, estimator, X, y):
    """fit and the output methods leave X untouched."""
    before = _copy_input(X)
    _fit(estimator, X, y)
    _output(estimator, X)
    _assert_same_input(X, before)


def check_tags_match_input(name, estimator, X, y):
    """The tags say 2-D input exactly when the estimator takes a 2-D table."""
    takes_table = ESTIMATORS[name][1] == "table"
    assert get_tags(estimator).input_tags.two_d_array == takes_table


VIDEO_CHECKS = [
    check_video_unfitted_raises,
    check_video_pickle,
    check_video_refit_idempotent,
    check_video_clone_is_unfitted,
    check_video_n_jobs_invariance,
    check_video_sample_order_invariance,
    check_video_input_unchanged,
    check_tags_match_input,
]


def _mark_expected_failure(request, name, check_name):
    reason = EXPECTED_FAILED_CHECKS.get(name, {}).get(check_name)
    if reason is not None:
        request.applymarker(pytest.mark.xfail(reason=reason, strict=True))


@pytest.mark.parametrize("check", VIDEO_CHECKS, ids=lambda c: c.__name__)
@pytest.mark.parametrize("name", list(ESTIMATORS))
def test_video_checks(name, check, request):
    _mark_expected_failure(request, name, check.__name__)
    X, y = _data(name)
    check(name, _build(name), X, y)
