"""The paper's convergence threshold on the training loss, carried over to other numbers of classes.

Used by :func:`sklearn_hardness.models.is_converged` (``threshold="chance"``)
and by the experiments' ``convergence_threshold="auto"``.
"""

from __future__ import annotations

import math
import numbers

from ._param_validation import Interval, validate_params

__all__ = ["chance_scaled_threshold"]


@validate_params(
    {
        "n_classes": [Interval(numbers.Integral, 2, None, closed="left")],
        "reference_classes": [Interval(numbers.Integral, 2, None, closed="left")],
        "reference_threshold": [Interval(numbers.Real, 0, None, closed="neither")],
    },
    prefer_skip_nested_validation=True,
)
def chance_scaled_threshold(n_classes, *, reference_classes=5, reference_threshold=1.0):
    """The paper's convergence threshold carried over to ``n_classes`` classes.

    The paper calls a ConvLSTM whose training loss after initial training
    exceeds 1 not converged; its robot data have 5 classes. A net that has
    learnt nothing predicts the uniform distribution, whose cross-entropy
    (chance loss) is ``ln K`` for ``K`` classes: 1.61 for 5, 2.20 for 9. A
    fixed threshold of 1 is therefore 62% of chance loss at 5 classes but
    45% at 9 (a stricter rule) and 91% at 3 (a laxer one). This rule keeps
    the paper's fraction of chance loss::

        threshold = reference_threshold * ln(n_classes) / ln(reference_classes)

    which is exactly ``reference_threshold`` at ``reference_classes``.

    Parameters
    ----------
    n_classes : int
        Number of classes of the net (at least 2).
    reference_classes : int, default=5
        Number of classes the reference threshold was set for (the paper's
        robot data: 5 objects).
    reference_threshold : float, default=1.0
        The threshold at ``reference_classes`` (the paper's 1).

    Returns
    -------
    threshold : float
        Largest training loss that counts as converged with ``n_classes``
        classes; pass it to :func:`~sklearn_hardness.models.is_converged`
        (whose ``threshold="chance"`` calls this function).

    Examples
    --------
    >>> from sklearn_hardness.utils._chance_threshold import chance_scaled_threshold
    >>> chance_scaled_threshold(5)
    1.0
    >>> round(chance_scaled_threshold(9), 3), round(chance_scaled_threshold(3), 3)
    (1.365, 0.683)
    """
    if n_classes == reference_classes:
        return float(reference_threshold)  # exactly the reference, whatever the rounding of the logs
    return float(reference_threshold) * math.log(n_classes) / math.log(reference_classes)
