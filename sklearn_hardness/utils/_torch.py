"""Torch helpers shared by the nets: the device ``"auto"`` and seeded sections of torch's global generator."""

from __future__ import annotations

import contextlib
import threading

import torch

__all__ = ["GLOBAL_TORCH_RNG_LOCK", "resolve_device", "seeded_torch_rng"]

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


def resolve_device(device):
    """Map ``"auto"`` to ``"cuda"`` when a GPU is available, else ``"cpu"``."""
    if isinstance(device, str) and device == "auto":
        return "cuda" if torch.cuda.is_available() else "cpu"
    return device
