"""The package's one t-interval: fold scores, paired differences, runs; clipped, and said in words when too few.

:func:`~sklearn_hardness.model_selection.corrected_interval` is its public
face (with the Nadeau-Bengio correction for cross-validation); the
experiments' paired tables call it with ``test_train_ratio=0``.
"""

from __future__ import annotations

import numpy as np
from scipy import stats

__all__ = ["MIN_VALUES_FOR_INTERVAL", "format_interval", "n_independent"]

#: Fewest independent values (degrees of freedom + 1) behind an interval that is printed: with fewer,
#: the t quantile (4.3 on 3 values, 12.7 on 2) makes an interval that says little beyond its width.
MIN_VALUES_FOR_INTERVAL = 5


def _finite(values):
    return np.asarray([v for v in np.ravel(np.asarray(values, dtype=object)) if v is not None and np.isfinite(v)],
                      dtype=float)


def _interval(values, test_train_ratio, df, *, bounds, level=0.95):
    """``corrected_interval`` without validation: the package's own calls."""
    values = _finite(values)
    lo, hi = bounds
    if len(values) < 2:
        m = float(np.clip(values.mean(), lo, hi)) if len(values) else float("nan")
        return m, (float("nan"), float("nan"))
    m = float(values.mean())
    t = stats.t.ppf(0.5 + level / 2, min(df, len(values) - 1))
    half = float(t * np.sqrt(values.var(ddof=1) * (1.0 / len(values) + test_train_ratio)))
    return float(np.clip(m, lo, hi)), (float(np.clip(m - half, lo, hi)), float(np.clip(m + half, lo, hi)))


def n_independent(n_values, df=None):
    """Values behind an interval as :data:`MIN_VALUES_FOR_INTERVAL` counts them: ``min(df, n - 1) + 1``."""
    return n_values if df is None else min(int(df) + 1, n_values)


def format_interval(low, high, n, *, what="pairs", fmt="{:.2f}"):
    """``"[low, high]"``, or in words why there is none: ``"3 pairs: too few for an interval"``.

    Parameters
    ----------
    low, high : float
        The interval (``corrected_interval``).
    n : int
        Independent values behind it (pairs, runs, folds of one repetition).
    what : str, default="pairs"
        What ``n`` counts, for the words.
    fmt : str or callable, default="{:.2f}"
        Format of each bound (``fmt.format(bound)``), or a function of it.

    Returns
    -------
    text : str

    Examples
    --------
    >>> from sklearn_hardness.utils._intervals import format_interval
    >>> format_interval(0.5, 0.8, 10), format_interval(-0.1, 1.5, 3)
    ('[0.50, 0.80]', '3 pairs: too few for an interval')
    """
    if n < MIN_VALUES_FOR_INTERVAL:
        return f"{n} {what}: too few for an interval"
    if not (np.isfinite(low) and np.isfinite(high)):
        return "n/a"
    text = fmt if callable(fmt) else fmt.format
    return f"[{text(low)}, {text(high)}]"
