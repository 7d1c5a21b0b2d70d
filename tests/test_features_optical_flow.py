import pickle
import warnings

import cv2
import joblib
import numpy as np
import pytest
from sklearn.base import clone
from sklearn.exceptions import NotFittedError
from sklearn.pipeline import make_pipeline
from sklearn.preprocessing import StandardScaler

from sklearn_hardness.features import OpticalFlowFeatures
from sklearn_hardness.utils._param_validation import InvalidParameterError

# scikit-learn's common checks and their 5-D equivalents run in tests/test_common.py.

def texture(shape, rng, sigma=1.5):
    """Smooth random texture in [0, 1] with plenty of corners."""
    img = cv2.GaussianBlur(rng.random(shape).astype(np.float32), (0, 0), sigma)
    img -= img.min()
    return img / img.max()


def translating_video(shift, k=4, size=(40, 48), rng=None, pad=12):
    """k frames of one texture translated by t * shift (dx, dy) px, t = 0..k-1."""
    rng = np.random.default_rng(0) if rng is None else rng
    H, W = size
    big = texture((H + 2 * pad, W + 2 * pad), rng)
    frames = []
    for t in range(k):
        M = np.float32([[1, 0, t * shift[0]], [0, 1, t * shift[1]]])
        moved = cv2.warpAffine(big, M, (W + 2 * pad, H + 2 * pad), flags=cv2.INTER_CUBIC,
                               borderMode=cv2.BORDER_REFLECT)
        frames.append(moved[pad:pad + H, pad:pad + W])
    return np.clip(np.stack(frames), 0, 1)[..., np.newaxis].astype(np.float32)


@pytest.fixture
def X_small():
    rng = np.random.default_rng(1)
    shifts = [(0.5, 0.0), (0.0, -0.8), (1.0, 0.6)]
    return np.stack([translating_video(s, k=3, size=(24, 28), rng=rng) for s in shifts])


def test_shapes_and_names(X_small):
    for kw, per_corner in [({}, 2 * 2), ({"include_positions": True}, 2 + 2 * 2),
                           ({"include_valid": True}, 2 * 3),
                           ({"include_positions": True, "include_valid": True}, 2 + 2 * 3)]:
        of = OpticalFlowFeatures(n_features=7, min_distance=2, **kw).fit(X_small)
        Xt = of.transform(X_small)
        assert Xt.shape == (3, 7 * per_corner) and Xt.dtype == np.float32
        assert of.n_features_out_ == Xt.shape[1]
        names = of.get_feature_names_out()
        assert len(names) == Xt.shape[1] and len(set(names)) == len(names)
    assert names[:5].tolist() == ["c0_x0", "c0_y0", "c0_t1_dx", "c0_t1_dy", "c0_t1_valid"]


@pytest.mark.parametrize("shift", [(0.7, -0.4), (-1.3, 0.9), (2.5, 0.0)])
def test_displacements_match_known_shift(shift):
    k = 4
    X = translating_video(shift, k=k)[np.newaxis]
    of = OpticalFlowFeatures(n_features=40, min_distance=3).fit(X)
    tr = of.track(X)
    assert tr.n_corners[0] >= 20
    m = tr.n_corners[0]
    start = tr.points[0, :m, 0]
    end = start + (k - 1) * np.asarray(shift, np.float32)
    H, W = X.shape[2:4]

    def inside(p, margin):
        return (p[:, 0] >= margin) & (p[:, 0] <= W - 1 - margin) & (p[:, 1] >= margin) & (p[:, 1] <= H - 1 - margin)

    full = tr.valid[0, :m].all(axis=1)  # tracked through all frames
    assert full[inside(end, 1)].all()  # every corner that stays in the image is tracked
    # Corners whose 15x15 window stays inside the image match the shift within 0.5 px.
    interior = full & inside(start, 8) & inside(end, 8)
    assert interior.sum() >= 10
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", UserWarning)
        disp = of.transform(X).reshape(1, 40, k - 1, 2)[0, :m]
    expected = np.arange(1, k)[:, None] * np.asarray(shift)[None, :]
    np.testing.assert_allclose(disp[interior], np.broadcast_to(expected, disp[interior].shape), atol=0.5)
    # Over all tracked corners, border ones included, the median is much closer.
    disp = disp[full]
    np.testing.assert_allclose(np.median(disp, axis=0), expected, atol=0.1)
    # Increments relative to the previous frame are the per-frame shift.
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", UserWarning)
        inc = of.set_params(reference="previous").transform(X).reshape(1, 40, k - 1, 2)[0, :m][full]
    np.testing.assert_allclose(np.median(inc, axis=0), np.tile(shift, (k - 1, 1)), atol=0.1)


def test_scaling_rgb_and_difference_inputs_agree():
    X = translating_video((1.0, 0.5), k=3)[np.newaxis]
    of = OpticalFlowFeatures(n_features=20, min_distance=3)
    ref = of.fit_transform(X)
    # Same frames as RGB, or mapped to [-1, 1] like differences: the per-sample
    # scaling gives the same grey images, hence identical tracks.
    rgb = np.repeat(X, 3, axis=-1)
    np.testing.assert_allclose(of.fit_transform(rgb), ref, atol=1e-4)
    np.testing.assert_array_equal(of.fit_transform(2 * X - 1), ref)
    # A fixed value range gives the same result when it matches the data range.
    lo, hi = float(X.min()), float(X.max())
    np.testing.assert_allclose(of.set_params(value_range=(lo, hi)).fit_transform(X), ref, atol=1e-4)


def test_stable_order_and_permutation(X_small):
    of = OpticalFlowFeatures(n_features=8, min_distance=2).fit(X_small)
    a = of.transform(X_small)
    np.testing.assert_array_equal(a, of.transform(X_small.copy()))
    perm = np.array([2, 0, 1])
    np.testing.assert_array_equal(of.transform(X_small[perm]), a[perm])
    # One sample alone gives the same row as in the batch.
    np.testing.assert_array_equal(of.transform(X_small[1:2]), a[1:2])
    # Corners are sorted by decreasing quality.
    q = of.track(X_small).quality
    assert np.all(np.diff(q, axis=1) <= 0)
    # Parallel runs give the same result.
    np.testing.assert_array_equal(of.set_params(n_jobs=2).transform(X_small), a)


def test_flat_frames_give_zeros_and_warning():
    X = np.zeros((2, 3, 16, 20, 3), dtype=np.float32)
    X[1] = 0.4  # constant, not zero
    of = OpticalFlowFeatures(n_features=10, include_valid=True, include_positions=True).fit(X)
    with pytest.warns(UserWarning, match=r"2 of 2 sample\(s\) had fewer than n_features=10 corners"):
        Xt = of.transform(X)
    assert Xt.shape == (2, of.n_features_out_)
    assert np.all(Xt == 0) and np.isfinite(Xt).all()
    assert of.track(X).n_corners.tolist() == [0, 0]


def test_fewer_corners_than_asked_are_padded():
    rng = np.random.default_rng(3)
    X = translating_video((0.5, 0.5), k=3, size=(16, 20), rng=rng)[np.newaxis]
    of = OpticalFlowFeatures(n_features=500, min_distance=3, include_valid=True).fit(X)
    with pytest.warns(UserWarning, match="padded with zeros"):
        Xt = of.transform(X)
    tr = of.track(X)
    m = int(tr.n_corners[0])
    assert 0 < m < 500
    blocks = Xt.reshape(500, 2, 3)  # corners x frames x (dx, dy, valid)
    assert np.all(blocks[m:] == 0)
    assert np.all(blocks[:m, :, 2] == 1.0)
    assert np.abs(blocks[:m, :, :2]).sum() > 0


def test_lost_tracks_fill_rule():
    # A textured strip moves right and leaves the image in the last frame.
    rng = np.random.default_rng(4)
    H, W = 24, 40
    strip = texture((H, 10), rng)
    frames = np.zeros((3, H, W), np.float32)
    for t, x0 in enumerate([22, 24, W + 5]):  # last frame: strip outside the image
        lo, hi = x0, min(x0 + 10, W)
        if lo < W:
            frames[t, :, lo:hi] = strip[:, : hi - lo]
    X = frames[np.newaxis, ..., np.newaxis]
    of = OpticalFlowFeatures(n_features=10, min_distance=2, win_size=(9, 9), max_level=1).fit(X)
    tr = of.track(X)
    lost = tr.valid[0, :, 0] & ~tr.valid[0, :, 2]
    assert lost.any()
    with pytest.warns(UserWarning, match="track\\(s\\) were lost"):
        zero = of.transform(X).reshape(10, 2, 2)
    with pytest.warns(UserWarning):
        last = of.set_params(fill_lost="last").transform(X).reshape(10, 2, 2)
    both = lost & tr.valid[0, :, 1]
    assert both.any()
    assert np.all(zero[both, 1] == 0)
    np.testing.assert_array_equal(last[both, 1], last[both, 0])
    np.testing.assert_allclose(last[both, 0, 0], 2.0, atol=0.5)
    assert np.isfinite(zero).all() and np.isfinite(last).all()


def test_bad_inputs(X_small):
    of = OpticalFlowFeatures(n_features=5)
    with pytest.raises(NotFittedError):
        of.transform(X_small)
    with pytest.raises(ValueError, match="n_samples, n_frames, height, width, channels"):
        of.fit(X_small[0])
    with pytest.raises(ValueError, match="at least 2 frames"):
        of.fit(X_small[:, :1])
    of.fit(X_small)
    with pytest.raises(ValueError, match="2 frames per sample but 3 were seen during fit"):
        of.transform(X_small[:, :2])
    with pytest.raises(ValueError, match="frames of shape"):
        of.transform(X_small[:, :, :20])
    bad = X_small.copy()
    bad[1, 0, 3, 3, 0] = np.nan
    with pytest.raises(ValueError, match=r"NaN or infinite values in sample\(s\) \[1\]"):
        of.transform(bad)
    with pytest.raises(TypeError, match="numeric"):
        of.transform(np.array(["a"], dtype=object))
    for params, exc, msg in [
        ({"n_features": 0}, InvalidParameterError, "'n_features' parameter"),
        ({"quality_level": 1.5}, InvalidParameterError, "'quality_level' parameter"),
        ({"win_size": (2, 2)}, InvalidParameterError, "'win_size' parameter"),
        ({"reference": "last"}, InvalidParameterError, "'reference' parameter"),
        ({"fill_lost": "nan"}, InvalidParameterError, "'fill_lost' parameter"),
        ({"value_range": (1, 0)}, InvalidParameterError, "'value_range' parameter"),
        ({"include_valid": "yes"}, InvalidParameterError, "'include_valid' parameter"),
    ]:
        with pytest.raises(exc, match=msg):
            OpticalFlowFeatures(**params).fit(X_small)


def test_estimator_contract_on_frames(X_small, tmp_path):
    of = OpticalFlowFeatures(n_features=6, min_distance=2)
    params = joblib.hash(of.get_params())
    assert of.fit(X_small) is of
    assert joblib.hash(of.get_params()) == params  # fit does not change parameters
    a = of.transform(X_small)
    state = joblib.hash(of.__dict__)
    of.transform(X_small)
    assert joblib.hash(of.__dict__) == state  # transform does not change state
    np.testing.assert_array_equal(of.fit(X_small).transform(X_small), a)  # idempotent
    np.testing.assert_array_equal(pickle.loads(pickle.dumps(of)).transform(X_small), a)
    np.testing.assert_array_equal(clone(of).fit_transform(X_small), a)
    # Read-only memory-mapped input.
    path = tmp_path / "x.npy"
    np.save(path, X_small)
    np.testing.assert_array_equal(of.transform(np.load(path, mmap_mode="r")), a)
    # float64 and uint8-valued input are accepted and converted.
    np.testing.assert_array_equal(of.transform(X_small.astype(np.float64)), a)


def test_in_pipeline_with_pandas_output(X_small):
    pd = pytest.importorskip("pandas")
    pipe = make_pipeline(OpticalFlowFeatures(n_features=4, min_distance=2), StandardScaler())
    pipe.set_output(transform="pandas")
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", UserWarning)
        df = pipe.fit_transform(X_small)
    assert isinstance(df, pd.DataFrame)
    assert list(df.columns[:2]) == ["c0_t1_dx", "c0_t1_dy"]


# ------------------------------------------------------------ magnitude quantiles
@pytest.mark.parametrize("shift", [(0.7, -0.4), (2.5, 0.0)])
def test_magnitude_quantiles_measure_the_motion(shift):
    """A translation by ``shift`` per frame: the median magnitude is t * |shift| at frame t."""
    k = 4
    X = translating_video(shift, k=k)[np.newaxis]
    of = OpticalFlowFeatures(n_features=40, min_distance=3, output="magnitude_quantiles").fit(X)
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", UserWarning)
        Xt = of.transform(X)
    assert Xt.shape == (1, (k - 1) * 6) == (1, of.n_features_out_) and Xt.dtype == np.float32
    names = of.get_feature_names_out().tolist()
    assert names[:6] == ["t1_mag_q50", "t1_mag_q75", "t1_mag_q90", "t1_mag_q99", "t1_mag_max", "t1_mag_mean"]
    assert len(names) == Xt.shape[1] and names[-1] == f"t{k - 1}_mag_mean"
    median = np.exp(Xt.reshape(k - 1, 6)[:, 0]) - 0.01
    np.testing.assert_allclose(median, np.arange(1, k) * np.hypot(*shift), rtol=0.1)
    # quantiles are ordered within each frame: q50 <= q75 <= q90 <= q99 <= max
    assert np.all(np.diff(Xt.reshape(k - 1, 6)[:, :5], axis=1) >= 0)


def test_magnitude_quantiles_do_not_depend_on_which_corner_is_which(X_small):
    """The flattened tracks change when the corners are re-ordered; the summary does not.

    Mirroring the frames moves every corner to a new place (and so to another
    slot of the quality order) but keeps every displacement's length.
    """
    kw = dict(n_features=12, min_distance=2)
    mirrored = X_small[:, :, :, ::-1].copy()
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", UserWarning)
        tracks = OpticalFlowFeatures(**kw).fit(X_small)
        summary = OpticalFlowFeatures(output="magnitude_quantiles", **kw).fit(X_small)
        np.testing.assert_allclose(summary.transform(mirrored), summary.transform(X_small), atol=0.05)
        assert np.abs(tracks.transform(mirrored) - tracks.transform(X_small)).max() > 0.5


def test_magnitude_quantiles_of_flat_frames_and_bad_options():
    X = np.zeros((2, 3, 16, 20, 1), dtype=np.float32)
    of = OpticalFlowFeatures(n_features=5, output="magnitude_quantiles").fit(X)
    with pytest.warns(UserWarning, match="corners found in the first frame"):
        Xt = of.transform(X)
    np.testing.assert_allclose(Xt, np.log(0.01))  # no corners: no motion seen, never NaN
    for bad in ({"include_valid": True}, {"include_positions": True}):
        with pytest.raises(ValueError, match="do not apply to output='magnitude_quantiles'"):
            OpticalFlowFeatures(output="magnitude_quantiles", **bad).fit(X)
    with pytest.raises(InvalidParameterError, match="output"):
        OpticalFlowFeatures(output="histogram").fit(X)


def test_previous_reference_gives_zero_increments_from_the_loss_on():
    # reference="previous": a lost track's increments are zero from the frame where
    # it is lost on, for both fill rules (no backward jump of its whole travel).
    rng = np.random.default_rng(4)
    H, W = 24, 40
    strip = texture((H, 10), rng)
    frames = np.zeros((4, H, W), np.float32)
    for t, x0 in enumerate([20, 22, 24, W + 5]):  # last frame: strip outside the image
        lo, hi = x0, min(x0 + 10, W)
        if lo < W:
            frames[t, :, lo:hi] = strip[:, : hi - lo]
    X = frames[np.newaxis, ..., np.newaxis]
    of = OpticalFlowFeatures(n_features=10, min_distance=2, win_size=(9, 9), max_level=1,
                             reference="previous", include_valid=True).fit(X)
    tr = of.track(X)
    valid = tr.valid[0, :, 1:]
    lost = tr.valid[0, :, 0] & ~tr.valid[0, :, -1] & tr.valid[0, :, 1]
    assert lost.any()
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", UserWarning)
        zero = of.transform(X).reshape(10, 3, 3)
        last = of.set_params(fill_lost="last").transform(X).reshape(10, 3, 3)
        first = of.set_params(reference="first", fill_lost="zero").transform(X).reshape(10, 3, 3)
    np.testing.assert_array_equal(zero, last)
    assert np.all(zero[..., :2][~valid] == 0)
    # where tracked, the increments are the differences of the cumulative ones
    inc = np.diff(first[..., :2], axis=1, prepend=0)
    np.testing.assert_allclose(zero[..., :2][valid], inc[valid], atol=1e-5)
    np.testing.assert_allclose(zero[lost, 0, 0], 2.0, atol=0.5)
