"""The paper's hyperparameters per dataset preset, and the config hash of a run.

Sec. III-C of the paper: ``s0 = s = 5`` presses, ``N = 5`` iterations,
dropout 0.2; on the robot data (our ``silicone5`` preset) the ConvLSTM is
trained ``e0 = 100`` epochs first and ``e = 50`` per iteration on at most
``M = 40`` reservoir samples, with two frames between the first and the last
contact frame; on Yuan's data (``shore9``) DINOv2NN with ``e0 = 50``,
``e = 25``, ``M = 80`` and one frame in between.
"""

from __future__ import annotations

import copy
import hashlib
import json
import numbers

import numpy as np

from ..models import pipeline_info
from ..utils._chance_threshold import chance_scaled_threshold
from ..utils._param_validation import FRAME_SIZE, Interval, StrOptions, validate_parameter_constraints
from ._models import MODEL_NAMES, default_frame_size, describe_model, selects_frames
from ._models import input_name as _input_name
from ._names import CONFIG_KEYS, QUICK_OVERRIDES

__all__ = ["PRESET_CONFIGS", "QUICK_OVERRIDES", "MODEL_NAMES", "get_config", "config_hash"]


def _selects_no_frames(model):
    """Whether ``model`` is a named model that selects no contact frames (no frame_size, color or crop_contact)."""
    return isinstance(model, str) and model in MODEL_NAMES and not selects_frames(model)


def _is_logistic(model):
    """Whether ``model`` is a named model with a logistic head (nothing random: no epochs, dropout, ensembles)."""
    return isinstance(model, str) and model in MODEL_NAMES and not pipeline_info(model).random

_COMMON = {
    "n_initial": 5,  # s0
    "n_per_query": 5,  # s
    "n_iterations": 5,  # N
    "n_test": 5,  # l, presses of the test object
    # presses per reference object held out of every run's pool and scored after
    # each iteration (accuracy on every class, not only the test object's); 0: none
    "n_holdout": 0,
    "n_samples": 50,  # n, MC-dropout passes per query
    # 0: uncertainty from MC dropout (the paper). k >= 2: from an ensemble of k differently
    # seeded nets (models.EnsembleClassifier); the strategies see one "pass" per member
    "n_ensemble": 0,
    "dropout": 0.2,
    # ConvLSTM only (ConvLSTMClassifier dropout_placement): "head", on the pooled features (ours);
    # "layers", after each ConvLSTM layer (the paper's); "channels", one mask per channel map
    "dropout_placement": "head",
    "lr": 1e-3,
    "batch_size": None,  # None: the model's default (8 ConvLSTM, 32 MLP heads)
    "frame_size": None,  # None: the model factory's (check_config fills it in)
    "color": None,
    # ConvLSTM input: frame differences are a small fraction of full scale and
    # the ConvLSTM barely trains on them; every run scales them with the
    # factory's FrameScaler fitted on its training presses (never the test
    # presses). None: raw.
    "input_scale": "std",
    "dinov2_model": "facebook/dinov2-small",
    "image_size": (240, 320),  # simulator frames (GelSight Mini)
    "data_seed": 0,  # simulator seed
    # torch device of the named models ("cpu", "cuda", "cuda:1", "auto"); frames are
    # prepared on the CPU either way
    "device": "cpu",
    # k: each training call after the initial one stops once the training loss has not
    # improved (by 0.1%) for k epochs (skorch EarlyStopping on train_loss); epochs_per_query
    # becomes an upper bound. The initial training runs in full (the convergence rule is about
    # it). None: every epoch of initial_epochs / epochs_per_query is trained (the paper's rule).
    # 5 is on the front of time against error (docs/user_guide/runtime.rst)
    "early_stopping": 5,
    # None: whole frames. f in (0, 1): each press cut to a window of f x the frame's height
    # and width centred on its contact before resizing to frame_size (ContactFrameSelector)
    "crop_contact": None,
    # the classifiers' class weights: None, the paper's unweighted loss (its classes have equal
    # counts); "balanced" is the pipelines' default for a user's own, imbalanced objects
    "class_weight": None,
}

#: Defaults per preset (Sec. III-C of the paper).
PRESET_CONFIGS = {
    "silicone5": dict(
        _COMMON,
        model="convlstm",
        # at the paper's 1e-3 fewer initial trainings converge (loss <= 1) than at 3e-3
        # (studies/scripts/convergence.py; ConvLSTMClassifier Notes); pass lr=1e-3 for the paper's
        lr=3e-3,
        n_between=2,
        initial_epochs=100,  # e0
        epochs_per_query=50,  # e
        max_reservoir=40,  # M
        # "auto": for the ConvLSTM the paper's loss <= 1 at 5 classes, ln(K) / ln(5) at K classes
        # (models.is_converged(threshold="chance"); resolve_convergence_threshold); None for the others
        convergence_threshold="auto",
        n_runs=10,  # seeds per test class: 5 x 10 = 50 runs per strategy
    ),
    "shore9": dict(
        _COMMON,
        model="dinov2nn",
        n_between=1,
        initial_epochs=50,
        epochs_per_query=25,
        max_reservoir=80,
        convergence_threshold="auto",  # no convergence issues reported for DINOv2NN; ConvLSTM: 1.365
        n_runs=5,  # 9 x 5 = 45 runs per strategy
    ),
}

_KNOWN_KEYS = set(PRESET_CONFIGS["silicone5"])

#: Configuration keys renamed before the first release, old name -> new name: an override by
#: the old name is an error that names the new one; :func:`config_hash` hashes the old name,
#: so results files written under it stay resumable.
RENAMED_KEYS = {"n_mc_samples": "n_samples"}


def get_config(preset="silicone5", *, quick=False, **overrides):
    """The experiment configuration of a preset, with overrides.

    Parameters
    ----------
    preset : {"silicone5", "shore9"}, default="silicone5"
        Which of the paper's setups to start from.
    quick : bool, default=False
        A first look in minutes: smaller images and frames, fewer epochs,
        MC passes and runs (listed by ``sklearn-hardness reproduce --help``).
    **overrides
        Any key of the configuration:

{keys}

    Returns
    -------
    config : dict
        A fresh dict; ``config["preset"]`` names the preset.

    Examples
    --------
    >>> from sklearn_hardness.experiments import get_config
    >>> cfg = get_config("silicone5")
    >>> cfg["model"], cfg["initial_epochs"], cfg["epochs_per_query"], cfg["max_reservoir"]
    ('convlstm', 100, 50, 40)
    """
    if not isinstance(preset, str) or preset not in PRESET_CONFIGS:
        raise ValueError(f"unknown preset {preset!r}; choose one of {sorted(PRESET_CONFIGS)}.")
    cfg = copy.deepcopy(PRESET_CONFIGS[preset])
    if quick:  # its frame size is the ConvLSTM's; models that select no frames keep None
        no_frames = _selects_no_frames(overrides.get("model"))
        cfg.update({k: v for k, v in QUICK_OVERRIDES.items() if not (k == "frame_size" and no_frames)})
    renamed = sorted(set(overrides) & set(RENAMED_KEYS))
    if renamed:
        raise ValueError("renamed configuration key(s): " + ", ".join(
            f"{old!r} is now {RENAMED_KEYS[old]!r}" for old in renamed) + "; use the new name.")
    unknown = sorted(set(overrides) - _KNOWN_KEYS)
    if unknown:
        raise ValueError(
            f"unknown configuration key(s) {unknown}; known keys are {sorted(_KNOWN_KEYS)}."
        )
    cfg.update(overrides)
    cfg["preset"] = preset
    return cfg


if get_config.__doc__:  # None under python -OO
    get_config.__doc__ = get_config.__doc__.replace("{keys}", "\n".join(
        f"        ``{key}``\n            {meaning}." for key, meaning in CONFIG_KEYS.items()))


def default_preset(dataset, preset):
    """The preset whose configuration an experiment on ``dataset`` starts from."""
    if preset is None:
        preset = dataset if isinstance(dataset, str) and dataset in ("silicone5", "shore9") else "silicone5"
    return preset


def run_config(dataset, preset, model, n_runs, quick, config):
    """The checked configuration of one model's runs (what they hash, with the data's id), and the model.

    ``quick``'s frame size depends on the model (frames or none), so a model
    given by name is passed to :func:`get_config`.
    """
    if n_runs is not None:
        config = dict(config, n_runs=n_runs)
    if isinstance(model, str):
        config = dict(config, model=model)
    cfg = get_config(default_preset(dataset, preset), quick=quick, **config)
    model = cfg["model"] if model is None else model
    cfg["model"] = describe_model(model)
    check_config(cfg)
    return cfg, model


def _ints_from(low):
    return [Interval(numbers.Integral, low, None, closed="left")]


#: What each configuration key may hold (scikit-learn's constraint language).
_CONFIG_CONSTRAINTS = {
    **{name: _ints_from(1) for name in ("n_initial", "n_per_query", "n_test", "n_samples",
                                        "initial_epochs", "epochs_per_query", "n_runs")},
    **{name: _ints_from(0) for name in ("n_iterations", "n_holdout", "n_between", "n_ensemble")},
    "input_scale": [StrOptions({"std"}), None],
    "max_reservoir": [*_ints_from(1), None],
    "dropout": [Interval(numbers.Real, 0.0, 1.0, closed="left")],
    "dropout_placement": [StrOptions({"head", "layers", "channels"})],
    "convergence_threshold": [StrOptions({"auto"}), Interval(numbers.Real, None, None, closed="neither"), None],
    "device": [str],
    "early_stopping": [*_ints_from(1), None],
    "crop_contact": [Interval(numbers.Real, 0.0, 1.0, closed="neither"), None],
    "frame_size": [None, FRAME_SIZE],
    "class_weight": [StrOptions({"balanced"}), dict, None],
}


def check_config(cfg):
    """Check a configuration before any run starts, and complete it.

    Parameters
    ----------
    cfg : dict
        A configuration (:func:`get_config`).

    Returns
    -------
    cfg : dict
        The same dict, with the model's frame size written out.

    Raises
    ------
    ValueError
        A value out of range or keys that do not go together.

    Examples
    --------
    >>> from sklearn_hardness.experiments import check_config, get_config
    >>> cfg = check_config(get_config("silicone5", n_iterations=3))
    >>> cfg["n_iterations"], cfg["model"]
    (3, 'convlstm')
    """
    validate_parameter_constraints(
        _CONFIG_CONSTRAINTS, {k: cfg[k] for k in _CONFIG_CONSTRAINTS}, caller_name="the experiment configuration"
    )
    if cfg["dropout_placement"] != "head" and cfg.get("model") != "convlstm":
        raise ValueError(
            f"dropout_placement={cfg['dropout_placement']!r} applies to the ConvLSTM only, but the model is "
            f"{cfg.get('model')!r}; leave it at 'head' or use model='convlstm'."
        )
    if _selects_no_frames(cfg.get("model")) and any(
            cfg.get(k) is not None for k in ("frame_size", "color", "crop_contact")):
        reads = ("ContactProfileFeatures read the whole video" if pipeline_info(cfg["model"]).input == "video"
                 else "it reads each press's force and position, not its frames")
        raise ValueError(
            f"frame_size, color and crop_contact select contact frames, which {cfg['model']} does not "
            f"use ({reads}); leave them at None."
        )
    if _is_logistic(cfg.get("model")) and cfg["n_ensemble"]:
        raise ValueError(
            f"n_ensemble applies to the nets; {cfg['model']}'s samples come from the Laplace posterior of "
            "its logistic regression. Leave n_ensemble at 0."
        )
    if cfg["n_ensemble"] == 1:
        raise ValueError("n_ensemble must be 0 (MC dropout) or at least 2 members, got 1.")
    if cfg["max_reservoir"] is not None and cfg["max_reservoir"] < cfg["n_per_query"]:
        raise ValueError(
            f"max_reservoir (M={cfg['max_reservoir']}) is smaller than the batch of "
            f"n_per_query={cfg['n_per_query']} new presses per iteration; the training "
            "subset could not even hold one batch."
        )
    if cfg["frame_size"] is None:
        # the model's frame size, written out: the config hash and config.json then say which
        # frames a run saw, also after the default changed (18x24 before 12x16)
        cfg["frame_size"] = default_frame_size(cfg.get("model"))
    if cfg["frame_size"] is not None:  # checked by FRAME_SIZE above
        cfg["frame_size"] = tuple(int(s) for s in cfg["frame_size"])
    if cfg["convergence_threshold"] == "auto" and cfg["model"] != "convlstm":
        cfg["convergence_threshold"] = None  # the paper's rule is for the ConvLSTM
    return cfg


def resolve_convergence_threshold(cfg, n_classes):
    """Write the number ``convergence_threshold="auto"`` means for ``n_classes`` into ``cfg``.

    The paper's rule ("loss > 1 after initial training": not converged) is for
    the ConvLSTM on 5 classes; ``"auto"`` keeps its fraction of chance loss
    ``ln K`` (:func:`~sklearn_hardness.models.is_converged` with ``threshold="chance"``), so 1.0
    at 5 classes (the hash of ``silicone5`` runs is the same as before) and
    1.365 at 9 (``shore9``: a new hash, its runs judged at 1.0 are not reread).
    Called by the experiments once the data give ``n_classes``, before the
    config hash. Returns ``cfg``.
    """
    if cfg["convergence_threshold"] == "auto":
        cfg["convergence_threshold"] = chance_scaled_threshold(int(n_classes))
    return cfg


def _jsonable(value):
    if isinstance(value, dict):
        return {str(k): _jsonable(v) for k, v in sorted(value.items(), key=lambda kv: str(kv[0]))}
    if isinstance(value, (list, tuple)):
        return [_jsonable(v) for v in value]
    if isinstance(value, np.ndarray):
        return _jsonable(value.tolist())
    if isinstance(value, np.generic):
        return value.item()
    if value is None or isinstance(value, (bool, int, float, str)):
        return value
    return repr(value)


#: Keys added after results files existed, with the value that means "as before": hashed
#: only when set to something else, so earlier results files stay resumable.
_LATER_KEYS = {"n_ensemble": 0, "device": "cpu", "early_stopping": None, "crop_contact": None,
               "dropout_placement": "head", "class_weight": None}


#: The frame size ``frame_size=None`` meant in the hash, per :func:`_input_name` (before
#: check_config wrote the size out and the ConvLSTM's default became 12x16): hashed as None,
#: so results files made then stay resumable under the same frames.
_SIZES_HASHED_AS_NONE = {"convlstm": (18, 24), "ofnn": (120, 160), "dinov2nn": (112, 150), "contact_profile_nn": None,
                         "contact_profile": None, "contact_profile_3": None, "contact_geometry": None,
                         "loading_compliance": None}


def config_hash(config):
    """A short stable hash of a configuration (JSON with sorted keys, SHA-256).

    Runs are resumed only under the same hash, so changing any setting starts
    new runs instead of mixing results. A renamed key (:data:`RENAMED_KEYS`)
    is hashed under its former name: renaming changes no hash.
    """
    config = {k: v for k, v in config.items() if not (k in _LATER_KEYS and v == _LATER_KEYS[k])}
    new_names = {new: old for old, new in RENAMED_KEYS.items()}
    config = {new_names.get(k, k): v for k, v in config.items()}
    size = config.get("frame_size")
    if size is not None and tuple(size) == _SIZES_HASHED_AS_NONE[_input_name(config.get("model"))]:
        config["frame_size"] = None
    text = json.dumps(_jsonable(config), sort_keys=True, separators=(",", ":"))
    return hashlib.sha256(text.encode()).hexdigest()[:12]
