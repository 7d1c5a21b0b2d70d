"""Use the class-level strategies as modAL query strategies."""

from __future__ import annotations

import functools
from numbers import Integral

import numpy as np
from sklearn.pipeline import Pipeline
from sklearn.utils import check_random_state

from ..utils._param_validation import Interval, validate_params

__all__ = ["as_modal_strategy"]


def _mc_samples(estimator, X, n_samples, random_state):
    """MC-dropout probabilities from a net, a Pipeline ending in one, or a learner wrapping one."""
    if hasattr(estimator, "predict_proba_samples"):
        return estimator.predict_proba_samples(X, n_samples=n_samples, random_state=random_state)
    if isinstance(estimator, Pipeline) and hasattr(estimator[-1], "predict_proba_samples"):
        Xt = estimator[:-1].transform(X)
        return estimator[-1].predict_proba_samples(Xt, n_samples=n_samples, random_state=random_state)
    inner = getattr(estimator, "estimator", None)  # modAL's ActiveLearner
    if inner is not None and inner is not estimator:
        return _mc_samples(inner, X, n_samples, random_state)
    raise TypeError(
        f"{type(estimator).__name__} has no predict_proba_samples: uncertainty "
        "strategies need a Monte-Carlo-dropout classifier (e.g. "
        "sklearn_hardness.models.OFNNClassifier), a Pipeline ending in one, or "
        "a learner wrapping one."
    )


@validate_params(
    {"strategy": [callable], "n_samples": [Interval(Integral, 1, None, closed="left")]},
    prefer_skip_nested_validation=True,
)
def as_modal_strategy(strategy, n_samples=50):
    """Adapt a class-level strategy to modAL's ``query_strategy`` convention.

    modAL calls ``query_strategy(learner, X, n_instances=1, **kwargs)``;
    our strategies are functions of MC-dropout probabilities. The adapter
    runs ``n_samples`` MC-dropout passes of the learner's classifier on
    ``X`` (the test presses) once and hands them to ``strategy``.

    Parameters
    ----------
    strategy : callable
        A strategy such as :func:`variance_sampling`, called as
        ``strategy(proba_samples, n_instances, random_state=...)``.
    n_samples : int, default=50
        MC-dropout passes per query.

    Returns
    -------
    query_strategy : callable
        ``query_strategy(learner, X_test, n_instances=1, *, random_state=None)``
        returning ``(class_indices, scores)``. ``learner`` is a fitted
        classifier with ``predict_proba_samples``, a
        :class:`~sklearn.pipeline.Pipeline` ending in one, or an object
        whose ``estimator`` attribute is one of these
        (``modAL.models.ActiveLearner``). ``random_state`` seeds the
        dropout masks and then the strategy.

    Notes
    -----
    modAL >= 0.4 unpacks ``(query_result, query_metrics)`` from a strategy,
    so the per-class scores come back with ``return_metrics=True``. The
    indices are *class* indices, not rows of ``X_test``: the rows that
    modAL's ``query`` also returns (``X_test[class_indices]``) are
    meaningless here.

    Examples
    --------
    >>> import numpy as np
    >>> from sklearn_hardness.active import as_modal_strategy, entropy_sampling
    >>> class Net:  # any fitted classifier with predict_proba_samples
    ...     def predict_proba_samples(self, X, n_samples=50, random_state=None):
    ...         return np.tile([0.7, 0.2, 0.1], (n_samples, len(X), 1))
    >>> query = as_modal_strategy(entropy_sampling, n_samples=10)
    >>> query(Net(), np.zeros((4, 2)), n_instances=2)[0]
    array([1, 0])
    """

    @functools.wraps(strategy)
    def query_strategy(learner, X_test, n_instances=1, *, random_state=None):
        if X_test is None or len(X_test) == 0:
            raise ValueError(
                "X_test is empty: uncertainty strategies need at least one press of "
                "the test object."
            )
        rng = check_random_state(random_state)
        mc_seed, strategy_seed = (int(s) for s in rng.randint(np.iinfo(np.int32).max, size=2))
        proba = _mc_samples(learner, X_test, n_samples, mc_seed)
        return strategy(proba, n_instances, random_state=strategy_seed)

    return query_strategy
