"""The paper's comparison table (Table I) from experiment results."""

from __future__ import annotations

import numpy as np

__all__ = ["comparison_table", "format_table", "baseline_table", "HUMAN_ACCURACY"]

#: The paper's human study (Sec. III-G): 10 participants, 5 rounds each, on the
#: robot-data objects. A constant reference, not measured by this library.
HUMAN_ACCURACY = (0.48, 0.2227)

_ORDER = ("variance", "entropy", "random", "bald")


def _mean_std(values):
    v = np.asarray([x for x in values if x is not None], dtype=float)
    v = v[np.isfinite(v)]
    if v.size == 0:
        return float("nan"), float("nan")
    return float(v.mean()), float(v.std())


def comparison_table(result, iteration=-1, human=True):
    """:meth:`ExperimentResult.comparison_table` (documented there) of ``result``."""
    rows = []
    records = [r for r in result.records if r["key"].get("experiment") == "active_sampling"]
    if not records:
        raise ValueError("the result has no active-sampling runs.")
    seen = {}
    for r in records:
        seen.setdefault((r["key"]["test_class"], r["key"].get("test_object"), r["key"]["seed"]), r)
    base = list(seen.values())
    conv = [r for r in base if r.get("converged", True)]
    acc, acc_sd = _mean_std(r["accuracy"][0] for r in conv)
    mae, mae_sd = _mean_std(r["mae"][0] for r in conv)
    rows.append({"name": "no resampling", "accuracy_mean": acc, "accuracy_std": acc_sd, "mae_mean": mae,
                 "mae_std": mae_sd, "n_runs": len(conv), "n_total": len(base),
                 "converged_fraction": len(conv) / len(base)})
    names = [s for s in _ORDER if s in {r["key"]["strategy"] for r in records}]
    names += [s for s in dict.fromkeys(r["key"]["strategy"] for r in records) if s not in names]
    for s in names:
        runs = [r for r in records if r["key"]["strategy"] == s]
        conv = [r for r in runs if r.get("converged", True)]
        acc, acc_sd = _mean_std(r["accuracy"][iteration] for r in conv)
        mae, mae_sd = _mean_std(r["mae"][iteration] for r in conv)
        rows.append({"name": s, "accuracy_mean": acc, "accuracy_std": acc_sd, "mae_mean": mae,
                     "mae_std": mae_sd, "n_runs": len(conv), "n_total": len(runs),
                     "converged_fraction": len(conv) / len(runs)})
    if human:
        rows.append({"name": "humans (paper)", "accuracy_mean": HUMAN_ACCURACY[0],
                     "accuracy_std": HUMAN_ACCURACY[1], "mae_mean": float("nan"), "mae_std": float("nan"),
                     "n_runs": None, "n_total": None, "converged_fraction": None})
    return rows


def baseline_table(result):
    """:meth:`ExperimentResult.baseline_table` (documented there) of ``result``."""
    key = "model" if any(r["key"].get("experiment") == "model_baselines" for r in result.records) else "dropout"
    groups = {}
    for r in result.records:
        groups.setdefault(r["key"][key], []).append(r)
    rows = []
    for name, runs in groups.items():
        acc, acc_sd = _mean_std(r["accuracy"] for r in runs)
        tr, tr_sd = _mean_std(r["train_accuracy"] for r in runs)
        mae, mae_sd = _mean_std(r["mae"] for r in runs)
        rows.append({"name": str(name), "train_accuracy_mean": tr, "train_accuracy_std": tr_sd,
                     "accuracy_mean": acc, "accuracy_std": acc_sd, "mae_mean": mae, "mae_std": mae_sd,
                     "n_runs": len(runs),
                     "converged_fraction": float(np.mean([r.get("converged", True) for r in runs]))})
    return rows


def _pct(m, s):
    return "n/a" if not np.isfinite(m) else f"{100 * m:6.2f}% +- {100 * s:5.2f}%"


def _num(m, s):
    return "n/a" if not np.isfinite(m) else f"{m:.3f} +- {s:.3f}"


def format_table(rows, mae_unit=None):
    """:meth:`ExperimentResult.format_table` (documented there) of ``result``."""
    mae_head = "MAE" + (f" ({mae_unit})" if mae_unit else "")
    has_train = any("train_accuracy_mean" in r for r in rows)
    head = ["", "accuracy"] + (["train accuracy"] if has_train else []) + [mae_head, "runs", "converged"]
    lines = []
    for r in rows:
        conv = r.get("converged_fraction")
        runs = "" if r.get("n_runs") is None else (
            f"{r['n_runs']}/{r['n_total']}" if r.get("n_total") is not None else str(r["n_runs"]))
        row = [r["name"], _pct(r["accuracy_mean"], r["accuracy_std"])]
        if has_train:
            row.append(_pct(r.get("train_accuracy_mean", np.nan), r.get("train_accuracy_std", np.nan)))
        row += [_num(r["mae_mean"], r["mae_std"]), runs, "" if conv is None else f"{100 * conv:.0f}%"]
        lines.append(row)
    return render_columns(head, lines)


def render_columns(head, lines):
    """Plain-text columns padded to their widest cell, a dashed rule under the header."""
    widths = [max(len(str(x)) for x in col) for col in zip(head, *lines)]
    fmt = lambda row: "  ".join(str(x).ljust(w) for x, w in zip(row, widths)).rstrip()  # noqa: E731
    return "\n".join([fmt(head), fmt(["-" * w for w in widths])] + [fmt(r) for r in lines])
