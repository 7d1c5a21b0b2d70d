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

from sklearn_hardness.model_selection import evaluate_pipelines
from sklearn_hardness.utils._force_position import force_position, presses_lacking_force_position


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
    rows = None if presses_lacking_force_position(data) else force_position(data, ["loading_compliance"])
    return evaluate_pipelines(estimators, data.videos, data.target,
                              groups=data.object_id if groups is None else groups,
                              target_names=data.target_names, hardness=getattr(data, "hardness", None),
                              force_position=rows, error_score=error_score, **kwargs)
