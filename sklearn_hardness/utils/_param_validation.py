"""Parameter constraints scikit-learn does not ship, for ``_parameter_constraints`` tables.

They plug into scikit-learn's own machinery (``_fit_context``,
``validate_params``), so a wrong value raises
:class:`~sklearn.utils._param_validation.InvalidParameterError` with
scikit-learn's message format, like every other parameter.
"""

from __future__ import annotations

import numbers

import numpy as np
from sklearn.utils._param_validation import Interval, Options, make_constraint

__all__ = ["Pair", "ValueRange", "FRAME_SIZE"]


class _CustomConstraint(Options):
    """Base of our constraints.

    scikit-learn's ``make_constraint`` accepts only its own constraint
    classes; deriving from ``Options`` (and overriding its test) makes it
    take ours unchanged.
    """

    def __init__(self):
        super().__init__(type=object, options=set())


class Pair(_CustomConstraint):
    """A tuple or list of exactly two values, each satisfying ``item``.

    Parameters
    ----------
    item : constraint
        Any constraint scikit-learn accepts (an ``Interval``, a type, ...).
    description : str
        How the pair is named in the error message, e.g. ``"(width, height)"``.

    Examples
    --------
    >>> from numbers import Integral
    >>> from sklearn.utils._param_validation import Interval
    >>> from sklearn_hardness.utils._param_validation import Pair
    >>> c = Pair(Interval(Integral, 3, None, closed="left"), "(width, height)")
    >>> c.is_satisfied_by((15, 15)), c.is_satisfied_by((2, 15)), c.is_satisfied_by(15)
    (True, False, False)
    """

    def __init__(self, item, description):
        super().__init__()
        self.item = make_constraint(item)
        self.description = description

    def is_satisfied_by(self, val):
        return (
            isinstance(val, (tuple, list))
            and len(val) == 2
            and all(not isinstance(v, (bool, np.bool_)) and self.item.is_satisfied_by(v) for v in val)
        )

    def __str__(self):
        return f"a pair {self.description} of which each is {self.item}"


class ValueRange(_CustomConstraint):
    """A pair ``(low, high)`` of finite real numbers with ``low < high``.

    Examples
    --------
    >>> from sklearn_hardness.utils._param_validation import ValueRange
    >>> ValueRange().is_satisfied_by((0, 1)), ValueRange().is_satisfied_by((1, 0))
    (True, False)
    """

    def __init__(self):
        super().__init__()
        self._finite = Pair(Interval(numbers.Real, None, None, closed="neither"), "(low, high)")

    def is_satisfied_by(self, val):
        return (
            self._finite.is_satisfied_by(val)
            and bool(np.all(np.isfinite(val)))
            and val[0] < val[1]
        )

    def __str__(self):
        return "a pair (low, high) of finite numbers with low < high, e.g. (0, 1) or (-1, 1)"


#: The size of frames fed to a model, ``(height, width)`` with ints >= 2: the one rule for
#: ``ContactFrameSelector(frame_size=...)``, the factories' and the experiments' ``frame_size``
#: and ``record_video(image_size=...)``.
FRAME_SIZE = Pair(Interval(numbers.Integral, 2, None, closed="left"), "(height, width)")
