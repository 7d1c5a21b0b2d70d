"""Classifiers with Monte-Carlo-dropout uncertainty (skorch nets).

* :class:`OFNNClassifier`: MLP head on optical-flow features.
* :class:`DINOv2NNClassifier`: MLP head on frozen DINOv2 features.
* :class:`ContactProfileNNClassifier`: MLP head on contact-profile features of the
  loading phase (the input that carries over to new objects).
* :class:`ConvLSTMClassifier`: ConvLSTM trained end to end on selected frames.
* :class:`ImprintCNNClassifier`: a small CNN trained from scratch on every
  selected frame (with augmentation), frame probabilities averaged per press.
* :class:`FrameAugmenter`: random mirroring, gain, drift and noise of the
  ConvLSTM's training batches.
* :class:`EnsembleClassifier`: differently seeded copies of a classifier, whose
  spread replaces MC dropout as the source of ``predict_proba_samples``.
* :class:`StackedConvLSTMNet`: K ConvLSTM nets stepped as one torch module
  (``EnsembleClassifier(stacked=True)``'s, for many small nets on a GPU).
* :class:`LaplaceLogisticRegression`: scikit-learn's logistic regression with
  ``predict_proba_samples`` from the Laplace approximation of its posterior
  (the contact-profile pipeline's logistic head).
* :func:`pipeline_names`, :func:`pipeline_info`, :func:`make_named_pipeline`:
  the ready-made pipelines by name (the names ``sklearn-hardness evaluate`` and
  ``reproduce`` take), and their ``make_*_pipeline`` builders;
  :func:`make_peak_change_baseline`, the one-number baseline.

* :class:`FrameScaler`: the one global input scale of the frame pipelines;
  :class:`EarlyStoppingAfterFirstFit`: skorch's early stopping on every
  training call but the first.

The nets have ``predict_proba_samples(X, n_samples, random_state)`` for
batched MC-dropout samples, :func:`is_converged` implements the paper's
convergence rule and :func:`chance_scaled_threshold` carries its threshold
over to other numbers of classes.
"""

from .._registry import make_named_pipeline, pipeline_info, pipeline_names
from ._augmentation import FrameAugmenter
from ._callbacks import EarlyStoppingAfterFirstFit
from ._convergence import chance_scaled_threshold, is_converged
from ._convlstm import ConvLSTMClassifier
from ._ensemble import EnsembleClassifier
from ._imprint_cnn import ImprintCNNClassifier
from ._laplace import LaplaceLogisticRegression
from ._mlp import ContactProfileNNClassifier, DINOv2NNClassifier, OFNNClassifier
from ._peak_change import make_peak_change_baseline
from ._pipelines import (
    FrameScaler,
    MCDropoutPipeline,
    make_contact_geometry_pipeline,
    make_contact_profile_pipeline,
    make_convlstm_pipeline,
    make_dinov2nn_pipeline,
    make_imprint_cnn_pipeline,
    make_imprint_texture_pipeline,
    make_loading_compliance_pipeline,
    make_ofnn_pipeline,
)
from ._stacked import StackedConvLSTMNet

__all__ = [
    "pipeline_names",
    "pipeline_info",
    "make_named_pipeline",
    "make_peak_change_baseline",
    "make_convlstm_pipeline",
    "make_imprint_cnn_pipeline",
    "make_ofnn_pipeline",
    "make_dinov2nn_pipeline",
    "make_contact_profile_pipeline",
    "make_contact_geometry_pipeline",
    "make_imprint_texture_pipeline",
    "make_loading_compliance_pipeline",
    "FrameAugmenter",
    "MCDropoutPipeline",
    "OFNNClassifier",
    "DINOv2NNClassifier",
    "ContactProfileNNClassifier",
    "ConvLSTMClassifier",
    "ImprintCNNClassifier",
    "EnsembleClassifier",
    "StackedConvLSTMNet",
    "LaplaceLogisticRegression",
    "is_converged",
    "chance_scaled_threshold",
    "FrameScaler",
    "EarlyStoppingAfterFirstFit",
]
