"""The experiments' named models, built by the public ``make_*_pipeline`` factories.

One place decides what a model named ``"convlstm"``, ``"ofnn"``, ``"dinov2nn"``,
``"contact_profile_nn"``, ``"contact_profile"``, ``"contact_profile_3"`` or ``"loading_compliance"``
is: its factory in :mod:`sklearn_hardness.models`.
The experiments take the factory's pipeline apart: its ``"frames"`` step
(contact-frame selection) and its frozen ``"features"`` step run once per
dataset (:mod:`._data` caches them), and its ``"clf"`` step is the net each
run trains. What the experiments choose differently from a user's default is
written here, with the reason: they reproduce the paper (:data:`PAPER_CHOICES`).
"""

from __future__ import annotations

import inspect

import numpy as np
from sklearn.base import BaseEstimator, clone
from sklearn.pipeline import Pipeline

from .._experiment_names import (CONTACT_PROFILE_3_FEATURES, CONTACT_PROFILE_MODELS, FORCE_POSITION_MODELS,
                                 LOGISTIC_MODELS, MODEL_NAMES)
from .. import models
from ..models import EarlyStoppingAfterFirstFit
from ..utils._random import set_random_states

#: Factory of each named model.
FACTORIES = {
    "convlstm": models.make_convlstm_pipeline,
    "ofnn": models.make_ofnn_pipeline,
    "dinov2nn": models.make_dinov2nn_pipeline,
    "contact_profile_nn": models.make_contact_profile_pipeline,
    "contact_profile": models.make_contact_profile_pipeline,
    "contact_profile_3": models.make_contact_profile_pipeline,
    "loading_compliance": models.make_loading_compliance_pipeline,
}

#: What a named model is beyond its factory's defaults (before the experiments' choices below).
NAMED_CHOICES = {"contact_profile_3": {"features": CONTACT_PROFILE_3_FEATURES}}

#: Where the experiments depart from the factories' defaults (which are for a user's own,
#: unseen objects): the paper's inputs and its unweighted loss. The ConvLSTM gets the frames
#: alone and OFNN the flattened corner tracks, as in the paper; the nets weigh every class
#: alike (its classes have equal counts). The frame sizes are the factories': 12x16 grey
#: frames for the ConvLSTM (on the front of time against error of
#: ``benchmarks/bench_time_error.py``: half the time of 18x24 per run, no higher error),
#: 120x160 raw (not differenced) frames for optical flow, which tracks the gel's markers
#: (on simulated silicone5, 5 train presses per object, 5 seeds, OFNN reached 33.8% +- 2.9%
#: on raw frames and 21.5% +- 1.1%, chance, on differences to the first frame), 112x150 RGB
#: for DINOv2, and none for the contact profile, whose features read the whole video.
PAPER_CHOICES = {
    "convlstm": {"intensity_channels": False, "class_weight": None},
    "ofnn": {"flow_output": "tracks", "class_weight": None},
    "dinov2nn": {},
    "contact_profile_nn": {"head": "nn", "class_weight": None},
    "contact_profile": {"head": "logistic", "class_weight": None},
    "contact_profile_3": {"head": "logistic", "class_weight": None},
    "loading_compliance": {"class_weight": None},
}


def input_name(model):
    """The named model whose input a model gets: its own if named, the ConvLSTM's for any estimator."""
    return model if isinstance(model, str) and model in FACTORIES else "convlstm"


def default_frame_size(model):
    """The frame size of the model's factory (None where it selects no frames)."""
    parameter = inspect.signature(FACTORIES[input_name(model)]).parameters.get("frame_size")
    return None if parameter is None else tuple(parameter.default)


def model_pipeline(name, cfg, **classifier_params):
    """The factory's pipeline of a named model, with the experiments' choices and ``cfg``'s input settings."""
    kwargs = {**NAMED_CHOICES.get(name, {}), **PAPER_CHOICES[name], **classifier_params}
    if name in CONTACT_PROFILE_MODELS:
        kwargs["max_side"] = 80
    elif name not in FORCE_POSITION_MODELS:
        kwargs["n_between"] = int(cfg["n_between"])
        if cfg.get("frame_size") is not None:
            kwargs["frame_size"] = tuple(int(s) for s in cfg["frame_size"])
    if name == "dinov2nn":
        kwargs["model"] = cfg["dinov2_model"]
    pipe = FACTORIES[name](**kwargs)
    if "frames" in pipe.named_steps:
        if cfg.get("color") is not None:
            pipe.set_params(frames__color=cfg["color"])
        if cfg.get("crop_contact") is not None:
            pipe.set_params(frames__crop_contact=float(cfg["crop_contact"]))
    return pipe


def frame_params(cfg, model):
    """ContactFrameSelector's parameters for the model's input, or None where it reads whole videos.

    Any estimator gets the ConvLSTM's frames. The keys are those of the cache of
    earlier inputs (``crop_contact`` only when set), so cached frames stay valid.
    """
    pipe = model_pipeline(input_name(model), cfg)
    if "frames" not in pipe.named_steps:
        return None
    selector = pipe.named_steps["frames"]
    params = {
        "n_between": int(selector.n_between),
        # the cache's key keeps the selector's former parameter name, so cached frames stay valid
        "output_size": tuple(int(s) for s in selector.frame_size),
        "color": selector.color,
        "subtract_first": bool(selector.subtract_first),
    }
    if selector.crop_contact is not None:
        params["crop_contact"] = float(selector.crop_contact)
    return params


def input_scaler(model, cfg):
    """The factory's ``"scale"`` step of a named model, unfitted; None where the model's inputs are not scaled.

    The one place the experiments' input scaling comes from: the same
    transformer a user's pipeline of the model fits (:class:`FrameScaler` for
    the ConvLSTM, a ``StandardScaler`` for the contact profile; for the
    loading compliance its median imputer and ``StandardScaler``, the imputer
    filling the presses whose loading phase was too short to fit). The
    experiments fit it on the training presses a run may see (see
    :func:`~._run._initial_state`); ``cfg["input_scale"] = None`` leaves the
    ConvLSTM's frames raw. Estimators passed by the user scale their own input.
    """
    if not isinstance(model, str) or (model == "convlstm" and cfg.get("input_scale") is None):
        return None
    pipe = model_pipeline(model, cfg)
    if "impute" in pipe.named_steps:
        return clone(Pipeline([(name, pipe.named_steps[name]) for name in ("impute", "scale")]))
    step = pipe.named_steps.get("scale")
    return None if step is None else clone(step)


def feature_params(cfg, model):
    """The frozen feature step of a named model as the cache describes it (None: the frames are the input)."""
    if not isinstance(model, str):
        return None
    step = model_pipeline(model, cfg).named_steps.get("features")
    if model == "ofnn":
        return {"kind": "optical_flow", "n_features": int(step.n_features)}
    if model == "dinov2nn":
        return {"kind": "dinov2", "model": step.model}
    if model in CONTACT_PROFILE_MODELS:
        params = {"kind": "contact_profile", "max_side": int(step.max_side)}
        if step.features != "all":  # the key of all twelve stays that of the inputs cached before features=
            params["features"] = list(step.features)
        return params
    if model in FORCE_POSITION_MODELS:
        return {"kind": "loading_compliance", "features": list(step.features), "onset": float(step.onset),
                "drive_compliance": float(step.drive_compliance)}
    return None


def make_estimator(model, cfg, seed, n_classes, dropout=None):
    """A fresh classifier for one run: a named model's net from its factory, or a seeded clone."""
    dropout = cfg["dropout"] if dropout is None else dropout
    if model in LOGISTIC_MODELS:
        # a logistic regression, refitted on all its presses at each iteration: no epochs, learning
        # rate, dropout or batches; its samples come from the Laplace posterior
        return model_pipeline(model, cfg, random_state=int(seed)).named_steps["clf"]
    if isinstance(model, str):
        kwargs = dict(dropout=float(dropout), lr=cfg["lr"], random_state=int(seed),
                      classes=np.arange(n_classes), max_epochs=int(cfg["initial_epochs"]),
                      device=cfg.get("device", "cpu"))
        if cfg["batch_size"] is not None:
            kwargs["batch_size"] = int(cfg["batch_size"])
        if model == "convlstm":
            kwargs["dropout_placement"] = cfg.get("dropout_placement", "head")
        if cfg.get("early_stopping") is not None:
            kwargs["callbacks"] = [("early_stopping", EarlyStoppingAfterFirstFit(
                monitor="train_loss", patience=int(cfg["early_stopping"]), threshold=1e-3))]
        net = model_pipeline(model, cfg, **kwargs).named_steps["clf"]
        if cfg.get("n_ensemble", 0):
            return models.EnsembleClassifier(net, n_estimators=int(cfg["n_ensemble"]), random_state=int(seed))
        return net
    if not isinstance(model, BaseEstimator):
        raise TypeError(
            f"model must be one of {list(MODEL_NAMES)} or a scikit-learn estimator, got {type(model).__name__}."
        )
    est = set_random_states(clone(model), int(seed))
    if dropout is not None and cfg.get("_override_dropout"):
        keys = [k for k in est.get_params(deep=True) if k == "dropout" or k.endswith("__dropout")]
        if keys:
            est.set_params(**{k: float(dropout) for k in keys})
    return est


def describe_model(model):
    """A stable text description of a model for the config hash."""
    if isinstance(model, str):
        return model
    if not isinstance(model, BaseEstimator):
        raise TypeError(
            f"model must be one of {list(MODEL_NAMES)} or a scikit-learn estimator, got {type(model).__name__}."
        )
    params = model.get_params(deep=False)
    return f"{type(model).__module__}.{type(model).__qualname__}({sorted((k, repr(v)) for k, v in params.items())})"
