"""Seeding of (possibly nested) estimators, and int seeds for APIs that want one."""

import numbers

import numpy as np
from sklearn.utils import check_random_state


def int_seed(random_state):
    """An int seed from a ``random_state``: None stays None, an int is kept, a RandomState draws one."""
    if random_state is None or isinstance(random_state, numbers.Integral):
        return random_state
    return int(check_random_state(random_state).randint(np.iinfo(np.int32).max))


def set_random_states(estimator, seed):
    """Set ``random_state`` and every nested ``*__random_state`` parameter of ``estimator`` to ``seed``.

    Returns the estimator (changed in place), as ``set_params`` does.
    """
    keys = [k for k in estimator.get_params(deep=True) if k == "random_state" or k.endswith("__random_state")]
    if keys:
        estimator.set_params(**{k: int(seed) for k in keys})
    return estimator
