"""The paper's active-sampling experiment (Sec. III-F, Algorithm 1)."""

from __future__ import annotations

import copy
import numbers
import warnings
import zlib

import joblib
import numpy as np

from .._experiment_names import STRATEGIES
from ._config import check_config, config_hash, get_config, resolve_convergence_threshold
from ._data import _dataset_spec, describe_model, load_dataset, make_estimator, prepare_inputs
from ._results import ExperimentResult, ResultsStore
from ._runner import run_tasks

__all__ = ["run_active_sampling", "planned_config_hash", "STRATEGIES"]


def _seeds(seed, test_class, n, test_object=None):
    """Independent int seeds for one (test object, seed): the same for every strategy (paired runs).

    Without object ids the test object is the class (the seeds of earlier results files);
    with them the object's id enters the seed too.
    """
    entropy = [int(seed), int(test_class), 20240917]
    if test_object is not None:
        entropy.append(zlib.crc32(str(test_object).encode()))
    ss = np.random.SeedSequence(entropy)
    return [int(s) for s in ss.generate_state(n, dtype=np.uint32) % (2**31 - 1)]


def _has_objects(object_id, y):
    """True when some class has presses of more than one object (the object-disjoint protocol)."""
    if object_id is None:
        return False
    return any(np.unique(object_id[y == c]).size > 1 for c in np.unique(y))


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
    """The factor that brings the run's training frames to unit standard deviation (None if unscaled).

    Fitted on the initial training presses of the run only (fixed for the run),
    never on the test object's held-out presses. For ``contact_profile_nn``
    a (mean, 1 / std) pair per feature: its features differ in scale by orders
    of magnitude (frames, fractions, log intensities), as a ``StandardScaler``
    would see them.
    """
    if model == "contact_profile_nn":
        std = X_train.std(axis=0)
        return X_train.mean(axis=0).astype(np.float32), (1.0 / np.where(std > 0, std, 1.0)).astype(np.float32)
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


def _split_objects(y, groups, cfg, n_classes, test_object, split_seed):
    """The object-disjoint split: test presses of one object, held-out presses of unseen objects.

    The test presses are ``n_test`` presses of ``test_object`` (all of them if
    it has fewer); none of its other presses is used. For ``n_holdout``, the
    other objects of every class are taken whole, in a seeded random order,
    until they hold at least ``n_holdout`` presses, and ``n_holdout`` of
    those presses are scored; the rest of those objects' presses is unused.
    The pool is every press of the remaining objects. A class whose pool
    would hold no object or fewer than ``n_initial`` presses is a
    ``ValueError`` naming it.
    """
    rng = np.random.default_rng([split_seed, 2])
    own = np.flatnonzero(groups == test_object)
    test_idx = np.sort(rng.choice(own, min(cfg["n_test"], own.size), replace=False))
    n_hold = cfg.get("n_holdout", 0)
    hold, hold_objects = [], []
    used = groups == test_object
    for c in range(n_classes):
        objs = np.unique(groups[(y == c) & ~used])
        if n_hold:
            objs = rng.permutation(objs)
            counts = np.array([np.sum(groups == o) for o in objs])
            k = int(np.searchsorted(np.cumsum(counts), n_hold)) + 1  # objects to reach n_hold presses
            if k > objs.size - 1:
                raise ValueError(
                    f"class {c} has {objs.size} object(s) besides the test object {test_object!r} with "
                    f"{counts.sum()} presses: holding out n_holdout={n_hold} presses of unseen objects "
                    "needs objects with that many presses and one more object to press. Use a smaller "
                    "n_holdout, or n_holdout=0."
                )
            members = np.flatnonzero(np.isin(groups, objs[:k]))
            hold.append(np.sort(rng.choice(members, n_hold, replace=False)))
            hold_objects.extend(objs[:k].tolist())
            objs = objs[k:]
        n_pool = int(np.sum(np.isin(groups, objs)))
        if objs.size == 0 or n_pool < cfg["n_initial"]:
            raise ValueError(
                f"class {c} has {objs.size} reference object(s) with {n_pool} presses left when "
                f"{test_object!r} is the test object" + (f" and n_holdout={n_hold}" if n_hold else "")
                + f"; the initial training needs n_initial={cfg['n_initial']} presses of it."
            )
    holdout_idx = np.concatenate(hold) if hold else np.empty(0, dtype=int)
    pool = np.flatnonzero(~used & ~np.isin(groups, hold_objects))
    return test_idx, holdout_idx, pool


def _initial_state(X, y, cfg, model, n_classes, test_class, seed, strategy, groups=None, test_object=None):
    """What the paired runs of one (test object, seed) share: split, oracle, initial training."""
    from ..active import ActiveLearner, PressOracle

    split_seed, oracle_seed, learner_seed, model_seed, mc_seed = _seeds(seed, test_class, 5, test_object)
    if test_object is None:
        test_idx, holdout_idx, pool = _split(y, cfg, n_classes, test_class, split_seed)
        oracle = PressOracle(pool, y[pool], random_state=oracle_seed)
    else:
        test_idx, holdout_idx, pool = _split_objects(y, groups, cfg, n_classes, test_object, split_seed)
        # a robot can press a reference object again: a replay reuses its recorded presses once
        # every reference object of the class is pressed out (n_repeated_presses in the record)
        oracle = PressOracle(pool, y[pool], groups=groups[pool], random_state=oracle_seed,
                             on_exhausted="recycle")
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
    if scale is None:
        return X[idx]
    if isinstance(scale, tuple):  # per-feature standardisation
        return (X[idx] - scale[0]) * scale[1]
    return X[idx] * scale


def _continue_run(X, y, hardness, cfg, n_classes, target_names, test_class, state, strategy,
                  test_object=None):
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
    if test_object is not None:
        n0 = len(init_idx)
        rec.update(test_object=str(test_object), initial_objects=[str(o) for o in oracle.drawn_objects_[:n0]],
                   drawn_objects=[])

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
        with warnings.catch_warnings():
            warnings.filterwarnings("ignore", message=".*reusing its presses.*")  # counted below
            new_idx, new_y = oracle.press(label, cfg["n_per_query"])
        if test_object is not None:
            rec["drawn_objects"].append([str(o) for o in oracle.drawn_objects_[-len(new_idx):]])
        learner.teach(_rows(X, new_idx, scale), new_y)
        rec["queried"].append(label)
        rec["drawn_indices"].append(new_idx)
        rec["train_loss"].append(learner.history_[-1]["train_loss"])
        rec["reservoir_size"].append(learner.history_[-1]["reservoir_size"])
        rec["epochs"].append(learner.history_[-1]["epochs"])
    record_state(_uncertainty(learner, X_test, state["mc_seed"]))
    if test_object is not None:
        drawn = np.concatenate([init_idx] + [np.asarray(d) for d in rec["drawn_indices"]])
        rec["n_repeated_presses"] = int(drawn.size - np.unique(drawn).size)
    return rec


def _active_run(X, y, hardness, cfg, model, n_classes, target_names, strategy, test_class, seed, key,
                groups=None, test_object=None):
    """One run: (strategy, test object, seed), trained from scratch. Returns the record (without provenance)."""
    state = _initial_state(X, y, cfg, model, n_classes, test_class, seed, strategy, groups, test_object)
    return _continue_run(X, y, hardness, cfg, n_classes, target_names, test_class, state, strategy,
                         test_object)


def _active_pair(X, y, hardness, cfg, model, n_classes, target_names, strategies, test_class, seed, keys,
                 groups=None, test_object=None):
    """The paired runs of one (test object, seed): the initial model is trained once and copied.

    Each strategy continues from a deep copy of the trained learner and of
    the oracle (weights, optimizer state, random generators), so its record
    equals that of :func:`_active_run` with the same arguments.
    """
    state = _initial_state(X, y, cfg, model, n_classes, test_class, seed, strategies[0], groups, test_object)
    records = []
    for i, strategy in enumerate(strategies):
        run_state = state if i == len(strategies) - 1 else copy.deepcopy(state)
        records.append(_continue_run(X, y, hardness, cfg, n_classes, target_names, test_class,
                                     run_state, strategy, test_object))
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


def _check_class_counts(inputs, cfg, test_classes):
    counts = np.bincount(inputs.y, minlength=inputs.n_classes)
    worst = cfg["n_initial"] + cfg["n_iterations"] * cfg["n_per_query"]
    for c in range(inputs.n_classes):
        need = worst + cfg["n_holdout"] + (cfg["n_test"] if c in test_classes else 0)
        if counts[c] < need:
            raise ValueError(
                f"class {c} ({inputs.target_names[c]}) has {counts[c]} presses, but a run may need "
                f"{need}: n_initial={cfg['n_initial']} + n_iterations={cfg['n_iterations']} x "
                f"n_per_query={cfg['n_per_query']}"
                + (f" + n_holdout={cfg['n_holdout']}" if cfg["n_holdout"] else "")
                + (f" + n_test={cfg['n_test']}" if c in test_classes else "")
                + ". Use fewer iterations or presses, or a larger dataset."
            )


def _object_pairs(inputs, cfg, test_classes, test_objects, seeds):
    """The (test class, test object, seed) of every pair, each split checked before any run."""
    y, groups = inputs.y, inputs.object_id
    for obj in np.unique(groups):
        classes = np.unique(y[groups == obj])
        if classes.size > 1:
            raise ValueError(f"object_id {obj!r} has presses of classes {classes.tolist()}; an object has "
                             "one class (give objects of different classes different ids).")
    n_objects = {c: np.unique(groups[y == c]).size for c in range(inputs.n_classes)}
    if test_classes is not None:
        test_classes = _check_int_list(test_classes, "test_classes", set(range(inputs.n_classes)))
        lonely = [c for c in test_classes if n_objects[c] < 2]
        if lonely:
            raise ValueError(f"classes {lonely} have one object only: it cannot be the test object "
                             "(no reference object of its class would be left).")
    if test_objects is None:
        classes = test_classes if test_classes is not None else [c for c in n_objects if n_objects[c] >= 2]
        test_objects = [str(o) for c in classes for o in np.unique(groups[y == c])]
    else:
        if isinstance(test_objects, str):
            test_objects = [test_objects]
        test_objects = [str(o) for o in test_objects]
        unknown = sorted(set(test_objects) - set(groups.astype(str).tolist()))
        if unknown or not test_objects or len(set(test_objects)) != len(test_objects):
            raise ValueError(f"test_objects must be distinct object ids of the dataset; unknown: {unknown}.")
        if test_classes is not None:
            test_objects = [o for o in test_objects if int(y[groups.astype(str) == o][0]) in test_classes]
    groups = groups.astype(str)
    pairs = []
    for obj in test_objects:
        tc = int(y[groups == obj][0])
        if n_objects[tc] < 2:
            raise ValueError(f"object {obj!r} is the only object of class {tc}; it cannot be the test object.")
        for seed in seeds:
            _split_objects(y, groups, cfg, inputs.n_classes, obj, _seeds(seed, tc, 1, obj)[0])
            pairs.append((tc, obj, seed))
    return pairs


def _dataset_name(dataset):
    """What a table's header calls the dataset: the preset, the manifest's path or "a Bunch"."""
    if isinstance(dataset, str) or hasattr(dataset, "__fspath__"):
        return str(dataset)
    return "a Bunch"


def _run_config(dataset, preset, model, n_runs, quick, config):
    """The checked configuration of :func:`run_active_sampling` (what it hashes, with the data's id)."""
    if preset is None:
        preset = dataset if isinstance(dataset, str) and dataset in ("silicone5", "shore9") else "silicone5"
    if n_runs is not None:
        config = dict(config, n_runs=n_runs)
    cfg = get_config(preset, quick=quick, **config)
    model = cfg["model"] if model is None else model
    cfg["model"] = describe_model(model)
    check_config(cfg)
    return cfg, model


def planned_config_hash(dataset="silicone5", *, preset=None, model=None, n_runs=None, quick=False, **config):
    """The configuration hash :func:`run_active_sampling` gives these arguments, without running.

    It keys the runs in a results file and is written into the provenance of
    the tables made from them (:func:`provenance_header`), so a test can tell
    whether a table's configuration is still what the code computes.

    Parameters
    ----------
    dataset : str or path-like, default="silicone5"
        A simulator preset or a manifest CSV path (as in :func:`run_active_sampling`;
        an in-memory Bunch has no hash before its inputs are computed).
    preset, model, n_runs, quick, **config
        As in :func:`run_active_sampling`.

    Returns
    -------
    config_hash : str
        The hash stored in the records' ``key["config"]``.

    Examples
    --------
    >>> from sklearn_hardness.experiments import planned_config_hash
    >>> len(planned_config_hash("silicone5", quick=True))
    12
    """
    cfg, _ = _run_config(dataset, preset, model, n_runs, quick, config)
    spec = _dataset_spec(dataset, cfg)
    if spec is None:
        raise ValueError("dataset must be a simulator preset or a manifest CSV path to hash it before a run.")
    data = load_dataset(dataset, cfg)  # lazy videos: labels and object ids only
    y = np.asarray(data["target"])
    object_id = data.get("object_id")
    object_id = None if object_id is None else np.asarray(object_id)
    n_classes = max(len(data.get("target_names", ())), int(y.max()) + 1)  # as prepare_inputs counts them
    resolve_convergence_threshold(cfg, n_classes)
    return _results_hash(cfg, list(spec), object_id, y)


def _results_hash(cfg, data_id, object_id, y):
    """The config hash that keys a run's records: object-disjoint runs also hash the protocol and objects.

    Class-level results (no object ids, or one object per class) keep the hash they had
    before the object-disjoint protocol existed.
    """
    if _has_objects(object_id, y):
        return config_hash(dict(cfg, data=data_id, n_runs=None, protocol="object-disjoint",
                                objects=joblib.hash(object_id.astype(str).tolist())))
    return config_hash(dict(cfg, data=data_id, n_runs=None))  # n_runs picks seeds only


def run_active_sampling(
    dataset="silicone5",
    *,
    preset=None,
    model=None,
    strategies=STRATEGIES,
    n_runs=None,
    test_classes=None,
    test_objects=None,
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

    **Many objects per class** (an ``object_id`` with more than one object
    in some class: the ``"everyday"`` preset, or a manifest with an
    ``object_id`` column): the runs are object-disjoint. A run's test object
    is one physical object: up to ``n_test`` of its presses are the test
    presses and none of its presses is trained on, in the pool or held out.
    The other objects are the reference objects, with their known class. The
    strategies still score classes (Eq. 1, 2); the oracle presses the
    reference object of the chosen class pressed least so far (ties at
    random, seeded), object after object until ``n_per_query`` presses are
    in; once every reference object of a class is pressed out, their
    recorded presses are reused (``n_repeated_presses`` in the record).
    ``n_holdout`` presses per class come from whole objects that are neither
    the test object nor in the pool: per class, the other objects, in a seeded
    random order, are held out whole until they hold ``n_holdout`` presses,
    and ``n_holdout`` of those presses are scored. Runs iterate over
    test objects (every object of a class with at least two objects, or
    ``test_objects``) and seeds; a pair is (test object, seed). A class
    without enough objects or presses for this is a ``ValueError`` before any
    run. Without object ids, or with one object per class (``silicone5``,
    ``shore9``), the test object is the class, as above, and splits, records
    and configuration hashes are those of earlier versions.

    Following the paper, a run whose training loss after the initial training
    exceeds ``convergence_threshold`` is reported as not converged and not
    continued. ``"auto"``: the paper's 1.0 for the ConvLSTM at 5 classes
    (``silicone5``), the same fraction of chance loss at K classes
    (:func:`~sklearn_hardness.models.chance_scaled_threshold`; 1.365 on
    ``shore9``), no rule for the other models.

    Parameters
    ----------
    dataset : {"silicone5", "shore9", "everyday"}, path-like or Bunch, default="silicone5"
        A simulator preset (:func:`~sklearn_hardness.datasets.make_presses`),
        a manifest CSV of recordings
        (:func:`~sklearn_hardness.datasets.load_press_videos`) or a Bunch
        with ``videos``, ``target`` and optionally ``hardness`` and
        ``object_id``.
    preset : {"silicone5", "shore9"} or None, default=None
        Whose hyperparameters to use (:func:`get_config`); None: the
        dataset's preset, or ``"silicone5"`` (the ConvLSTM, robot presses)
        for other datasets, ``"everyday"`` and manifests included.
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
        Which classes serve as test object (all if None); with many objects
        per class, the classes whose objects serve as test objects.
    test_objects : sequence of str or None, default=None
        Object ids that serve as test objects, one pair per (object, seed)
        (None: every object of a class with at least two objects). Only for
        datasets with several objects per class.
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
        ``strategy``, ``test_class``, with many objects per class also
        ``test_object``, ``seed``, ``config``), ``converged``,
        ``initial_train_loss``, and per iteration 0..N ``accuracy``, ``mae``,
        ``entropy``, ``variance``, ``bald`` (class means) and their
        ``*_per_class`` values, ``predictions``, and with ``n_holdout``
        presses per class held out of the pool, ``holdout_accuracy`` and
        ``holdout_mae`` on them (every reference object); per query ``queried`` (class
        index), ``train_loss`` and ``reservoir_size``; ``epochs`` trained (the initial
        training, then each query; below the configured counts when ``early_stopping``
        stopped a training call); with many objects per class
        ``test_object``, ``initial_objects`` (object of each initial press),
        ``drawn_objects`` (per query, the object of each press) and
        ``n_repeated_presses``; and provenance
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
    cfg, model = _run_config(dataset, preset, model, n_runs, quick, config)
    strategies, names = _check_strategies(strategies)
    # the ConvLSTM's input scale is fitted per run on its training presses (_input_scale)
    inputs = prepare_inputs(dataset, cfg, model, memory=memory, verbose=verbose, scale=False, n_jobs=n_jobs)
    n_classes = inputs.n_classes
    resolve_convergence_threshold(cfg, n_classes)  # "auto": scaled to ln(n_classes), hashed
    seeds = list(range(cfg["n_runs"])) if seeds is None else _check_int_list(seeds, "seeds")

    by_object = _has_objects(inputs.object_id, inputs.y)
    if test_objects is not None and not by_object:
        raise ValueError("test_objects needs a dataset with object ids and several objects per class "
                         "(e.g. 'everyday' or a manifest with an object_id column).")
    if by_object:
        pairs = _object_pairs(inputs, cfg, test_classes, test_objects, seeds)
    else:
        test_classes = list(range(n_classes)) if test_classes is None else _check_int_list(
            test_classes, "test_classes", set(range(n_classes)))
        _check_class_counts(inputs, cfg, test_classes)
        pairs = [(tc, None, seed) for tc in test_classes for seed in seeds]
    chash = _results_hash(cfg, inputs.data_id, inputs.object_id, inputs.y)
    tasks, groups = [], []
    for tc, obj, seed in pairs:
        keys = []
        extra = {} if obj is None else {"test_object": obj}
        for strat, name in zip(strategies, names):
            key = {"experiment": "active_sampling", "strategy": name, "test_class": tc, **extra,
                   "seed": seed, "config": chash}
            tasks.append({"strategy": strat, "test_class": tc, "seed": seed, "key": key})
            keys.append(key)
        # one task per (test object, seed): the paired strategies share the initial training
        groups.append({"strategies": list(strategies), "test_class": tc, "seed": seed, "keys": keys, **extra})
    common = {"X": inputs.X, "y": inputs.y, "hardness": inputs.hardness, "cfg": cfg,
              "model": model, "n_classes": n_classes,
              "target_names": [str(n) for n in inputs.target_names]}
    if by_object:
        common["groups"] = inputs.object_id.astype(str)
    store = ResultsStore(results_path)
    run_tasks(_active_pair, groups, common, store, n_jobs=n_jobs, verbose=verbose, desc="active sampling",
              group_field="strategies")

    def run_id(key):
        return key["strategy"], key["test_class"], key.get("test_object"), key["seed"]

    order = {run_id(t["key"]): i for i, t in enumerate(tasks)}
    records = [r for r in store.records if r["key"].get("experiment") == "active_sampling"
               and r["key"].get("config") == chash and run_id(r["key"]) in order]
    records.sort(key=lambda r: order[run_id(r["key"])])
    cfg = dict(cfg, target_names=[str(n) for n in inputs.target_names],
               hardness=None if inputs.hardness is None else inputs.hardness.tolist(),
               hardness_unit=inputs.hardness_unit, strategies=names, config_hash=chash,
               dataset=_dataset_name(dataset), protocol="object-disjoint" if by_object else "class")
    return ExperimentResult(records, config=cfg, path=None if results_path is None else str(results_path))
