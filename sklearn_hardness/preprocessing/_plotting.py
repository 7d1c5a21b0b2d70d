"""Plotting what ContactFrameSelector selected."""

from __future__ import annotations

import numpy as np

from ..utils._optional import import_optional

__all__ = ["plot_contact_selection"]


def plot_contact_selection(selection, *, labels=None, timestamps=None, ax=None, max_videos=20):
    """Plot contact curves with the selected frames marked.

    Parameters
    ----------
    selection : :class:`~sklearn.utils.Bunch` or ContactFrameSelector
        The result of :meth:`ContactFrameSelector.select`, or a fitted
        selector (its ``selection_`` is used).
    labels : sequence of str or None, default=None
        One label per video; curves of the same label share a colour.
    timestamps : sequence of array-like or None, default=None
        Per-frame times (s) per video for the x axis; frame index otherwise.
    ax : matplotlib Axes or None, default=None
        Where to draw; a new figure is made if None.
    max_videos : int, default=20
        Plot at most this many videos (the first ones).

    Returns
    -------
    fig : matplotlib Figure

    Examples
    --------
    Needs matplotlib (``pip install "sklearn-hardness[plot]"``)::

        from sklearn_hardness.datasets import make_presses
        from sklearn_hardness.preprocessing import ContactFrameSelector, plot_contact_selection

        data = make_presses("everyday", n_per_class=2, n_objects=3, random_state=0)
        selector = ContactFrameSelector().fit(data.videos)
        plot_contact_selection(selector, labels=data.target_names[data.target]).savefig("curves.png")
    """
    plt = import_optional("matplotlib.pyplot", "plot", "plot_contact_selection")

    if hasattr(selection, "selection_"):
        selection = selection.selection_
    if ax is None:
        fig, ax = plt.subplots(figsize=(7, 4))
    else:
        fig = ax.figure
    n = min(len(selection.curves), max_videos)
    uniq = list(dict.fromkeys(labels[:n])) if labels is not None else []
    cmap = plt.get_cmap("viridis", max(len(uniq), 1))
    seen = set()
    for i in range(n):
        curve = selection.curves[i]
        x = np.asarray(timestamps[i]) if timestamps is not None else np.arange(len(curve))
        color = cmap(uniq.index(labels[i])) if labels is not None else f"C{i % 10}"
        label = None
        if labels is not None and labels[i] not in seen:
            label = str(labels[i])
            seen.add(labels[i])
        ax.plot(x, curve, color=color, lw=1, alpha=0.8, label=label)
        idx = selection.indices[i]
        marker = "o" if selection.contact_found[i] else "x"
        ax.plot(x[idx], curve[idx], marker, color=color, ms=5)
    ax.set_xlabel("time (s)" if timestamps is not None else "frame")
    ax.set_ylabel("mean |change| to first frame (0-255)")
    ax.set_title("Contact curves; markers: selected frames (x: no contact found)")
    if labels is not None:
        ax.legend(title="class", fontsize="small")
    return fig
