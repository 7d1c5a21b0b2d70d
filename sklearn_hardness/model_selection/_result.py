"""What :func:`~sklearn_hardness.model_selection.evaluate_pipelines` returns: its ``cv_results_`` and what they say."""

from __future__ import annotations

import numpy as np

__all__ = ["EvaluationResult"]


class EvaluationResult:
    """The result of :func:`~sklearn_hardness.model_selection.evaluate_pipelines`.

    One format: ``cv_results_``, a dict of arrays with one entry per
    (pipeline, fold), as :func:`sklearn.model_selection.cross_validate`
    gives for one estimator, that :class:`pandas.DataFrame` takes as is.
    Everything else is derived from it: :attr:`summary` (one row per
    pipeline: means, intervals, margins over the baseline),
    :attr:`recommended`, :meth:`confusion_matrix`, ``str(result)`` (the text
    ``print(result)`` writes: one line per pipeline, its balanced accuracy, or
    primary score, with its 95% interval over folds, hardness MAE, time and
    the margin over the one-number baseline; then the balanced accuracy and
    margin per object where some object has several presses, any other
    score, each pipeline's recall per class, the notes on the presses and the
    recommendation; with fewer than 5 folds a repetition the intervals are
    said in words, ``"3 folds: too few for an interval"``), and
    :meth:`ConfusionMatricesDisplay.from_result
    <sklearn_hardness.model_selection.ConfusionMatricesDisplay.from_result>`
    draws it.

    Attributes
    ----------
    cv_results_ : dict of str to ndarray
        One entry per (pipeline, fold), pipeline by pipeline, folds in the
        splitter's order: ``pipeline`` (its name), ``split`` (the fold's
        index), ``repeat`` (its repetition), ``fit_time`` and
        ``score_time`` (seconds), ``per_press_time`` (the pipeline's
        once-per-run pass of its per-press steps, shared out equally over
        its folds), ``test_<name>`` per scorer (``test_score`` for a single
        one; by default ``test_balanced_accuracy``,
        ``test_object_balanced_accuracy`` and, with ``hardness``,
        ``test_neg_hardness_mae``), ``train_<name>`` with
        ``return_train_score``, ``train_indices`` and ``test_indices`` (the
        fold's presses), ``test_predictions`` (the predicted class indices
        of its test presses, None where the fit failed), ``error`` (None, or
        the failure's type and message) and, with ``return_estimator``,
        ``estimator`` (the fold's fitted pipeline).
    estimators : dict of str to estimator
        The pipelines evaluated, by name, unfitted (the baseline first).
    baseline : str or None
        Name of the baseline pipeline.
    notes : list of str
        What the per-press steps found on the presses that the folds'
        warnings would say (contact found, corners tracked, loading phases),
        and the presses on which they failed.
    target, target_names : ndarray
        Labels (class indices) and class names.
    groups : ndarray
        The group of each press that no fold splits (``groups`` of
        :func:`evaluate_pipelines`: the object, or e.g. its family).
    objects : ndarray
        The object of each press, by which the per-object scores pool
        presses (``objects``, else ``groups``).
    n_splits : int
        Folds a repetition.
    n_repeats : int
        Repetitions of the splitter's folds.

    Examples
    --------
    >>> import pandas as pd
    >>> from sklearn.model_selection import GroupKFold
    >>> from sklearn_hardness.datasets import make_presses
    >>> from sklearn_hardness.model_selection import evaluate_pipelines
    >>> data = make_presses("everyday", n_per_class=2, n_objects=9, class_ratio=[1, 1, 1],
    ...                     image_size=(32, 40), codec=None, random_state=0)
    >>> result = evaluate_pipelines(["contact_profile"], data.videos, data.target, groups=data.object_id,
    ...                             cv=GroupKFold(3), target_names=data.target_names)
    >>> frame = pd.DataFrame(result.cv_results_)
    >>> frame.groupby("pipeline", sort=False)["test_balanced_accuracy"].size().to_dict()
    {'peak_change': 3, 'contact_profile': 3}
    >>> int(result.confusion_matrix("contact_profile").sum())
    18
    """

    def __init__(self, *, cv_results_, estimators, baseline, notes, target, target_names, groups, objects, n_splits,
                 n_repeats):
        self.cv_results_ = cv_results_
        self.estimators = estimators
        self.baseline = baseline
        self.notes = notes
        self.target = target
        self.target_names = target_names
        self.groups = groups
        self.objects = objects
        self.n_splits = n_splits
        self.n_repeats = n_repeats

    @property
    def pipelines(self):
        """The names of the pipelines, in ``cv_results_``' order (the baseline first)."""
        return list(dict.fromkeys(self.cv_results_["pipeline"].tolist()))

    @property
    def chance(self):
        """``1 / n_classes``: the balanced accuracy of a guess."""
        return 1.0 / len(self.target_names)

    @property
    def summary(self):
        """One row per pipeline, derived from ``cv_results_`` (a dict of columns, for
        :class:`pandas.DataFrame` too).

        Columns: ``pipeline``; for each score ``NAME``: ``NAME`` (mean over
        folds), ``NAME_low`` and ``NAME_high`` (its 95% interval corrected
        for the folds' overlap and clipped to the score's range),
        ``NAME_vs_baseline`` with ``_low`` and ``_high`` (the margin over the
        baseline, paired by fold; NaN for the baseline itself); ``time``,
        ``predict_proba_samples`` and ``error``.
        """
        from ._report import summarize

        return summarize(self)

    @property
    def recommended(self):
        """The best pipeline whose margin's interval lies above 0, by balanced accuracy; None when none does."""
        from ._report import recommend

        return recommend(self)[0]

    @property
    def recommended_with_samples(self):
        """As :attr:`recommended`, among the pipelines with ``predict_proba_samples`` (for active sampling)."""
        from ._report import recommend

        return recommend(self)[1]

    def _rows(self, pipeline):
        if pipeline not in self.pipelines:
            raise ValueError(f"unknown pipeline {pipeline!r}; the result has {self.pipelines}.")
        return np.flatnonzero(self.cv_results_["pipeline"] == pipeline)

    def out_of_fold_predictions(self, pipeline, repeat=0):
        """Each press's predicted class index in the fold that tested it, in repetition ``repeat``.

        Parameters
        ----------
        pipeline : str
        repeat : int, default=0

        Returns
        -------
        predictions : ndarray of shape (n_presses,)
            -1 where a press was not tested in that repetition, or its fold
            failed.
        """
        out = np.full(len(self.target), -1)
        for i in self._rows(pipeline):
            pred = self.cv_results_["test_predictions"][i]
            if self.cv_results_["repeat"][i] == repeat and pred is not None:
                out[self.cv_results_["test_indices"][i]] = pred
        return out

    def confusion_matrix(self, pipeline, *, normalize=None):
        """The confusion matrix of ``pipeline``'s out-of-fold predictions, over every fold of every repetition.

        Parameters
        ----------
        pipeline : str
        normalize : {"true", "pred", "all"} or None, default=None
            As :func:`sklearn.metrics.confusion_matrix`: over the true
            classes (rows), the predicted ones (columns), all presses, or
            counts.

        Returns
        -------
        confusion : ndarray of shape (n_classes, n_classes)
            True class per row.
        """
        from sklearn.metrics import confusion_matrix

        true, pred = [], []
        for i in self._rows(pipeline):
            fold_pred = self.cv_results_["test_predictions"][i]
            if fold_pred is not None:
                true.append(self.target[self.cv_results_["test_indices"][i]])
                pred.append(fold_pred)
        n_classes = len(self.target_names)
        if not pred:
            return np.zeros((n_classes, n_classes), dtype=float if normalize else int)
        with np.errstate(all="ignore"):
            return confusion_matrix(np.concatenate(true), np.concatenate(pred), labels=np.arange(n_classes),
                                    normalize=normalize)

    def __str__(self):
        from ._report import format_evaluation

        return format_evaluation(self)

    def __repr__(self):
        return (f"{type(self).__name__}(pipelines={self.pipelines}, n_folds={self.n_splits * self.n_repeats}, "
                f"recommended={self.recommended!r})")
