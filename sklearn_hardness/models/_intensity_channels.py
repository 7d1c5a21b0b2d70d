"""Per-frame contact-intensity statistics as extra channels: :class:`IntensityChannels`."""

from __future__ import annotations

import numbers

import numpy as np
from sklearn.base import BaseEstimator, TransformerMixin
from sklearn.utils.validation import check_is_fitted

from ..utils._param_validation import Interval, fit_context
from ..utils._tags import frames_tags
from ..utils._validation import check_frames_array

__all__ = ["IntensityChannels"]

#: The statistics appended per frame, one channel each, in this order.
INTENSITY_STATS = ("log_mean", "log_std", "log_max")


class IntensityChannels(TransformerMixin, BaseEstimator):
    """Append each frame's log mean, spread and maximum absolute change as constant channels.

    For every selected frame (differences to the first frame, e.g. after
    :class:`FrameScaler`), the mean, standard deviation and maximum of its
    absolute values over pixels and channels are taken, as ``log(floor +
    value)``, and appended as three channels that hold that value at every
    pixel. The frame itself is kept as it is.

    How strong a contact is and how concentrated (a sharp edge or point
    against a broad soft contact) are ratios of intensities, which is what
    separates hardness ranks across objects of different shapes. A
    ConvLSTM sees linear intensities through saturating gates and a spatial
    average, and from the presses of a few dozen objects it learns the
    objects' shapes instead. On a log scale these ratios are differences
    the recurrent layers can use directly. Object-disjoint on the simulator
    the ConvLSTM needed them to read new objects. It is a strong
    pull towards intensity, though: on presses of the *same* few objects
    (the paper's setting), where the spatial pattern of the change is what
    tells them apart, it costs the ConvLSTM accuracy. Use it for objects
    not seen in training (``make_convlstm_pipeline(intensity_channels=True)``;
    evidence: ``studies/pages/net_inputs.md``).

    Parameters
    ----------
    floor : float, default=0.25
        Added before the logarithm, in the units of the input (with
        :class:`FrameScaler` before it: standard deviations of the training
        frames). Keeps frames without change finite and damps noise-level
        differences.

    Attributes
    ----------
    n_channels_in_ : int
        Channels of the input frames.

    See Also
    --------
    FrameScaler : Brings the frames to unit variance first.
    sklearn_hardness.features.ContactProfileFeatures : Hand-made per-press features.

    Examples
    --------
    >>> import numpy as np
    >>> from sklearn_hardness.models._intensity_channels import IntensityChannels
    >>> X = np.zeros((1, 2, 4, 4, 1), np.float32)
    >>> X[0, 1, 1:3, 1:3] = 2.0                     # contact in the second frame
    >>> Xt = IntensityChannels().fit_transform(X)
    >>> Xt.shape
    (1, 2, 4, 4, 4)
    >>> Xt[0, :, 0, 0, 1:].astype(float).round(2).tolist()  # log mean, std, max per frame
    [[-1.39, -1.39, -1.39], [-0.29, 0.11, 0.81]]
    """

    _parameter_constraints: dict = {
        "floor": [Interval(numbers.Real, 0, None, closed="neither")],
    }

    def __init__(self, floor=0.25):
        self.floor = floor

    @fit_context(prefer_skip_nested_validation=True)
    def fit(self, X, y=None):
        """Check the parameters and remember the number of channels.

        Parameters
        ----------
        X : array-like of shape (n, k, H, W, C)
            Selected frames.
        y : ignored

        Returns
        -------
        self : IntensityChannels
        """
        X = check_frames_array(X)
        self.n_channels_in_ = int(X.shape[-1])
        return self

    def transform(self, X):
        """Append the three statistics channels.

        Parameters
        ----------
        X : array-like of shape (n, k, H, W, C)
            Selected frames with the channels seen in :meth:`fit`.

        Returns
        -------
        Xt : ndarray of shape (n, k, H, W, C + 3), float32
        """
        check_is_fitted(self, "n_channels_in_")
        X = check_frames_array(X)
        if X.shape[-1] != self.n_channels_in_:
            raise ValueError(
                f"X has {X.shape[-1]} channel(s) but IntensityChannels was fitted on {self.n_channels_in_}."
            )
        n, k, h, w, c = X.shape
        a = np.abs(X).reshape(n, k, -1)
        stats = np.log(self.floor + np.stack([a.mean(axis=2), a.std(axis=2), a.max(axis=2)], axis=-1))
        out = np.empty((n, k, h, w, c + len(INTENSITY_STATS)), np.float32)
        out[..., :c] = X
        out[..., c:] = stats[:, :, None, None, :]
        return out

    def __sklearn_tags__(self):
        return frames_tags(super().__sklearn_tags__())
