"""Tests of ContactProfileFeatures (shape-normalised features of the loading phase)."""

import numpy as np
import pytest
from sklearn.base import clone
from sklearn.linear_model import LogisticRegression
from sklearn.model_selection import cross_val_score
from sklearn.pipeline import make_pipeline
from sklearn.preprocessing import StandardScaler
from sklearn.utils._param_validation import InvalidParameterError

from sklearn_hardness.experiments import evaluate_pipelines, peak_contact_change
from sklearn_hardness.features import ContactProfileFeatures

from ._synthetic import growing_disc_press


def _press(rise, radius, rng):
    return growing_disc_press(rise, radius, rng)


def test_shape_names_and_short_videos():
    rng = np.random.default_rng(0)
    X = [_press(3, 6, rng), _press(30, 6, rng), np.full((1, 16, 16, 3), 9, np.uint8),
         np.full((2, 16, 16, 3), 9, np.uint8)]
    est = ContactProfileFeatures().fit(X)
    F = est.transform(X)
    assert F.shape == (4, 10) and np.all(np.isfinite(F))
    names = est.get_feature_names_out().tolist()
    assert len(names) == 10 and names[2] == "rise_frames"
    # slow loading is seen as slow loading, at the same peak
    assert F[1, names.index("rise_frames")] > F[0, names.index("rise_frames")] + 10
    assert abs(F[1, 0] - F[0, 0]) < 0.2
    # larger contact at the same change level: more area
    big = ContactProfileFeatures().fit_transform([_press(3, 12, rng)])
    assert big[0, names.index("area_at_peak")] > 2 * F[0, names.index("area_at_peak")]
    assert clone(est).get_params() == est.get_params()
    np.testing.assert_allclose(ContactProfileFeatures(n_jobs=2).fit_transform(X), F)


def test_separates_what_the_peak_change_cannot():
    # Two "ranks" with the same peak change: soft ones load slowly, hard ones fast.
    rng = np.random.default_rng(1)
    X, y = [], []
    for i in range(30):
        soft = i % 2
        X.append(_press(int(rng.integers(25, 40)) if soft else int(rng.integers(2, 6)),
                        float(rng.uniform(5, 9)), rng))
        y.append(soft)
    y = np.array(y)
    head = make_pipeline(StandardScaler(), LogisticRegression())
    F = ContactProfileFeatures().fit_transform(X)
    assert cross_val_score(head, F, y, cv=3).mean() >= 0.9
    assert cross_val_score(head, peak_contact_change(X), y, cv=3).mean() <= 0.75


@pytest.mark.parametrize("params", [dict(max_side=2), dict(noise_factor=0), dict(noise_factor="3")])
def test_bad_parameters(params):
    with pytest.raises(InvalidParameterError):
        ContactProfileFeatures(**params).fit([np.zeros((3, 8, 8, 3), np.uint8)])


def test_bad_input():
    with pytest.raises(TypeError, match="sequence of videos"):
        ContactProfileFeatures().fit("videos")
    with pytest.raises(ValueError):
        ContactProfileFeatures().fit_transform([np.zeros((3, 8, 8, 3), np.float32) + np.nan])


def test_contact_profile_pipeline_in_evaluate():
    from sklearn_hardness.datasets import make_presses

    d = make_presses("everyday", n_per_class=2, n_objects=9, class_ratio=[1, 1, 1], image_size=(32, 40),
                     codec=None, random_state=0)
    result = evaluate_pipelines(d, ["contact_profile"], cv=3)
    assert [r["pipeline"] for r in result.table] == ["peak_change", "contact_profile"]
    assert np.isfinite(result.table[1]["balanced_accuracy"])
