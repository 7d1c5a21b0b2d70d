"""The one-number baseline: the peak change of a press video to its first frame, and a classifier on it.

What a first look at a press gives, and what every pipeline is measured
against (:func:`~sklearn_hardness.model_selection.evaluate_pipelines` runs it
beside them): :class:`~sklearn_hardness.features.PeakContactChange` turns a
video into one number, :func:`make_peak_change_baseline` classifies with it.
"""

from __future__ import annotations

from sklearn.linear_model import LogisticRegression
from sklearn.pipeline import make_pipeline
from sklearn.preprocessing import StandardScaler

from ..features import PeakContactChange
from ..utils._validation import check_roi

__all__ = ["make_peak_change_baseline"]


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
        height and width; see
        :class:`~sklearn_hardness.features.PeakContactChange`). Where the frame
        shows more than the gel (a GelSight Wedge grasp shows the housing
        and the other finger), the region matters: trained on the
        ``everyday`` preset, the baseline orders the public real grasps of
        ``GelSight-lab/EstimateModulus`` by softness better on the gel
        region than on the whole frame (evidence:
        ``studies/pages/sim_to_real_wedge.md``).

    Returns
    -------
    pipeline : :class:`~sklearn.pipeline.Pipeline`
        :class:`~sklearn_hardness.features.PeakContactChange` ->
        ``StandardScaler`` -> ``LogisticRegression``; takes a sequence of
        videos.

    Examples
    --------
    >>> from sklearn_hardness.models import make_peak_change_baseline
    >>> [name for name, _ in make_peak_change_baseline().steps]
    ['peakcontactchange', 'standardscaler', 'logisticregression']
    """
    roi = check_roi(roi)
    return make_pipeline(PeakContactChange(roi=roi), StandardScaler(), LogisticRegression(class_weight=class_weight))
