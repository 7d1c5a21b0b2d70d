"""Frozen DINOv2 embeddings of selected press frames (the paper's DINOv2NN input)."""

from __future__ import annotations

import copy
import importlib
import os
import warnings
from numbers import Integral

import numpy as np
import torch
from sklearn.base import BaseEstimator, TransformerMixin
from sklearn.utils.validation import check_is_fitted

from ..utils._param_validation import (
    HasMethods,
    Interval,
    Options,
    Pair,
    StrOptions,
    ValueRange,
    fit_context,
)
from ..utils._per_press import PerPressTransformerMixin, transform_presses
from ..utils._tags import frames_tags
from ..utils._torch import TorchDevices
from ..utils._validation import check_frames_array
from ._common import sample_range

__all__ = ["DINOv2Features"]

_TOKENS = ("cls", "mean", "cls+mean")
_DTYPES = {"float32": torch.float32, "float16": torch.float16, "bfloat16": torch.bfloat16}
_IMAGENET_MEAN = (0.485, 0.456, 0.406)
_IMAGENET_STD = (0.229, 0.224, 0.225)
_INSTALL_HINT = "pip install 'sklearn-hardness[dinov2]'"


class DINOv2Features(PerPressTransformerMixin, TransformerMixin, BaseEstimator):
    """Embeddings of every selected frame by a frozen DINOv2 backbone, concatenated.

    Each of the ``k`` frames of a sample is scaled to [0, 1], resized,
    normalised with the ImageNet mean and standard deviation and passed
    through a frozen DINOv2 vision transformer (Hugging Face
    :class:`transformers.Dinov2Model`); the chosen token embedding(s) of the
    ``k`` frames are concatenated. This is the input of the DINOv2NN model
    of the paper (Sec. II-B, DINOv2-S/14 backbone).

    The backbone is loaded once in :meth:`fit` and never trained; features
    are computed once per sample by :meth:`transform` (in a
    :class:`~sklearn.pipeline.Pipeline` the classifier then trains all its
    epochs and Monte-Carlo-dropout passes on the cached array). Where a
    pipeline is fitted again and again on growing subsets of the same
    presses (active learning), transform all presses once and train the
    classifier on the array, or give the pipeline a ``memory`` so that
    refits reuse the features (this needs ``model`` as an id or directory:
    joblib does not hash an ``nn.Module`` the same after cloning).

    Parameters
    ----------
    model : str, path-like or torch.nn.Module, default="facebook/dinov2-small"
        The backbone:

        - a Hugging Face model id, loaded with
          ``transformers.AutoModel.from_pretrained`` (from the local cache
          when offline, see ``local_files_only``);
        - a local directory holding ``config.json`` and the weights (as
          written by ``save_pretrained``);
        - an already built :class:`torch.nn.Module`, e.g. a
          ``Dinov2Model``; it is deep-copied in :meth:`fit`, so the object
          passed is left unchanged. Any module mapping a ``(B, 3, h, w)``
          float tensor to a ``(B, n_tokens, dim)`` token sequence whose first
          token is the CLS token works (an output with ``last_hidden_state``
          or a tuple whose first item is that sequence too); a module
          returning pooled ``(B, dim)`` features works with ``token="cls"``
          only.

        Nothing can be downloaded without network access: in that case pass
        a local directory or a module (the error message says so).
    token : {"cls", "mean", "cls+mean"}, default="cls"
        Which embedding of each frame to keep: the CLS token of the last
        layer (after the final layer norm), the mean of the patch tokens
        (register tokens excluded), or both concatenated (``2 * dim``
        values, as in DINOv2's linear evaluation).
    batch_size : int, default=32
        Number of frames per forward pass.
    device : {"cpu", "cuda", "auto"}, str or torch.device, default="cpu"
        Where the backbone runs (any device string torch takes, e.g.
        ``"cuda:1"``); ``"auto"`` picks CUDA when available. The output is
        always a NumPy array in host memory.
    image_size : int or tuple of int (height, width), default=224
        Size the frames are resized to (bilinear with antialiasing), after
        rounding each side down to a multiple of the backbone's patch size
        (``config.patch_size``, 14 for DINOv2; at least one patch). An int
        gives a square image; DINOv2 was trained at 224x224 (16x16 patches).
        Pass e.g. ``(224, 294)`` to keep the 3:4 aspect of 240x320 frames.
    value_range : None or tuple of float (low, high), default=None
        How frames are scaled to [0, 1] before the ImageNet normalisation.
        With ``None`` each sample is scaled by its own minimum and maximum
        over its ``k`` frames (one scaling per sample, so brightness changes
        between its frames are kept), which suits both raw frames in [0, 1]
        and differences to the first frame in [-1, 1]; with ``(low, high)``
        all samples use the same linear map (clipped), e.g. ``(0, 1)`` to
        keep absolute intensities of raw frames. Grey frames (``C = 1``) are
        repeated to three channels.
    local_files_only : bool, default=False
        Passed to ``from_pretrained`` for a model id: True never tries the
        network (the environment variable ``HF_HUB_OFFLINE=1`` does the
        same).
    dtype : {"float32", "float16", "bfloat16"} or one of those torch.dtype, default="float32"
        Precision of the backbone's computation (half precision mainly
        pays on a GPU). The output is float32.
    memory : None, str or object with the joblib.Memory interface, default=None
        Cache each sample's embeddings here (a folder, or a
        :class:`joblib.Memory`), keyed by the parameters that change them
        (the backbone's weights included) and a hash of the sample's frames,
        so that a later fit or transform on the same frames embeds none of
        them again (the backbone is still loaded in :meth:`fit`). Validated
        as :func:`sklearn.utils.validation.check_memory` validates a
        :class:`~sklearn.pipeline.Pipeline`'s ``memory``. An entry holds the
        row: ``4 n_features_out_`` bytes (6 kB for 4 frames of DINOv2-S).

    Attributes
    ----------
    model_ : torch.nn.Module
        The frozen backbone in eval mode on ``device_``.
    device_ : torch.device
        The device used.
    input_size_ : tuple of int
        ``(height, width)`` the frames are resized to.
    embed_dim_ : int
        Size of one token embedding.
    n_frames_in_ : int
        Number of frames ``k`` per sample seen during :meth:`fit`.
    frame_shape_in_ : tuple of int
        Frame shape ``(H, W, C)`` seen during :meth:`fit`.
    n_features_out_ : int
        ``k * embed_dim_`` (twice that for ``token="cls+mean"``).

    See Also
    --------
    OpticalFlowFeatures : Lucas-Kanade displacements of the same frames.

    Notes
    -----
    The row of one sample is ``[frame 0 features, frame 1 features, ...]``;
    for ``"cls+mean"`` each frame's block is ``[cls, mean]``.
    :meth:`get_feature_names_out` names the columns (``"f0_cls0"``, ...).

    A fitted transformer pickles with its backbone weights (about 90 MB
    for DINOv2-S). One fitted with ``device="cuda"`` needs CUDA to unpickle.

    Examples
    --------
    A tiny randomly initialised backbone (use ``"facebook/dinov2-small"`` or
    a local copy of it for real features):

    >>> import numpy as np
    >>> from transformers import Dinov2Config, Dinov2Model
    >>> from sklearn_hardness.features import DINOv2Features
    >>> backbone = Dinov2Model(Dinov2Config(
    ...     hidden_size=32, num_hidden_layers=1, num_attention_heads=2,
    ...     intermediate_size=64, image_size=28, patch_size=14))
    >>> X = np.random.default_rng(0).random((2, 3, 20, 24, 3), dtype=np.float32)
    >>> dino = DINOv2Features(model=backbone, token="cls+mean", image_size=28)
    >>> dino.fit_transform(X).shape    # 2 samples, 3 frames x (32 + 32)
    (2, 192)
    """

    _parameter_constraints: dict = {
        "model": [str, os.PathLike, torch.nn.Module],
        "token": [StrOptions(set(_TOKENS))],
        "batch_size": [Interval(Integral, 1, None, closed="left")],
        "device": [TorchDevices()],
        "image_size": [
            Interval(Integral, 1, None, closed="left"),
            Pair(Interval(Integral, 1, None, closed="left"), "(height, width)"),
        ],
        "value_range": [None, ValueRange()],
        "local_files_only": ["boolean"],
        "dtype": [StrOptions(set(_DTYPES)), Options(torch.dtype, set(_DTYPES.values()))],
        "memory": [None, str, HasMethods(["cache"])],
    }

    _per_press_input = "frames"
    _per_press_ignored = ("memory", "batch_size")

    def __init__(
        self,
        model="facebook/dinov2-small",
        *,
        token="cls",
        batch_size=32,
        device="cpu",
        image_size=224,
        value_range=None,
        local_files_only=False,
        dtype="float32",
        memory=None,
    ):
        self.model = model
        self.token = token
        self.batch_size = batch_size
        self.device = device
        self.image_size = image_size
        self.value_range = value_range
        self.local_files_only = local_files_only
        self.dtype = dtype
        self.memory = memory

    # --------------------------------------------------------------- sklearn API
    @fit_context(prefer_skip_nested_validation=True)
    def fit(self, X, y=None):
        """Load and freeze the backbone and remember the number and shape of frames.

        Parameters
        ----------
        X : array-like of shape (n_samples, k, H, W, C)
            Selected frames, ``C`` in {1, 3}.
        y : None
            Ignored.

        Returns
        -------
        self : DINOv2Features

        Raises
        ------
        ImportError
            If a model id or directory is given and ``transformers`` is not
            installed.
        OSError
            If the model cannot be loaded (e.g. offline and not cached).
        """
        X = check_frames_array(X, name="X")
        device = _resolve_device(self.device)
        dtype = _resolve_dtype(self.dtype)
        backbone = _load_backbone(self.model, local_files_only=bool(self.local_files_only))
        backbone.requires_grad_(False)
        backbone.eval()
        backbone.to(device=device, dtype=dtype)
        self.model_ = backbone
        self.device_ = device
        patch = _patch_size(backbone)
        self.input_size_ = tuple(max(patch, (s // patch) * patch) for s in _image_size_pair(self.image_size))
        self.n_frames_in_ = int(X.shape[1])
        self.frame_shape_in_ = tuple(int(s) for s in X.shape[2:])
        # One probe frame: finds the embedding size and fails early on a bad module.
        probe = self._embed(torch.zeros((1, 3) + self.input_size_, device=device))
        self.embed_dim_ = int(probe.shape[1] // (2 if self.token == "cls+mean" else 1))
        self.n_features_out_ = self.n_frames_in_ * int(probe.shape[1])
        return self

    def transform(self, X):
        """Embed every frame and concatenate the embeddings of each sample.

        Parameters
        ----------
        X : array-like of shape (n_samples, k, H, W, C)
            Selected frames with the ``k`` and frame shape seen in :meth:`fit`.

        Returns
        -------
        X_out : ndarray of shape (n_samples, n_features_out_), float32
        """
        check_is_fitted(self)
        X = check_frames_array(X, name="X", n_frames=self.n_frames_in_, frame_shape=self.frame_shape_in_)
        return transform_presses(self, X)[0]

    def _transform_presses(self, X):
        n, k = X.shape[:2]
        lo, hi = sample_range(X, self.value_range)
        frames = X.reshape((n * k,) + X.shape[2:])
        sample_of = np.repeat(np.arange(n), k)
        out = np.empty((n * k, self.n_features_out_ // k), dtype=np.float32)
        bs = int(self.batch_size)
        for start in range(0, n * k, bs):
            stop = min(start + bs, n * k)
            s = sample_of[start:stop]
            batch = self._preprocess(frames[start:stop], lo[s], hi[s])
            out[start:stop] = self._embed(batch).float().cpu().numpy()
        return out.reshape(n, -1), {}

    def get_feature_names_out(self, input_features=None):
        """Names of the output columns, e.g. ``"f0_cls0"``, ``"f2_mean31"``.

        Parameters
        ----------
        input_features : None
            Ignored (the input is not tabular).

        Returns
        -------
        names : ndarray of str of shape (n_features_out_,)
        """
        check_is_fitted(self)
        kinds = self.token.split("+")
        return np.asarray(
            [
                f"f{t}_{kind}{d}"
                for t in range(self.n_frames_in_)
                for kind in kinds
                for d in range(self.embed_dim_)
            ],
            dtype=object,
        )

    def __getstate__(self):
        # tensors on a GPU cannot be unpickled where torch has no CUDA: save the frozen
        # backbone's weights on the CPU; __setstate__ moves them back to device_
        state = dict(super().__getstate__())  # a copy: object.__getstate__ may return __dict__ itself
        model = state.get("model_")
        if isinstance(model, torch.nn.Module) and self.device_.type != "cpu":
            state["model_"] = copy.deepcopy(model).cpu()
        return state

    def __setstate__(self, state):
        super().__setstate__(state)
        device = self.__dict__.get("device_")
        if isinstance(self.__dict__.get("model_"), torch.nn.Module) and device is not None and device.type != "cpu":
            if device.type == "cuda" and not torch.cuda.is_available():
                warnings.warn(
                    f"DINOv2Features was fitted on {device} but CUDA is not available here; "
                    "the backbone runs on the CPU (set_params(device='cpu') and refit to silence this).",
                    UserWarning,
                )
                self.device_ = torch.device("cpu")
            self.model_.to(self.device_)

    def __sklearn_tags__(self):
        return frames_tags(super().__sklearn_tags__())

    # ----------------------------------------------------------------- helpers
    def _preprocess(self, frames, lo, hi):
        """(B, H, W, C) float32 frames -> normalised (B, 3, h, w) tensor on the device."""
        dev = self.device_
        x = torch.from_numpy(np.ascontiguousarray(frames)).to(dev).permute(0, 3, 1, 2)
        lo_t = torch.from_numpy(lo).to(dev).view(-1, 1, 1, 1)
        hi_t = torch.from_numpy(hi).to(dev).view(-1, 1, 1, 1)
        x = ((x - lo_t) / (hi_t - lo_t)).clamp_(0.0, 1.0)
        if x.shape[1] == 1:
            x = x.expand(-1, 3, -1, -1)
        if tuple(x.shape[2:]) != self.input_size_:
            x = torch.nn.functional.interpolate(
                x, size=self.input_size_, mode="bilinear", align_corners=False, antialias=True
            )
        mean = torch.tensor(_IMAGENET_MEAN, device=dev).view(1, 3, 1, 1)
        std = torch.tensor(_IMAGENET_STD, device=dev).view(1, 3, 1, 1)
        return (x - mean) / std

    def _embed(self, pixels):
        """Normalised (B, 3, h, w) tensor -> (B, dim) or (B, 2 dim) token features."""
        model = self.model_
        param = next(model.parameters(), None)
        if param is not None:
            pixels = pixels.to(dtype=param.dtype)
        with torch.inference_mode():
            out = model(pixels)
        hidden = _last_hidden(out)
        if hidden.ndim == 2:
            if self.token != "cls":
                raise ValueError(
                    f"The model returns pooled features of shape {tuple(hidden.shape)} (no token "
                    f"sequence), so only token='cls' is possible, not {self.token!r}."
                )
            return hidden
        if hidden.ndim != 3:
            raise ValueError(
                "The model must return a token sequence (B, n_tokens, dim) or pooled features "
                f"(B, dim); got an output of shape {tuple(hidden.shape)}."
            )
        n_reg = int(getattr(getattr(model, "config", None), "num_register_tokens", 0) or 0)
        cls = hidden[:, 0]
        if self.token == "cls":
            return cls
        patches = hidden[:, 1 + n_reg:]
        if patches.shape[1] == 0:
            raise ValueError("The model's output has no patch tokens to average.")
        mean = patches.mean(dim=1)
        return mean if self.token == "mean" else torch.cat([cls, mean], dim=1)


def _last_hidden(out):
    if hasattr(out, "last_hidden_state"):
        return out.last_hidden_state
    if isinstance(out, dict) and "last_hidden_state" in out:
        return out["last_hidden_state"]
    if isinstance(out, (tuple, list)) and len(out) and isinstance(out[0], torch.Tensor):
        return out[0]
    if isinstance(out, torch.Tensor):
        return out
    raise TypeError(
        "The model must return a tensor, a tuple whose first item is a tensor, or an object "
        f"with last_hidden_state; got {type(out).__name__}."
    )


def _resolve_device(device):
    """A device the constraints took (TorchDevices) -> an available torch.device."""
    if isinstance(device, torch.device):
        return device
    if device == "auto":
        return torch.device("cuda" if torch.cuda.is_available() else "cpu")
    dev = torch.device(device)
    if dev.type == "cuda" and not torch.cuda.is_available():
        raise ValueError(f"device={device!r} was asked for but CUDA is not available; use 'cpu' or 'auto'.")
    return dev


def _resolve_dtype(dtype):
    """A dtype name or torch.dtype the constraints took -> the torch.dtype."""
    return dtype if isinstance(dtype, torch.dtype) else _DTYPES[dtype]


def _image_size_pair(image_size):
    size = (image_size, image_size) if isinstance(image_size, Integral) else image_size
    return int(size[0]), int(size[1])


def _patch_size(model):
    patch = getattr(getattr(model, "config", None), "patch_size", 14)
    if isinstance(patch, (tuple, list)):
        patch = patch[0]
    return int(patch)


def _import_transformers():
    try:
        return importlib.import_module("transformers")
    except ImportError as exc:
        raise ImportError(
            "DINOv2Features needs the optional dependency 'transformers' to load a model by name or "
            f"directory: {_INSTALL_HINT}. Alternatively pass an already built torch.nn.Module as model."
        ) from exc


def _offline_hint(model):
    return (
        f"Could not load the DINOv2 backbone {model!r}. Without network access nothing can be "
        "downloaded. Pass model= as either (a) a local directory with config.json and the weights, "
        "made on a machine with internet access by "
        "transformers.Dinov2Model.from_pretrained('facebook/dinov2-small').save_pretrained(DIR) "
        "(or `hf download facebook/dinov2-small --local-dir DIR`), or (b) an already built "
        "torch.nn.Module. If the weights are in the Hugging Face cache, check HF_HOME."
    )


def _load_backbone(model, *, local_files_only):
    """Return a fresh nn.Module for ``model`` (id, directory or module)."""
    if isinstance(model, torch.nn.Module):
        return copy.deepcopy(model)
    if isinstance(model, os.PathLike):
        model = os.fspath(model)
    if not isinstance(model, str):
        raise TypeError(
            "model must be a Hugging Face model id, a local directory or a torch.nn.Module, "
            f"got {type(model).__name__}."
        )
    path = os.path.expanduser(model)
    looks_like_path = (
        os.path.isabs(path) or model.startswith((".", "~")) or model.count("/") > 1 or "\\" in model
    )
    if os.path.isdir(path):
        if not os.path.isfile(os.path.join(path, "config.json")):
            raise OSError(f"The model directory {model!r} has no config.json. " + _offline_hint(model))
        transformers = _import_transformers()
        try:
            return transformers.AutoModel.from_pretrained(path, local_files_only=True)
        except OSError as exc:
            raise OSError(_offline_hint(model) + f" (Loading failed with: {exc})") from exc
    if looks_like_path:
        raise OSError(f"The model directory {model!r} does not exist. " + _offline_hint(model))
    transformers = _import_transformers()
    try:
        return transformers.AutoModel.from_pretrained(model, local_files_only=local_files_only)
    except OSError as exc:
        first = str(exc).strip().splitlines()[0] if str(exc).strip() else type(exc).__name__
        raise OSError(_offline_hint(model) + f" (Hugging Face said: {first})") from exc
