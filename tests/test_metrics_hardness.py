"""hardness_mae and its scorer."""

import numpy as np
import pytest
from sklearn.model_selection import GridSearchCV, cross_val_score
from sklearn.neighbors import KNeighborsClassifier

from sklearn_hardness.metrics import hardness_mae, make_hardness_mae_scorer

COMPLIANCE = [1.13, 1.02, 0.79, 0.68, 0.44]  # silicone5, mm/N


def test_values_by_index():
    assert hardness_mae([0, 1, 2], [0, 1, 2], COMPLIANCE) == 0.0
    assert hardness_mae([0], [4], COMPLIANCE) == pytest.approx(1.13 - 0.44)
    assert hardness_mae([0, 4], [1, 3], COMPLIANCE) == pytest.approx((0.11 + 0.24) / 2)
    # symmetric, and closer confusions cost less
    assert hardness_mae([1, 3], [0, 4], COMPLIANCE) == hardness_mae([0, 4], [1, 3], COMPLIANCE)
    assert hardness_mae([0], [1], COMPLIANCE) < hardness_mae([0], [4], COMPLIANCE)


def test_mapping_and_classes():
    shore = {"s8": 8.0, "s95": 95.0, "s46": 46.0}
    assert hardness_mae(["s8", "s95"], ["s46", "s95"], shore) == pytest.approx(19.0)
    assert hardness_mae([10, 20], [20, 20], [5.0, 7.0], classes=[10, 20]) == pytest.approx(1.0)
    assert hardness_mae(np.array(["b", "a"]), ["a", "a"], [1.0, 4.0], classes=["a", "b"]) == 1.5
    # a mapping with integer keys in any order
    assert hardness_mae([3, 1], [1, 1], {3: 0.5, 1: 2.0}) == pytest.approx(0.75)


def test_sample_weight():
    mae = hardness_mae([0, 0], [0, 4], COMPLIANCE, sample_weight=[3, 1])
    assert mae == pytest.approx(0.69 / 4)


def test_scorer_in_cross_val_and_grid_search():
    rng = np.random.default_rng(0)
    y = np.repeat(np.arange(5), 12)
    X = (np.asarray(COMPLIANCE)[y] + rng.normal(0, 0.05, y.size))[:, None]
    scorer = make_hardness_mae_scorer(COMPLIANCE)
    scores = cross_val_score(KNeighborsClassifier(3), X, y, cv=3, scoring=scorer)
    assert np.all(scores <= 0)  # negative MAE, greater is better
    clf = KNeighborsClassifier(3).fit(X[::2], y[::2])
    assert scorer(clf, X[1::2], y[1::2]) == pytest.approx(
        -hardness_mae(y[1::2], clf.predict(X[1::2]), COMPLIANCE))
    search = GridSearchCV(KNeighborsClassifier(), {"n_neighbors": [1, 5]}, scoring=scorer, cv=3)
    search.fit(X, y)
    assert search.best_score_ <= 0
    assert search.best_score_ > -0.1


@pytest.mark.parametrize(
    "args, kwargs, match",
    [
        (([0, 5], [0, 1], COMPLIANCE), {}, r"y_true has labels \[5\] with no hardness"),
        (([0, 1], [0, -1], COMPLIANCE), {}, r"y_pred has labels \[-1\]"),
        ((["x"], ["a"], {"a": 1.0}), {}, r"y_true has labels \['x'\]"),
        (([0, 1], [0], COMPLIANCE), {}, "y_true has 2 samples but y_pred has 1"),
        (([0], [0], [1.0, 2.0]), {"classes": [0, 1, 2]}, "classes has 3 entries but hardness has 2"),
        (([0], [0], [1.0, np.nan]), {}, "NaN"),
        (([0], [0], []), {}, "empty"),
        (([0], [0], [[1.0, 2.0]]), {}, "1-D"),
        (([0], [0], {0: 1.0}), {"classes": [0]}, "not both"),
        (([], [], COMPLIANCE), {}, "empty"),
        (([0], [0], [1.0, 2.0]), {"classes": [0, 0]}, "duplicate"),
        (([0, 1], [0, 1], COMPLIANCE), {"sample_weight": [1.0]}, "sample_weight"),
        (([[0, 1]], [[0, 1]], COMPLIANCE), {}, "1-D"),
    ],
)
def test_bad_input(args, kwargs, match):
    with pytest.raises(ValueError, match=match):
        hardness_mae(*args, **kwargs)


def test_scorer_validates_eagerly():
    with pytest.raises(ValueError, match="NaN"):
        make_hardness_mae_scorer([1.0, np.inf])
