"""The figure of an object-disjoint evaluation: its confusion matrices, as a scikit-learn Display."""

from __future__ import annotations

import numpy as np

from ..utils._optional import import_optional

__all__ = ["ConfusionMatricesDisplay"]


class ConfusionMatricesDisplay:
    """Confusion matrices of an evaluation, one panel per pipeline, as scikit-learn's displays draw them.

    Build it with :meth:`from_result` (``normalize`` chooses how the
    matrices are made), or from matrices; like
    :class:`sklearn.metrics.ConfusionMatrixDisplay`, it stores what it
    draws and :meth:`plot` draws it, each panel by scikit-learn's display.
    Needs matplotlib (``pip install "sklearn-hardness[plot]"``).

    Parameters
    ----------
    confusion_matrices : dict of str to ndarray of shape (n_classes, n_classes)
        The matrix of each pipeline (true class per row), drawn as given.
    display_labels : array-like of shape (n_classes,) or None, default=None
        Class names; None: ``0 .. n_classes - 1``.
    scores : dict of str to float or None, default=None
        A score per pipeline, for the panels' titles.
    score_name : str, default="bal. acc."
        What ``scores`` are, in the titles.

    Attributes
    ----------
    figure_ : matplotlib.figure.Figure
        The figure drawn on (after :meth:`plot`).
    axes_ : ndarray of matplotlib.axes.Axes
        One per pipeline.
    displays_ : dict of str to sklearn.metrics.ConfusionMatrixDisplay
        Each panel's display (its ``im_``, ``text_``).

    See Also
    --------
    sklearn.metrics.ConfusionMatrixDisplay : One matrix.

    Examples
    --------
    >>> import numpy as np
    >>> from sklearn_hardness.model_selection import ConfusionMatricesDisplay
    >>> display = ConfusionMatricesDisplay({"a": np.eye(3, dtype=int)},
    ...                                    display_labels=["soft", "moderate", "hard"]).plot(cmap="Greys")
    >>> display.axes_.shape, display.displays_["a"].im_.get_cmap().name
    ((1,), 'Greys')
    """

    def __init__(self, confusion_matrices, *, display_labels=None, scores=None, score_name="bal. acc."):
        self.confusion_matrices = confusion_matrices
        self.display_labels = display_labels
        self.scores = scores
        self.score_name = score_name

    def plot(self, *, include_values=True, cmap="viridis", xticks_rotation="horizontal", values_format=None,
             ax=None, colorbar=False, im_kw=None, text_kw=None):
        """Draw the matrices, one panel per pipeline.

        Parameters
        ----------
        include_values : bool, default=True
            Write each cell's value.
        cmap : str or matplotlib Colormap, default="viridis"
        xticks_rotation : {"vertical", "horizontal"} or float, default="horizontal"
        values_format : str or None, default=None
            Format of the cells' values; None: ``".2f"`` for normalised
            (float) matrices, ``"d"`` for counts.
        ax : array-like of matplotlib Axes or None, default=None
            One axes per pipeline; None: a new figure with one row of them.
        colorbar : bool, default=False
            A colorbar beside each panel (scikit-learn's display draws one by
            default; the panels here share a scale when normalised).
        im_kw : dict or None, default=None
            Passed to :func:`matplotlib.pyplot.imshow`.
        text_kw : dict or None, default=None
            Passed to :func:`matplotlib.pyplot.text`.

        Returns
        -------
        display : ConfusionMatricesDisplay
            ``self``, with ``figure_``, ``axes_`` and ``displays_``.
        """
        plt = import_optional("matplotlib.pyplot", "plot", f"{type(self).__name__}.plot")
        from sklearn.metrics import ConfusionMatrixDisplay

        names = list(self.confusion_matrices)
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
            cm = np.asarray(self.confusion_matrices[name])
            fmt = values_format or (".2f" if np.issubdtype(cm.dtype, np.floating) else "d")
            self.displays_[name] = ConfusionMatrixDisplay(cm, display_labels=self.display_labels).plot(
                include_values=include_values, cmap=cmap, xticks_rotation=xticks_rotation, values_format=fmt,
                ax=a, colorbar=colorbar, im_kw=im_kw, text_kw=text_kw)
            score = None if self.scores is None else self.scores.get(name)
            a.set_title(name if score is None else f"{name}\n{self.score_name} {score:.2f}")
        if ax is None:
            fig.tight_layout()
        self.figure_, self.axes_ = fig, np.asarray(axes, dtype=object)
        return self

    @classmethod
    def from_result(cls, result, *, normalize="true", display_labels=None, include_values=True, cmap="viridis",
                    xticks_rotation="horizontal", values_format=None, ax=None, colorbar=False, im_kw=None,
                    text_kw=None):
        """Draw the confusion matrices of :func:`~sklearn_hardness.model_selection.evaluate_pipelines`.

        Parameters
        ----------
        result : EvaluationResult
            What :func:`~sklearn_hardness.model_selection.evaluate_pipelines`
            returned.
        normalize : {"true", "pred", "all"} or None, default="true"
            How the matrices are made from the out-of-fold predictions, as
            :func:`sklearn.metrics.confusion_matrix` normalises: over the
            true classes (each row sums to 1: the recall of each class on
            its diagonal), the predicted ones, all presses, or counts.
        display_labels : array-like of shape (n_classes,) or None, default=None
            None: the result's ``target_names``.
        include_values, cmap, xticks_rotation, values_format, ax, colorbar, im_kw, text_kw
            As :meth:`plot` takes them.

        Returns
        -------
        display : ConfusionMatricesDisplay
            Its ``figure_`` is the figure (``display.figure_.savefig(path)``).
        """
        from ._report import primary_score

        if normalize not in ("true", "pred", "all", None):
            raise ValueError(f"normalize must be 'true', 'pred', 'all' or None, got {normalize!r}.")
        summary, score = result.summary, primary_score(result)
        scores = dict(zip(summary["pipeline"], summary[score]))
        matrices = {name: result.confusion_matrix(name, normalize=normalize) for name in result.pipelines}
        labels = result.target_names if display_labels is None else display_labels
        display = cls(matrices, display_labels=labels, scores=scores,
                      score_name="bal. acc." if score == "balanced_accuracy" else score)
        return display.plot(include_values=include_values, cmap=cmap, xticks_rotation=xticks_rotation,
                            values_format=values_format, ax=ax, colorbar=colorbar, im_kw=im_kw, text_kw=text_kw)
