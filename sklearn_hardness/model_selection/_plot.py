"""The figure of an object-disjoint evaluation: its confusion matrices."""

from __future__ import annotations

from pathlib import Path

import numpy as np
from sklearn.metrics import ConfusionMatrixDisplay

__all__ = ["plot_confusion_matrices"]


def plot_confusion_matrices(result, path=None):
    """Row-normalised confusion matrices of :func:`evaluate_pipelines`, one panel per pipeline.

    Parameters
    ----------
    result : Bunch
        What :func:`evaluate_pipelines` returned.
    path : str, path-like or None, default=None
        Also save the figure there (PNG).

    Returns
    -------
    fig : matplotlib.figure.Figure
    """
    import matplotlib

    if path is not None:
        matplotlib.use("Agg", force=False)
    import matplotlib.pyplot as plt

    names = list(result.confusion)
    fig, axes = plt.subplots(1, len(names), figsize=(3.6 * len(names), 3.4), squeeze=False)
    for ax, (name, row) in zip(axes[0], zip(names, result.table)):
        cm = result.confusion[name].astype(float)
        cm = cm / np.maximum(cm.sum(axis=1, keepdims=True), 1)
        ConfusionMatrixDisplay(cm, display_labels=result.target_names).plot(
            ax=ax, colorbar=False, values_format=".2f")
        ax.set_title(f"{name}\nbal. acc. {row['balanced_accuracy']:.2f}")
    fig.tight_layout()
    if path is not None:
        Path(path).parent.mkdir(parents=True, exist_ok=True)
        fig.savefig(path, dpi=100)
    return fig
