"""Common checks for every public estimator, in one place.

As in imbalanced-learn's ``tests/test_common.py`` and scikit-learn's
``utils/_test_common/instance_generator.py`` there are two tables:

- ``ESTIMATORS``: how to build each public estimator for the checks (small
  and fast) and which input it takes (``"videos"``, selected ``"frames"``
  (n, k, H, W, C) or a 2-D ``"table"``);
- ``EXPECTED_FAILED_CHECKS``: every check an estimator is known to fail
  today, each with its reason.

Four families of checks run:

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

4. Parameter validation (``check_param_validation``, as scikit-learn's and
   imbalanced-learn's ``test_check_param_validation``) on every public
   estimator, found through the subpackages' ``__all__``, and scikit-learn's
   ``test_public_functions`` check on every public function decorated with
   ``validate_params``: each constrained parameter given an invalid value
   raises our ``InvalidParameterError`` naming it.

The video checks are public (:mod:`sklearn_hardness.utils.estimator_checks`),
so users of our estimators can run them on theirs. Every expected failure is
strict (``xfail_strict = true`` in pyproject.toml, which scikit-learn's marks
of family 1 take too; families 2 and 3 pass ``strict=True``): once an
estimator is fixed the test reports XPASS as a failure, so the table cannot
silently go stale.
"""

from __future__ import annotations

import inspect
import types
import warnings

import numpy as np
import pytest
import torch
from sklearn.base import BaseEstimator
from sklearn.datasets import make_blobs
from sklearn.utils import estimator_checks as ec
from sklearn.utils import get_tags

import sklearn_hardness
from sklearn_hardness.active import ActiveLearner
from sklearn_hardness.features import (
    ContactGeometryFeatures,
    ContactProfileFeatures,
    DINOv2Features,
    ImprintTextureFeatures,
    LoadingCompliance,
    OpticalFlowFeatures,
    PeakContactChange,
)
from sklearn_hardness.models import (
    ContactProfileNNClassifier,
    ConvLSTMClassifier,
    DINOv2NNClassifier,
    EnsembleClassifier,
    FrameAugmenter,
    ImprintCNNClassifier,
    LaplaceLogisticRegression,
    MCDropoutPipeline,
    OFNNClassifier,
)
from sklearn_hardness.models._intensity_channels import IntensityChannels
from sklearn_hardness.models._pipelines import FrameScaler
from sklearn_hardness.preprocessing import ContactFrameSelector
from sklearn_hardness.utils._param_validation import InvalidParameterError, generate_valid_param, make_constraint
from sklearn_hardness.utils.estimator_checks import (
    _invalid_values,
    _parameter_error_message,
    check_param_validation,
    parametrize_with_video_checks,
)

from ._synthetic import hertz_press, synthetic_press


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
    "ContactFrameSelector": (lambda: ContactFrameSelector(n_between=1, frame_size=(12, 16)), "videos"),
    "OpticalFlowFeatures": (lambda: OpticalFlowFeatures(n_features=8, min_distance=3), "frames"),
    "DINOv2Features": (
        lambda: DINOv2Features(model=_tiny_dinov2_backbone(), image_size=28, batch_size=4), "frames"
    ),
    "FrameScaler": (FrameScaler, "frames"),
    "IntensityChannels": (IntensityChannels, "frames"),
    "ContactProfileFeatures": (lambda: ContactProfileFeatures(), "videos"),
    "ContactGeometryFeatures": (lambda: ContactGeometryFeatures(max_side=40), "videos"),
    "ImprintTextureFeatures": (lambda: ImprintTextureFeatures(max_side=40), "videos"),
    "LoadingCompliance": (LoadingCompliance, "force_position"),
    "PeakContactChange": (PeakContactChange, "videos"),
    "OFNNClassifier": (_ofnn, "table"),
    "DINOv2NNClassifier": (
        lambda: DINOv2NNClassifier(hidden_units=16, lr=3e-2, max_epochs=5, batch_size=64, random_state=0),
        "table",
    ),
    "ContactProfileNNClassifier": (
        lambda: ContactProfileNNClassifier(hidden_units=16, lr=3e-2, max_epochs=5, batch_size=64, random_state=0),
        "table",
    ),
    "LaplaceLogisticRegression": (LaplaceLogisticRegression, "table"),
    "ConvLSTMClassifier": (lambda: ConvLSTMClassifier(filters=(2,), max_epochs=2, random_state=0), "frames"),
    "ImprintCNNClassifier": (lambda: ImprintCNNClassifier(width=2, max_epochs=2, random_state=0), "frames"),
    "EnsembleClassifier": (lambda: EnsembleClassifier(_ofnn(), n_estimators=2, random_state=0), "table"),
    "ActiveLearner": (
        lambda: ActiveLearner(_ofnn(), initial_epochs=5, epochs_per_query=2, n_samples=4, random_state=0),
        "table",
    ),
}

#: Public estimator-like classes deliberately not in ESTIMATORS, with the reason.
NOT_CHECKED = {
    "MCDropoutClassifierBase": "abstract base of the nets (no module); checked through its subclasses",
    "MCDropoutPipeline": "a sklearn Pipeline (meta-estimator); its steps are checked one by one "
    "(its parameters: test_check_param_validation)",
    "FrameAugmenter": "a parameter object of ConvLSTMClassifier (no fit, predict or transform); "
    "its get_params/clone are checked through the net's, in tests/test_models_augmentation.py "
    "(its parameters: test_check_param_validation)",
}

# ------------------------------------------------------------------ table 2
_SKORCH_INIT = (
    "skorch's NeuralNet.__init__ sets history_, initialized_, virtual_params_ (skorch design, "
    "not ours to change)"
)
_NET_2D_MESSAGES = {
    "check_no_attributes_set_in_init": _SKORCH_INIT,
    "check_set_params": "skorch's set_params fails on the check's arbitrary values ('float' has no 'add')",
}
_LEARNER_INT_LABELS = (
    "without classes=, integer labels are class indices 0..K-1 and every class must be in the "
    "initial set (design: the learner must name the classes it has not seen)"
)

EXPECTED_FAILED_CHECKS = {
    "ConvLSTMClassifier": {
        "check_no_attributes_set_in_init": _SKORCH_INIT,
        "check_set_params": _NET_2D_MESSAGES["check_set_params"],
    },
    "ImprintCNNClassifier": {
        "check_no_attributes_set_in_init": _SKORCH_INIT,
        "check_set_params": _NET_2D_MESSAGES["check_set_params"],
    },
    "OFNNClassifier": {
        **_NET_2D_MESSAGES,
    },
    "DINOv2NNClassifier": {
        **_NET_2D_MESSAGES,
    },
    "ContactProfileNNClassifier": {
        **_NET_2D_MESSAGES,
    },
    "ActiveLearner": {
        "check_n_features_in_after_fitting": "does not set n_features_in_ (delegates to its estimator)",
        "check_n_features_in": "does not set n_features_in_ (delegates to its estimator)",
        "check_estimators_dtypes": _LEARNER_INT_LABELS,
        "check_classifiers_classes": _LEARNER_INT_LABELS,
        "check_fit2d_1sample": _LEARNER_INT_LABELS,
        "check_fit2d_1feature": _LEARNER_INT_LABELS,
        "check_classifier_data_not_an_array":
            "rejects sklearn's _NotAnArray wrapper ('X must be an array or a sequence')",
        "check_supervised_y_2d": "a column-vector y is an error ('y must be 1-D'), not a DataConversionWarning",
        "check_requires_y_none": "fit(X, None) fails without saying 'requires y to be passed'",
    },
}


# Under load on 2 cores, 2 torch threads made check_classifiers_train 4-15x slower than 1.
pytestmark = pytest.mark.torch_threads(1)


def _build(name):
    return ESTIMATORS[name][0]()


def _expected_failed_checks(estimator):
    return EXPECTED_FAILED_CHECKS.get(type(estimator).__name__, {})


# ----------------------------------------------------------- completeness
def _public(predicate):
    """``name -> object`` for every name in the ``__all__`` of a public subpackage that ``predicate`` takes.

    The subpackages are those ``sklearn_hardness.__all__`` names, so that what becomes public or
    private later is found (or left) without a list here."""
    found = {}
    for sub in sklearn_hardness.__all__:
        mod = getattr(sklearn_hardness, sub)  # imports the subpackage
        if not isinstance(mod, types.ModuleType):  # __version__
            continue
        for name in getattr(mod, "__all__", []):
            obj = getattr(mod, name)
            if predicate(obj):
                found[name] = obj
    return found


def _public_estimator_classes():
    return _public(lambda obj: inspect.isclass(obj) and issubclass(obj, BaseEstimator))


def test_every_public_estimator_is_in_the_tables():
    public = set(_public_estimator_classes())
    # the tables may check private estimators too (the pipelines' FrameScaler, IntensityChannels)
    assert public - set(NOT_CHECKED) <= set(ESTIMATORS), (
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


def _force_position(n=6, seed=0):
    rng = np.random.default_rng(seed)  # lengths differ; position = offset + c F^(2/3), noisy force
    X = [hertz_press(1 + i % 2, rng.uniform(2, 6), n_load=8 + i, offset=rng.uniform(-5, 5), noise=0.02, rng=rng)
         for i in range(n)]
    return X, np.arange(n) % 2


_DATA = {"videos": _videos, "frames": _frames, "table": _table, "force_position": _force_position}


def _data(name, seed=0):
    return _DATA[ESTIMATORS[name][1]](seed=seed)


def _mark_expected_failure(request, name, check_name):
    reason = EXPECTED_FAILED_CHECKS.get(name, {}).get(check_name)
    if reason is not None:
        request.applymarker(pytest.mark.xfail(reason=reason, strict=True))


@parametrize_with_video_checks(
    {name: (ESTIMATORS[name][0], lambda name=name: _data(name)) for name in ESTIMATORS},
    expected_failed_checks=lambda name: EXPECTED_FAILED_CHECKS.get(name, {}),
)
def test_video_checks(name, factory, data, check):
    check(name, factory(), *data())


#: Configurations other than the default whose output and fitted attributes differ from it: a choice of
#: features, in another order than the default's (``features_``, ``get_feature_names_out`` follow it).
FEATURE_SUBSETS = {
    "ContactProfileFeatures(features=2)": (
        lambda: ContactProfileFeatures(features=("log_loading_time", "log_peak_change")), "videos"),
    "ContactGeometryFeatures(features=scale_free)": (
        lambda: ContactGeometryFeatures(features="scale_free", max_side=40), "videos"),
    "ImprintTextureFeatures(descriptors=2, moments=3)": (
        lambda: ImprintTextureFeatures(descriptors=("spectrum", "lbp"), moments=(1.0, 0.25, 0.5), max_side=40),
        "videos"),
    "LoadingCompliance(features=2)": (
        lambda: LoadingCompliance(features=("travel", "hertz_compliance")), "force_position"),
}


@parametrize_with_video_checks(
    {name: (factory, lambda kind=kind: _DATA[kind]()) for name, (factory, kind) in FEATURE_SUBSETS.items()}
)
def test_video_checks_on_a_choice_of_features(name, factory, data, check):
    check(name, factory(), *data())


def test_tags_match_the_input_table():
    """The ESTIMATORS table's input kinds and the estimators' own tags agree."""
    for name, (factory, kind) in ESTIMATORS.items():
        assert get_tags(factory()).input_tags.two_d_array == (kind == "table"), name


def test_expected_failures_are_strict(pytestconfig):
    """scikit-learn's xfail marks carry no strict= of their own: pyproject.toml's xfail_strict decides."""
    assert pytestconfig.getini("xfail_strict") is True


# --------------------------------------------------- 4. parameter validation
#: Public estimators whose parameters scikit-learn validates, not our machinery: they inherit a
#: scikit-learn class's table and raise scikit-learn's own InvalidParameterError. scikit-learn's
#: public ``check_param_validation`` runs on them instead (it needs 2-D input, which both take).
SKLEARN_VALIDATED = {
    "LaplaceLogisticRegression": (
        LaplaceLogisticRegression,
        "a LogisticRegression: scikit-learn's table and its fit validate the parameters (it adds none)"),
    "MCDropoutPipeline": (
        lambda: MCDropoutPipeline([("clf", _ofnn())]),
        "a Pipeline: scikit-learn's table and its fit validate steps, memory, transform_input and verbose; "
        "the steps are checked one by one"),
}

#: How the check runs public estimators that ESTIMATORS does not build: name -> (factory, data, methods).
PARAM_CHECK_CASES = {
    # a parameter object of ConvLSTMClassifier: its augment(X) validates the parameters
    "FrameAugmenter": (FrameAugmenter, lambda: (torch.from_numpy(_frames()[0]), None), ("augment",)),
}

_PUBLIC_ESTIMATORS = sorted(_public_estimator_classes())


def _param_check_case(name):
    if name in PARAM_CHECK_CASES:
        return PARAM_CHECK_CASES[name]
    assert name in ESTIMATORS, f"add {name} to ESTIMATORS (or PARAM_CHECK_CASES, saying how to run it)"

    def factory():
        estimator = _build(name)
        # the check is about parameters, not training: a net fits for no epoch (max_epochs=0 is valid)
        return estimator.set_params(max_epochs=0) if "max_epochs" in estimator.get_params(deep=False) else estimator

    return factory, lambda: _data(name), None


@pytest.mark.parametrize("name", _PUBLIC_ESTIMATORS)
def test_check_param_validation(name):
    if name in SKLEARN_VALIDATED:
        factory = SKLEARN_VALIDATED[name][0]
        owner = next(k for k in type(factory()).__mro__ if "_parameter_constraints" in vars(k))
        assert owner.__module__.startswith("sklearn."), f"{name}'s table is {owner.__module__}'s: drop it here"
        with warnings.catch_warnings():
            warnings.simplefilter("ignore")  # convergence and deprecation warnings of the fits
            ec.check_param_validation(name, factory())
        return
    factory, data, methods = _param_check_case(name)
    check_param_validation(name, factory(), *data(), methods=methods)


def test_the_parameter_check_tables_name_public_estimators():
    assert set(SKLEARN_VALIDATED) | set(PARAM_CHECK_CASES) <= set(_PUBLIC_ESTIMATORS)
    assert all(reason for _, reason in SKLEARN_VALIDATED.values())


_VALIDATED_FUNCTIONS = _public(lambda obj: inspect.isfunction(obj) and hasattr(obj, "_skl_parameter_constraints"))


def _check_function_param_validation(name, func):
    """scikit-learn's ``_check_function_param_validation`` (sklearn/tests/test_public_functions.py)."""
    constraints = func._skl_parameter_constraints
    signature = inspect.signature(func)
    own = [p for p in signature.parameters.values() if p.kind not in (p.VAR_POSITIONAL, p.VAR_KEYWORD)]
    assert set(constraints) == {p.name for p in own}, (
        f"Mismatch between the constraints and the parameters of {name}: "
        f"{sorted(set(constraints) ^ {p.name for p in own})}")
    required = {
        p.name: 1 if constraints[p.name] == "no_validation" else generate_valid_param(
            make_constraint(constraints[p.name][0]))
        for p in own if p.default is p.empty
    }
    for param in (p.name for p in own):
        if constraints[param] == "no_validation":
            continue
        for bad in _invalid_values(name, param, constraints[param]):
            with pytest.raises(InvalidParameterError) as exc_info:
                func(**{**required, param: bad})
            assert _parameter_error_message(param, func.__qualname__).search(str(exc_info.value)), (
                f"{name} with {param}={bad!r}: {exc_info.value}")


def test_public_functions_are_found():
    assert {"read_video", "hardness_mae", "entropy_sampling", "load_press_videos"} <= set(_VALIDATED_FUNCTIONS)


@pytest.mark.parametrize("name", sorted(_VALIDATED_FUNCTIONS))
def test_function_param_validation(name):
    _check_function_param_validation(name, _VALIDATED_FUNCTIONS[name])

