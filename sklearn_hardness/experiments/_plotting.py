"""Figures like the paper's (matplotlib), from experiment results."""

from __future__ import annotations

import os
import textwrap

import numpy as np
from scipy.signal import savgol_filter

from ..utils._optional import import_optional
from ._tables import baseline_table

__all__ = [
    "plot_active_sampling",
    "plot_uncertainty",
    "plot_dropout_sweep",
    "plot_model_baselines",
    "save_figures",
]

_LABELS = {"accuracy": "accuracy", "mae": "hardness MAE", "entropy": "mean entropy",
           "variance": "mean variance", "bald": "mean BALD"}


def _axes(ax):
    plt = import_optional("matplotlib.pyplot", "plot", "the experiments' figures")

    if ax is None:
        fig, ax = plt.subplots(figsize=(4.5, 3.4), layout="constrained")
    return ax


def plot_active_sampling(result, metric="accuracy", ax=None, band="std"):
    """:meth:`ExperimentResult.plot_active_sampling` (documented there) of ``result``."""
    if metric not in _LABELS:
        raise ValueError(f"metric must be one of {list(_LABELS)}, got {metric!r}.")
    if band not in ("std", "sem", None):
        raise ValueError(f"band must be 'std', 'sem' or None, got {band!r}.")
    ax = _axes(ax)
    for strategy in result.groups("strategy"):
        curves = result.curves(metric, strategy=strategy)
        if curves.size == 0:
            continue
        scale = 100.0 if metric == "accuracy" else 1.0
        mean = np.nanmean(curves, axis=0) * scale
        it = np.arange(mean.size)
        (line,) = ax.plot(it, mean, marker="o", ms=3, label=f"{strategy} (n={len(curves)})")
        if band is not None and len(curves) > 1:
            spread = np.nanstd(curves, axis=0) * scale
            if band == "sem":
                spread = spread / np.sqrt(len(curves))
            lo, hi = mean - spread, mean + spread
            if metric == "accuracy":  # a band past 0% or 100% means nothing
                lo, hi = np.clip(lo, 0, 100), np.clip(hi, 0, 100)
            ax.fill_between(it, lo, hi, color=line.get_color(), alpha=0.15)
    ax.set_xlabel("active sampling iteration")
    if not ax.get_lines():
        ax.text(0.5, 0.5, "no converged runs", ha="center", va="center", transform=ax.transAxes)
    unit = (result.config or {}).get("hardness_unit") if metric == "mae" else None
    ax.set_ylabel(_LABELS[metric] + (" (%)" if metric == "accuracy" else f" ({unit})" if unit else ""))
    if ax.get_lines():
        ax.legend(fontsize="small")
    ax.grid(alpha=0.3)
    return ax


def plot_uncertainty(result, kind="entropy", ax=None):
    """:meth:`ExperimentResult.plot_uncertainty` (documented there) of ``result``."""
    return plot_active_sampling(result, metric=kind, ax=ax, band="std")


def _smooth(y, window):
    n = len(y)
    w = min(window, n if n % 2 else n - 1)
    if w < 3:
        return y
    return savgol_filter(y, w, polyorder=min(2, w - 1))


def plot_dropout_sweep(result, metric="accuracy", ax=None, smooth=5):
    """:meth:`ExperimentResult.plot_dropout_sweep` (documented there) of ``result``."""
    if metric not in ("accuracy", "mae"):
        raise ValueError(f"metric must be 'accuracy' or 'mae', got {metric!r}.")
    ax = _axes(ax)
    rates = sorted({r["key"]["dropout"] for r in result.records})
    scale = 100.0 if metric == "accuracy" else 1.0
    vals = [[r[metric] for r in result.records if r["key"]["dropout"] == d and r[metric] is not None]
            for d in rates]
    mean = np.array([np.mean(v) if v else np.nan for v in vals]) * scale
    std = np.array([np.std(v) if v else np.nan for v in vals]) * scale
    x = np.asarray(rates)
    m_s = _smooth(mean, smooth) if smooth else mean
    s_s = _smooth(std, smooth) if smooth else std
    (line,) = ax.plot(x, m_s, label="mean" + (" (Savitzky-Golay)" if smooth else ""))
    ax.plot(x, mean, "o", ms=3, color=line.get_color())
    ax.fill_between(x, m_s - s_s, m_s + s_s, color=line.get_color(), alpha=0.15, label="std")
    ax.set_xlabel("dropout rate")
    ax.set_ylabel(_LABELS[metric] + (" (%)" if metric == "accuracy" else ""))
    ax.legend(fontsize="small")
    ax.grid(alpha=0.3)
    return ax


def plot_model_baselines(result, ax=None):
    """:meth:`ExperimentResult.plot_model_baselines` (documented there) of ``result``."""

    ax = _axes(ax)
    rows = baseline_table(result)
    x = np.arange(len(rows))
    w = 0.38
    ax.bar(x - w / 2, [100 * r["train_accuracy_mean"] for r in rows], w,
           yerr=[100 * r["train_accuracy_std"] for r in rows], capsize=3, label="train")
    ax.bar(x + w / 2, [100 * r["accuracy_mean"] for r in rows], w,
           yerr=[100 * r["accuracy_std"] for r in rows], capsize=3, label="validation")
    ax.set_xticks(x, [textwrap.fill(str(r["name"]), 14) for r in rows], fontsize="small")
    ax.set_ylabel("accuracy (%)")
    ax.set_ylim(0, 105)
    ax.legend(fontsize="small")
    ax.grid(alpha=0.3, axis="y")
    return ax


def save_figures(result, out_dir, prefix=""):
    """:meth:`ExperimentResult.save_figures` (documented there) of ``result``."""
    Figure = import_optional("matplotlib.figure", "plot", "save_figures").Figure  # no pyplot: no display needed

    os.makedirs(out_dir, exist_ok=True)
    experiments = {r["key"].get("experiment") for r in result.records}
    paths = []

    def save(fn, name, **kw):
        fig = Figure(figsize=(4.5, 3.4), layout="constrained")
        fn(result, ax=fig.add_subplot(), **kw)
        path = os.path.join(out_dir, prefix + name)
        fig.savefig(path, dpi=120)
        paths.append(path)

    if "active_sampling" in experiments:
        for metric in ("accuracy", "mae"):
            if metric == "mae" and all(v is None for r in result.records for v in r["mae"]):
                continue
            save(plot_active_sampling, f"{metric}.png", metric=metric)
        for kind in ("entropy", "variance"):
            save(plot_uncertainty, f"{kind}.png", kind=kind)
    if "model_baselines" in experiments:
        save(plot_model_baselines, "baselines.png")
    if "dropout_sweep" in experiments:
        for metric in ("accuracy", "mae"):
            save(plot_dropout_sweep, f"dropout_{metric}.png", metric=metric)
    return paths
