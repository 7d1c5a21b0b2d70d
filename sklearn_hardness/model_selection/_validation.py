"""Object-disjoint evaluation: the engine (folds, fits, scores, progress) of :func:`evaluate_pipelines`.

The paper tests on new presses of the *same* objects. A user with their own
objects needs the other question answered: how well does a pipeline rank the
hardness of an object it has never seen? :func:`evaluate_pipelines` answers
it with folds that keep every object's presses together, and runs each
pipeline beside the one-number baseline. It behaves as
:func:`sklearn.model_selection.cross_validate` does, for several estimators
on the same folds: the same validation whatever ``n_jobs``, ``cv`` and
``scoring`` as it takes them, the same failures. What the results say
(intervals, margins, the recommendation, the text) is :mod:`._report`.
"""

from __future__ import annotations

import numbers
import time
import warnings

import numpy as np
from sklearn.base import clone
from sklearn.exceptions import FitFailedWarning
from sklearn.metrics import balanced_accuracy_score, get_scorer
from sklearn.pipeline import Pipeline
from sklearn.utils import _safe_indexing
from sklearn.utils.parallel import Parallel, delayed

from ..metrics import hardness_mae
from ..models import make_named_pipeline, pipeline_info, pipeline_names
from ..utils._param_validation import Interval, StrOptions, validate_params
from ..utils._progress import ProgressLog
from ..utils._random import int_seed
from ..utils._unreadable import raise_unreadable
from ..utils._warnings import external_stacklevel
from ._per_press import first_input, per_press_inputs
from ._result import EvaluationResult
from ._split import RepeatedStratifiedGroupKFold

__all__ = ["evaluate_pipelines"]

#: The scores that need what a scorer ``(estimator, X, y)`` is not given (the presses' objects, the classes'
#: hardness), by name: what ``scoring=None`` computes, and names ``scoring`` takes beside scikit-learn's.
OWN_SCORERS = ("balanced_accuracy", "object_balanced_accuracy", "neg_hardness_mae")


def _check_scoring(scoring, hardness):
    """``{name: scorer}`` of ``scoring`` (our names stay names) and whether the result keys carry the names."""
    if scoring is None:
        names = OWN_SCORERS if hardness is not None else OWN_SCORERS[:2]
        return {name: name for name in names}, True
    if isinstance(scoring, str) or callable(scoring):
        return {"score": _scorer(scoring, hardness)}, False
    if isinstance(scoring, (list, tuple, set)):
        if not scoring or not all(isinstance(s, str) for s in scoring) or len(set(scoring)) != len(scoring):
            raise ValueError(f"scoring as a list must hold distinct scorer names; got {scoring!r}.")
        return {s: _scorer(s, hardness) for s in scoring}, True
    if not scoring or not all(isinstance(k, str) for k in scoring):
        raise ValueError(f"scoring as a dict must map names (str) to scorers; got {scoring!r}.")
    return {k: _scorer(v, hardness) for k, v in scoring.items()}, True


def _scorer(scoring, hardness):
    if isinstance(scoring, str) and scoring in OWN_SCORERS:
        if scoring == "neg_hardness_mae" and hardness is None:
            raise ValueError("scoring 'neg_hardness_mae' needs hardness, the hardness of each class.")
        return scoring
    if callable(scoring):
        return scoring
    return get_scorer(scoring)  # its error lists the names scikit-learn knows


def _class_proba(estimator, X, pred, n_classes):
    """Probabilities of classes ``0 .. n_classes - 1`` per press: ``predict_proba``, else the prediction's vote."""
    if not hasattr(estimator, "predict_proba"):
        return np.eye(n_classes)[pred]
    found = np.asarray(estimator.predict_proba(X))
    classes = getattr(estimator, "classes_", np.arange(found.shape[1]))
    proba = np.zeros((len(pred), n_classes))
    proba[:, np.asarray(classes, dtype=int)] = found
    return proba


def _per_object(proba, y, objects):
    """Each object's label and predicted class: the class of the mean of its presses' probabilities."""
    _, first, index = np.unique(objects, return_index=True, return_inverse=True)
    total = np.zeros((len(first), proba.shape[1]))
    np.add.at(total, index, proba)
    return y[first], np.argmax(total, axis=1)  # an object's presses share its label


def _scores(estimator, X, y, objects, scorers, hardness, n_classes):
    """Each scorer's score of ``estimator`` on ``(X, y)``, and its predictions (ours share them)."""
    pred = np.asarray(estimator.predict(X))
    out = {}
    for name, scorer in scorers.items():
        if scorer == "balanced_accuracy":
            out[name] = balanced_accuracy_score(y, pred)
        elif scorer == "object_balanced_accuracy":
            out[name] = balanced_accuracy_score(*_per_object(_class_proba(estimator, X, pred, n_classes), y, objects))
        elif scorer == "neg_hardness_mae":
            out[name] = -hardness_mae(y, pred, hardness)
        else:
            out[name] = scorer(estimator, X, y)
    return {name: float(score) for name, score in out.items()}, pred


def _fold_params(params, train, n_samples):
    """``params`` for a fit on ``train``: values with one entry per press are indexed, others passed whole."""
    return {key: (_safe_indexing(value, train) if _per_sample(value, n_samples) else value)
            for key, value in params.items()}


def _per_sample(value, n_samples):
    """Whether ``value`` has one entry per press (as scikit-learn's ``cross_validate`` indexes its ``params``)."""
    if isinstance(value, (str, bytes, dict)) or not hasattr(value, "__len__"):
        return False
    return len(value) == n_samples


def _fit_and_score(estimator, X, y, objects, train, test, scorers, hardness, n_classes, error_score, params,
                   return_train_score, return_estimator):
    """One fit on ``train``, scored on ``test``: ``cross_validate``'s fit and score, with the predictions kept."""
    out = {"error": None, "fit_failed": False, "pred": None, "estimator": None, "train_scores": {}}
    t0 = time.perf_counter()
    try:
        with warnings.catch_warnings():
            # each fold would repeat the steps' warnings (weak contacts, lost tracks): the notes say them once
            warnings.simplefilter("ignore", UserWarning)
            est = clone(estimator).fit(_safe_indexing(X, train), y[train], **_fold_params(params, train, len(y)))
    except Exception as exc:
        if error_score == "raise":
            raise
        out.update(fit_time=time.perf_counter() - t0, score_time=0.0, error=f"{type(exc).__name__}: {exc}",
                   fit_failed=True, test_scores=dict.fromkeys(scorers, error_score))
        if return_train_score:
            out["train_scores"] = dict.fromkeys(scorers, error_score)
        return out
    out["fit_time"] = time.perf_counter() - t0
    t0 = time.perf_counter()
    try:
        with warnings.catch_warnings():
            warnings.simplefilter("ignore", UserWarning)
            out["test_scores"], out["pred"] = _scores(est, _safe_indexing(X, test), y[test], objects[test], scorers,
                                                      hardness, n_classes)
            if return_train_score:
                out["train_scores"] = _scores(est, _safe_indexing(X, train), y[train], objects[train], scorers,
                                              hardness, n_classes)[0]
    except Exception as exc:
        if error_score == "raise":
            raise
        warnings.warn(f"Scoring failed. The score on this train-test partition is set to {error_score}. "
                      f"Details: {type(exc).__name__}: {exc}", UserWarning, stacklevel=external_stacklevel())
        out["error"] = f"{type(exc).__name__}: {exc}"
        out["test_scores"] = dict.fromkeys(scorers, error_score)
        if return_train_score:
            out["train_scores"] = dict.fromkeys(scorers, error_score)
    out["score_time"] = time.perf_counter() - t0
    if return_estimator:
        out["estimator"] = est
    return out


def _seconds_left(fit_seconds, n_fits, n_workers):
    """Estimated seconds until every timed pipeline has its ``n_fits`` fits, and the pipelines not timed yet.

    Each fit left counts as long as its pipeline's finished fits on average
    (a net's fit can last a thousand times the baseline's). The estimate is the
    longer of that work shared among ``n_workers`` and the longest fit left.
    A pipeline with no finished fit has no time to go by: it is left out of
    the estimate and named in the second value, for the line to say so.
    """
    left = [(n_fits - len(times), float(np.mean(times))) for times in fit_seconds.values()
            if times and len(times) < n_fits]
    untimed = [name for name, times in fit_seconds.items() if not times]
    if not left:
        return 0.0, untimed
    return max(sum(n * t for n, t in left) / max(n_workers, 1), max(t for _, t in left)), untimed


def _indexed(j, func, *args):
    return j, func(*args)


def _run_folds(rests, inputs, y, objects, folds, scorers, hardness, n_classes, error_score, params,
               return_train_score, return_estimator, n_jobs, verbose):
    """Every (pipeline, fold) fit's outcome, by pipeline, in the folds' order."""
    from joblib import effective_n_jobs

    # fold by fold, so that each pipeline's first fit ends early and times the rest of its fits
    jobs = [(name, k) for k in range(len(folds)) for name in rests]
    progress = ProgressLog(len(jobs), desc="evaluate", verbose=verbose, unit="fits")
    fit_seconds, n_workers = {name: [] for name in rests}, effective_n_jobs(n_jobs)
    outs = [None] * len(jobs)
    calls = (delayed(_indexed)(j, _fit_and_score, rests[name], inputs[name], y, objects, folds[k][0], folds[k][1],
                               scorers, hardness, n_classes, error_score, params.get(name) or {},
                               return_train_score, return_estimator)
             for j, (name, k) in enumerate(jobs))
    # one fit a batch: joblib's automatic batching, timed on the quick fits of the baseline, would
    # otherwise queue several slow fits (a net's) in one batch on one worker while the others wait
    for j, out in Parallel(n_jobs=n_jobs, return_as="generator_unordered", batch_size=1)(calls):
        outs[j] = out
        fit_seconds[jobs[j][0]].append(out["fit_time"] + out["score_time"])
        seconds, untimed = _seconds_left(fit_seconds, len(folds), n_workers)
        progress.update(1, seconds, f"not counting {', '.join(untimed)} (no fit finished yet)" if untimed else None)
    return {name: [o for (n, _), o in zip(jobs, outs) if n == name] for name in rests}


def _warn_or_raise_about_fit_failures(outs, error_score):
    """As scikit-learn's searches: raise where every fit failed, else warn how many did, with their errors."""
    errors = [(name, o["error"]) for name, rows in outs.items() for o in rows if o["fit_failed"]]
    n_fits = sum(len(rows) for rows in outs.values())
    if not errors:
        return
    counts = {}
    for name, error in errors:
        counts[(name, error)] = counts.get((name, error), 0) + 1
    details = "\n".join(f"{n} fits of {name!r} failed with the following error:\n{error}"
                        for (name, error), n in counts.items())
    if len(errors) == n_fits:
        raise ValueError(f"All the {n_fits} fits failed.\nIt is very likely that your model is misconfigured.\n"
                         "You can try to debug the error by setting error_score='raise'.\n\n"
                         f"Below are more details about the failures:\n{details}")
    warnings.warn(f"\n{len(errors)} fits failed out of a total of {n_fits}.\nThe score on these train-test "
                  f"partitions for these parameters will be set to {error_score}.\nIf these failures are not "
                  "expected, you can try to debug them by setting error_score='raise'.\n\n"
                  f"Below are more details about the failures:\n{details}", FitFailedWarning,
                  stacklevel=external_stacklevel())


def _cv_results(outs, folds, n_splits, scorers, multimetric, seconds_once, return_train_score, return_estimator,
                prefixes):
    """``cv_results_``: one entry per (pipeline, fold), pipeline by pipeline, as arrays."""
    rows = [(name, k, o) for name, fold_outs in outs.items() for k, o in enumerate(fold_outs)]

    def objects(values):
        out = np.empty(len(values), dtype=object)
        out[:] = values
        return out

    results = {
        "pipeline": objects([name for name, _, _ in rows]),
        "split": np.array([k for _, k, _ in rows], dtype=int),
        "repeat": np.array([k // n_splits for _, k, _ in rows], dtype=int),
        "fit_time": np.array([o["fit_time"] for _, _, o in rows]),
        "score_time": np.array([o["score_time"] for _, _, o in rows]),
        # the once-per-run pass of the pipeline's per-press steps, shared out equally over its folds
        "per_press_time": np.array([seconds_once[name] / len(folds) for name, _, _ in rows]),
    }
    for key, which in [("test", "test_scores"), ("train", "train_scores")]:
        if key == "train" and not return_train_score:
            continue
        for scorer in scorers:
            column = f"{key}_{scorer}" if multimetric else f"{key}_score"
            results[column] = np.array([o[which][scorer] for _, _, o in rows], dtype=float)
    results["train_indices"] = objects([folds[k][0] for _, k, _ in rows])
    results["test_indices"] = objects([folds[k][1] for _, k, _ in rows])
    results["test_predictions"] = objects([o["pred"] for _, _, o in rows])
    results["error"] = objects([o["error"] for _, _, o in rows])
    if return_estimator:
        results["estimator"] = objects([_whole(prefixes[name], o["estimator"]) for name, _, o in rows])
    return results


def _whole(prefix, fitted):
    """The fitted pipeline of a fold: its per-press steps (fitted once, shared by the folds) and its fitted rest."""
    if fitted is None or prefix is None:
        return fitted
    return Pipeline(prefix.steps + fitted.steps)


@validate_params(
    {
        "estimators": [dict, list, tuple, None],
        "X": "no_validation",
        "y": ["array-like"],
        "groups": ["array-like", None],
        "scoring": [str, callable, list, tuple, set, dict, None],
        "cv": ["cv_object"],
        "n_repeats": [Interval(numbers.Integral, 1, None, closed="left")],
        "baseline": [str, tuple, None],
        "target_names": ["array-like", None],
        "objects": ["array-like", None],
        "hardness": ["array-like", None],
        "force_position": [list, tuple, None],
        "params": [dict, None],
        "error_score": [StrOptions({"raise"}), numbers.Real],
        "return_train_score": ["boolean"],
        "return_estimator": ["boolean"],
        "n_jobs": [numbers.Integral, None],
        "random_state": ["random_state"],
        "verbose": ["verbose"],
    },
    prefer_skip_nested_validation=False,  # the estimators are not validated yet: their fit does it, in every fold
)
def evaluate_pipelines(estimators, X, y, *, groups=None, scoring=None, cv=5, n_repeats=1, baseline="peak_change",
                       target_names=None, objects=None, hardness=None, force_position=None, params=None,
                       error_score=np.nan, return_train_score=False, return_estimator=False, n_jobs=None,
                       random_state=None, verbose=0):
    """Cross-validate press pipelines on the same group-disjoint folds, each beside a baseline.

    :func:`sklearn.model_selection.cross_validate` for several estimators at
    once: every pipeline sees the same folds, and its margin over the
    baseline (the one-number pipeline ``"peak_change"``,
    :func:`~sklearn_hardness.models.make_peak_change_baseline`) is paired by
    fold. An integer ``cv`` makes folds that keep every group's presses
    together (:class:`RepeatedStratifiedGroupKFold`), so the scores say how
    a pipeline does on new objects. The leading steps that turn each press
    into its row by that press alone (the per-press steps: frame selection,
    frozen features, the peak change) run once over all presses, not once
    per fold, shared by the pipelines that start with them: the same scores
    for less work. As in ``cross_validate``, the estimators are validated
    by their own ``fit`` in every fold whatever ``n_jobs``, a failing fit
    scores ``error_score``, and where every fit fails the call raises. How
    to read the results: ``docs/user_guide/recording.rst``.

    Parameters
    ----------
    estimators : dict, list or None
        ``{name: estimator}``, a list of registry names
        (:func:`~sklearn_hardness.models.pipeline_names`, built by
        :func:`~sklearn_hardness.models.make_named_pipeline` seeded by
        ``random_state``) or ``(name, estimator)`` pairs. None: the default
        pipelines (those whose ``pipeline_info(name).default`` is True), and ``"loading_compliance"``
        where ``force_position`` is given.
    X : sequence of videos
        One press per entry: a list of ``(T, H, W, 3)`` arrays or a lazy
        sequence (a dataset's ``videos``).
    y : array-like of shape (n_presses,)
        Labels: class indices into ``target_names``, or any labels (then
        encoded as indices of their sorted unique values).
    groups : array-like of shape (n_presses,) or None, default=None
        The group of each press (its object, or its family of objects):
        no group is on both sides of a fold. Needed with an integer ``cv``.
    scoring : str, callable, list, tuple, set, dict or None, default=None
        As ``cross_validate``'s: a scorer name or callable ``(estimator, X,
        y)`` gives ``cv_results_["test_score"]``; a list, tuple, set or dict
        of them ``cv_results_["test_<name>"]``. Beside scikit-learn's names,
        ``"object_balanced_accuracy"`` (each test object classed by the mean
        of its presses' probabilities, or their votes without
        ``predict_proba``) and ``"neg_hardness_mae"`` (the negative hardness
        MAE of the predictions; needs ``hardness``). None:
        ``"balanced_accuracy"``, ``"object_balanced_accuracy"`` and, with
        ``hardness``, ``"neg_hardness_mae"``.
    cv : int, cross-validation generator, iterable or None, default=5
        What :func:`~sklearn.model_selection.check_cv` takes. An integer (or
        None, 5) is the folds per repetition of
        :class:`RepeatedStratifiedGroupKFold` (stratified, group-disjoint);
        a splitter (anything with ``split(X, y, groups)``, e.g.
        :class:`~sklearn.model_selection.GroupKFold`) or an iterable of
        ``(train, test)`` index pairs gives its folds.
    n_repeats : int, default=1
        With an integer ``cv``: repetitions with other assignments of groups
        to folds. The means and intervals run over all folds, with the
        ``cv - 1`` degrees of freedom of one repetition. A splitter's own
        ``n_repeats`` attribute counts the same way.
    baseline : str, (name, estimator) or None, default="peak_change"
        The pipeline every other one is paired with (a registry name or a
        pair); added first where ``estimators`` lack it. None: no margins.
    target_names : array-like of shape (n_classes,) or None, default=None
        Class names, with ``y`` as indices into them.
    objects : array-like of shape (n_presses,) or None, default=None
        The object of each press, for the per-object scores. None:
        ``groups``, or each press by itself.
    hardness : array-like of shape (n_classes,) or None, default=None
        The hardness of each class (a dataset's ``hardness``), for the
        hardness MAE of the predictions.
    force_position : list of ndarray of shape (T, 2) or None, default=None
        Each press's force and position per frame: the input of the
        pipelines whose first per-press step reads them (a
        :class:`~sklearn_hardness.features.LoadingCompliance`).
    params : dict of str to dict or None, default=None
        Fit parameters per pipeline name, as ``cross_validate``'s ``params``:
        values with one entry per press are indexed to each fold's training
        presses. E.g. ``{"grid": {"groups": object_id}}`` gives a
        :class:`~sklearn.model_selection.GridSearchCV` named ``"grid"`` the
        training fold's groups, for nested selection.
    error_score : "raise" or float, default=np.nan
        What a failing fit scores: raise, or this value (with a
        :class:`~sklearn.exceptions.FitFailedWarning`; where every fit
        fails, a ValueError as ``cross_validate`` raises).
    return_train_score : bool, default=False
        Also score each fold's training presses (``train_<name>``).
    return_estimator : bool, default=False
        Keep each fold's fitted pipeline (``cv_results_["estimator"]``): its
        per-press steps, fitted once and shared by the folds, and the rest
        fitted on the fold.
    n_jobs : int or None, default=None
        Fits (and the chunks of the per-press pass) run in parallel through
        :class:`sklearn.utils.parallel.Parallel`, which carries
        scikit-learn's configuration into the workers; one fit to a task.
    random_state : int, RandomState instance or None, default=None
        Seed of an integer ``cv``'s fold assignment and of the pipelines
        given by name.
    verbose : int, default=0
        Progress on stderr: one line per finished fit with an estimate of
        the time left.

    Returns
    -------
    result : EvaluationResult
        ``cv_results_``, a dict of arrays with one entry per (pipeline,
        fold) that :class:`pandas.DataFrame` takes as is, and what it says
        (``summary``, ``recommended``, the notes, the text).

    Raises
    ------
    ValueError
        Where every fit failed ("All the N fits failed"), a class with fewer
        groups than an integer ``cv``, an unknown pipeline name, lengths
        that disagree, or a force/position pipeline without
        ``force_position``. Also, before any fit, videos that cannot be
        read and (with ``error_score="raise"``) presses on which a
        pipeline's per-press steps fail, each listed.

    See Also
    --------
    EvaluationResult, ConfusionMatricesDisplay, corrected_interval

    Examples
    --------
    >>> from sklearn.model_selection import GroupKFold
    >>> from sklearn_hardness.datasets import make_presses
    >>> from sklearn_hardness.model_selection import evaluate_pipelines
    >>> data = make_presses("everyday", n_per_class=2, n_objects=9, class_ratio=[1, 1, 1],
    ...                     image_size=(32, 40), codec=None, random_state=0)
    >>> result = evaluate_pipelines([], data.videos, data.target, groups=data.object_id,
    ...                             cv=GroupKFold(3), target_names=data.target_names)
    >>> sorted(result.cv_results_)[:4]
    ['error', 'fit_time', 'per_press_time', 'pipeline']
    >>> result.cv_results_["test_balanced_accuracy"].shape, result.summary["pipeline"]
    ((3,), ['peak_change'])
    """
    seed = int_seed(random_state)
    named, base = _named_estimators(estimators, baseline, seed, force_position)
    y, groups, target_names = _check_targets(X, y, groups, target_names)
    objects = np.asarray(objects) if objects is not None else groups if groups is not None else np.arange(len(y))
    folds, n_splits, n_repeats = _folds(cv, n_repeats, X, y, groups, target_names, random_state)
    hardness = None if hardness is None else np.asarray(hardness, dtype=float)
    scorers, multimetric = _check_scoring(scoring, hardness)
    log = ProgressLog(0, desc="evaluate", verbose=verbose)  # messages; the fits get their own below
    log.write(f"{len(named)} pipeline(s) ({', '.join(named)}) x {len(folds)} folds on {len(y)} presses of "
              f"{len(np.unique(objects))} objects")
    inputs = _inputs(named, X, force_position)
    keys = getattr(X, "keys", None)
    paths = keys if isinstance(keys, list) and keys and all(isinstance(k, str) for k in keys) else None
    inputs, rests, prefixes, seconds_once, notes = per_press_inputs(
        named, inputs, n_jobs, log, error_score, paths,
        check_readable=lambda presses, exc: raise_unreadable(presses, exc) if presses is X else None)
    outs = _run_folds(rests, inputs, y, objects, folds, scorers, hardness, len(target_names), error_score,
                      params or {}, return_train_score, return_estimator, n_jobs, verbose)
    _warn_or_raise_about_fit_failures(outs, error_score)
    if return_estimator:
        prefixes = {name: _fitted_prefix(prefix, inputs_of(named[name], X, force_position))
                    for name, prefix in prefixes.items()}
    cv_results = _cv_results(outs, folds, n_splits, scorers, multimetric, seconds_once, return_train_score,
                             return_estimator, prefixes)
    return EvaluationResult(cv_results_=cv_results, estimators=named, baseline=base, notes=notes, target=y,
                            target_names=target_names, groups=objects if groups is None else groups, objects=objects,
                            n_splits=n_splits, n_repeats=n_repeats)


def inputs_of(estimator, X, force_position):
    """The presses ``estimator`` reads: ``force_position`` where its first per-press step reads them, else ``X``."""
    return force_position if first_input(estimator) == "force_position" else X


def _fitted_prefix(prefix, presses):
    """``prefix`` fitted once, on the first press (its steps learn nothing from the presses), or None."""
    if prefix is None:
        return None
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", UserWarning)
        return clone(prefix).fit(_safe_indexing(presses, [0]))


def _inputs(named, X, force_position):
    """Each pipeline's presses; an error where a pipeline reads force and position that were not given."""
    reads_force = [name for name, est in named.items() if first_input(est) == "force_position"]
    if reads_force and force_position is None:
        raise ValueError(f"pipeline(s) {reads_force} read each press's force and position per frame: pass "
                         "force_position, one (T, 2) array of force and position per press.")
    if force_position is not None and len(force_position) != len(X):
        raise ValueError(f"force_position has {len(force_position)} entries for {len(X)} presses.")
    return {name: inputs_of(est, X, force_position) for name, est in named.items()}


def _named_estimators(estimators, baseline, seed, force_position):
    """``{name: estimator}`` of ``estimators`` (dict, names, pairs or None), the baseline first; its name."""
    if estimators is None:
        estimators = [name for name in pipeline_names() if pipeline_info(name).default] + (
            ["loading_compliance"] if force_position is not None else [])
    items = estimators.items() if isinstance(estimators, dict) else estimators
    named = {}
    for item in items:
        if isinstance(item, str):
            if item not in pipeline_names():
                raise ValueError(f"unknown pipeline {item!r}; choose among {list(pipeline_names())} or pass "
                                 "(name, estimator) pairs or a dict {name: estimator}.")
            item = (item, make_named_pipeline(item, random_state=seed))
        if not (isinstance(item, tuple) and len(item) == 2 and hasattr(item[1], "fit")):
            raise ValueError(f"estimators must be a dict {{name: estimator}}, registry names or (name, estimator) "
                             f"pairs; got {item!r}.")
        named[str(item[0])] = item[1]
    base = _baseline(baseline, seed)
    if base is not None and base[0] not in named:
        named = {base[0]: base[1], **named}
    if not named:
        raise ValueError("no pipelines to evaluate.")
    return named, (None if base is None else base[0])


def _baseline(baseline, seed):
    """``(name, estimator)`` of ``baseline`` (a registry name, a pair or None)."""
    if baseline is None:
        return None
    if isinstance(baseline, str):
        if baseline not in pipeline_names():
            raise ValueError(f"unknown baseline {baseline!r}; choose among {list(pipeline_names())} or pass a "
                             "(name, estimator) pair.")
        return baseline, make_named_pipeline(baseline, random_state=seed)
    if isinstance(baseline, tuple) and len(baseline) == 2 and hasattr(baseline[1], "fit"):
        return str(baseline[0]), baseline[1]
    raise ValueError(f"baseline must be a registry name, a (name, estimator) pair or None; got {baseline!r}.")


def _check_targets(X, y, groups, target_names):
    """``y`` as class indices, the groups and the class names; errors where lengths disagree."""
    y = np.asarray(y)
    if len(X) != len(y):
        raise ValueError(f"X has {len(X)} presses but y has {len(y)} labels.")
    if target_names is None:
        target_names, y = np.unique(y, return_inverse=True)
    else:
        target_names = np.asarray(target_names)
        if not np.issubdtype(y.dtype, np.integer) or y.min() < 0 or y.max() >= len(target_names):
            raise ValueError(f"with target_names, y must be class indices in [0, {len(target_names)}).")
    if groups is not None:
        groups = np.asarray(groups)
        if len(groups) != len(y):
            raise ValueError(f"groups has {len(groups)} entries for {len(y)} presses: give the group of each press.")
    return y, groups, target_names


def _check_group_counts(y, groups, target_names, cv):
    """Errors where a class has fewer groups than folds (an integer ``cv``), saying what to do."""
    if groups is None:
        raise ValueError("an integer cv makes folds grouped by object: pass groups (the object of each press; "
                         "a manifest's object_id column), or a splitter as cv.")
    objects_per_class = [len(np.unique(groups[y == c])) for c in range(len(target_names))]
    counts = dict(zip(np.asarray(target_names).tolist(), objects_per_class))
    if min(objects_per_class) < 2:
        nameless = np.array_equal(groups.astype(str), np.asarray(target_names)[y].astype(str))
        raise ValueError(
            f"object-disjoint folds need at least 2 objects of every class; the dataset has {counts}"
            + ("; it names no objects (a manifest without an object_id column counts every label as one "
               "object): add an object_id column saying which physical object each press is of."
               if nameless else ": record more objects of those classes."))
    short = [str(target_names[c]) for c, n in enumerate(objects_per_class) if n < cv]
    if short:
        raise ValueError(f"classes {short} have fewer than cv={cv} objects ({counts}); lower cv to at most "
                         f"{min(objects_per_class)}.")


def _folds(cv, n_repeats, X, y, groups, target_names, random_state):
    """The folds ``(train, test)`` of ``cv`` and the number of folds a repetition, repetitions."""
    from sklearn.model_selection import check_cv

    if cv is None:
        cv = 5
    if isinstance(cv, numbers.Integral) and not isinstance(cv, bool):
        if cv < 2:
            raise ValueError(f"cv must be at least 2, got {cv}.")
        _check_group_counts(y, groups, target_names, cv)
        cv = RepeatedStratifiedGroupKFold(n_splits=cv, n_repeats=n_repeats, random_state=random_state)
    else:
        cv = check_cv(cv, y, classifier=True)
    folds = [(np.asarray(train), np.asarray(test)) for train, test in cv.split(np.zeros(len(y)), y, groups)]
    if not folds:
        raise ValueError("cv gives no folds.")
    repeats = int(getattr(cv, "n_repeats", 1))
    if groups is not None and any(set(groups[train]) & set(groups[test]) for train, test in folds):
        warnings.warn("cv puts presses of one group on both sides of a fold: the scores are not those of new "
                      "objects. Use a group-aware splitter (GroupKFold, StratifiedGroupKFold) or an integer cv.",
                      UserWarning, stacklevel=external_stacklevel())
    return folds, max(len(folds) // repeats, 1), repeats

