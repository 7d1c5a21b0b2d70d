"""Object-disjoint evaluation: cross-validation grouped by ``object_id``.

The paper tests on new presses of the *same* objects. A user with their own
objects needs the other question answered: how well does a pipeline rank the
hardness of an object it has never seen? :func:`evaluate_pipelines` answers
it with folds that keep every object's presses together
(:class:`~sklearn.model_selection.StratifiedGroupKFold`), and reports each
pipeline beside the one-number baseline of :func:`~sklearn_hardness.models.make_peak_change_baseline`.
"""

from __future__ import annotations

import numbers
import time
import warnings
from collections import Counter

import numpy as np
from joblib import Parallel, delayed, effective_n_jobs
from sklearn.base import BaseEstimator, clone
from sklearn.metrics import balanced_accuracy_score, confusion_matrix
from sklearn.pipeline import Pipeline
from sklearn.utils import _safe_indexing

from .._registry import PIPELINE_NAMES, default_pipelines, make_named_pipeline
from ..features import ConventionWarning, LoadingCompliance, OpticalFlowFeatures
from ..metrics import hardness_mae
from ..utils._intervals import _interval
from ..utils._param_validation import HasMethods, Interval, StrOptions, validate_params
from ..utils._progress import ProgressLog
from ..utils._random import int_seed
from ..utils._unreadable import raise_unreadable
from ._intervals import paired_difference
from ._per_press import FailingPressesError, all_columns, describe, prefix_key, split_per_press, transform_per_press
from ._result import EvaluationResult
from ._split import RepeatedStratifiedGroupKFold

__all__ = ["evaluate_pipelines"]


def _takes_force_position(estimator):
    """Whether ``estimator`` (or its first step) reads force and position per frame, not videos."""
    first = estimator.steps[0][1] if isinstance(estimator, Pipeline) else estimator
    return isinstance(first, LoadingCompliance)


class _FailedPerPress(BaseEstimator):
    """Stands in for a pipeline whose per-press steps fail on some presses: every fold fails at once.

    Each fold has every press in its training or its test presses, so each
    would meet the failing presses (after training a net, where they are
    among the test presses); this one fails at once with ``message``.
    """

    def __init__(self, message=""):
        self.message = message

    def fit(self, X, y=None):
        raise FailingPressesError(self.message)


def _failing_presses(prefix, failures, names, n_presses, paths, lines):
    """The presses on which the pass of ``prefix`` failed, by index and file, for ``names``' users.

    One press a line (for an error) where ``lines``, else all on one line (a note).
    """
    presses = [f"press {i}" + (f" ({paths[i]})" if paths is not None else "") + f": {message}"
               for i, message in failures]
    head = f"{', '.join(names)}: {describe(prefix)} fails on {len(presses)} of {n_presses} presses, each by itself:"
    return head + ("\n  " + "\n  ".join(presses) if lines else " " + "; ".join(presses))


def _per_press_inputs(named, X, n_jobs, log, error_score="raise", paths=None):
    """Run each pipeline's leading per-press steps once over all presses (:mod:`._per_press`).

    Returns, per name, the input its folds get (the rows of those steps, or
    the videos), the estimator they fit (the remaining steps, or the whole
    pipeline) and the seconds of the one pass (counted in full for every
    pipeline that uses its rows: what the pipeline would take alone); and
    the notes on the presses that the passes found (:func:`_contact_note`,
    :func:`_flow_note`; one for the pipelines whose steps found the same on
    every press).
    Pipelines with the same leading steps share one pass, and so do
    contact-profile steps that differ only in the features they output
    (:func:`all_columns`: each pipeline takes its columns). Where a pass
    fails on videos that cannot be read, one error lists them all
    (:func:`~sklearn_hardness.datasets._lazy.raise_unreadable`); where
    presses fail it by themselves (a one-frame video), one error lists them
    by index and ``paths`` (a :class:`FailingPressesError`), or, with a
    numeric ``error_score``, a note does and every fold of its pipelines
    fails at once; where it fails otherwise, its pipelines run whole in
    every fold, where ``error_score`` decides.
    """
    inputs, rests, seconds = {}, {}, {}
    passes = {}
    for name, est in named.items():
        prefix, rest = split_per_press(est)
        inputs[name], rests[name], seconds[name] = X, est, 0.0
        if prefix is not None:
            prefix, columns = all_columns(prefix)
            passes.setdefault(prefix_key(prefix), (prefix, []))[1].append((name, rest, columns))
    contacts, flows = [], []  # (what a pass found on every press, the pipelines whose pass found it)
    notes = []  # on presses that failed a pass
    checked = False  # whether every video was found readable
    for prefix, users in passes.values():
        names = [name for name, _, _ in users]
        log.write(f"{describe(prefix)} of every press, once for all folds ({', '.join(names)})")
        try:
            Xt, once, found = transform_per_press(prefix, X, n_jobs=n_jobs)
        except Exception as exc:  # noqa: BLE001 - the folds run the whole pipelines and report it
            if not checked:  # unless videos cannot be read: then every pipeline would fail on every fold
                raise_unreadable(X, exc)
                checked = True
            if isinstance(exc, FailingPressesError):  # every fold would fail: say on which presses, now
                if error_score == "raise":
                    raise FailingPressesError(
                        _failing_presses(prefix, exc.failures, names, len(X), paths, lines=True)
                        + "\nRemove their rows from the manifest or record them again; with error_score=np.nan, "
                        "evaluate_pipelines gives these pipelines an error and scores the others.",
                        exc.failures) from exc
                note = _failing_presses(prefix, exc.failures, names, len(X), paths, lines=False)
                notes.append(note)
                log.write(note)
                for name in names:
                    rests[name] = _FailedPerPress(f"{describe(prefix)} fails on {len(exc.failures)} of "
                                                  f"{len(X)} presses (the notes name them)")
            continue
        for name, rest, columns in users:
            inputs[name], rests[name], seconds[name] = (Xt if columns is None else Xt[:, columns]), rest, once
        if "contact_status" in found:
            _merge(contacts, (found["contact_status"],), names)
        if "flow_corners" in found:
            flow = next(step for _, step in prefix.steps if isinstance(step, OpticalFlowFeatures))
            _merge(flows, (found["flow_corners"], found["flow_tracks_lost"], int(flow.n_features)), names)
    found_notes = ([_contact_note(status, names) for (status,), names in contacts]
                   + [_flow_note(*found, names) for found, names in flows])
    for note in found_notes:
        log.write(note)
    return inputs, rests, seconds, found_notes + notes


def _merge(seen, found, names):
    """Add ``names`` to the entry of ``seen`` that found the same on every press, or a new entry."""
    for other, users in seen:
        if all(np.array_equal(a, b) for a, b in zip(other, found)):
            users += names
            return
    seen.append((found, list(names)))


def _contact_note(status, users):
    """What the contact-frame selection of ``users`` found: one line of counts per status.

    The folds fit with warnings silenced (each fold would repeat the
    selector's warning about the same presses); this line says it once.
    """
    status = np.asarray(status)
    n, count = len(status), Counter(status.tolist())  # 0 for a status not found
    found = count["contact"] + count["weak contact"]
    text = f"contact ({', '.join(users)}): found on {found} of {n} presses ({count['weak contact']} weak)"
    missing = [f"{what} {count[what]}" for what in ("no contact", "too short") if count[what]]
    if missing:
        text += (f"; {', '.join(missing)}: their frames are spread from the first frame to the frame of "
                 "largest change (`sklearn-hardness select` lists them)")
    return text


def _flow_note(corners, lost, n_features, users):
    """What the optical flow of ``users`` found: corners per press, presses without any, tracks lost.

    The folds fit with :class:`~sklearn_hardness.features.OpticalFlowFeatures`'
    warnings silenced (each fold would repeat them); this line says it once.
    """
    corners, lost = np.asarray(corners), np.asarray(lost)
    text = (f"optical flow ({', '.join(users)}): corners in a press's first frame {int(np.median(corners))} "
            f"(median; fewest {int(corners.min())}, most {int(corners.max())}, at most n_features={n_features})")
    none = int(np.sum(corners == 0))
    if none:
        text += f"; none on {none} of {len(corners)} presses: their rows are those of a press without motion"
    if corners.sum():
        text += (f"; {lost.sum() / corners.sum():.0%} of the tracks lost before the last frame "
                 f"(on {int(np.sum(lost > 0))} of {len(corners)} presses)")
    return text


def _loading_phase_note(estimator, rows, name):
    """On how many presses a :class:`~sklearn_hardness.features.LoadingCompliance` first step finds a loading phase.

    None where that step fails on the presses (the folds report the error).
    """
    first = estimator.steps[0][1] if isinstance(estimator, Pipeline) else estimator
    try:
        # the class itself, not a subclass given in a dict: the folds alone fit the user's estimators
        first = LoadingCompliance(**{k: v for k, v in first.get_params(deep=False).items()
                                     if k in LoadingCompliance._get_param_names()})
        with warnings.catch_warnings(record=True) as caught:
            warnings.simplefilter("always", UserWarning)  # counted here instead, or said below
            missing = int(np.isnan(first.fit_transform(rows)).any(axis=1).sum())
    except Exception:  # noqa: BLE001 - the folds meet the same error, where error_score decides
        return None
    text = f"loading phase ({name}): found on {len(rows) - missing} of {len(rows)} presses"
    if missing:
        text += (f"; none on {missing} (no positive force, or fewer than {first.min_loading_frames} frames from "
                 f"{first.onset:g} of the peak force to the peak): their figures are NaN, for an imputer in the "
                 "pipeline to fill")
    # the input's conventions (force sign, position's direction and unit): the folds' warnings are silenced
    conventions = [str(w.message) for w in caught if issubclass(w.category, ConventionWarning)]
    return "; ".join([text, *conventions])


def _fold_params(params, train, n_samples):
    """``params`` for a fit on ``train``: values with one entry per press are indexed, others passed whole."""
    return {key: (_safe_indexing(value, train) if _per_sample(value, n_samples) else value)
            for key, value in params.items()}


def _per_sample(value, n_samples):
    """Whether ``value`` has one entry per press (as scikit-learn's ``cross_validate`` indexes its ``params``)."""
    if isinstance(value, (str, bytes, dict)) or not hasattr(value, "__len__"):
        return False
    return len(value) == n_samples


def _fit_fold(name, estimator, X, y, groups, train, test, hardness, error_score, params=None):
    t0 = time.perf_counter()
    try:
        with warnings.catch_warnings():
            warnings.simplefilter("ignore", UserWarning)
            est = clone(estimator).fit(_safe_indexing(X, train), y[train], **_fold_params(params or {}, train, len(y)))
            X_test = _safe_indexing(X, test)
            pred = np.asarray(est.predict(X_test))
            proba = _class_proba(est, X_test, pred, int(y.max()) + 1)
    except Exception as exc:
        if error_score == "raise":
            raise
        warnings.warn(f"pipeline {name!r} failed on a fold: {type(exc).__name__}: {exc}", RuntimeWarning)
        return dict(pred=None, time=time.perf_counter() - t0, error=f"{type(exc).__name__}: {exc}")
    seconds = time.perf_counter() - t0
    mae = None if hardness is None else hardness_mae(y[test], pred, hardness)
    object_y, object_pred = _per_object(proba, y[test], groups[test])
    return dict(pred=pred, time=seconds, error=None,
                balanced_accuracy=balanced_accuracy_score(y[test], pred), mae=mae,
                object_balanced_accuracy=balanced_accuracy_score(object_y, object_pred))


def _class_proba(estimator, X, pred, n_classes):
    """Probabilities of classes ``0 .. n_classes - 1`` per press: ``predict_proba``, else the prediction's vote."""
    if not hasattr(estimator, "predict_proba"):
        return np.eye(n_classes)[pred]
    found = np.asarray(estimator.predict_proba(X))
    classes = getattr(estimator, "classes_", np.arange(found.shape[1]))
    proba = np.zeros((len(pred), n_classes))
    proba[:, np.asarray(classes, dtype=int)] = found
    return proba


def _per_object(proba, y, groups):
    """Each object's label and predicted class: the class of the mean of its presses' probabilities."""
    _, first, index = np.unique(groups, return_index=True, return_inverse=True)
    total = np.zeros((len(first), proba.shape[1]))
    np.add.at(total, index, proba)
    return y[first], np.argmax(total, axis=1)  # an object's presses share its label


def _indexed(j, func, *args):
    return j, func(*args)


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




def _named_estimators(estimators, baseline, seed, force_position):
    """``{name: estimator}`` of ``estimators`` (dict, names, pairs or None), the baseline first; its name."""
    if estimators is None:
        estimators = default_pipelines(force_position is not None)
    items = estimators.items() if isinstance(estimators, dict) else estimators
    named = {}
    for item in items:
        if isinstance(item, str):
            if item not in PIPELINE_NAMES:
                raise ValueError(f"unknown pipeline {item!r}; choose among {list(PIPELINE_NAMES)} or pass "
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
        if baseline not in PIPELINE_NAMES:
            raise ValueError(f"unknown baseline {baseline!r}; choose among {list(PIPELINE_NAMES)} or pass a "
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
    if isinstance(cv, numbers.Integral) and not isinstance(cv, bool):
        if cv < 2:
            raise ValueError(f"cv must be at least 2, got {cv}.")
        _check_group_counts(y, groups, target_names, cv)
        cv = RepeatedStratifiedGroupKFold(n_splits=cv, n_repeats=n_repeats, random_state=random_state)
    elif not hasattr(cv, "split"):
        raise ValueError(f"cv must be an integer or a splitter with split(X, y, groups); got {cv!r}.")
    folds = [(np.asarray(train), np.asarray(test)) for train, test in cv.split(np.zeros(len(y)), y, groups)]
    repeats = int(getattr(cv, "n_repeats", 1))
    if groups is not None and any(set(groups[train]) & set(groups[test]) for train, test in folds):
        warnings.warn("cv puts presses of one group on both sides of a fold: the scores are not those of new "
                      "objects. Use a group-aware splitter (GroupKFold, StratifiedGroupKFold) or an integer cv.",
                      UserWarning, stacklevel=3)
    return folds, max(len(folds) // repeats, 1), repeats


def _prepare_inputs(named, X, force_position, n_jobs, log, error_score):
    """Each pipeline's input, estimator to fit per fold, seconds of its one pass, and the notes."""
    reads_force = [name for name, est in named.items() if _takes_force_position(est)]
    if reads_force and force_position is None:
        raise ValueError(f"pipeline(s) {reads_force} read each press's force and position per frame: pass "
                         "force_position, one (T, 2) array of force and position per press.")
    keys = getattr(X, "keys", None)
    paths = keys if isinstance(keys, list) and keys and all(isinstance(k, str) for k in keys) else None
    inputs, rests, seconds_once, notes = _per_press_inputs(
        {name: est for name, est in named.items() if name not in reads_force}, X, n_jobs, log, error_score, paths)
    for name in reads_force:
        inputs[name], rests[name], seconds_once[name] = force_position, named[name], 0.0
        note = _loading_phase_note(named[name], force_position, name)
        if note is not None:
            notes.append(note)
            log.write(note)
    return inputs, rests, seconds_once, notes


def _run_folds(named, rests, inputs, y, objects, folds, hardness, error_score, params, n_jobs, verbose):
    """Every (pipeline, fold) fit's outcome, by pipeline, in the folds' order."""
    # fold by fold, so that each pipeline's first fit ends early and times the rest of its fits
    jobs = [(name, k) for k in range(len(folds)) for name in named]
    progress = ProgressLog(len(jobs), desc="evaluate", verbose=verbose, unit="fits")
    fit_seconds, n_workers = {name: [] for name in named}, effective_n_jobs(n_jobs)
    outs = [None] * len(jobs)
    calls = (delayed(_indexed)(j, _fit_fold, name, rests[name], inputs[name], y, objects, folds[k][0],
                               folds[k][1], hardness, error_score, params.get(name))
             for j, (name, k) in enumerate(jobs))
    # one fit a batch: joblib's automatic batching, timed on the quick fits of the baseline, would
    # otherwise queue several slow fits (a net's) in one batch on one worker while the others wait
    for j, out in Parallel(n_jobs=n_jobs, return_as="generator_unordered", batch_size=1)(calls):
        outs[j] = out
        fit_seconds[jobs[j][0]].append(out["time"])
        seconds, untimed = _seconds_left(fit_seconds, len(folds), n_workers)
        progress.update(1, seconds, f"not counting {', '.join(untimed)} (no fit finished yet)" if untimed else None)
    return {name: [o for (n, _), o in zip(jobs, outs) if n == name] for name in named}


def _row(name, rows, estimator, y, folds, n_splits, n_repeats, hardness, error_score, seconds_once, n_classes):
    """The table's row of one pipeline (without its margin), its fold scores and out-of-fold predictions."""
    ratio, df = float(np.mean([len(test) / len(train) for train, test in folds])), n_splits - 1
    pred = np.full((n_repeats, len(y)), -1)
    for k, ((_, test), o) in enumerate(zip(folds, rows)):
        if o["pred"] is not None:
            pred[min(k // n_splits, n_repeats - 1), test] = o["pred"]
    scores = np.array([o.get("balanced_accuracy", error_score) for o in rows], dtype=float)
    object_scores = np.array([o.get("object_balanced_accuracy", error_score) for o in rows], dtype=float)
    ba, ba_ci = _interval(scores, ratio, df, bounds=(0.0, 1.0))
    object_ba, object_ba_ci = _interval(object_scores, ratio, df, bounds=(0.0, 1.0))
    mae, mae_ci = (None, None) if hardness is None else _interval([o.get("mae") for o in rows], ratio, df,
                                                                  bounds=(0.0, np.inf))
    ok = pred >= 0
    confusion = (confusion_matrix(np.broadcast_to(y, pred.shape)[ok], pred[ok], labels=np.arange(n_classes))
                 if ok.any() else np.zeros((n_classes, n_classes), dtype=int))
    errors = sorted({o["error"] for o in rows if o["error"]})
    row = dict(pipeline=name, balanced_accuracy=ba, balanced_accuracy_ci=ba_ci, mae=mae, mae_ci=mae_ci,
               object_balanced_accuracy=object_ba, object_balanced_accuracy_ci=object_ba_ci,
               fit_predict_seconds=seconds_once + float(sum(o["time"] for o in rows)), n_folds=n_splits,
               n_repeats=n_repeats, predict_proba_samples=hasattr(estimator, "predict_proba_samples"),
               error="; ".join(errors) or None)
    return row, scores, object_scores, pred[0], confusion


def _add_margins(table, fold_scores, object_fold_scores, baseline, folds, df):
    """Each row's margin over the baseline, paired by fold, with its corrected interval (None for the baseline)."""
    ratio = float(np.mean([len(test) / len(train) for train, test in folds]))
    base, object_base = fold_scores.get(baseline), object_fold_scores.get(baseline)
    for row in table:
        own = row["pipeline"] == baseline
        row["vs_baseline"], row["vs_baseline_ci"] = paired_difference(
            fold_scores[row["pipeline"]], None if own else base, ratio, df)
        row["object_vs_baseline"], row["object_vs_baseline_ci"] = paired_difference(
            object_fold_scores[row["pipeline"]], None if own else object_base, ratio, df)


def _recall(confusion, target_names):
    """Out-of-fold recall of each class (None for a class without presses)."""
    support = confusion.sum(axis=1)
    return {str(n): (float(confusion[c, c] / support[c]) if support[c] else None) for c, n in enumerate(target_names)}


def _recommend(table):
    """The best pipeline above the baseline (paired interval above 0), overall and with predict_proba_samples."""
    above = [r for r in table if r["vs_baseline_ci"] is not None and r["vs_baseline_ci"][0] > 0]
    best = max(above, key=lambda r: r["balanced_accuracy"], default=None)
    sampled = max((r for r in above if r["predict_proba_samples"]), key=lambda r: r["balanced_accuracy"],
                  default=None)
    return (None if best is None else best["pipeline"]), (None if sampled is None else sampled["pipeline"])


@validate_params(
    {
        "estimators": [dict, list, tuple, None],
        "X": "no_validation",
        "y": ["array-like"],
        "groups": ["array-like", None],
        "cv": [Interval(numbers.Integral, 2, None, closed="left"), HasMethods(["split"])],
        "n_repeats": [Interval(numbers.Integral, 1, None, closed="left")],
        "baseline": [str, tuple, None],
        "target_names": ["array-like", None],
        "objects": ["array-like", None],
        "hardness": ["array-like", None],
        "force_position": [list, tuple, None],
        "params": [dict, None],
        "error_score": [StrOptions({"raise"}), numbers.Real],
        "n_jobs": [numbers.Integral, None],
        "random_state": ["random_state"],
        "verbose": ["verbose"],
    },
    prefer_skip_nested_validation=True,
)
def evaluate_pipelines(estimators, X, y, *, groups=None, cv=5, n_repeats=1, baseline="peak_change",
                       target_names=None, objects=None, hardness=None, force_position=None, params=None,
                       error_score=np.nan, n_jobs=None, random_state=None, verbose=0):
    """Cross-validate press pipelines on the same group-disjoint folds, each beside a baseline.

    Shaped like :func:`sklearn.model_selection.cross_validate`, for several
    estimators at once: every pipeline sees the same folds, and its margin
    over the baseline (the one-number pipeline ``"peak_change"``,
    :func:`~sklearn_hardness.models.make_peak_change_baseline`) is paired by
    fold. An integer ``cv`` makes folds that keep every group's presses
    together (:class:`RepeatedStratifiedGroupKFold`), so the scores say how
    a pipeline does on new objects. Every interval is corrected for the
    folds' overlapping training sets (:func:`corrected_interval`) and
    clipped to the range its score can take. ``recommended`` names the best
    pipeline whose margin's interval lies above 0, or None when the
    baseline does as well. The leading steps that turn each press into its
    row by that press alone (frame selection, frozen features, the peak
    change) run once over all presses, not once per fold, shared by the
    pipelines that start with them: the same scores for less work. How to
    read the results: ``docs/user_guide/recording.rst``.

    Parameters
    ----------
    estimators : dict, list or None
        ``{name: estimator}``, a list of registry names
        (:func:`~sklearn_hardness.models.pipeline_names`, built by
        :func:`~sklearn_hardness.models.make_named_pipeline` seeded by
        ``random_state``) or ``(name, estimator)`` pairs. None: the default
        pipelines (``DEFAULT_PIPELINES``), and ``"loading_compliance"``
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
    cv : int or splitter, default=5
        Folds per repetition (stratified, group-disjoint), or any
        scikit-learn splitter (anything with ``split(X, y, groups)``, e.g.
        :class:`~sklearn.model_selection.GroupKFold`).
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
        The object of each press, for the per-object scores (each test
        object classed by the mean of its presses' probabilities). None:
        ``groups``, or each press by itself.
    hardness : array-like of shape (n_classes,) or None, default=None
        The hardness of each class (a dataset's ``hardness``), for the
        hardness MAE of the predictions.
    force_position : list of ndarray of shape (T, 2) or None, default=None
        Each press's force and position per frame: the input of the
        pipelines whose first step is a
        :class:`~sklearn_hardness.features.LoadingCompliance`.
    params : dict of str to dict or None, default=None
        Fit parameters per pipeline name, as ``cross_validate``'s ``params``:
        values with one entry per press are indexed to each fold's training
        presses. E.g. ``{"grid": {"groups": object_id}}`` gives a
        :class:`~sklearn.model_selection.GridSearchCV` named ``"grid"`` the
        training fold's groups, for nested selection.
    error_score : "raise" or float, default=np.nan
        What a failing fit gives: raise, or warn and score the fold as this
        value; the table names the error.
    n_jobs : int or None, default=None
        Fits run in parallel through joblib, one fit to a task.
    random_state : int, RandomState instance or None, default=None
        Seed of an integer ``cv``'s fold assignment and of the pipelines
        given by name.
    verbose : int, default=0
        Progress on stderr: one line per finished fit with an estimate of
        the time left.

    Returns
    -------
    result : EvaluationResult
        ``summary`` (one row per pipeline), per-fold scores, out-of-fold
        predictions, confusion matrices, paired differences against the
        baseline and the recommendation.

    Raises
    ------
    ValueError
        A class with fewer groups than an integer ``cv``, an unknown
        pipeline name, lengths that disagree, or a force/position pipeline
        without ``force_position``. Also, before any fit, videos that cannot
        be read and (with ``error_score="raise"``) presses on which a
        pipeline's per-press steps fail, each listed.

    See Also
    --------
    format_evaluation, ConfusionMatricesDisplay

    Examples
    --------
    >>> from sklearn.model_selection import GroupKFold
    >>> from sklearn_hardness.datasets import make_presses
    >>> from sklearn_hardness.model_selection import evaluate_pipelines
    >>> data = make_presses("everyday", n_per_class=2, n_objects=9, class_ratio=[1, 1, 1],
    ...                     image_size=(32, 40), codec=None, random_state=0)
    >>> result = evaluate_pipelines([], data.videos, data.target, groups=data.object_id,
    ...                             cv=GroupKFold(3), target_names=data.target_names)
    >>> result.summary["pipeline"], result.confusion["peak_change"].shape
    (['peak_change'], (3, 3))
    """
    seed = int_seed(random_state)
    named, base = _named_estimators(estimators, baseline, seed, force_position)
    y, groups, target_names = _check_targets(X, y, groups, target_names)
    objects = np.asarray(objects) if objects is not None else groups if groups is not None else np.arange(len(y))
    folds, n_splits, n_repeats = _folds(cv, n_repeats, X, y, groups, target_names, random_state)
    log = ProgressLog(0, desc="evaluate", verbose=verbose)  # messages; the fits get their own below
    log.write(f"{len(named)} pipeline(s) ({', '.join(named)}) x {len(folds)} folds on {len(y)} presses of "
              f"{len(np.unique(objects))} objects")
    inputs, rests, seconds_once, notes = _prepare_inputs(named, X, force_position, n_jobs, log, error_score)
    hardness = None if hardness is None else np.asarray(hardness, dtype=float)
    outs = _run_folds(named, rests, inputs, y, objects, folds, hardness, error_score, params or {}, n_jobs, verbose)
    table, fold_scores, object_fold_scores, predictions, confusion = [], {}, {}, {}, {}
    for name in named:
        row, fold_scores[name], object_fold_scores[name], predictions[name], confusion[name] = _row(
            name, outs[name], named[name], y, folds, n_splits, n_repeats, hardness, error_score,
            seconds_once[name], len(target_names))
        row["recall"] = _recall(confusion[name], target_names)
        table.append(row)
    _add_margins(table, fold_scores, object_fold_scores, base, folds, n_splits - 1)
    recommended, with_samples = _recommend(table)
    return EvaluationResult(table=table, fold_scores=fold_scores, object_fold_scores=object_fold_scores,
                            predictions=predictions, confusion=confusion, recommended=recommended,
                            recommended_with_samples=with_samples, baseline=base, notes=notes, target=y,
                            target_names=target_names, groups=objects if groups is None else groups, objects=objects,
                            folds=[test for _, test in folds],
                            n_repeats=n_repeats)
