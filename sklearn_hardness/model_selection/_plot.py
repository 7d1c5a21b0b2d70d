"""The figure of an object-disjoint evaluation: its confusion matrices, as a scikit-learn Display."""

from __future__ import annotations

import numpy as np
from sklearn.metrics import ConfusionMatrixDisplay

__all__ = ["ConfusionMatricesDisplay"]


class ConfusionMatricesDisplay:
    """Row-normalised confusion matrices of an evaluation, one panel per pipeline.

    Build it with :meth:`from_result`; like scikit-learn's displays, it
    stores what it draws and :meth:`plot` draws it.

    Parameters
    ----------
    confusion : dict of str to ndarray of shape (n_classes, n_classes)
        Counts per pipeline (true class per row).
    display_labels : array-like of shape (n_classes,)
        Class names.
    scores : dict of str to float or None, default=None
        Balanced accuracy per pipeline, for the panels' titles.

    Attributes
    ----------
    figure_ : matplotlib.figure.Figure
        The figure drawn on (after :meth:`plot`).
    axes_ : ndarray of matplotlib.axes.Axes
        One per pipeline.
    displays_ : dict of str to sklearn.metrics.ConfusionMatrixDisplay
        Each panel's display.

    Examples
    --------
    >>> import numpy as np
    >>> from sklearn_hardness.model_selection import ConfusionMatricesDisplay
    >>> display = ConfusionMatricesDisplay({"a": np.eye(3, dtype=int)}, ["soft", "moderate", "hard"]).plot()
    >>> display.axes_.shape
    (1,)
    """

    def __init__(self, confusion, display_labels, scores=None):
        self.confusion = confusion
        self.display_labels = display_labels
        self.scores = scores

    def plot(self, ax=None, *, values_format=".2f"):
        """Draw the matrices, each row divided by its presses.

        Parameters
        ----------
        ax : array-like of matplotlib Axes or None, default=None
            One axes per pipeline; None: a new figure with one row of them.
        values_format : str, default=".2f"
            Format of the numbers in the cells.

        Returns
        -------
        display : ConfusionMatricesDisplay
            ``self``, with ``figure_``, ``axes_`` and ``displays_``.
        """
        import matplotlib.pyplot as plt

        names = list(self.confusion)
        if ax is None:
            fig, axes = plt.subplots(1, len(names), figsize=(3.6 * len(names), 3.4), squeeze=False)
            axes = axes[0]
        else:
            axes = np.ravel(np.asarray(ax, dtype=object))
            if len(axes) != len(names):
                raise ValueError(f"ax has {len(axes)} axes for {len(names)} pipelines; give one per pipeline.")
            fig = axes[0].figure
        self.displays_ = {}
        for a, name in zip(axes, names):
            cm = np.asarray(self.confusion[name], dtype=float)
            cm = cm / np.maximum(cm.sum(axis=1, keepdims=True), 1)
            self.displays_[name] = ConfusionMatrixDisplay(cm, display_labels=self.display_labels).plot(
                ax=a, colorbar=False, values_format=values_format)
            score = None if self.scores is None else self.scores.get(name)
            a.set_title(name if score is None else f"{name}\nbal. acc. {score:.2f}")
        if ax is None:
            fig.tight_layout()
        self.figure_, self.axes_ = fig, np.asarray(axes, dtype=object)
        return self

    @classmethod
    def from_result(cls, result, *, ax=None, values_format=".2f"):
        """Draw the confusion matrices of :func:`~sklearn_hardness.model_selection.evaluate_pipelines`.

        Parameters
        ----------
        result : EvaluationResult
            What :func:`~sklearn_hardness.model_selection.evaluate_pipelines`
            returned.
        ax : array-like of matplotlib Axes or None, default=None
            One axes per pipeline; None: a new figure.
        values_format : str, default=".2f"
            Format of the numbers in the cells.

        Returns
        -------
        display : ConfusionMatricesDisplay
            Its ``figure_`` is the figure (``display.figure_.savefig(path)``).
        """
        scores = {row["pipeline"]: row["balanced_accuracy"] for row in result.table}
        return cls(result.confusion, result.target_names, scores).plot(ax=ax, values_format=values_format)
