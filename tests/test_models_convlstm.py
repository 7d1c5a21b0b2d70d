"""ConvLSTMClassifier: architecture, input checks and learning."""

import numpy as np
import pytest
import torch

from sklearn_hardness.models import ConvLSTMClassifier
from sklearn_hardness.models._convlstm import ConvLSTMLayer, ConvLSTMNet
from tests._threads import torch_threads

pytestmark = pytest.mark.torch_threads(1)


def _brightness_task(n=20, seed=0, shape=(3, 8, 10, 3)):
    """Class 1 videos get brighter over time, class 0 stay dark: trivially separable."""
    rng = np.random.default_rng(seed)
    y = np.arange(n) % 2
    X = rng.normal(scale=0.05, size=(n,) + shape).astype(np.float32)
    ramp = np.linspace(0.2, 0.8, shape[0], dtype=np.float32)[None, :, None, None, None]
    X += y[:, None, None, None, None] * ramp
    return X, np.where(y == 1, "hard", "soft")


@pytest.fixture(scope="module")
def fitted():
    X, y = _brightness_task()
    with torch_threads(1):
        net = ConvLSTMClassifier(max_epochs=3, dropout_placement="layers", random_state=0).fit(X, y)
    return X, y, net


def test_learns_trivial_video_task():
    X, y = _brightness_task(n=24)
    net = ConvLSTMClassifier(max_epochs=25, lr=1e-2, random_state=0).fit(X, y)
    assert net.score(X, y) == 1.0
    X_test, y_test = _brightness_task(n=16, seed=1)
    assert net.score(X_test, y_test) == 1.0
    losses = net.history[:, "train_loss"]
    assert losses[-1] < 0.5 * losses[0]


def test_architecture_matches_paper(fitted):
    X, y, net = fitted
    m = net.module_
    assert isinstance(m, ConvLSTMNet)
    assert [layer.hidden_channels for layer in m.layers] == [4, 8, 14, 16]
    assert [layer.input_conv.in_channels for layer in m.layers] == [3, 4, 8, 14]
    assert all(layer.input_conv.kernel_size == (3, 3) for layer in m.layers)
    assert [d.p for d in m.dropouts] == [0.2] * 4
    assert m.head.in_features == 16 and m.head.out_features == 2
    assert net.n_frames_in_ == 3 and net.frame_shape_ == (8, 10, 3)
    assert m.input_shape.tolist() == [3, 8, 10, 3]


def test_convlstm_layer_matches_reference_equations():
    torch.manual_seed(0)
    layer = ConvLSTMLayer(2, 3, kernel_size=3)
    x = torch.randn(2, 4, 2, 5, 6)
    out = layer(x)
    assert out.shape == (2, 4, 3, 5, 6)
    # reference: one convolution of [x_t, h_{t-1}] with the concatenated weights
    w = torch.cat([layer.input_conv.weight, layer.hidden_conv.weight], dim=1)
    h = torch.zeros(2, 3, 5, 6)
    c = torch.zeros(2, 3, 5, 6)
    for t in range(4):
        gates = torch.nn.functional.conv2d(torch.cat([x[:, t], h], 1), w, layer.input_conv.bias, padding=1)
        i, f, g, o = gates.chunk(4, 1)
        c = torch.sigmoid(f) * c + torch.sigmoid(i) * torch.tanh(g)
        h = torch.sigmoid(o) * torch.tanh(c)
        torch.testing.assert_close(out[:, t], h, atol=1e-5, rtol=1e-5)
    torch.testing.assert_close(layer(x, return_sequence=False), h, atol=1e-5, rtol=1e-5)
    # forget-gate bias starts at 1
    assert torch.all(layer.input_conv.bias[3:6] == 1) and torch.all(layer.input_conv.bias[:3] == 0)


def test_replicated_forward_runs_first_layer_once(fitted):
    X, y, net = fitted
    m = net.module_.eval()
    seen = {}

    def record(name):
        def hook(mod, inp, out):
            seen.setdefault(name, inp[0].shape[0])

        return hook

    hooks = [
        conv.register_forward_hook(record(name))
        for name, conv in [("l0_in", m.layers[0].input_conv), ("l0_h", m.layers[0].hidden_conv),
                           ("l1_in", m.layers[1].input_conv), ("l1_h", m.layers[1].hidden_conv)]
    ]
    try:
        with torch.no_grad():
            out = m(torch.as_tensor(X[:2]), n_replicas=5)
            plain = m(torch.as_tensor(X[:2]))
    finally:
        for h in hooks:
            h.remove()
    # the first layer (before any dropout) sees 2 inputs; the second one 5 replicas of each
    assert seen == {"l0_in": 2 * 3, "l0_h": 2, "l1_in": 10 * 3, "l1_h": 10}
    torch.testing.assert_close(out.reshape(5, 2, 2)[4], plain, atol=1e-5, rtol=1e-5)


def test_head_placement_replicates_only_the_pooled_features():
    X, y = _brightness_task(n=6)
    net = ConvLSTMClassifier(max_epochs=1, random_state=0).fit(X, y)
    m = net.module_.eval()
    assert net.dropout_placement == "head" and len(m.dropouts) == 1
    seen = []
    hook = m.layers[-1].hidden_conv.register_forward_hook(lambda mod, inp, out: seen.append(inp[0].shape[0]))
    try:
        with torch.no_grad():
            out = m(torch.as_tensor(X[:2]), n_replicas=5)
            plain = m(torch.as_tensor(X[:2]))
    finally:
        hook.remove()
    assert set(seen) == {2}  # the whole recurrent stack runs once per input
    torch.testing.assert_close(out.reshape(5, 2, 2)[3], plain, atol=1e-5, rtol=1e-5)


def _mc_share_task(n, seed):
    rng = np.random.default_rng(seed)
    y = np.arange(n) % 3
    X = rng.normal(size=(n, 3, 6, 8, 1)).astype(np.float32)
    X += 0.5 * y[:, None, None, None, None] * np.linspace(0.3, 1, 3)[None, :, None, None, None]
    return X, y


def test_mc_part_of_eq2_variance_is_not_negligible():
    """On a trained net the MC passes carry a real share of Eq. 2 (the paper's placement: ~3%)."""
    from sklearn_hardness.active import variance_decomposition

    X, y = _mc_share_task(24, 0)
    X_test, y_test = _mc_share_task(12, 1)
    shares = {}
    for placement in ("head", "layers"):
        net = ConvLSTMClassifier(dropout_placement=placement, filters=(4, 8), lr=5e-3, max_epochs=20,
                                 random_state=0).fit(X, y)
        assert net.final_train_loss_ < 0.7  # trained, not near uniform
        dec = variance_decomposition(net.predict_proba_samples(X_test[y_test == 0], n_samples=50, random_state=0))
        shares[placement] = dec["mc"].sum() / dec["total"].sum()
    assert shares["head"] > 0.15, shares
    assert shares["head"] > 3 * shares["layers"], shares


def test_any_frame_size_and_grey(fitted):
    X, y = _brightness_task(n=6, shape=(2, 5, 7, 1))
    net = ConvLSTMClassifier(max_epochs=1, filters=(3, 5), random_state=0).fit(X, y)
    assert net.predict_proba_samples(X, n_samples=3, random_state=0).shape == (3, 6, 2)
    assert len(net.module_.layers) == 2


@pytest.mark.parametrize(
    "X_bad, match",
    [
        (np.zeros((4, 3, 8, 10), np.float32), "5 dimension|dimension\\(s\\)"),
        (np.zeros((4, 2, 8, 10, 3), np.float32), "2 frames per sample but 3"),
        (np.zeros((4, 3, 8, 12, 3), np.float32), "frames of shape \\(8, 12, 3\\)"),
        (np.zeros((4, 3, 8, 10, 1), np.float32), "frames of shape \\(8, 10, 1\\)"),
        (np.full((4, 3, 8, 10, 3), np.nan, np.float32), "NaN"),
        (np.array([["a"]]), "numeric|dimension"),
    ],
)
def test_bad_inputs_give_clear_errors(fitted, X_bad, match):
    _, _, net = fitted
    with pytest.raises((ValueError, TypeError), match=match):
        net.predict_proba(X_bad)
    with pytest.raises((ValueError, TypeError), match=match):
        net.predict_proba_samples(X_bad, n_samples=2)


def test_bad_parameters():
    X, y = _brightness_task(n=6)
    with pytest.raises(ValueError, match="filters"):
        ConvLSTMClassifier(filters=(4, 0), max_epochs=1).fit(X, y)
    with pytest.raises(ValueError, match="odd"):
        ConvLSTMClassifier(kernel_size=2, max_epochs=1).fit(X, y)
    with pytest.raises(ValueError, match="NaN"):
        ConvLSTMClassifier(max_epochs=1).fit(np.where(X > 0.5, np.nan, X), y)


def test_layer_placement_masks_reach_the_output_and_survive_clone_and_pickle():
    """The paper's placement (dropout after each ConvLSTM layer): every layer's masks change the MC passes."""
    import pickle

    from sklearn.base import clone

    from sklearn_hardness.models import make_convlstm_pipeline

    X, y = _brightness_task(n=8)
    net = ConvLSTMClassifier(dropout_placement="layers", dropout=0.3, filters=(3, 4), max_epochs=2,
                             random_state=0).fit(X, y)
    m = net.module_
    assert len(m.dropouts) == 2  # one after each layer, none on the pooled features only
    seen = []
    hooks = [d.register_forward_hook(lambda mod, inp, out: seen.append(bool(torch.any(out != inp[0]))))
             for d in m.dropouts]
    try:
        passes = net.predict_proba_samples(X[:3], n_samples=8, random_state=0)
    finally:
        for h in hooks:
            h.remove()
    assert seen and all(seen)  # every layer's dropout zeroes something in the MC passes
    assert passes.std(axis=0).max() > 1e-4  # ... and the passes differ at the output
    proba = net.predict_proba(X[:3])  # dropout off: deterministic, and no pass is it exactly
    np.testing.assert_allclose(net.predict_proba(X[:3]), proba)
    assert not np.allclose(passes, proba[None], atol=1e-6)
    # without dropout the passes collapse to predict_proba: the spread above is the masks'
    still = ConvLSTMClassifier(dropout_placement="layers", dropout=0.0, filters=(3, 4), max_epochs=1,
                               random_state=0).fit(X, y)
    np.testing.assert_allclose(still.predict_proba_samples(X[:3], n_samples=4, random_state=0),
                               np.broadcast_to(still.predict_proba(X[:3]), (4, 3, 2)), atol=1e-5)
    # clone keeps the parameter; a pickle keeps the net and its seeded passes
    assert clone(net).get_params()["dropout_placement"] == "layers"
    back = pickle.loads(pickle.dumps(net))
    assert len(back.module_.dropouts) == 2
    np.testing.assert_allclose(back.predict_proba_samples(X[:3], n_samples=8, random_state=0), passes, atol=1e-6)
    # the ready-made pipeline passes it on
    pipe = make_convlstm_pipeline(dropout_placement="layers")
    assert pipe.named_steps["clf"].dropout_placement == "layers"
