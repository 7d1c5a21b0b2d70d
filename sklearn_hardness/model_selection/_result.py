"""What :func:`~sklearn_hardness.model_selection.evaluate_pipelines` returns: a small result object."""

from __future__ import annotations

__all__ = ["EvaluationResult", "SummaryTable"]

_INTERVALS = ("balanced_accuracy", "vs_baseline", "mae", "object_balanced_accuracy", "object_vs_baseline")


class SummaryTable(dict):
    """One row per pipeline, as a dict of columns (name -> list), without needing pandas.

    Columns: ``pipeline``; ``balanced_accuracy``, ``vs_baseline`` (margin
    over the baseline, paired by fold), ``mae``,
    ``object_balanced_accuracy`` and ``object_vs_baseline``, each with its
    interval's ``*_low`` and ``*_high``; ``fit_predict_seconds``,
    ``predict_proba_samples`` and ``error``. :meth:`to_frame` gives a
    :class:`pandas.DataFrame` where pandas is installed.
    """

    @classmethod
    def from_rows(cls, rows):
        """The columns of ``rows`` (the result's ``table``)."""
        columns = {"pipeline": [r["pipeline"] for r in rows]}
        for key in _INTERVALS:
            columns[key] = [r[key] for r in rows]
            ci = [r[f"{key}_ci"] or (None, None) for r in rows]
            columns[f"{key}_low"], columns[f"{key}_high"] = [c[0] for c in ci], [c[1] for c in ci]
        for key in ("fit_predict_seconds", "predict_proba_samples", "error"):
            columns[key] = [r[key] for r in rows]
        return cls(columns)

    def to_frame(self):
        """The table as a :class:`pandas.DataFrame` indexed by pipeline (needs pandas).

        Returns
        -------
        frame : pandas.DataFrame
        """
        import pandas as pd

        return pd.DataFrame(self).set_index("pipeline")

    def __str__(self):
        cells = {k: ["-" if v is None else f"{v:.3f}" if isinstance(v, float) else str(v) for v in col]
                 for k, col in self.items()}
        widths = {k: max([len(k)] + [len(c) for c in col]) for k, col in cells.items()}
        lines = ["  ".join(f"{k:<{widths[k]}}" for k in cells)]
        lines += ["  ".join(f"{cells[k][i]:<{widths[k]}}" for k in cells) for i in range(len(self["pipeline"]))]
        return "\n".join(line.rstrip() for line in lines)


class EvaluationResult:
    """The result of :func:`~sklearn_hardness.model_selection.evaluate_pipelines`.

    ``str(result)`` is its text report
    (:func:`~sklearn_hardness.model_selection.format_evaluation`);
    :meth:`ConfusionMatricesDisplay.from_result
    <sklearn_hardness.model_selection.ConfusionMatricesDisplay.from_result>`
    draws its confusion matrices.

    Attributes
    ----------
    summary : SummaryTable
        One row per pipeline (dict of columns; ``summary.to_frame()`` with
        pandas).
    table : list of dict
        The same rows, one dict per pipeline, intervals as ``*_ci``
        ``(low, high)`` pairs (None where they do not apply), ``recall``
        (class name -> out-of-fold recall), ``n_folds`` (folds a
        repetition) and ``n_repeats``.
    fold_scores, object_fold_scores : dict of str to ndarray of shape (n_folds,)
        Balanced accuracy per fold, per press and per test object.
    differences : dict of str to ndarray of shape (n_folds,)
        Each pipeline's fold scores minus the baseline's (not for the
        baseline itself; empty without one).
    predictions : dict of str to ndarray of shape (n_samples,)
        Out-of-fold predictions of the first repetition (-1 where a press
        was not tested, or its fold failed).
    confusion : dict of str to ndarray of shape (n_classes, n_classes)
        Confusion matrix of the out-of-fold predictions of all folds.
    recommended, recommended_with_samples : str or None
        The best pipeline whose margin's interval lies above 0 (among those
        with ``predict_proba_samples``); None when none does.
    baseline : str or None
        Name of the baseline pipeline.
    notes : list of str
        What the per-press steps found that the folds' warnings would say.
    target, target_names : ndarray
        Labels and class names.
    groups : ndarray
        The group of each press that no fold splits (``groups`` of
        :func:`evaluate_pipelines`: the object, or e.g. its family).
    objects : ndarray
        The object of each press, by which the per-object figures pool
        presses (``objects``, else ``groups``).
    folds : list of ndarray
        The test indices of every fold.
    n_repeats : int
        Repetitions of the splitter's folds.
    chance : float
        ``1 / n_classes``.
    """

    def __init__(self, *, table, fold_scores, object_fold_scores, predictions, confusion, recommended,
                 recommended_with_samples, baseline, notes, target, target_names, groups, folds, n_repeats,
                 objects=None):
        self.table = table
        self.summary = SummaryTable.from_rows(table)
        self.fold_scores = fold_scores
        self.object_fold_scores = object_fold_scores
        base = fold_scores.get(baseline) if baseline is not None else None
        self.differences = {} if base is None else {name: scores - base for name, scores in fold_scores.items()
                                                    if name != baseline}
        self.predictions = predictions
        self.confusion = confusion
        self.recommended = recommended
        self.recommended_with_samples = recommended_with_samples
        self.baseline = baseline
        self.notes = notes
        self.target = target
        self.target_names = target_names
        self.groups = groups
        self.objects = groups if objects is None else objects
        self.folds = folds
        self.n_repeats = n_repeats
        self.chance = 1.0 / len(target_names)

    def __str__(self):
        from ._report import format_evaluation

        return format_evaluation(self)

    def __repr__(self):
        return (f"{type(self).__name__}(pipelines={list(self.fold_scores)}, n_folds={len(self.folds)}, "
                f"recommended={self.recommended!r})")
