"""Paired comparison of active-sampling strategies: 95% intervals and p-values against a reference.

Runs of different strategies with the same (test object, seed) start from the
same initial model and test presses, so a strategy is judged by its
per-pair difference to the reference strategy (``random`` by default): the
mean difference with a t-interval over the pairs, a paired t-test and a
Wilcoxon signed-rank test (:mod:`scipy.stats`).
"""

from __future__ import annotations

import numpy as np

__all__ = ["paired_table", "format_paired_table", "PAIRED_METRICS", "decision_stop"]

#: Metrics of :func:`paired_table`: (name, record field, reduction, higher is better).
#: ``auc`` is the mean of the accuracy over iterations 0..N (trapezoid rule,
#: normalised to [0, 1]): a strategy that gets there sooner scores higher.
#: ``presses_at_stop`` and ``accuracy_at_stop`` are the reference presses used
#: and the test accuracy when :func:`decision_stop` (its defaults) ends the run.
PAIRED_METRICS = (
    ("accuracy", "accuracy", "final", True),
    ("mae", "mae", "final", False),
    ("auc", "accuracy", "auc", True),
    ("holdout_accuracy", "holdout_accuracy", "final", True),
    ("holdout_mae", "holdout_mae", "final", False),
    ("presses_at_stop", "predictions", "stop_presses", False),
    ("accuracy_at_stop", "predictions", "stop_accuracy", True),
)


def decision_stop(record, *, threshold=0.8, patience=2):
    """Where a run would have stopped: the iteration, presses used and accuracy then.

    The paper always makes ``N`` iterations; a robot stops once its decision
    on the test object is settled. Replayed on a finished run's record: the
    *decision* after iteration ``t`` is the class most of the test presses are
    predicted as, its *agreement* the fraction of them predicted so. The run
    stops at the first ``t`` where the agreement is at least ``threshold``
    and the decision was the same in the last ``patience`` iterations
    (``t`` included; iteration 0 is the initial model), and at the last
    iteration (the press budget) otherwise. The same rule, on mean MC
    probabilities instead of votes, is :class:`~sklearn_hardness.active.ActiveLearner`'s
    ``stop_threshold`` / ``stop_patience``.

    Parameters
    ----------
    record : dict
        One run of :func:`run_active_sampling` (``predictions``,
        ``initial_indices``, ``drawn_indices`` and ``key["test_class"]``).
    threshold : float in (0, 1], default=0.8
        Least fraction of the test presses that agree (4 of 5 at 0.8).
    patience : int >= 1, default=2
        Iterations whose decisions must agree.

    Returns
    -------
    stop : dict
        ``iteration`` (0..N), ``presses`` (reference presses pressed up to
        then: the initial ones and those drawn by the queries so far),
        ``accuracy`` (fraction of the test presses classified correctly then)
        and ``settled`` (False when the budget ended the run).

    Examples
    --------
    >>> from sklearn_hardness.experiments import decision_stop
    >>> rec = {"key": {"test_class": 1}, "initial_indices": list(range(10)),
    ...        "drawn_indices": [[10, 11], [12, 13], [14, 15]],
    ...        "predictions": [[0, 1, 0], [1, 1, 0], [1, 1, 1], [1, 1, 1]]}
    >>> decision_stop(rec, threshold=0.6, patience=2)
    {'iteration': 2, 'presses': 14, 'accuracy': 1.0, 'settled': True}
    """
    if not 0 < threshold <= 1:
        raise ValueError(f"threshold must be in (0, 1], got {threshold!r}.")
    if int(patience) != patience or patience < 1:
        raise ValueError(f"patience must be an integer >= 1, got {patience!r}.")
    preds = record.get("predictions")
    if not preds:
        raise ValueError("the record has no 'predictions' (a run of run_active_sampling is needed).")
    truth = record["key"]["test_class"]
    decisions, settled = [], False
    for t, p in enumerate(preds):
        p = np.asarray(p, dtype=int)
        counts = np.bincount(p)
        decisions.append(int(np.argmax(counts)))
        recent = decisions[-int(patience):]
        if counts.max() / p.size >= threshold and len(recent) == patience and len(set(recent)) == 1:
            settled = True
            break
    presses = len(record.get("initial_indices", [])) + sum(len(d) for d in record.get("drawn_indices", [])[:t])
    return {"iteration": t, "presses": int(presses),
            "accuracy": float(np.mean(np.asarray(preds[t]) == truth)), "settled": bool(settled)}


def _value(record, field, reduce):
    if reduce in ("stop_presses", "stop_accuracy"):
        if not record.get(field):
            return np.nan
        stop = decision_stop(record)
        return float(stop["presses"] if reduce == "stop_presses" else stop["accuracy"])
    v = record.get(field)
    if v is None or len(v) == 0 or any(x is None for x in v):
        return np.nan
    v = np.asarray(v, dtype=float)
    if reduce == "final":
        return float(v[-1])
    return float((v[:-1] + v[1:]).sum() / 2 / (len(v) - 1)) if len(v) > 1 else float(v[0])  # trapezoid rule


def _t_interval(d, level=0.95):
    from scipy import stats

    n = d.size
    mean = float(d.mean()) if n else float("nan")
    if n < 2:
        return mean, float("nan"), float("nan")
    half = float(stats.t.ppf(0.5 + level / 2, n - 1) * d.std(ddof=1) / np.sqrt(n))
    return mean, mean - half, mean + half


def _p_values(d):
    from scipy import stats

    if d.size < 2 or np.all(d == 0):
        return (1.0, 1.0) if d.size >= 2 else (float("nan"), float("nan"))
    p_t = float(stats.ttest_1samp(d, 0.0).pvalue) if np.std(d) > 0 else 0.0
    p_w = float(stats.wilcoxon(d).pvalue)
    return p_t, p_w


def paired_table(result, reference="random", metrics=None, level=0.95):
    """Per strategy and metric: mean with its interval, and the paired difference to ``reference``.

    Parameters
    ----------
    result : ExperimentResult
        From :func:`run_active_sampling`.
    reference : str, default="random"
        The strategy every other one is compared with.
    metrics : sequence of str or None, default=None
        Names from :data:`PAIRED_METRICS` (all whose field the records have, if None).
    level : float, default=0.95
        Confidence level of the t-intervals.

    Returns
    -------
    rows : list of dict
        ``strategy``, ``metric``, ``n`` (converged runs), ``mean``, ``ci_low``,
        ``ci_high`` (t-interval of the mean over runs), and for strategies other
        than the reference ``n_pairs`` (pairs where both runs converged),
        ``diff`` (mean of strategy minus reference), ``diff_low``, ``diff_high``
        (t-interval over pairs), ``p_ttest`` (paired t-test) and ``p_wilcoxon``
        (Wilcoxon signed-rank; 1.0 when every difference is 0).

    Examples
    --------
    >>> from sklearn_hardness.experiments import ExperimentResult, paired_table
    >>> recs = [{"key": {"strategy": s, "test_class": 0, "seed": k}, "converged": True,
    ...          "accuracy": [0.2, a], "mae": [0.1, 0.0]}
    ...         for k in range(4) for s, a in (("random", 0.4 + 0.1 * k), ("variance", 0.6 + 0.1 * k))]
    >>> row = [r for r in paired_table(ExperimentResult(recs)) if r["strategy"] == "variance"][0]
    >>> round(row["diff"], 3), row["n_pairs"], row["p_ttest"] < 0.05
    (0.2, 4, True)
    """
    records = [r for r in result.records if r["key"].get("strategy") is not None]
    if not records:
        raise ValueError("the result has no active-sampling runs.")
    known = {m[0]: m for m in PAIRED_METRICS}
    if metrics is None:
        metrics = [m for m in known if any(known[m][1] in r for r in records)]
    unknown = [m for m in metrics if m not in known]
    if unknown:
        raise ValueError(f"unknown metrics {unknown}; choose from {list(known)}.")
    strategies = list(dict.fromkeys(r["key"]["strategy"] for r in records))
    if reference not in strategies:
        raise ValueError(f"the reference strategy {reference!r} is not in the result ({strategies}).")
    by = {(r["key"]["strategy"], r["key"]["test_class"], r["key"]["seed"]): r
          for r in records if r.get("converged", True)}
    rows = []
    for s in strategies:
        for name in metrics:
            _, field, reduce, _ = known[name]
            own = {k[1:]: _value(r, field, reduce) for k, r in by.items() if k[0] == s}
            vals = np.array([v for v in own.values() if np.isfinite(v)])
            mean, lo, hi = _t_interval(vals, level)
            row = {"strategy": s, "metric": name, "n": int(vals.size), "mean": mean, "ci_low": lo,
                   "ci_high": hi}
            if s != reference:
                ref = {k[1:]: _value(r, field, reduce) for k, r in by.items() if k[0] == reference}
                d = np.array([own[p] - ref[p] for p in own if p in ref and np.isfinite(own[p] - ref[p])])
                diff, dlo, dhi = _t_interval(d, level)
                p_t, p_w = _p_values(d)
                row.update(n_pairs=int(d.size), diff=diff, diff_low=dlo, diff_high=dhi, p_ttest=p_t,
                           p_wilcoxon=p_w)
            rows.append(row)
    return rows


def _f(x, pct):
    if x is None or not np.isfinite(x):
        return "n/a"
    if pct is None:
        return f"{x:.1f}"
    return f"{100 * x:.1f}" if pct else f"{x:.3f}"


def format_paired_table(rows, reference="random"):
    """Plain-text table of :func:`paired_table` rows (accuracies in %)."""
    head = ["strategy", "metric", "n", "mean [95% CI]", f"- {reference} [95% CI]", "p (t)", "p (Wilcoxon)"]
    lines = []
    for r in rows:
        pct = "accuracy" in r["metric"] or r["metric"] == "auc"
        if r["metric"] == "presses_at_stop":
            pct = None  # a count: one decimal
        mean = f"{_f(r['mean'], pct)} [{_f(r['ci_low'], pct)}, {_f(r['ci_high'], pct)}]"
        if "diff" in r:
            diff = f"{'+' if r['diff'] >= 0 else ''}{_f(r['diff'], pct)} [{_f(r['diff_low'], pct)}, " \
                   f"{_f(r['diff_high'], pct)}]"
            pt = "n/a" if not np.isfinite(r["p_ttest"]) else f"{r['p_ttest']:.3g}"
            pw = "n/a" if not np.isfinite(r["p_wilcoxon"]) else f"{r['p_wilcoxon']:.3g}"
            n = f"{r['n']} ({r['n_pairs']} pairs)"
        else:
            diff, pt, pw, n = "(reference)", "", "", str(r["n"])
        lines.append([r["strategy"], r["metric"] + (" %" if pct else ""), n, mean, diff, pt, pw])
    widths = [max(len(str(x)) for x in col) for col in zip(head, *lines)]
    fmt = lambda row: "  ".join(str(x).ljust(w) for x, w in zip(row, widths)).rstrip()  # noqa: E731
    return "\n".join([fmt(head), fmt(["-" * w for w in widths])] + [fmt(r) for r in lines])
