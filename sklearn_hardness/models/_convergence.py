"""The paper's convergence rule: training loss after initial training <= 1 (for 5 classes)."""

from __future__ import annotations

import numbers
import warnings

import numpy as np
from sklearn.exceptions import ConvergenceWarning

from ..utils._chance_threshold import chance_scaled_threshold
from ..utils._warnings import external_stacklevel

__all__ = ["is_converged", "check_convergence"]


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
