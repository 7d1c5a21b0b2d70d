"""Torch helpers shared by the nets: the device ``"auto"`` and seeded sections of torch's global generator."""

from __future__ import annotations

import contextlib
import threading

import torch

from ._param_validation import _Constraint

__all__ = ["GLOBAL_TORCH_RNG_LOCK", "TorchDevices", "resolve_device", "seeded_torch_rng"]

#: Seeding torch's *global* generator (fork_rng + manual_seed) is process-wide: two
#: threads doing it at once (joblib's threading backend, a Dask cluster of threads)
#: would draw from each other's seeds. Every such section holds this lock.
GLOBAL_TORCH_RNG_LOCK = threading.RLock()


@contextlib.contextmanager
def seeded_torch_rng(seed, device=None):
    """Run a block with torch's global generator seeded with ``seed``, restored afterwards.

    Holds :data:`GLOBAL_TORCH_RNG_LOCK`, so other threads cannot reseed the
    generator meanwhile. ``device``: a CUDA device whose generator is forked
    (and seeded) too; CPU only otherwise.
    """
    device = None if device is None else torch.device(device)
    devices = [device] if device is not None and device.type == "cuda" else []
    with GLOBAL_TORCH_RNG_LOCK, torch.random.fork_rng(devices=devices):
        torch.manual_seed(seed)
        yield


class TorchDevices(_Constraint):
    """The constraint of a ``device`` parameter: ``"auto"``, a device string torch takes, or a :class:`torch.device`.

    ``"cpu"``, ``"cuda"``, ``"cuda:1"``, ``"mps"``...: what :class:`torch.device` parses, whether or
    not that device is present here (a missing GPU is another error, raised where it is used).

    Examples
    --------
    >>> from sklearn_hardness.utils._torch import TorchDevices
    >>> [TorchDevices().is_satisfied_by(d) for d in ("auto", "cuda:1", "gpu", "", 0)]
    [True, True, False, False, False]
    """

    def is_satisfied_by(self, val):
        if isinstance(val, torch.device) or (isinstance(val, str) and val == "auto"):
            return True
        if not isinstance(val, str):
            return False
        try:
            torch.device(val)
        except (RuntimeError, ValueError):
            return False
        return True

    def __str__(self):
        return "'cpu', 'cuda', 'auto', a torch device string or a torch.device"

    def _invalid_value(self):  # for generate_invalid_param_val
        return "not a device"

    def _valid_value(self):  # for generate_valid_param
        return "cpu"


def resolve_device(device):
    """Map ``"auto"`` to ``"cuda"`` when a GPU is available, else ``"cpu"``."""
    if isinstance(device, str) and device == "auto":
        return "cuda" if torch.cuda.is_available() else "cpu"
    return device
