"""The text of an object-disjoint evaluation: its table, recall per class, notes and recommendation."""

from __future__ import annotations

import numpy as np

from ..utils._intervals import MIN_VALUES_FOR_INTERVAL, format_interval

__all__ = ["format_evaluation"]


def format_evaluation(result):
    """The table of :func:`evaluate_pipelines` as text.

    Parameters
    ----------
    result : EvaluationResult
        What :func:`evaluate_pipelines` returned.

    Returns
    -------
    text : str
        One line per pipeline: balanced accuracy with its 95% interval over
        folds, hardness MAE, time, and the margin over the one-number
        baseline; then the balanced accuracy and margin per object (where
        some object has several presses), each pipeline's recall per class,
        the notes on the presses (``notes``: contact found, the optical
        flow's corners, loading phases missing) and the recommendation.
        With fewer than 5 folds a repetition, the intervals are said in
        words (``"3 folds: too few for an interval"``) instead.
    """
    n_folds = result.table[0]["n_folds"] if result.table else 0
    n_repeats = getattr(result, "n_repeats", 1)
    repeats = f" x {n_repeats} repetitions" if n_repeats > 1 else ""
    n_objects, n_groups = len(np.unique(result.objects)), len(np.unique(result.groups))
    disjoint = "object-disjoint" if n_groups == n_objects else f"group-disjoint ({n_groups} groups of objects)"
    lines = [f"{disjoint} {n_folds}-fold CV{repeats}, {n_objects} objects, "
             f"{len(result.target)} presses, chance {result.chance:.2f}; 95% t-intervals corrected for the "
             "folds' overlapping training sets (Nadeau-Bengio), clipped to the score's range"]
    if n_folds < MIN_VALUES_FOR_INTERVAL:
        lines.append(format_interval(np.nan, np.nan, n_folds, what="folds")
                     + f" (at least {MIN_VALUES_FOR_INTERVAL} a repetition); the table gives the means alone")
    width = max([16] + [len(str(r["pipeline"])) for r in result.table])  # long names keep the columns
    lines.append(f"{'pipeline':<{width}} {'bal. accuracy [95% CI]':<24} {'MAE':>6} {'vs peak [95% CI]':>22} "
                 f"{'time s':>8}")
    for r in result.table:
        mae = "-" if r["mae"] is None else f"{r['mae']:.2f}"
        lines.append(f"{_score_cells(r, width)} {mae:>6} {_margin_cell(r)} {r['fit_predict_seconds']:>8.1f}")
        if r["error"]:
            lines.append(f"  error: {r['error']}")
    lines += _object_lines(result, width)
    lines += _recall_lines(result, width)
    lines += [f"data: {note}" for note in getattr(result, "notes", ())]
    lines += _recommendation_lines(result)
    return "\n".join(lines)


def _object_lines(result, width):
    """Balanced accuracy over the test objects, each classed by the mean of its presses' probabilities.

    Nothing when every object has one press (the figures are those above).
    """
    rows = [r for r in result.table if r.get("object_balanced_accuracy") is not None]
    _, presses = np.unique(result.objects, return_counts=True)
    if not rows or presses.max() == 1:
        return []
    lines = [f"per object: each test object classed by the mean of its presses' predicted probabilities "
             f"(their votes without predict_proba; {len(presses)} objects, median {np.median(presses):g} "
             "presses each); same folds and intervals"]
    for r in rows:
        lines.append(f"{_score_cells(r, width, 'object_')} {'':>6} {_margin_cell(r, 'object_')}".rstrip())
    return lines


def _score_cells(row, width, prefix=""):
    """The pipeline's name and its balanced accuracy with the 95% interval (``prefix``: ``"object_"`` per object)."""
    lo, hi = row[f"{prefix}balanced_accuracy_ci"]
    interval = "" if row["n_folds"] < MIN_VALUES_FOR_INTERVAL else format_interval(lo, hi, row["n_folds"])
    return f"{row['pipeline']:<{width}} {row[f'{prefix}balanced_accuracy']:.2f} {interval:<19}"


def _margin_cell(row, prefix=""):
    """The margin over the one-number baseline with its 95% interval, blank for the baseline itself."""
    delta = ""
    if row.get(f"{prefix}vs_baseline") is not None:
        d_lo, d_hi = row[f"{prefix}vs_baseline_ci"]
        interval = ("" if row["n_folds"] < MIN_VALUES_FOR_INTERVAL
                    else format_interval(d_lo, d_hi, row["n_folds"], fmt="{:+.2f}"))
        delta = f"{row[f'{prefix}vs_baseline']:+.2f} {interval}".rstrip()
    return f"{delta:>22}"


def _recall_lines(result, width):
    """Recall of each class per pipeline, over the out-of-fold predictions (the confusion matrices' diagonals)."""
    rows = [r for r in result.table if r.get("recall")]
    if not rows:
        return []
    names = [str(n) for n in result.target_names]
    lines = [f"recall per class, out of fold ({' / '.join(names)}):"]
    for r in rows:
        values = " / ".join("-" if r["recall"].get(n) is None else f"{r['recall'][n]:.2f}" for n in names)
        lines.append(f"{r['pipeline']:<{width}} {values}")
    return lines


def _recommendation_lines(result):
    """What the table says to choose (the rule of :func:`evaluate_pipelines`'s ``recommended``)."""
    rows = [r for r in result.table if r.get("vs_baseline_ci") is not None]
    if not rows:
        return []
    lines = ["vs peak: each fold's balanced accuracy minus the one-number baseline's, mean over folds and "
             "its corrected 95% t-interval."]
    best, sampled = getattr(result, "recommended", None), getattr(result, "recommended_with_samples", None)
    if best is None:
        lines.append("No pipeline is above the one-number baseline beyond the spread of the folds (every "
                     "interval includes 0 or lies below): on these objects peak_change does as well; more "
                     "objects narrow the intervals.")
        return lines
    lines.append(f"Choose {best}: the highest balanced accuracy among the pipelines above the baseline.")
    if sampled is not None and sampled != best:
        lines.append(f"For active sampling (predict_proba_samples): {sampled}.")
    elif sampled == best:
        lines.append(f"{best} has predict_proba_samples: it drives active sampling too.")
    elif sampled is None:
        lines.append("No pipeline above the baseline has predict_proba_samples for active sampling.")
    return lines
