"""Monte-Carlo-dropout sampling: the dropout layer and the batched sampler.

* :class:`MCDropout`, a dropout layer that can draw its masks from a
  :class:`torch.Generator` of its own (so MC sampling and seeded training never
  touch torch's global random number generator), element-wise or one mask per
  channel map;
* :func:`sample_proba`, the batched sampler the classifiers call.

How batched MC sampling works
-----------------------------
A module used with :func:`sample_proba` has a ``forward(X, n_replicas=1)``
method. It computes the deterministic part of the network that precedes its
first active dropout layer once for the ``b`` inputs, then tiles the result
``n_replicas`` times along the batch axis (replica-major: row ``r * b + i`` is
replica ``r`` of input ``i``) and runs the rest of the network on the
``n_replicas * b`` rows in one call. Each row gets its own dropout mask, so one
call gives ``n_replicas`` independent MC passes. Chunks of inputs and replicas
bound the memory of one call.
"""

from __future__ import annotations

import contextlib

import numpy as np
import torch

from ..utils._torch import seeded_torch_rng

__all__ = ["MCDropout", "sample_proba", "softmax"]

#: Bytes of activations one MC forward call may hold, per device type. On CPU
#: small chunks that stay in cache are fastest (benchmarks/bench_mc_dropout.py);
#: a GPU wants big batches.
MC_MEMORY_BUDGET = {"cpu": 32 * 2**20, "cuda": 1024 * 2**20}

#: torch's dropout layers (the public subclasses of its private ``_DropoutNd``)
_DROPOUT_TYPES = (
    torch.nn.Dropout,
    torch.nn.Dropout1d,
    torch.nn.Dropout2d,
    torch.nn.Dropout3d,
    torch.nn.AlphaDropout,
    torch.nn.FeatureAlphaDropout,
)


class MCDropout(torch.nn.Module):
    """Dropout whose masks can come from a dedicated random generator.

    In training mode each element (or, with ``per_channel=True``, each channel
    map) is zeroed with probability ``p`` and the rest are scaled by
    ``1 / (1 - p)`` (inverted dropout, as :class:`torch.nn.Dropout`). In
    evaluation mode the layer is the identity. Masks are drawn from
    ``self.generator`` when it is set (the classifiers set it while training
    with a ``random_state`` and while drawing MC samples) and from torch's
    global generator otherwise.

    Parameters
    ----------
    p : float, default=0.2
        Probability of zeroing an element, in [0, 1).
    per_channel : bool, default=False
        One mask value per sample and channel, shared over the last two
        (spatial) axes and any axes between the batch and the channel axis
        (time): the channel axis is the third from last, as in
        :class:`torch.nn.Dropout2d`. A following spatial average then keeps
        the mask instead of averaging it away.

    Attributes
    ----------
    generator : torch.Generator or None
        Source of the masks; ``None`` means torch's global generator. It is
        not part of the module's state dict and is not pickled.

    Examples
    --------
    >>> import torch
    >>> from sklearn_hardness.models._mc_sampling import MCDropout
    >>> layer = MCDropout(0.5, per_channel=True).train()
    >>> layer.generator = torch.Generator().manual_seed(0)
    >>> out = layer(torch.ones(1, 3, 2, 2))
    >>> sorted(torch.unique(out).tolist()) in ([0.0, 2.0], [0.0], [2.0])
    True
    """

    def __init__(self, p=0.2, per_channel=False):
        super().__init__()
        self.p = float(p)
        self.per_channel = bool(per_channel)
        self.generator = None

    def forward(self, x):
        if not self.training or self.p == 0:
            return x
        keep = 1.0 - self.p
        shape = x.shape
        if self.per_channel:
            shape = x.shape[:1] + (1,) * (x.dim() - 4) + (x.shape[-3], 1, 1)
        # U < keep with U ~ Uniform[0, 1) is Bernoulli(keep); on CPU faster than
        # Tensor.bernoulli_ (benchmarks/bench_mc_dropout.py).
        # out of place: under torch.func.vmap (StackedConvLSTMNet) the in-place lt_ has no
        # batching rule and falls back to a slow loop
        mask = torch.rand(shape, generator=self.generator, device=x.device, dtype=x.dtype)
        return x * mask.lt(keep).to(x.dtype).mul_(1.0 / keep)

    def extra_repr(self):
        return f"p={self.p}, per_channel={self.per_channel}"

    def __setstate__(self, state):
        state.setdefault("per_channel", False)  # pickles from before per_channel existed
        super().__setstate__(state)

    def __getstate__(self):
        state = self.__dict__.copy()
        state["generator"] = None  # a generator is run-time state, never saved
        return state


def softmax(logits):
    """Softmax over the last axis in float32 (or wider), numerically stable.

    Same values as :func:`torch.softmax`, but several times faster on CPU for
    the few classes (< 32) of these nets, which matters for MC sampling.
    """
    x = logits if logits.dtype in (torch.float32, torch.float64) else logits.float()
    e = (x - x.amax(dim=-1, keepdim=True)).exp_()
    return e.div_(e.sum(dim=-1, keepdim=True))


@contextlib.contextmanager
def dropout_generator(module, generator):
    """Temporarily make every :class:`MCDropout` of ``module`` use ``generator``."""
    if generator is None:
        yield
        return
    layers = [m for m in module.modules() if isinstance(m, MCDropout)]
    old = [m.generator for m in layers]
    for m in layers:
        m.generator = generator
    try:
        yield
    finally:
        for m, g in zip(layers, old):
            m.generator = g


def _is_dropout(m):
    return isinstance(m, (MCDropout,) + _DROPOUT_TYPES)


def sample_proba(module, X, *, n_samples, seed, rows_per_call, device, nonlinearity, n_classes):
    """``n_samples`` MC-dropout passes of ``module`` over ``X``, batched.

    Every dropout layer is on and everything else in evaluation mode; the
    module's ``training`` flags and torch's global random generator are the
    same afterwards.

    Parameters
    ----------
    module : torch.nn.Module
        Has ``forward(X, n_replicas=1)`` (see the module docstring).
    X : ndarray
        Validated input.
    n_samples : int
        Number of passes.
    seed : int
        Seed of the dropout masks.
    rows_per_call : int
        Most rows (inputs x replicas) per forward call.
    device : torch.device
    nonlinearity : callable
        Logits to probabilities.
    n_classes : int

    Returns
    -------
    proba : ndarray of shape (n_samples, len(X), n_classes), float32
        ``None`` when the module has no active dropout (every pass would equal
        the deterministic prediction).
    """
    if not any(_is_dropout(m) and m.p > 0 for m in module.modules()):
        return None
    n = len(X)
    b = max(1, min(n, rows_per_call // n_samples))  # inputs per chunk
    r = max(1, min(n_samples, rows_per_call // b))  # replicas per chunk
    gen = torch.Generator(device=device).manual_seed(seed)
    out = np.empty((n_samples, n, n_classes), dtype=np.float32)
    # torch's own dropout layers draw from the global generator: seed a forked copy
    plain_dropout = any(isinstance(m, _DROPOUT_TYPES) for m in module.modules())
    flags = [(m, m.training) for m in module.modules()]
    try:
        module.eval()
        for m in module.modules():
            if _is_dropout(m):
                m.training = True
        seeded = seeded_torch_rng(seed, device) if plain_dropout else contextlib.nullcontext()
        with seeded, dropout_generator(module, gen), torch.inference_mode():
            for i0 in range(0, n, b):
                xb = torch.as_tensor(X[i0 : i0 + b]).to(device)
                for j0 in range(0, n_samples, r):
                    rr = min(r, n_samples - j0)
                    proba = nonlinearity(module(xb, n_replicas=rr)).reshape(rr, len(xb), n_classes)
                    out[j0 : j0 + rr, i0 : i0 + len(xb)] = proba.cpu().numpy()
    finally:
        for m, flag in flags:
            m.training = flag
    return out
