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

from sklearn_hardness.datasets import force_and_position
from sklearn_hardness.model_selection import evaluate_pipelines


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
    rows = force_and_position(data, missing="none")
    return evaluate_pipelines(estimators, data.videos, data.target,
                              groups=data.object_id if groups is None else groups,
                              target_names=data.target_names, hardness=getattr(data, "hardness", None),
                              force_position=rows, error_score=error_score, **kwargs)


def fold_scores(result, pipeline, score="balanced_accuracy"):
    """The test ``score`` of ``pipeline`` on each fold, in the folds' order (from ``result.cv_results_``)."""
    cv = result.cv_results_
    rows = np.flatnonzero(cv["pipeline"] == pipeline)
    return np.asarray(cv[f"test_{score}"], dtype=float)[rows[np.argsort(cv["split"][rows], kind="stable")]]


def test_folds(result):
    """The test presses of every fold, in the folds' order."""
    cv = result.cv_results_
    return list(cv["test_indices"][cv["pipeline"] == result.pipelines[0]])


def table_rows(result):
    """``{pipeline: row}`` of ``result.summary`` in the studies' printed layout: ``balanced_accuracy`` and its
    ``balanced_accuracy_ci``, ``vs_baseline`` (None for the baseline) and ``vs_baseline_ci``, the same with
    ``object_``, ``mae`` (positive) and ``fit_predict_seconds`` (the pipeline's time)."""
    summary = result.summary

    def finite(value):
        return None if value is None or not np.isfinite(value) else float(value)

    rows = {}
    for i, name in enumerate(summary["pipeline"]):
        row = {"pipeline": name, "fit_predict_seconds": summary["time"][i], "error": summary["error"][i]}
        for prefix in ("", "object_"):
            score = f"{prefix}balanced_accuracy"
            row[score] = summary[score][i]
            row[f"{score}_ci"] = (summary[f"{score}_low"][i], summary[f"{score}_high"][i])
            margin = finite(summary[f"{score}_vs_baseline"][i])
            row[f"{prefix}vs_baseline"] = margin
            row[f"{prefix}vs_baseline_ci"] = None if margin is None else (
                summary[f"{score}_vs_baseline_low"][i], summary[f"{score}_vs_baseline_high"][i])
        if "neg_hardness_mae" in summary:
            row["mae"] = -summary["neg_hardness_mae"][i]
        rows[name] = row
    return rows
