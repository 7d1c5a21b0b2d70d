"""scikit-learn's common estimator checks.

Our transformers take a sequence of videos, not a 2-D table; sklearn's data
checks feed 2-D tables, which we reject with a clear error. Those checks are
listed as expected failures with the reason, as imbalanced-learn does; the
same properties are tested on videos in the estimator's own test module
(fit idempotence, sample order and subset invariance, clone, pickling).
"""

from sklearn.utils.estimator_checks import parametrize_with_checks

from sklearn_hardness.preprocessing import ContactFrameSelector

_VIDEO_INPUT = (
    "X is a sequence of videos (T, H, W, C); the check passes a 2-D table, which is rejected "
    "with an error asking for videos. Tested on videos in tests/test_contact.py."
)

_SELECTOR_XFAIL = {
    name: _VIDEO_INPUT
    for name in [
        "check_fit_score_takes_y",
        "check_estimators_overwrite_params",
        "check_dont_overwrite_parameters",
        "check_estimators_fit_returns_self",
        "check_readonly_memmap_input",
        "check_n_features_in_after_fitting",
        "check_positive_only_tag_during_fit",
        "check_estimators_dtypes",
        "check_dtype_object",
        "check_estimators_empty_data_messages",
        "check_pipeline_consistency",
        "check_estimators_nan_inf",
        "check_estimators_pickle",
        "check_f_contiguous_array_estimator",
        "check_transformer_data_not_an_array",
        "check_transformer_general",
        "check_transformer_preserve_dtypes",
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
}


def _expected_failed_checks(estimator):
    if isinstance(estimator, ContactFrameSelector):
        return _SELECTOR_XFAIL
    return {}


@parametrize_with_checks([ContactFrameSelector()], expected_failed_checks=_expected_failed_checks)
def test_sklearn_compatible(estimator, check):
    check(estimator)
