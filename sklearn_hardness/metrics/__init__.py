"""Hardness-aware metrics.

- :func:`hardness_mae`: mean absolute error between the hardness of the
  predicted and the true reference objects (the paper's MAE).
- :func:`make_hardness_mae_scorer`: the same as a scorer (negative MAE) for
  ``cross_val_score`` and ``GridSearchCV``.
"""

from ._hardness import hardness_mae, make_hardness_mae_scorer

__all__ = ["hardness_mae", "make_hardness_mae_scorer"]
