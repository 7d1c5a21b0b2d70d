import warnings

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st
from sklearn.base import BaseEstimator, clone
from sklearn.linear_model import LogisticRegression
from sklearn.model_selection import cross_val_score
from sklearn.pipeline import make_pipeline
from sklearn.preprocessing import FunctionTransformer

from sklearn_hardness.preprocessing import ContactFrameSelector, ContactNotFoundWarning, contact_curve

from ._synthetic import no_contact, synthetic_press
from ._weak_contact import weak_press


def test_finds_start_and_peak():
    video = synthetic_press(n_frames=30, contact_start=10, peak=20)
    sel = ContactFrameSelector(n_between=2).fit([video])
    s = sel.selection_
    assert s.contact_found.all()
    # the synthetic blob's change grows quadratically from zero at frame 10: it passes
    # the auto threshold (5% of the contrast above the noise) within two frames
    assert 10 <= s.contact_start[0] <= 12
    assert 19 <= s.contact_peak[0] <= 20
    idx = s.indices[0]
    assert idx[0] == s.contact_start[0] and idx[-1] == s.contact_peak[0]
    assert np.all(np.diff(idx) > 0)
    # equal spacing up to rounding
    assert np.ptp(np.diff(idx)) <= 1


def test_output_values_and_layout():
    video = synthetic_press(n_frames=25, contact_start=8, peak=16)
    sel = ContactFrameSelector(n_between=1)
    out = sel.fit_transform([video, video])
    assert out.shape == (2, 3, 48, 64, 3) and out.dtype == np.float32
    idx = sel.selection_.indices[0]
    expected = (video[idx].astype(np.float32) - video[0]) / 255.0
    np.testing.assert_allclose(out[0], expected, atol=1e-6)
    raw = ContactFrameSelector(n_between=1, subtract_first=False).fit_transform([video])
    np.testing.assert_allclose(raw[0], video[idx] / 255.0, atol=1e-6)
    assert raw.min() >= 0 and raw.max() <= 1


def test_resize_crop_and_grey():
    video = synthetic_press(n_frames=25, size=(48, 64))
    sel = ContactFrameSelector(frame_size=(12, 16), roi=(0.25, 0.75, 0.25, 0.75), color="gray")
    out = sel.fit_transform([video])
    assert out.shape == (1, 4, 12, 16, 1)
    assert sel.frame_shape_ == (12, 16, 1)
    # the crop keeps the blob, which is bright in red: the grey difference is positive at the centre
    assert out[0, -1, 6, 8, 0] > 0.05


@pytest.mark.parametrize("drift,gain_drift", [(0.6, 0.0), (0.0, 0.004), (0.4, 0.003)])
def test_illumination_drift_does_not_move_contact(drift, gain_drift):
    # up to ~18 grey levels of drift before contact, larger than the blob's first frames
    clean = synthetic_press(n_frames=40, contact_start=25, peak=33)
    drifting = synthetic_press(n_frames=40, contact_start=25, peak=33, drift=drift, gain_drift=gain_drift)
    sel = ContactFrameSelector()
    a = sel.select([clean])
    b = sel.select([drifting])
    assert b.contact_found.all()
    assert abs(b.contact_start[0] - a.contact_start[0]) <= 1
    assert abs(b.contact_peak[0] - a.contact_peak[0]) <= 1


def test_drift_is_removed_from_curve():
    drifting = synthetic_press(n_frames=30, contact_start=40, peak=41, drift=0.5, gain_drift=0.003)
    curve = contact_curve(drifting)
    # without removal, frame 29 would differ by ~ 15 + 0.087 * 150 levels on average
    assert curve[1:].max() < 2.5


def test_press_peaking_within_one_frame_repeats_indices():
    video = synthetic_press(n_frames=20, contact_start=12, peak=12)
    s = ContactFrameSelector(n_between=2).select([video])
    assert s.contact_found[0]
    assert s.contact_start[0] == s.contact_peak[0] == 12
    assert s.indices[0].tolist() == [12, 12, 12, 12]
    two = synthetic_press(n_frames=20, contact_start=12, peak=13)
    s = ContactFrameSelector(n_between=2).select([two])
    assert set(s.indices[0].tolist()) <= {12, 13} and len(s.indices[0]) == 4


def test_no_contact_fallback_warns_with_count():
    videos = [no_contact(seed=1), synthetic_press(), no_contact(seed=2)]
    sel = ContactFrameSelector()
    with pytest.warns(ContactNotFoundWarning, match=r"2 of 3 video\(s\) never reach contact \(X\[0, 2\]\)"):
        out = sel.fit_transform(videos)
    assert out.shape[0] == 3
    assert sel.selection_.contact_found.tolist() == [False, True, False]
    assert sel.selection_.indices[0][0] == 0


def test_no_contact_raise():
    with pytest.raises(ValueError, match=r"1 of 2 video\(s\) never reach contact: X\[1\]"):
        ContactFrameSelector(on_no_contact="raise").fit([synthetic_press(), no_contact()])


def test_constant_video_falls_back_to_whole_video():
    video = np.full((6, 8, 8, 3), 90, np.uint8)
    with pytest.warns(ContactNotFoundWarning):
        s = ContactFrameSelector(n_between=1).select([video])
    assert s.indices[0].tolist() == [0, 2, 5] or s.indices[0].tolist() == [0, 3, 5]


def test_numeric_threshold():
    video = synthetic_press(n_frames=30, contact_start=10, peak=20)
    low = ContactFrameSelector(threshold=2.0).select([video])
    high = ContactFrameSelector(threshold=3.5).select([video])
    assert high.contact_start[0] > low.contact_start[0]
    assert (low.threshold == 2.0).all()
    with pytest.warns(ContactNotFoundWarning):
        ContactFrameSelector(threshold=1e6).select([video])


def test_videos_of_different_lengths_and_sizes():
    a = synthetic_press(n_frames=25, size=(48, 64))
    b = synthetic_press(n_frames=35, size=(48, 64), contact_start=15, peak=28)
    c = synthetic_press(n_frames=30, size=(60, 80))
    out = ContactFrameSelector().fit_transform([a, b])
    assert out.shape == (2, 4, 48, 64, 3)
    with pytest.raises(ValueError, match="different frame sizes.*frame_size"):
        ContactFrameSelector().fit_transform([a, c])
    out = ContactFrameSelector(frame_size=(24, 32)).fit_transform([a, b, c])
    assert out.shape == (3, 4, 24, 32, 3)
    sel = ContactFrameSelector().fit([a])
    with pytest.raises(ValueError, match="seen in fit"):
        sel.transform([c])


def test_output_size_is_the_deprecated_name_of_frame_size():
    a = synthetic_press(n_frames=25, size=(48, 64))
    c = synthetic_press(n_frames=30, size=(60, 80))
    new = ContactFrameSelector(frame_size=(24, 32)).fit_transform([a, c])
    with pytest.warns(FutureWarning, match="`output_size` was renamed `frame_size`"):
        old = ContactFrameSelector(output_size=(24, 32)).fit_transform([a, c])
    np.testing.assert_array_equal(old, new)
    with pytest.warns(FutureWarning, match="renamed"):
        selection = ContactFrameSelector(output_size=(24, 32)).select([a, c])
    np.testing.assert_array_equal(selection.indices, ContactFrameSelector().select([a, c]).indices)
    with warnings.catch_warnings():
        warnings.simplefilter("error", FutureWarning)  # the new name does not warn
        ContactFrameSelector(frame_size=(24, 32)).fit([a])
    with pytest.raises(ValueError, match="Both frame_size and output_size are set"), \
            pytest.warns(FutureWarning):
        ContactFrameSelector(frame_size=(24, 32), output_size=(24, 32)).fit([a])


@pytest.mark.parametrize("call", ["fit", "fit_transform", "pipeline", "select"])
def test_warnings_name_the_users_line_whatever_the_path(call):
    # scikit-learn's fit and set_output wrappers add a different number of frames per
    # method; the warnings must still point here, not into scikit-learn or this package
    videos = [synthetic_press(n_frames=25, size=(48, 64)), no_contact(n_frames=20, size=(48, 64))]
    sel = ContactFrameSelector(output_size=(24, 32))
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        if call == "fit":
            sel.fit(videos)
        elif call == "fit_transform":
            sel.fit_transform(videos)
        elif call == "pipeline":
            make_pipeline(sel).fit_transform(videos)
        else:
            sel.select(videos)
    kinds = {w.category for w in caught}
    assert {FutureWarning, ContactNotFoundWarning} <= kinds
    assert {w.filename for w in caught if w.category in kinds} == {__file__}


def test_float_and_grey_input():
    video = synthetic_press()
    as_float = video.astype(np.float32) / 255.0
    a = ContactFrameSelector().fit_transform([video])
    b = ContactFrameSelector().fit_transform([as_float])
    np.testing.assert_allclose(a, b, atol=1e-5)
    grey = video.mean(axis=-1).astype(np.uint8)
    out = ContactFrameSelector().fit_transform([grey])
    assert out.shape[-1] == 3  # rgb output from grey input: replicated


@pytest.mark.parametrize(
    "bad,error,match",
    [
        ([np.zeros((1, 8, 8, 3), np.uint8)], ValueError, "1 frame"),
        ([np.zeros((5, 8, 8, 4), np.uint8)], ValueError, "channels"),
        ([np.zeros((5, 8), np.uint8)], ValueError, "dimension"),
        ([np.array([["a"]])], TypeError, "numeric dtype"),
        ([np.full((5, 8, 8, 3), 3.0)], ValueError, r"scaled to \[0, 1\]"),
        ("video.mp4", TypeError, "sequence of videos"),
        ([], ValueError, "no videos"),
        (np.zeros((5, 8, 8, 3), np.uint8), ValueError, "For a single video, pass"),
    ],
)
def test_bad_input(bad, error, match):
    with pytest.raises(error, match=match):
        ContactFrameSelector().fit(bad)


def test_nan_frames_name_the_video_and_frame():
    video = synthetic_press().astype(np.float32) / 255
    video[7, 3, 3, 0] = np.nan
    with pytest.raises(ValueError, match=r"X\[1\] contains NaN or infinite values in frame\(s\) \[7\]"):
        ContactFrameSelector().fit([synthetic_press(), video])


@pytest.mark.parametrize(
    "params,match",
    [
        ({"n_between": -1}, "n_between"),
        ({"threshold": "high"}, "threshold"),
        ({"threshold": -2}, "threshold"),
        ({"frame_size": (10,)}, "frame_size"),
        ({"roi": (0.5, 0.2, 0, 1)}, "roi"),
        ({"color": "hsv"}, "color"),
        ({"on_no_contact": "skip"}, "on_no_contact"),
        ({"n_baseline": 0}, "n_baseline"),
    ],
)
def test_bad_params(params, match):
    with pytest.raises(ValueError, match=match):
        ContactFrameSelector(**params).fit([synthetic_press()])


def test_transform_before_fit():
    from sklearn.exceptions import NotFittedError

    with pytest.raises(NotFittedError):
        ContactFrameSelector().transform([synthetic_press()])


def test_sklearn_api_with_videos():
    videos = [synthetic_press(seed=s, contact_start=8 + s % 3) for s in range(6)]
    sel = ContactFrameSelector(n_between=1, frame_size=(12, 16), n_jobs=2)
    assert clone(sel).get_params() == sel.get_params()
    out = sel.fit_transform(videos)
    np.testing.assert_array_equal(out, sel.transform(videos))  # fit_transform == fit + transform
    np.testing.assert_array_equal(out[::-1], sel.transform(videos[::-1]))  # order invariant
    np.testing.assert_array_equal(out[2:4], sel.transform(videos[2:4]))  # subset invariant
    assert sel.set_params(n_between=3).fit_transform(videos).shape[1] == 5


def test_in_a_pipeline_with_cross_validation():
    y = np.array([0, 1] * 6)
    # class 1 presses are brighter: learnable from the selected frames
    videos = [synthetic_press(seed=i, amplitude=30 + 60 * y[i], size=(24, 32)) for i in range(12)]
    pipe = make_pipeline(
        ContactFrameSelector(frame_size=(6, 8)),
        FunctionTransformer(lambda x: x.reshape(len(x), -1)),
        LogisticRegression(max_iter=500),
    )
    scores = cross_val_score(pipe, videos, y, cv=3)
    assert scores.mean() > 0.9


@settings(max_examples=25, deadline=None)
@given(
    n_frames=st.integers(2, 30),
    start=st.integers(0, 35),
    length=st.integers(0, 10),
    n_between=st.integers(0, 4),
    seed=st.integers(0, 100),
)
def test_indices_property(n_frames, start, length, n_between, seed):
    video = synthetic_press(
        n_frames=n_frames, size=(12, 16), contact_start=start, peak=start + length, radius=4, seed=seed
    )
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", ContactNotFoundWarning)
        s = ContactFrameSelector(n_between=n_between).select([video])
    idx = s.indices[0]
    assert len(idx) == n_between + 2
    assert 0 <= idx.min() and idx.max() < n_frames
    assert np.all(np.diff(idx) >= 0)
    assert np.isfinite(s.curves[0]).all()
    if s.contact_found[0]:
        assert s.contact_start[0] <= s.contact_peak[0]


def test_each_video_is_loaded_once():
    from sklearn_hardness.utils._lazy import LazyVideoSequence

    loads = []
    videos = [synthetic_press(seed=s) for s in range(4)]
    lazy = LazyVideoSequence(lambda k: loads.append(k) or videos[k], range(4))
    sel = ContactFrameSelector(n_jobs=2)
    out = sel.fit_transform(lazy)
    assert sorted(loads) == [0, 1, 2, 3]  # decoding/rendering is the expensive part: once per video
    loads.clear()
    np.testing.assert_array_equal(sel.transform(lazy), out)
    assert sorted(loads) == [0, 1, 2, 3]
    loads.clear()
    sel.select(lazy)
    assert sorted(loads) == [0, 1, 2, 3]


def test_other_joblib_backends_around_the_call():
    # the per-video jobs fill shared arrays: a process backend configured by the
    # user (e.g. dask, loky) must not make their results disappear
    import joblib

    videos = [synthetic_press(seed=s) for s in range(3)]
    expected = ContactFrameSelector(n_jobs=1).fit_transform(videos)
    with joblib.parallel_config(backend="loky"):
        out = ContactFrameSelector(n_jobs=2).fit_transform(videos)
    np.testing.assert_array_equal(out, expected)


# ---------------------------------------------------------------- weak contacts
# Compressed (mp4v) marker-less presses calibrated to real GelSight Mini presses of
# soft objects: the contact lifts the curve by a fraction of a grey level to ~1.5
# levels over a codec floor of ~1 level (see tests/_weak_contact.py).
_WEAK = dict(n_frames=64, size=(64, 96))


@pytest.fixture(scope="module")
def weak_videos():
    presses = [
        weak_press(kind, strength=strength, seed=seed, **_WEAK)
        for seed, (kind, strength) in enumerate(
            [("fabric", 2.5), ("fabric", 3.0), ("edge", 0.5), ("edge", 0.8), ("dome", 0.5), ("dome", 0.8)]
        )
    ]
    empty = [weak_press(contact=False, seed=100 + s, **_WEAK)[0] for s in range(4)]
    return presses, empty


def test_weak_compressed_contacts_are_found(weak_videos):
    presses, _ = weak_videos
    videos = [v for v, _, _ in presses]
    s = ContactFrameSelector().select(videos)
    assert s.contact_found.all(), s.status
    # the mean curve rises by less than the strong test's 1 level on most of them
    assert (s.status == "weak contact").sum() >= 3
    for i, (_, start, peak) in enumerate(presses):
        # slow soft presses cross the threshold some frames after the first touch
        assert start - 2 <= s.contact_start[i] <= start + 12, (i, s.contact_start[i], start)
        assert abs(s.contact_peak[i] - peak) <= 6, (i, s.contact_peak[i], peak)
        assert s.contact_start[i] <= s.contact_peak[i]
        assert s.indices[i][0] == s.contact_start[i] and s.indices[i][-1] == s.contact_peak[i]
    assert np.isnan(s.threshold[s.status == "weak contact"]).all()


def test_weak_contact_needs_min_contrast(weak_videos):
    presses, _ = weak_videos
    weak = [v for (v, _, _), st in zip(presses, ContactFrameSelector().select([p[0] for p in presses]).status)
            if st == "weak contact"]
    with pytest.warns(ContactNotFoundWarning):
        s = ContactFrameSelector(min_contrast=50.0).select(weak)
    assert not s.contact_found.any()


def test_compressed_videos_without_contact_are_reported(weak_videos):
    # noise, drift, the codec's rise over the first frames and key-frame dips only
    _, empty = weak_videos
    with pytest.warns(ContactNotFoundWarning, match=r"4 of 4 video\(s\) never reach contact"):
        s = ContactFrameSelector().select(empty)
    assert (s.status == "no contact").all()
    with pytest.raises(ValueError, match="never reach contact"):
        ContactFrameSelector(on_no_contact="raise").fit(empty[:1])


def test_weak_contact_is_not_diluted_by_the_pad():
    # a short sharp edge changes a few percent of the pad: the mean curve hardly moves
    video, start, peak = weak_press("edge", strength=0.4, seed=7, **_WEAK)
    curve = contact_curve(video)
    assert curve[peak:].max() - np.median(curve[5:start]) < 1.0  # below the strong test
    s = ContactFrameSelector().select([video])
    assert s.status[0] == "weak contact"
    assert abs(s.contact_peak[0] - peak) <= 6


@pytest.mark.parametrize("n_frames", [3, 5, 7])
def test_too_short_videos_have_a_defined_outcome(n_frames):
    video = synthetic_press(n_frames=30, contact_start=1, peak=2)[:n_frames]
    with pytest.warns(ContactNotFoundWarning, match=r"1 of 1 video\(s\) are too short .*fewer than 8 frames"):
        s = ContactFrameSelector(n_between=2).select([video])
    assert s.status[0] == "too short" and not s.contact_found[0]
    # frames spread over the whole video, repeated where it has fewer than k
    assert s.indices[0][0] == 0 and s.indices[0][-1] == n_frames - 1 and len(s.indices[0]) == 4
    with pytest.raises(ValueError, match="too short"):
        ContactFrameSelector(on_no_contact="raise").select([video])
    # a numeric threshold needs no baseline: it still finds the contact
    s = ContactFrameSelector(threshold=1.0).select([video])
    assert s.contact_found[0] and s.status[0] == "contact"
    # the minimum follows n_baseline
    s = ContactFrameSelector(n_baseline=1).select([synthetic_press(n_frames=30, contact_start=2, peak=5)[:6]])
    assert s.status[0] == "contact"


def test_mixed_outcomes_are_counted_separately():
    videos = [synthetic_press(), no_contact(seed=3), synthetic_press()[:4]]
    with pytest.warns(ContactNotFoundWarning) as record:
        s = ContactFrameSelector().select(videos)
    assert s.status.tolist() == ["contact", "no contact", "too short"]
    message = str(record[0].message)
    assert "1 of 3 video(s) never reach contact (X[1])" in message
    assert "1 of 3 video(s) are too short" in message and "(X[2])" in message


def test_parameters_are_validated_by_sklearn():
    from sklearn_hardness.utils._param_validation import InvalidParameterError

    with pytest.raises(InvalidParameterError, match="'threshold' parameter of ContactFrameSelector"):
        ContactFrameSelector(threshold=float("nan")).fit([synthetic_press()])
    with pytest.raises(InvalidParameterError, match="'min_contrast'"):
        ContactFrameSelector(min_contrast=-1).select([synthetic_press()])
    # sklearn's own _validate_params is no longer shadowed
    assert ContactFrameSelector._validate_params is BaseEstimator._validate_params


def test_crop_contact_centres_a_fixed_window_on_the_change():
    rng = np.random.default_rng(0)
    video = rng.integers(100, 103, size=(20, 40, 60, 3)).astype(np.uint8)
    for t in range(8, 20):  # a blob in the top-left part of the pad, growing from frame 8
        r = min(t - 7, 5)
        video[t, 10 - r:10 + r, 15 - r:15 + r] = 200
    full = ContactFrameSelector(color="gray").fit_transform([video])
    crop = ContactFrameSelector(color="gray", crop_contact=0.5).fit_transform([video])
    assert crop.shape == (1, 4, 20, 30, 1)  # half the height and width, no frame_size
    # the window is the 20x30 block centred on the blob, clipped into the frame: rows 0..20, cols 0..30
    np.testing.assert_allclose(crop[0], full[0, :, 0:20, 0:30], rtol=1e-5, atol=1e-7)  # float32 sums differ by order
    # the fixed size keeps the contact's size: the blob covers the same number of pixels
    assert (np.abs(crop[0, -1]) > 0.2).sum() == (np.abs(full[0, -1]) > 0.2).sum()
    # with frame_size the crop is resized: the blob fills a larger part of the output
    small_full = ContactFrameSelector(color="gray", frame_size=(10, 15)).fit_transform([video])
    small_crop = ContactFrameSelector(color="gray", frame_size=(10, 15), crop_contact=0.5).fit_transform([video])
    assert (np.abs(small_crop[0, -1]) > 0.1).sum() > 2 * (np.abs(small_full[0, -1]) > 0.1).sum()


def test_crop_contact_without_change_keeps_the_centre_and_bad_values_raise():
    from sklearn_hardness.utils._param_validation import InvalidParameterError

    video = np.full((12, 40, 60, 3), 120, dtype=np.uint8)
    with pytest.warns(ContactNotFoundWarning):
        out = ContactFrameSelector(subtract_first=False, crop_contact=0.5).fit_transform([video])
    assert out.shape[2:4] == (20, 30)
    for bad in (0, 1, 1.5, "contact"):
        with pytest.raises(InvalidParameterError, match="crop_contact"):
            ContactFrameSelector(crop_contact=bad).fit([video])


@pytest.mark.parametrize("n_frames", [60, 100, 160])
def test_a_long_hold_does_not_hide_the_contact(n_frames):
    # 7 quiet frames after the first, loading over frames 8-14, then held: over 80% of the frames after
    # the first are held, which put the whole video's 20th percentile (the quiet level) on the plateau
    video = synthetic_press(n_frames=n_frames, contact_start=8, peak=14)
    s = ContactFrameSelector().select([video])
    assert s.status[0] == "contact"
    assert 8 <= s.contact_start[0] <= 11 and 13 <= s.contact_peak[0] <= 16


def test_weak_contact_quiet_level_comes_from_before_a_long_hold():
    from sklearn_hardness.preprocessing._contact_curve import _locate_weak

    local = np.r_[0.0, np.full(7, 1.0), 1.5, 2.0, 2.5, np.full(89, 3.0)]  # held over 89 of 99 frames
    start, peak, found = _locate_weak(local, 0.3)
    assert found and 8 <= start <= peak <= 11


@pytest.mark.parametrize("n_frames", [4, 5, 6, 7, 8, 9])
def test_numeric_threshold_applies_to_short_videos(n_frames):
    # the curve passes the threshold: contact, where the noise-based peak tolerance used to put the
    # peak at frame 0 or 1, under the threshold, and report no contact
    video = synthetic_press(n_frames=n_frames, contact_start=1, peak=n_frames - 1)
    curve = contact_curve(video)
    assert curve.max() > 3.0
    s = ContactFrameSelector(threshold=3.0).select([video])
    start, peak = s.contact_start[0], s.contact_peak[0]
    assert s.status[0] == "contact" and s.threshold[0] == 3.0
    assert 1 <= start <= peak and curve[peak] > 3.0 and curve[start] > 3.0 >= curve[start - 1]
    assert (curve[start : peak + 1] > 3.0).all()


def test_float_range_is_checked_on_the_whole_video():
    # frames of 200 x 240 are strided by 3 for the curve; frame 3 is not selected
    video = synthetic_press(n_frames=30, contact_start=10, peak=20, size=(200, 240)) / 255.0
    video[3, 1, 1, 0] = 7.0
    with pytest.raises(ValueError, match=r"X\[0\] has float frames with values in \[0\.\d+, 7\]"):
        ContactFrameSelector().fit([video])
    with pytest.raises(ValueError, match=r"video has float frames .* scaled to \[0, 1\]"):
        contact_curve(video)
    with pytest.raises(ValueError, match=r"X\[0\] has float frames"):  # outside the region read, too
        ContactFrameSelector(roi=(0.5, 1.0, 0.5, 1.0)).select([video])
