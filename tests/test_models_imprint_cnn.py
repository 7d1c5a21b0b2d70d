"""ImprintCNNClassifier: every frame a training example, probabilities pooled per press, augmentation, MC dropout."""

import numpy as np
import pytest
import torch
from sklearn.base import clone
from sklearn.model_selection import GridSearchCV
from sklearn.utils.class_weight import compute_class_weight
from skorch.callbacks import Callback

from sklearn_hardness.models import (
    FrameAugmenter,
    ImprintCNNClassifier,
    make_imprint_cnn_pipeline,
    make_named_pipeline,
    pipeline_info,
)
from sklearn_hardness.models._imprint_cnn import ImprintCNN
from sklearn_hardness.utils._param_validation import InvalidParameterError

from ._synthetic import synthetic_press

pytestmark = pytest.mark.torch_threads(1)


def _blobs_and_stripes(n=24, k=3, size=(16, 20), seed=0):
    """Class 0: every frame a bright blob somewhere; class 1: stripes of random phase and direction."""
    rng = np.random.default_rng(seed)
    H, W = size
    yy, xx = np.mgrid[:H, :W].astype(np.float32)
    X = np.empty((n, k, H, W, 1), np.float32)
    y = np.arange(n) % 2
    for i in range(n):
        for j in range(k):
            if y[i] == 0:
                cy, cx = rng.uniform(4, H - 4), rng.uniform(4, W - 4)
                img = np.exp(-((yy - cy) ** 2 + (xx - cx) ** 2) / (2 * 2.5**2))
            else:
                axis = xx if rng.random() < 0.5 else yy
                img = 0.5 + 0.5 * np.sin(2 * np.pi * axis / 4 + rng.uniform(0, 2 * np.pi))
            X[i, j, :, :, 0] = rng.uniform(0.5, 1.5) * img + rng.normal(0, 0.05, (H, W))
    return X, y


def _clf(**kw):
    params = {"width": 4, "max_epochs": 3, "batch_size": 8, "lr": 1e-2, "random_state": 0, **kw}
    return ImprintCNNClassifier(**params)


@pytest.fixture(scope="module")
def data():
    return _blobs_and_stripes()


@pytest.fixture(scope="module")
def fitted(data):
    X, y = data
    return _clf().fit(X, y)


class _TrainingRows(Callback):
    """Counts the examples of the training batches and keeps their shapes."""

    def initialize(self):
        self.rows, self.shapes = 0, set()
        return self

    def on_batch_end(self, net, batch=None, training=None, **kwargs):
        if training:
            self.rows += len(batch[0])
            self.shapes.add(tuple(batch[0].shape[1:]))


class _RecordingCNN(ImprintCNN):
    """ImprintCNN that keeps a copy of every input it is given."""

    def __init__(self, *args, **kwargs):
        super().__init__(*args, **kwargs)
        self.seen = []

    def forward(self, X, n_replicas=1):
        self.seen.append((self.training, X.detach().clone()))
        return super().forward(X, n_replicas=n_replicas)


def test_learns_frames_of_a_separable_task(data, fitted):
    X, y = data
    assert (fitted.predict(X) == y).mean() >= 0.9
    losses = fitted.history[:, "train_loss"]
    assert losses[-1] < 0.5 * losses[0]
    X_new, y_new = _blobs_and_stripes(seed=1)  # other blobs and stripes
    assert (fitted.predict(X_new) == y_new).mean() >= 0.8


def test_training_sees_every_frame_as_one_example(data):
    X, y = data
    counter = _TrainingRows()
    _clf(max_epochs=2, callbacks=[("rows", counter)]).fit(X, y)
    n, k = X.shape[:2]
    assert counter.rows == 2 * n * k  # 2 epochs of n * k frames, not n presses
    assert counter.shapes == {(1,) + X.shape[2:]}  # one-frame presses


def test_predict_proba_is_the_mean_of_the_frames_probabilities(data, fitted):
    X, _ = data
    net = fitted.module_.eval()
    x = torch.as_tensor(X[:6])
    with torch.no_grad():
        flat = ((x - net.input_mean) / net.input_scale).reshape(-1, *X.shape[2:]).permute(0, 3, 1, 2)
        frame_proba = torch.softmax(net.head(net.features(flat).mean(dim=(-2, -1))), dim=-1)
    frame_proba = frame_proba.reshape(6, X.shape[1], -1).numpy()
    proba = fitted.predict_proba(X[:6])
    np.testing.assert_allclose(proba, frame_proba.mean(axis=1), rtol=1e-4, atol=1e-6)
    assert proba.shape == (6, 2)
    # the frames of a press do not all agree, so the pooling is not a pick of one frame
    assert np.abs(frame_proba - frame_proba.mean(axis=1, keepdims=True)).max() > 1e-3


def test_predict_proba_samples_pool_per_press_and_follow_dropout(data, fitted):
    X, y = data
    samples = fitted.predict_proba_samples(X[:5], n_samples=7, random_state=0)
    assert samples.shape == (7, 5, 2) and samples.dtype == np.float32
    np.testing.assert_allclose(samples.sum(axis=-1), 1.0, rtol=1e-5)
    assert samples.std(axis=0).max() > 1e-4  # dropout 0.3 on the pooled features: passes differ
    np.testing.assert_array_equal(samples, fitted.predict_proba_samples(X[:5], n_samples=7, random_state=0))

    no_dropout = _clf(dropout=0.0).fit(X, y)
    passes = no_dropout.predict_proba_samples(X[:5], n_samples=4, random_state=0)
    np.testing.assert_allclose(passes, np.broadcast_to(no_dropout.predict_proba(X[:5]), passes.shape), rtol=1e-5)


def test_augmentation_only_in_training(data):
    X, y = data
    clf = _clf(module=_RecordingCNN, max_epochs=2, batch_size=len(X) * X.shape[1], iterator_train__shuffle=False)
    clf.fit(X, y)
    train = [x for training, x in clf.module_.seen if training]
    assert len(train) == 2 and not torch.equal(train[0], train[1])  # same frames, other draws each epoch
    flat = torch.as_tensor(X).reshape(-1, 1, *X.shape[2:])
    assert not torch.equal(train[0], flat)
    clf.module_.seen.clear()
    first, second = clf.predict_proba(X), clf.predict_proba(X)
    np.testing.assert_array_equal(first, second)
    assert all(torch.equal(x, torch.as_tensor(X)) for _, x in clf.module_.seen)  # prediction: as given

    plain = _clf(module=_RecordingCNN, augment=False, max_epochs=2, batch_size=len(X) * X.shape[1],
                 iterator_train__shuffle=False).fit(X, y)
    train = [x for training, x in plain.module_.seen if training]
    assert torch.equal(train[0], flat) and torch.equal(train[1], flat)


def test_default_augmentation_and_a_given_augmenter(data):
    X, y = data
    clf = _clf(max_epochs=0).fit(X, y)
    aug = clf._training_augmenter()
    assert (aug.flip, aug.gain, aug.shift) == (True, 0.3, 0.125)
    # noise of 0.05 in standardised units: 0.05 times the frames' s.d.
    assert aug.noise == pytest.approx(0.05 * float(X.std()), rel=1e-3)
    given = FrameAugmenter(gain=0.0, noise=0.1)
    assert _clf(augment=given)._training_augmenter() is given
    with pytest.raises(ValueError, match="set augment=FrameAugmenter"):
        _clf().set_params(augment__gain=0.1)
    clf = _clf(augment=FrameAugmenter()).set_params(augment__shift=0.25)
    assert clf.augment.shift == 0.25


def test_defaults_params_and_clone(data):
    X, y = data
    clf = ImprintCNNClassifier()
    params = clf.get_params()
    expected = {"width": 16, "dropout": 0.3, "augment": True, "class_weight": "balanced", "lr": 2e-3,
                "max_epochs": 8, "batch_size": 64, "train_split": None, "device": "cpu",
                "optimizer": torch.optim.AdamW, "optimizer__weight_decay": 1e-3}
    assert {key: params[key] for key in expected} == expected
    twin = clone(_clf(dropout=0.1, optimizer__weight_decay=0.0))
    assert twin.dropout == 0.1 and twin.get_params()["optimizer__weight_decay"] == 0.0
    assert not hasattr(twin, "module_") or not twin.initialized_
    twin.set_params(width=2, augment=False).fit(X, y)
    assert twin.module_.head.in_features == 4 * 2
    assert twin.optimizer_.param_groups[0]["weight_decay"] == 0.0
    assert isinstance(twin.optimizer_, torch.optim.AdamW)


def test_balanced_class_weight_from_the_training_presses(data):
    X, y = data
    y = np.where(np.arange(len(y)) < 18, 0, 1)  # 18 against 6 presses
    clf = _clf(max_epochs=0).fit(X, y)
    expected = compute_class_weight("balanced", classes=np.array([0, 1]), y=y)
    np.testing.assert_allclose(clf.criterion_.weight.numpy(), expected, rtol=1e-6)
    assert _clf(max_epochs=0, class_weight=None).fit(X, y).criterion_.weight is None


def test_grid_search_over_dropout_on_the_pipeline():
    videos = [synthetic_press(n_frames=14, size=(24, 32), contact_start=4, peak=8, radius=5 + 4 * (i % 2), seed=i)
              for i in range(8)]
    y = np.arange(8) % 2
    pipe = make_imprint_cnn_pipeline(k=3, frame_size=(16, 20), width=2, max_epochs=2, batch_size=16, random_state=0)
    search = GridSearchCV(pipe, {"clf__dropout": [0.0, 0.3]}, cv=2).fit(videos, y)
    assert search.best_params_["clf__dropout"] in (0.0, 0.3)
    assert len(search.cv_results_["mean_test_score"]) == 2
    best = search.best_estimator_
    assert best.named_steps["frames"].n_between == 1
    assert best.predict_proba_samples(videos[:2], n_samples=3, random_state=0).shape == (3, 2, 2)


def test_named_pipeline():
    info = pipeline_info("imprint_cnn")
    assert info.input == "video" and info.samples and info.random
    assert not pipeline_info("imprint_cnn").default
    pipe = make_named_pipeline("imprint_cnn", random_state=3)
    assert [name for name, _ in pipe.steps] == ["frames", "scale", "clf"]
    clf = pipe.named_steps["clf"]
    assert isinstance(clf, ImprintCNNClassifier) and clf.random_state == 3
    frames = pipe.named_steps["frames"]
    assert (frames.n_between + 2, frames.frame_size, frames.color) == (8, (60, 80), "rgb")


@pytest.mark.parametrize("k", [1, 0, 2.0, True])
def test_pipeline_needs_two_frames_or_more(k):
    with pytest.raises(ValueError, match="k must be an int of at least 2"):
        make_imprint_cnn_pipeline(k=k)


def test_bad_input_is_named(data, fitted):
    X, y = data
    with pytest.raises(ValueError, match=r"must have shape \(n_samples, n_frames, height, width, channels\)"):
        _clf().fit(X[:, 0], y)
    with pytest.raises(ValueError, match="empty samples"):
        _clf().fit(X[:, :0], y)
    bad = X.copy()
    bad[3, 1, 2, 2, 0] = np.nan
    with pytest.raises(ValueError, match=r"NaN or infinite values in sample\(s\) \[3\]"):
        _clf().fit(bad, y)
    with pytest.raises(ValueError, match=r"NaN or infinite values in sample\(s\) \[3\]"):
        fitted.predict_proba(bad)
    with pytest.raises(ValueError, match="frames of shape"):
        fitted.predict(X[:, :, :8])
    with pytest.raises(InvalidParameterError, match="'augment' parameter"):
        _clf(augment="strong").fit(X, y)
    with pytest.raises(InvalidParameterError, match="'width' parameter"):
        _clf(width=0).fit(X, y)


def test_saved_parameters_load_into_a_fresh_net(tmp_path, data, fitted):
    X, _ = data
    path = tmp_path / "cnn.pt"
    fitted.save_params(f_params=str(path))
    fresh = ImprintCNNClassifier(width=4, classes=fitted.classes_).load_params(f_params=str(path))
    np.testing.assert_allclose(fresh.predict_proba(X), fitted.predict_proba(X), rtol=1e-5, atol=1e-7)
    assert fresh.n_frames_in_ == X.shape[1] and fresh.frame_shape_ == X.shape[2:]
