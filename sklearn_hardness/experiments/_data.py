"""Inputs of the experiments: the per-press steps, computed once per dataset.

Contact-frame selection and the frozen feature extractors (optical flow,
DINOv2, the contact profile and geometry, a robot's loading figures) do not
change between runs, strategies or seeds, so every experiment computes them
once for all presses of a dataset; each run then only indexes into the
arrays. They are per-press steps
(:class:`~sklearn_hardness.utils.PerPressTransformerMixin`): with ``memory``
(a folder or :class:`joblib.Memory`; by default :func:`default_cache_dir`)
each press's rows are cached on disk, as every per-press step caches them
(one cache format, one key: the step's parameters, the code that computes
rows, the press), between calls and processes, and shared with a user's own
pipelines given the same ``memory``.
"""

from __future__ import annotations

import os
import warnings

import joblib
import numpy as np
from sklearn.utils import Bunch

from ..datasets import force_and_position, load_press_videos, make_presses
from ..features import ContactGeometryFeatures, ContactProfileFeatures, DINOv2Features, OpticalFlowFeatures
from ..models import make_named_pipeline
from ..preprocessing import ContactFrameSelector
from ..utils._per_press import default_cache_dir
from ..utils._progress import progress_bar
from ..utils._unreadable import raise_unreadable
from ..utils._validation import rename_videos
from ..utils._warnings import external_stacklevel
from ._config import MODEL_NAMES
from ._models import feature_params as _feature_params
from ._models import frame_params as _frame_params

__all__ = ["load_dataset", "prepare_inputs"]

_SIM_PRESETS = ("silicone5", "shore9", "everyday")


def _dataset_spec(dataset, cfg):
    """A hashable description of the dataset (None if it cannot be described)."""
    if isinstance(dataset, str) and dataset in _SIM_PRESETS:
        return ("make_presses", dataset, tuple(cfg["image_size"]), int(cfg["data_seed"]))
    if isinstance(dataset, (str, os.PathLike)):
        path = os.path.abspath(os.fspath(dataset))
        if not os.path.isfile(path):
            raise ValueError(
                f"dataset {os.fspath(dataset)!r} is neither a simulator preset "
                f"({', '.join(_SIM_PRESETS)}) nor an existing manifest CSV file."
            )
        st = os.stat(path)
        return ("manifest", path, st.st_mtime_ns, st.st_size)
    return None


def load_dataset(dataset, cfg):
    """The dataset an experiment runs on, as a Bunch.

    Parameters
    ----------
    dataset : str, path-like or Bunch
        A simulator preset name (``"silicone5"``, ``"shore9"``,
        ``"everyday"``, simulated with ``cfg["image_size"]`` and
        ``cfg["data_seed"]``), the path of a manifest CSV
        (:func:`~sklearn_hardness.datasets.load_press_videos`) or a Bunch
        with at least ``videos`` and ``target``.
    cfg : dict
        A configuration (:func:`get_config`).

    Returns
    -------
    data : Bunch
        ``videos`` (loaded lazily), ``target``, ``hardness``, ...

    Examples
    --------
    >>> from sklearn_hardness.experiments import get_config, load_dataset
    >>> data = load_dataset("silicone5", get_config("silicone5", image_size=(32, 40)))
    >>> len(data.videos), data.target_names.tolist()
    (455, ['0.44', '0.68', '0.79', '1.02', '1.13'])
    """
    spec = _dataset_spec(dataset, cfg)
    if spec is not None and spec[0] == "make_presses":
        return make_presses(spec[1], image_size=spec[2], random_state=spec[3])
    if spec is not None:
        return load_press_videos(spec[1])
    if not (hasattr(dataset, "videos") or hasattr(dataset, "get")) :
        raise TypeError(
            "dataset must be a preset name ('silicone5', 'shore9', 'everyday'), a manifest CSV path or a "
            f"Bunch with 'videos' and 'target', got {type(dataset).__name__}."
        )
    for field in ("videos", "target"):
        if field not in dataset:
            raise ValueError(f"the dataset Bunch has no {field!r} field.")
    return dataset


def _select_frames(videos, frame_params, verbose, n_jobs=None, memory=None):
    params = dict(frame_params)
    params["frame_size"] = params.pop("output_size")  # the parameter's former name, in frame_params
    selector = ContactFrameSelector(on_no_contact="fallback", n_jobs=n_jobs, memory=memory, **params)
    n = len(videos)
    if n == 0:
        raise ValueError("the dataset has no videos.")
    chunk = 32
    out = []

    with warnings.catch_warnings():
        # no-contact fallbacks are reported once, below, not per chunk
        warnings.filterwarnings("ignore", message=".*contact.*")
        n_fallback = 0
        with progress_bar(total=n, desc="contact frames", unit="video", enabled=bool(verbose)) as bar:
            for start in range(0, n, chunk):
                idx = np.arange(start, min(n, start + chunk))
                part = videos[idx] if hasattr(videos, "shape") else [videos[i] for i in idx]
                try:
                    out.append(selector.fit_transform(part))  # one pass: frames and selection_
                except ValueError as exc:  # it names X[k] of the chunk: say which press of the dataset
                    keys = getattr(videos, "keys", None)  # a manifest's lazy videos: their files

                    def press(k):
                        i = start + k
                        path = keys[i] if keys is not None and isinstance(keys[i], (str, os.PathLike)) else None
                        return f"press {i}" + (f" ({path})" if path is not None else "")

                    raise ValueError(rename_videos(str(exc), press)) from exc
                n_fallback += int(np.sum(~np.asarray(selector.selection_.contact_found)))
                bar.update(len(idx))
    if n_fallback:
        warnings.warn(
            f"{n_fallback} of {n} videos never reached contact; their frames were chosen by "
            "ContactFrameSelector's fallback rule.",
            UserWarning,
            stacklevel=external_stacklevel(),
        )
    return np.concatenate(out, axis=0)


def _features(frames, feature_params, memory):
    if feature_params is None:
        return frames
    if feature_params["kind"] == "optical_flow":
        # one pass over every press: its warning (presses padded, tracks lost) comes once, with the counts
        return OpticalFlowFeatures(n_features=feature_params["n_features"], memory=memory).fit_transform(frames)

    return DINOv2Features(model=feature_params["model"], memory=memory).fit_transform(frames)


def _video_inputs(videos, frame_params, feature_params, verbose, n_jobs, memory):
    """One row per press from its video: the contact profile, or selected frames and their features."""
    if frame_params is None and feature_params["kind"] == "contact_geometry":  # whole videos too
        step = ContactGeometryFeatures(max_side=feature_params["max_side"], features=feature_params["features"],
                                       n_jobs=n_jobs, memory=memory)
        return step.fit_transform(videos).astype(np.float32)
    if frame_params is None:  # contact_profile(_nn, _3): features of the whole videos, no frame selection
        step = ContactProfileFeatures(max_side=feature_params["max_side"],
                                      features=feature_params.get("features", "all"), n_jobs=n_jobs, memory=memory)
        return step.fit_transform(videos).astype(np.float32)
    return _features(_select_frames(videos, frame_params, verbose, n_jobs, memory), feature_params, memory)


def _compute(data, frame_params, feature_params, verbose, n_jobs=None, memory=None):
    """The inputs ``X`` (one row per press) and labels ``y`` of ``data``, its presses' rows read from ``memory``."""
    if feature_params is not None and feature_params["kind"] == "loading_compliance":
        # each press's force and position, no video: the factory's features and log steps (stateless);
        # its imputer and scaler are fitted per run (experiments._models.input_scaler)
        steps = make_named_pipeline("loading_compliance", features=feature_params["features"],
                                    onset=feature_params["onset"],
                                    drive_compliance=feature_params["drive_compliance"], memory=memory)[:2]
        X = steps.fit_transform(force_and_position(data)).astype(np.float32)
    else:
        try:
            X = _video_inputs(data["videos"], frame_params, feature_params, verbose, n_jobs, memory)
        except (ValueError, TypeError, OSError) as exc:
            raise_unreadable(data["videos"], exc)  # every video that cannot be read, in one error
            raise
    y = np.asarray(data["target"])
    return X, y


def _meta(data_or_none, dataset, cfg, y):
    data = data_or_none
    n_classes = int(y.max()) + 1 if y.size else 0
    names = data.get("target_names") if data is not None else None
    hardness = data.get("hardness") if data is not None else None
    unit = data.get("hardness_unit") if data is not None else None
    if names is None:
        names = np.array([str(i) for i in range(n_classes)])
    if hardness is not None:
        hardness = np.asarray(hardness, dtype=float)
        if hardness.size == 0 or not np.all(np.isfinite(hardness)):
            hardness = None
    return np.asarray(names), hardness, unit


def _family_column(data):
    """The family of each press: a ``family`` field (``load_physiclear``) or manifest column, or None."""
    if data.get("family") is not None:
        return data.get("family")
    return (data.get("metadata") or {}).get("family")


def prepare_inputs(dataset, cfg, model, *, memory=None, verbose=1, n_jobs=None):
    """Selected frames (ConvLSTM, custom estimators) or frozen features for all presses.

    Parameters
    ----------
    dataset : str, path-like or Bunch
        See :func:`load_dataset`.
    cfg : dict
        The experiment configuration (:func:`get_config`).
    model : str or estimator
        A name in :data:`MODEL_NAMES` or an estimator (it gets the selected frames).
    memory : None, False, str or joblib.Memory, default=None
        Where each press's rows are cached (the per-press steps' ``memory``):
        a folder or :class:`joblib.Memory`, None for
        :func:`~sklearn_hardness.utils.default_cache_dir`, False for none.
    verbose : int, default=1
    n_jobs : int or None, default=None
        Threads that find the contact frames (``ContactFrameSelector``
        ``n_jobs``); not part of the cache key.

    Returns
    -------
    inputs : Bunch
        ``X`` (one row per press), ``y`` (class index), ``target_names``,
        ``hardness`` (per class, or None), ``hardness_unit``, ``n_classes``,
        ``object_id`` (the physical object of each press, or None),
        ``family`` (the whole object it is a part of, where the dataset says, or None).
    """
    if isinstance(model, str) and model not in MODEL_NAMES:
        raise ValueError(f"unknown model {model!r}; choose one of {list(MODEL_NAMES)} or pass an estimator.")
    spec = _dataset_spec(dataset, cfg)
    frame_params = _frame_params(cfg, model)
    feature_params = _feature_params(cfg, model)
    if memory is False:
        memory = None
    elif memory is None:
        memory = joblib.Memory(default_cache_dir(), verbose=0)
    elif isinstance(memory, os.PathLike):
        memory = os.fspath(memory)  # a folder; the steps take a str, as a Pipeline's memory
    data = load_dataset(dataset, cfg)  # a preset's or manifest's videos are lazy: nothing is read yet
    X, y = _compute(data, frame_params, feature_params, verbose, n_jobs, memory)
    if cfg.get("input_scale") not in (None, "std"):
        raise ValueError(f"input_scale must be 'std' or None, got {cfg.get('input_scale')!r}.")
    y = np.asarray(y)
    if y.ndim != 1 or y.size == 0 or not np.issubdtype(y.dtype, np.integer) or y.min() < 0:
        raise ValueError("the dataset's target must be a non-empty 1-D array of class indices 0 .. n_classes - 1.")
    names, hardness, unit = _meta(data, dataset, cfg, y)
    n_classes = max(len(names), int(y.max()) + 1)
    counts = np.bincount(y, minlength=n_classes)
    if np.any(counts == 0):
        missing = np.flatnonzero(counts == 0).tolist()
        raise ValueError(
            f"classes {missing} have no presses in the dataset; every reference object needs "
            "presses for the initial training set."
        )
    if hardness is not None and hardness.shape[0] != n_classes:
        raise ValueError(f"the dataset gives {hardness.shape[0]} hardness values for {n_classes} classes.")
    data_id = list(spec) if spec is not None else joblib.hash((X, y))
    object_id = None if data is None or data.get("object_id") is None else np.asarray(data.get("object_id"))
    if object_id is not None and object_id.shape != y.shape:
        raise ValueError(f"the dataset has {object_id.shape[0]} object ids for {y.shape[0]} presses.")
    family = None if object_id is None or _family_column(data) is None else np.asarray(_family_column(data))
    if family is not None and family.shape != y.shape:
        raise ValueError(f"the dataset has {family.shape[0]} families for {y.shape[0]} presses.")
    return Bunch(X=X, y=y, target_names=names, hardness=hardness, hardness_unit=unit,
                 n_classes=n_classes, model=model if isinstance(model, str) else "custom",
                 data_id=data_id, object_id=object_id, family=family)
