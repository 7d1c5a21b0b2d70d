"""An oracle that answers "press a reference object of class c s more times" from a pool."""

from __future__ import annotations

import warnings
from numbers import Integral

import numpy as np
from sklearn.utils import _safe_indexing, check_random_state

from ..utils._param_validation import Interval, StrOptions, validate_params
from ..utils._warnings import external_stacklevel

__all__ = ["PressOracle"]

_ON_EXHAUSTED = ("raise", "truncate", "recycle")


class PressOracle:
    """Draws unseen presses of a reference object from a pool of recordings.

    In an experiment, the robot cannot press again: its presses were recorded
    beforehand. The oracle stands in for it: each class's presses are
    shuffled once (seeded) and handed out in that order, without
    replacement, so a press is never given twice.

    With ``groups`` (the physical object of each press; many objects per
    class), the learner still asks for a class and the oracle presses one
    *reference object* of that class: the object of the class pressed least
    so far (presses handed out), ties broken at random by ``random_state``,
    among the objects with unseen presses left. :meth:`press_object` answers
    as a robot would, ``(object_id, X, y)`` with up to ``n_presses`` presses
    of that one object; :meth:`press` (and :meth:`initial`) fill
    ``n_presses`` by pressing objects in turn by that rule, so an answer
    may span several objects when one has too few recorded presses. Each
    object's presses are shuffled once. Without ``groups`` (or with one
    object per class) the object is the class and nothing changes.

    Parameters
    ----------
    X_pool : array-like or sequence of videos
        The presses to draw from (anything :func:`sklearn.utils._safe_indexing`
        can index: arrays, lists, lazy video sequences).
    y_pool : array-like of shape (n_pool,)
        Their labels (class of each press).
    groups : array-like of shape (n_pool,) or None, default=None
        The physical object of each press (e.g. a manifest's ``object_id``),
        each object in one class. None: one object per class (the label).
    random_state : int, RandomState instance or None, default=None
        Seeds the order in which presses are handed out.
    on_exhausted : {"raise", "truncate", "recycle"}, default="raise"
        What happens when more presses of a class are asked for than remain
        unseen (with ``groups``: than remain over all objects of the class):

        - ``"raise"``: ``ValueError`` naming the class and how many remain;
          nothing is drawn.
        - ``"truncate"``: return the remaining presses (possibly none) and
          warn.
        - ``"recycle"``: return the remaining unseen presses, then start
          again through a fresh shuffle of all the class's presses (so
          presses repeat) and warn. With ``groups``, the class's last unseen
          presses come first (least-pressed object first, as always); then
          every object of the class gets a fresh shuffle of its presses, and
          the least-pressed rule goes on over all of them (press counts are
          kept).

        .. versionchanged:: 0.1
           With ``groups`` and ``"recycle"``, unseen presses come before
           reused ones; until then every object was refilled first, so the
           least-pressed rule could hand out reused presses of one object
           while others still had unseen ones.

    Attributes
    ----------
    classes_ : ndarray of shape (n_classes,)
        The labels in the pool, sorted.
    drawn_ : list of int
        Pool indices handed out so far, in order.
    drawn_objects_ : list
        The object of each press in ``drawn_`` (the label without ``groups``).
    n_pressed_ : dict
        Presses handed out so far per object (per class without ``groups``).

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

    With several objects per class, the answer names the object to press:

    >>> groups = np.array(["cup", "cup", "mug", "foam", "sponge", "sponge"])
    >>> oracle = PressOracle(X, y, groups=groups, random_state=0)
    >>> obj, X1, y1 = oracle.press_object(0, 2)   # a class-0 object, twice
    >>> str(obj), len(y1)
    ('mug', 1)
    >>> str(oracle.press_object(0, 2)[0])          # the one pressed least so far
    'cup'
    """

    # not an estimator (it is not fit): the constructor validates, as scikit-learn's
    # public functions do
    @validate_params(
        {
            "X_pool": ["array-like"],
            "y_pool": ["array-like"],
            "groups": ["array-like", None],
            "random_state": ["random_state"],
            "on_exhausted": [StrOptions(set(_ON_EXHAUSTED))],
        },
        prefer_skip_nested_validation=True,
    )
    def __init__(self, X_pool, y_pool, *, groups=None, random_state=None, on_exhausted="raise"):
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
        self.groups = groups
        self.random_state = random_state
        self.on_exhausted = on_exhausted
        self._rng = check_random_state(random_state)
        self.classes_ = np.unique(y)
        self._members = {c: np.flatnonzero(y == c) for c in self.classes_.tolist()}
        self._objects = None
        if groups is None:
            # one object per class: the class's presses in one seeded order (as always)
            self._order = {c: self._rng.permutation(m) for c, m in self._members.items()}
            self._next = dict.fromkeys(self._members, 0)
            self.n_pressed_ = dict.fromkeys(self._members, 0)
        else:
            g = np.asarray(groups)
            if g.shape != y.shape:
                raise ValueError(f"groups has shape {g.shape}, y_pool {y.shape}; give one object per press.")
            self._objects = {}
            for c, m in self._members.items():
                objs = [o.item() if isinstance(o, np.generic) else o for o in np.unique(g[m])]
                self._objects[c] = objs
            owner = {}
            for o, c in zip(g.tolist(), y.tolist()):
                if owner.setdefault(o, c) != c:
                    raise ValueError(f"object {o!r} has presses of classes {owner[o]!r} and {c!r}; "
                                     "an object belongs to one class.")
            objects = [o for c in self._members for o in self._objects[c]]
            self._obj_members = {o: np.flatnonzero(g == o) for o in objects}
            self._order = {o: self._rng.permutation(m) for o, m in self._obj_members.items()}
            self._next = dict.fromkeys(objects, 0)
            self.n_pressed_ = dict.fromkeys(objects, 0)
        self.drawn_ = []
        self.drawn_objects_ = []

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
            return {c: self.n_remaining(c) for c in self._members}
        key = self._key(label)
        if self._objects is None:
            return len(self._order[key]) - self._next[key]
        return sum(self._left(o) for o in self._objects[key])

    def _left(self, obj):
        return len(self._order[obj]) - self._next[obj]

    def _pick_object(self, key):
        """The object of class ``key`` pressed least so far among those with unseen presses; ties at random."""
        objs = [o for o in self._objects[key] if self._left(o) > 0]
        if not objs:
            return None
        counts = np.array([self.n_pressed_[o] for o in objs])
        least = [o for o, n in zip(objs, counts) if n == counts.min()]
        return least[int(self._rng.randint(len(least)))] if len(least) > 1 else least[0]

    def _take_objects(self, key, n):
        """``n`` presses of class ``key`` from its objects in turn (least pressed first)."""
        out = []
        if n > self.n_remaining(key):
            n = self._exhausted(key, n, self.n_remaining(key))
            if self.on_exhausted == "recycle":
                while self.n_remaining(key) > 0:  # the unseen presses first
                    got = self._take_one(self._pick_object(key), n)
                    out.append(got)
                    n -= len(got)
                while self.n_remaining(key) < n:
                    for o in self._objects[key]:
                        self._order[o] = np.concatenate(
                            [self._order[o], self._rng.permutation(self._obj_members[o])])
        while n > 0:
            obj = self._pick_object(key)
            got = self._take_one(obj, n)
            out.append(got)
            n -= len(got)
        return np.concatenate(out) if out else np.empty(0, dtype=np.intp)

    def _take_one(self, obj, n):
        start = self._next[obj]
        idx = self._order[obj][start: start + n]
        self._next[obj] = start + len(idx)
        self.n_pressed_[obj] += len(idx)
        self.drawn_objects_.extend([obj] * len(idx))
        return idx

    def _exhausted(self, key, n, left):
        """Warn for ``truncate`` / ``recycle``; the number of presses to hand out."""
        if self.on_exhausted == "truncate":
            warnings.warn(
                f"reference object {key!r}: asked for {n} presses, only {left} "
                "unseen remain; returning those.",
                UserWarning,
                stacklevel=external_stacklevel(),
            )
            return left
        warnings.warn(
            f"reference object {key!r}: asked for {n} presses, only {left} "
            "unseen remain; reusing its presses in a new random order.",
            UserWarning,
            stacklevel=external_stacklevel(),
        )
        return n

    def _take(self, key, n):
        if self._objects is not None:
            return self._take_objects(key, n)
        left = len(self._order[key]) - self._next[key]
        if n > left:
            n = self._exhausted(key, n, left)
            if self.on_exhausted == "recycle":
                while len(self._order[key]) - self._next[key] < n:
                    self._order[key] = np.concatenate(
                        [self._order[key], self._rng.permutation(self._members[key])]
                    )
        return self._take_one(key, n)

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
            Their labels. With ``groups``, ``drawn_objects_[-n:]`` says
            which object each press is of.

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
        {"n_presses": [Interval(Integral, 1, None, closed="left")]},
        prefer_skip_nested_validation=True,
    )
    def press_object(self, label, n_presses=1):
        """Press one reference object of class ``label``: the robot's answer to a query.

        The object is the one of that class pressed least so far among those
        with unseen presses left (ties broken at random by ``random_state``);
        without ``groups``, the class itself.

        Parameters
        ----------
        label : label
            The class asked for, e.g. ``learner.classes_[idx[0]]``.
        n_presses : int, default=1
            Presses wanted. An object gives at most its unseen presses (a
            recording holds only so many); ask again for more.

        Returns
        -------
        object_id : object
            The object pressed (``groups`` value, or the label).
        X : same kind as ``X_pool``
            Its presses (``n_presses`` or fewer).
        y : ndarray of shape (n,)
            Their labels.

        Raises
        ------
        ValueError
            For an unknown label, or when no unseen press of the class is
            left and ``on_exhausted="raise"``.
        """
        key = self._key(label.item() if isinstance(label, np.generic) else label)
        if self._objects is None:
            X, y = self.press(key, n_presses)
            return key, X, y
        if self.n_remaining(key) == 0:
            if self.on_exhausted == "raise":
                raise ValueError(f"reference object {key!r} has no unseen presses left in the pool.")
            if self.on_exhausted == "truncate":
                self._exhausted(key, n_presses, 0)
                return None, _safe_indexing(self.X_pool, np.empty(0, np.intp)), self.y_pool[:0]
            idx = self._take_objects(key, 1)  # recycle: refill the class, then one press
            obj = self.drawn_objects_[-1]
            idx = np.concatenate([idx, self._take_one(obj, int(n_presses) - 1)])
        else:
            obj = self._pick_object(key)
            idx = self._take_one(obj, int(n_presses))
        idx = idx.astype(np.intp)
        self.drawn_.extend(idx.tolist())
        return obj, _safe_indexing(self.X_pool, idx), self.y_pool[idx]

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
