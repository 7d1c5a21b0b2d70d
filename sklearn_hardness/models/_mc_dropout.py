"""The skorch base class of the three Monte-Carlo-dropout classifiers.

:class:`MCDropoutClassifierBase` is a :class:`skorch.NeuralNetClassifier`
customised only through skorch's hooks and callbacks (``fit`` is skorch's):

* :class:`_TrainingDataSetter`, a default callback, validates the training
  data at ``on_train_begin``; on a cold start (the first ``fit`` or
  ``partial_fit`` after ``initialize``) it records what the network's size
  depends on (input shape, classes, input statistics, class weights) and
  rebuilds module, criterion and optimizer for it, as skorch's
  ``InputShapeSetter`` does;
* ``get_dataset`` validates ``X`` and encodes labels of any sortable type to
  ``0..n_classes-1`` (their positions in the sorted ``classes_``); ``predict``
  maps them back (a :class:`torch.utils.data.Dataset`, such as skorch's
  validation ``Subset``, goes through skorch's own prediction path and gets
  the encoded labels its targets hold);
* ``initialize`` validates the parameters (``_parameter_constraints``) and
  seeds the initial weights, the shuffling and the dropout masks from
  ``random_state``; ``get_iterator`` and ``train_step`` use those generators;
* :meth:`MCDropoutClassifierBase.predict_proba_samples` calls the batched
  sampler of :mod:`._mc_sampling`.
"""

from __future__ import annotations

import numbers

import numpy as np
import torch
from sklearn.exceptions import NotFittedError
from sklearn.utils.class_weight import compute_class_weight
from sklearn.utils.multiclass import check_classification_targets
from sklearn.utils.validation import check_consistent_length, column_or_1d
from skorch import NeuralNetClassifier
from skorch.callbacks import Callback
from skorch.dataset import Dataset

from ..utils._param_validation import (
    HasMethods,
    Interval,
    InvalidParameterError,
    Options,
    StrOptions,
    validate_parameter_constraints,
)
from ..utils._random import draw_seeds
from ..utils._torch import TorchDevices, resolve_device, seeded_torch_rng
from ._mc_sampling import MC_MEMORY_BUDGET, MCDropout, dropout_generator, sample_proba, softmax
from ._persistence import NetPersistenceMixin

__all__ = ["MCDropout", "MCDropoutClassifierBase"]


class _TrainingDataSetter(Callback):
    """Validate the training data; on a cold start size the net from it.

    The first callback of every :class:`MCDropoutClassifierBase`, so that
    callbacks after it (``LRScheduler``...) see the rebuilt optimizer.
    """

    def on_train_begin(self, net, X=None, y=None, **kwargs):
        net._prepare_training(X, y)


class MCDropoutClassifierBase(NetPersistenceMixin, NeuralNetClassifier):
    """Base class of the MC-dropout classifiers (not for direct use).

    Subclasses define ``_check_X(X, reset)`` (validate input, remember its
    shape when ``reset``), ``_input_meta_attrs`` (the fitted attributes set
    by ``_check_X``), ``_module_defaults()`` (keyword arguments of the module
    derived from the fitted data and parameters), ``_placeholder_meta()``
    (input metadata of the tiny module skorch builds before it has seen data),
    ``_meta_from_state_dict(state_dict)`` (restore the input metadata from
    saved parameters) and ``_mc_bytes_per_row(X)`` (activation memory of one
    forward row, for chunking).

    Labels and class weights, for every subclass:

    * ``classes_`` is sorted, as scikit-learn's (:func:`numpy.unique`),
      whatever the order of the ``classes`` parameter or of the ``classes``
      argument of :meth:`partial_fit`; an unsorted list gives the same fitted
      model as the sorted one (the parameter itself is kept as given).
    * ``class_weight="balanced"`` weights each class present in the
      cold-start training labels by ``n_samples / (n_present_classes *
      count)`` (scikit-learn's formula over the classes present, exactly its
      weights when every class is present); a class declared by ``classes``
      but absent from ``y`` gets weight 1.0.
    """

    #: Draws its dropout masks and initial weights from its own generators, seeded by
    #: ``random_state``, never from torch's global one (``ActiveLearner`` reads it so that it
    #: seeds and locks the global generator only for models that need it).
    _own_torch_generators = True

    _parameter_constraints = {
        "dropout": [Interval(numbers.Real, 0, 1, closed="left")],
        "random_state": ["random_state"],
        "lr": [Interval(numbers.Real, 0, None, closed="neither")],
        "max_epochs": [Interval(numbers.Integral, 0, None, closed="left")],
        "batch_size": [Interval(numbers.Integral, 1, None, closed="left"), Options(numbers.Integral, {-1})],
        "classes": ["array-like", None],
        "class_weight": [dict, StrOptions({"balanced"}), None],
        "verbose": ["verbose"],
        "device": [TorchDevices(), None],
        "warm_start": ["boolean"],
        # skorch's own parameters, as skorch.NeuralNet documents them
        "module": [HasMethods(["forward"])],  # a torch.nn.Module class or instance
        "criterion": [callable],
        "optimizer": [callable],
        "iterator_train": [callable],
        "iterator_valid": [callable],
        "dataset": [callable],
        "train_split": [callable, None],
        "callbacks": [list, StrOptions({"disable"}), None],
        "predict_nonlinearity": [callable, StrOptions({"auto"}), None],
        "compile": ["boolean"],
        "use_caching": ["boolean", StrOptions({"auto"})],
        "torch_load_kwargs": [dict, None],
    }
    _input_meta_attrs = ()
    _predict_proba_samples_constraints = {
        "n_samples": [Interval(numbers.Integral, 1, None, closed="left")],
        "random_state": ["random_state"],
        "batch_size": [Interval(numbers.Integral, 1, None, closed="left"), None],
    }

    def __init__(
        self,
        module,
        *,
        dropout=0.2,
        class_weight=None,
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
        self.class_weight = class_weight
        self.random_state = random_state

    def get_default_callbacks(self):
        return [("training_data", _TrainingDataSetter())] + list(super().get_default_callbacks())

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

    def set_params(self, **kwargs):
        # scikit-learn convention: set_params stores and never raises; a bad value is
        # reported by the next fit / predict_proba_samples (_check_dropout).
        super().set_params(**kwargs)
        if "dropout" in kwargs and getattr(self, "initialized_", False) and hasattr(self, "module_"):
            try:
                self._check_dropout()
            except InvalidParameterError:
                return self
            for m in self.module_.modules():
                if isinstance(m, MCDropout):
                    m.p = float(kwargs["dropout"])
        return self

    @property
    def classes_(self):
        """Class labels, sorted (:func:`numpy.unique`).

        The ``classes`` parameter when set (sorted; the parameter keeps the
        order given), else the classes of the first training call.
        """
        if self.classes is not None and len(self.classes):
            return np.unique(np.asarray(self.classes))
        return super().classes_

    def _check_dropout(self):
        validate_parameter_constraints(
            {"dropout": self._parameter_constraints["dropout"]},
            {"dropout": self.dropout},
            caller_name=type(self).__name__,
        )

    # ------------------------------------------------------------------
    # initialisation and seeding
    def initialize(self):
        """Validate the parameters, seed the generators and initialise the net.

        Before the net has seen data, the module is a placeholder of the right
        kind; the first ``fit``/``partial_fit`` sizes it from the data (or
        :meth:`load_params` from saved parameters). With an integer
        ``random_state`` the initial weights, the shuffling of training
        batches and the dropout masks during training are reproducible, and
        torch's global random generator is left untouched.

        Returns
        -------
        self
        """
        validate_parameter_constraints(
            self._parameter_constraints, self.get_params(deep=False), caller_name=type(self).__name__
        )
        for attr in self._input_meta_attrs + ("classes_inferred_", "class_weight_"):
            self.__dict__.pop(attr, None)
        if self.random_state is None:
            self.init_seed_ = None
            self.shuffle_generator_ = None
            self.dropout_generator_ = None
        else:
            init_seed, shuffle_seed, dropout_seed = draw_seeds(self.random_state, 3)
            self.init_seed_ = init_seed
            self.shuffle_generator_ = torch.Generator().manual_seed(shuffle_seed)
            self.dropout_generator_ = torch.Generator(device=torch.device(self.device)).manual_seed(
                dropout_seed
            )
        return super().initialize()

    def _has_input_meta(self):
        return all(hasattr(self, a) for a in self._input_meta_attrs) and (
            self.classes is not None or hasattr(self, "classes_inferred_")
        )

    def initialize_module(self):
        """Build the module from the fitted input metadata and the parameters."""
        if self._has_input_meta():
            kwargs = self._module_defaults()
        else:  # skorch initialises before fit sees data: a tiny stand-in, rebuilt on train begin
            kwargs = self._placeholder_meta()
        kwargs.update(self.get_params_for("module"))
        module_cls = self.module if isinstance(self.module, type) else type(self.module)
        seed = getattr(self, "init_seed_", None)
        if seed is None:
            module = module_cls(**kwargs)
        else:
            with seeded_torch_rng(seed):
                module = module_cls(**kwargs)
        self.module_ = module.to(self.device)
        return self

    def initialize_criterion(self):
        """Build the criterion; ``class_weight`` becomes its ``weight``."""
        kwargs = self.get_params_for("criterion")
        weight = getattr(self, "class_weight_", None)
        if weight is not None and "weight" not in kwargs:
            kwargs["weight"] = torch.as_tensor(weight, dtype=torch.float32)
        self.criterion_ = self.initialized_instance(self.criterion, kwargs)
        if isinstance(self.criterion_, torch.nn.Module):
            self.criterion_ = self.criterion_.to(self.device)
        return self

    def _rebuild(self):
        # module, criterion and optimizer for the data just seen (skorch's public hooks)
        self.initialize_module()
        self.initialize_criterion()
        self.initialize_optimizer()

    def _prepare_training(self, X, y):
        """Validate training data; on a cold start size the net from it."""
        cold = not self._has_input_meta()
        if y is None:
            raise ValueError(f"{type(self).__name__} requires y to be passed, but the target y is None "
                             "(it needs labels y for training).")
        X = self._check_X(X, reset=cold)
        y = self._check_y(y)
        check_consistent_length(X, y)
        if not cold:
            self._encode(y)  # unknown labels fail here, before any training
            return
        classes = getattr(self, "_partial_fit_classes", None)
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
                f"{type(self).__name__} needs at least 2 classes, got {len(cls)} class "
                f"({cls.tolist()}); pass classes=[...] to declare all labels."
            )
        cls = np.unique(cls)  # sorted, as scikit-learn's classes_ (and the classes_ property)
        self.classes_inferred_ = cls
        self._encode(y)
        self.class_weight_ = None if self.class_weight is None else self._class_weights(cls, y)
        self._fit_input_stats(X)
        self._rebuild()

    def _class_weights(self, cls, y):
        """``class_weight`` as an array over the sorted classes ``cls``.

        ``"balanced"`` is scikit-learn's over the classes present in ``y``;
        declared classes absent from ``y`` get 1.0.
        """
        if isinstance(self.class_weight, str) and self.class_weight == "balanced":
            present = np.isin(cls, y)
            weight = np.ones(len(cls), dtype=np.float64)
            weight[present] = compute_class_weight("balanced", classes=cls[present], y=y)
        else:
            weight = compute_class_weight(self.class_weight, classes=cls, y=y)
        return weight.astype(np.float32)

    def _fit_input_stats(self, X):
        """Statistics of the cold-start training input the module keeps (none here)."""

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
        with dropout_generator(self.module_, gen):
            return super().train_step(batch, **fit_params)

    # ------------------------------------------------------------------
    # data validation and labels
    def check_data(self, X, y=None):
        # Labels are validated and classes inferred by _TrainingDataSetter; skorch's
        # own check would overwrite classes_ with the encoded labels.
        pass

    def get_dataset(self, X, y=None):
        """skorch's dataset of validated ``X`` and labels encoded to ``0..n_classes-1``."""
        if isinstance(X, torch.utils.data.Dataset):
            return super().get_dataset(X, y)
        X = self._check_X(X, reset=False)
        if y is not None:
            y = self._encode(self._check_y(y))
        return Dataset(X, y)

    def _check_X(self, X, reset):
        raise NotImplementedError

    def _placeholder_meta(self):
        raise NotImplementedError

    def _module_defaults(self):
        raise NotImplementedError

    def _meta_from_state_dict(self, state_dict):
        raise NotImplementedError

    def _mc_bytes_per_row(self, X):
        raise NotImplementedError

    @staticmethod
    def _check_y(y):
        y = np.asarray(y)
        if y.ndim == 2 and y.shape[1] == 1:
            y = column_or_1d(y, warn=True)  # DataConversionWarning, as scikit-learn's estimators
        if y.ndim != 1:
            raise ValueError(f"y must be a 1-D array of labels, got shape {y.shape}.")
        if y.dtype.kind == "f" and not np.isfinite(y).all():
            raise ValueError("y contains NaN or infinite labels.")
        check_classification_targets(y)  # continuous targets: "Unknown label type"
        return y

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
            every class and the ``classes`` parameter is not set (as in
            scikit-learn's ``partial_fit``). In any order: ``classes_`` is
            the sorted labels.
        **fit_params : dict
            ``epochs=e`` trains for ``e`` epochs (default ``max_epochs``).

        Returns
        -------
        self
        """
        # skorch's partial_fit ignores classes; _TrainingDataSetter reads it from here
        self._partial_fit_classes = classes
        try:
            return super().partial_fit(X, y, classes=classes, **fit_params)
        finally:
            del self._partial_fit_classes

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
    def check_is_fitted(self, attributes=None, *args, **kwargs):
        """Raise :class:`sklearn.exceptions.NotFittedError` unless fitted (or loaded)."""
        if not getattr(self, "initialized_", False) or not self._has_input_meta():
            raise NotFittedError(
                f"This {type(self).__name__} instance is not fitted yet. Call 'fit' with "
                "appropriate arguments (or 'load_params' with saved parameters) before using it."
            )
        return super().check_is_fitted(attributes, *args, **kwargs)

    def _get_predict_nonlinearity(self):
        # skorch's "auto" gives torch.softmax for CrossEntropyLoss; ours gives the same
        # values (float32 at least) faster for few classes.
        if isinstance(self.predict_nonlinearity, str) and self.predict_nonlinearity == "auto":
            self.check_is_fitted()
            if isinstance(self.criterion_, torch.nn.CrossEntropyLoss):
                return softmax
        return super()._get_predict_nonlinearity()

    def _check_predict_X(self, X):
        self.check_is_fitted()
        return self._check_X(X, reset=False)

    def predict_proba(self, X):
        """Class probabilities with dropout off (deterministic).

        Parameters
        ----------
        X : array-like or torch.utils.data.Dataset
            Input of the shape seen during fit, or a dataset of it such as
            :meth:`get_dataset` builds (skorch's validation ``Subset`` of it
            included), passed to skorch as is.

        Returns
        -------
        proba : ndarray of shape (n_samples, n_classes), float32
            Softmax of the logits; columns follow ``classes_``.
        """
        if isinstance(X, torch.utils.data.Dataset):
            # skorch's scoring callbacks (valid_acc) predict on its validation Subset;
            # get_dataset takes datasets as they are, so does prediction.
            self.check_is_fitted()
        else:
            X = self._check_predict_X(X)
        return np.asarray(super().predict_proba(X), dtype=np.float32)

    def predict(self, X):
        """Most probable class label (dropout off).

        Parameters
        ----------
        X : array-like or torch.utils.data.Dataset
            Input of the shape seen during fit, or a dataset of it.

        Returns
        -------
        y_pred : ndarray of shape (n_samples,)
            Labels from ``classes_``. For a dataset, skorch's prediction:
            the encoded labels ``0..n_classes-1`` (positions in ``classes_``)
            that the targets of :meth:`get_dataset`'s datasets hold, so that
            skorch's ``valid_acc`` compares like with like.
        """
        proba = self.predict_proba(X)  # first: it raises NotFittedError before classes_ is read
        if isinstance(X, torch.utils.data.Dataset):
            return proba.argmax(axis=1)
        return np.asarray(self.classes_)[proba.argmax(axis=1)]

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
        validate_parameter_constraints(
            self._predict_proba_samples_constraints,
            {"n_samples": n_samples, "random_state": random_state, "batch_size": batch_size},
            caller_name=f"{type(self).__name__}.predict_proba_samples",
        )
        X = self._check_predict_X(X)
        self._check_dropout()
        device = torch.device(self.device)
        if batch_size is None:
            budget = MC_MEMORY_BUDGET.get(device.type, MC_MEMORY_BUDGET["cuda"])
            rows = max(1, int(budget // max(1, self._mc_bytes_per_row(X))))
        else:
            rows = int(batch_size)
        (seed,) = draw_seeds(random_state, 1)
        out = sample_proba(
            self.module_, X, n_samples=n_samples, seed=seed, rows_per_call=rows, device=device,
            nonlinearity=self._get_predict_nonlinearity(), n_classes=len(self.classes_),
        )
        if out is None:
            # No active dropout: every pass equals the deterministic one (bit-identical,
            # so their variance is exactly 0).
            out = np.repeat(self.predict_proba(X)[np.newaxis], n_samples, axis=0)
        return out
