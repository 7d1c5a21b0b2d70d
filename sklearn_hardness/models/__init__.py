"""Classifiers with Monte-Carlo-dropout uncertainty (skorch nets), and the ready-made pipelines by name.

* :func:`pipeline_names`, :func:`pipeline_info`, :func:`make_named_pipeline`:
  the ready-made pipelines by name (the names ``sklearn-hardness evaluate`` and
  ``reproduce`` take): the one door to the table of named pipelines, which
  ``model_selection``, the experiments and the command line use too; their
  ``make_*_pipeline`` factories; :func:`make_peak_change_baseline`, the
  one-number baseline.
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
* :class:`LaplaceLogisticRegression`: scikit-learn's logistic regression with
  ``predict_proba_samples`` from the Laplace approximation of its posterior
  (the contact-profile pipeline's logistic head).
* :class:`MCDropoutPipeline`: the pipeline of the factories, with the last
  step's ``predict_proba_samples``.

The nets have ``predict_proba_samples(X, n_samples, random_state)`` for
batched MC-dropout samples, and :func:`is_converged` implements the paper's
convergence rule (``threshold="chance"`` carries its threshold over to other
numbers of classes).

The names of the table of named pipelines import nothing beyond the standard
library; the others (the nets, torch) are imported when first asked for, so
that ``import sklearn_hardness.models`` and the modules that build pipelines
by name stay light.
"""

from ..utils._lazy_names import lazy_names
from ._registry import make_named_pipeline, pipeline_info, pipeline_names

#: Each public name that is imported when first asked for, and its module.
_LAZY = {
    "make_peak_change_baseline": "._peak_change",
    "make_convlstm_pipeline": "._pipelines",
    "make_imprint_cnn_pipeline": "._pipelines",
    "make_ofnn_pipeline": "._pipelines",
    "make_dinov2nn_pipeline": "._pipelines",
    "make_contact_profile_pipeline": "._pipelines",
    "make_contact_geometry_pipeline": "._pipelines",
    "make_imprint_texture_pipeline": "._pipelines",
    "make_loading_compliance_pipeline": "._pipelines",
    "MCDropoutPipeline": "._pipelines",
    "FrameAugmenter": "._augmentation",
    "OFNNClassifier": "._mlp",
    "DINOv2NNClassifier": "._mlp",
    "ContactProfileNNClassifier": "._mlp",
    "ConvLSTMClassifier": "._convlstm",
    "ImprintCNNClassifier": "._imprint_cnn",
    "EnsembleClassifier": "._ensemble",
    "LaplaceLogisticRegression": "._laplace",
    "is_converged": "._convergence",
}

__all__ = ["pipeline_names", "pipeline_info", "make_named_pipeline", *_LAZY]


__getattr__, __dir__ = lazy_names(__name__, globals(), _LAZY)
