import numpy as np
import pytest
from sklearn.base import clone
from sklearn.exceptions import NotFittedError

from sklearn_hardness.models import ConvLSTMClassifier, make_convlstm_pipeline, make_ofnn_pipeline
from sklearn_hardness.models._intensity_channels import IntensityChannels
from sklearn_hardness.models._pipelines import FrameScaler

from ._exp_data import tiny_presses


def _frames(rng, n=3, k=4, shape=(6, 8, 1)):
    return rng.normal(size=(n, k) + shape).astype(np.float32)


def test_channels_hold_the_log_statistics_of_each_frame():
    rng = np.random.default_rng(0)
    X = _frames(rng)
    Xt = IntensityChannels(floor=0.5).fit_transform(X)
    assert Xt.shape == X.shape[:-1] + (4,) and Xt.dtype == np.float32
    np.testing.assert_array_equal(Xt[..., :1], X)  # the frames are kept as they are
    a = np.abs(X).reshape(3, 4, -1)
    expected = np.log(0.5 + np.stack([a.mean(2), a.std(2), a.max(2)], -1))
    for c in range(3):  # each statistic is constant over the frame
        np.testing.assert_allclose(Xt[..., 1 + c], np.broadcast_to(expected[:, :, None, None, c], X.shape[:-1]),
                                   rtol=1e-5)


def test_scale_and_concentration_become_differences():
    """Scaling a press by s shifts its log channels by about log s; a concentrated contact has a larger max/mean."""
    X = np.zeros((2, 2, 8, 8, 1), np.float32)
    X[0, 1] = 1.0                      # broad: the whole frame changes by 1
    X[1, 1, 3:5, 3:5] = 16.0           # concentrated: same mean change on 1/16 of the frame
    t = IntensityChannels(floor=1e-6).fit_transform(X)[:, 1, 0, 0, 1:]  # (press, [mean, std, max])
    np.testing.assert_allclose(t[0, 0], t[1, 0], atol=1e-5)  # same mean change
    assert t[1, 2] - t[1, 0] > np.log(15) and abs(t[0, 2] - t[0, 0]) < 1e-5  # max/mean tells them apart
    scaled = IntensityChannels(floor=1e-6).fit_transform(10 * X)[:, 1, 0, 0, 1:]
    np.testing.assert_allclose(scaled[:, [0, 2]] - t[:, [0, 2]], np.log(10), atol=1e-4)


def test_bad_input_and_state():
    rng = np.random.default_rng(1)
    X = _frames(rng)
    with pytest.raises(NotFittedError):
        IntensityChannels().transform(X)
    tr = IntensityChannels().fit(X)
    with pytest.raises(ValueError, match=r"3 channel\(s\) but IntensityChannels was fitted on 1"):
        tr.transform(np.repeat(X, 3, axis=-1))
    with pytest.raises(ValueError, match="n_samples, n_frames"):
        IntensityChannels().fit(X.reshape(3, -1))
    with pytest.raises(ValueError, match="floor"):
        IntensityChannels(floor=0).fit(X)
    np.testing.assert_array_equal(clone(tr).fit_transform(X), tr.transform(X))


def test_pipeline_inputs_and_their_switches():
    """Intensity channels are one switch away in the ConvLSTM pipeline; OFNN summarises the flow by default."""
    data = tiny_presses()
    pipe = make_convlstm_pipeline(intensity_channels=True, frame_size=(8, 10), max_epochs=2, random_state=0)
    assert [n for n, _ in pipe.steps] == ["frames", "scale", "intensity", "clf"]
    assert pipe[-1].class_weight == "balanced"
    pipe.fit(data.videos[:20], data.target[:20])
    assert pipe[-1].frame_shape_ == (8, 10, 4) and pipe[-1].n_frames_in_ == 4
    assert pipe.predict_proba_samples(data.videos[20:23], n_samples=4, random_state=0).shape == (4, 3, 5)
    paper = make_convlstm_pipeline(class_weight=None)
    assert [n for n, _ in paper.steps] == ["frames", "scale", "clf"] and paper[-1].class_weight is None
    assert paper.named_steps["frames"].frame_size == (12, 16)
    ofnn = make_ofnn_pipeline(flow_output="tracks", class_weight=None)
    assert ofnn.named_steps["features"].output == "tracks" and ofnn[-1].class_weight is None
    assert make_ofnn_pipeline().named_steps["features"].output == "magnitude_quantiles"
    assert make_ofnn_pipeline()[-1].class_weight == "balanced"


def test_intensity_channels_feed_the_convlstm_like_any_channel():
    rng = np.random.default_rng(2)
    X = _frames(rng, n=8)
    y = np.arange(8) % 2
    Xt = IntensityChannels().fit_transform(FrameScaler().fit_transform(X))
    clf = ConvLSTMClassifier(filters=(2,), max_epochs=2, random_state=0).fit(Xt, y)
    assert clf.input_mean_.shape == (4,)  # the net standardises the new channels too
