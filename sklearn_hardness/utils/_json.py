"""Values as JSON takes them: the experiments' results files and ``evaluate --json``."""

from __future__ import annotations

import numpy as np

__all__ = ["to_json"]


def to_json(value):
    """``value`` with numpy arrays and scalars as lists and Python numbers, and NaN/inf as None."""
    if isinstance(value, dict):
        return {str(k): to_json(v) for k, v in value.items()}
    if isinstance(value, (list, tuple)):
        return [to_json(v) for v in value]
    if isinstance(value, np.ndarray):
        return to_json(value.tolist())
    if isinstance(value, np.generic):
        return value.item()
    if isinstance(value, float) and not np.isfinite(value):
        return None  # JSON has no NaN/inf
    return value
