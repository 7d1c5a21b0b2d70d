"""One run of the active-sampling experiment (Algorithm 1): split, initial training, the query loop.

A run is identified by (strategy, test object, seed); :func:`_active_pair`
runs every strategy of one (test object, seed) from one trained initial model.
:mod:`._active` plans the runs and collects their records.
"""

from __future__ import annotations

import copy
import warnings
import zlib

import numpy as np

from ..active import ActiveLearner, PressOracle, class_uncertainty
from ..metrics import hardness_mae
from ..models import is_converged
from ._models import input_scaler, make_estimator


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


def _uncertainty(learner, X_test, seed):
    proba = learner.predict_proba_samples(X_test, random_state=seed)
    return {k: class_uncertainty(proba, k) for k in ("entropy", "variance", "bald")}


def _evaluate(learner, X_test, y_test, hardness):
    pred = learner.predict(X_test)
    acc = float(np.mean(pred == y_test))
    mae = None if hardness is None else hardness_mae(y_test, pred, hardness)
    return acc, mae, pred


def _input_scaler(X_train, cfg, model):
    """The model's input scaler fitted on the run's initial training presses (None if unscaled).

    The factory's ``"scale"`` step (:func:`~._models.input_scaler`): fitted
    once per run on its initial training presses only, never on the test
    object's or the held-out presses, and kept for the run.
    """
    scaler = input_scaler(model, cfg)
    return None if scaler is None else scaler.fit(X_train)


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


def _split_objects(y, groups, cfg, n_classes, test_object, split_seed, family=None):
    """The object-disjoint split: test presses of one object, held-out presses of unseen objects.

    The test presses are ``n_test`` presses of ``test_object`` (all of them if
    it has fewer); none of its other presses is used. With ``family`` (the
    whole object each press's object is a part of), no press of the test
    object's family is used either: the handle is not a reference object when
    the bristles of the same brush are the test object. For ``n_holdout``, the
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
    used = groups == test_object if family is None else family == family[own[0]]
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


def _initial_state(X, y, cfg, model, n_classes, test_class, seed, strategy, groups=None, test_object=None,
                   family=None):
    """What the paired runs of one (test object, seed) share: split, oracle, initial training."""

    split_seed, oracle_seed, learner_seed, model_seed, mc_seed = _seeds(seed, test_class, 5, test_object)
    if test_object is None:
        test_idx, holdout_idx, pool = _split(y, cfg, n_classes, test_class, split_seed)
        oracle = PressOracle(pool, y[pool], random_state=oracle_seed)
    else:
        test_idx, holdout_idx, pool = _split_objects(y, groups, cfg, n_classes, test_object, split_seed, family)
        # a robot can press a reference object again: a replay reuses its recorded presses once
        # every reference object of the class is pressed out (n_repeated_presses in the record)
        oracle = PressOracle(pool, y[pool], groups=groups[pool], random_state=oracle_seed,
                             on_exhausted="recycle")
    init_idx, y0 = oracle.initial(cfg["n_initial"])
    scale = _input_scaler(X[init_idx], cfg, model)

    learner = ActiveLearner(
        make_estimator(model, cfg, model_seed, n_classes),
        strategy,
        initial_epochs=cfg["initial_epochs"],
        epochs_per_query=cfg["epochs_per_query"],
        max_reservoir=cfg["max_reservoir"],
        n_samples=cfg["n_samples"],
        classes=np.arange(n_classes),
        random_state=learner_seed,
    )
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", UserWarning)
        learner.fit(_rows(X, init_idx, scale), y0)
    return {"learner": learner, "oracle": oracle, "scale": scale, "test_idx": test_idx,
            "holdout_idx": holdout_idx, "init_idx": init_idx, "mc_seed": mc_seed}


def _rows(X, idx, scale):
    return X[idx] if scale is None else scale.transform(X[idx])


def _continue_run(X, y, hardness, cfg, n_classes, target_names, test_class, state, strategy,
                  test_object=None):
    """The queries of one strategy from a trained initial state. Returns the record."""

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
                groups=None, test_object=None, family=None):
    """One run: (strategy, test object, seed), trained from scratch. Returns the record (without provenance)."""
    state = _initial_state(X, y, cfg, model, n_classes, test_class, seed, strategy, groups, test_object, family)
    return _continue_run(X, y, hardness, cfg, n_classes, target_names, test_class, state, strategy,
                         test_object)


def _active_pair(X, y, hardness, cfg, model, n_classes, target_names, strategies, test_class, seed, keys,
                 groups=None, test_object=None, family=None):
    """The paired runs of one (test object, seed): the initial model is trained once and copied.

    Each strategy continues from a deep copy of the trained learner and of
    the oracle (weights, optimizer state, random generators), so its record
    equals that of :func:`_active_run` with the same arguments.
    """
    state = _initial_state(X, y, cfg, model, n_classes, test_class, seed, strategies[0], groups, test_object,
                           family)
    records = []
    for i, strategy in enumerate(strategies):
        run_state = state if i == len(strategies) - 1 else copy.deepcopy(state)
        records.append(_continue_run(X, y, hardness, cfg, n_classes, target_names, test_class,
                                     run_state, strategy, test_object))
    return records
