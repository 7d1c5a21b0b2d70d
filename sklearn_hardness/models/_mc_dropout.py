"""Monte-Carlo dropout machinery shared by the classifiers.

This module holds

* :class:`MCDropout`, a dropout layer that can draw its masks from a
  :class:`torch.Generator` of its own, so Monte-Carlo sampling and seeded
  training never touch torch's global random number generator;
* :class:`MCDropoutClassifierBase`, a :class:`skorch.NeuralNetClassifier`
  with the behaviour all three classifiers share: label encoding (any
  hashable labels), input validation, seeding through ``random_state``,
  ``dropout`` as a plain parameter, ``device="auto"``, the training loss
  after fit, and the batched :meth:`~MCDropoutClassifierBase.predict_proba_samples`.

How batched MC sampling works
-----------------------------
A module used with :class:`MCDropoutClassifierBase` has a ``forward(X,
n_replicas=1)`` method. It computes the deterministic part of the network
that precedes the first dropout layer once for the ``b`` inputs, then tiles
the result ``n_replicas`` times along the batch axis (replica-major: row
``r * b + i`` is replica ``r`` of input ``i``) and runs the rest of the
network on the ``n_replicas * b`` rows in one call. Each row gets its own
dropout mask, so one call gives ``n_replicas`` independent MC passes; the
output is reshaped to ``(n_replicas, b, n_classes)``. Chunks of inputs and
replicas bound the memory of one call.
"""

from __future__ import annotations

import contextlib
import numbers
import threading

import numpy as np
import torch
from skorch import NeuralNet, NeuralNetClassifier
from sklearn.utils import check_random_state
from sklearn.utils.validation import check_consistent_length, column_or_1d

from ..utils._validation import check_positive_int

__all__ = ["MCDropout", "MCDropoutClassifierBase"]

# Seeding torch's *global* generator (fork_rng + manual_seed) is process-wide: two
# threads doing it at once (joblib's threading backend, a Dask cluster of threads)
# would draw from each other's seeds. Every such section holds this lock.
_GLOBAL_RNG_LOCK = threading.RLock()

#: Bytes of activations one MC forward call may hold, per device type (the
#: default chunk size of :meth:`MCDropoutClassifierBase.predict_proba_samples`
#: is derived from it). On CPU small chunks that stay in cache are fastest
#: (measured in benchmarks/bench_mc_dropout.py); a GPU wants big batches.
MC_MEMORY_BUDGET = {"cpu": 32 * 2**20, "cuda": 1024 * 2**20}


class MCDropout(torch.nn.Module):
    """Dropout whose masks can come from a dedicated random generator.

    In training mode each element is zeroed with probability ``p`` and the
    rest are scaled by ``1 / (1 - p)`` (inverted dropout, as
    :class:`torch.nn.Dropout`). In evaluation mode the layer is the identity.
    Masks are drawn from ``self.generator`` when it is set (the classifiers
    set it while training with a ``random_state`` and while drawing MC
    samples) and from torch's global generator otherwise.

    Parameters
    ----------
    p : float, default=0.2
        Probability of zeroing an element, in [0, 1).

    Attributes
    ----------
    generator : torch.Generator or None
        Source of the masks; ``None`` means torch's global generator. It is
        not part of the module's state dict.
    """

    def __init__(self, p=0.2):
        super().__init__()
        self.p = _check_dropout(p)
        self.generator = None

    def forward(self, x):
        if not self.training or self.p == 0:
            return x
        keep = 1.0 - self.p
        # U < keep with U ~ Uniform[0, 1) is Bernoulli(keep); on CPU this is about
        # 3x faster than Tensor.bernoulli_ (benchmarks/bench_mc_dropout.py).
        mask = torch.rand(x.shape, generator=self.generator, device=x.device, dtype=x.dtype)
        return x * mask.lt_(keep).mul_(1.0 / keep)

    def extra_repr(self):
        return f"p={self.p}"

    def __getstate__(self):
        state = self.__dict__.copy()
        state["generator"] = None  # a generator is run-time state, never saved
        return state


def _check_dropout(p):
    if isinstance(p, bool) or not isinstance(p, numbers.Real) or not (0.0 <= p < 1.0):
        raise ValueError(f"dropout must be a float in [0, 1), got {p!r}.")
    return float(p)


def softmax(logits):
    """Softmax over the last axis in float32 (or wider), numerically stable.

    Same values as :func:`torch.softmax`, but several times faster on CPU for
    the few classes (< 32) of these nets, which matters for MC sampling.
    """
    x = logits if logits.dtype in (torch.float32, torch.float64) else logits.float()
    e = (x - x.amax(dim=-1, keepdim=True)).exp_()
    return e.div_(e.sum(dim=-1, keepdim=True))


def resolve_device(device):
    """Map ``"auto"`` to ``"cuda"`` when a GPU is available, else ``"cpu"``."""
    if isinstance(device, str) and device == "auto":
        return "cuda" if torch.cuda.is_available() else "cpu"
    return device


class MCDropoutClassifierBase(NeuralNetClassifier):
    """Base class of the MC-dropout classifiers (not for direct use).

    Subclasses define ``_check_X(X, reset)`` (validate input, remember its
    shape when ``reset``), ``_module_defaults()`` (keyword arguments of the
    module derived from the fitted data and parameters),
    ``_meta_from_state_dict(state_dict)`` (restore the input metadata from
    saved parameters) and ``_mc_bytes_per_row(X)`` (activation memory of one
    forward row, for chunking).
    """

    def __init__(
        self,
        module,
        *,
        dropout=0.2,
        random_state=None,
        criterion=torch.nn.CrossEntropyLoss,
        optimizer=torch.optim.Adam,
        lr=1e-3,
        max_epochs=50,
        batch_size=32,
        train_split=None,
        classes=None,
        verbose=0,
        device="cpu",
        **kwargs,
    ):
        kwargs.setdefault("iterator_train__shuffle", True)
        super().__init__(
            module,
            criterion=criterion,
            optimizer=optimizer,
            lr=lr,
            max_epochs=max_epochs,
            batch_size=batch_size,
            train_split=train_split,
            classes=classes,
            verbose=verbose,
            device=device,
            **kwargs,
        )
        self.dropout = dropout
        self.random_state = random_state

    # ------------------------------------------------------------------
    # device="auto": the parameter keeps what the user passed, skorch sees
    # the resolved device.
    @property
    def device(self):
        return resolve_device(self.__dict__.get("device", "cpu"))

    @device.setter
    def device(self, value):
        self.__dict__["device"] = value

    def get_params(self, deep=True, **kwargs):
        params = super().get_params(deep=deep, **kwargs)
        if "device" in self.__dict__:
            params["device"] = self.__dict__["device"]
        return params

    def __setstate__(self, state):
        raw = state.get("device")
        state["device"] = resolve_device(raw)
        super().__setstate__(state)
        if raw == "auto":
            self.__dict__["device"] = raw

    def set_params(self, **kwargs):
        super().set_params(**kwargs)
        if "dropout" in kwargs and getattr(self, "initialized_", False) and hasattr(self, "module_"):
            p = _check_dropout(kwargs["dropout"])
            for m in self.module_.modules():
                if isinstance(m, MCDropout):
                    m.p = p
        return self

    # ------------------------------------------------------------------
    # initialisation and seeding
    def initialize(self):
        """Initialise module, criterion, optimizer and the random generators.

        With an integer ``random_state`` the initial weights, the shuffling
        of training batches and the dropout masks during training are
        reproducible, and torch's global random generator is left untouched.
        """
        if self.random_state is None:
            self.init_seed_ = None
            self.shuffle_generator_ = None
            self.dropout_generator_ = None
        else:
            rs = check_random_state(self.random_state)
            init_seed, shuffle_seed, dropout_seed = (int(s) for s in rs.randint(0, 2**31 - 1, size=3))
            self.init_seed_ = init_seed
            self.shuffle_generator_ = torch.Generator().manual_seed(shuffle_seed)
            self.dropout_generator_ = torch.Generator(device=torch.device(self.device)).manual_seed(
                dropout_seed
            )
        return super().initialize()

    def initialize_module(self):
        """Build the module from the fitted input shape and the parameters."""
        if not self._has_input_meta():
            raise ValueError(
                f"{type(self).__name__} infers the size of its network from the data: call "
                "fit(X, y) (or load_params on a fresh net), not initialize() on its own."
            )
        kwargs = self._module_defaults()
        kwargs.update(self.get_params_for("module"))
        if "dropout" in kwargs:
            kwargs["dropout"] = _check_dropout(kwargs["dropout"])
        module_cls = self.module if isinstance(self.module, type) else type(self.module)
        seed = getattr(self, "init_seed_", None)
        if seed is None:
            module = module_cls(**kwargs)
        else:
            with _GLOBAL_RNG_LOCK, torch.random.fork_rng(devices=[]):
                torch.manual_seed(seed)
                module = module_cls(**kwargs)
        self.module_ = module
        return self

    def _get_predict_nonlinearity(self):
        # skorch's "auto" gives torch.softmax for CrossEntropyLoss; ours gives the same
        # values (float32 at least) faster for few classes.
        if isinstance(self.predict_nonlinearity, str) and self.predict_nonlinearity == "auto":
            self.check_is_fitted()
            if isinstance(self.criterion_, torch.nn.CrossEntropyLoss):
                return softmax
        return super()._get_predict_nonlinearity()

    def get_iterator(self, dataset, training=False):
        """Like skorch's, but seeded shuffling when ``random_state`` is set."""
        if training:
            kwargs = self.get_params_for("iterator_train")
            iterator = self.iterator_train
            gen = getattr(self, "shuffle_generator_", None)
            if gen is not None and kwargs.get("shuffle") and "generator" not in kwargs:
                kwargs["generator"] = gen
        else:
            kwargs = self.get_params_for("iterator_valid")
            iterator = self.iterator_valid
        kwargs.setdefault("batch_size", self.batch_size)
        if kwargs["batch_size"] == -1:
            kwargs["batch_size"] = len(dataset)
        return iterator(dataset, **kwargs)

    def train_step(self, batch, **fit_params):
        """skorch's train step, with dropout masks from the seeded generator."""
        gen = getattr(self, "dropout_generator_", None)
        if gen is not None and gen.device != torch.device(self.device):
            gen = self.dropout_generator_ = torch.Generator(device=torch.device(self.device)).manual_seed(
                int(gen.initial_seed())
            )
        with _dropout_generator(self.module_, gen):
            return super().train_step(batch, **fit_params)

    # ------------------------------------------------------------------
    # data validation and labels
    def check_data(self, X, y=None):
        # Labels are validated and encoded in fit/partial_fit; skorch's own
        # check would overwrite classes_ with the encoded labels.
        pass

    def _has_input_meta(self):
        raise NotImplementedError

    def _check_X(self, X, reset):
        raise NotImplementedError

    def _module_defaults(self):
        raise NotImplementedError

    def _meta_from_state_dict(self, state_dict):
        raise NotImplementedError

    def _mc_bytes_per_row(self, X):
        raise NotImplementedError

    def _validate_training_data(self, X, y, *, reset, classes=None):
        if y is None:
            raise ValueError(f"{type(self).__name__} needs labels y for training, got y=None.")
        X = self._check_X(X, reset=reset)
        y = np.asarray(y)
        if y.ndim == 2 and y.shape[1] == 1:
            y = y.ravel()
        if y.ndim != 1:
            raise ValueError(f"y must be a 1-D array of labels, got shape {y.shape}.")
        y = column_or_1d(y)
        check_consistent_length(X, y)
        if y.dtype.kind == "f" and not np.isfinite(y).all():
            raise ValueError("y contains NaN or infinite labels.")
        if reset:
            if self.classes is not None:
                cls = np.asarray(self.classes)
            elif classes is not None:
                cls = np.asarray(classes)
            else:
                cls = np.unique(y)
            if cls.ndim != 1 or len(np.unique(cls)) != len(cls):
                raise ValueError(f"classes must be a 1-D list of distinct labels, got {cls!r}.")
            if len(cls) < 2:
                raise ValueError(
                    f"{type(self).__name__} needs at least 2 classes, got {len(cls)} "
                    f"({cls.tolist()}); pass classes=[...] to declare all labels."
                )
            self.classes_inferred_ = cls
        return X, self._encode(y)

    def _encode(self, y):
        cls = np.asarray(self.classes_)
        try:
            sorter = np.argsort(cls)
            pos = np.searchsorted(cls, y, sorter=sorter)
            pos = sorter[np.clip(pos, 0, len(cls) - 1)]
            known = cls[pos] == y
        except TypeError as exc:
            raise ValueError(
                f"y has labels of type {y.dtype} that cannot be compared with the classes "
                f"{cls.tolist()} seen during fit."
            ) from exc
        if not np.all(known):
            unknown = np.unique(y[~known])
            raise ValueError(
                f"y contains labels {unknown[:10].tolist()} that are not among the classes "
                f"{cls.tolist()} of {type(self).__name__}; pass classes=[...] to declare all labels."
            )
        return pos.astype(np.int64)

    # ------------------------------------------------------------------
    # training
    def fit(self, X, y, **fit_params):
        """Initialise (unless ``warm_start``) and train for ``max_epochs`` epochs.

        Parameters
        ----------
        X : array-like
            Training input (see the class docstring for its shape).
        y : array-like of shape (n_samples,)
            Labels of any sortable type (ints, strings).
        **fit_params : dict
            Passed on to skorch's fit loop and the module's ``forward``. To
            train for a given number of epochs without re-initialising, use
            :meth:`partial_fit` with ``epochs=``.

        Returns
        -------
        self
        """
        reset = not (self.warm_start and self.initialized_)
        X, y = self._validate_training_data(X, y, reset=reset)
        if reset:
            self.initialize()
        NeuralNet.partial_fit(self, X, y, _routing_method="fit", **fit_params)
        return self

    def partial_fit(self, X, y, classes=None, **fit_params):
        """Continue training without re-initialising (warm start).

        The module, optimizer state (e.g. Adam moments) and history are kept.
        On the first call the net is initialised from ``X`` and ``classes``
        (or the ``classes`` parameter, or the labels in ``y``).

        Parameters
        ----------
        X : array-like
            Training input, same shape as seen before.
        y : array-like of shape (n_samples,)
            Labels; all must be among ``classes_``.
        classes : array-like or None, default=None
            All labels, needed on the first call when ``y`` does not contain
            every class and the ``classes`` parameter is not set.
        **fit_params : dict
            ``epochs=e`` trains for ``e`` epochs (default ``max_epochs``).

        Returns
        -------
        self
        """
        reset = not self.initialized_
        X, y = self._validate_training_data(X, y, reset=reset, classes=classes)
        if reset:
            self.initialize()
        return super().partial_fit(X, y, **fit_params)

    @property
    def final_train_loss_(self):
        """Mean training loss of the last epoch (dropout on, as recorded by skorch)."""
        history = getattr(self, "history_", None)
        if not getattr(self, "initialized_", False) or not history or "train_loss" not in history[-1]:
            raise AttributeError(
                f"{type(self).__name__} has no final_train_loss_: it has not been trained yet."
            )
        return float(history[-1, "train_loss"])

    # ------------------------------------------------------------------
    # prediction
    def _check_predict_X(self, X):
        self.check_is_fitted()
        return self._check_X(X, reset=False)

    def predict_proba(self, X):
        """Class probabilities with dropout off (deterministic).

        Parameters
        ----------
        X : array-like
            Input of the shape seen during fit.

        Returns
        -------
        proba : ndarray of shape (n_samples, n_classes), float32
            Softmax of the logits; columns follow ``classes_``.
        """
        X = self._check_predict_X(X)
        return np.asarray(super().predict_proba(X), dtype=np.float32)

    def predict(self, X):
        """Most probable class label (dropout off).

        Parameters
        ----------
        X : array-like
            Input of the shape seen during fit.

        Returns
        -------
        y_pred : ndarray of shape (n_samples,)
            Labels from ``classes_``.
        """
        return np.asarray(self.classes_)[self.predict_proba(X).argmax(axis=1)]

    def predict_proba_samples(self, X, n_samples=50, random_state=None, batch_size=None):
        """Monte-Carlo-dropout class probabilities.

        Runs ``n_samples`` stochastic forward passes with every dropout layer
        on and everything else in evaluation mode. The passes are batched:
        the deterministic part before the first dropout layer is computed once
        per input and its output replicated along the batch axis, so there is
        no Python loop over passes (only over memory-bounded chunks). The
        module's state (parameters, ``training`` flags) and torch's global
        random generator are the same afterwards.

        Parameters
        ----------
        X : array-like
            Input of the shape seen during fit.
        n_samples : int, default=50
            Number of MC passes.
        random_state : int, RandomState instance or None, default=None
            Seed of the dropout masks. The same seed (with the same
            ``batch_size`` and device) gives identical samples. ``None``
            draws a seed from numpy's global random state.
        batch_size : int or None, default=None
            Most rows (inputs x replicas) per forward call. ``None`` derives it
            from a budget of activation memory per call: 32 MiB on CPU (small
            chunks that stay in cache run fastest there), 1 GiB on a GPU.

        Returns
        -------
        proba : ndarray of shape (n_samples, n_X, n_classes), float32
            Softmax probabilities of every pass.
        """
        X = self._check_predict_X(X)
        n_samples = check_positive_int(n_samples, "n_samples")
        n = len(X)
        device = torch.device(self.device)
        if batch_size is None:
            budget = MC_MEMORY_BUDGET.get(device.type, MC_MEMORY_BUDGET["cuda"])
            rows = max(1, int(budget // max(1, self._mc_bytes_per_row(X))))
        else:
            rows = check_positive_int(batch_size, "batch_size")
        b = max(1, min(n, rows // n_samples))  # inputs per chunk
        r = max(1, min(n_samples, rows // b))  # replicas per chunk
        seed = int(check_random_state(random_state).randint(0, 2**31 - 1))
        gen = torch.Generator(device=device).manual_seed(seed)
        nonlin = self._get_predict_nonlinearity()
        module = self.module_
        n_classes = len(self.classes_)
        out = np.empty((n_samples, n, n_classes), dtype=np.float32)
        plain_dropout = any(
            isinstance(m, torch.nn.modules.dropout._DropoutNd) for m in module.modules()
        )
        stochastic = any(
            isinstance(m, (MCDropout, torch.nn.modules.dropout._DropoutNd)) and m.p > 0
            for m in module.modules()
        )
        if not stochastic:
            # No active dropout: every pass equals the deterministic one; compute it once
            # (this also makes the samples bit-identical, so their variance is exactly 0).
            out[:] = self.predict_proba(X)[np.newaxis]
            return out
        flags = [(m, m.training) for m in module.modules()]
        try:
            module.eval()
            for m in module.modules():
                if isinstance(m, (MCDropout, torch.nn.modules.dropout._DropoutNd)):
                    m.training = True
            fork = (
                torch.random.fork_rng(devices=[device] if device.type == "cuda" else [])
                if plain_dropout
                else contextlib.nullcontext()
            )
            lock = _GLOBAL_RNG_LOCK if plain_dropout else contextlib.nullcontext()
            with lock, fork, _dropout_generator(module, gen), torch.inference_mode():
                if plain_dropout:
                    torch.manual_seed(seed)
                for i0 in range(0, n, b):
                    xb = torch.as_tensor(X[i0 : i0 + b]).to(device)
                    for j0 in range(0, n_samples, r):
                        rr = min(r, n_samples - j0)
                        logits = module(xb, n_replicas=rr)
                        proba = nonlin(logits).reshape(rr, len(xb), n_classes)
                        out[j0 : j0 + rr, i0 : i0 + len(xb)] = proba.cpu().numpy()
        finally:
            for m, flag in flags:
                m.training = flag
        return out

    # ------------------------------------------------------------------
    # persistence
    def load_params(self, f_params=None, *args, **kwargs):
        """Load saved parameters (``torch.load(..., weights_only=True)``).

        On a fresh, unfitted net the input size is read from the saved
        parameters; pass ``classes=[...]`` to the constructor to get the
        original labels back (otherwise ``classes_`` is ``0..n_classes-1``).
        See :meth:`skorch.NeuralNet.load_params` for the other arguments.
        """
        raw_device = self.__dict__.get("device")
        if not self.initialized_ and f_params is not None and not kwargs.get("use_safetensors"):
            pos = f_params.tell() if hasattr(f_params, "tell") else None
            state = torch.load(f_params, map_location="cpu", weights_only=True)
            if pos is not None:
                f_params.seek(pos)
            n_classes = self._meta_from_state_dict(state)
            if self.classes is None:
                self.classes_inferred_ = np.arange(n_classes)
            elif len(self.classes) != n_classes:
                raise ValueError(
                    f"The saved parameters have {n_classes} classes but classes has "
                    f"{len(self.classes)} labels."
                )
            self.initialize()
        result = super().load_params(f_params, *args, **kwargs)
        if raw_device == "auto":
            self.__dict__["device"] = raw_device
        return result


@contextlib.contextmanager
def _dropout_generator(module, generator):
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
