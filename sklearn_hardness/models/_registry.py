"""The named pipelines: one table of name -> builder, what it reads and what it gives.

Every part of the library that builds a pipeline by name goes through this
table, by the public names of :mod:`sklearn_hardness.models` (its one door):
:func:`~sklearn_hardness.models.make_named_pipeline`,
:func:`~sklearn_hardness.models.pipeline_names` and
:func:`~sklearn_hardness.models.pipeline_info`, for users,
:func:`~sklearn_hardness.model_selection.evaluate_pipelines`, the paper's
experiments (``reproduce``) and the command line, which builds its ``--help``
from it. A name is one model everywhere; two variants of a model are two names.

The builders are named by module and function, imported only when a pipeline is
built, so that this module needs nothing beyond the standard library
(``sklearn_hardness.models`` imports its nets only when they are asked for: the
command line's ``--help`` and ``import sklearn_hardness.model_selection`` stay
fast).
"""

from __future__ import annotations

import importlib
from dataclasses import dataclass, field

#: The ContactProfileFeatures of ``"contact_profile_3"``: the video's readings of the depth, the loading
#: time and the size of the contact (the quantities of the simulator's ideal reader of the gel).
CONTACT_PROFILE_3_FEATURES = ("log_peak_change", "log_loading_time", "log_contact_spread")

_PIPELINES = "sklearn_hardness.models._pipelines"
_PEAK_CHANGE = "sklearn_hardness.models._peak_change"


@dataclass(frozen=True)
class PipelineInfo:
    """What a named pipeline reads and gives (:func:`sklearn_hardness.models.pipeline_info`).

    Attributes
    ----------
    name : str
        The pipeline's name.
    input : {"video", "force_position"}
        ``"video"``: a sequence of press videos; ``"force_position"``: each
        press's force and sensor position per frame, shape ``(T, 2)``.
    samples : bool
        Whether the pipeline has ``predict_proba_samples`` (so it can drive
        active sampling).
    random : bool
        Whether fitting it is random (a net's weights, shuffling, dropout), so
        that ``random_state`` seeds it; pipelines with nothing random ignore it.
    summary : str
        One line on what the pipeline is.
    default : bool
        Whether :func:`~sklearn_hardness.model_selection.evaluate_pipelines`
        and ``sklearn-hardness evaluate`` run it by default (beside the
        baseline; ``"loading_compliance"`` too where every press has force
        and position).
    builder : str
        The name of its factory in :mod:`sklearn_hardness.models` (e.g.
        ``"make_convlstm_pipeline"``), whose parameters
        :func:`make_named_pipeline` passes on.
    """

    name: str
    input: str
    samples: bool
    random: bool
    summary: str
    default: bool = False
    builder: str = ""


@dataclass(frozen=True)
class _Entry:
    info: PipelineInfo
    module: str
    function: str
    fixed: dict = field(default_factory=dict)  # the builder's arguments that make the name's model


def _entry(name, module, function, fixed=None, *, input="video", samples=True, random=True, summary):
    default = name in _DEFAULTS
    return name, _Entry(PipelineInfo(name, input, samples, random, summary, default, function), module, function,
                        dict(fixed or {}))


#: What ``evaluate`` runs by default (beside the baseline; and ``"loading_compliance"`` where every
#: press has force and position): the pipeline chosen for real hand presses of new objects
#: (studies/pages/anchor_split.md, studies/pages/real_development_objects.md) and the contact
#: profile, cheap, with posterior samples. The ConvLSTMs left the defaults: on the development
#: objects they took 96% of evaluate's time and scored below the one number.
_DEFAULTS = ("contact_geometry", "contact_profile")


#: Name -> entry, in the order the names are listed.
_REGISTRY = dict([
    _entry("peak_change", _PEAK_CHANGE, "make_peak_change_baseline",
           samples=False, random=False,
           summary="the one-number baseline: peak change to the first frame + balanced logistic regression"),
    _entry("contact_geometry", _PIPELINES, "make_contact_geometry_pipeline", {"head": "logistic"}, random=False,
           summary="contact geometry from the gel's shading (twelve scale-free features) + logistic regression "
                   "(Laplace posterior samples)"),
    _entry("contact_profile", _PIPELINES, "make_contact_profile_pipeline", {"head": "logistic"}, random=False,
           summary="contact-profile features of the whole video + logistic regression (Laplace posterior samples)"),
    _entry("contact_profile_3", _PIPELINES, "make_contact_profile_pipeline",
           {"head": "logistic", "features": CONTACT_PROFILE_3_FEATURES}, random=False,
           summary="contact_profile with three features: log_peak_change, log_loading_time, log_contact_spread"),
    _entry("imprint_texture", _PIPELINES, "make_imprint_texture_pipeline", {"head": "logistic"}, random=False,
           summary="texture of the imprint at half rise and peak (local binary patterns, co-occurrence, Gabor, "
                   "spectrum, colour) + logistic regression (Laplace posterior samples)"),
    _entry("contact_profile_nn", _PIPELINES, "make_contact_profile_pipeline", {"head": "nn"},
           summary="contact-profile features of the whole video + an MC-dropout MLP"),
    _entry("convlstm", _PIPELINES, "make_convlstm_pipeline", {"intensity_channels": False},
           summary="the paper's ConvLSTM on the selected contact frames alone"),
    _entry("convlstm_intensity", _PIPELINES, "make_convlstm_pipeline", {"intensity_channels": True},
           summary="the ConvLSTM on the selected frames + intensity channels (for objects not seen in training)"),
    _entry("ofnn", _PIPELINES, "make_ofnn_pipeline", {"flow_output": "tracks"},
           summary="the paper's OFNN: flattened Lucas-Kanade corner tracks + an MC-dropout MLP"),
    _entry("ofnn_quantiles", _PIPELINES, "make_ofnn_pipeline", {"flow_output": "magnitude_quantiles"},
           summary="OFNN on quantiles of the corners' displacement magnitudes + an MC-dropout MLP"),
    _entry("dinov2nn", _PIPELINES, "make_dinov2nn_pipeline",
           summary="the paper's DINOv2NN: frozen DINOv2 features of the selected frames + an MC-dropout MLP"),
    _entry("imprint_cnn", _PIPELINES, "make_imprint_cnn_pipeline",
           summary="a small CNN trained from scratch, with augmentation, on each selected frame; "
                   "frame probabilities averaged per press"),
    _entry("loading_compliance", _PIPELINES, "make_loading_compliance_pipeline", input="force_position",
           random=False,
           summary="each press's force and position (no video): Hertz compliance + logistic regression"),
])

#: Every name, in the table's order.
PIPELINE_NAMES = tuple(_REGISTRY)


def _check_name(name):
    if not isinstance(name, str) or name not in _REGISTRY:
        raise ValueError(f"unknown pipeline name {name!r}; the names are {list(PIPELINE_NAMES)}.")
    return _REGISTRY[name]


def pipeline_names(input=None):
    """The names of the ready-made pipelines.

    Parameters
    ----------
    input : {"video", "force_position"} or None, default=None
        Only the pipelines that read this input; None: all.

    Returns
    -------
    names : tuple of str

    Examples
    --------
    >>> from sklearn_hardness.models import pipeline_names
    >>> pipeline_names(input="force_position")
    ('loading_compliance',)
    """
    if input not in (None, "video", "force_position"):
        raise ValueError(f"input must be 'video', 'force_position' or None, got {input!r}.")
    return tuple(name for name, entry in _REGISTRY.items() if input is None or entry.info.input == input)


def pipeline_info(name):
    """What the named pipeline reads and gives.

    Parameters
    ----------
    name : str
        One of :func:`pipeline_names`.

    Returns
    -------
    info : PipelineInfo
        A frozen record with ``name``, ``input`` (``"video"`` or
        ``"force_position"``), ``samples`` (whether it has
        ``predict_proba_samples``), ``random`` (whether ``random_state``
        seeds it), ``summary``, ``default`` (whether ``evaluate`` runs it by
        default) and ``builder`` (the name of its factory).

    Examples
    --------
    >>> from sklearn_hardness.models import pipeline_info
    >>> info = pipeline_info("convlstm")
    >>> info.input, info.samples, info.random, info.builder
    ('video', True, True, 'make_convlstm_pipeline')
    """
    return _check_name(name).info


def builder(name):
    """The builder function of a named pipeline and the arguments that make the name's model."""
    entry = _check_name(name)
    return getattr(importlib.import_module(entry.module), entry.function), dict(entry.fixed)


def make_named_pipeline(name, *, random_state=None, memory=None, **params):
    """A fresh, unfitted pipeline known by name.

    Parameters
    ----------
    name : str
        One of :func:`pipeline_names`.
    random_state : int, RandomState instance or None, default=None
        Seeds the nets' initial weights, shuffling and dropout. Ignored by the
        pipelines with nothing random to seed (``pipeline_info(name).random``
        is False).
    memory : None, str or object with the joblib.Memory interface, default=None
        Cache the rows of each press: every per-press step of the pipeline
        (those marked by :class:`~sklearn_hardness.utils.PerPressTransformerMixin`:
        frame selection, optical flow, DINOv2, the contact profile and
        geometry, texture, the peak change, a robot's loading figures;
        nested ones too) gets it as its ``memory``, so that the folds of any
        :func:`~sklearn.model_selection.cross_val_score`, a grid search or a
        later run that meet a press again read its rows instead of reading
        the video and computing them again. A press is keyed by the step's
        parameters, the code that computes rows and the press itself (a
        video of a lazy sequence by its file or seed, without decoding it;
        a video in memory by a hash of its frames). Validated as
        :func:`sklearn.utils.validation.check_memory` validates a
        :class:`~sklearn.pipeline.Pipeline`'s ``memory``; the
        :class:`~sklearn.pipeline.Pipeline`'s own ``memory`` stays None.
        What an entry costs on disk: each step's ``memory`` parameter says
        (under 1 kB for a row of features; the selected frames of the nets'
        pipelines 12 kB a press at ``frame_size=(18, 24)``).
    **params
        Passed to the pipeline's builder (its ``make_*_pipeline`` factory),
        e.g. ``roi=`` for the video pipelines, ``max_epochs=`` for a net. The
        arguments that make the name's model (``intensity_channels`` of
        ``"convlstm"``, ``flow_output`` of ``"ofnn"``, ...) are fixed: another
        variant is another name.

    Returns
    -------
    estimator : Pipeline

    Raises
    ------
    ValueError
        An unknown name (the message lists the names).
    TypeError
        A parameter fixed by the name.

    Examples
    --------
    >>> from sklearn_hardness.models import make_named_pipeline
    >>> pipe = make_named_pipeline("convlstm_intensity", random_state=0)
    >>> [step for step, _ in pipe.steps]
    ['frames', 'scale', 'intensity', 'clf']

    With a memory, the folds of a second cross-validation (other folds,
    another grid) read every press's features from it:

    >>> import tempfile
    >>> pipe = make_named_pipeline("contact_geometry", memory=tempfile.mkdtemp())
    >>> pipe.named_steps["features"].memory is not None
    True
    """
    function, fixed = builder(name)
    clash = sorted(set(params) & set(fixed))
    if clash:
        others = [n for n, e in _REGISTRY.items() if e.function == _REGISTRY[name].function and n != name]
        raise TypeError(f"{clash} are fixed by the name {name!r} ({fixed}); the other variants are other names "
                        f"({others}), or call {function.__name__} yourself.")
    if random_state is not None and _REGISTRY[name].info.random:
        params["random_state"] = random_state
    pipe = function(**fixed, **params)
    if memory is not None:
        _cache_per_press(pipe, memory)
    return pipe


def _cache_per_press(pipe, memory):
    """Give ``memory`` to every per-press step of ``pipe``, nested ones too."""
    from sklearn.utils.validation import check_memory

    from ..utils._per_press import PerPressTransformerMixin

    check_memory(memory)  # the error a step would raise at fit, now
    for path, step in pipe.get_params(deep=True).items():
        if isinstance(step, PerPressTransformerMixin):
            pipe.set_params(**{f"{path}__memory": memory})
