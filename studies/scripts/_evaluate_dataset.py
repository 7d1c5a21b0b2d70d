"""``evaluate_pipelines`` on a dataset Bunch: its presses, labels, objects, class names and hardness.

The studies evaluate whole datasets (a simulator preset, PhysiCLeAR's
development objects, a Bunch of their own). :func:`evaluate_dataset` passes
a dataset's columns to
:func:`~sklearn_hardness.model_selection.evaluate_pipelines` as the studies'
committed outputs were made: folds grouped by ``object_id`` (or ``groups``),
each press's force and position where every press has them (so that
``estimators=None`` adds ``loading_compliance``, as ``sklearn-hardness
evaluate`` does), and a failing fit raises (``error_score="raise"``) rather
than leaving a fold out of a study's figure.
"""

import numpy as np

from sklearn_hardness.model_selection import evaluate_pipelines


def force_position(data):
    """Each press's ``(T, 2)`` force and position per frame, or None where some press lacks either."""
    force, position = getattr(data, "force", None), getattr(data, "position", None)
    if force is None or position is None or any(f is None or z is None for f, z in zip(force, position)):
        return None
    return [np.column_stack([np.asarray(f, dtype=float).ravel(), np.asarray(z, dtype=float).ravel()])
            for f, z in zip(force, position)]


def evaluate_dataset(data, estimators=None, *, groups=None, error_score="raise", **kwargs):
    """``evaluate_pipelines(estimators, data.videos, data.target, groups=data.object_id, ...)``.

    Parameters
    ----------
    data : Bunch
        ``videos``, ``target`` (class indices), ``target_names`` and
        ``object_id``; ``hardness``, ``force`` and ``position`` where it has them.
    estimators : dict, list or None, default=None
        As ``evaluate_pipelines`` takes them.
    groups : array-like or None, default=None
        The group of each press; None: ``data.object_id``. The per-object
        scores class each group.
    error_score : "raise" or float, default="raise"
        What a failing fit gives.
    **kwargs
        Passed on (``cv``, ``n_repeats``, ``n_jobs``, ``random_state``, ``verbose``...).

    Returns
    -------
    result : EvaluationResult
    """
    return evaluate_pipelines(estimators, data.videos, data.target,
                              groups=data.object_id if groups is None else groups,
                              target_names=data.target_names, hardness=getattr(data, "hardness", None),
                              force_position=force_position(data), error_score=error_score, **kwargs)
