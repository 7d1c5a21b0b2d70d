"""Uncertainty from an ensemble of independently seeded classifiers: :class:`EnsembleClassifier`."""

from __future__ import annotations

import itertools
import numbers

import numpy as np
import torch
from joblib import Parallel, delayed
from sklearn.base import BaseEstimator, ClassifierMixin, clone
from sklearn.utils.validation import check_is_fitted

from ..utils._param_validation import (
    HasMethods,
    Interval,
    StrOptions,
    fit_context,
    validate_estimator_params,
    validate_parameter_constraints,
)
from ..utils._random import draw_seeds, set_random_states
from ..utils._torch import resolve_device
from ._convlstm import ConvLSTMClassifier, ConvLSTMNet
from ._stacked import StackedConvLSTMNet

__all__ = ["EnsembleClassifier"]


def _fit_member(est, X, y, fit_params):
    return est.fit(X, y, **fit_params)


def _partial_fit_member(est, X, y, kwargs):
    return est.partial_fit(X, y, **kwargs)


#: Optimisers whose state and update are element-wise: one of them over the stacked
#: parameters is K optimisers of K separate nets.
_ELEMENTWISE_OPTIMIZERS = (torch.optim.Adam, torch.optim.AdamW, torch.optim.SGD, torch.optim.RMSprop)


def _stacking_obstacle(est, fit_params):
    """Why members cloned from ``est`` cannot train as one stacked net; None when they can."""
    if not isinstance(est, ConvLSTMClassifier):
        return f"the members are {type(est).__name__}, not ConvLSTMClassifier"
    if est.module is not ConvLSTMNet:
        return "the members' module is not ConvLSTMNet"
    if getattr(est, "augment", None) is not None:
        return "the members augment their training batches"
    if est.callbacks:
        return "the members have callbacks (they could stop at different epochs)"
    if est.train_split is not None:
        return "the members have a train_split"
    if est.optimizer not in _ELEMENTWISE_OPTIMIZERS:
        names = ", ".join(o.__name__ for o in _ELEMENTWISE_OPTIMIZERS)
        return f"the members' optimizer is not one of the element-wise {names}"
    if "param_groups" in est.get_params_for("optimizer"):
        return "the members' optimizer has param_groups"
    if est.criterion is not torch.nn.CrossEntropyLoss or est.get_params_for("criterion"):
        return "the members' criterion is not a plain CrossEntropyLoss"
    if est.iterator_train is not torch.utils.data.DataLoader:
        return "the members have a custom iterator_train"
    if fit_params:
        return f"fit parameters {sorted(fit_params)} were given"
    return None


def _stacked_optimizer_state(stacked_state, member_states, k=None):
    """Stack the members' optimiser states of one parameter (``k=None``), or take row ``k``."""
    if k is None:
        first = member_states[0]
        return {key: torch.stack([s[key] for s in member_states])
                if torch.is_tensor(v) and v.dim() > 0 else (v.clone() if torch.is_tensor(v) else v)
                for key, v in first.items()}
    return {key: v[k].clone() if torch.is_tensor(v) and v.dim() > 0 else (v.clone() if torch.is_tensor(v) else v)
            for key, v in stacked_state.items()}


def _train_stacked(members, X, y, epochs=None, classes=None):
    """Train ConvLSTMClassifier members as one StackedConvLSTMNet, then write the result back.

    Each member is prepared by its own skorch hooks (``on_train_begin``: data
    validation, a seeded net on a cold start), keeps its own batch order (its
    seeded training iterator) and records its own history; only the steps are
    shared. Weights, buffers and optimiser states end up in the members, so
    they predict, pickle and continue training as if trained separately.
    """
    for m in members:
        if not m.initialized_:
            m.initialize()
        m._partial_fit_classes = classes  # read by the members' on_train_begin, as in partial_fit
        try:
            m.notify("on_train_begin", X=X, y=y)
        finally:
            del m._partial_fit_classes
        m.check_training_readiness()
    first = members[0]
    device = torch.device(first.device)
    dataset = first.get_dataset(X, y)
    iterators = [m.get_iterator(dataset, training=True) for m in members]
    stacked = StackedConvLSTMNet([m.module_ for m in members]).to(device).train()
    named = [dict(m.module_.named_parameters()) for m in members]
    stacked_params = dict(zip(stacked._param_names, stacked.parameters()))
    args, kwargs = first.get_params_for_optimizer("optimizer", stacked.named_parameters())
    optimizer = first.optimizer(*args, **kwargs)
    for name, p in stacked_params.items():
        states = [m.optimizer_.state.get(named[k][name]) for k, m in enumerate(members)]
        if all(states):  # a warm start: continue every member's own moments
            optimizer.state[p] = _stacked_optimizer_state(None, states)
    weight = getattr(first.criterion_, "weight", None)
    gen = getattr(first, "dropout_generator_", None)
    if gen is not None:  # reproducible masks, and a new stream at each call
        seed = int(torch.randint(0, 2**62, (1,), generator=gen, device=gen.device))
        stacked.generator = torch.Generator().manual_seed(seed)
    on_epoch = {"dataset_train": dataset, "dataset_valid": None}
    for _ in range(first.max_epochs if epochs is None else int(epochs)):
        for m in members:
            m.notify("on_epoch_begin", **on_epoch)
        count = 0
        # zip_longest runs every iterator to its end: a DataLoader's sampler draws from the
        # member's shuffle generator once more when exhausted (zip would leave all but the first)
        for batches in itertools.zip_longest(*iterators):
            for m, b in zip(members, batches):
                m.notify("on_batch_begin", batch=b, training=True)
            Xb = torch.stack([torch.as_tensor(b[0]) for b in batches]).to(device)
            yb = torch.stack([torch.as_tensor(b[1]) for b in batches]).to(device)
            optimizer.zero_grad()
            logits = stacked(Xb)
            losses = stacked.member_losses(logits, yb, weight)
            losses.sum().backward()
            optimizer.step()
            values = losses.detach().cpu().tolist()
            for k, (m, b) in enumerate(zip(members, batches)):
                m.history.record_batch("train_loss", values[k])
                m.history.record_batch("train_batch_size", len(b[0]))
                m.notify("on_batch_end", batch=b, training=True, loss=losses[k].detach(),
                         y_pred=logits[k].detach())
            count += 1
        for m in members:
            m.history.record("train_batch_count", count)
            m.notify("on_epoch_end", **on_epoch)
    with torch.no_grad():
        for k, m in enumerate(members):
            state = stacked.member_state_dict(k)
            for name, t in list(m.module_.named_parameters()) + list(m.module_.named_buffers()):
                t.copy_(state[name])
            m.module_.train()
            for name, p in stacked_params.items():
                if p in optimizer.state:
                    m.optimizer_.state[named[k][name]] = _stacked_optimizer_state(optimizer.state[p], None, k)
    for m in members:
        m.notify("on_train_end", X=X, y=y)
    return members


class EnsembleClassifier(ClassifierMixin, BaseEstimator):
    """Several copies of a classifier with different seeds; their spread is the uncertainty.

    An alternative to Monte-Carlo dropout as the source of
    ``predict_proba_samples``: each member is a clone of ``estimator`` whose
    ``random_state`` parameters (its own and any nested ``*__random_state``)
    are set to a seed of its own, so the members differ in initial weights,
    batch order and dropout masks during training. A "sample" is one
    member's (deterministic) ``predict_proba``, so every strategy of
    :mod:`sklearn_hardness.active` works unchanged. Deep ensembles are often
    better calibrated than MC dropout in active learning (Beluch et al.,
    CVPR 2018), at ``n_estimators`` times the training cost; on frozen
    features (OFNN, DINOv2NN) the members are small heads on the same cached
    features, so that cost is small.

    Parameters
    ----------
    estimator : classifier
        The member to copy, e.g. :class:`OFNNClassifier`. It needs
        ``predict_proba``.
    n_estimators : int, default=5
        Number of members.
    random_state : int, RandomState instance or None, default=None
        Draws the members' seeds.
    n_jobs : int or None, default=None
        Members trained in parallel (:class:`joblib.Parallel`); not used
        when they train stacked.
    stacked : {"auto"} or bool, default="auto"
        Train the members as one stacked module (every step of
        every member in one batched call) instead of one after another.
        Possible when ``estimator`` is a :class:`ConvLSTMClassifier` with its
        default module, criterion and iterator, an element-wise optimiser
        (Adam, AdamW, SGD, RMSprop) and no callbacks or ``train_split``.
        Each member keeps its seed's initial weights, batch order, history
        and optimiser state; its dropout masks are drawn independently but
        are not those of separate training (see Notes). ``"auto"``: stacked
        on a CUDA device when possible, separate otherwise (on CPU stacking
        is no faster: ``benchmarks/bench_stacked.py``). ``True``:
        stacked, or a ``ValueError`` saying why not.

    Attributes
    ----------
    estimators_ : list of estimators
        The trained members.
    seeds_ : ndarray of shape (n_estimators,)
        The seed given to each member.
    classes_ : ndarray of shape (n_classes,)
    n_features_in_ : int
        Only when the members have it.
    stacked_ : bool
        Whether the last ``fit``/``partial_fit`` trained the members stacked.

    See Also
    --------
    ConvLSTMClassifier.predict_proba_samples : MC dropout, one net.

    Notes
    -----
    :class:`~sklearn_hardness.active.ActiveLearner` trains an ensemble of
    skorch nets like one net: ``partial_fit(X, y, classes=..., epochs=...)``
    continues every member from its current weights.

    Stacked training (``stacked``) runs the members' steps together on each
    member's own batches; without dropout it gives the members of separate
    training to float tolerance (``tests/test_models_ensemble.py``). With
    dropout the masks come from one seeded stream split between the members
    (one stacked module), so the members are distributed as, but not
    equal to, separately trained ones.

    Examples
    --------
    >>> from sklearn.datasets import make_blobs
    >>> from sklearn_hardness.models import EnsembleClassifier, OFNNClassifier
    >>> X, y = make_blobs(60, n_features=4, centers=3, random_state=0)
    >>> ens = EnsembleClassifier(OFNNClassifier(hidden_units=8, max_epochs=20, lr=0.05),
    ...                          n_estimators=3, random_state=0).fit(X.astype("float32"), y)
    >>> ens.predict_proba_samples(X[:2].astype("float32")).shape  # (members, presses, classes)
    (3, 2, 3)
    """

    _parameter_constraints = {
        "estimator": [HasMethods(["fit", "predict_proba"])],
        "n_estimators": [Interval(numbers.Integral, 1, None, closed="left")],
        "random_state": ["random_state"],
        "n_jobs": [numbers.Integral, None],
        "stacked": [StrOptions({"auto"}), "boolean"],
    }

    def __init__(self, estimator, *, n_estimators=5, random_state=None, n_jobs=None, stacked="auto"):
        self.estimator = estimator
        self.n_estimators = n_estimators
        self.random_state = random_state
        self.n_jobs = n_jobs
        self.stacked = stacked

    def _use_stacked(self, fit_params):
        if self.stacked is False:
            return False
        obstacle = _stacking_obstacle(self.estimator, fit_params)
        if self.stacked is True:
            if obstacle is not None:
                raise ValueError(f"stacked=True, but the members cannot train stacked: {obstacle}.")
            return True
        if obstacle is not None:
            return False
        return torch.device(resolve_device(self.estimator.device)).type == "cuda"

    def _new_members(self):
        self.seeds_ = np.array(draw_seeds(self.random_state, self.n_estimators))
        return [set_random_states(clone(self.estimator), s) for s in self.seeds_]

    def _set_classes(self):
        classes = [np.asarray(m.classes_) for m in self.estimators_]
        if any(c.shape != classes[0].shape or np.any(c != classes[0]) for c in classes[1:]):
            raise ValueError(
                "the members learned different classes; pass classes=[...] to the estimator so "
                "that every member knows all of them."
            )
        self.classes_ = classes[0]
        if hasattr(self.estimators_[0], "n_features_in_"):
            self.n_features_in_ = self.estimators_[0].n_features_in_

    @fit_context(prefer_skip_nested_validation=False)
    def fit(self, X, y, **fit_params):
        """Train every member from scratch on ``(X, y)``.

        Parameters
        ----------
        X : array-like
            Input of ``estimator``.
        y : array-like of shape (n_samples,)
        **fit_params
            Passed to each member's ``fit``.

        Returns
        -------
        self
        """
        members = self._new_members()
        self.stacked_ = self._use_stacked(fit_params)
        if self.stacked_:
            self.estimators_ = _train_stacked(members, X, y)
        else:
            self.estimators_ = Parallel(n_jobs=self.n_jobs, prefer="threads")(
                delayed(_fit_member)(m, X, y, fit_params) for m in members
            )
        self._set_classes()
        return self

    def partial_fit(self, X, y, classes=None, **kwargs):
        """Continue training every member (the first call creates them).

        For members that are skorch nets, ``epochs=`` gives the number of
        epochs, as in :meth:`skorch.NeuralNet.partial_fit`.

        Returns
        -------
        self
        """
        if not hasattr(self, "estimators_"):
            validate_estimator_params(self)
            self.estimators_ = self._new_members()
        if not all(hasattr(m, "partial_fit") for m in self.estimators_):
            raise TypeError(f"{type(self.estimator).__name__} has no partial_fit; use fit.")
        other = {k: v for k, v in kwargs.items() if k != "epochs"}
        self.stacked_ = self._use_stacked(other)
        if self.stacked_:
            self.estimators_ = _train_stacked(self.estimators_, X, y, epochs=kwargs.get("epochs"), classes=classes)
            self._set_classes()
            return self
        if classes is not None:
            kwargs["classes"] = classes
        self.estimators_ = Parallel(n_jobs=self.n_jobs, prefer="threads")(
            delayed(_partial_fit_member)(m, X, y, kwargs) for m in self.estimators_
        )
        self._set_classes()
        return self

    @property
    def history_(self):
        """The first member's training history (skorch members), for loss reports."""
        check_is_fitted(self, "estimators_")
        return self.estimators_[0].history_

    def predict_proba_samples(self, X, n_samples=None, random_state=None):
        """Each member's class probabilities: one "sample" per member.

        Parameters
        ----------
        X : array-like
        n_samples : int or None, default=None
            ``None`` returns one row per member. An int returns that many
            rows, cycling through the members (row ``j`` is member
            ``j % n_estimators``), so callers that ask for a fixed number of
            MC passes work unchanged; with a multiple of ``n_estimators`` the
            mean and variance over rows equal those over the members.
        random_state : ignored
            The members are deterministic at prediction time; accepted for
            the interface of the MC-dropout nets.

        Returns
        -------
        proba : ndarray of shape (n_samples or n_estimators, n_X, n_classes)
        """
        check_is_fitted(self, "estimators_")
        validate_parameter_constraints(
            {"n_samples": [Interval(numbers.Integral, 1, None, closed="left"), None]},
            {"n_samples": n_samples},
            caller_name=f"{type(self).__name__}.predict_proba_samples",
        )
        members = np.stack([np.asarray(m.predict_proba(X), dtype=np.float32) for m in self.estimators_])
        if n_samples is None:
            return members
        return members[np.arange(n_samples) % len(self.estimators_)]

    def predict_proba(self, X):
        """Mean of the members' class probabilities."""
        return self.predict_proba_samples(X).mean(axis=0)

    def predict(self, X):
        """The class with the highest mean probability."""
        proba = self.predict_proba(X)
        return self.classes_[np.argmax(proba, axis=1)]
