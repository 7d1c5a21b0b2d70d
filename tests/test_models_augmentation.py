"""FrameAugmenter and ConvLSTMClassifier(augment=...): the transforms, where they apply, and their effect."""

import pickle

import numpy as np
import pytest
import torch
from sklearn.base import clone
from sklearn.model_selection import GridSearchCV

from sklearn_hardness.models import (
    ConvLSTMClassifier,
    EnsembleClassifier,
    FrameAugmenter,
    make_convlstm_pipeline,
)


def _gen(seed=0):
    return torch.Generator().manual_seed(seed)


def test_flip_only_mirrors_each_press_as_a_whole():
    X = torch.arange(6 * 2 * 3 * 4 * 1, dtype=torch.float32).reshape(6, 2, 3, 4, 1)
    out = FrameAugmenter(flip=True, gain=0.0).augment(X, _gen())
    seen = set()
    for i in range(len(X)):
        candidates = {
            "none": X[i], "lr": X[i].flip(2), "ud": X[i].flip(1), "both": X[i].flip(1).flip(2),
        }
        match = [name for name, c in candidates.items() if torch.equal(out[i], c)]
        assert len(match) == 1, i
        seen.add(match[0])
    assert len(seen) >= 2  # 6 presses: not all left as they were
    assert torch.equal(X, torch.arange(X.numel(), dtype=torch.float32).reshape(X.shape))  # input untouched


def test_gain_is_one_factor_per_press_and_log_channels_shift_by_its_log():
    X = torch.rand(5, 3, 4, 4, 3) + 0.5
    out = FrameAugmenter(flip=False, gain=0.5, channels=[0], log_channels=[2]).augment(X, _gen(1))
    ratio = out[..., 0] / X[..., 0]
    g = ratio[:, 0, 0, 0]
    assert torch.allclose(ratio, g[:, None, None, None].expand_as(ratio), rtol=1e-5)
    assert not torch.allclose(g, torch.ones(5))
    assert torch.equal(out[..., 1], X[..., 1])  # listed in neither: untouched
    assert torch.allclose(out[..., 2] - X[..., 2], torch.log(g)[:, None, None, None].expand_as(ratio), atol=1e-5)


def test_drift_grows_linearly_over_the_frames_and_noise_is_added():
    X = torch.ones(4, 5, 2, 2, 1)
    out = FrameAugmenter(flip=False, gain=0.0, drift=0.3).augment(X, _gen(2))
    per_frame = out[:, :, 0, 0, 0]
    assert torch.allclose(per_frame[:, 0], torch.ones(4))
    steps = per_frame.diff(dim=1)
    assert torch.allclose(steps, steps[:, :1].expand_as(steps), atol=1e-6)
    noisy = FrameAugmenter(flip=False, gain=0.0, noise=0.5).augment(X, _gen(3))
    assert 0.3 < float((noisy - X).std()) < 0.7


def test_shift_moves_each_press_as_a_whole_within_bounds():
    n, k, H, W = 12, 2, 8, 16
    X = torch.arange(n * k * H * W, dtype=torch.float32).reshape(n, k, H, W, 1)
    out = FrameAugmenter(flip=False, gain=0.0, shift=0.25).augment(X, _gen(4))
    offsets = set()
    for i in range(n):
        # pixel (H/2, W/2) came from (H/2 - dy, W/2 - dx): the source's row and column give the shift
        src = int(out[i, 0, H // 2, W // 2, 0] - X[i, 0, 0, 0, 0])
        dy, dx = H // 2 - src // W, W // 2 - src % W
        assert abs(dy) <= 2 and abs(dx) <= 4  # round(0.25 * 8), round(0.25 * 16)
        rows = (torch.arange(H) - dy).clamp(0, H - 1)
        cols = (torch.arange(W) - dx).clamp(0, W - 1)
        expected = X[i][:, rows][:, :, cols]  # the same shift for every frame, edges repeated
        assert torch.equal(out[i], expected), i
        offsets.add((dy, dx))
    assert len(offsets) > 3
    # the shifts are drawn last: on uniform frames (which a shift leaves as they are) turning them
    # on leaves the other transforms' draws as they were
    uniform = torch.full((n, k, H, W, 1), 2.0)
    plain = FrameAugmenter(gain=0.3, noise=0.1).augment(uniform, _gen(5))
    assert torch.equal(FrameAugmenter(gain=0.3, noise=0.1, shift=0.25).augment(uniform, _gen(5)), plain)


def test_every_channel_at_once_is_the_same_as_listing_them():
    X = torch.rand(4, 3, 6, 7, 3)
    aug = dict(gain=0.3, drift=0.2, noise=0.1, shift=0.2)
    every = FrameAugmenter(**aug).augment(X, _gen(1))  # transformed in place
    listed = FrameAugmenter(**aug, channels=[2, 1, 0]).augment(X, _gen(1))  # gathered and scattered
    assert torch.equal(every, listed)


def test_same_generator_same_draws_and_dtype_kept():
    X = torch.rand(3, 2, 4, 5, 1)
    aug = FrameAugmenter(gain=0.3, drift=0.1, noise=0.1)
    a, b = aug.augment(X, _gen(7)), aug.augment(X, _gen(7))
    assert torch.equal(a, b) and a.dtype == X.dtype and a.shape == X.shape
    assert not torch.equal(a, aug.augment(X, _gen(8)))


@pytest.mark.parametrize(
    "params, match",
    [
        ({"channels": [3]}, r"channels must hold channel indices in \[0, 2\)"),
        ({"log_channels": [1, 1]}, "lists a channel twice"),
        ({"channels": [0, 1], "log_channels": [1]}, r"channels \[1\] are listed in both"),
        ({"gain": -1.0}, "'gain' parameter of FrameAugmenter must be"),
    ],
)
def test_bad_settings_are_named(params, match):
    with pytest.raises(ValueError, match=match):
        FrameAugmenter(**params).check(2)


def test_convlstm_rejects_bad_augmenter_before_training():
    X = np.random.default_rng(0).normal(size=(8, 2, 4, 5, 1)).astype("float32")
    y = np.arange(8) % 2
    with pytest.raises(ValueError, match="channels must hold channel indices"):
        ConvLSTMClassifier(augment=FrameAugmenter(channels=[2]), max_epochs=1).fit(X, y)
    with pytest.raises(ValueError, match="'augment' parameter"):
        ConvLSTMClassifier(augment="flip", max_epochs=1).fit(X, y)


class _Counting:
    """An augmenter that counts the rows it sees and leaves them unchanged."""

    def __init__(self):
        self.rows = 0

    def augment(self, X, generator=None):
        self.rows += len(X)
        return X


def test_augmenter_sees_every_training_row_once_per_epoch_and_nothing_at_prediction():
    X = np.random.default_rng(0).normal(size=(10, 2, 4, 5, 1)).astype("float32")
    y = np.arange(10) % 2
    counter = _Counting()
    clf = ConvLSTMClassifier(filters=(2,), augment=counter, max_epochs=3, batch_size=4, random_state=0).fit(X, y)
    assert counter.rows == 30
    clf.predict_proba(X)
    clf.predict_proba_samples(X, n_samples=5, random_state=0)
    clf.partial_fit(X, y, epochs=1)
    assert counter.rows == 40
    # an identity augmenter trains exactly as no augmenter (the draws of the net are untouched)
    plain = ConvLSTMClassifier(filters=(2,), max_epochs=3, batch_size=4, random_state=0).fit(X, y)
    same = ConvLSTMClassifier(filters=(2,), augment=_Counting(), max_epochs=3, batch_size=4,
                              random_state=0).fit(X, y)
    np.testing.assert_array_equal(plain.predict_proba(X), same.predict_proba(X))


def test_augmented_training_is_reproducible_and_survives_pickle_and_clone():
    X = np.random.default_rng(1).normal(size=(12, 2, 4, 5, 1)).astype("float32")
    y = np.arange(12) % 2
    make = lambda: ConvLSTMClassifier(filters=(3,), augment=FrameAugmenter(gain=0.3, noise=0.1), max_epochs=2,
                                      batch_size=4, random_state=0)
    a, b = make().fit(X, y), make().fit(X, y)
    np.testing.assert_array_equal(a.predict_proba(X), b.predict_proba(X))
    plain = ConvLSTMClassifier(filters=(3,), max_epochs=2, batch_size=4, random_state=0).fit(X, y)
    assert not np.allclose(a.predict_proba(X), plain.predict_proba(X))
    c = pickle.loads(pickle.dumps(a))
    a.partial_fit(X, y, epochs=1)
    c.partial_fit(X, y, epochs=1)  # the augmentation stream continues where it was
    np.testing.assert_array_equal(a.predict_proba(X), c.predict_proba(X))
    d = clone(make())
    assert d.get_params()["augment"].get_params() == make().augment.get_params()
    assert "augment__gain" in make().get_params(deep=True)


def test_nested_augmenter_parameters_work_in_a_grid_search():
    pipe = make_convlstm_pipeline(intensity_channels=True, augment=True)
    pipe.set_params(clf__augment__gain=0.7)
    assert pipe[-1].augment.gain == 0.7 and clone(pipe)[-1].augment.gain == 0.7
    assert pipe.get_params()["clf__augment__gain"] == 0.7
    assert "augment__gain" not in vars(pipe[-1])
    with pytest.raises(ValueError, match="set augment=FrameAugmenter"):
        ConvLSTMClassifier().set_params(augment__gain=0.5)
    X = np.random.default_rng(3).normal(size=(12, 2, 4, 5, 1)).astype("float32")
    y = np.arange(12) % 2
    search = GridSearchCV(ConvLSTMClassifier(filters=(2,), augment=FrameAugmenter(), max_epochs=1, random_state=0),
                          {"augment__gain": [0.0, 0.5]}, cv=2).fit(X, y)
    assert [p["augment__gain"] for p in search.cv_results_["params"]] == [0.0, 0.5]
    assert search.best_estimator_.augment.gain in (0.0, 0.5)


def test_ensemble_of_augmented_nets_trains_its_members_separately():
    X = np.random.default_rng(2).normal(size=(8, 2, 4, 5, 1)).astype("float32")
    y = np.arange(8) % 2
    ens = EnsembleClassifier(ConvLSTMClassifier(filters=(2,), augment=FrameAugmenter(), max_epochs=1),
                             n_estimators=2, stacked=True, random_state=0)
    with pytest.raises(ValueError, match="augment their training batches"):
        ens.fit(X, y)
    ens.set_params(stacked="auto").fit(X, y)
    assert len(ens.estimators_) == 2


def test_pipeline_augment_true_marks_the_intensity_channels_as_logs():
    clf = make_convlstm_pipeline(intensity_channels=True, augment=True)[-1]
    assert clf.augment.log_channels == [1, 2, 3]
    assert make_convlstm_pipeline(color="rgb", intensity_channels=True, augment=True)[-1].augment.log_channels \
        == [3, 4, 5]
    assert make_convlstm_pipeline(augment=True)[-1].augment.log_channels == []
    assert make_convlstm_pipeline()[-1].augment is None
    mine = FrameAugmenter(gain=0.5)
    assert make_convlstm_pipeline(augment=mine)[-1].augment is mine


def _brightness_confounded(n, rng, bright_class):
    """Class 1: a narrower change than class 0's; ``bright_class`` is drawn 3x stronger."""
    H = W = 8
    yy, xx = np.mgrid[:H, :W]
    X, y = [], []
    for i in range(n):
        label = i % 2
        cy, cx = rng.uniform(2.5, 4.5, size=2)
        r2 = (yy - cy) ** 2 + (xx - cx) ** 2
        width = 1.2 if label == 1 else 1.8
        blob = np.exp(-r2 / (2 * width ** 2))
        blob /= blob.max()
        amp = (3.0 if label == bright_class else 1.0) * rng.uniform(0.8, 1.25)
        frames = np.stack([t * amp * blob for t in (0.5, 1.0)])[..., None]
        X.append(frames + rng.normal(scale=0.05, size=frames.shape))
        y.append(label)
    return np.asarray(X, dtype=np.float32), np.asarray(y)


@pytest.mark.slow
def test_gain_augmentation_lets_the_net_learn_the_shape_instead_of_a_confounded_brightness():
    # Training: the narrower class is always the brighter one; test: the broader one is.
    # A net free to use brightness fails on the test set; with gain drawn over a wide
    # range, brightness tells nothing in training and the net learns the shape.
    rng = np.random.default_rng(0)
    Xtr, ytr = _brightness_confounded(64, rng, bright_class=1)
    Xte, yte = _brightness_confounded(64, rng, bright_class=0)
    scores = {}
    for name, augment in {"none": None, "gain": FrameAugmenter(flip=False, gain=1.0)}.items():
        accs = []
        for seed in range(2):
            clf = ConvLSTMClassifier(filters=(4, 4), augment=augment, max_epochs=40, batch_size=16,
                                     lr=1e-2, random_state=seed).fit(Xtr, ytr)
            accs.append(float(np.mean(clf.predict(Xte) == yte)))
        scores[name] = np.mean(accs)
    assert scores["none"] < 0.3  # measured: 0.0 for both seeds
    assert scores["gain"] > 0.8  # measured: 0.98 and 1.0
