"""The one number of a press: its peak change to the first frame, :class:`PeakContactChange`."""

from __future__ import annotations

import numpy as np
from sklearn.base import BaseEstimator, TransformerMixin
from sklearn.utils.validation import check_is_fitted

from ..preprocessing import contact_curve
from ..utils._param_validation import HasMethods, fit_context
from ..utils._per_press import PerPressTransformerMixin, map_presses, transform_presses
from ..utils._tags import videos_tags
from ..utils._validation import check_roi, check_video_sequence

__all__ = ["PeakContactChange"]


def _peak_row(video, roi=None, name="video"):
    """The one number of one press, as a row (``name`` is unused: the contact curve names no video)."""
    return np.array([np.log(0.1 + float(np.max(contact_curve(video, roi=roi))))])


class PeakContactChange(PerPressTransformerMixin, TransformerMixin, BaseEstimator):
    """Log of the peak mean absolute change of a press video to its first frame: one number per press.

    What a first look at a press gives, and what every pipeline is measured
    against: the maximum of
    :func:`~sklearn_hardness.preprocessing.contact_curve`, as
    ``log(0.1 + max_t curve(t))`` (the log evens out the spread of strong
    contacts; 0.1 keeps one-frame videos finite). The first step of the
    one-number baseline,
    :func:`~sklearn_hardness.models.make_peak_change_baseline`.

    Parameters
    ----------
    roi : tuple (top, bottom, left, right) or None, default=None
        Only this region of each frame (fractions of its height and width),
        e.g. the gel where the frame also shows the sensor housing.
    memory : None, str or object with the joblib.Memory interface, default=None
        Cache each press's number here (a folder, or a
        :class:`joblib.Memory`), keyed by ``roi`` and the press (a video of a
        lazy sequence by its file or seed, without decoding it; a video in
        memory by a hash of its frames), so that a later fit or transform on
        the same press reads it. Validated as
        :func:`sklearn.utils.validation.check_memory` validates a
        :class:`~sklearn.pipeline.Pipeline`'s ``memory``.

    Attributes
    ----------
    n_features_out_ : int
        1.

    See Also
    --------
    sklearn_hardness.preprocessing.contact_curve : The change per frame.

    Examples
    --------
    >>> import numpy as np
    >>> from sklearn_hardness.features import PeakContactChange
    >>> video = np.full((4, 16, 16, 3), 100, np.uint8)
    >>> video[3, :4, :4] = 116
    >>> PeakContactChange().fit_transform([video]).round(3).tolist()
    [[0.095]]
    """

    _parameter_constraints: dict = {
        "roi": [None, tuple, list],
        "memory": [None, str, HasMethods(["cache"])],
    }

    def __init__(self, roi=None, memory=None):
        self.roi = roi
        self.memory = memory

    @fit_context(prefer_skip_nested_validation=True)
    def fit(self, X, y=None):
        """Check the parameters and the input (stateless otherwise).

        Parameters
        ----------
        X : sequence of array-like of shape (T, H, W, C)
            Press videos.
        y : ignored

        Returns
        -------
        self : PeakContactChange
        """
        check_roi(self.roi)
        check_video_sequence(X)
        self.n_features_out_ = 1
        return self

    def transform(self, X):
        """The one number of each press.

        Parameters
        ----------
        X : sequence of array-like of shape (T, H, W, C)
            Press videos (lengths may differ).

        Returns
        -------
        feature : ndarray of shape (n_videos, 1)
        """
        check_is_fitted(self)
        X = check_video_sequence(X)
        return transform_presses(self, X)[0]

    def _transform_presses(self, X):
        return map_presses(_peak_row, X, {"roi": check_roi(self.roi)}), {}

    def get_feature_names_out(self, input_features=None):
        """The name of the one feature, ``"log_peak_change"``.

        Parameters
        ----------
        input_features : ignored

        Returns
        -------
        names : ndarray of str of shape (1,)
        """
        check_is_fitted(self)
        return np.array(["log_peak_change"], dtype=object)

    def __sklearn_tags__(self):
        return videos_tags(super().__sklearn_tags__())
