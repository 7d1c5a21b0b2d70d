"""Query strategies that pick the reference object (class) to press next.

The strategies follow modAL's calling convention,
``strategy(learner, X, n_instances=1, **kwargs)``, but they answer a
different question than modAL's pool-based strategies: they do not pick
samples of ``X`` to label. ``X`` holds presses of the *test object*; the
strategy returns the *classes* (reference objects) whose uncertainty on
those presses is highest, and the agent then presses those reference
objects to collect more training data (Algorithm 1 of the paper).
"""

from __future__ import annotations

import numbers

import numpy as np
from sklearn.pipeline import Pipeline
from sklearn.utils import check_random_state

from ._uncertainty import class_uncertainty

__all__ = [
    "entropy_sampling",
    "variance_sampling",
    "bald_sampling",
    "random_sampling",
    "get_strategy",
]


def _n_rows(X):
    if hasattr(X, "shape") and getattr(X, "ndim", 1) >= 1:
        return X.shape[0]
    return len(X)


def _seed_from(rng):
    """An int seed drawn from a RandomState (for APIs that want an int)."""
    return int(rng.randint(np.iinfo(np.int32).max))


def _predict_proba_samples(estimator, X, *, n_samples=50, random_state=None):
    """MC-dropout probabilities from an estimator, a Pipeline or a modAL learner.

    Parameters
    ----------
    estimator : object
        One of: an object with ``predict_proba_samples`` (our nets,
        :class:`ActiveLearner`); a :class:`~sklearn.pipeline.Pipeline` whose
        last step has it (``X`` goes through the earlier steps' ``transform``
        first); or an object with an ``estimator`` attribute that is one of
        these (e.g. ``modAL.models.ActiveLearner``).
    X : array-like or sequence of videos
        Test inputs.
    n_samples : int, default=50
        Number of stochastic forward passes.
    random_state : int, RandomState instance or None, default=None
        Seed for the dropout masks.

    Returns
    -------
    proba_samples : ndarray of shape (n_samples, n_X, n_classes)
    """
    if hasattr(estimator, "predict_proba_samples"):
        return estimator.predict_proba_samples(
            X, n_samples=n_samples, random_state=random_state
        )
    if isinstance(estimator, Pipeline):
        Xt = X
        for _, step in estimator.steps[:-1]:
            if step is None or step == "passthrough":
                continue
            Xt = step.transform(Xt)
        return _predict_proba_samples(
            estimator.steps[-1][1], Xt, n_samples=n_samples, random_state=random_state
        )
    inner = getattr(estimator, "estimator", None)
    if inner is not None and inner is not estimator:
        return _predict_proba_samples(
            inner, X, n_samples=n_samples, random_state=random_state
        )
    raise TypeError(
        f"{type(estimator).__name__} has no predict_proba_samples: uncertainty "
        "strategies need a Monte-Carlo-dropout classifier (e.g. "
        "sklearn_hardness.models.OFNNClassifier), a Pipeline ending in one, or "
        "a learner wrapping one."
    )


def _n_classes(learner):
    """Number of classes of a fitted learner, estimator, Pipeline or modAL learner."""
    for obj in (learner, getattr(learner, "estimator_", None), getattr(learner, "estimator", None)):
        if obj is None:
            continue
        if isinstance(obj, Pipeline):
            obj = obj.steps[-1][1]
        try:
            classes = obj.classes_
        except AttributeError:
            continue
        return len(classes)
    raise TypeError(
        f"cannot tell the number of classes of {type(learner).__name__}: it has "
        "no classes_ attribute. Fit it first."
    )


def _check_n_instances(n_instances, n_classes):
    if (
        isinstance(n_instances, bool)
        or not isinstance(n_instances, numbers.Integral)
        or n_instances < 1
    ):
        raise ValueError(f"n_instances must be a positive int, got {n_instances!r}.")
    if n_instances > n_classes:
        raise ValueError(
            f"n_instances={n_instances} is larger than the number of classes "
            f"({n_classes}); a strategy picks distinct classes."
        )


def _check_test_set(X):
    if X is None:
        raise ValueError("X_test is None; pass presses of the test object.")
    try:
        n = _n_rows(X)
    except TypeError:
        raise TypeError(
            f"X_test must be an array or a sequence of presses, got {type(X).__name__}."
        ) from None
    if n == 0:
        raise ValueError(
            "X_test is empty: uncertainty strategies need at least one press of "
            "the test object."
        )


def _top_classes(scores, n_instances, rng):
    """Indices of the n_instances highest scores, best first.

    Exactly equal scores are ordered by a random permutation drawn from
    ``rng``, so ties (e.g. uniform predictions) do not always favour class 0.
    """
    tiebreak = rng.permutation(scores.shape[0])
    order = np.lexsort((tiebreak, -scores))
    return order[:n_instances].astype(np.intp)


def _uncertainty_sampling(kind, learner, X_test, n_instances, n_samples, random_state):
    _check_test_set(X_test)
    if (
        isinstance(n_samples, bool)
        or not isinstance(n_samples, numbers.Integral)
        or n_samples < 1
    ):
        raise ValueError(f"n_samples must be a positive int, got {n_samples!r}.")
    rng = check_random_state(random_state)
    proba = _predict_proba_samples(
        learner, X_test, n_samples=int(n_samples), random_state=_seed_from(rng)
    )
    scores = class_uncertainty(proba, kind)
    _check_n_instances(n_instances, scores.shape[0])
    return _top_classes(scores, n_instances, rng), scores


_RETURNS = """
    Returns
    -------
    class_indices : ndarray of shape (n_instances,), int
        The chosen classes (indices into the learner's ``classes_``),
        highest score first. Exactly tied scores are ordered at random
        (seeded by ``random_state``).
    scores : ndarray of shape (n_classes,), float64
        The score of every class (not only the chosen ones), so the choice
        can be inspected or plotted.

    Notes
    -----
    The return value is the pair ``(class_indices, scores)`` that
    ``modAL.models.ActiveLearner.query`` expects from a strategy (modAL
    >= 0.4 unpacks ``query_result, query_metrics``; an index-only array of
    length 2 would be silently split into one index and one "metric"). The
    indices are
    *class* indices, not rows of ``X_test``: modAL's ``query`` also returns
    ``X_test[class_indices]``, which is meaningless here (and fails when
    ``X_test`` has fewer rows than the chosen index).
"""


def _make_doc(kind, eq):
    return f"""Pick the class(es) whose MC-dropout {kind} on the test presses is highest.

    {eq}
    See :func:`class_uncertainty` for the exact definition.

    Parameters
    ----------
    learner : estimator
        A fitted Monte-Carlo-dropout classifier with
        ``predict_proba_samples``, a :class:`~sklearn.pipeline.Pipeline`
        ending in one, an :class:`ActiveLearner`, or a
        ``modAL.models.ActiveLearner`` wrapping one of these.
    X_test : array-like or sequence of videos
        Presses of the test object (at least one).
    n_instances : int, default=1
        How many distinct classes to return.
    n_samples : int, default=50
        Number of MC-dropout forward passes.
    random_state : int, RandomState instance or None, default=None
        Seeds the dropout masks and the tie-breaking.
{_RETURNS}"""


def entropy_sampling(learner, X_test, n_instances=1, *, n_samples=50, random_state=None):
    return _uncertainty_sampling(
        "entropy", learner, X_test, n_instances, n_samples, random_state
    )


def variance_sampling(learner, X_test, n_instances=1, *, n_samples=50, random_state=None):
    return _uncertainty_sampling(
        "variance", learner, X_test, n_instances, n_samples, random_state
    )


def bald_sampling(learner, X_test, n_instances=1, *, n_samples=50, random_state=None):
    return _uncertainty_sampling(
        "bald", learner, X_test, n_instances, n_samples, random_state
    )


entropy_sampling.__doc__ = _make_doc(
    "entropy", "Eq. 1 of the paper: the mean of -p log p over passes and test presses."
) + """
    Examples
    --------
    >>> import numpy as np
    >>> from sklearn_hardness.active import entropy_sampling
    >>> class Net:  # any fitted classifier with predict_proba_samples
    ...     classes_ = np.arange(3)
    ...     def predict_proba_samples(self, X, n_samples=50, random_state=None):
    ...         p = np.tile([0.7, 0.2, 0.1], (n_samples, len(X), 1))
    ...         return p
    >>> idx, scores = entropy_sampling(Net(), np.zeros((4, 2)), n_instances=2)
    >>> idx  # -0.2 log 0.2 > -0.7 log 0.7 > -0.1 log 0.1
    array([1, 0])
"""
variance_sampling.__doc__ = _make_doc(
    "variance",
    "Eq. 2 of the paper: the variance of p pooled over passes and test presses.",
)
bald_sampling.__doc__ = _make_doc(
    "BALD mutual information",
    "Our addition: each class's share of the mutual information between the "
    "prediction and the dropout mask.",
)


def random_sampling(learner, X_test, n_instances=1, *, n_samples=50, random_state=None):
    """Pick class(es) uniformly at random (the paper's baseline).

    No forward pass is run; only the number of classes of the fitted
    ``learner`` is used.

    Parameters
    ----------
    learner : estimator
        A fitted classifier with ``classes_`` (or a Pipeline/learner
        wrapping one).
    X_test : array-like or sequence of videos
        Presses of the test object (checked to be non-empty, otherwise
        unused).
    n_instances : int, default=1
        How many distinct classes to return.
    n_samples : int, default=50
        Unused; accepted so all strategies share one signature.
    random_state : int, RandomState instance or None, default=None
        Seeds the choice.

    Returns
    -------
    class_indices : ndarray of shape (n_instances,), int
        Distinct classes drawn uniformly without replacement.
    scores : ndarray of shape (n_classes,), float64
        Uniform random priorities in [0, 1); ``class_indices`` are the
        classes with the highest priorities, so "highest score first"
        holds as for the other strategies.
    """
    _check_test_set(X_test)
    n_classes = _n_classes(learner)
    _check_n_instances(n_instances, n_classes)
    rng = check_random_state(random_state)
    scores = rng.random_sample(n_classes)
    return _top_classes(scores, n_instances, rng), scores


_STRATEGIES = {
    "entropy": entropy_sampling,
    "variance": variance_sampling,
    "bald": bald_sampling,
    "random": random_sampling,
}


def get_strategy(strategy):
    """Return the strategy callable for a name or a callable.

    Parameters
    ----------
    strategy : {"entropy", "variance", "bald", "random"} or callable
        A strategy name, or a callable
        ``strategy(learner, X_test, n_instances=1, **kwargs)``.

    Returns
    -------
    strategy : callable

    Raises
    ------
    ValueError
        For an unknown name.
    TypeError
        For something that is neither a string nor callable.

    Examples
    --------
    >>> from sklearn_hardness.active import get_strategy
    >>> get_strategy("variance").__name__
    'variance_sampling'
    """
    if isinstance(strategy, str):
        try:
            return _STRATEGIES[strategy]
        except KeyError:
            raise ValueError(
                f"unknown query strategy {strategy!r}; choose one of "
                f"{sorted(_STRATEGIES)} or pass a callable."
            ) from None
    if callable(strategy):
        return strategy
    raise TypeError(
        f"query_strategy must be a strategy name or a callable, got "
        f"{type(strategy).__name__}."
    )
