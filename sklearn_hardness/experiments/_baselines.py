"""Model baselines (Sec. III-D) and the dropout sweep (Sec. III-E)."""

from __future__ import annotations

import numbers
import warnings

import numpy as np

from ..metrics import hardness_mae
from ..model_selection import evaluate_pipelines
from ..models import is_converged, make_named_pipeline
from ..utils._random import derived_seeds
from ._config import config_hash, default_preset, get_config, resolve_convergence_threshold, run_config
from ._data import prepare_inputs
from ._models import input_scaler, make_estimator
from ._results import ExperimentResult, ResultsStore
from ._runner import run_tasks

__all__ = ["run_model_baselines", "run_dropout_sweep"]


def _fit_eval_run(X, y, hardness, cfg, model, n_classes, n_train, n_test, seed, key, dropout=None):
    """Train on n_train presses per class for e0 epochs, test on n_test others per class."""
    split_seed, model_seed = derived_seeds([seed, 777], 2)
    rng = np.random.default_rng(split_seed)
    train, test = [], []
    for c in range(n_classes):
        members = rng.permutation(np.flatnonzero(y == c))
        train.append(members[:n_train])
        test.append(members[n_train : n_train + n_test])
    train, test = np.concatenate(train), np.concatenate(test)
    est = make_estimator(model, dict(cfg, _override_dropout=dropout is not None), model_seed,
                         n_classes, dropout=dropout)
    X_train, X_test = X[train], X[test]
    scaler = input_scaler(model, cfg)  # the factory's scale step, fitted on the run's training presses
    if scaler is not None:
        X_train = scaler.fit_transform(X_train)
        X_test = scaler.transform(X_test)
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", UserWarning)
        est.fit(X_train, y[train])
    pred_train, pred_test = est.predict(X_train), est.predict(X_test)
    history = getattr(est, "history_", None)
    losses = [] if history is None else [float(v) for v in history[:, "train_loss"]]
    loss = losses[-1] if losses else None
    threshold = cfg["convergence_threshold"]
    return {
        "train_accuracy": float(np.mean(pred_train == y[train])),
        "accuracy": float(np.mean(pred_test == y[test])),
        "mae": None if hardness is None else hardness_mae(y[test], pred_test, hardness),
        "train_loss": loss,
        "train_loss_curve": losses,
        "converged": bool(threshold is None or loss is None or is_converged(loss, threshold)),
        "test_indices": test,
        "predictions": pred_test,
    }


def _cv_dataset(dataset):
    """A dataset Bunch as evaluate loads one: itself, a manifest (or its folder), else a preset seeded 0."""
    import os

    from ..datasets import load_press_videos, make_presses

    if hasattr(dataset, "videos"):
        return dataset
    if os.path.exists(dataset):
        return load_press_videos(os.path.join(dataset, "manifest.csv") if os.path.isdir(dataset) else dataset)
    return make_presses(dataset, random_state=0)


def _check_n(value, name):
    if isinstance(value, bool) or not isinstance(value, numbers.Integral) or value < 1:
        raise ValueError(f"{name} must be a positive int, got {value!r}.")
    return int(value)


def _check_counts(y, n_classes, need, names):
    counts = np.bincount(y, minlength=n_classes)
    short = [c for c in range(n_classes) if counts[c] < need]
    if short:
        raise ValueError(
            f"classes {[str(names[c]) for c in short]} have fewer than the {need} presses needed "
            "(n_train_per_class + n_test_per_class)."
        )


def run_model_baselines(
    dataset="silicone5",
    *,
    models=("ofnn", "dinov2nn", "convlstm"),
    n_train_per_class=5,
    n_test_per_class=5,
    n_runs=10,
    preset=None,
    quick=False,
    n_jobs=None,
    results_path=None,
    memory=None,
    verbose=1,
    cv=None,
    **config,
):
    """Train each model on a few presses per object and test it (Sec. III-D).

    Each run draws ``n_train_per_class`` training and ``n_test_per_class``
    test presses per class (disjoint; the same draw for every model with the
    same seed), trains for ``initial_epochs`` epochs and records training and
    test accuracy, the hardness MAE and the training loss per epoch.

    Parameters
    ----------
    dataset : {"silicone5", "shore9"}, path-like or Bunch, default="silicone5"
        See :func:`run_active_sampling`.
    models : sequence of {"ofnn", "dinov2nn", "convlstm"} or (name, estimator) pairs
        The models. ``"dinov2nn"`` needs the DINOv2 weights
        (``dinov2_model=...``: a Hugging Face id in the local cache, a local
        directory or a module); without them it fails with a message that
        says what to pass.
    n_train_per_class, n_test_per_class : int, default=5
    n_runs : int, default=10
        Seeds per model.
    preset, quick, n_jobs, results_path, memory, verbose, **config
        As in :func:`run_active_sampling`.
    cv : int or None, default=None
        None: the paper's protocol above. An int: object-disjoint
        cross-validation instead (folds grouped by ``object_id``), the
        models at their ready-made defaults beside the one-number baseline;
        the result is then that of
        :func:`~sklearn_hardness.model_selection.evaluate_pipelines` (balanced
        accuracy, MAE, confusion matrices), and ``n_train_per_class``,
        ``n_test_per_class``, ``n_runs``, ``quick``, ``results_path``,
        ``memory`` and ``**config`` do not apply.

    Returns
    -------
    result : ExperimentResult or Bunch
        One record per (model, seed): ``train_accuracy``, ``accuracy``,
        ``mae``, ``train_loss``, ``train_loss_curve``, ``converged``. With
        ``cv``: the :class:`~sklearn_hardness.model_selection.EvaluationResult` of
        :func:`~sklearn_hardness.model_selection.evaluate_pipelines`.

    Examples
    --------
    A quick comparison of the named models on the simulator (minutes on 2 cores)::

        from sklearn_hardness.experiments import run_model_baselines

        res = run_model_baselines("silicone5", models=("contact_profile", "convlstm"), quick=True, n_jobs=2)
        print(res.format_table(res.baseline_table(), mae_unit="mm/N"))
    """
    if cv is not None:
        if isinstance(models, str):
            models = (models,)
        pipes = {m: m for m in models} if all(isinstance(m, str) for m in models) else None
        if pipes is not None:
            pipes = {m: make_named_pipeline(m) for m in models}
        else:
            pipes = {str(n): e for n, e in models}
        if isinstance(dataset, str) and preset is not None and dataset == preset:
            dataset = preset
        data = _cv_dataset(dataset)
        return evaluate_pipelines(pipes, data.videos, data.target, groups=data.object_id, cv=cv,
                                  target_names=data.target_names, hardness=getattr(data, "hardness", None),
                                  error_score="raise", n_jobs=n_jobs, random_state=0)
    n_train = _check_n(n_train_per_class, "n_train_per_class")
    n_test = _check_n(n_test_per_class, "n_test_per_class")
    n_runs = _check_n(n_runs, "n_runs")
    cfg = get_config(default_preset(dataset, preset), quick=quick, **config)  # the runs' shared settings
    if isinstance(models, str):
        models = (models,)
    pairs = []
    for m in models:
        name, est = (m, m) if isinstance(m, str) else m
        pairs.append((str(name), est))
    if not pairs:
        raise ValueError("models is empty.")
    names = [p[0] for p in pairs]
    if len(set(names)) != len(names):
        raise ValueError(f"models has duplicate names: {names}.")
    store = ResultsStore(results_path)
    records = []
    for name, model in pairs:
        mcfg, _ = run_config(dataset, preset, model, None, quick, config)  # quick's frame size is per model
        inputs = prepare_inputs(dataset, mcfg, model, memory=memory, verbose=verbose, n_jobs=n_jobs)
        _check_counts(inputs.y, inputs.n_classes, n_train + n_test, inputs.target_names)
        resolve_convergence_threshold(mcfg, inputs.n_classes)
        chash = config_hash(dict(mcfg, n_runs=None, n_train=n_train, n_test=n_test, data=inputs.data_id))
        tasks = [{"seed": s, "key": {"experiment": "model_baselines", "model": name, "seed": s,
                                     "config": chash}} for s in range(n_runs)]
        common = {"X": inputs.X, "y": inputs.y, "hardness": inputs.hardness, "cfg": mcfg, "model": model,
                  "n_classes": inputs.n_classes, "n_train": n_train, "n_test": n_test}
        run_tasks(_fit_eval_run, tasks, common, store, n_jobs=n_jobs, verbose=verbose, desc=f"baseline {name}")
        keys = {(t["key"]["model"], t["seed"], chash) for t in tasks}
        records += [r for r in store.records if r["key"].get("experiment") == "model_baselines"
                    and (r["key"]["model"], r["key"]["seed"], r["key"]["config"]) in keys]
    return ExperimentResult(records, config=dict(cfg, models=names), path=results_path)


def run_dropout_sweep(
    dataset="silicone5",
    *,
    model=None,
    dropouts=tuple(np.round(np.arange(0.05, 0.501, 0.05), 2).tolist()),
    n_train_per_class=5,
    n_test_per_class=5,
    n_runs=9,
    preset=None,
    quick=False,
    n_jobs=None,
    results_path=None,
    memory=None,
    verbose=1,
    **config,
):
    """Accuracy and hardness MAE against the dropout rate (Sec. III-E).

    The paper sweeps DINOv2NN on Yuan's data from 0.05 to 0.5 (9 runs each)
    and finds that rates above 0.2 degrade accuracy and stability.

    Parameters
    ----------
    dataset : {"silicone5", "shore9"}, path-like or Bunch, default="silicone5"
    model : {"convlstm", "ofnn", "dinov2nn"}, estimator or None, default=None
        None: the preset's model. An estimator must have a ``dropout``
        parameter (possibly nested, e.g. ``clf__dropout``).
    dropouts : sequence of float, default=(0.05, 0.1, ..., 0.5)
    n_train_per_class, n_test_per_class : int, default=5
    n_runs : int, default=9
        Seeds per dropout rate (the same splits for every rate).
    preset, quick, n_jobs, results_path, memory, verbose, **config
        As in :func:`run_active_sampling`.

    Returns
    -------
    result : ExperimentResult
        One record per (dropout, seed), as in :func:`run_model_baselines`.

    Examples
    --------
    Accuracy against the dropout rate of the ConvLSTM (the paper's Sec. III-E)::

        from sklearn_hardness.experiments import run_dropout_sweep

        res = run_dropout_sweep("silicone5", dropouts=(0.1, 0.2, 0.5), quick=True, n_jobs=2)
        print(res.format_table(res.baseline_table()))
    """
    n_train = _check_n(n_train_per_class, "n_train_per_class")
    n_test = _check_n(n_test_per_class, "n_test_per_class")
    n_runs = _check_n(n_runs, "n_runs")
    dropouts = [float(d) for d in np.atleast_1d(np.asarray(dropouts, dtype=float))]
    if not dropouts:
        raise ValueError("dropouts is empty.")
    for d in dropouts:
        if not 0.0 <= d < 1.0:
            raise ValueError(f"dropout rates must lie in [0, 1), got {d!r}.")
    cfg, model = run_config(dataset, preset, model, None, quick, config)
    if not isinstance(model, str):
        if not any(k == "dropout" or k.endswith("__dropout") for k in model.get_params(deep=True)):
            raise ValueError(f"{type(model).__name__} has no dropout parameter to sweep.")
    inputs = prepare_inputs(dataset, cfg, model, memory=memory, verbose=verbose, n_jobs=n_jobs)
    _check_counts(inputs.y, inputs.n_classes, n_train + n_test, inputs.target_names)
    resolve_convergence_threshold(cfg, inputs.n_classes)
    chash = config_hash(dict(cfg, dropout=None, n_runs=None, n_train=n_train, n_test=n_test, data=inputs.data_id))
    tasks = [{"seed": s, "dropout": d,
              "key": {"experiment": "dropout_sweep", "dropout": d, "seed": s, "config": chash}}
             for d in dropouts for s in range(n_runs)]
    common = {"X": inputs.X, "y": inputs.y, "hardness": inputs.hardness, "cfg": cfg, "model": model,
              "n_classes": inputs.n_classes, "n_train": n_train, "n_test": n_test}
    store = ResultsStore(results_path)
    run_tasks(_fit_eval_run, tasks, common, store, n_jobs=n_jobs, verbose=verbose, desc="dropout sweep")
    keys = {(t["dropout"], t["seed"]) for t in tasks}
    records = [r for r in store.records if r["key"].get("experiment") == "dropout_sweep"
               and r["key"]["config"] == chash and (r["key"]["dropout"], r["key"]["seed"]) in keys]
    records.sort(key=lambda r: (r["key"]["dropout"], r["key"]["seed"]))
    return ExperimentResult(records, config=dict(cfg, dropouts=dropouts), path=results_path)
