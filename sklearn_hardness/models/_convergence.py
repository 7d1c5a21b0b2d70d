"""The paper's convergence rule: training loss after initial training <= 1 (for 5 classes)."""

from __future__ import annotations

import math
import numbers
import warnings

import numpy as np
from sklearn.exceptions import ConvergenceWarning

from ..utils._param_validation import Interval, validate_params
from ..utils._warnings import external_stacklevel

__all__ = ["chance_scaled_threshold", "is_converged", "check_convergence"]


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
        classes; pass it to :func:`is_converged`.

    See Also
    --------
    is_converged : Apply a threshold (``threshold="chance"`` calls this function).

    Examples
    --------
    >>> from sklearn_hardness.models._convergence import chance_scaled_threshold
    >>> chance_scaled_threshold(5)
    1.0
    >>> round(chance_scaled_threshold(9), 3), round(chance_scaled_threshold(3), 3)
    (1.365, 0.683)
    """
    if n_classes == reference_classes:
        return float(reference_threshold)  # exactly the reference, whatever the rounding of the logs
    return float(reference_threshold) * math.log(n_classes) / math.log(reference_classes)


def _final_loss(net):
    if isinstance(net, numbers.Real) and not isinstance(net, bool):
        return float(net)
    try:
        return float(net.final_train_loss_)
    except AttributeError:
        pass
    history = getattr(net, "history_", None)
    if history:
        try:
            return float(history[-1, "train_loss"])
        except KeyError:
            pass
    raise TypeError(
        "is_converged needs a trained classifier (with final_train_loss_ or a skorch history "
        f"with train_loss) or a loss value, got {type(net).__name__}."
    )


def _threshold(net, threshold, n_classes):
    """The numeric threshold: ``threshold`` itself, or the chance-scaled one for ``"chance"``."""
    if isinstance(threshold, str):
        if threshold != "chance":
            raise ValueError(f'threshold must be a number or "chance", got {threshold!r}.')
        if n_classes is None:
            classes = getattr(net, "classes_", None)
            if classes is None:
                raise ValueError(
                    'threshold="chance" needs the number of classes: pass n_classes=..., or a fitted '
                    "classifier (with classes_) instead of a loss value."
                )
            n_classes = len(classes)
        return chance_scaled_threshold(n_classes)
    if n_classes is not None:
        raise ValueError(f'n_classes is used only with threshold="chance"; got threshold={threshold!r}.')
    if isinstance(threshold, bool) or not isinstance(threshold, numbers.Real):
        raise TypeError(f'threshold must be a number or "chance", got {type(threshold).__name__}.')
    return float(threshold)


def is_converged(net, threshold=1.0, *, n_classes=None):
    """Whether a trained net converged by the paper's rule.

    The paper reports a ConvLSTM "whose training loss after initial training
    exceeds 1" as not converged and leaves it out. The loss is the mean cross-entropy of the last training
    epoch, as recorded by skorch (dropout on). The paper's data have 5
    classes; ``threshold="chance"`` carries its rule over to any number of
    classes as the same fraction of chance loss ``ln K``
    (the paper's 1 times ``ln K / ln 5``: 1 at 5 classes, 1.365 at 9).

    Parameters
    ----------
    net : fitted classifier or float
        A classifier of :mod:`sklearn_hardness.models` (or any skorch net
        with a ``train_loss`` history) after ``fit``, or the loss itself.
    threshold : float or "chance", default=1.0
        Largest training loss that counts as converged. ``"chance"``:
        the paper's 1 times ``ln K / ln 5`` at ``K`` classes.
    n_classes : int or None, default=None
        Number of classes for ``threshold="chance"``; None takes it from the
        net's ``classes_`` (needed when ``net`` is a loss value).

    Returns
    -------
    converged : bool
        ``loss <= threshold``; a NaN or infinite loss is never converged.

    Examples
    --------
    >>> from sklearn_hardness.models import is_converged
    >>> is_converged(0.4), is_converged(1.3), is_converged(float("nan"))
    (True, False, False)
    >>> is_converged(1.3, "chance", n_classes=9)  # 1.3 <= ln 9 / ln 5 = 1.365
    True
    """
    limit = _threshold(net, threshold, n_classes)
    loss = _final_loss(net)
    return bool(np.isfinite(loss) and loss <= limit)


def check_convergence(net, threshold=1.0, *, n_classes=None):
    """Like :func:`is_converged`, and warn when the net did not converge.

    Parameters
    ----------
    net : fitted classifier or float
        See :func:`is_converged`.
    threshold : float or "chance", default=1.0
        See :func:`is_converged`.
    n_classes : int or None, default=None
        See :func:`is_converged`.

    Returns
    -------
    converged : bool

    Warns
    -----
    sklearn.exceptions.ConvergenceWarning
        If the final training loss is above ``threshold`` or not finite.
    """
    limit = _threshold(net, threshold, n_classes)
    loss = _final_loss(net)
    converged = is_converged(loss, limit)
    if not converged:
        warnings.warn(
            f"Training did not converge: final training loss {loss:.4g} > {limit:.4g} "
            "(the paper skips such runs). Train longer, lower the learning rate or check the input.",
            ConvergenceWarning,
            stacklevel=external_stacklevel(),
        )
    return converged
