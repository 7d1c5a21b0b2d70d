"""K independent nets stepped as one: :class:`StackedConvLSTMNet`.

The members' parameters and buffers are stacked along a new leading axis
(:func:`torch.func.stack_module_state`) and one forward call runs every
member with :func:`torch.func.vmap` over :func:`torch.func.functional_call`
of a weightless copy of the net (its template, kept on the ``meta`` device).
The members stay independent: each has its own weights, its own dropout
masks (``vmap(..., randomness="different")``) and, with one element-wise
optimiser such as :class:`torch.optim.Adam` over the stacked parameters, its
own optimiser state. Small nets then make calls K times larger, which is
what a GPU (launch-bound on one small net) and small CPU calls need.

Only torch is imported here (no skorch), so benchmarks can use it on
machines without skorch.
"""

from __future__ import annotations

import copy
import numbers

import torch
from torch.func import functional_call, stack_module_state, vmap

from ..utils._random import draw_seeds
from ..utils._torch import seeded_torch_rng

__all__ = ["StackedConvLSTMNet"]

_SEP = "__"


def _flat(name):
    return name.replace(".", _SEP)


class StackedConvLSTMNet(torch.nn.Module):
    """K independent copies of a net (e.g. the ConvLSTM of :class:`ConvLSTMClassifier`) trained and run as one module.

    Parameter ``p`` of member ``k`` is row ``k`` of the stacked parameter
    (shape ``(K,) + p.shape``; the dots of its name become ``__``). A forward
    call runs all members on their own inputs (``X`` of shape ``(K, B, ...)``)
    or on one shared input (``shared_input=True``), each with its own dropout
    masks: the result equals K separate forward calls up to float rounding,
    in one batched call per layer (grouped convolutions and batched matrix
    products under :func:`torch.func.vmap`).

    Training: sum the members' losses (:meth:`member_losses` gives them)
    before ``backward``, so member ``k``'s gradient is the gradient of its own
    loss (a mean would divide it by K). An element-wise optimiser over
    :meth:`~torch.nn.Module.parameters` (Adam, AdamW, SGD with momentum, RMSprop) then keeps
    per-element state, which is exactly K optimisers of K separate nets
    stepped together. Optimisers or steps that mix elements (gradient-norm
    clipping over all parameters, LBFGS) are not per member.

    Parameters
    ----------
    nets : sequence of torch.nn.Module
        The members: modules of one class with the same parameter and buffer
        names and shapes (e.g. ``ConvLSTMNet``, the default ``module`` of
        :class:`ConvLSTMClassifier`, built with the same
        arguments). Their current weights are copied; the nets themselves are
        not kept. Their ``forward(X, n_replicas=1)`` is called per member.

    Attributes
    ----------
    n_members : int
        Number of members K.
    generator : torch.Generator or None
        When set, the dropout masks of a training-mode forward call are
        reproducible: each call draws a seed from it and runs with torch's
        global generator forked and seeded with it. ``None`` (default): masks
        from torch's global generator. Not saved in pickles.

    See Also
    --------
    ConvLSTMClassifier : whose net (``module_``) is the usual member.
    EnsembleClassifier : trains identically configured ConvLSTM members as
        one stacked net (``stacked=True``).

    Notes
    -----
    Dropout masks come from vmap's ``randomness="different"``, so they are
    independent between members (and rows) but are not the masks K separate
    nets would draw from their own generators: with dropout a stacked run is
    statistically, not bitwise, the same as separate runs. Without dropout
    (``dropout=0`` or evaluation mode) stacked and separate nets agree to
    float tolerance (``tests/test_models_stacked.py``).

    Examples
    --------
    >>> import torch
    >>> from sklearn_hardness.models._stacked import StackedConvLSTMNet
    >>> stacked = StackedConvLSTMNet.from_seeds(3, [0, 1, 2], in_channels=1, n_classes=2, filters=(2,))
    >>> X = torch.randn(3, 4, 2, 6, 8, 1)  # (members, batch, frames, H, W, C)
    >>> stacked(X).shape
    torch.Size([3, 4, 2])
    >>> len(stacked.unstack())
    3
    """

    def __init__(self, nets):
        super().__init__()
        nets = list(nets)
        if not nets or not all(isinstance(n, torch.nn.Module) for n in nets):
            raise ValueError("nets must be a non-empty sequence of torch.nn.Module instances.")
        cls = type(nets[0])
        if any(type(n) is not cls for n in nets[1:]):
            raise ValueError(f"every member must be a {cls.__name__}, got {sorted({type(n).__name__ for n in nets})}.")
        shapes = [{k: tuple(v.shape) for k, v in n.state_dict().items()} for n in nets]
        if any(s != shapes[0] for s in shapes[1:]):
            raise ValueError("the members' parameters and buffers differ in names or shapes: build them alike.")
        params, buffers = stack_module_state(nets)
        self._param_names = tuple(params)
        self._buffer_names = tuple(buffers)
        flat = [_flat(n) for n in self._param_names + self._buffer_names]
        if len(set(flat)) != len(flat):
            raise ValueError("parameter names of the members collide once their dots are replaced.")
        for name, value in params.items():
            self.register_parameter(_flat(name), torch.nn.Parameter(value.detach().clone()))
        for name, value in buffers.items():
            self.register_buffer(_flat(name), value.detach().clone())
        template = copy.deepcopy(nets[0]).to("meta")
        for m in template.modules():
            if hasattr(m, "generator"):
                m.generator = None  # masks come from vmap's randomness, see forward
        # not a registered submodule: .to(), parameters() and state_dict() ignore it
        object.__setattr__(self, "_template", template)
        self.n_members = len(nets)
        self.generator = None
        self.train(nets[0].training)

    @classmethod
    def from_seeds(cls, n_members, seeds, net_cls=None, **net_kwargs):
        """K members built as separate nets with those seeds would be.

        Member ``k`` is ``net_cls(**net_kwargs)`` built with torch's global
        generator seeded with ``seeds[k]`` (and restored afterwards), which is
        how :class:`ConvLSTMClassifier` builds its module from its seed: the
        same initial weights, not only the same distribution.

        Parameters
        ----------
        n_members : int
            Number of members K.
        seeds : sequence of int, int, RandomState instance or None
            K seeds, or a ``random_state`` from which K seeds are drawn.
        net_cls : torch.nn.Module class or None, default=None
            The member's class; ``None`` means ``ConvLSTMNet``, the default
            ``module`` of :class:`ConvLSTMClassifier`.
        **net_kwargs
            Arguments of ``net_cls``.

        Returns
        -------
        stacked : StackedConvLSTMNet
        """
        if isinstance(n_members, bool) or not isinstance(n_members, numbers.Integral) or n_members < 1:
            raise ValueError(f"n_members must be a positive int, got {n_members!r}.")
        if seeds is None or isinstance(seeds, numbers.Integral) or hasattr(seeds, "randint"):
            seeds = draw_seeds(seeds, int(n_members))
        seeds = [int(s) for s in seeds]
        if len(seeds) != n_members:
            raise ValueError(f"got {len(seeds)} seeds for {n_members} members.")
        if net_cls is None:
            from ._convlstm import ConvLSTMNet as net_cls
        nets = []
        for s in seeds:
            with seeded_torch_rng(s):
                nets.append(net_cls(**net_kwargs))
        return cls(nets)

    # ------------------------------------------------------------------
    def _stacked(self):
        params = {n: getattr(self, _flat(n)) for n in self._param_names}
        buffers = {n: getattr(self, _flat(n)) for n in self._buffer_names}
        return params, buffers

    def train(self, mode=True):
        """Set training mode of this module and of the members' template (dropout on/off)."""
        super().train(mode)
        self._template.train(mode)
        return self

    def forward(self, X, n_replicas=1, shared_input=False):
        """Logits of every member: shape ``(K, n_replicas * B, n_classes)``.

        Parameters
        ----------
        X : torch.Tensor
            ``(K, B, ...)``: member ``k`` runs on ``X[k]``; with
            ``shared_input=True``, ``(B, ...)`` run by every member.
        n_replicas : int, default=1
            Passed to each member's ``forward`` (MC passes, replica-major).
        shared_input : bool, default=False
            Whether all members take the same ``X``.

        Returns
        -------
        logits : torch.Tensor
        """
        if not shared_input and X.shape[0] != self.n_members:
            raise ValueError(
                f"X has {X.shape[0]} rows on its first axis but the net has {self.n_members} members; "
                "pass shared_input=True to run every member on the same X."
            )
        params, buffers = self._stacked()
        template = self._template

        def one(p, b, x):
            return functional_call(template, (p, b), (x,), {"n_replicas": n_replicas})

        call = vmap(one, in_dims=(0, 0, None if shared_input else 0), randomness="different")
        if self.training and self.generator is not None:
            seed = int(torch.randint(0, 2**62, (1,), generator=self.generator))
            with seeded_torch_rng(seed, X.device):
                return call(params, buffers, X)
        return call(params, buffers, X)

    @staticmethod
    def member_losses(logits, y, weight=None):
        """Mean cross-entropy of each member: shape ``(K,)``.

        Equals ``torch.nn.functional.cross_entropy(logits[k], y[k], weight)``
        per member (a class-weighted mean when ``weight`` is given, as
        :class:`torch.nn.CrossEntropyLoss`). Sum them (not mean) before
        ``backward``.

        Parameters
        ----------
        logits : torch.Tensor of shape (K, B, n_classes)
        y : torch.Tensor of shape (K, B) or (B,)
            Class indices; ``(B,)`` is the same labels for every member.
        weight : torch.Tensor of shape (n_classes,) or None, default=None

        Returns
        -------
        losses : torch.Tensor of shape (K,)
        """
        K, B, C = logits.shape
        y = y.expand(K, B) if y.dim() == 1 else y
        losses = torch.nn.functional.cross_entropy(logits.reshape(K * B, C), y.reshape(-1), reduction="none")
        losses = losses.reshape(K, B)
        if weight is None:
            return losses.mean(dim=1)
        w = weight.to(logits.dtype)[y]
        return (losses * w).sum(dim=1) / w.sum(dim=1)

    def unstack(self):
        """K ordinary nets with the members' current weights and buffers.

        Returns
        -------
        nets : list of torch.nn.Module
            Independent modules (copies, on this module's device and with its
            dtype, in its training mode).
        """
        nets = []
        for k in range(self.n_members):
            state = {n: t.clone() for n, t in self.member_state_dict(k).items()}
            net = copy.deepcopy(self._template)  # on "meta": assign takes the copies' device and dtype
            net.load_state_dict(state, assign=True)
            nets.append(net.train(self.training))
        return nets

    def member_state_dict(self, k):
        """The state dict of member ``k``, as its net would have (views of the stacked tensors).

        Parameters
        ----------
        k : int

        Returns
        -------
        state_dict : dict of str to torch.Tensor
        """
        params, buffers = self._stacked()
        return {n: t[k].detach() for n, t in {**params, **buffers}.items()}

    def extra_repr(self):
        return f"n_members={self.n_members}, member={type(self._template).__name__}"

    def __getstate__(self):
        state = self.__dict__.copy()
        state["generator"] = None  # run-time state, as MCDropout's
        return state
