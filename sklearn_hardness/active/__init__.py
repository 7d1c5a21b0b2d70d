"""Active sampling: which reference object to press next.

The paper's strategies score every *class* (reference object) by the
Monte-Carlo-dropout uncertainty of the classifier on presses of the test
object, and press the most uncertain one again (Algorithm 1).

- :func:`class_uncertainty`: per-class entropy (Eq. 1), variance (Eq. 2) and
  BALD from an ``(n_samples, n_X, n_classes)`` array of MC-dropout
  probabilities; :func:`variance_decomposition` splits Eq. 2 into its
  MC-dropout part and its between-press part.
- :func:`entropy_sampling`, :func:`variance_sampling`, :func:`bald_sampling`,
  :func:`margin_sampling`, :func:`mc_variance_sampling`,
  :func:`thompson_sampling`, :func:`random_sampling`: strategies, functions of the MC-dropout
  probabilities on the test presses, returning ``(class_indices, scores)``;
  :func:`as_modal_strategy` adapts one to modAL; :func:`check_strategies`
  checks a list of them before a run.
- :class:`ActiveLearner`: fit / query / teach with a capped training
  reservoir and warm-started retraining.
- :class:`PressOracle`: draws unseen presses of a queried object from a pool.
"""

from ._learner import ActiveLearner
from ._modal import as_modal_strategy
from ._oracle import PressOracle
from ._strategies import (
    bald_sampling,
    check_strategies,
    entropy_sampling,
    margin_sampling,
    mc_variance_sampling,
    random_sampling,
    thompson_sampling,
    variance_sampling,
)
from ._uncertainty import class_uncertainty, variance_decomposition

__all__ = [
    "ActiveLearner",
    "PressOracle",
    "class_uncertainty",
    "variance_decomposition",
    "entropy_sampling",
    "variance_sampling",
    "bald_sampling",
    "margin_sampling",
    "mc_variance_sampling",
    "thompson_sampling",
    "random_sampling",
    "as_modal_strategy",
    "check_strategies",
]
