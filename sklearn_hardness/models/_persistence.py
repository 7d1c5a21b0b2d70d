"""Saving and loading the MC-dropout nets.

* :class:`SavedGenerator`: a seeded ``torch.Generator`` pickled as (device
  type, seed, state), so a net trained on a GPU unpickles on a CPU-only
  machine (a pickled CUDA generator cannot be loaded without CUDA);
* :class:`NetPersistenceMixin`: pickling through it, and ``load_params``
  that works on a fresh net (``torch.load(..., weights_only=True)``; the input
  metadata is read from the saved parameters).
"""

from __future__ import annotations

import numpy as np
import torch

from ..utils._torch import resolve_device

__all__ = ["SavedGenerator", "NetPersistenceMixin"]


class SavedGenerator(tuple):
    """A pickled torch.Generator: device type, initial seed, state (a CPU byte tensor)."""

    def __new__(cls, device_type, seed, gen_state):
        return super().__new__(cls, (device_type, seed, gen_state))

    def __getnewargs__(self):
        return tuple(self)

    def restore(self, device):
        device_type, seed, gen_state = self
        gen = torch.Generator(device=device).manual_seed(seed)
        if device.type == device_type:
            gen.set_state(gen_state)  # same kind of device: continue exactly where it stopped
        return gen


class NetPersistenceMixin:
    """Pickling and ``load_params`` for :class:`MCDropoutClassifierBase` (before skorch's net in the MRO)."""

    # The seeded generators are saved as (device type, seed, state) rather than as
    # torch.Generator objects: a CUDA generator cannot be unpickled where torch has no
    # CUDA, so a net trained on a GPU could not be loaded on a CPU-only machine.
    _generator_attrs = ("shuffle_generator_", "dropout_generator_")

    def __getstate__(self):
        state = super().__getstate__()
        for name in self._generator_attrs:
            gen = state.get(name)
            if isinstance(gen, torch.Generator):
                state[name] = SavedGenerator(gen.device.type, int(gen.initial_seed()), gen.get_state())
        return state

    def __setstate__(self, state):
        raw = state.get("device")
        state["device"] = resolve_device(raw)
        super().__setstate__(state)
        if raw == "auto":
            self.__dict__["device"] = raw
        for name in self._generator_attrs:
            saved = self.__dict__.get(name)
            if isinstance(saved, SavedGenerator):
                # the shuffling and augmentation generators are CPU ones; the dropout masks'
                # lives on the net's device, which skorch has just mapped to the CPU if CUDA is
                # missing here
                device = torch.device(self.device) if name == "dropout_generator_" else torch.device("cpu")
                self.__dict__[name] = saved.restore(device)

    def load_params(self, f_params=None, *args, **kwargs):
        """Load saved parameters (``torch.load(..., weights_only=True)``).

        Works on a fresh net (after ``initialize()`` or not): the input
        metadata (input size, and for the ConvLSTM the input statistics) is
        read from the saved parameters; pass ``classes=[...]`` to the
        constructor to get the original labels back (otherwise ``classes_``
        is ``0..n_classes-1``). See :meth:`skorch.NeuralNet.load_params` for
        the other arguments.

        Returns
        -------
        self
        """
        raw_device = self.__dict__.get("device")
        fresh = not (getattr(self, "initialized_", False) and self._has_input_meta())
        if fresh and f_params is not None and not kwargs.get("use_safetensors"):
            pos = f_params.tell() if hasattr(f_params, "tell") else None
            state = torch.load(f_params, map_location="cpu", weights_only=True)
            if pos is not None:
                f_params.seek(pos)
            if not getattr(self, "initialized_", False):
                self.initialize()
            n_classes = self._meta_from_state_dict(state)
            if self.classes is None:
                self.classes_inferred_ = np.arange(n_classes)
            elif len(self.classes) != n_classes:
                raise ValueError(
                    f"The saved parameters have {n_classes} classes but classes has "
                    f"{len(self.classes)} labels."
                )
            self._rebuild()
        super().load_params(f_params, *args, **kwargs)
        if raw_device == "auto":
            self.__dict__["device"] = raw_device
        return self
