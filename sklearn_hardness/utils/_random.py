"""Seeding of (possibly nested) estimators."""


def set_random_states(estimator, seed):
    """Set ``random_state`` and every nested ``*__random_state`` parameter of ``estimator`` to ``seed``.

    Returns the estimator (changed in place), as ``set_params`` does.
    """
    keys = [k for k in estimator.get_params(deep=True) if k == "random_state" or k.endswith("__random_state")]
    if keys:
        estimator.set_params(**{k: int(seed) for k in keys})
    return estimator
