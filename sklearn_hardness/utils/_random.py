"""Seeds: the library's two rules for deriving them, and seeding of (possibly nested) estimators.

- :func:`draw_seeds`: seeds drawn from a ``random_state`` (an estimator's
  own generators, an ensemble's members, one MC sampling call);
- :func:`derived_seeds`: seeds derived from integers that name a run (an
  experiment's (seed, test object) pairs), the same on every machine and in
  every process.
"""

import numbers

import numpy as np
from sklearn.utils import check_random_state

#: Seeds are drawn below this bound (a non-negative int32, accepted by every seeding API).
SEED_BOUND = 2**31 - 1


def draw_seeds(random_state, n):
    """``n`` int seeds drawn from ``random_state`` (None: fresh entropy; an int: reproducible).

    Returns a list of Python ints in ``[0, SEED_BOUND)``.
    """
    return [int(s) for s in check_random_state(random_state).randint(0, SEED_BOUND, size=n)]


def derived_seeds(entropy, n):
    """``n`` int seeds derived from a list of ints (numpy's ``SeedSequence``), in ``[0, SEED_BOUND)``."""
    ss = np.random.SeedSequence([int(e) for e in entropy])
    return [int(s) for s in ss.generate_state(n, dtype=np.uint32) % SEED_BOUND]


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
