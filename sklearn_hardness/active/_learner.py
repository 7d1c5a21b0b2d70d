"""A modAL-style active learner that retrains on a capped reservoir (Algorithm 1)."""

from __future__ import annotations

import contextlib
import inspect
from numbers import Integral, Real

import numpy as np
from sklearn.base import (
    BaseEstimator,
    ClassifierMixin,
    MetaEstimatorMixin,
    clone,
)
from sklearn.exceptions import NotFittedError
from sklearn.metrics import accuracy_score
from sklearn.pipeline import Pipeline
from sklearn.utils import check_random_state
from sklearn.utils.validation import check_is_fitted
from skorch import NeuralNet

from ..models import EnsembleClassifier
from ..utils._param_validation import (
    HasMethods,
    Interval,
    StrOptions,
    fit_context,
    validate_estimator_params,
    validate_params,
)
from ..utils._random import int_seed
from ..utils._torch import seeded_torch_rng
from ._rows import concat_rows, n_rows, training_subset
from ._strategies import STRATEGY_NAMES, get_strategy, variance_sampling
from ._uncertainty import UNCERTAINTY_KINDS, class_uncertainty, variance_decomposition

__all__ = ["ActiveLearner"]


def _is_skorch_net(est):
    return isinstance(est, NeuralNet)


def _trains_in_epochs(est):
    """A skorch net, or an ensemble of them: trained with partial_fit(..., epochs=) (warm start)."""
    if isinstance(est, EnsembleClassifier):
        return _is_skorch_net(est.estimator)
    return _is_skorch_net(est)


def _accepts_kwargs(func, names):
    """The subset of ``names`` that ``func`` accepts as keyword arguments."""
    try:
        params = inspect.signature(func).parameters
    except (TypeError, ValueError):  # builtins, odd callables
        return set()
    if any(p.kind is inspect.Parameter.VAR_KEYWORD for p in params.values()):
        return set(names)
    return {n for n in names if n in params}


class ActiveLearner(MetaEstimatorMixin, ClassifierMixin, BaseEstimator):
    """Active sampling of reference objects with a capped training reservoir.

    Implements Algorithm 1 of the paper with a modAL-like interface:
    :meth:`fit` trains on the initial presses (``s0`` per reference object)
    for ``initial_epochs`` epochs; :meth:`query` runs ``n_samples``
    MC-dropout passes on presses of the test object and returns the
    reference object(s) to press next; :meth:`teach` adds the new presses to
    the reservoir and continues training (warm start) for
    ``epochs_per_query`` epochs on the whole reservoir, or on a random
    subset of ``max_reservoir`` samples when the reservoir is larger.

    Parameters
    ----------
    estimator : estimator
        A classifier with ``predict_proba_samples`` (e.g.
        :class:`~sklearn_hardness.models.OFNNClassifier`) or a
        :class:`~sklearn.pipeline.Pipeline` ending in one. It is cloned in
        :meth:`fit`; the trained copy is ``estimator_``. If the final
        estimator is a skorch net it is trained with
        ``partial_fit(X, y, classes=classes_, epochs=...)``: the first call
        initialises the (cloned, untrained) net, later calls continue from
        its current weights and optimizer state (warm start); so is an
        :class:`~sklearn_hardness.models.EnsembleClassifier` of skorch nets,
        member by member. Any other final
        estimator is refit from scratch on each training set (the epoch
        counts are then unused). For a Pipeline, the steps before the last
        are fit once, on the initial presses, and their output for every
        reservoir sample is kept, so frozen features (optical flow, DINOv2)
        are computed once per press.
    query_strategy : {"variance", "entropy", "bald", "margin", "mc_variance", \
            "thompson", "random"} or callable, default=variance_sampling
        The strategy, by name or as a callable
        ``strategy(proba_samples, n_instances=1, *, random_state=None)``
        that receives the MC-dropout probabilities on the test presses,
        shape ``(n_samples, n_test, n_classes)``, and returns
        ``(class_indices, scores)`` or ``class_indices`` (``random_state``
        is passed only if accepted). See :func:`variance_sampling` and the
        other strategies.
    initial_epochs : int, default=100
        Epochs of the initial training (``e0``).
    epochs_per_query : int, default=50
        Epochs of training after each :meth:`teach` (``e``).
    max_reservoir : int or None, default=None
        Largest training set per :meth:`teach` (``M``). When the reservoir
        holds more samples, a random subset of this size is used. ``None``
        always trains on the whole reservoir. Must be at least the number of
        presses passed to one :meth:`teach`.
    n_samples : int, default=50
        MC-dropout passes per :meth:`query` (``n``): the ``n_samples`` of
        :meth:`predict_proba_samples`, under the same name everywhere
        (the experiments' configuration, ``reproduce --set``).
    classes : array-like or None, default=None
        All class labels (reference objects). Every class must be in the
        initial training set. ``None`` takes them from the final
        estimator's ``classes`` parameter if set, else from ``y`` in
        :meth:`fit`; integer labels must then be ``0 .. n_classes - 1``
        with none missing.
    cache_test_features : bool, default=True
        For a Pipeline, keep the feature-step output of the last ``X``
        passed to :meth:`query`, :meth:`predict`, :meth:`predict_proba`,
        :meth:`predict_proba_samples` or :meth:`score`, reused while the
        *same object* is passed again (the test presses are evaluated every
        iteration). Set to False if you modify ``X`` in place between calls.
    random_state : int, RandomState instance or None, default=None
        Seeds the reservoir subsets, the MC-dropout masks, tie-breaking and
        the random strategy; with an int, training (weight init, batch
        order, dropout) is seeded too, through a forked torch RNG that
        leaves the global torch seed untouched.
    stop_threshold : float in (0, 1] or None, default=None
        Optional stopping rule (not in the paper; ``None``, the default,
        turns it off and Algorithm 1 runs unchanged). The *decision* on the
        test object is the class with the highest mean MC probability
        (mean over the passes and test presses of a :meth:`query`, recorded
        as ``"decision"`` and ``"confidence"`` in ``history_``). The decision
        is *settled*, and :meth:`query` sets ``stop_reason_ = "settled"``,
        when that mean probability is at least ``stop_threshold``
        and the decision was the same in the last ``stop_patience``
        queries. It reads the same seeded MC passes as the strategy and
        draws no random numbers, so turning it on changes no query.
    stop_patience : int, default=2
        Number of consecutive queries (this one included) whose decision
        must agree before the rule stops (``k``).
    max_presses : int or None, default=None
        Press budget: the most presses :meth:`teach` may add after
        :meth:`fit` (the hard cap, with or without ``stop_threshold``).
        A :meth:`teach` that would exceed it raises and adds nothing; the
        first :meth:`query` after the budget is spent sets
        ``stop_reason_ = "budget"``. ``None``: no budget.

    Attributes
    ----------
    estimator_ : estimator
        The trained clone of ``estimator``.
    classes_ : ndarray of shape (n_classes,)
        Class labels; :meth:`query` returns indices into this array.
    reservoir_X_ : ndarray, tensor or list
        The training reservoir: for a Pipeline, the output of its feature
        steps; otherwise the raw samples.
    reservoir_y_ : ndarray of shape (n_reservoir,)
        Labels of the reservoir.
    history_ : list of dict
        One entry per event, in order; ``pandas.DataFrame(history_)`` gives a
        table. Every entry has ``"event"`` (``"fit"``, ``"query"`` or
        ``"teach"``) and ``"iteration"`` (number of :meth:`teach` calls so
        far). ``"fit"`` and ``"teach"`` entries have ``n_new``,
        ``new_classes``, ``reservoir_size``, ``train_size``, ``epochs`` (run,
        fewer than asked when a callback such as skorch's ``EarlyStopping``
        stopped the training; None for an estimator refit from scratch) and
        ``train_loss`` (the last epoch's training loss for a skorch net,
        else None). ``"query"`` entries have ``queried`` (class indices),
        ``scores`` (the strategy's per-class scores or None), ``n_test``,
        the per-class ``entropy``, ``variance`` and ``bald`` of the
        same MC passes (see :func:`class_uncertainty`), and the two parts of
        the variance, ``variance_mc`` and ``variance_between`` (see
        :func:`variance_decomposition`; they sum to ``variance``), the
        ``decision`` on the test object (class index of the highest mean MC
        probability), its ``confidence`` (that mean probability) and
        ``stop`` (the stopping rule's verdict: ``"settled"``, ``"budget"``
        or None).
    initial_train_loss_ : float or None
        Training loss after the initial training (the paper reports
        ConvLSTM runs with a loss above 1 as not converged).
    n_iterations_ : int
        Number of :meth:`teach` calls since :meth:`fit`.
    n_presses_ : int
        Presses added by :meth:`teach` since :meth:`fit`.
    stop_reason_ : {"settled", "budget"} or None
        Why the run should stop, set by the first :meth:`query` that found
        the decision settled or the press budget spent; None until then
        (always None without ``stop_threshold`` and ``max_presses``).
    stop_iteration_ : int or None
        ``n_iterations_`` (teaches so far) when ``stop_reason_`` was set.

    See Also
    --------
    PressOracle : draws new presses of a queried reference object.
    class_uncertainty : the per-class scores.

    Examples
    --------
    One active-sampling run (Algorithm 1) in a few lines, with ``clf`` a
    Monte-Carlo-dropout classifier and ``oracle`` a :class:`PressOracle`::

        X0, y0 = oracle.initial(5)                 # s0 = 5 presses per object
        learner = ActiveLearner(clf, "variance", initial_epochs=100,
                                epochs_per_query=50, max_reservoir=40)
        learner.fit(X0, y0)
        for _ in range(5):                         # N = 5 iterations
            idx, scores = learner.query(X_test)
            learner.teach(*oracle.press(learner.classes_[idx[0]], 5))
            acc = learner.score(X_test, y_test)    # dropout off

    With the stopping rule, press until the decision is settled, at most 25
    presses::

        learner = ActiveLearner(clf, "variance", stop_threshold=0.9,
                                stop_patience=2, max_presses=25).fit(X0, y0)
        while True:
            idx, _ = learner.query(X_test)
            if learner.stop_reason_ is not None:   # "settled" or "budget"
                break
            learner.teach(*oracle.press(learner.classes_[idx[0]], 5))
        decision = learner.history_[-1]["decision"]

    A runnable version on blobs:

    >>> import numpy as np
    >>> from sklearn.discriminant_analysis import LinearDiscriminantAnalysis
    >>> from sklearn_hardness.active import ActiveLearner, PressOracle
    >>> class BootstrapLDA(LinearDiscriminantAnalysis):
    ...     # "MC passes" from LDAs fit on bootstrap resamples of the training set
    ...     def fit(self, X, y):
    ...         self.X_, self.y_ = X, y
    ...         return super().fit(X, y)
    ...     def predict_proba_samples(self, X, n_samples=50, random_state=None):
    ...         rng = np.random.default_rng(random_state)
    ...         out = []
    ...         for _ in range(n_samples):
    ...             i = rng.choice(len(self.y_), len(self.y_))
    ...             i = np.concatenate([i, np.unique(self.y_, return_index=True)[1]])
    ...             lda = LinearDiscriminantAnalysis().fit(self.X_[i], self.y_[i])
    ...             out.append(lda.predict_proba(X))
    ...         return np.stack(out)
    >>> rng = np.random.default_rng(0)
    >>> y = np.repeat([0, 1, 2], 30)
    >>> X = rng.normal(size=(90, 2)) + 4.0 * np.eye(3)[y][:, :2]
    >>> oracle = PressOracle(X, y, random_state=0)
    >>> X_test, _ = oracle.press(1, 4)          # presses of the test object
    >>> learner = ActiveLearner(BootstrapLDA(), "margin", n_samples=10,
    ...                         stop_threshold=0.9, max_presses=15, random_state=0)
    >>> _ = learner.fit(*oracle.initial(3))
    >>> while True:
    ...     idx, _ = learner.query(X_test)
    ...     if learner.stop_reason_ is not None:
    ...         break
    ...     _ = learner.teach(*oracle.press(learner.classes_[idx[0]], 5))
    >>> learner.stop_reason_, learner.n_presses_, learner.history_[-1]["decision"]
    ('settled', 5, 1)
    """

    _parameter_constraints = {
        "estimator": [HasMethods(["fit"])],
        "query_strategy": [StrOptions(set(STRATEGY_NAMES)), callable],
        "initial_epochs": [Interval(Integral, 1, None, closed="left")],
        "epochs_per_query": [Interval(Integral, 1, None, closed="left")],
        "max_reservoir": [Interval(Integral, 1, None, closed="left"), None],
        "n_samples": [Interval(Integral, 1, None, closed="left")],
        "classes": ["array-like", None],
        "cache_test_features": ["boolean"],
        "random_state": ["random_state"],
        "stop_threshold": [Interval(Real, 0, 1, closed="right"), None],
        "stop_patience": [Interval(Integral, 1, None, closed="left")],
        "max_presses": [Interval(Integral, 1, None, closed="left"), None],
    }

    def __init__(
        self,
        estimator,
        query_strategy=variance_sampling,
        *,
        initial_epochs=100,
        epochs_per_query=50,
        max_reservoir=None,
        n_samples=50,
        classes=None,
        cache_test_features=True,
        random_state=None,
        stop_threshold=None,
        stop_patience=2,
        max_presses=None,
    ):
        self.estimator = estimator
        self.query_strategy = query_strategy
        self.initial_epochs = initial_epochs
        self.epochs_per_query = epochs_per_query
        self.max_reservoir = max_reservoir
        self.n_samples = n_samples
        self.classes = classes
        self.cache_test_features = cache_test_features
        self.random_state = random_state
        self.stop_threshold = stop_threshold
        self.stop_patience = stop_patience
        self.max_presses = max_presses

    def __getstate__(self):
        # the cached test features are a convenience, not state worth pickling
        state = super().__getstate__()
        state.pop("_feature_cache", None)
        return state

    # ------------------------------------------------------------------ helpers
    def _final(self):
        est = self.estimator_
        return est.steps[-1][1] if isinstance(est, Pipeline) else est

    def _has_feature_steps(self):
        return isinstance(self.estimator_, Pipeline) and len(self.estimator_.steps) > 1

    def _transform(self, X, *, cache=False):
        if not self._has_feature_steps():
            return X
        if cache and self.cache_test_features:
            cached = getattr(self, "_feature_cache", None)
            if cached is not None and cached[0] is X:
                return cached[1]
        # scikit-learn's own slicing: skips "passthrough" steps as Pipeline does
        Xt = self.estimator_[:-1].transform(X)
        if cache and self.cache_test_features:
            self._feature_cache = (X, Xt)
        return Xt

    @contextlib.contextmanager
    def _seeded_torch(self):
        if self.random_state is None:
            yield
            return
        seed = int_seed(self._rng)
        final = self._final()
        if getattr(final, "_own_torch_generators", False) and final.random_state is not None:
            # our nets draw from their own generators, seeded by random_state: no
            # need to seed (and lock) torch's process-wide generator for the training
            yield
            return
        # other torch code draws from the global generator: seed it, and hold the
        # lock so that runs in other threads cannot reseed it meanwhile
        with seeded_torch_rng(seed):
            yield

    def _train(self, Xt, y, epochs):
        """Train; return the last training loss and the number of epochs run."""
        final = self._final()
        before = self._n_history_rows() or 0  # an uninitialised net has no history yet: 0 rows
        with self._seeded_torch():
            if _trains_in_epochs(final):
                # the clone is uninitialised, so the first partial_fit initialises
                # it; later calls continue (module, optimizer state, history)
                final.partial_fit(Xt, y, classes=self.classes_, epochs=epochs)
            else:
                final.fit(Xt, y)
        after = self._n_history_rows()
        if after is not None and after >= before:
            run = after - before  # fewer than asked when a callback (EarlyStopping) stopped it
        else:
            run = epochs if _trains_in_epochs(final) else None
        return self._last_train_loss(), run

    def _n_history_rows(self):
        hist = getattr(self._final(), "history_", None)
        return None if hist is None else len(hist)

    def _last_train_loss(self):
        hist = getattr(self._final(), "history_", None)
        if hist is None:
            return None
        try:
            return float(hist[-1, "train_loss"])
        except (KeyError, IndexError, TypeError, ValueError):
            return None

    def _check_labels(self, y, what):
        y = np.asarray(y)
        if y.ndim != 1:
            raise ValueError(f"{what} must be 1-D, got shape {y.shape}.")
        unknown = np.setdiff1d(np.unique(y), self.classes_)
        if unknown.size:
            raise ValueError(
                f"{what} has labels {unknown.tolist()} that are not among the "
                f"classes {self.classes_.tolist()}."
            )
        return y

    def _resolve_classes(self, y):
        classes = self.classes
        if classes is None and isinstance(self.estimator, Pipeline):
            classes = getattr(self.estimator.steps[-1][1], "classes", None)
        elif classes is None:
            classes = getattr(self.estimator, "classes", None)
        present = np.unique(y)
        if classes is not None and len(classes) > 0:
            classes = np.asarray(classes)
            if np.unique(classes).size != classes.size:
                raise ValueError(f"classes has duplicates: {classes.tolist()}.")
            classes = np.sort(classes)
        elif np.issubdtype(present.dtype, np.integer):
            if present.min() < 0:
                raise ValueError(
                    f"integer labels must be class indices 0 .. n_classes - 1, got "
                    f"{present.min()}."
                )
            classes = np.arange(present.max() + 1)
        else:
            classes = present
        unknown = np.setdiff1d(present, classes)
        if unknown.size:
            raise ValueError(
                f"y has labels {unknown.tolist()} that are not among the classes "
                f"{classes.tolist()}."
            )
        missing = np.setdiff1d(classes, present)
        if missing.size:
            raise ValueError(
                f"classes {missing.tolist()} are missing from the initial training "
                "set: every reference object needs initial presses (s0 > 0) before "
                "active sampling can choose between them. (Without classes=..., "
                "integer labels are taken as class indices 0 .. n_classes - 1; pass "
                "classes=[...] to declare the labels explicitly.)"
            )
        return classes

    def _n_out_check(self, n_out):
        if n_out != len(self.classes_):
            raise ValueError(
                f"the model outputs {n_out} class probabilities but there are "
                f"{len(self.classes_)} classes {self.classes_.tolist()}; the model's "
                "number of classes must match the labels seen in fit."
            )

    # ------------------------------------------------------------------ API
    @fit_context(prefer_skip_nested_validation=False)
    def fit(self, X, y):
        """Initial training on the first presses of every reference object.

        Parameters
        ----------
        X : array-like or sequence of videos
            Initial presses (``s0`` per reference object). For a Pipeline,
            raw input of its first step.
        y : array-like of shape (n_presses,)
            Their labels. Every class must be present.

        Returns
        -------
        self : ActiveLearner
        """
        if not (hasattr(X, "__len__") or hasattr(X, "shape")):
            raise TypeError(f"X must be an array or a sequence, got {type(X).__name__}.")
        y = np.asarray(y)
        if y.ndim != 1:
            raise ValueError(f"y must be 1-D, got shape {y.shape}.")
        n = n_rows(X)
        if n == 0:
            raise ValueError("X is empty: the initial training set needs presses.")
        if n != y.shape[0]:
            raise ValueError(f"X has {n} samples but y has {y.shape[0]} labels.")

        self.classes_ = self._resolve_classes(y)
        self._rng = check_random_state(self.random_state)
        self._feature_cache = None
        self.estimator_ = clone(self.estimator)
        if not hasattr(self._final(), "predict_proba_samples"):
            raise TypeError(
                f"{type(self._final()).__name__} has no predict_proba_samples: active "
                "sampling needs a Monte-Carlo-dropout classifier (e.g. "
                "sklearn_hardness.models.OFNNClassifier) or a Pipeline ending in one."
            )
        Xt = self.estimator_[:-1].fit_transform(X, y) if self._has_feature_steps() else X
        loss, epochs_run = self._train(Xt, y, self.initial_epochs)
        final_classes = getattr(self._final(), "classes_", None)
        if final_classes is not None and not (
            len(final_classes) == len(self.classes_)
            and np.array_equal(np.asarray(final_classes), self.classes_)
        ):
            raise ValueError(
                f"the trained estimator's classes_ {np.asarray(final_classes).tolist()} "
                f"differ from the learner's classes {self.classes_.tolist()}; pass the "
                "same classes=[...] to both."
            )
        self.reservoir_X_ = Xt
        self.reservoir_y_ = y.copy()
        self.n_iterations_ = 0
        self.n_presses_ = 0
        self.stop_reason_ = None
        self.stop_iteration_ = None
        self.initial_train_loss_ = loss
        self.history_ = [
            {
                "event": "fit",
                "iteration": 0,
                "n_new": n,
                "new_classes": np.unique(y),
                "reservoir_size": n,
                "train_size": n,
                "epochs": epochs_run,
                "train_loss": loss,
            }
        ]
        return self

    @validate_params(
        {
            "n_samples": [Interval(Integral, 1, None, closed="left"), None],
            "random_state": ["random_state"],
        },
        prefer_skip_nested_validation=True,
    )
    def predict_proba_samples(self, X, n_samples=None, random_state=None):
        """Class probabilities of MC-dropout passes (dropout on).

        Parameters
        ----------
        X : array-like or sequence of videos
            Inputs (raw input of the Pipeline's first step).
        n_samples : int or None, default=None
            Number of passes; ``None`` uses the ``n_samples`` parameter.
        random_state : int, RandomState instance or None, default=None
            Seed for the dropout masks.

        Returns
        -------
        proba_samples : ndarray of shape (n_samples, n_X, n_classes)
        """
        check_is_fitted(self, "estimator_")
        n_samples = self.n_samples if n_samples is None else n_samples
        proba = self._final().predict_proba_samples(
            self._transform(X, cache=True), n_samples=n_samples, random_state=random_state
        )
        proba = np.asarray(proba)
        self._n_out_check(proba.shape[-1])
        return proba

    @validate_params(
        {"n_instances": [Interval(Integral, 1, None, closed="left")]},
        prefer_skip_nested_validation=True,
    )
    def query(self, X_test, n_instances=1):
        """Choose the reference object(s) to press next.

        Runs ``n_samples`` MC-dropout passes on the test presses once,
        hands those probabilities to the query strategy, and records in
        ``history_`` the strategy's choice and the per-class entropy,
        variance, BALD and the two parts of the variance of the same passes.

        Parameters
        ----------
        X_test : array-like or sequence of videos
            Presses of the test object (at least one).
        n_instances : int, default=1
            Number of distinct classes to return.

        Returns
        -------
        class_indices : ndarray of shape (n_instances,), int
            Indices into ``classes_``, most informative first.
        scores : ndarray of shape (n_classes,) or None
            The strategy's per-class scores (None if a custom strategy
            returns indices only).
        """
        check_is_fitted(self, "estimator_")
        validate_estimator_params(self)  # set_params may have changed them since fit
        strategy = get_strategy(self.query_strategy)
        if X_test is None:
            raise ValueError("X_test is None; pass presses of the test object.")
        if n_rows(X_test) == 0:
            raise ValueError(
                "X_test is empty: uncertainty strategies need at least one press of "
                "the test object."
            )
        proba = self.predict_proba_samples(
            X_test, n_samples=self.n_samples, random_state=int_seed(self._rng)
        )
        kwargs = {"random_state": int_seed(self._rng)}
        kwargs = {k: v for k, v in kwargs.items() if k in _accepts_kwargs(strategy, kwargs)}
        result = strategy(proba, n_instances, **kwargs)
        if isinstance(result, tuple) and len(result) == 2:
            idx, scores = result
            scores = None if scores is None else np.asarray(scores, dtype=np.float64)
        else:
            idx, scores = result, None
        idx = np.atleast_1d(np.asarray(idx))
        n_classes = len(self.classes_)
        if (
            idx.ndim != 1
            or not np.issubdtype(idx.dtype, np.integer)
            or np.any(idx < 0)
            or np.any(idx >= n_classes)
        ):
            raise ValueError(
                f"the query strategy must return class indices in [0, {n_classes}), "
                f"got {idx!r}."
            )
        mu = np.asarray(proba, dtype=np.float64).mean(axis=(0, 1))
        entry = {
            "event": "query",
            "iteration": self.n_iterations_,
            "queried": idx,
            "scores": scores,
            "n_test": int(proba.shape[1]),
            "decision": int(np.argmax(mu)),
            "confidence": float(mu.max()),
        }
        for kind in UNCERTAINTY_KINDS:
            entry[kind] = class_uncertainty(proba, kind)
        parts = variance_decomposition(proba)
        entry["variance_mc"], entry["variance_between"] = parts["mc"], parts["between"]
        entry["stop"] = self._stop_reason(entry)
        if entry["stop"] is not None and self.stop_reason_ is None:
            self.stop_reason_, self.stop_iteration_ = entry["stop"], self.n_iterations_
        self.history_.append(entry)
        return idx, scores

    def _stop_reason(self, entry):
        """"settled", "budget" or None for a new query entry (see ``stop_threshold``)."""
        if self.stop_threshold is not None and entry["confidence"] >= self.stop_threshold:
            decisions = [h["decision"] for h in self.history_ if h["event"] == "query"]
            recent = (decisions + [entry["decision"]])[-self.stop_patience :]
            if len(recent) == self.stop_patience and len(set(recent)) == 1:
                return "settled"
        if self.max_presses is not None and self.n_presses_ >= self.max_presses:
            return "budget"
        return None

    def teach(self, X_new, y_new):
        """Add presses to the reservoir and continue training.

        Trains ``epochs_per_query`` epochs (warm start) on the whole
        reservoir, or on a random subset of ``max_reservoir`` samples when
        the reservoir is larger.

        Parameters
        ----------
        X_new : array-like or sequence of videos
            New presses (raw input of the Pipeline's first step).
        y_new : array-like of shape (n_new,)
            Their labels (must be among ``classes_``).

        Returns
        -------
        self : ActiveLearner
        """
        if not hasattr(self, "estimator_"):
            raise NotFittedError(
                "teach() called before fit(): train on the initial presses first."
            )
        y_new = self._check_labels(y_new, "y_new")
        n_new = n_rows(X_new)
        if n_new == 0:
            raise ValueError("X_new is empty: teach() needs at least one new press.")
        if n_new != y_new.shape[0]:
            raise ValueError(f"X_new has {n_new} samples but y_new has {y_new.shape[0]} labels.")
        if self.max_presses is not None and self.n_presses_ + n_new > self.max_presses:
            raise ValueError(
                f"teaching {n_new} presses would exceed the press budget "
                f"max_presses={self.max_presses} ({self.n_presses_} used); nothing "
                "was added."
            )
        M = self.max_reservoir
        if M is not None and M < n_new:
            raise ValueError(
                f"max_reservoir={M} is smaller than the batch of {n_new} new presses; "
                "the training subset could not even hold one batch. Increase "
                "max_reservoir or teach fewer presses at a time."
            )
        Xt_new = self._transform(X_new)
        self.reservoir_X_ = concat_rows(self.reservoir_X_, Xt_new)
        self.reservoir_y_ = np.concatenate([self.reservoir_y_, y_new])
        size = self.reservoir_y_.shape[0]
        # a model refitted from scratch must see every class; a net is told them (partial_fit's classes)
        X_train, y_train = training_subset(self.reservoir_X_, self.reservoir_y_, M, self._rng,
                                           keep_classes=not _trains_in_epochs(self._final()))
        loss, epochs_run = self._train(X_train, y_train, self.epochs_per_query)
        self.n_iterations_ += 1
        self.n_presses_ += n_new
        self.history_.append(
            {
                "event": "teach",
                "iteration": self.n_iterations_,
                "n_new": n_new,
                "new_classes": np.unique(y_new),
                "reservoir_size": size,
                "train_size": int(y_train.shape[0]),
                "epochs": epochs_run,
                "train_loss": loss,
            }
        )
        return self

    def predict_proba(self, X):
        """Class probabilities with dropout off.

        Parameters
        ----------
        X : array-like or sequence of videos

        Returns
        -------
        proba : ndarray of shape (n_X, n_classes)
        """
        check_is_fitted(self, "estimator_")
        proba = np.asarray(self._final().predict_proba(self._transform(X, cache=True)))
        self._n_out_check(proba.shape[-1])
        return proba

    def predict(self, X):
        """Predicted class labels with dropout off.

        Parameters
        ----------
        X : array-like or sequence of videos

        Returns
        -------
        y_pred : ndarray of shape (n_X,)
        """
        proba = self.predict_proba(X)  # NotFittedError before fit
        return self.classes_[np.argmax(proba, axis=1)]

    def score(self, X, y, sample_weight=None):
        """Accuracy with dropout off.

        Parameters
        ----------
        X : array-like or sequence of videos
        y : array-like of shape (n_X,)
        sample_weight : array-like of shape (n_X,), default=None

        Returns
        -------
        accuracy : float
        """
        return accuracy_score(y, self.predict(X), sample_weight=sample_weight)

    @validate_params(
        {
            "kind": [StrOptions({*UNCERTAINTY_KINDS, "variance_mc", "variance_between"})],
            "reduce": [StrOptions({"mean", "max"}), None],
        },
        prefer_skip_nested_validation=True,
    )
    def uncertainty_history(self, kind="variance", reduce="mean"):
        """Per-query uncertainty, e.g. for the paper's entropy/variance plots.

        Parameters
        ----------
        kind : {"entropy", "variance", "bald", "variance_mc", "variance_between"}, \
                default="variance"
            Which per-class value of the ``history_`` query entries.
        reduce : {"mean", "max", None}, default="mean"
            How to reduce over classes; None keeps all classes.

        Returns
        -------
        values : ndarray of shape (n_queries,) or (n_queries, n_classes)
        """
        check_is_fitted(self, "estimator_")
        rows = [h[kind] for h in self.history_ if h["event"] == "query"]
        values = np.array(rows).reshape(len(rows), len(self.classes_))
        if reduce is None:
            return values
        return getattr(values, reduce)(axis=1)
