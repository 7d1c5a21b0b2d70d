"""Ready-made pipelines from raw press videos to a Monte-Carlo-dropout classifier.

Each pipeline is ``ContactFrameSelector -> [features] -> classifier`` with the
paper's frame selection (Sec. II): the frames at contact start and peak plus
``n_between`` frames in between, differences to the first frame; optical flow
or frozen DINOv2 features, or the ConvLSTM on the frames themselves. The
OFNN pipeline summarises the flow by magnitude quantiles, and the ConvLSTM
pipeline takes intensity channels for objects not seen in training; their
docstrings say how to get the paper's exact inputs and what each costs.
"""

from __future__ import annotations

import numpy as np
from sklearn.base import BaseEstimator, TransformerMixin
from sklearn.impute import SimpleImputer
from sklearn.pipeline import FeatureUnion, Pipeline
from sklearn.preprocessing import FunctionTransformer, StandardScaler
from sklearn.utils.metaestimators import available_if
from sklearn.utils.validation import check_is_fitted

from ..features import (
    ContactGeometryFeatures,
    ContactProfileFeatures,
    DINOv2Features,
    ImprintTextureFeatures,
    LoadingCompliance,
    OpticalFlowFeatures,
)
from ..preprocessing import ContactFrameSelector
from ..utils._tags import frames_tags
from ..utils._validation import check_frames_array
from ._augmentation import FrameAugmenter
from ._convlstm import ConvLSTMClassifier
from ._imprint_cnn import ImprintCNNClassifier
from ._intensity_channels import INTENSITY_STATS, IntensityChannels
from ._laplace import LaplaceLogisticRegression
from ._mlp import ContactProfileNNClassifier, DINOv2NNClassifier, OFNNClassifier

__all__ = [
    "FrameScaler",
    "MCDropoutPipeline",
    "make_convlstm_pipeline",
    "make_imprint_cnn_pipeline",
    "make_ofnn_pipeline",
    "make_dinov2nn_pipeline",
    "make_contact_profile_pipeline",
    "make_contact_geometry_pipeline",
    "make_imprint_texture_pipeline",
    "make_loading_compliance_pipeline",
]


def _final_estimator_has_samples(pipeline):
    return hasattr(pipeline._final_estimator, "predict_proba_samples")


class MCDropoutPipeline(Pipeline):
    """A :class:`~sklearn.pipeline.Pipeline` that also forwards ``predict_proba_samples``.

    Identical to scikit-learn's Pipeline, plus :meth:`predict_proba_samples`:
    ``X`` goes through the ``transform`` of every step but the last, and the
    last step's Monte-Carlo-dropout sampler is called on the result, so
    frame selection and frozen features run once for all passes. The
    ``make_*_pipeline`` functions return one.

    Examples
    --------
    >>> from sklearn.preprocessing import StandardScaler
    >>> from sklearn_hardness.models import MCDropoutPipeline, OFNNClassifier
    >>> import numpy as np
    >>> X = np.random.default_rng(0).normal(size=(20, 6)).astype(np.float32)
    >>> y = np.arange(20) % 2
    >>> pipe = MCDropoutPipeline([("scale", StandardScaler()),
    ...                           ("clf", OFNNClassifier(max_epochs=2, random_state=0))]).fit(X, y)
    >>> pipe.predict_proba_samples(X[:3], n_samples=4, random_state=0).shape
    (4, 3, 2)
    """

    @available_if(_final_estimator_has_samples)
    def predict_proba_samples(self, X, n_samples=50, random_state=None, **params):
        """Monte-Carlo-dropout class probabilities of the final step.

        Parameters
        ----------
        X : iterable
            Input of the first step (e.g. a sequence of press videos).
        n_samples : int, default=50
            Stochastic forward passes.
        random_state : int or None, default=None
            Seed of the dropout masks.
        **params
            Passed to the final step's ``predict_proba_samples``.

        Returns
        -------
        proba_samples : ndarray of shape (n_samples, n_X, n_classes)
        """
        check_is_fitted(self)
        Xt = X
        for _, _, transformer in self._iter(with_final=False):
            Xt = transformer.transform(Xt)
        return self._final_estimator.predict_proba_samples(
            Xt, n_samples=n_samples, random_state=random_state, **params
        )


class FrameScaler(TransformerMixin, BaseEstimator):
    """Divide selected frames by their standard deviation over the training set.

    Differences to the first frame are small (a few hundredths of full scale)
    and a ConvLSTM barely trains on them; one global scale learnt in
    ``fit`` brings them to unit variance.

    Attributes
    ----------
    scale_ : float
        Standard deviation of the training frames (1.0 if they are constant).

    Notes
    -----
    The one global input scale of the package: :func:`make_convlstm_pipeline`
    puts it before the net, and the experiments fit the same step (the
    factory's ``"scale"``) on each run's training presses, or on all presses
    for the model baselines (``input_scale="std"`` of
    :func:`~sklearn_hardness.experiments.get_config`). The net's own
    ``standardize`` is a different operation, per channel; a constant factor
    cancels in it, but not before ``IntensityChannels``, whose ``floor``
    is in the units this step makes (the frames' spread), so the pipeline
    gives the same intensity channels whether a camera's frames come in grey
    levels 0-255 or 0-1.

    Examples
    --------
    >>> import numpy as np
    >>> from sklearn_hardness.models._pipelines import FrameScaler
    >>> X = np.random.default_rng(0).normal(0, 3, size=(4, 2, 6, 8, 1)).astype(np.float32)
    >>> scaler = FrameScaler().fit(X)
    >>> round(float(scaler.transform(X).std()), 3)
    1.0
    """

    def fit(self, X, y=None):
        X = check_frames_array(X)
        std = float(np.std(X))
        self.scale_ = std if std > 0 else 1.0
        return self

    def transform(self, X):
        check_is_fitted(self, "scale_")
        return check_frames_array(X) / np.float32(self.scale_)

    def __sklearn_tags__(self):
        return frames_tags(super().__sklearn_tags__())


def _selector(n_between, frame_size, color, roi, subtract_first=True):
    return ContactFrameSelector(
        n_between=n_between, frame_size=frame_size, color=color, roi=roi, subtract_first=subtract_first
    )


def make_convlstm_pipeline(*, n_between=2, frame_size=(12, 16), color="gray", intensity_channels=False,
                           augment=False, roi=None, **classifier_params):
    """Videos -> contact frames -> ``FrameScaler`` -> [``IntensityChannels``] -> ConvLSTM classifier.

    Which input is best depends on whether the test objects were seen in
    training:

    - presses of the *same* objects (the paper's setting): the frames alone,
      the default;
    - objects the model has *not* seen (a user's own objects, evaluated
      object-disjoint): ``intensity_channels=True``.

    Which input ranks new objects better is measured, not assumed: compare
    them with :func:`~sklearn_hardness.model_selection.evaluate_pipelines`
    (``"convlstm"`` and ``"convlstm_intensity"``) on your own objects, beside
    the one-number baseline (evidence: ``studies/pages/net_inputs.md``).

    Parameters
    ----------
    n_between : int, default=2
        Frames between contact start and peak (2 for the robot data, 1 for Yuan's).
    frame_size : (int, int), default=(12, 16)
        Size of the selected frames; small grey frames keep training on a CPU
        fast (the experiments' default, see ``docs/user_guide/runtime.rst``).
    color : {"gray", "rgb"}, default="gray"
    intensity_channels : bool, default=False
        Append each frame's log mean, spread and maximum change as channels
        (an ``IntensityChannels`` step): for objects not seen in training.
    augment : bool or FrameAugmenter, default=False
        Random mirroring and gain of every training batch (the
        :class:`ConvLSTMClassifier`'s ``augment``). True: a default
        :class:`FrameAugmenter` whose ``log_channels`` are the intensity
        channels when ``intensity_channels=True``; a :class:`FrameAugmenter`
        is used as given. Off by default: it gave no measurable gain
        (:class:`FrameAugmenter`'s Notes).
    roi : tuple (top, bottom, left, right) or None, default=None
        ``roi`` of the :class:`~sklearn_hardness.preprocessing.ContactFrameSelector`
        (step ``"frames"``): find contact and take frames only in this region
        (fractions of height and width), e.g. the gel where the frame also
        shows the sensor housing.
    **classifier_params
        Passed to :class:`ConvLSTMClassifier` (e.g. ``dropout``,
        ``dropout_placement="layers"`` for the paper's dropout after each
        ConvLSTM layer, ``max_epochs``, ``random_state``). ``class_weight`` defaults to ``"balanced"`` here
        (the same as None when every class has as many presses; pass None for
        the paper's unweighted loss).

    Returns
    -------
    pipeline : MCDropoutPipeline
        Steps ``"frames"``, ``"scale"``, [``"intensity"``,] ``"clf"``; works
        with :class:`~sklearn_hardness.active.ActiveLearner` and
        ``GridSearchCV`` (``clf__dropout``).

    Examples
    --------
    >>> from sklearn_hardness.models import make_convlstm_pipeline
    >>> [name for name, _ in make_convlstm_pipeline().steps]
    ['frames', 'scale', 'clf']
    >>> [name for name, _ in make_convlstm_pipeline(intensity_channels=True).steps]
    ['frames', 'scale', 'intensity', 'clf']
    """

    classifier_params.setdefault("class_weight", "balanced")
    if augment is True:
        n_frame_channels = 3 if color == "rgb" else 1
        n_log = len(INTENSITY_STATS) if intensity_channels else 0
        log_channels = list(range(n_frame_channels, n_frame_channels + n_log))
        augment = FrameAugmenter(log_channels=log_channels)
    elif augment is False:
        augment = None
    classifier_params["augment"] = augment
    steps = [("frames", _selector(n_between, frame_size, color, roi)), ("scale", FrameScaler())]
    if intensity_channels:
        steps.append(("intensity", IntensityChannels()))
    steps.append(("clf", ConvLSTMClassifier(**classifier_params)))
    return MCDropoutPipeline(steps)


def make_imprint_cnn_pipeline(*, k=8, frame_size=(60, 80), color="rgb", roi=None, random_state=None,
                              **classifier_params):
    """Videos -> ``k`` contact frames -> ``FrameScaler`` -> :class:`~sklearn_hardness.models.ImprintCNNClassifier`.

    A small CNN, trained from scratch with strong augmentation, reads every
    selected frame of a press as one example (the imprint's appearance:
    texture and shape, which tell the material); a press's probabilities are
    the mean of its frames'.

    Parameters
    ----------
    k : int, default=8
        Frames kept per press (at least 2): contact start, peak change and
        ``k - 2`` frames at equal spacing between (``n_between=k - 2`` of
        the :class:`~sklearn_hardness.preprocessing.ContactFrameSelector`),
        each a difference to the video's first frame.
    frame_size : (int, int), default=(60, 80)
        (height, width) of the selected frames: a quarter of GelSight Mini's
        240x320 stream in each direction.
    color : {"rgb", "gray"}, default="rgb"
    roi : tuple (top, bottom, left, right) or None, default=None
        ``roi`` of the frame selector (step ``"frames"``), as in
        :func:`make_convlstm_pipeline`.
    random_state : int, RandomState instance or None, default=None
        Seeds the net (weights, shuffling, dropout masks, augmentations).
    **classifier_params
        Passed to :class:`ImprintCNNClassifier` (``dropout``, ``width``,
        ``augment``, ``max_epochs``, ``device``...).

    Returns
    -------
    pipeline : MCDropoutPipeline
        Steps ``"frames"``, ``"scale"``, ``"clf"``, with
        ``predict_proba_samples``; ``GridSearchCV`` searches ``clf__dropout``.

    Examples
    --------
    >>> from sklearn_hardness.models import make_imprint_cnn_pipeline
    >>> pipe = make_imprint_cnn_pipeline(k=4, random_state=0)
    >>> [name for name, _ in pipe.steps], pipe.named_steps["frames"].n_between
    (['frames', 'scale', 'clf'], 2)
    """
    if isinstance(k, bool) or not isinstance(k, (int, np.integer)) or k < 2:
        raise ValueError(f"k must be an int of at least 2 (contact start and peak), got {k!r}.")
    clf = ImprintCNNClassifier(random_state=random_state, **classifier_params)
    return MCDropoutPipeline([("frames", _selector(int(k) - 2, frame_size, color, roi)), ("scale", FrameScaler()),
                              ("clf", clf)])


def make_ofnn_pipeline(*, n_between=2, frame_size=(120, 160), n_features=500, flow_output="magnitude_quantiles",
                       roi=None, **classifier_params):
    """Videos -> contact frames -> optical-flow features -> the OFNN classifier.

    Parameters
    ----------
    n_between : int, default=2
        Frames between contact start and peak.
    frame_size : (int, int), default=(120, 160)
        Size of the selected (raw, not differenced) frames the corners are
        tracked on.
    n_features : int, default=500
        Corners tracked per press (the paper's 500).
    flow_output : {"magnitude_quantiles", "tracks"}, default="magnitude_quantiles"
        ``output`` of :class:`~sklearn_hardness.features.OpticalFlowFeatures`.
        The default summarises how far the corners moved, whichever corner
        is which; it ranks unseen objects (``everyday``, object-disjoint) and
        the paper's own setting (5 training presses per object on
        ``silicone5`` and ``shore9``) better than the paper's flattened
        ``"tracks"``, which the :mod:`~sklearn_hardness.experiments` use to
        reproduce the paper (evidence: ``studies/pages/net_inputs.md``).
    roi : tuple (top, bottom, left, right) or None, default=None
        ``roi`` of the :class:`~sklearn_hardness.preprocessing.ContactFrameSelector`
        (step ``"frames"``): find contact and track corners only in this
        region (fractions of height and width).
    **classifier_params
        Passed to :class:`OFNNClassifier`; ``class_weight`` defaults to
        ``"balanced"`` here.

    Returns
    -------
    pipeline : MCDropoutPipeline
        Steps ``"frames"``, ``"features"``, ``"clf"``.

    Examples
    --------
    >>> from sklearn_hardness.models import make_ofnn_pipeline
    >>> make_ofnn_pipeline().named_steps["features"].output
    'magnitude_quantiles'
    """

    classifier_params.setdefault("class_weight", "balanced")
    # raw frames, not differences: optical flow tracks the gel's markers or texture
    return MCDropoutPipeline([("frames", _selector(n_between, frame_size, "gray", roi, subtract_first=False)),
                     ("features", OpticalFlowFeatures(n_features=n_features, output=flow_output)),
                     ("clf", OFNNClassifier(**classifier_params))])


def make_dinov2nn_pipeline(*, n_between=1, frame_size=(112, 150), model="facebook/dinov2-small", roi=None,
                           **classifier_params):
    """Videos -> contact frames -> frozen DINOv2 features -> the DINOv2NN classifier.

    Parameters
    ----------
    n_between : int, default=1
        Frames between contact start and peak.
    frame_size : (int, int), default=(112, 150)
        Size of the selected RGB frames (differences to the first frame) fed
        to the backbone.
    model : str, path-like or torch.nn.Module, default="facebook/dinov2-small"
        The DINOv2 backbone: a Hugging Face id in the local cache, a local
        directory or a module (see :class:`~sklearn_hardness.features.DINOv2Features`; nothing is
        downloaded at run time).
    roi : tuple (top, bottom, left, right) or None, default=None
        ``roi`` of the :class:`~sklearn_hardness.preprocessing.ContactFrameSelector`
        (step ``"frames"``), as in :func:`make_convlstm_pipeline`.
    **classifier_params
        Passed to :class:`DINOv2NNClassifier`.

    Returns
    -------
    pipeline : MCDropoutPipeline
        Steps ``"frames"``, ``"features"``, ``"clf"``.

    Examples
    --------
    >>> from sklearn_hardness.models import make_dinov2nn_pipeline
    >>> make_dinov2nn_pipeline(roi=(0.1, 0.9, 0.1, 0.9)).named_steps["frames"].roi
    (0.1, 0.9, 0.1, 0.9)
    """

    return MCDropoutPipeline([("frames", _selector(n_between, frame_size, "rgb", roi)),
                     ("features", DINOv2Features(model=model)),
                     ("clf", DINOv2NNClassifier(**classifier_params))])


def _logistic_head(params):
    """The pipelines' logistic head: balanced classes and 2000 iterations unless ``params`` say otherwise."""
    return LaplaceLogisticRegression(**{"class_weight": "balanced", "max_iter": 2000, **params})


def make_contact_profile_pipeline(*, head="logistic", features="all", max_side=80, roi=None, **classifier_params):
    """Videos -> :class:`~sklearn_hardness.features.ContactProfileFeatures` -> scaler -> classifier.

    The pipeline for objects the model has not seen: twelve features of the
    loading phase (peak change and its ratio to the video's own pre-contact
    noise, loading time in whole frames and between frames, contact area and
    spread, how contact area grows with intensity, concentration, texture
    ratio, ...) computed on the whole video, without frame selection, then a
    classifier. The default head is the logistic regression, whose posterior
    samples drive active sampling; ``head="nn"`` is an MC-dropout MLP. How
    the heads and inputs compare on real and simulated new objects:
    ``studies/pages/pipelines_new_objects.md`` and
    ``studies/pages/real_development_objects.md``.

    Parameters
    ----------
    head : {"logistic", "nn"}, default="logistic"
        ``"logistic"``: balanced logistic regression,
        :class:`LaplaceLogisticRegression` (scikit-learn's
        :class:`~sklearn.linear_model.LogisticRegression`, whose
        ``predict_proba_samples`` draws from the Laplace approximation of its
        posterior; what ``evaluate``'s ``"contact_profile"`` runs).
        ``"nn"``: :class:`ContactProfileNNClassifier`, an MLP with MC dropout
        (what ``evaluate``'s ``"contact_profile_nn"`` runs; its ``dropout``
        is a parameter to search over). Either way the pipeline has
        :meth:`~MCDropoutPipeline.predict_proba_samples` and drives active
        sampling.
    features : "all" or sequence of str, default="all"
        ``features`` of :class:`~sklearn_hardness.features.ContactProfileFeatures`:
        which of its twelve features the head reads (a grid searches it as
        ``features__features``).
    max_side : int, default=80
        ``max_side`` of :class:`~sklearn_hardness.features.ContactProfileFeatures`.
    roi : tuple (top, bottom, left, right) or None, default=None
        ``roi`` of :class:`~sklearn_hardness.features.ContactProfileFeatures`:
        read only this region of the frames (fractions of height and
        width), e.g. the gel where the frame also shows the sensor housing.
    **classifier_params
        Passed to the head; ``class_weight`` defaults to ``"balanced"``
        (imbalanced ranks otherwise collapse onto the majority class), and
        the logistic head's ``max_iter`` to 2000. A parameter the head does
        not take (``max_epochs`` with the logistic head, ``C`` with the MLP)
        raises a ``TypeError`` that names it and the other head.

    .. versionchanged:: 0.1
       ``head`` defaults to ``"logistic"`` (it was ``"nn"`` until the
       logistic head had ``predict_proba_samples``); pass ``head="nn"`` for
       the MLP.

    Returns
    -------
    pipeline : MCDropoutPipeline
        Steps ``"features"``, ``"scale"``, ``"clf"``.

    Examples
    --------
    >>> import numpy as np
    >>> from sklearn_hardness.models import make_contact_profile_pipeline
    >>> rng = np.random.default_rng(0)
    >>> videos = []
    >>> for k in range(12):  # a contact that grows from frame 8, stronger for harder classes
    ...     video = rng.integers(118, 122, size=(20, 32, 32, 3)).astype(np.uint8)
    ...     for t in range(8, 20):
    ...         video[t, 8:24, 8:24] += np.uint8(5 * (k % 3 + 1))
    ...     videos.append(video)
    >>> y = np.arange(12) % 3
    >>> pipe = make_contact_profile_pipeline().fit(videos, y)
    >>> pipe.predict_proba_samples(videos[:2], n_samples=5, random_state=0).shape
    (5, 2, 3)
    >>> mlp = make_contact_profile_pipeline(head="nn", max_epochs=20, random_state=0).fit(videos, y)
    """
    heads = {"logistic": LaplaceLogisticRegression, "nn": ContactProfileNNClassifier}
    if head not in heads:
        raise ValueError(f"head must be 'logistic' or 'nn', got {head!r}.")
    known = heads[head]().get_params(deep=False)
    # skorch routes prefixed parameters (optimizer__weight_decay, ...) and checks them itself
    unknown = sorted(k for k in classifier_params if k not in known and not (head == "nn" and "__" in k))
    if unknown:
        other = "nn" if head == "logistic" else "logistic"
        takes = sorted(set(unknown) & set(heads[other]().get_params(deep=False)))
        hint = f"; {takes} belong to head={other!r}" if takes else ""
        raise TypeError(f"head={head!r} ({heads[head].__name__}) takes no parameter(s) {unknown}{hint}.")
    classifier_params.setdefault("class_weight", "balanced")
    clf = _logistic_head(classifier_params) if head == "logistic" else heads[head](**classifier_params)
    return MCDropoutPipeline([("features", ContactProfileFeatures(features=features, max_side=max_side, roi=roi)),
                              ("scale", StandardScaler()), ("clf", clf)])


#: Figures at or below this (mm, N, mm/N) are logged as this: a press can fit a
#: compliance of zero or below when force noise outweighs a rigid object's travel.
_LOG_FLOOR = 1e-3


def _log_positive(X):
    """Natural log of ``X``, with values under 1e-3 taken as 1e-3 (NaN stays NaN).

    The log step of :func:`make_loading_compliance_pipeline` (a module-level
    function, so that the pipeline pickles).

    Parameters
    ----------
    X : array-like

    Returns
    -------
    ndarray
    """
    return np.log(np.maximum(np.asarray(X, dtype=np.float64), _LOG_FLOOR))  # maximum keeps NaN; fmax would not


def make_loading_compliance_pipeline(*, features=("hertz_compliance",), onset=0.1, drive_compliance=0.0,
                                     **classifier_params):
    """Force and position per frame -> :class:`~sklearn_hardness.features.LoadingCompliance` -> classifier.

    For presses whose force and position a robot (or gripper) records beside
    the video. The compliance of gel and object in series, fitted over
    the loading phase, is logged, imputed where a press is too short
    to fit (the median of the training presses), scaled, and classified by
    a balanced logistic regression with ``predict_proba_samples``
    (:class:`LaplaceLogisticRegression`), so active sampling works with it.

    The default input is the Hertz compliance alone (position against
    ``F^(2/3)``): it does not depend on the force a press reaches, so a
    model trained on the simulator's presses of a few newtons carries over
    to grasps of tens of newtons (evidence:
    ``studies/pages/force_and_position.md``, from
    ``studies/scripts/loading_compliance.py`` on simulated presses and
    ``studies/scripts/wedge_force.py`` on real GelSight Wedge grasps).

    Parameters
    ----------
    features : "all" or sequence of str, default=("hertz_compliance",)
        ``features`` of :class:`~sklearn_hardness.features.LoadingCompliance`.
    onset : float in (0, 1), default=0.1
        ``onset`` of :class:`~sklearn_hardness.features.LoadingCompliance`.
    drive_compliance : float, default=0.0
        ``drive_compliance`` of
        :class:`~sklearn_hardness.features.LoadingCompliance`, mm/N: 0 for a
        measured position (encoders, a gripper's width); an impedance
        controller's compliance for its commanded position.
    **classifier_params
        Passed to :class:`LaplaceLogisticRegression`; ``class_weight``
        defaults to ``"balanced"`` and ``max_iter`` to 2000.

    Returns
    -------
    pipeline : MCDropoutPipeline
        Steps ``"features"``, ``"log"``, ``"impute"``, ``"scale"``, ``"clf"``.

    See Also
    --------
    make_contact_profile_pipeline : What the video alone can do.

    Examples
    --------
    >>> import numpy as np
    >>> from sklearn_hardness.models import make_loading_compliance_pipeline
    >>> rng = np.random.default_rng(0)
    >>> force = np.linspace(0.0, 5.0, 30)
    >>> compliance = {0: 0.5, 1: 1.0, 2: 2.0}  # mm/N^(2/3): hard, moderate, soft
    >>> y = np.arange(30) % 3
    >>> X = [np.column_stack([force, compliance[k] * rng.uniform(0.8, 1.2) * force ** (2 / 3)]) for k in y]
    >>> pipe = make_loading_compliance_pipeline().fit(X, y)
    >>> pipe.predict([np.column_stack([4 * force, 2.0 * (4 * force) ** (2 / 3)])])  # pushed 4x harder
    array([2])
    >>> pipe.predict_proba_samples(X[:2], n_samples=5, random_state=0).shape
    (5, 2, 3)
    """
    unknown = sorted(k for k in classifier_params if k not in LaplaceLogisticRegression().get_params(deep=False))
    if unknown:
        raise TypeError(f"LaplaceLogisticRegression takes no parameter(s) {unknown}.")
    clf = _logistic_head(classifier_params)
    return MCDropoutPipeline([
        ("features", LoadingCompliance(features=features, onset=onset, drive_compliance=drive_compliance)),
        ("log", FunctionTransformer(_log_positive, feature_names_out="one-to-one")),
        ("impute", SimpleImputer(strategy="median")),
        ("scale", StandardScaler()),
        ("clf", clf),
    ])


def _table_head(head, classifier_params):
    """The head of a features -> scaler -> classifier pipeline: balanced logistic regression or MC-dropout MLP."""
    if head not in ("logistic", "nn"):
        raise ValueError(f"head must be 'logistic' or 'nn', got {head!r}.")
    params = {"class_weight": "balanced", **classifier_params}
    if head == "logistic":
        params.setdefault("max_iter", 2000)
        return LaplaceLogisticRegression(**params)
    return ContactProfileNNClassifier(**params)


def make_contact_geometry_pipeline(*, head="logistic", features="scale_free", with_profile=False, max_side=80, roi=None,
                                   **classifier_params):
    """Videos -> contact-geometry features (and optionally the contact profile) -> scaler -> classifier.

    Parameters
    ----------
    head : {"logistic", "nn"}, default="logistic"
        ``"logistic"``: balanced :class:`~sklearn_hardness.models.LaplaceLogisticRegression`
        (``predict_proba_samples`` from its Laplace posterior);
        ``"nn"``: :class:`~sklearn_hardness.models.ContactProfileNNClassifier`
        (an MLP with MC dropout). Either way the pipeline has
        ``predict_proba_samples`` and can drive active sampling.
    features : "all", "scale_free" or sequence of str, default="scale_free"
        ``features`` of :class:`~sklearn_hardness.features.ContactGeometryFeatures`;
        by default the twelve that do not grow with how hard the press is made
        (shapes, ratios and growth slopes), the
        choice made on real hand presses of new objects (see
        ``studies/pages/real_development_objects.md``).
    with_profile : bool, default=False
        Also read the twelve
        :class:`~sklearn_hardness.features.ContactProfileFeatures` (a
        :class:`~sklearn.pipeline.FeatureUnion` of the two).
    max_side : int, default=80
        ``max_side`` of the feature transformers.
    roi : tuple (top, bottom, left, right) or None, default=None
        ``roi`` of the feature transformers.
    **classifier_params
        Passed to the head; ``class_weight`` defaults to ``"balanced"``
        (and the logistic head's ``max_iter`` to 2000).

    Returns
    -------
    pipeline : :class:`~sklearn_hardness.models.MCDropoutPipeline`
        Steps ``"features"``, ``"scale"``, ``"clf"``.

    Examples
    --------
    >>> from sklearn_hardness.models import make_contact_geometry_pipeline
    >>> pipe = make_contact_geometry_pipeline(features=["log_depth", "area_depth_slope"])
    >>> [name for name, _ in pipe.steps]
    ['features', 'scale', 'clf']
    """
    clf = _table_head(head, classifier_params)
    geometry = ContactGeometryFeatures(features=features, max_side=max_side, roi=roi)
    if with_profile:
        step = FeatureUnion([("geometry", geometry),
                             ("profile", ContactProfileFeatures(max_side=max_side, roi=roi))])
    else:
        step = geometry
    return MCDropoutPipeline([("features", step), ("scale", StandardScaler()), ("clf", clf)])


def make_imprint_texture_pipeline(*, head="logistic", descriptors="all", moments=(0.5, 1.0), max_side=160, roi=None,
                                  **classifier_params):
    """Videos -> :class:`~sklearn_hardness.features.ImprintTextureFeatures` -> scaler -> classifier.

    The texture of the imprint (local binary patterns, co-occurrence,
    Gabor energies, power spectrum and colour of the change to the
    pre-contact frames) at half rise and at the peak: the material an
    everyday object is made of, which its hardness goes with.

    Parameters
    ----------
    head : {"logistic", "nn"}, default="logistic"
        ``"logistic"``: balanced :class:`~sklearn_hardness.models.LaplaceLogisticRegression`
        (``predict_proba_samples`` from its Laplace posterior), with
        ``C=0.1`` unless given (156 features for a few hundred presses);
        ``"nn"``: :class:`~sklearn_hardness.models.ContactProfileNNClassifier`
        (an MLP with MC dropout). Either way the pipeline has
        ``predict_proba_samples`` and can drive active sampling.
    descriptors : "all" or sequence of str, default="all"
        ``descriptors`` of :class:`~sklearn_hardness.features.ImprintTextureFeatures`.
    moments : sequence of float in (0, 1], default=(0.5, 1.0)
        ``moments`` of :class:`~sklearn_hardness.features.ImprintTextureFeatures`.
    max_side : int, default=160
        ``max_side`` of the feature transformer.
    roi : tuple (top, bottom, left, right) or None, default=None
        ``roi`` of the feature transformer.
    **classifier_params
        Passed to the head; ``class_weight`` defaults to ``"balanced"``
        (and the logistic head's ``max_iter`` to 2000).

    Returns
    -------
    pipeline : :class:`~sklearn_hardness.models.MCDropoutPipeline`
        Steps ``"features"``, ``"scale"``, ``"clf"``.

    See Also
    --------
    make_contact_geometry_pipeline : The contact's shape at the same moments.

    Examples
    --------
    >>> from sklearn_hardness.models import make_imprint_texture_pipeline
    >>> pipe = make_imprint_texture_pipeline(descriptors=["lbp", "spectrum"], moments=[1.0])
    >>> [name for name, _ in pipe.steps], pipe.named_steps["clf"].C
    (['features', 'scale', 'clf'], 0.1)
    """
    if head == "logistic":
        classifier_params = {"C": 0.1, **classifier_params}  # many features for few presses: a firm penalty
    clf = _table_head(head, classifier_params)
    texture = ImprintTextureFeatures(descriptors=descriptors, moments=moments, max_side=max_side, roi=roi)
    return MCDropoutPipeline([("features", texture), ("scale", StandardScaler()), ("clf", clf)])
