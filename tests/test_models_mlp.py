"""OFNNClassifier / DINOv2NNClassifier / ContactProfileNNClassifier: input checks, learning, docs."""

import inspect
import re

import numpy as np
import pytest
import torch
from sklearn.pipeline import make_pipeline
from sklearn.preprocessing import StandardScaler

from sklearn_hardness.models import ContactProfileNNClassifier, DINOv2NNClassifier, OFNNClassifier
from sklearn_hardness.models._mlp import MLPHead

pytestmark = pytest.mark.torch_threads(1)


@pytest.fixture(scope="module")
def fitted():
    rng = np.random.default_rng(0)
    X = rng.normal(size=(15, 6)).astype(np.float32)
    y = np.arange(15) % 3
    return X, y, OFNNClassifier(max_epochs=2, random_state=0).fit(X, y)


@pytest.mark.parametrize("cls", [OFNNClassifier, DINOv2NNClassifier])
def test_learns_separable_problem(cls):
    rng = np.random.default_rng(1)
    n, d = 90, 40
    y = np.repeat([10, 20, 30], n // 3)
    centers = rng.normal(scale=3.0, size=(3, d))
    X = (centers[np.searchsorted([10, 20, 30], y)] + rng.normal(size=(n, d))).astype(np.float32)
    pipe = make_pipeline(StandardScaler(), cls(max_epochs=30, random_state=0))
    pipe.fit(X, y)
    assert pipe.score(X, y) >= 0.95
    net = pipe[-1]
    losses = net.history[:, "train_loss"]
    assert losses[-1] < 0.5 * losses[0]
    assert net.final_train_loss_ == losses[-1]


def test_architecture_matches_paper(fitted):
    X, y, net = fitted
    m = net.module_
    assert isinstance(m, MLPHead)
    assert (m.hidden.in_features, m.hidden.out_features) == (6, 128)
    assert (m.out.in_features, m.out.out_features) == (128, 3)
    assert m.dropout.p == 0.2
    assert net.n_features_in_ == 6
    assert isinstance(net.criterion_, torch.nn.CrossEntropyLoss)
    assert isinstance(net.optimizer_, torch.optim.Adam)
    # predict_proba is the softmax of the module's logits
    with torch.no_grad():
        logits = m.eval()(torch.as_tensor(X))
    np.testing.assert_allclose(net.predict_proba(X), torch.softmax(logits, -1).numpy(), atol=1e-6)


def test_replicated_forward_runs_head_only_once_per_input(fitted):
    X, y, net = fitted
    m = net.module_.eval()
    calls = []
    handle = m.hidden.register_forward_hook(lambda mod, inp, out: calls.append(inp[0].shape[0]))
    try:
        with torch.no_grad():
            out = m(torch.as_tensor(X[:4]), n_replicas=10)
    finally:
        handle.remove()
    assert calls == [4]  # the first layer saw each input once
    assert out.shape == (40, 3)
    # replica-major: in eval mode every replica equals the plain output
    np.testing.assert_allclose(out.reshape(10, 4, 3)[7].numpy(), m(torch.as_tensor(X[:4])).detach().numpy(), atol=1e-6)


@pytest.mark.parametrize(
    "X_bad, match",
    [
        (np.zeros((4, 2, 8, 10, 3), np.float32), "2-D array of features"),
        (np.zeros(6, np.float32), "(?s)Expected 2D array.*Reshape your data"),
        (np.zeros((4, 5), np.float32), "5 features.*expecting 6 features"),
        (np.full((4, 6), np.nan, np.float32), "NaN"),
        (np.full((4, 6), np.inf, np.float32), "infinity"),
    ],
)
def test_bad_inputs_give_clear_errors(fitted, X_bad, match):
    _, _, net = fitted
    with pytest.raises(ValueError, match=match):
        net.predict_proba(X_bad)
    with pytest.raises(ValueError, match=match):
        net.predict_proba_samples(X_bad, n_samples=2)


def test_bad_training_inputs(fitted):
    X, y, _ = fitted
    with pytest.raises(ValueError, match="NaN"):
        OFNNClassifier(max_epochs=1).fit(np.where(X > 1, np.nan, X), y)
    with pytest.raises(ValueError, match="1-D array of labels"):
        OFNNClassifier(max_epochs=1).fit(X, np.stack([y, y], 1))
    with pytest.raises(ValueError, match="NaN or infinite labels"):
        OFNNClassifier(max_epochs=1).fit(X, np.where(y == 0, np.nan, y))


def test_unfitted_net_raises():
    from sklearn.exceptions import NotFittedError

    with pytest.raises(NotFittedError):
        OFNNClassifier().predict_proba(np.zeros((2, 3), np.float32))
    with pytest.raises(NotFittedError):
        OFNNClassifier().predict_proba_samples(np.zeros((2, 3), np.float32))
    with pytest.raises(AttributeError, match="not been trained"):
        OFNNClassifier().final_train_loss_


MLP_CLASSES = [OFNNClassifier, DINOv2NNClassifier, ContactProfileNNClassifier]


def _documented_parameters(cls):
    doc = inspect.getdoc(cls)
    section = doc[doc.index("Parameters\n----------"):doc.index("Attributes\n----------")]
    return dict(re.findall(r"^(\**\w+)(?: : (.*))?$", section, flags=re.M)[1:])  # [0]: the heading


@pytest.mark.parametrize("cls", MLP_CLASSES, ids=lambda c: c.__name__)
def test_mlp_docstring_lists_the_signature_with_its_defaults(cls):
    documented = _documented_parameters(cls)
    signature = inspect.signature(cls).parameters
    assert list(documented) == [("**" + n) if p.kind is p.VAR_KEYWORD else n for n, p in signature.items()]
    for name in ("hidden_units", "dropout", "lr", "max_epochs", "batch_size"):
        assert documented[name].endswith(f"default={signature[name].default}"), (name, documented[name])


def test_mlp_docstrings_share_one_text():
    # one implementation, one docstring source: the parameter lists agree word for word except
    # for defaults; only the paper's two classes cite the paper's 128 hidden units
    docs = {cls: inspect.getdoc(cls) for cls in MLP_CLASSES}
    assert len({tuple(_documented_parameters(cls)) for cls in MLP_CLASSES}) == 1
    assert ContactProfileNNClassifier().hidden_units == 64 and "default=64" in docs[ContactProfileNNClassifier]
    assert [("(128 in the paper)" in doc) for doc in docs.values()] == [True, True, False]
    assert all(">>> clf.predict_proba" in doc for doc in docs.values())
