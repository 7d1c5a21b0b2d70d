import builtins
import pickle

import joblib
import numpy as np
import pytest
import torch
import transformers  # the [dinov2] extra; CI installs it (no skipping)
from sklearn.base import clone
from sklearn.exceptions import NotFittedError

from sklearn_hardness.features import DINOv2Features
from sklearn_hardness.utils._param_validation import InvalidParameterError

DIM = 32


def tiny_backbone(seed=0, **kw):
    torch.manual_seed(seed)
    cfg = transformers.Dinov2Config(
        hidden_size=DIM, num_hidden_layers=1, num_attention_heads=2, intermediate_size=64,
        image_size=28, patch_size=14, **kw,
    )
    return transformers.Dinov2Model(cfg).eval()


@pytest.fixture(scope="module")
def backbone():
    return tiny_backbone()


@pytest.fixture(scope="module")
def model_dir(tmp_path_factory, backbone):
    path = tmp_path_factory.mktemp("tiny_dinov2")
    backbone.save_pretrained(path)
    return path


@pytest.fixture
def X():
    return np.random.default_rng(0).random((3, 4, 16, 20, 3), dtype=np.float32)


@pytest.mark.parametrize("token, per_frame", [("cls", DIM), ("mean", DIM), ("cls+mean", 2 * DIM)])
def test_token_options_and_dims(X, backbone, token, per_frame):
    dino = DINOv2Features(model=backbone, token=token, image_size=28).fit(X)
    Xt = dino.transform(X)
    assert Xt.shape == (3, 4 * per_frame) and Xt.dtype == np.float32
    assert dino.n_features_out_ == Xt.shape[1] and dino.embed_dim_ == DIM
    assert np.isfinite(Xt).all()
    names = dino.get_feature_names_out()
    assert len(names) == Xt.shape[1] and names[0] == f"f0_{token.split('+')[0]}0"


def test_tokens_match_backbone_output(X, backbone):
    """cls and mean are the CLS token and the mean patch token of the frame, in frame order."""
    dino = DINOv2Features(model=backbone, token="cls+mean", image_size=28).fit(X)
    Xt = dino.transform(X).reshape(3, 4, 2, DIM)
    # Reference preprocessing written out by hand for sample 1, frame 2.
    lo, hi = X[1].min(), X[1].max()
    img = torch.from_numpy((X[1, 2] - lo) / (hi - lo)).permute(2, 0, 1)[None]
    img = torch.nn.functional.interpolate(img, size=(28, 28), mode="bilinear", antialias=True)
    mean = torch.tensor([0.485, 0.456, 0.406]).view(1, 3, 1, 1)
    std = torch.tensor([0.229, 0.224, 0.225]).view(1, 3, 1, 1)
    with torch.no_grad():
        hidden = backbone(pixel_values=(img - mean) / std).last_hidden_state[0]
    np.testing.assert_allclose(Xt[1, 2, 0], hidden[0].numpy(), atol=1e-5)
    np.testing.assert_allclose(Xt[1, 2, 1], hidden[1:].mean(0).numpy(), atol=1e-5)
    cls_only = DINOv2Features(model=backbone, token="cls", image_size=28).fit_transform(X)
    np.testing.assert_allclose(cls_only.reshape(3, 4, DIM), Xt[:, :, 0], atol=1e-6)


def test_register_tokens_excluded_from_mean(X):
    torch.manual_seed(0)
    cfg = transformers.Dinov2WithRegistersConfig(
        hidden_size=DIM, num_hidden_layers=1, num_attention_heads=2, intermediate_size=64,
        image_size=28, patch_size=14, num_register_tokens=4,
    )
    model = transformers.Dinov2WithRegistersModel(cfg).eval()
    dino = DINOv2Features(model=model, token="mean", image_size=28).fit(X[:1, :1])
    x = dino._preprocess(X[0, :1], np.array([X[0, 0].min()]), np.array([X[0, 0].max()]))
    with torch.no_grad():
        hidden = model(x).last_hidden_state[0]
    assert hidden.shape[0] == 1 + 4 + 4  # cls, registers, 2x2 patches
    np.testing.assert_allclose(dino.transform(X[:1, :1])[0], hidden[5:].mean(0).numpy(), atol=1e-5)


def test_determinism_batch_size_and_order(X, backbone):
    dino = DINOv2Features(model=backbone, token="cls+mean", image_size=28, batch_size=5).fit(X)
    a = dino.transform(X)
    np.testing.assert_array_equal(a, dino.transform(X))
    for bs in (1, 3, 64):
        np.testing.assert_allclose(dino.set_params(batch_size=bs).transform(X), a, atol=1e-5)
    perm = np.array([2, 0, 1])
    np.testing.assert_allclose(dino.transform(X[perm]), a[perm], atol=1e-5)
    # Different frames give different features (the input is used).
    assert not np.allclose(a[0], a[1])


def test_module_path_and_directory_give_same_features(X, backbone, model_dir):
    from_module = DINOv2Features(model=backbone, image_size=28).fit_transform(X)
    from_dir = DINOv2Features(model=str(model_dir), image_size=28).fit_transform(X)
    from_pathlike = DINOv2Features(model=model_dir, image_size=28).fit_transform(X)
    np.testing.assert_allclose(from_dir, from_module, atol=1e-6)
    np.testing.assert_allclose(from_pathlike, from_module, atol=1e-6)


def test_fit_freezes_a_copy_and_leaves_the_module_alone(X):
    model = tiny_backbone().train()
    dino = DINOv2Features(model=model, image_size=28).fit(X)
    assert model.training and all(p.requires_grad for p in model.parameters())
    assert dino.model_ is not model
    assert not dino.model_.training
    assert not any(p.requires_grad for p in dino.model_.parameters())


def test_grey_frames_and_image_size_rounding(backbone):
    Xg = np.random.default_rng(1).random((2, 3, 16, 20, 1), dtype=np.float32)
    dino = DINOv2Features(model=backbone, image_size=(30, 45)).fit(Xg)
    assert dino.input_size_ == (28, 42)  # rounded down to multiples of 14
    assert dino.transform(Xg).shape == (2, 3 * DIM)
    # A grey frame is the same as its RGB repetition.
    rgb = np.repeat(Xg, 3, axis=-1)
    np.testing.assert_allclose(
        DINOv2Features(model=backbone, image_size=(30, 45)).fit_transform(rgb),
        dino.transform(Xg), atol=1e-6,
    )
    assert DINOv2Features(model=backbone, image_size=5).fit(Xg).input_size_ == (14, 14)


def test_value_range(X, backbone):
    dino = DINOv2Features(model=backbone, image_size=28)
    auto = dino.fit_transform(X)
    # Differences in [-1, 1] are scaled per sample: same features as [0, 1] frames.
    np.testing.assert_allclose(dino.fit_transform(2 * X - 1), auto, atol=1e-5)
    fixed = dino.set_params(value_range=(0.0, 1.0)).fit_transform(X)
    assert not np.allclose(fixed, auto)  # X is not exactly min-max scaled per sample
    flat = np.zeros((1, 4, 16, 20, 3), np.float32)
    assert np.isfinite(dino.set_params(value_range=None).fit_transform(flat)).all()


def test_pickle_clone_and_contract(X, backbone):
    dino = DINOv2Features(model=backbone, image_size=28)
    params = joblib.hash(dino.get_params())
    assert dino.fit(X) is dino
    assert joblib.hash(dino.get_params()) == params
    a = dino.transform(X)
    restored = pickle.loads(pickle.dumps(dino))
    np.testing.assert_array_equal(restored.transform(X), a)
    np.testing.assert_allclose(clone(dino).fit_transform(X), a, atol=1e-6)


def test_bad_inputs(X, backbone):
    dino = DINOv2Features(model=backbone, image_size=28)
    with pytest.raises(NotFittedError):
        dino.transform(X)
    with pytest.raises(ValueError, match="n_samples, n_frames, height, width, channels"):
        dino.fit(X[0])
    dino.fit(X)
    with pytest.raises(ValueError, match="3 frames per sample but 4 were seen during fit"):
        dino.transform(X[:, :3])
    bad = X.copy()
    bad[2, 1, 0, 0, 0] = np.inf
    with pytest.raises(ValueError, match=r"NaN or infinite values in sample\(s\) \[2\]"):
        dino.transform(bad)
    for params, exc, msg in [
        ({"token": "patch"}, InvalidParameterError, "'token' parameter"),
        ({"batch_size": 0}, InvalidParameterError, "'batch_size' parameter"),
        ({"image_size": (0, 14)}, InvalidParameterError, "'image_size' parameter"),
        ({"dtype": "int8"}, InvalidParameterError, "'dtype' parameter"),
        ({"device": 3}, InvalidParameterError, "'device' parameter"),
        ({"device": "gpu"}, InvalidParameterError, "'device' parameter of DINOv2Features must be 'cpu', 'cuda', "
                                                   "'auto', a torch device string or a torch.device. Got 'gpu'"),
        ({"dtype": torch.int64}, InvalidParameterError, r"'dtype' parameter .* or a torch.dtype among .*torch.int64"),
        ({"model": 3}, InvalidParameterError, "'model' parameter"),
        ({"value_range": (0, 0)}, InvalidParameterError, "'value_range' parameter"),
    ]:
        with pytest.raises(exc, match=msg):
            DINOv2Features(**{"model": backbone, "image_size": 28, **params}).fit(X)
    if not torch.cuda.is_available():
        with pytest.raises(ValueError, match="CUDA is not available"):
            DINOv2Features(model=backbone, device="cuda").fit(X)


def test_pooled_output_module(X):
    class Pooled(torch.nn.Module):
        def __init__(self):
            super().__init__()
            self.proj = torch.nn.Linear(3, 8)

        def forward(self, x):
            return self.proj(x.mean(dim=(2, 3)))

    dino = DINOv2Features(model=Pooled(), image_size=28).fit(X)
    assert dino.transform(X).shape == (3, 4 * 8)
    with pytest.raises(ValueError, match="only token='cls'"):
        DINOv2Features(model=Pooled(), token="mean", image_size=28).fit(X)


def test_offline_missing_model_gives_clear_error(X, tmp_path, monkeypatch):
    import huggingface_hub.constants

    monkeypatch.setenv("HF_HUB_OFFLINE", "1")
    # huggingface_hub reads the variable when imported; set its constant too.
    monkeypatch.setattr(huggingface_hub.constants, "HF_HUB_OFFLINE", True)
    monkeypatch.setenv("HF_HOME", str(tmp_path / "hf_home"))  # empty cache
    with pytest.raises(OSError, match="local directory with config.json") as info:
        DINOv2Features(model="facebook/dinov2-small").fit(X)
    assert "nn.Module" in str(info.value)
    with pytest.raises(OSError, match="does not exist"):
        DINOv2Features(model=str(tmp_path / "no_such_dir")).fit(X)
    (tmp_path / "empty").mkdir()
    with pytest.raises(OSError, match="no config.json"):
        DINOv2Features(model=str(tmp_path / "empty")).fit(X)


def test_missing_transformers_gives_install_hint(X, monkeypatch, model_dir, backbone):
    real_import = builtins.__import__

    def fake_import(name, *args, **kwargs):
        if name == "transformers" or name.startswith("transformers."):
            raise ImportError("No module named 'transformers'")
        return real_import(name, *args, **kwargs)

    import importlib

    monkeypatch.setattr(importlib, "import_module", lambda name, *a: fake_import(name))
    with pytest.raises(ImportError, match=r"pip install 'sklearn-hardness\[dinov2\]'"):
        DINOv2Features(model=str(model_dir)).fit(X)
    # An nn.Module does not need transformers to be importable.
    assert DINOv2Features(model=backbone, image_size=28).fit_transform(X).shape == (3, 4 * DIM)



def test_features_computed_once_per_video_in_cached_pipeline(X, tmp_path, model_dir, monkeypatch):
    from sklearn.linear_model import LogisticRegression
    from sklearn.pipeline import Pipeline

    n_embedded = []
    embed = DINOv2Features._embed

    def counting_embed(self, pixels):
        n_embedded.append(pixels.shape[0])
        return embed(self, pixels)

    monkeypatch.setattr(DINOv2Features, "_embed", counting_embed)
    y = np.array([0, 1, 0])
    # With model given as a directory (or id) the fitted transformer is cached by
    # joblib; an nn.Module parameter does not hash the same after clone.
    pipe = Pipeline(
        [("dino", DINOv2Features(model=str(model_dir), image_size=28)), ("clf", LogisticRegression())],
        memory=str(tmp_path / "cache"),
    )
    pipe.fit(X, y)
    assert sum(n_embedded) == 1 + X.shape[0] * X.shape[1]  # one probe frame in fit, then each frame once
    proba = pipe.predict_proba(X)
    n_after_predict = sum(n_embedded)
    pipe.set_params(clf__C=0.5).fit(X, y)  # refitting the head reuses the cached features
    assert sum(n_embedded) == n_after_predict
    assert proba.shape == (3, 2)


def test_half_precision_and_auto_device(X, backbone):
    ref = DINOv2Features(model=backbone, image_size=28).fit_transform(X)
    dino = DINOv2Features(model=backbone, image_size=28, dtype="bfloat16", device="auto").fit(X)
    assert dino.device_.type == ("cuda" if torch.cuda.is_available() else "cpu")
    assert next(dino.model_.parameters()).dtype == torch.bfloat16
    out = dino.transform(X)
    assert out.dtype == np.float32
    np.testing.assert_allclose(out, ref, atol=0.1 * np.abs(ref).max())
    assert next(backbone.parameters()).dtype == torch.float32  # the given module is untouched


def test_fitted_on_gpu_loads_on_cpu_only_machine(X, backbone, monkeypatch):
    # stands for a pickle made on a GPU machine: device_ says cuda; loading where torch
    # has no CUDA must warn and run on the CPU, not fail to deserialise the backbone
    import pickle

    dino = DINOv2Features(model=backbone).fit(X)
    expected = dino.transform(X)
    dino.device_ = torch.device("cuda")
    fitted_model = dino.model_
    blob = pickle.dumps(dino)
    assert dino.model_ is fitted_model  # pickling left the fitted estimator alone
    monkeypatch.setattr(torch.cuda, "is_available", lambda: False)
    with pytest.warns(UserWarning, match="CUDA is not available"):
        restored = pickle.loads(blob)
    assert restored.device_.type == "cpu"
    np.testing.assert_allclose(restored.transform(X), expected, rtol=1e-5, atol=1e-6)
