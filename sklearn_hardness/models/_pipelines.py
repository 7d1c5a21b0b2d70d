"""Ready-made pipelines from raw press videos to a Monte-Carlo-dropout classifier.

Each pipeline is ``ContactFrameSelector -> [features] -> classifier`` with the
paper's choices (Sec. II): the frames at contact start and peak plus
``n_between`` frames in between, differences to the first frame; optical flow
or frozen DINOv2 features, or the ConvLSTM on the frames themselves.
"""

from __future__ import annotations

import numpy as np
from sklearn.base import BaseEstimator, TransformerMixin
from sklearn.pipeline import Pipeline
from sklearn.utils.validation import check_is_fitted

from ..utils._validation import check_frames_array

__all__ = ["FrameScaler", "make_convlstm_pipeline", "make_ofnn_pipeline", "make_dinov2nn_pipeline"]


class FrameScaler(TransformerMixin, BaseEstimator):
    """Divide selected frames by their standard deviation over the training set.

    Differences to the first frame are small (a few hundredths of full scale)
    and a ConvLSTM barely trains on them; one global scale learnt in
    :meth:`fit` brings them to unit variance.

    Attributes
    ----------
    scale_ : float
        Standard deviation of the training frames (1.0 if they are constant).
    """

    def fit(self, X, y=None):
        X = check_frames_array(X)
        std = float(np.std(X))
        self.scale_ = std if std > 0 else 1.0
        return self

    def transform(self, X):
        check_is_fitted(self, "scale_")
        return check_frames_array(X) / np.float32(self.scale_)


def _selector(n_between, frame_size, color, subtract_first=True):
    from ..preprocessing import ContactFrameSelector

    return ContactFrameSelector(
        n_between=n_between, output_size=frame_size, color=color, subtract_first=subtract_first
    )


def make_convlstm_pipeline(*, n_between=2, frame_size=(18, 24), color="gray", **classifier_params):
    """Videos -> contact frames -> :class:`FrameScaler` -> :class:`ConvLSTMClassifier`.

    Parameters
    ----------
    n_between : int, default=2
        Frames between contact start and peak (2 for the robot data, 1 for Yuan's).
    frame_size : (int, int), default=(18, 24)
        Size of the selected frames; small grey frames keep training on a CPU fast.
    color : {"gray", "rgb"}, default="gray"
    **classifier_params
        Passed to :class:`ConvLSTMClassifier` (e.g. ``dropout``, ``max_epochs``,
        ``random_state``).

    Returns
    -------
    pipeline : sklearn.pipeline.Pipeline
        Steps ``"frames"``, ``"scale"``, ``"clf"``; works with
        :class:`~sklearn_hardness.active.ActiveLearner` and ``GridSearchCV``
        (``clf__dropout``).
    """
    from ._convlstm import ConvLSTMClassifier

    return Pipeline([("frames", _selector(n_between, frame_size, color)), ("scale", FrameScaler()),
                     ("clf", ConvLSTMClassifier(**classifier_params))])


def make_ofnn_pipeline(*, n_between=2, frame_size=(120, 160), n_features=500, **classifier_params):
    """Videos -> contact frames -> :class:`OpticalFlowFeatures` -> :class:`OFNNClassifier`."""
    from ..features import OpticalFlowFeatures
    from ._mlp import OFNNClassifier

    # raw frames, not differences: optical flow tracks the gel's markers
    return Pipeline([("frames", _selector(n_between, frame_size, "gray", subtract_first=False)),
                     ("features", OpticalFlowFeatures(n_features=n_features)),
                     ("clf", OFNNClassifier(**classifier_params))])


def make_dinov2nn_pipeline(*, n_between=1, frame_size=(112, 150), model="facebook/dinov2-small",
                           **classifier_params):
    """Videos -> contact frames -> :class:`DINOv2Features` -> :class:`DINOv2NNClassifier`.

    ``model`` is the DINOv2 backbone (Hugging Face id in the local cache, a
    local directory or a module; see :class:`DINOv2Features`).
    """
    from ..features import DINOv2Features
    from ._mlp import DINOv2NNClassifier

    return Pipeline([("frames", _selector(n_between, frame_size, "rgb")),
                     ("features", DINOv2Features(model=model)),
                     ("clf", DINOv2NNClassifier(**classifier_params))])
