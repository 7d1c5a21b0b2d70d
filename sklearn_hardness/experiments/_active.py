"""The paper's active-sampling experiment (Sec. III-F, Algorithm 1)."""

from __future__ import annotations

import copy
import numbers
import warnings

import numpy as np

from ._config import check_config, config_hash, get_config, resolve_convergence_threshold
from ._data import describe_model, make_estimator, prepare_inputs
from ._results import ExperimentResult, ResultsStore
from ._runner import run_tasks

__all__ = ["run_active_sampling", "STRATEGIES"]

#: The strategies compared by default (BALD is our addition to the paper's three).
STRATEGIES = ("variance", "entropy", "random", "bald")


def _seeds(seed, test_class, n):
    """Independent int seeds for one (test class, seed): the same for every strategy (paired runs)."""
    ss = np.random.SeedSequence([int(seed), int(test_class), 20240917])
    return [int(s) for s in ss.generate_state(n, dtype=np.uint32) % (2**31 - 1)]


def _uncertainty(learner, X_test, seed):
    from ..active import class_uncertainty

    proba = learner.predict_proba_samples(X_test, random_state=seed)
    return {k: class_uncertainty(proba, k) for k in ("entropy", "variance", "bald")}


def _evaluate(learner, X_test, y_test, hardness):
    from ..metrics import hardness_mae

    pred = learner.predict(X_test)
    acc = float(np.mean(pred == y_test))
    mae = None if hardness is None else hardness_mae(y_test, pred, hardness)
    return acc, mae, pred


def _input_scale(X_train, cfg, model):
    """The factor that brings the run's training frames to unit standard deviation (1 if unscaled).

    Fitted on the initial training presses of the run only (fixed for the run),
    never on the test object's held-out presses.
    """
    if model != "convlstm" or cfg.get("input_scale") is None:
        return None
    std = float(np.std(X_train))
    return np.float32(1.0 / std) if std > 0 else None


def _split(y, cfg, n_classes, test_class, split_seed):
    """The test object's presses and ``n_holdout`` held-out presses of every class (never trained on)."""
    rng = np.random.default_rng(split_seed)
    members = np.flatnonzero(y == test_class)
    test_idx = np.sort(rng.choice(members, cfg["n_test"], replace=False))
    n_hold = cfg.get("n_holdout", 0)
    hold = []
    if n_hold:
        hold_rng = np.random.default_rng([split_seed, 1])  # separate stream: the test split stays as without
        for c in range(n_classes):
            free = np.setdiff1d(np.flatnonzero(y == c), test_idx)
            hold.append(np.sort(hold_rng.choice(free, n_hold, replace=False)))
    holdout_idx = np.concatenate(hold) if hold else np.empty(0, dtype=int)
    pool = np.setdiff1d(np.arange(len(y)), np.concatenate([test_idx, holdout_idx]))
    return test_idx, holdout_idx, pool


def _initial_state(X, y, cfg, model, n_classes, test_class, seed, strategy):
    """What the paired runs of one (test object, seed) share: split, oracle, initial training."""
    from ..active import ActiveLearner, PressOracle

    split_seed, oracle_seed, learner_seed, model_seed, mc_seed = _seeds(seed, test_class, 5)
    test_idx, holdout_idx, pool = _split(y, cfg, n_classes, test_class, split_seed)
    oracle = PressOracle(pool, y[pool], random_state=oracle_seed)
    init_idx, y0 = oracle.initial(cfg["n_initial"])
    scale = _input_scale(X[init_idx], cfg, model)

    learner = ActiveLearner(
        make_estimator(model, cfg, model_seed, n_classes),
        strategy,
        initial_epochs=cfg["initial_epochs"],
        epochs_per_query=cfg["epochs_per_query"],
        max_reservoir=cfg["max_reservoir"],
        n_mc_samples=cfg["n_mc_samples"],
        classes=np.arange(n_classes),
        random_state=learner_seed,
    )
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", UserWarning)
        learner.fit(_rows(X, init_idx, scale), y0)
    return {"learner": learner, "oracle": oracle, "scale": scale, "test_idx": test_idx,
            "holdout_idx": holdout_idx, "init_idx": init_idx, "mc_seed": mc_seed}


def _rows(X, idx, scale):
    return X[idx] if scale is None else X[idx] * scale


def _continue_run(X, y, hardness, cfg, n_classes, target_names, test_class, state, strategy):
    """The queries of one strategy from a trained initial state. Returns the record."""
    from ..models import is_converged

    learner, oracle, scale = state["learner"], state["oracle"], state["scale"]
    learner.query_strategy = strategy
    test_idx, holdout_idx, init_idx = state["test_idx"], state["holdout_idx"], state["init_idx"]
    X_test = _rows(X, test_idx, scale)
    y_test = np.full(len(test_idx), test_class)
    X_hold = _rows(X, holdout_idx, scale) if len(holdout_idx) else None
    loss = learner.initial_train_loss_
    threshold = cfg["convergence_threshold"]
    converged = threshold is None or loss is None or is_converged(loss, threshold)

    rec = {
        "converged": bool(converged),
        "initial_train_loss": loss,
        "test_name": str(target_names[test_class]),
        "test_indices": test_idx,
        "initial_indices": init_idx,
        "accuracy": [], "mae": [], "entropy": [], "variance": [], "bald": [],
        "entropy_per_class": [], "variance_per_class": [], "bald_per_class": [],
        "predictions": [], "queried": [], "train_loss": [loss], "reservoir_size": [len(init_idx)],
        "epochs": [learner.history_[0]["epochs"]],
        "drawn_indices": [],
    }
    if X_hold is not None:
        rec.update(holdout_indices=holdout_idx, holdout_accuracy=[], holdout_mae=[])

    def record_state(unc):
        acc, mae, pred = _evaluate(learner, X_test, y_test, hardness)
        rec["accuracy"].append(acc)
        rec["mae"].append(mae)
        rec["predictions"].append(pred)
        for k in ("entropy", "variance", "bald"):
            rec[k].append(float(np.mean(unc[k])))
            rec[k + "_per_class"].append(unc[k])
        if X_hold is not None:
            acc, mae, _ = _evaluate(learner, X_hold, y[holdout_idx], hardness)
            rec["holdout_accuracy"].append(acc)
            rec["holdout_mae"].append(mae)

    n_iter = cfg["n_iterations"] if converged else 0
    for it in range(n_iter):
        idx, _ = learner.query(X_test)
        entry = learner.history_[-1]
        record_state({k: entry[k] for k in ("entropy", "variance", "bald")})
        label = int(learner.classes_[idx[0]])
        new_idx, new_y = oracle.press(label, cfg["n_per_query"])
        learner.teach(_rows(X, new_idx, scale), new_y)
        rec["queried"].append(label)
        rec["drawn_indices"].append(new_idx)
        rec["train_loss"].append(learner.history_[-1]["train_loss"])
        rec["reservoir_size"].append(learner.history_[-1]["reservoir_size"])
        rec["epochs"].append(learner.history_[-1]["epochs"])
    record_state(_uncertainty(learner, X_test, state["mc_seed"]))
    return rec


def _active_run(X, y, hardness, cfg, model, n_classes, target_names, strategy, test_class, seed, key):
    """One run: (strategy, test object, seed), trained from scratch. Returns the record (without provenance)."""
    state = _initial_state(X, y, cfg, model, n_classes, test_class, seed, strategy)
    return _continue_run(X, y, hardness, cfg, n_classes, target_names, test_class, state, strategy)


def _active_pair(X, y, hardness, cfg, model, n_classes, target_names, strategies, test_class, seed, keys):
    """The paired runs of one (test object, seed): the initial model is trained once and copied.

    Each strategy continues from a deep copy of the trained learner and of
    the oracle (weights, optimizer state, random generators), so its record
    equals that of :func:`_active_run` with the same arguments.
    """
    state = _initial_state(X, y, cfg, model, n_classes, test_class, seed, strategies[0])
    records = []
    for i, strategy in enumerate(strategies):
        run_state = state if i == len(strategies) - 1 else copy.deepcopy(state)
        records.append(_continue_run(X, y, hardness, cfg, n_classes, target_names, test_class,
                                     run_state, strategy))
    return records


def _check_strategies(strategies):
    from ..active import get_strategy

    if isinstance(strategies, str) or callable(strategies):
        strategies = (strategies,)
    strategies = tuple(strategies)
    if not strategies:
        raise ValueError("strategies is empty; pass e.g. ('variance', 'entropy', 'random').")
    names = []
    for s in strategies:
        get_strategy(s)  # ValueError for an unknown name
        names.append(s if isinstance(s, str) else getattr(s, "__name__", repr(s)))
    if len(set(names)) != len(names):
        raise ValueError(f"strategies has duplicates: {names}.")
    return strategies, names


def _check_int_list(values, name, allowed=None):
    out = []
    for v in np.atleast_1d(np.asarray(values)).tolist():
        if isinstance(v, bool) or not isinstance(v, numbers.Integral) or v < 0:
            raise ValueError(f"{name} must be non-negative ints, got {v!r}.")
        if allowed is not None and v not in allowed:
            raise ValueError(f"{name} has {v!r}, not one of {sorted(allowed)}.")
        out.append(int(v))
    if len(set(out)) != len(out) or not out:
        raise ValueError(f"{name} must be distinct and non-empty, got {out}.")
    return out


def run_active_sampling(
    dataset="silicone5",
    *,
    preset=None,
    model=None,
    strategies=STRATEGIES,
    n_runs=None,
    test_classes=None,
    seeds=None,
    quick=False,
    n_jobs=None,
    results_path=None,
    memory=None,
    verbose=1,
    **config,
):
    """Compare active-sampling strategies as in the paper (Algorithm 1, Sec. III-F).

    A run is (strategy, test object, seed). The test object is one reference
    class: ``n_test`` of its presses are held out as the presses of the
    object to classify (``X_test``); the reference presses for training come
    from the remaining pool through a :class:`~sklearn_hardness.active.PressOracle`.
    The classifier is trained on ``n_initial`` presses per class for
    ``initial_epochs`` epochs; then, ``n_iterations`` times, the strategy
    scores every class by the MC-dropout uncertainty on ``X_test`` (Eq. 1, 2),
    ``n_per_query`` new presses of the chosen class join the reservoir, and
    the net trains ``epochs_per_query`` epochs on the reservoir (or a random
    subset of ``max_reservoir`` presses). After the initial training and
    after every iteration the run records the accuracy (fraction of test
    presses predicted as the test object, dropout off), the hardness MAE and
    the per-class entropy, variance and BALD. Runs of different strategies
    with the same (test object, seed) share the test presses, the initial
    presses, the initial weights and the oracle's order (paired): the
    initial model is trained once per pair and copied into each strategy.
    The ConvLSTM's input scale (``input_scale="std"``) is fitted on the
    run's initial training presses.

    Following the paper, a run whose training loss after the initial training
    exceeds ``convergence_threshold`` is reported as not converged and not
    continued. ``"auto"``: the paper's 1.0 for the ConvLSTM at 5 classes
    (``silicone5``), the same fraction of chance loss at K classes
    (:func:`~sklearn_hardness.models.chance_scaled_threshold`; 1.365 on
    ``shore9``), no rule for the other models.

    Parameters
    ----------
    dataset : {"silicone5", "shore9"}, path-like or Bunch, default="silicone5"
        A simulator preset (:func:`~sklearn_hardness.datasets.make_presses`),
        a manifest CSV of recordings
        (:func:`~sklearn_hardness.datasets.load_press_videos`) or a Bunch
        with ``videos``, ``target`` and optionally ``hardness``.
    preset : {"silicone5", "shore9"} or None, default=None
        Whose hyperparameters to use (:func:`get_config`); None: the
        dataset's preset, or ``"silicone5"`` for other datasets.
    model : {"convlstm", "ofnn", "dinov2nn"}, estimator or None, default=None
        None: the preset's model (ConvLSTM for ``silicone5``, DINOv2NN for
        ``shore9``). An estimator (a classifier with
        ``predict_proba_samples``, or a Pipeline ending in one) gets the
        selected frames, shape ``(n, n_between + 2, H, W, C)``; it is cloned
        and seeded for every run.
    strategies : sequence of str or callable, default=("variance", "entropy", "random", "bald")
    n_runs : int or None, default=None
        Seeds per test object (the preset's ``n_runs`` if None).
    test_classes : sequence of int or None, default=None
        Which classes serve as test object (all if None).
    seeds : sequence of int or None, default=None
        Explicit seeds (default ``range(n_runs)``).
    quick : bool, default=False
        Use :data:`QUICK_OVERRIDES` (smaller, fewer, faster).
    n_jobs : int or None, default=None
        Parallel runs through :class:`joblib.Parallel`; each worker uses one
        torch thread. ``joblib.parallel_config(backend="dask")`` sends them
        to a Dask cluster.
    results_path : str, path-like or None, default=None
        JSON Lines file; every finished run is appended (and fsynced) as it
        ends. Rerunning with the same file skips the runs already there.
    memory : None, False, str or joblib.Memory, default=None
        Disk cache of frame selection and frozen features, computed once
        per dataset and configuration: a folder, None for
        ``$SKLEARN_HARDNESS_CACHE`` or ``~/.cache/sklearn_hardness``, False
        for none.
    verbose : int, default=1
        1: a line per finished run on stderr (done/total, elapsed time, an
        estimate of the rest), also when stderr is a file or a pipe; 0: silent.
    **config
        Overrides of the configuration: ``initial_epochs``,
        ``epochs_per_query``, ``max_reservoir``, ``n_initial``,
        ``n_per_query``, ``n_iterations``, ``n_test``, ``n_holdout``, ``n_mc_samples``,
        ``dropout``, ``dropout_placement`` (ConvLSTM), ``lr``, ``batch_size``, ``frame_size``, ``color``,
        ``n_between``, ``convergence_threshold``, ``image_size``,
        ``data_seed``, ``dinov2_model``.

    Returns
    -------
    result : ExperimentResult
        ``result.records``: one dict per run with ``key`` (``experiment``,
        ``strategy``, ``test_class``, ``seed``, ``config``), ``converged``,
        ``initial_train_loss``, and per iteration 0..N ``accuracy``, ``mae``,
        ``entropy``, ``variance``, ``bald`` (class means) and their
        ``*_per_class`` values, ``predictions``, and with ``n_holdout``
        presses per class held out of the pool, ``holdout_accuracy`` and
        ``holdout_mae`` on them (every reference object); per query ``queried`` (class
        index), ``train_loss`` and ``reservoir_size``; ``epochs`` trained (the initial
        training, then each query; below the configured counts when ``early_stopping``
        stopped a training call); and provenance
        (``wall_time``, ``finished_at``, ``pid``, ``host``). See
        :func:`comparison_table` and :func:`plot_active_sampling`.

    Examples
    --------
    A tiny run (the real one uses the defaults)::

        from sklearn_hardness.experiments import run_active_sampling, comparison_table
        res = run_active_sampling("silicone5", quick=True, n_jobs=2,
                                  results_path="runs.jsonl")
        print(format_table(comparison_table(res)))
    """
    if preset is None:
        preset = dataset if isinstance(dataset, str) and dataset in ("silicone5", "shore9") else "silicone5"
    if n_runs is not None:
        config["n_runs"] = n_runs
    cfg = get_config(preset, quick=quick, **config)
    model = cfg["model"] if model is None else model
    cfg["model"] = describe_model(model)
    check_config(cfg)
    strategies, names = _check_strategies(strategies)
    # the ConvLSTM's input scale is fitted per run on its training presses (_input_scale)
    inputs = prepare_inputs(dataset, cfg, model, memory=memory, verbose=verbose, scale=False, n_jobs=n_jobs)
    n_classes = inputs.n_classes
    resolve_convergence_threshold(cfg, n_classes)  # "auto": scaled to ln(n_classes), hashed
    test_classes = list(range(n_classes)) if test_classes is None else _check_int_list(
        test_classes, "test_classes", set(range(n_classes)))
    seeds = list(range(cfg["n_runs"])) if seeds is None else _check_int_list(seeds, "seeds")

    counts = np.bincount(inputs.y, minlength=n_classes)
    worst = cfg["n_initial"] + cfg["n_iterations"] * cfg["n_per_query"]
    for c in range(n_classes):
        need = worst + cfg["n_holdout"] + (cfg["n_test"] if c in test_classes else 0)
        if counts[c] < need:
            raise ValueError(
                f"class {c} ({inputs.target_names[c]}) has {counts[c]} presses, but a run may need "
                f"{need}: n_initial={cfg['n_initial']} + n_iterations={cfg['n_iterations']} x "
                f"n_per_query={cfg['n_per_query']}"
                + (f" + n_holdout={cfg['n_holdout']}" if cfg["n_holdout"] else "") + (f" + n_test={cfg['n_test']}" if c in test_classes else "")
                + ". Use fewer iterations or presses, or a larger dataset."
            )
    chash = config_hash(dict(cfg, data=inputs.data_id, n_runs=None))  # n_runs picks seeds only
    tasks, groups = [], []
    for tc in test_classes:
        for seed in seeds:
            keys = []
            for strat, name in zip(strategies, names):
                key = {"experiment": "active_sampling", "strategy": name, "test_class": tc,
                       "seed": seed, "config": chash}
                tasks.append({"strategy": strat, "test_class": tc, "seed": seed, "key": key})
                keys.append(key)
            # one task per (test object, seed): the paired strategies share the initial training
            groups.append({"strategies": list(strategies), "test_class": tc, "seed": seed, "keys": keys})
    common = {"X": inputs.X, "y": inputs.y, "hardness": inputs.hardness, "cfg": cfg,
              "model": model, "n_classes": n_classes,
              "target_names": [str(n) for n in inputs.target_names]}
    store = ResultsStore(results_path)
    run_tasks(_active_pair, groups, common, store, n_jobs=n_jobs, verbose=verbose, desc="active sampling",
              group_field="strategies")
    wanted = {(t["key"]["strategy"], t["test_class"], t["seed"]) for t in tasks}
    records = [
        r for r in store.records
        if r["key"].get("experiment") == "active_sampling" and r["key"].get("config") == chash
        and (r["key"]["strategy"], r["key"]["test_class"], r["key"]["seed"]) in wanted
    ]
    order = {k: i for i, k in enumerate((t["key"]["strategy"], t["test_class"], t["seed"]) for t in tasks)}
    records.sort(key=lambda r: order[(r["key"]["strategy"], r["key"]["test_class"], r["key"]["seed"])])
    cfg = dict(cfg, target_names=[str(n) for n in inputs.target_names],
               hardness=None if inputs.hardness is None else inputs.hardness.tolist(),
               hardness_unit=inputs.hardness_unit, strategies=names, config_hash=chash)
    return ExperimentResult(records, config=cfg, path=None if results_path is None else str(results_path))
