"""The paper's convergence rule: training loss after initial training <= 1."""

from __future__ import annotations

import numbers
import warnings

import numpy as np
from sklearn.exceptions import ConvergenceWarning

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


def is_converged(net, threshold=1.0):
    """Whether a trained net converged by the paper's rule.

    The paper reports a ConvLSTM "whose training loss after initial training
    exceeds 1" as not converged and leaves it out (81% of its runs
    converged). The loss is the mean cross-entropy of the last training
    epoch, as recorded by skorch (dropout on).

    Parameters
    ----------
    net : fitted classifier or float
        A classifier of :mod:`sklearn_hardness.models` (or any skorch net
        with a ``train_loss`` history) after ``fit``, or the loss itself.
    threshold : float, default=1.0
        Largest training loss that counts as converged.

    Returns
    -------
    converged : bool
        ``loss <= threshold``; a NaN or infinite loss is never converged.

    Examples
    --------
    >>> from sklearn_hardness.models import is_converged
    >>> is_converged(0.4), is_converged(1.3), is_converged(float("nan"))
    (True, False, False)
    """
    loss = _final_loss(net)
    return bool(np.isfinite(loss) and loss <= threshold)


def check_convergence(net, threshold=1.0):
    """Like :func:`is_converged`, and warn when the net did not converge.

    Parameters
    ----------
    net : fitted classifier or float
        See :func:`is_converged`.
    threshold : float, default=1.0
        Largest training loss that counts as converged.

    Returns
    -------
    converged : bool

    Warns
    -----
    sklearn.exceptions.ConvergenceWarning
        If the final training loss is above ``threshold`` or not finite.
    """
    loss = _final_loss(net)
    converged = is_converged(loss, threshold)
    if not converged:
        warnings.warn(
            f"Training did not converge: final training loss {loss:.4g} > {threshold} "
            "(the paper skips such runs). Train longer, lower the learning rate or check the input.",
            ConvergenceWarning,
            stacklevel=2,
        )
    return converged
