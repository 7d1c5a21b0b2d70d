"""The experiments' named models, built from the registry of named pipelines.

A name means the model :func:`sklearn_hardness.models.make_named_pipeline`
builds under it; the experiments add the
run's settings, each a documented configuration key (:func:`~._config.get_config`):
``class_weight`` (None, the paper's unweighted loss, by default), the frames'
``n_between``, ``frame_size``, ``color`` and ``crop_contact``, ``dinov2_model``,
and the classifier's training settings (``dropout``, ``lr``, epochs, ``device``,
...). Each run's classifier carries the run's seed.
The experiments take the pipeline apart: its ``"frames"`` step
(contact-frame selection) and its frozen ``"features"`` step run once per
dataset (:mod:`._data` caches them), and its ``"clf"`` step is the net each
run trains.
"""

from __future__ import annotations

import inspect

import numpy as np
from sklearn.base import BaseEstimator, clone
from sklearn.pipeline import Pipeline

from .. import models
from ..features import (
    ContactGeometryFeatures,
    ContactProfileFeatures,
    DINOv2Features,
    LoadingCompliance,
    OpticalFlowFeatures,
)
from ..models import make_named_pipeline, pipeline_info
from ..utils._random import set_random_states
from ._callbacks import EarlyStoppingAfterFirstFit
from ._names import EXPERIMENT_MODELS

MODEL_NAMES = EXPERIMENT_MODELS

#: The builders' arguments that the configuration sets (builder argument -> configuration key),
#: where a builder takes them.
_CONFIG_ARGUMENTS = {"n_between": "n_between", "frame_size": "frame_size", "model": "dinov2_model"}


def input_name(model):
    """The named model whose input a model gets: its own if named, the ConvLSTM's for any estimator."""
    return model if isinstance(model, str) and model in EXPERIMENT_MODELS else "convlstm"


def _builder_parameters(name):
    return inspect.signature(getattr(models, pipeline_info(name).builder)).parameters


def selects_frames(name):
    """Whether the named model's pipeline starts with contact-frame selection (its builder takes ``n_between``)."""
    return "n_between" in _builder_parameters(name)


def default_frame_size(model):
    """The frame size of the model's builder (None where it selects no frames)."""
    parameter = _builder_parameters(input_name(model)).get("frame_size")
    return None if parameter is None else tuple(parameter.default)


def model_pipeline(name, cfg, random_state=None, **classifier_params):
    """The registry's pipeline of a named model with ``cfg``'s settings of the run.

    ``classifier_params`` go to the builder (its classifier), after ``cfg``'s
    ``class_weight``. ``random_state`` seeds the classifier, also where its
    fit has nothing random (a logistic regression): every run's classifier
    carries its seed.
    """
    parameters = _builder_parameters(name)
    params = {"class_weight": cfg.get("class_weight"), **classifier_params}
    for argument, key in _CONFIG_ARGUMENTS.items():
        if argument in parameters and cfg.get(key) is not None:
            value = cfg[key]
            params[argument] = (tuple(int(s) for s in value) if argument == "frame_size"
                                else int(value) if argument == "n_between" else value)
    pipe = make_named_pipeline(name, random_state=random_state, **params)
    if random_state is not None and not pipeline_info(name).random:
        pipe.set_params(clf__random_state=random_state)
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
    transformer a user's pipeline of the model fits (the frames' one global
    scale for the ConvLSTM, a ``StandardScaler`` for the contact profile; for the
    loading compliance its median imputer and ``StandardScaler``, the imputer
    filling the presses whose loading phase was too short to fit). The
    experiments fit it on the training presses a run may see (see
    :func:`~._run._initial_state`); ``cfg["input_scale"] = None`` leaves the
    ConvLSTM's frames raw. Estimators passed by the user scale their own input.
    """
    if not isinstance(model, str):
        return None
    pipe = model_pipeline(model, cfg)
    if "impute" in pipe.named_steps:
        return clone(Pipeline([(name, pipe.named_steps[name]) for name in ("impute", "scale")]))
    step = pipe.named_steps.get("scale")
    if step is None or ("frames" in pipe.named_steps and cfg.get("input_scale") is None):
        return None  # the frame pipelines' scale is the ConvLSTM's FrameScaler: input_scale=None keeps frames raw
    return clone(step)


def feature_params(cfg, model):
    """The frozen feature step of a named model as the cache describes it (None: the frames are the input)."""
    if not isinstance(model, str):
        return None
    step = model_pipeline(model, cfg).named_steps.get("features")
    if isinstance(step, OpticalFlowFeatures):
        # the cache computes the transformer's default output, the flattened tracks of "ofnn"
        return {"kind": "optical_flow", "n_features": int(step.n_features)}
    if isinstance(step, DINOv2Features):
        return {"kind": "dinov2", "model": step.model}
    if isinstance(step, ContactProfileFeatures):
        params = {"kind": "contact_profile", "max_side": int(step.max_side)}
        if step.features != "all":  # the key of all twelve stays that of the inputs cached before features=
            params["features"] = list(step.features)
        return params
    if isinstance(step, ContactGeometryFeatures):
        return {"kind": "contact_geometry", "max_side": int(step.max_side),
                "features": step.features if isinstance(step.features, str) else list(step.features)}
    if isinstance(step, LoadingCompliance):
        return {"kind": "loading_compliance", "features": list(step.features), "onset": float(step.onset),
                "drive_compliance": float(step.drive_compliance)}
    return None


def _net_parameters(name):
    return model_pipeline(name, {}).named_steps["clf"].get_params(deep=False)


def make_estimator(model, cfg, seed, n_classes, dropout=None):
    """A fresh classifier for one run: a named model's last step, or a seeded clone of an estimator."""
    dropout = cfg["dropout"] if dropout is None else dropout
    if isinstance(model, str) and not pipeline_info(model).random:
        # a logistic regression, refitted on all its presses at each iteration: no epochs, learning
        # rate, dropout or batches; its samples come from the Laplace posterior
        return model_pipeline(model, cfg, random_state=int(seed)).named_steps["clf"]
    if isinstance(model, str):
        kwargs = dict(dropout=float(dropout), lr=cfg["lr"], random_state=int(seed),
                      classes=np.arange(n_classes), max_epochs=int(cfg["initial_epochs"]),
                      device=cfg.get("device", "cpu"))
        if cfg["batch_size"] is not None:
            kwargs["batch_size"] = int(cfg["batch_size"])
        if "dropout_placement" in _net_parameters(model):  # the ConvLSTM's
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
