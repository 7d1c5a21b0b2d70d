"""Paired comparison of active-sampling strategies: 95% intervals and p-values against a reference.

Runs of different strategies with the same (test object, seed) start from the
same initial model and test presses, so a strategy is judged by its
per-pair difference to the reference strategy (``random`` by default): the
mean difference with a t-interval over the pairs, a paired t-test and a
Wilcoxon signed-rank test (:mod:`scipy.stats`).
"""

from __future__ import annotations

import numpy as np
from scipy import stats

from ..utils._intervals import _interval, format_interval
from ._tables import render_columns

__all__ = ["paired_table", "format_paired_table", "PAIRED_METRICS", "decision_stop", "presses_to_reach",
           "format_presses_to_reach"]

#: Metrics of :meth:`ExperimentResult.paired_table`: (name, record field, reduction, higher is better),
#: in the order a robot user reads them: first the reference presses used and the
#: test accuracy when :func:`decision_stop` (its defaults) ends the run
#: (``presses_at_stop``, ``accuracy_at_stop``), then the accuracy on the test
#: object's presses and on held-out presses of other objects after the press budget,
#: then ``auc`` (the mean of the accuracy over iterations 0..N, trapezoid rule,
#: normalised to [0, 1]: a strategy that gets there sooner scores higher) and the MAEs.
PAIRED_METRICS = (
    ("presses_at_stop", "predictions", "stop_presses", False),
    ("accuracy_at_stop", "predictions", "stop_accuracy", True),
    ("accuracy", "accuracy", "final", True),
    ("holdout_accuracy", "holdout_accuracy", "final", True),
    ("auc", "accuracy", "auc", True),
    ("mae", "mae", "final", False),
    ("holdout_mae", "holdout_mae", "final", False),
)


def _pair_id(record):
    """The (test class, test object, seed) a run belongs to; its paired runs share it.

    ``test_object`` is None for runs whose test object is a class (one object per class).
    """
    key = record["key"]
    return key["test_class"], key.get("test_object"), key["seed"]


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
    >>> from sklearn_hardness.experiments._stats import decision_stop
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


def _bounds(name, records):
    """The range of metric ``name`` and of a difference of it: accuracies within [0, 1], presses within the budget."""
    if name == "presses_at_stop":
        budget = max((len(r.get("initial_indices", [])) + sum(len(d) for d in r.get("drawn_indices", []))
                      for r in records), default=np.inf)
        return (0.0, float(budget)), (-float(budget), float(budget))
    if name.startswith("mae") or name.endswith("mae"):
        return (0.0, np.inf), (-np.inf, np.inf)
    return (0.0, 1.0), (-1.0, 1.0)


def _t_interval(d, level, bounds):
    """Mean and t-interval of independent values, clipped to ``bounds`` (the package's one interval)."""
    mean, (lo, hi) = _interval(d, 0.0, np.inf, bounds=bounds, level=level)
    return mean, lo, hi


def _p_values(d):
    if d.size < 2 or np.all(d == 0):
        return (1.0, 1.0) if d.size >= 2 else (float("nan"), float("nan"))
    p_t = float(stats.ttest_1samp(d, 0.0).pvalue) if np.std(d) > 0 else 0.0
    p_w = float(stats.wilcoxon(d).pvalue)
    return p_t, p_w


def paired_table(result, reference="random", metrics=None, level=0.95):
    """:meth:`ExperimentResult.paired_table` (documented there) of ``result``."""
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
    by = {(r["key"]["strategy"],) + _pair_id(r): r
          for r in records if r.get("converged", True)}
    rows = []
    for s in strategies:
        for name in metrics:
            _, field, reduce, _ = known[name]
            bounds, diff_bounds = _bounds(name, records)
            own = {k[1:]: _value(r, field, reduce) for k, r in by.items() if k[0] == s}
            vals = np.array([v for v in own.values() if np.isfinite(v)])
            mean, lo, hi = _t_interval(vals, level, bounds)
            row = {"strategy": s, "metric": name, "n": int(vals.size), "mean": mean, "ci_low": lo,
                   "ci_high": hi}
            if s != reference:
                ref = {k[1:]: _value(r, field, reduce) for k, r in by.items() if k[0] == reference}
                d = np.array([own[p] - ref[p] for p in own if p in ref and np.isfinite(own[p] - ref[p])])
                diff, dlo, dhi = _t_interval(d, level, diff_bounds)
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
    """:meth:`ExperimentResult.format_paired_table` (documented there) of ``result``."""
    head = ["strategy", "metric", "n", "mean [95% CI]", f"- {reference} [95% CI]", "p (t)", "p (Wilcoxon)"]
    lines = []
    for r in rows:
        pct = "accuracy" in r["metric"] or r["metric"] == "auc"
        if r["metric"] == "presses_at_stop":
            pct = None  # a count: one decimal
        def bound(x, pct=pct):
            return _f(x, pct)

        # with fewer than MIN_VALUES_FOR_INTERVAL runs or pairs, words instead of a t-interval that says little
        mean = f"{_f(r['mean'], pct)} {format_interval(r['ci_low'], r['ci_high'], r['n'], what='runs', fmt=bound)}"
        if "diff" in r:
            diff = f"{'+' if r['diff'] >= 0 else ''}{_f(r['diff'], pct)} " \
                   f"{format_interval(r['diff_low'], r['diff_high'], r['n_pairs'], fmt=bound)}"
            pt = "n/a" if not np.isfinite(r["p_ttest"]) else f"{r['p_ttest']:.3g}"
            pw = "n/a" if not np.isfinite(r["p_wilcoxon"]) else f"{r['p_wilcoxon']:.3g}"
            n = f"{r['n']} ({r['n_pairs']} pairs)"
        else:
            diff, pt, pw, n = "(reference)", "", "", str(r["n"])
        lines.append([r["strategy"], r["metric"] + (" %" if pct else ""), n, mean, diff, pt, pw])
    return render_columns(head, lines)


def _curves(records, field="accuracy"):
    """Per-iteration values (n_runs, N + 1) and the reference presses after each iteration."""
    curves = np.array([np.asarray(r[field], dtype=float) for r in records])
    first = records[0]
    n0 = len(first.get("initial_indices", []))
    drawn = [len(d) for d in first.get("drawn_indices", [])]
    presses = n0 + np.concatenate([[0], np.cumsum(drawn)])[: curves.shape[1]]
    return curves, presses


def presses_to_reach(result, reference="random", *, n_boot=2000, level=0.95, random_state=0):
    """:meth:`ExperimentResult.presses_to_reach` (documented there) of ``result``."""
    if not 0 < level < 1:
        raise ValueError(f"level must be in (0, 1), got {level!r}.")
    if int(n_boot) != n_boot or n_boot < 1:
        raise ValueError(f"n_boot must be a positive integer, got {n_boot!r}.")
    records = [r for r in result.records if r["key"].get("strategy") is not None and r.get("accuracy")]
    if not records:
        raise ValueError("the result has no active-sampling runs with an accuracy per iteration.")
    strategies = list(dict.fromkeys(r["key"]["strategy"] for r in records))
    if reference not in strategies:
        raise ValueError(f"the reference strategy {reference!r} is not in the result ({strategies}).")
    by = {(r["key"]["strategy"],) + _pair_id(r): r
          for r in records if r.get("converged", True)}
    length = max(len(r["accuracy"]) for r in by.values()) if by else 0
    rng = np.random.default_rng(random_state)
    lo_q, hi_q = 100 * (1 - level) / 2, 100 * (1 + level) / 2

    def first_reach(curves, target, presses):
        ok = curves >= target[:, None] - 1e-9  # (n_boot or 1, N + 1)
        hit = ok.any(axis=1)
        return np.where(hit, presses[np.argmax(ok, axis=1)], np.inf)

    def interval(values):  # press counts are discrete, and inf (never) must stay inf: no interpolation
        return tuple(float(np.percentile(values, q, method="inverted_cdf")) for q in (lo_q, hi_q))

    rows = []
    for s in strategies:
        pairs = sorted(p[1:] for p in by if p[0] == s and (reference,) + p[1:] in by
                       and len(by[p]["accuracy"]) == length and len(by[(reference,) + p[1:]]["accuracy"]) == length)
        row = {"strategy": s, "n_pairs": len(pairs)}
        if not pairs:
            rows.append(dict(row, target=np.nan, curve=[], presses=[], presses_to_reach=np.nan,
                             ci_low=np.nan, ci_high=np.nan, p_reached=np.nan))
            continue
        own, presses = _curves([by[(s,) + p] for p in pairs])
        ref, _ = _curves([by[(reference,) + p] for p in pairs])
        target = ref[:, -1].mean()
        point = first_reach(own.mean(axis=0)[None], np.array([target]), presses)[0]
        idx = rng.integers(0, len(pairs), size=(int(n_boot), len(pairs)))
        boot_target = ref[idx, -1].mean(axis=1)
        boot = first_reach(own[idx].mean(axis=1), boot_target, presses)
        lo, hi = interval(boot)
        row.update(target=float(target), curve=own.mean(axis=0).tolist(), presses=presses.tolist(),
                   presses_to_reach=float(point),
                   ci_low=lo, ci_high=hi, p_reached=float(np.mean(np.isfinite(boot))))
        if s != reference:
            ref_boot = first_reach(ref[idx].mean(axis=1), boot_target, presses)  # finite: the final reaches
            ref_point = first_reach(ref.mean(axis=0)[None], np.array([target]), presses)[0]
            d = boot - ref_boot  # inf where the strategy did not reach the target
            dlo, dhi = interval(d)
            row.update(diff=float(point - ref_point), diff_low=dlo, diff_high=dhi)
        rows.append(row)
    return rows


def format_presses_to_reach(rows, reference="random"):
    """:meth:`ExperimentResult.format_presses_to_reach` (documented there) of ``result``."""
    def num(x):
        return "n/a" if x is None or np.isnan(x) else ("never" if np.isinf(x) else f"{x:g}")

    head = ["strategy", "pairs", f"{reference}'s final accuracy", "presses to reach it [95% CI]",
            "reached in", f"- {reference} [95% CI]"]
    lines = []
    for r in rows:
        reach = f"{num(r['presses_to_reach'])} [{num(r['ci_low'])}, {num(r['ci_high'])}]"
        target = "n/a" if np.isnan(r["target"]) else f"{100 * r['target']:.1f}%"
        if "diff" in r:
            sign = "+" if 0 < r["diff"] < np.inf else ""
            diff = f"{sign}{num(r['diff'])} [{num(r['diff_low'])}, {num(r['diff_high'])}]"
        else:
            diff = "(reference)" if r["strategy"] == reference else ""
        p = "n/a" if np.isnan(r["p_reached"]) else f"{100 * r['p_reached']:.0f}%"
        lines.append([r["strategy"], str(r["n_pairs"]), target, reach, p, diff])
    return render_columns(head, lines)
