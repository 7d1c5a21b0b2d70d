"""What the nets on selected frames (n, k, H, W, C) share.

* :class:`FramesNetMixin`, mixed in before
  :class:`~sklearn_hardness.models._mc_dropout.MCDropoutClassifierBase` by
  :class:`~sklearn_hardness.models.ConvLSTMClassifier` and
  :class:`~sklearn_hardness.models.ImprintCNNClassifier`: validation of the
  frames, per-channel standardisation statistics, the random transforms of
  training batches (``augment``) and their seeded generator;
* :func:`register_input_buffers`, which keeps the fitted input's shape and
  statistics in the module, so saved parameters and pickles carry them.
"""

from __future__ import annotations

import numpy as np
import torch
from skorch.dataset import unpack_data

from ..utils._random import derived_seeds
from ..utils._tags import frames_tags
from ..utils._validation import check_frames_array
from ._persistence import NetPersistenceMixin

__all__ = ["FramesNetMixin", "register_input_buffers"]


def register_input_buffers(module, in_channels, input_shape=None, input_mean=None, input_scale=None):
    """Register ``input_shape``, ``input_mean`` and ``input_scale`` as buffers of ``module``.

    Parameters
    ----------
    module : torch.nn.Module
        The net being built.
    in_channels : int
        Channels of the frames.
    input_shape : tuple of int or None, default=None
        The (k, H, W, C) seen during fit (None: unknown, stored as -1).
    input_mean, input_scale : sequence of float or None, default=None
        Per-channel statistics; the net standardises its input as
        ``(X - input_mean) / input_scale``. None means 0 and 1.
    """
    shape = torch.tensor(input_shape if input_shape is not None else [-1, -1, -1, in_channels])
    module.register_buffer("input_shape", shape.to(torch.int64))
    mean = torch.zeros(int(in_channels)) if input_mean is None else torch.as_tensor(input_mean)
    scale = torch.ones(int(in_channels)) if input_scale is None else torch.as_tensor(input_scale)
    module.register_buffer("input_mean", mean.to(torch.float32).reshape(-1))
    module.register_buffer("input_scale", scale.to(torch.float32).reshape(-1))


class FramesNetMixin:
    """Frames input, standardisation and training augmentation of an MC-dropout net.

    For a subclass of ``(FramesNetMixin, MCDropoutClassifierBase)`` whose
    parameters include ``standardize`` and ``augment`` and whose module
    registers :func:`register_input_buffers` and ends in a linear ``head``.
    The transforms of :meth:`_training_augmenter` (by default the
    ``augment`` parameter) are applied to every training batch in
    :meth:`train_step_single`, drawn from a generator seeded by
    ``random_state``; prediction and MC-dropout passes never see them.
    """

    _input_meta_attrs = ("n_frames_in_", "frame_shape_", "input_mean_", "input_scale_")
    _generator_attrs = NetPersistenceMixin._generator_attrs + ("augment_generator_",)

    def set_params(self, **kwargs):
        """Set parameters; ``augment__<name>`` sets a parameter of the augmenter.

        skorch keeps every other ``<prefix>__<name>`` key for its own parts
        (``module__``, ``optimizer__``...), so nested augmenter parameters are
        routed here, as scikit-learn does for nested estimators
        (``GridSearchCV(pipe, {"clf__augment__gain": [...]})``).

        Returns
        -------
        self
        """
        nested = {k[len("augment__"):]: kwargs.pop(k) for k in list(kwargs) if k.startswith("augment__")}
        super().set_params(**kwargs)
        if nested:
            if not hasattr(self.augment, "set_params"):
                raise ValueError(
                    f"augment__{next(iter(nested))} was given but augment is {self.augment!r}; "
                    "set augment=FrameAugmenter(...) first."
                )
            self.augment.set_params(**nested)
        return self

    def initialize(self):
        """Validate the parameters, seed the generators (augmentations too) and initialise the net.

        Returns
        -------
        self
        """
        super().initialize()
        seed = self.init_seed_
        # derived from the initial-weight seed, so the other generators' seeds are unchanged
        self.augment_generator_ = (
            None if seed is None else torch.Generator().manual_seed(derived_seeds([seed, 1], 1)[0])
        )
        return self

    def _training_augmenter(self):
        """The object whose ``augment(X, generator)`` transforms training batches, or None."""
        return self.augment

    def _prepare_training(self, X, y):
        super()._prepare_training(X, y)
        augmenter = self._training_augmenter()
        if augmenter is not None and hasattr(augmenter, "check"):
            augmenter.check(self.frame_shape_[-1])

    def train_step_single(self, batch, **fit_params):
        """skorch's step on a batch transformed by the augmenter (when there is one)."""
        augmenter = self._training_augmenter()
        if augmenter is not None:
            Xi, yi = unpack_data(batch)
            Xi = augmenter.augment(torch.as_tensor(Xi), generator=self.augment_generator_)
            batch = (Xi, yi)
        return super().train_step_single(batch, **fit_params)

    def _check_X(self, X, reset):
        if reset:
            X = check_frames_array(X)
            self.n_frames_in_ = int(X.shape[1])
            self.frame_shape_ = tuple(int(s) for s in X.shape[2:])
            return X
        if self.n_frames_in_ is None:  # loaded from parameters without the shape
            X = check_frames_array(X)
            if X.shape[-1] != self.frame_shape_[-1]:
                raise ValueError(
                    f"X has {X.shape[-1]} channel(s) but the net was trained on "
                    f"{self.frame_shape_[-1]}."
                )
            return X
        return check_frames_array(X, n_frames=self.n_frames_in_, frame_shape=self.frame_shape_)

    def _fit_input_stats(self, X):
        C = X.shape[-1]
        if self.standardize:
            flat = X.reshape(-1, C)
            mean = flat.mean(axis=0, dtype=np.float64)
            std = flat.std(axis=0, dtype=np.float64)
            self.input_mean_ = mean.astype(np.float32)
            self.input_scale_ = np.where(std > 0, std, 1.0).astype(np.float32)
        else:
            self.input_mean_ = np.zeros(C, np.float32)
            self.input_scale_ = np.ones(C, np.float32)

    def _input_buffers(self):
        """The module's keyword arguments for :func:`register_input_buffers` (but ``in_channels``)."""
        shape = (self.n_frames_in_ or -1,) + tuple(s if s is not None else -1 for s in self.frame_shape_)
        return {"input_shape": shape, "input_mean": self.input_mean_, "input_scale": self.input_scale_}

    def _meta_from_state_dict(self, state_dict):
        shape = [int(s) for s in state_dict["input_shape"].tolist()]
        self.n_frames_in_ = shape[0] if shape[0] > 0 else None
        self.frame_shape_ = tuple(shape[1:]) if shape[1] > 0 else (None, None, shape[3])
        C = shape[3]
        self.input_mean_ = state_dict.get("input_mean", torch.zeros(C)).numpy().astype(np.float32)
        self.input_scale_ = state_dict.get("input_scale", torch.ones(C)).numpy().astype(np.float32)
        return int(state_dict["head.weight"].shape[0])

    def __sklearn_tags__(self):
        return frames_tags(super().__sklearn_tags__())
