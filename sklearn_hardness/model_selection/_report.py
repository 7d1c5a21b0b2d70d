"""What an evaluation's ``cv_results_`` say: the summary (intervals, margins), the recommendation, the text.

Everything here is derived from :attr:`EvaluationResult.cv_results_`: one
row per pipeline with each score's mean over the folds, its 95% t-interval
corrected for the folds' overlapping training sets (Nadeau-Bengio) and
clipped to the range the score can take, and its margin over the baseline
paired by fold; the pipeline to choose; the text of ``sklearn-hardness
evaluate``.
"""

from __future__ import annotations

import numpy as np

from ..utils._intervals import MIN_VALUES_FOR_INTERVAL, _interval, format_interval

__all__ = ["format_evaluation", "recommend", "summarize"]

#: The range of the scores whose range is known, for their intervals (others are not clipped).
_BOUNDS = {"balanced_accuracy": (0.0, 1.0), "object_balanced_accuracy": (0.0, 1.0),
           "neg_hardness_mae": (-np.inf, 0.0), "accuracy": (0.0, 1.0)}


def _bounds(scorer):
    return _BOUNDS.get(scorer, (-np.inf, np.inf))


def score_names(cv_results):
    """The scores of ``cv_results`` by name (``"score"`` for a single scorer), in their order."""
    return [key[len("test_"):] for key in cv_results
            if key.startswith("test_") and key not in ("test_indices", "test_predictions")]


def fold_scores(cv_results, pipeline, score):
    """The test ``score`` of ``pipeline`` on each fold, in the folds' order."""
    rows = np.flatnonzero(cv_results["pipeline"] == pipeline)
    rows = rows[np.argsort(cv_results["split"][rows], kind="stable")]
    return np.asarray(cv_results[f"test_{score}"], dtype=float)[rows]


def _test_train_ratio(cv_results, pipeline):
    rows = np.flatnonzero(cv_results["pipeline"] == pipeline)
    return float(np.mean([len(cv_results["test_indices"][i]) / len(cv_results["train_indices"][i]) for i in rows]))


def summarize(result):
    """One row per pipeline of ``result.cv_results_``: each score's mean, interval and margin over the baseline.

    Parameters
    ----------
    result : EvaluationResult

    Returns
    -------
    summary : dict of str to list
        ``pipeline``; per score ``NAME`` (``balanced_accuracy``,
        ``object_balanced_accuracy``, ``neg_hardness_mae`` or the user's):
        ``NAME`` (mean over folds), ``NAME_low``, ``NAME_high`` (its 95%
        interval) and ``NAME_vs_baseline`` with ``_low``, ``_high`` (the
        margin over the baseline paired by fold; NaN for the baseline and
        without one); ``time`` (seconds: the per-press pass, fits and
        scoring), ``predict_proba_samples`` and ``error`` (the failures'
        messages, or None). NaN where a figure cannot be computed.
    """
    cv = result.cv_results_
    names, scores = result.pipelines, score_names(cv)
    df = result.n_splits - 1
    summary = {"pipeline": list(names)}
    for score in scores:
        lo, hi = _bounds(score)
        base = None if result.baseline is None else fold_scores(cv, result.baseline, score)
        columns = {key: [] for key in ("", "_low", "_high", "_vs_baseline", "_vs_baseline_low", "_vs_baseline_high")}
        for name in names:
            values, ratio = fold_scores(cv, name, score), _test_train_ratio(cv, name)
            mean, (low, high) = _interval(values, ratio, df, bounds=(lo, hi))
            margin, (m_low, m_high) = np.nan, (np.nan, np.nan)
            if base is not None and name != result.baseline:
                margin, (m_low, m_high) = _interval(values - base, ratio, df, bounds=(lo - hi, hi - lo))
            for key, value in zip(columns, (mean, low, high, margin, m_low, m_high)):
                columns[key].append(float(value))
        summary.update({score + key: values for key, values in columns.items()})
    rows = {name: np.flatnonzero(cv["pipeline"] == name) for name in names}
    summary["time"] = [float(sum(cv[key][rows[name]].sum() for key in ("fit_time", "score_time", "per_press_time")))
                       for name in names]
    summary["predict_proba_samples"] = [hasattr(result.estimators[name], "predict_proba_samples") for name in names]
    summary["error"] = ["; ".join(sorted({e for e in cv["error"][rows[name]] if e is not None})) or None
                        for name in names]
    return summary


def primary_score(result):
    """The score the margins and the recommendation go by: balanced accuracy where scored, else the first."""
    scores = score_names(result.cv_results_)
    return "balanced_accuracy" if "balanced_accuracy" in scores else scores[0]


def recommend(result, summary=None):
    """The best pipeline above the baseline (paired interval above 0), overall and with ``predict_proba_samples``.

    By the primary score (:func:`primary_score`); None where none is above.
    """
    summary = summarize(result) if summary is None else summary
    score = primary_score(result)
    above = [i for i, low in enumerate(summary[f"{score}_vs_baseline_low"]) if np.isfinite(low) and low > 0]
    best = max(above, key=lambda i: summary[score][i], default=None)
    sampled = max((i for i in above if summary["predict_proba_samples"][i]), key=lambda i: summary[score][i],
                  default=None)
    return tuple(None if i is None else summary["pipeline"][i] for i in (best, sampled))


def format_evaluation(result):
    """``str(result)`` of an :class:`EvaluationResult` (documented there).

    Examples
    --------
    >>> from sklearn.model_selection import GroupKFold
    >>> from sklearn_hardness.datasets import make_presses
    >>> from sklearn_hardness.model_selection import evaluate_pipelines
    >>> data = make_presses("everyday", n_per_class=2, n_objects=9, class_ratio=[1, 1, 1],
    ...                     image_size=(32, 40), codec=None, random_state=0)
    >>> result = evaluate_pipelines([], data.videos, data.target, groups=data.object_id,
    ...                             cv=GroupKFold(3), target_names=data.target_names)
    >>> print(str(result).splitlines()[0][:45])
    object-disjoint 3-fold CV, 9 objects, 18 pres
    """
    summary = summarize(result)
    score = primary_score(result)
    rows = [{key: values[i] for key, values in summary.items()} for i in range(len(summary["pipeline"]))]
    n_folds = result.n_splits
    repeats = f" x {result.n_repeats} repetitions" if result.n_repeats > 1 else ""
    n_objects, n_groups = len(np.unique(result.objects)), len(np.unique(result.groups))
    disjoint = "object-disjoint" if n_groups == n_objects else f"group-disjoint ({n_groups} groups of objects)"
    lines = [f"{disjoint} {n_folds}-fold CV{repeats}, {n_objects} objects, "
             f"{len(result.target)} presses, chance {result.chance:.2f}; 95% t-intervals corrected for the "
             "folds' overlapping training sets (Nadeau-Bengio), clipped to the score's range"]
    if n_folds < MIN_VALUES_FOR_INTERVAL:
        lines.append(format_interval(np.nan, np.nan, n_folds, what="folds")
                     + f" (at least {MIN_VALUES_FOR_INTERVAL} a repetition); the table gives the means alone")
    width = max([16] + [len(str(r["pipeline"])) for r in rows])  # long names keep the columns
    title = "bal. accuracy" if score == "balanced_accuracy" else score
    lines.append(f"{'pipeline':<{width}} {title + ' [95% CI]':<24} {'MAE':>6} {'vs peak [95% CI]':>22} "
                 f"{'time s':>8}")
    has_mae = "neg_hardness_mae" in summary
    for r in rows:
        mae = "-" if not has_mae or not np.isfinite(r["neg_hardness_mae"]) else f"{-r['neg_hardness_mae']:.2f}"
        lines.append(f"{_score_cells(r, score, width, n_folds)} {mae:>6} {_margin_cell(r, score, n_folds)} "
                     f"{r['time']:>8.1f}")
        if r["error"]:
            lines.append(f"  error: {r['error']}")
    lines += _object_lines(result, rows, width, n_folds)
    lines += _other_score_lines(rows, score_names(result.cv_results_), score, width, n_folds)
    lines += _recall_lines(result, width)
    lines += [f"data: {note}" for note in result.notes]
    lines += _recommendation_lines(result, summary, score)
    return "\n".join(lines)


def _object_lines(result, rows, width, n_folds):
    """Balanced accuracy over the test objects, each classed by the mean of its presses' probabilities.

    Nothing when every object has one press (the figures are those above), or without that score.
    """
    if "object_balanced_accuracy" not in rows[0]:
        return []
    _, presses = np.unique(result.objects, return_counts=True)
    if presses.max() == 1:
        return []
    lines = [f"per object: each test object classed by the mean of its presses' predicted probabilities "
             f"(their votes without predict_proba; {len(presses)} objects, median {np.median(presses):g} "
             "presses each); same folds and intervals"]
    for r in rows:
        lines.append(f"{_score_cells(r, 'object_balanced_accuracy', width, n_folds)} {'':>6} "
                     f"{_margin_cell(r, 'object_balanced_accuracy', n_folds)}".rstrip())
    return lines


def _other_score_lines(rows, scores, primary, width, n_folds):
    """Each score the lines above do not show: its mean with the 95% interval and the margin, per pipeline."""
    lines = []
    for score in scores:
        if score in (primary, "object_balanced_accuracy", "neg_hardness_mae"):
            continue
        lines.append(f"{score} (mean over folds [95% CI], margin over the baseline):")
        lines += [f"{_score_cells(r, score, width, n_folds)} {'':>6} {_margin_cell(r, score, n_folds)}".rstrip()
                  for r in rows]
    return lines


def _score_cells(row, score, width, n_folds):
    """The pipeline's name and its mean ``score`` with the 95% interval."""
    interval = ("" if n_folds < MIN_VALUES_FOR_INTERVAL
                else format_interval(row[f"{score}_low"], row[f"{score}_high"], n_folds))
    return f"{row['pipeline']:<{width}} {row[score]:.2f} {interval:<19}"


def _margin_cell(row, score, n_folds):
    """The margin over the one-number baseline with its 95% interval, blank for the baseline itself."""
    delta = ""
    if np.isfinite(row[f"{score}_vs_baseline"]):
        interval = ("" if n_folds < MIN_VALUES_FOR_INTERVAL
                    else format_interval(row[f"{score}_vs_baseline_low"], row[f"{score}_vs_baseline_high"], n_folds,
                                         fmt="{:+.2f}"))
        delta = f"{row[f'{score}_vs_baseline']:+.2f} {interval}".rstrip()
    return f"{delta:>22}"


def _recall_lines(result, width):
    """Recall of each class per pipeline, over the out-of-fold predictions (the confusion matrices' diagonals)."""
    names = [str(n) for n in result.target_names]
    lines = [f"recall per class, out of fold ({' / '.join(names)}):"]
    for pipeline in result.pipelines:
        confusion = result.confusion_matrix(pipeline)
        support = confusion.sum(axis=1)
        values = " / ".join("-" if not support[c] else f"{confusion[c, c] / support[c]:.2f}"
                            for c in range(len(names)))
        lines.append(f"{pipeline:<{width}} {values}")
    return lines


def _recommendation_lines(result, summary, score):
    """What the table says to choose (the rule of :attr:`EvaluationResult.recommended`)."""
    if result.baseline is None or len(summary["pipeline"]) < 2:
        return []
    what = "balanced accuracy" if score == "balanced_accuracy" else score
    lines = [f"vs peak: each fold's {what} minus the one-number baseline's, mean over folds and "
             "its corrected 95% t-interval."]
    best, sampled = recommend(result, summary)
    if best is None:
        lines.append("No pipeline is above the one-number baseline beyond the spread of the folds (every "
                     f"interval includes 0 or lies below): on these objects {result.baseline} does as well; more "
                     "objects narrow the intervals.")
        return lines
    lines.append(f"Choose {best}: the highest {what} among the pipelines above the baseline.")
    if sampled is not None and sampled != best:
        lines.append(f"For active sampling (predict_proba_samples): {sampled}.")
    elif sampled == best:
        lines.append(f"{best} has predict_proba_samples: it drives active sampling too.")
    else:
        lines.append("No pipeline above the baseline has predict_proba_samples for active sampling.")
    return lines
