"""Tests of ContactProfileFeatures (shape-normalised features of the loading phase)."""

import numpy as np
import pytest
from sklearn.base import clone
from sklearn.linear_model import LogisticRegression
from sklearn.model_selection import cross_val_score
from sklearn.pipeline import make_pipeline
from sklearn.preprocessing import StandardScaler

from sklearn_hardness.features import ContactProfileFeatures, PeakContactChange
from sklearn_hardness.model_selection import evaluate_pipelines
from sklearn_hardness.utils._param_validation import InvalidParameterError

from ._synthetic import FRAMED_GEL, framed_press, growing_disc_press, synthetic_press


def _press(rise, radius, rng):
    return growing_disc_press(rise, radius, rng)


def test_shape_names_and_short_videos():
    rng = np.random.default_rng(0)
    X = [_press(3, 6, rng), _press(30, 6, rng), np.full((1, 16, 16, 3), 9, np.uint8),
         np.full((2, 16, 16, 3), 9, np.uint8)]
    est = ContactProfileFeatures().fit(X)
    F = est.transform(X)
    assert F.shape == (4, 12) and np.all(np.isfinite(F))
    names = est.get_feature_names_out().tolist()
    assert len(names) == 12 and names[2] == "rise_frames"
    assert names[10:] == ["log_loading_time", "log_contact_spread"]
    # slow loading is seen as slow loading, at the same peak
    assert F[1, names.index("rise_frames")] > F[0, names.index("rise_frames")] + 10
    assert abs(F[1, 0] - F[0, 0]) < 0.2
    # larger contact at the same change level: more area
    big = ContactProfileFeatures().fit_transform([_press(3, 12, rng)])
    assert big[0, names.index("area_at_peak")] > 2 * F[0, names.index("area_at_peak")]
    assert clone(est).get_params() == est.get_params()
    np.testing.assert_allclose(ContactProfileFeatures(n_jobs=2).fit_transform(X), F)


def test_loading_time_between_frames():
    # rise_frames counts whole frames; log_loading_time follows the rise between them
    rng = np.random.default_rng(2)
    names = ContactProfileFeatures().fit([_press(3, 6, rng)]).get_feature_names_out().tolist()
    rises = [4, 5, 6, 8, 10, 16]
    F = ContactProfileFeatures().fit_transform([growing_disc_press(r, 8, rng, n=80, level=60) for r in rises])
    loading = F[:, names.index("log_loading_time")]
    assert np.all(np.diff(loading) > 0)
    # proportional to the rise: twice the rise, twice the loading time (within 20%)
    assert abs((loading[4] - loading[1]) - np.log(2)) < 0.2
    assert abs((loading[5] - loading[3]) - np.log(2)) < 0.2


def _rim_press(radius, level, rng, n=40, start=10, size=64):
    """A flat contact whose change shows only at its rim (a ring 2 px wide), as a gel's shading does."""
    video = np.full((n, size, size, 3), 100.0)
    yy, xx = np.mgrid[:size, :size]
    rr = np.sqrt((yy - size / 2) ** 2 + (xx - size / 2) ** 2)
    for t in range(start, n):
        r = radius * min(1.0, (t - start + 1) / 4)
        video[t][np.abs(rr - r) <= 1.0] += level
    video += rng.normal(0, 1.0, video.shape)
    return np.clip(video, 0, 255).astype(np.uint8)


def test_contact_spread_follows_the_contact_size_not_its_strength():
    rng = np.random.default_rng(3)
    est = ContactProfileFeatures().fit([_rim_press(8, 30, rng)])
    names = est.get_feature_names_out().tolist()
    radii, levels = (6, 8, 12, 16, 24), (15, 60)
    F = est.transform([_rim_press(r, lv, rng) for lv in levels for r in radii])
    spread = F[:, names.index("log_contact_spread")].reshape(len(levels), len(radii))
    area = F[:, names.index("area_at_peak")].reshape(len(levels), len(radii))
    # a wider rim, a wider spread, at either strength (15 and 60 times the pixel noise)
    assert np.all(np.diff(spread, axis=1) > 0.05)
    # it is a second moment: twice the radius (12 -> 24) gives about four times it, where the share of
    # changed pixels of a rim only doubles
    assert abs((spread[1, 4] - spread[1, 2]) - np.log(4)) < 0.2
    assert area[1, 4] / area[1, 2] < 2.2
    # a contact well above the noise: the same spread at a quarter of the strength
    assert np.all(np.abs(spread[0, 3:] - spread[1, 3:]) < 0.05)
    # no change at all: the floor, not a NaN
    still = est.transform([np.full((20, 32, 32, 3), 100, np.uint8)])
    assert np.isfinite(still).all()


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
    assert cross_val_score(head, PeakContactChange().fit_transform(X), y, cv=3).mean() <= 0.75


def test_roi_reads_the_gel_only():
    rng = np.random.default_rng(1)
    gel, X, y = [], [], []
    for i in range(30):
        soft = i % 2
        press = _press(int(rng.integers(25, 40)) if soft else int(rng.integers(2, 6)), float(rng.uniform(5, 9)), rng)
        gel.append(press)
        X.append(framed_press(press, rng))
        y.append(soft)
    y = np.array(y)
    # the same features as on videos cropped to the region, strided or not
    for max_side in (80, 16):
        np.testing.assert_array_equal(ContactProfileFeatures(max_side=max_side, roi=FRAMED_GEL).fit_transform(X),
                                      ContactProfileFeatures(max_side=max_side).fit_transform(gel))
    # the effect: the loading speed is told on the gel, lost in the whole frame's change
    head = make_pipeline(StandardScaler(), LogisticRegression())
    assert cross_val_score(head, ContactProfileFeatures(roi=list(FRAMED_GEL)).fit_transform(X), y, cv=3).mean() >= 0.9
    assert cross_val_score(head, ContactProfileFeatures().fit_transform(X), y, cv=3).mean() <= 0.6


@pytest.mark.parametrize("roi, message", [
    ((0.9, 0.1, 0.0, 1.0), "top < bottom and left < right"),
    ((0.0, 1.0, 0.0), "top < bottom and left < right"),
    ((0.0, 1.5, 0.0, 1.0), "fractions in \\[0, 1\\]"),
    ((0.0, 1.0, "a", 1.0), "got \\(0.0, 1.0, 'a', 1.0\\)"),
])
def test_bad_roi_is_named(roi, message):
    with pytest.raises(ValueError, match=message):
        ContactProfileFeatures(roi=roi).fit([np.zeros((3, 8, 8, 3), np.uint8)])


def test_roi_smaller_than_two_pixels_names_the_video():
    videos = [np.zeros((3, 32, 32, 3), np.uint8), np.zeros((3, 8, 8, 3), np.uint8)]
    with pytest.raises(ValueError, match="fewer than 2x2 pixels of the 8x8 frames of video 1"):
        ContactProfileFeatures(roi=(0.0, 0.1, 0.0, 1.0)).fit_transform(videos)


@pytest.mark.parametrize("params", [dict(max_side=2), dict(noise_factor=0), dict(noise_factor="3"),
                                    dict(features="some"), dict(features=3)])
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
    result = evaluate_pipelines(["contact_profile"], d.videos, d.target, groups=d.object_id, cv=3,
                                target_names=d.target_names, hardness=d.hardness, error_score="raise", random_state=0)
    assert result.pipelines == ["peak_change", "contact_profile"]
    assert np.isfinite(result.summary["balanced_accuracy"][1])


def test_features_pick_and_order_the_columns_of_the_twelve():
    rng = np.random.default_rng(4)
    X = [_press(3, 6, rng), _press(20, 9, rng), _press(8, 4, rng)]
    full = ContactProfileFeatures().fit(X)
    names = full.get_feature_names_out().tolist()
    picked = ["log_loading_time", "log_peak_change", "log_contact_spread"]
    est = ContactProfileFeatures(features=picked).fit(X)
    assert est.features_ == tuple(picked) and est.n_features_out_ == 3
    assert est.get_feature_names_out().tolist() == picked
    np.testing.assert_array_equal(est.transform(X), full.transform(X)[:, [names.index(n) for n in picked]])
    assert full.features_ == tuple(names) and full.n_features_out_ == 12


@pytest.mark.parametrize("features, message", [
    (["log_peak_change", "stiffness"], "got unknown \\['stiffness'\\]"),
    (["rise_frames", "rise_frames"], "got \\['rise_frames'\\] more than once"),
    ([], "got none"),
])
def test_bad_feature_names_are_named_with_the_known_ones(features, message):
    with pytest.raises(ValueError, match=message) as error:
        ContactProfileFeatures(features=features).fit([np.zeros((3, 8, 8, 3), np.uint8)])
    assert "'log_peak_change'" in str(error.value) and "'log_contact_spread'" in str(error.value)  # the known names


def test_a_grid_search_over_features_finds_the_one_that_tells_the_classes():
    """Classes differ in loading time only; contact size and strength vary per object as nuisances.

    Object-disjoint, a search over ``features__features`` keeps the loading
    time (>= 0.9), where the contact's size alone is near chance: the
    parameter changes what the head reads.
    """
    from sklearn.model_selection import GridSearchCV, StratifiedGroupKFold

    from sklearn_hardness.models import make_contact_profile_pipeline

    rng = np.random.default_rng(7)
    videos, y, groups = [], [], []
    for obj in range(18):
        cls = obj % 3
        radius, level = rng.uniform(4, 12), rng.uniform(25, 60)  # the object's shape and the press's strength
        for _ in range(3):
            videos.append(growing_disc_press((3, 9, 24)[cls] + int(rng.integers(-1, 2)), radius, rng, n=50,
                                             level=level * rng.uniform(0.9, 1.1)))
            y.append(cls)
            groups.append(obj)
    y, groups = np.array(y), np.array(groups)
    grid = GridSearchCV(make_contact_profile_pipeline(),
                        {"features__features": [["area_at_peak"], ["log_loading_time"], "all"]},
                        cv=StratifiedGroupKFold(3, shuffle=True, random_state=0), scoring="balanced_accuracy")
    grid.fit(videos, y, groups=groups)
    scores = dict(zip(map(str, grid.cv_results_["param_features__features"]), grid.cv_results_["mean_test_score"]))
    assert grid.best_params_["features__features"] == ["log_loading_time"]
    assert scores["['log_loading_time']"] >= 0.9
    assert scores["['area_at_peak']"] <= 0.6
    assert grid.best_estimator_["clf"].coef_.shape == (3, 1)


def test_uint16_frames_give_the_features_of_the_same_frames_in_uint8():
    # 16-bit frames are read in 0..255 intensity units, as the contact curve reads them
    video = growing_disc_press(6, 8, np.random.default_rng(0))
    as16 = video.astype(np.uint16) * 257
    features = ContactProfileFeatures()
    np.testing.assert_allclose(features.fit_transform([as16]), features.fit_transform([video]), rtol=1e-5,
                               atol=1e-6)



def test_features_do_not_depend_on_how_long_the_press_is_held():
    # Contact from frame 6 (before a quarter of the video): the pre-contact window ends before the rise,
    # so a longer hold leaves the features of the same press as they are; it used to count the held
    # frames as pre-contact (peak_over_precontact 3.68 -> 1.49, rise_frames 5 -> 1 from 40 to 160 frames).
    # The two videos share their first 40 frames; what differs is the held frame the peak falls on (the
    # plateau's argmax, a matter of pixel noise: about 1% in concentration and texture) and the window.
    est = ContactProfileFeatures().fit([_press(3, 6, np.random.default_rng(0))])
    names = est.get_feature_names_out().tolist()
    short, long = est.transform([synthetic_press(n_frames=n, contact_start=6, peak=15) for n in (40, 160)])
    same = [i for i, n in enumerate(names) if n not in ("rise_fraction", "hold_fraction")]  # shares of T
    np.testing.assert_allclose(long[same], short[same], rtol=0.02)
    assert long[names.index("rise_frames")] == short[names.index("rise_frames")] == 5


def test_presses_with_contact_after_the_window_keep_their_features(monkeypatch):
    """Where the rise starts after the first window, the window is the old one: the same features.

    Compared on this machine with the rule before the fix (a quarter of the
    video, at most 25 frames, whatever the curve), so no digits of one CPU
    are pinned.
    """
    import sklearn_hardness.features._contact_profile as module

    videos = [growing_disc_press(6, 8, np.random.default_rng(0)),  # contact exactly at the window's end
              synthetic_press(n_frames=126, contact_start=30, peak=40)]
    now = ContactProfileFeatures().fit_transform(videos)
    monkeypatch.setattr(module, "_n_precontact", lambda curve, i_peak: max(2, min(len(curve) // 4, 25)))
    before = ContactProfileFeatures().fit_transform(videos)
    np.testing.assert_array_equal(now, before)
    # ... while where contact starts inside the old window, the two rules differ
    early = [synthetic_press(n_frames=160, contact_start=6, peak=15)]
    old_rule = ContactProfileFeatures().fit_transform(early)
    monkeypatch.undo()
    assert not np.allclose(ContactProfileFeatures().fit_transform(early), old_rule, rtol=1e-3)


def test_float_frames_are_read_by_dtype_and_checked_whole():
    video = synthetic_press(n_frames=20, contact_start=8, peak=14, size=(40, 200))  # strided by 2
    as_float = video / 255.0
    est = ContactProfileFeatures().fit([video])
    np.testing.assert_allclose(est.transform([as_float]), est.transform([video]), rtol=1e-5, atol=1e-6)
    over = as_float.copy()
    over[0, 0, 0, 0] = 1.02  # e.g. a resize's overshoot: no longer read as 0..255 levels, silently
    with pytest.raises(ValueError, match=r"video 1 has float frames with values in \[0\.\d+, 1\.02\]"):
        est.transform([as_float, over])
    hidden = as_float.copy()
    hidden[3, 1, 1, 0] = 7.0  # a pixel the stride does not read
    with pytest.raises(ValueError, match=r"video 0 has float frames .* scaled to \[0, 1\]"):
        est.transform([hidden])


def test_constant_short_videos_give_the_row_of_longer_ones():
    est = ContactProfileFeatures().fit([np.zeros((3, 8, 8), np.uint8)])
    rows = est.transform([np.full((n, 5, 5), 7, np.uint8) for n in (1, 2, 3, 20)])
    np.testing.assert_allclose(rows, np.repeat(rows[-1:], 4, axis=0), rtol=1e-6)  # log(0.1 + 0) in float32
    assert np.all(rows[:, [1, 6, 8, 9]] == 0.0)
