"""The one-number baseline: the peak change of a press video to its first frame.

What a first look at a press gives, and what every pipeline is measured
against (:func:`~sklearn_hardness.model_selection.evaluate_pipelines` runs it
beside them): :func:`peak_contact_change` turns a video into one number,
:func:`make_peak_change_baseline` classifies with it.
"""

from __future__ import annotations

import numpy as np
from sklearn.linear_model import LogisticRegression
from sklearn.pipeline import make_pipeline
from sklearn.preprocessing import FunctionTransformer, StandardScaler

from ..preprocessing import contact_curve
from ..utils._press_cache import press_rows
from ..utils._validation import check_roi

__all__ = ["make_peak_change_baseline", "peak_contact_change"]


def _peak_row(video, roi=None, name="video"):
    """The one number of one press, as a row (``name`` is unused: the contact curve names no video)."""
    return np.array([np.log(0.1 + float(np.max(contact_curve(video, roi=roi))))])


def peak_contact_change(videos, roi=None, memory=None):
    """Log of the peak mean absolute change to the first frame, one per video.

    The one number a first look at a press gives: the maximum of
    :func:`~sklearn_hardness.preprocessing.contact_curve`.

    Parameters
    ----------
    videos : sequence of array-like of shape (T, H, W, 3)
        Press videos (a list or a lazy sequence).
    roi : tuple (top, bottom, left, right) or None, default=None
        Only this region of each frame (fractions of its height and width),
        e.g. the gel where the frame also shows the sensor housing.
    memory : None, str, path-like or joblib.Memory, default=None
        Cache each press's number here, keyed by ``roi`` and the press (a
        video of a lazy sequence by its loader and key, without decoding it;
        a video in memory by a hash of its frames), so that a later call on
        the same press reads it. The
        :class:`~sklearn.preprocessing.FunctionTransformer` of
        :func:`make_peak_change_baseline` passes it through ``kw_args``
        (what :func:`~sklearn_hardness.models.make_named_pipeline` does
        with its ``memory``).

    Returns
    -------
    feature : ndarray of shape (n_videos, 1)
        ``log(0.1 + max_t curve(t))`` (the log evens out the spread of
        strong contacts; 0.1 keeps one-frame videos finite).

    Examples
    --------
    >>> import numpy as np
    >>> from sklearn_hardness.models import peak_contact_change
    >>> video = np.full((4, 16, 16, 3), 100, np.uint8)
    >>> video[3, :4, :4] = 116
    >>> peak_contact_change([video]).round(3).tolist()
    [[0.095]]
    """
    roi = check_roi(roi)
    if memory is None:
        return np.array([_peak_row(v, roi) for v in videos])
    return press_rows(_peak_row, videos, {"roi": roi}, memory=memory)


def make_peak_change_baseline(class_weight="balanced", roi=None):
    """The one-number baseline: peak change to the first frame + logistic regression.

    Parameters
    ----------
    class_weight : "balanced", dict or None, default="balanced"
        Passed to :class:`~sklearn.linear_model.LogisticRegression`;
        ``"balanced"`` keeps imbalanced ranks from collapsing onto the
        majority class.
    roi : tuple (top, bottom, left, right) or None, default=None
        Measure the change on this region of the frames only (fractions of
        height and width; see :func:`peak_contact_change`). Where the frame
        shows more than the gel (a GelSight Wedge grasp shows the housing
        and the other finger), the region matters: trained on the
        ``everyday`` preset, the baseline orders the public real grasps of
        ``GelSight-lab/EstimateModulus`` by softness better on the gel
        region than on the whole frame (evidence:
        ``studies/pages/sim_to_real_wedge.md``).

    Returns
    -------
    pipeline : :class:`~sklearn.pipeline.Pipeline`
        ``FunctionTransformer(peak_contact_change)`` -> ``StandardScaler`` ->
        ``LogisticRegression``; takes a sequence of videos.

    Examples
    --------
    >>> from sklearn_hardness.models import make_peak_change_baseline
    >>> [name for name, _ in make_peak_change_baseline().steps]
    ['functiontransformer', 'standardscaler', 'logisticregression']
    """
    roi = check_roi(roi)
    return make_pipeline(FunctionTransformer(peak_contact_change, kw_args=None if roi is None else {"roi": roi}),
                         StandardScaler(), LogisticRegression(class_weight=class_weight))
