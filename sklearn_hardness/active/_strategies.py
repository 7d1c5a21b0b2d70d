"""Query strategies: which reference object (class) to press next.

Every strategy is a function of the Monte-Carlo-dropout probabilities that a
classifier gave on presses of the *test object*,
``strategy(proba_samples, n_instances=1, *, random_state=None)``, with
``proba_samples`` of shape ``(n_samples, n_X, n_classes)``, and returns
``(class_indices, scores)``. They answer a different question than modAL's
pool-based strategies: they do not pick rows of ``X`` to label, they pick the
*classes* (reference objects) to press again (Algorithm 1 of the paper).
:class:`ActiveLearner` runs the MC passes once per query and hands them to
the strategy; :func:`as_modal_strategy` adapts a strategy to modAL.
"""

from __future__ import annotations

from numbers import Integral

import numpy as np
from sklearn.utils import check_random_state

from ..utils._param_validation import Interval, StrOptions, validate_params
from ._uncertainty import check_proba_samples, class_uncertainty, variance_decomposition

__all__ = [
    "entropy_sampling",
    "variance_sampling",
    "bald_sampling",
    "margin_sampling",
    "mc_variance_sampling",
    "thompson_sampling",
    "random_sampling",
    "get_strategy",
]

_STRATEGY_PARAMS = {
    "proba_samples": ["array-like"],
    "n_instances": [Interval(Integral, 1, None, closed="left")],
    "random_state": ["random_state"],
}


def _top_classes(scores, n_instances, random_state, *, secondary=None):
    """Indices of the n_instances highest scores, best first.

    Exactly equal scores are ordered by ``secondary`` (highest first) when
    given, then by a random permutation drawn from ``random_state``, so ties
    (e.g. uniform predictions) do not always favour class 0. The permutation
    is drawn in every case, so ``random_state`` advances the same way.
    """
    n_classes = scores.shape[0]
    if n_instances > n_classes:
        raise ValueError(
            f"n_instances={n_instances} is larger than the number of classes "
            f"({n_classes}); a strategy picks distinct classes."
        )
    tiebreak = check_random_state(random_state).permutation(n_classes)
    if secondary is None:
        order = np.lexsort((tiebreak, -scores))
    else:
        order = np.lexsort((tiebreak, -secondary, -scores))
    return order[:n_instances].astype(np.intp)


@validate_params(_STRATEGY_PARAMS, prefer_skip_nested_validation=True)
def entropy_sampling(proba_samples, n_instances=1, *, random_state=None):
    r"""Pick the class(es) whose MC-dropout entropy on the test presses is highest.

    Eq. 1 of the paper, :math:`H_i = -\frac{1}{nl}\sum_{j,k} p_{ijk}\log
    p_{ijk}` over ``n`` passes and ``l`` test presses; see
    :func:`class_uncertainty`.

    Parameters
    ----------
    proba_samples : array-like of shape (n_samples, n_X, n_classes)
        MC-dropout probabilities on the test presses, e.g.
        ``clf.predict_proba_samples(X_test, n_samples=50)``.
    n_instances : int, default=1
        How many distinct classes to return.
    random_state : int, RandomState instance or None, default=None
        Seeds the order of exactly tied scores.

    Returns
    -------
    class_indices : ndarray of shape (n_instances,), int
        The chosen classes (indices into the classifier's ``classes_``),
        highest score first.
    scores : ndarray of shape (n_classes,), float64
        The score of every class, so the choice can be inspected.

    See Also
    --------
    as_modal_strategy : use this strategy in ``modAL.models.ActiveLearner``.

    Examples
    --------
    >>> import numpy as np
    >>> from sklearn_hardness.active import entropy_sampling
    >>> p = np.tile([0.7, 0.2, 0.1], (10, 4, 1))  # 10 passes, 4 presses, 3 classes
    >>> idx, scores = entropy_sampling(p, n_instances=2)
    >>> idx  # -0.2 log 0.2 > -0.7 log 0.7 > -0.1 log 0.1
    array([1, 0])
    """
    scores = class_uncertainty(proba_samples, "entropy")
    return _top_classes(scores, n_instances, random_state), scores


@validate_params(_STRATEGY_PARAMS, prefer_skip_nested_validation=True)
def variance_sampling(proba_samples, n_instances=1, *, random_state=None):
    r"""Pick the class(es) whose pooled MC-dropout variance is highest (the paper's).

    Eq. 2 of the paper, :math:`\mathrm{Var}_i = \frac{1}{nl}\sum_{j,k}
    (p_{ijk}-\mu_i)^2`, pooled over ``n`` passes *and* ``l`` test presses;
    see :func:`class_uncertainty`. By the law of total variance it is the MC
    part plus the between-press part (:func:`variance_decomposition`); when
    the between-press part dominates, the query follows disagreement between
    the test presses rather than the model's uncertainty, and it reinforces
    itself (adding presses of a class the model confuses with the test
    object pushes that class's probability towards 0.5 on some test presses,
    which raises its variance further). :func:`mc_variance_sampling` keeps
    the MC part only.

    Parameters
    ----------
    proba_samples : array-like of shape (n_samples, n_X, n_classes)
        MC-dropout probabilities on the test presses.
    n_instances : int, default=1
        How many distinct classes to return.
    random_state : int, RandomState instance or None, default=None
        Seeds the order of exactly tied scores.

    Returns
    -------
    class_indices : ndarray of shape (n_instances,), int
        The chosen classes, highest score first.
    scores : ndarray of shape (n_classes,), float64
        Eq. 2 for every class.

    Examples
    --------
    >>> import numpy as np
    >>> from sklearn_hardness.active import variance_sampling
    >>> p = np.array([[[0.9, 0.1, 0.0], [0.5, 0.3, 0.2]],
    ...               [[0.7, 0.3, 0.0], [0.5, 0.3, 0.2]]])  # 2 passes, 2 presses
    >>> idx, scores = variance_sampling(p)
    >>> idx, scores.round(4)
    (array([0]), array([0.0275, 0.0075, 0.01  ]))
    """
    scores = class_uncertainty(proba_samples, "variance")
    return _top_classes(scores, n_instances, random_state), scores


@validate_params(_STRATEGY_PARAMS, prefer_skip_nested_validation=True)
def bald_sampling(proba_samples, n_instances=1, *, random_state=None):
    r"""Pick the class(es) with the highest share of the BALD mutual information.

    Our addition to the paper (Houlsby et al. 2011): per class,
    :math:`B_i = \frac{1}{l}\sum_k [-\bar p_{ik}\log\bar p_{ik} +
    \frac{1}{n}\sum_j p_{ijk}\log p_{ijk}]`; see :func:`class_uncertainty`.
    It is zero when all passes agree, so it ignores disagreement between
    test presses.

    Parameters
    ----------
    proba_samples : array-like of shape (n_samples, n_X, n_classes)
        MC-dropout probabilities on the test presses.
    n_instances : int, default=1
        How many distinct classes to return.
    random_state : int, RandomState instance or None, default=None
        Seeds the order of exactly tied scores.

    Returns
    -------
    class_indices : ndarray of shape (n_instances,), int
        The chosen classes, highest score first.
    scores : ndarray of shape (n_classes,), float64
        The class-wise BALD share of every class.

    Examples
    --------
    >>> import numpy as np
    >>> from sklearn_hardness.active import bald_sampling
    >>> p = np.array([[[0.9, 0.1, 0.0]], [[0.5, 0.1, 0.4]]])  # 2 passes, 1 press
    >>> bald_sampling(p)[0]  # class 1 is the same in every pass
    array([2])
    """
    scores = class_uncertainty(proba_samples, "bald")
    return _top_classes(scores, n_instances, random_state), scores


@validate_params(_STRATEGY_PARAMS, prefer_skip_nested_validation=True)
def mc_variance_sampling(proba_samples, n_instances=1, *, random_state=None):
    r"""Pick the class(es) whose probability varies most between MC-dropout passes.

    The MC part of the paper's Eq. 2 (:func:`variance_decomposition`): with
    :math:`m_{ik} = \frac{1}{n}\sum_j p_{ijk}` the mean over passes of test
    press :math:`k`,

    .. math::

        V^{\mathrm{MC}}_i = \frac{1}{l}\sum_k \frac{1}{n}\sum_j
        (p_{ijk} - m_{ik})^2 .

    Why this form: it is the variance the dropout masks cause, per press,
    averaged over the test presses, i.e. the model's own (epistemic)
    uncertainty, which more training presses of class :math:`i` reduce. The
    paper's Eq. 2 adds the between-press part
    :math:`\frac{1}{l}\sum_k (m_{ik}-\mu_i)^2`, which dropout does not cause
    and training does not remove (test presses classified differently), and
    which grows when a confused class's probability moves towards 0.5 on some
    presses: the self-reinforcing queries of :func:`variance_sampling`. The
    other candidate, the variance across passes of the press-averaged
    prediction :math:`\mathrm{Var}_j(\frac{1}{l}\sum_k p_{ijk})`, depends on
    whether a pass shares its dropout masks across presses (batched passes
    do not, so it shrinks like :math:`1/l`); :math:`V^{\mathrm{MC}}_i` does
    not. It is the class-wise MC-dropout variance used as an acquisition
    function by Gal et al. (2017), averaged over the test presses.

    Parameters
    ----------
    proba_samples : array-like of shape (n_samples, n_X, n_classes)
        MC-dropout probabilities on the test presses.
    n_instances : int, default=1
        How many distinct classes to return.
    random_state : int, RandomState instance or None, default=None
        Seeds the order of exactly tied scores.

    Returns
    -------
    class_indices : ndarray of shape (n_instances,), int
        The chosen classes, highest score first.
    scores : ndarray of shape (n_classes,), float64
        :math:`V^{\mathrm{MC}}_i` for every class (``variance_decomposition(p)["mc"]``).

    References
    ----------
    Gal, Islam and Ghahramani (2017), "Deep Bayesian Active Learning with
    Image Data", ICML (MC-dropout acquisition functions).

    Examples
    --------
    >>> import numpy as np
    >>> from sklearn_hardness.active import mc_variance_sampling, variance_sampling
    >>> # class 0: the presses disagree; class 1: the passes disagree most
    >>> p = np.array([[[0.9, 0.1, 0.0], [0.1, 0.7, 0.2]],
    ...               [[0.9, 0.1, 0.0], [0.2, 0.4, 0.4]]])
    >>> variance_sampling(p)[0], mc_variance_sampling(p)[0]
    (array([0]), array([1]))
    """
    scores = variance_decomposition(proba_samples)["mc"]
    return _top_classes(scores, n_instances, random_state), scores


@validate_params(_STRATEGY_PARAMS, prefer_skip_nested_validation=True)
def margin_sampling(proba_samples, n_instances=1, *, random_state=None):
    r"""Pick the class(es) most confused with the current decision (class-level margin).

    With :math:`\mu_i = \frac{1}{nl}\sum_{j,k} p_{ijk}` the mean MC
    probability of class :math:`i` on the test presses and
    :math:`t = \arg\max_i \mu_i` the current decision, every other class
    scores minus its margin to the decision, and the decision itself scores
    the lowest possible value:

    .. math::

        M_i = \mu_i - \mu_t \in [-1, 0] \quad (i \ne t), \qquad M_t = -1 .

    The highest score is the runner-up: the reference object the test
    object is most easily mistaken for. Margin sampling (the smallest gap
    between the two most probable classes) is a strong baseline across
    active-learning benchmarks (Bahri et al. 2022). Here the unit is a class,
    not a sample, and of the two classes that define the margin the
    runner-up is the informative one to press: if the decision is right,
    presses of the runner-up show the model where that class lies and move
    the boundary away from the test object; if it is wrong and the
    runner-up is the true class, its presses raise it directly. Pressing the
    decision class again only adds presses like those it already favours.
    Unlike Eq. 2 the score does not rise when a class's probability moves
    towards 0.5 on some presses, so it does not feed on its own queries.

    Parameters
    ----------
    proba_samples : array-like of shape (n_samples, n_X, n_classes)
        MC-dropout probabilities on the test presses.
    n_instances : int, default=1
        How many distinct classes to return (the decision class comes last).
    random_state : int, RandomState instance or None, default=None
        Seeds the order of exactly tied scores (and of tied decisions).

    Returns
    -------
    class_indices : ndarray of shape (n_instances,), int
        The chosen classes, smallest margin first.
    scores : ndarray of shape (n_classes,), float64
        :math:`M_i` for every class.

    References
    ----------
    Bahri, Jiang, Gupta and Nachum (2022), "Is margin all you need? An
    extensive empirical study of active learning on tabular data",
    arXiv:2210.03822.

    Examples
    --------
    >>> import numpy as np
    >>> from sklearn_hardness.active import margin_sampling
    >>> p = np.tile([0.5, 0.15, 0.35], (10, 4, 1))  # decision: class 0
    >>> idx, scores = margin_sampling(p)
    >>> idx, scores.round(2)
    (array([2]), array([-1.  , -0.35, -0.15]))
    """
    mu = check_proba_samples(proba_samples).mean(axis=(0, 1))
    rng = check_random_state(random_state)
    top = _top_classes(mu, 1, rng)[0]
    scores = mu - mu[top]
    scores[top] = -1.0
    # The decision class ranks strictly last, also when another class ties
    # it at -1 (a saturated model: mu_top = 1, mu_i = 0); the returned
    # scores keep M_t = -1.
    ranking = scores.copy()
    ranking[top] = -np.inf
    return _top_classes(ranking, n_instances, rng), scores


@validate_params(_STRATEGY_PARAMS, prefer_skip_nested_validation=True)
def thompson_sampling(proba_samples, n_instances=1, *, random_state=None):
    r"""Press a class drawn with the probability that it is the test object's class.

    Thompson sampling (Thompson 1933) on the question the robot is asking,
    "which reference object is the test object?": with
    :math:`\mu_i = \frac{1}{nl}\sum_{j,k} p_{ijk}` the mean MC-dropout
    probability of class :math:`i` over the passes and the test presses, the
    first class is drawn with probability :math:`\mu_i`, further ones without
    replacement (weighted sampling by priorities :math:`u_i^{1/\mu_i}`,
    :math:`u_i \sim U[0, 1)`, Efraimidis and Spirakis 2006).

    Why: presses of the test object's own class are the most useful new
    training presses for deciding on the test object, and the uncertainty
    scores of the paper (Eq. 2 and alike) are largest for the classes the model
    *confuses* with it, which keeps pressing a wrong class (see
    :func:`variance_sampling`). Drawing by :math:`\mu` presses the believed
    class most often, keeps pressing its competitors in proportion to the
    doubt, and spreads the presses when the model is unsure. The price is
    measured, not assumed: it presses the other classes less than
    :func:`random_sampling`, so check the accuracy on held-out presses of
    every class (``n_holdout`` in :func:`~sklearn_hardness.experiments.run_active_sampling`)
    beside the test object's.

    Parameters
    ----------
    proba_samples : array-like of shape (n_samples, n_X, n_classes)
        MC-dropout probabilities on the test presses.
    n_instances : int, default=1
        How many distinct classes to return.
    random_state : int, RandomState instance or None, default=None
        Seeds the draw.

    Returns
    -------
    class_indices : ndarray of shape (n_instances,), int
        The drawn classes, in the order drawn.
    scores : ndarray of shape (n_classes,), float64
        The priorities :math:`u_i^{1/\mu_i}` in [0, 1); ``class_indices`` are
        the classes with the highest, so "highest score first" holds as for
        the other strategies. A class with :math:`\mu_i = 0` has priority 0.
        Priorities that underflow to 0 (small :math:`\mu_i`) are still
        ranked by :math:`\log(u_i)/\mu_i`, so later draws stay weighted.
        The probabilities :math:`\mu` themselves are
        ``proba_samples.mean(axis=(0, 1))``.

    References
    ----------
    Thompson (1933), "On the likelihood that one unknown probability exceeds
    another in view of the evidence of two samples", Biometrika 25.
    Efraimidis and Spirakis (2006), "Weighted random sampling with a
    reservoir", Information Processing Letters 97.

    Examples
    --------
    >>> import numpy as np
    >>> from sklearn_hardness.active import thompson_sampling
    >>> p = np.tile([0.7, 0.2, 0.1], (10, 4, 1))  # the model believes class 0
    >>> firsts = [thompson_sampling(p, random_state=s)[0][0] for s in range(1000)]
    >>> np.bincount(firsts) / 1000  # about 0.7, 0.2, 0.1
    array([0.679, 0.207, 0.114])
    """
    mu = check_proba_samples(proba_samples).astype(np.float64).mean(axis=(0, 1))
    mu = np.clip(np.nan_to_num(mu), 0.0, None)
    total = mu.sum()
    mu = mu / total if total > 0 else np.full(mu.shape, 1.0 / mu.shape[0])
    rng = check_random_state(random_state)
    u = rng.random_sample(mu.shape[0])
    with np.errstate(divide="ignore", under="ignore"):
        # log-priorities log(u_i) / mu_i (-inf for mu_i = 0); their exp, the
        # returned priorities, underflows to 0 for small mu_i, so the ties
        # of exp are ordered by the log-priorities, not by the random
        # tie-break (the order is otherwise that of the priorities).
        keys = np.where(mu > 0, np.log(u) / np.where(mu > 0, mu, 1.0), -np.inf)
        scores = np.where(mu > 0, np.exp(keys), 0.0)
    return _top_classes(scores, n_instances, rng, secondary=keys), scores


@validate_params(_STRATEGY_PARAMS, prefer_skip_nested_validation=True)
def random_sampling(proba_samples, n_instances=1, *, random_state=None):
    """Pick class(es) uniformly at random (the paper's baseline).

    Only the number of classes of ``proba_samples`` is used (its shape is
    validated like the other strategies' input).

    Parameters
    ----------
    proba_samples : array-like of shape (n_samples, n_X, n_classes)
        MC-dropout probabilities on the test presses.
    n_instances : int, default=1
        How many distinct classes to return.
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

    Examples
    --------
    >>> import numpy as np
    >>> from sklearn_hardness.active import random_sampling
    >>> p = np.full((5, 2, 4), 0.25)
    >>> idx, _ = random_sampling(p, n_instances=4, random_state=0)
    >>> sorted(idx.tolist())
    [0, 1, 2, 3]
    """
    n_classes = check_proba_samples(proba_samples).shape[-1]
    rng = check_random_state(random_state)
    scores = rng.random_sample(n_classes)
    return _top_classes(scores, n_instances, rng), scores


_STRATEGIES = {
    "entropy": entropy_sampling,
    "variance": variance_sampling,
    "bald": bald_sampling,
    "margin": margin_sampling,
    "mc_variance": mc_variance_sampling,
    "thompson": thompson_sampling,
    "random": random_sampling,
}

#: The registered strategy names (:func:`get_strategy` accepts these).
STRATEGY_NAMES = tuple(_STRATEGIES)


@validate_params(
    {"strategy": [StrOptions(set(_STRATEGIES)), callable]},
    prefer_skip_nested_validation=True,
)
def get_strategy(strategy):
    """Return the strategy callable for a name or a callable.

    Parameters
    ----------
    strategy : {"entropy", "variance", "bald", "margin", "mc_variance", \
            "thompson", "random"} or callable
        A strategy name, or a callable
        ``strategy(proba_samples, n_instances=1, *, random_state=None)``
        returning ``(class_indices, scores)`` or ``class_indices``
        (returned as it is).

    Returns
    -------
    strategy : callable

    Raises
    ------
    ValueError
        For an unknown name or something that is neither a string nor
        callable (an ``InvalidParameterError``, with scikit-learn's message
        format, which is also a TypeError).

    Examples
    --------
    >>> from sklearn_hardness.active._strategies import get_strategy
    >>> get_strategy("variance").__name__
    'variance_sampling'
    """
    return _STRATEGIES[strategy] if isinstance(strategy, str) else strategy


def check_strategies(strategies):
    """Check a list of strategies (names or callables) and name each one.

    One strategy (a name or a callable) counts as a list of one. Used by the
    experiments and by the command line before anything runs.

    Parameters
    ----------
    strategies : str, callable or sequence of them

    Returns
    -------
    strategies : tuple
        As given.
    names : list of str
        The name of each (a callable's ``__name__``).

    Raises
    ------
    ValueError
        An empty list, an unknown name (one the package does not register), or the
        same strategy twice.

    Examples
    --------
    >>> from sklearn_hardness.active import check_strategies, random_sampling
    >>> check_strategies(["variance", random_sampling])[1]
    ['variance', 'random_sampling']
    """
    if isinstance(strategies, str) or callable(strategies):
        strategies = (strategies,)
    strategies = tuple(strategies)
    if not strategies:
        raise ValueError("strategies is empty; pass e.g. ('variance', 'entropy', 'random').")
    names = []
    for s in strategies:
        get_strategy(s)  # ValueError for an unknown name
        names.append(s if isinstance(s, str) else getattr(s, "__name__", repr(s)))
    if len(set(names)) != len(names):
        raise ValueError(f"strategies has duplicates: {names}.")
    return strategies, names
