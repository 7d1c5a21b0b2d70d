"""Repeated stratified, group-disjoint folds: the splitter an integer ``cv`` stands for."""

from __future__ import annotations

import numbers

import numpy as np
from sklearn.model_selection import StratifiedGroupKFold
from sklearn.utils import check_random_state

__all__ = ["RepeatedStratifiedGroupKFold"]


class RepeatedStratifiedGroupKFold:
    """:class:`~sklearn.model_selection.StratifiedGroupKFold`, repeated with other assignments of groups to folds.

    Every repetition shuffles the groups (the objects) anew and splits them
    into ``n_splits`` folds that keep each group's samples together and the
    classes' proportions as far as the groups allow. One random stream runs
    through all repetitions, as in scikit-learn's repeated splitters, so the
    first repetition's folds are those of
    ``StratifiedGroupKFold(n_splits, shuffle=True, random_state=random_state)``.

    Parameters
    ----------
    n_splits : int, default=5
        Folds per repetition (at least 2).
    n_repeats : int, default=1
        Repetitions (at least 1).
    random_state : int, RandomState instance or None, default=None
        Seed of the assignments.

    Examples
    --------
    >>> import numpy as np
    >>> from sklearn_hardness.model_selection import RepeatedStratifiedGroupKFold
    >>> y, groups = np.repeat([0, 1], 6), np.repeat(np.arange(6), 2)
    >>> cv = RepeatedStratifiedGroupKFold(n_splits=3, n_repeats=2, random_state=0)
    >>> cv.get_n_splits(), all(not set(groups[tr]) & set(groups[te]) for tr, te in cv.split(y, y, groups))
    (6, True)
    """

    def __init__(self, n_splits=5, n_repeats=1, random_state=None):
        for name, value, least in (("n_splits", n_splits, 2), ("n_repeats", n_repeats, 1)):
            if isinstance(value, bool) or not isinstance(value, numbers.Integral) or value < least:
                raise ValueError(f"{name} must be an integer >= {least}, got {value!r}.")
        self.n_splits = int(n_splits)
        self.n_repeats = int(n_repeats)
        self.random_state = random_state

    def get_n_splits(self, X=None, y=None, groups=None):
        """Number of folds in all: ``n_splits * n_repeats``."""
        return self.n_splits * self.n_repeats

    def split(self, X, y, groups):
        """Training and test indices of every fold, repetition after repetition.

        Parameters
        ----------
        X : array-like of shape (n_samples, ...)
            Only its length is used.
        y : array-like of shape (n_samples,)
            Classes to stratify by.
        groups : array-like of shape (n_samples,)
            The group (object) of each sample; no group is on both sides.

        Yields
        ------
        train, test : ndarray
        """
        rng = check_random_state(self.random_state)
        for _ in range(self.n_repeats):
            splitter = StratifiedGroupKFold(n_splits=self.n_splits, shuffle=True, random_state=rng)
            yield from splitter.split(np.zeros(len(y)), y, groups)

    def __repr__(self):
        return (f"{type(self).__name__}(n_splits={self.n_splits}, n_repeats={self.n_repeats}, "
                f"random_state={self.random_state!r})")
