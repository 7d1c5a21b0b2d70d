"""The paper's active-sampling experiment (Sec. III-F, Algorithm 1): which runs, and their results.

One run is :mod:`._run`; this module plans the (strategy, test object, seed)
runs of a dataset, runs them (in parallel, resumably) and collects them.
"""

from __future__ import annotations

import numbers

import joblib
import numpy as np

from ..active import check_strategies
from ._config import config_hash, resolve_convergence_threshold, run_config
from ._data import prepare_inputs
from ._names import STRATEGIES
from ._results import ExperimentResult, ResultsStore
from ._run import _active_pair, _seeds, _split_objects
from ._runner import run_tasks

__all__ = ["run_active_sampling", "STRATEGIES"]


def _has_objects(object_id, y):
    """True when some class has presses of more than one object (the object-disjoint protocol)."""
    if object_id is None:
        return False
    return any(np.unique(object_id[y == c]).size > 1 for c in np.unique(y))


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
            _split_objects(y, groups, cfg, inputs.n_classes, obj, _seeds(seed, tc, 1, obj)[0], _family(inputs))
            pairs.append((tc, obj, seed))
    return pairs


def _dataset_name(dataset):
    """What a table's header calls the dataset: the preset, the manifest's path or "a Bunch"."""
    if isinstance(dataset, str) or hasattr(dataset, "__fspath__"):
        return str(dataset)
    return "a Bunch"


def _family(inputs):
    """The family of each press as str where it groups some objects together, else None."""
    family = inputs.get("family")
    if family is None or inputs.object_id is None:
        return None
    family = np.asarray(family).astype(str)
    return None if np.unique(family).size == np.unique(inputs.object_id).size else family


def _results_hash(cfg, data_id, object_id, y, family=None):
    """The config hash that keys a run's records: object-disjoint runs also hash the protocol and objects.

    Class-level results (no object ids, or one object per class) keep the hash they had
    before the object-disjoint protocol existed; object-disjoint runs without families
    keep theirs.
    """
    if _has_objects(object_id, y):
        extra = {} if family is None else {"families": joblib.hash(family.tolist())}
        protocol = "object-disjoint" if family is None else "family-disjoint"
        return config_hash(dict(cfg, data=data_id, n_runs=None, protocol=protocol,
                                objects=joblib.hash(object_id.astype(str).tolist()), **extra))
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
    The model's input scaling, its factory's ``"scale"`` step (the ConvLSTM's
    per-channel frame scaler with ``input_scale="std"``,
    the contact profile's ``StandardScaler``), is fitted on the run's initial
    training presses.

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
    ``test_objects``) and seeds; a pair is (test object, seed). **Families**:
    where the dataset also gives each press's ``family`` (the whole object a
    part belongs to: ``load_physiclear``'s ``family``, or a manifest's
    ``family`` column) and some family holds several objects, the runs are
    family-disjoint: no press of the test object's family (its sibling parts,
    pressed in one sitting, of the same maker's materials) is in the pool or
    held out either (``protocol="family-disjoint"`` in the result's config). A class
    without enough objects or presses for this is a ``ValueError`` before any
    run. Without object ids, or with one object per class (``silicone5``,
    ``shore9``), the test object is the class, as above, and splits, records
    and configuration hashes are those of earlier versions.

    Following the paper, a run whose training loss after the initial training
    exceeds ``convergence_threshold`` is reported as not converged and not
    continued. ``"auto"``: the paper's 1.0 for the ConvLSTM at 5 classes
    (``silicone5``), the same fraction of chance loss at K classes
    (:func:`~sklearn_hardness.models.is_converged` with ``threshold="chance"``; 1.365 on
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
        Smaller images and frames, fewer epochs, MC passes and runs (the
        changes are listed by ``sklearn-hardness reproduce --help``).
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
        ``n_per_query``, ``n_iterations``, ``n_test``, ``n_holdout``, ``n_samples``,
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
        :meth:`ExperimentResult.comparison_table` and
        :meth:`ExperimentResult.plot_active_sampling`.

    Examples
    --------
    A tiny run (the real one uses the defaults)::

        from sklearn_hardness.experiments import run_active_sampling
        res = run_active_sampling("silicone5", quick=True, n_jobs=2,
                                  results_path="runs.jsonl")
        print(res.format_table(res.comparison_table()))
    """
    cfg, model = run_config(dataset, preset, model, n_runs, quick, config)
    strategies, names = check_strategies(strategies)
    # the factory's scale step is fitted per run on its training presses (_run._input_scaler)
    inputs = prepare_inputs(dataset, cfg, model, memory=memory, verbose=verbose, n_jobs=n_jobs)
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
    family = _family(inputs) if by_object else None
    chash = _results_hash(cfg, inputs.data_id, inputs.object_id, inputs.y, family)
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
    if family is not None:
        common["family"] = family
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
               dataset=_dataset_name(dataset),
               protocol="class" if not by_object else "object-disjoint" if family is None else "family-disjoint")
    return ExperimentResult(records, config=cfg, path=None if results_path is None else str(results_path))
