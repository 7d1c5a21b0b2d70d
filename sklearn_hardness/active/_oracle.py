"""An oracle that answers "press reference object i s more times" from a pool."""

from __future__ import annotations

import warnings
from numbers import Integral

import numpy as np
from sklearn.utils import _safe_indexing, check_random_state
from sklearn.utils._param_validation import Interval, StrOptions, validate_params

__all__ = ["PressOracle"]

_ON_EXHAUSTED = ("raise", "truncate", "recycle")


class PressOracle:
    """Draws unseen presses of a reference object from a pool of recordings.

    In an experiment, the robot cannot press again: its presses were recorded
    beforehand. The oracle stands in for it: each class's presses are
    shuffled once (seeded) and handed out in that order, without
    replacement, so a press is never given twice.

    Parameters
    ----------
    X_pool : array-like or sequence of videos
        The presses to draw from (anything :func:`sklearn.utils._safe_indexing`
        can index: arrays, lists, lazy video sequences).
    y_pool : array-like of shape (n_pool,)
        Their labels (reference object of each press).
    random_state : int, RandomState instance or None, default=None
        Seeds the order in which presses are handed out.
    on_exhausted : {"raise", "truncate", "recycle"}, default="raise"
        What happens when more presses of a class are asked for than remain
        unseen:

        - ``"raise"``: ``ValueError`` naming the class and how many remain;
          nothing is drawn.
        - ``"truncate"``: return the remaining presses (possibly none) and
          warn.
        - ``"recycle"``: return the remaining unseen presses, then start
          again through a fresh shuffle of all the class's presses (so
          presses repeat) and warn.

    Attributes
    ----------
    classes_ : ndarray of shape (n_classes,)
        The labels in the pool, sorted.
    drawn_ : list of int
        Pool indices handed out so far, in order.

    Examples
    --------
    >>> import numpy as np
    >>> from sklearn_hardness.active import PressOracle
    >>> X = np.arange(12).reshape(6, 2); y = np.array([0, 0, 0, 1, 1, 1])
    >>> oracle = PressOracle(X, y, random_state=0)
    >>> X0, y0 = oracle.initial(1)        # one press of every object
    >>> y0
    array([0, 1])
    >>> X1, y1 = oracle.press(1, 2)       # press object 1 twice more
    >>> oracle.n_remaining()
    {0: 2, 1: 0}
    """

    # not an estimator (it is not fit): the constructor validates, as scikit-learn's
    # public functions do
    @validate_params(
        {
            "X_pool": ["array-like"],
            "y_pool": ["array-like"],
            "random_state": ["random_state"],
            "on_exhausted": [StrOptions(set(_ON_EXHAUSTED))],
        },
        prefer_skip_nested_validation=True,
    )
    def __init__(self, X_pool, y_pool, *, random_state=None, on_exhausted="raise"):
        y = np.asarray(y_pool)
        if y.ndim != 1:
            raise ValueError(f"y_pool must be 1-D, got shape {y.shape}.")
        n = X_pool.shape[0] if hasattr(X_pool, "shape") else len(X_pool)
        if n != y.shape[0]:
            raise ValueError(f"X_pool has {n} presses but y_pool has {y.shape[0]} labels.")
        if n == 0:
            raise ValueError("the pool is empty.")
        self.X_pool = X_pool
        self.y_pool = y
        self.random_state = random_state
        self.on_exhausted = on_exhausted
        self._rng = check_random_state(random_state)
        self.classes_ = np.unique(y)
        self._members = {c: np.flatnonzero(y == c) for c in self.classes_.tolist()}
        self._order = {c: self._rng.permutation(m) for c, m in self._members.items()}
        self._next = {c: 0 for c in self._members}
        self.drawn_ = []

    def _key(self, label):
        key = label.item() if isinstance(label, np.generic) else label
        if key not in self._members:
            raise ValueError(
                f"unknown reference object {key!r}; the pool has {self.classes_.tolist()}."
            )
        return key

    def n_remaining(self, label=None):
        """Unseen presses left, for one class or (``label=None``) as a dict."""
        if label is None:
            return {c: len(self._order[c]) - self._next[c] for c in self._members}
        key = self._key(label)
        return len(self._order[key]) - self._next[key]

    def _take(self, key, n):
        left = len(self._order[key]) - self._next[key]
        if n > left:
            if self.on_exhausted == "truncate":
                warnings.warn(
                    f"reference object {key!r}: asked for {n} presses, only {left} "
                    "unseen remain; returning those.",
                    UserWarning,
                    stacklevel=3,
                )
                n = left
            elif self.on_exhausted == "recycle":
                warnings.warn(
                    f"reference object {key!r}: asked for {n} presses, only {left} "
                    "unseen remain; reusing its presses in a new random order.",
                    UserWarning,
                    stacklevel=3,
                )
                while len(self._order[key]) - self._next[key] < n:
                    self._order[key] = np.concatenate(
                        [self._order[key], self._rng.permutation(self._members[key])]
                    )
        start = self._next[key]
        self._next[key] = start + n
        return self._order[key][start : start + n]

    @validate_params(
        {"n_presses": [Interval(Integral, 1, None, closed="left")]},
        prefer_skip_nested_validation=True,
    )
    def press(self, label, n_presses=1):
        """Draw ``n_presses`` unseen presses of one or more reference objects.

        Parameters
        ----------
        label : label or array-like of labels
            The reference object(s), e.g. ``learner.classes_[idx]`` after
            ``idx, _ = learner.query(X_test)``. For several labels,
            ``n_presses`` of each are drawn.
        n_presses : int, default=1
            Presses per object (``s`` in the paper).

        Returns
        -------
        X : same kind as ``X_pool``
            The presses.
        y : ndarray of shape (n,)
            Their labels.

        Raises
        ------
        ValueError
            For an unknown label, or (``on_exhausted="raise"``) when fewer
            than ``n_presses`` unseen presses remain for a class; the message
            names the class and how many remain, and nothing is drawn.
        """
        labels = np.atleast_1d(np.asarray(label))
        if labels.ndim != 1 or labels.size == 0:
            raise ValueError(f"label must be one label or a 1-D list of labels, got {label!r}.")
        keys = [self._key(lab) for lab in labels]
        if len(set(keys)) != len(keys):
            raise ValueError(f"label has repeated reference objects: {labels.tolist()}.")
        if self.on_exhausted == "raise":
            for key in keys:
                left = self.n_remaining(key)
                if n_presses > left:
                    raise ValueError(
                        f"reference object {key!r} has only {left} unseen presses left "
                        f"in the pool, {n_presses} asked for. Use a larger pool, fewer "
                        "presses per iteration, or on_exhausted='truncate'/'recycle'."
                    )
        idx = np.concatenate([self._take(key, int(n_presses)) for key in keys]).astype(np.intp)
        self.drawn_.extend(idx.tolist())
        return _safe_indexing(self.X_pool, idx), self.y_pool[idx]

    @validate_params(
        {"n_per_class": [Interval(Integral, 1, None, closed="left")]},
        prefer_skip_nested_validation=True,
    )
    def initial(self, n_per_class):
        """Draw the initial training set: ``n_per_class`` presses of every object.

        Parameters
        ----------
        n_per_class : int
            Presses per reference object (``s0`` in the paper).

        Returns
        -------
        X : same kind as ``X_pool``
        y : ndarray of shape (n_classes * n_per_class,)
        """
        return self.press(self.classes_, n_per_class)
