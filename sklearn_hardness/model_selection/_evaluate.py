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

import numpy as np
from joblib import Parallel, delayed, effective_n_jobs
from sklearn.base import BaseEstimator, clone
from sklearn.metrics import balanced_accuracy_score, confusion_matrix
from sklearn.model_selection import StratifiedGroupKFold
from sklearn.pipeline import Pipeline
from sklearn.utils import Bunch, _safe_indexing, check_random_state
from sklearn.utils._param_validation import Interval, StrOptions, validate_params

from .._registry import DEFAULT_PIPELINES, PIPELINE_NAMES, make_named_pipeline, pipeline_info
from ..datasets import load_press_videos, make_presses
from ..datasets._lazy import raise_unreadable
from ..datasets._manifest import manifest_file
from ..datasets._sim_presets import PRESETS
from ..features import LoadingCompliance, OpticalFlowFeatures
from ..features._loading_compliance import ConventionWarning
from ..metrics import hardness_mae
from ..preprocessing._contact_curve import _STATUSES
from ..utils._random import int_seed
from ..utils._validation import check_roi
from ._force_position import force_position, presses_lacking_force_position
from ._per_press import (FailingPressesError, all_columns, describe, prefix_key, split_per_press,
                         transform_per_press)
from ..utils._progress import ProgressLog
from ._intervals import _interval, paired_difference

__all__ = ["evaluate_pipelines"]


def _pipeline_by_name(name, seed=None, roi=None):
    """The registry's pipeline ``name``; ``seed`` seeds the nets, ``roi`` goes to the pipelines that read video."""
    video = pipeline_info(name).input == "video"
    return make_named_pipeline(name, random_state=seed, **({"roi": roi} if video else {}))


def _takes_force_position(estimator):
    """Whether ``estimator`` (or its first step) reads force and position per frame, not videos."""
    first = estimator.steps[0][1] if isinstance(estimator, Pipeline) else estimator
    return isinstance(first, LoadingCompliance)


def _default_pipelines(data):
    """``DEFAULT_PIPELINES``, and ``"loading_compliance"`` where every press has force and position."""
    return list(DEFAULT_PIPELINES) + ([] if presses_lacking_force_position(data) else ["loading_compliance"])


def _load_dataset(dataset, random_state):
    if isinstance(dataset, Bunch) or hasattr(dataset, "videos"):
        return dataset

    if isinstance(dataset, str) and dataset in PRESETS:
        return make_presses(dataset, random_state=random_state)
    path = manifest_file(dataset)
    if not path.exists():
        raise FileNotFoundError(
            f"dataset {str(dataset)!r} is neither a simulator preset ({sorted(PRESETS)}) nor an "
            "existing manifest (a .csv file, or a folder holding manifest.csv)."
        )
    return load_press_videos(path)


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
    n, count = len(status), {s: int(np.sum(status == s)) for s in _STATUSES}
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


def _fit_fold(name, estimator, X, y, groups, train, test, hardness, error_score):
    t0 = time.perf_counter()
    try:
        with warnings.catch_warnings():
            warnings.simplefilter("ignore", UserWarning)
            est = clone(estimator).fit(_safe_indexing(X, train), y[train])
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


@validate_params(
    {
        "dataset": "no_validation",
        "pipelines": [dict, list, tuple, None],
        "cv": [Interval(numbers.Integral, 2, None, closed="left")],
        "n_repeats": [Interval(numbers.Integral, 1, None, closed="left")],
        "baseline": ["boolean"],
        "roi": [None, tuple, list],
        "error_score": [StrOptions({"raise"}), numbers.Real],
        "n_jobs": [numbers.Integral, None],
        "random_state": ["random_state"],
        "verbose": ["verbose"],
    },
    prefer_skip_nested_validation=True,
)
def evaluate_pipelines(dataset, pipelines=None, *, cv=5, n_repeats=1, baseline=True, roi=None,
                       error_score="raise", n_jobs=None, random_state=0, verbose=1):
    """Object-disjoint cross-validation of press-video pipelines.

    Each fold tests on objects that no training press came from
    (:class:`~sklearn.model_selection.StratifiedGroupKFold` over
    ``object_id``), so the score says how a pipeline does on a new object.
    Every pipeline sees the same folds; the one-number baseline
    (:func:`~sklearn_hardness.models.make_peak_change_baseline`) runs beside
    them, and each pipeline's margin over it is paired by fold. Every
    interval is corrected for the folds' overlapping training sets
    (:func:`corrected_interval`) and clipped to the range its score can
    take. ``recommended`` names the best pipeline whose margin's interval
    lies above 0, or None when the one number does as well. How to read the
    results: ``docs/user_guide/recording.rst``; whether the intervals keep
    their level: ``studies/pages/evaluate_intervals.md``.

    Parameters
    ----------
    dataset : Bunch, str or path
        A dataset Bunch (``videos``, ``target``, ``target_names``,
        ``object_id``; ``hardness`` for the MAE), the name of a simulator
        preset (``"everyday"``, ...), or a manifest (``.csv``, or a folder
        holding ``manifest.csv``) read with
        :func:`~sklearn_hardness.datasets.load_press_videos`.
    pipelines : dict, list of str or None, default=None
        ``{name: estimator}``, or names of
        :func:`~sklearn_hardness.models.pipeline_names` (built by
        :func:`~sklearn_hardness.models.make_named_pipeline`;
        ``"loading_compliance"`` reads each press's ``force`` and
        ``position``, as does a given pipeline whose first step is a
        :class:`~sklearn_hardness.features.LoadingCompliance`). None:
        ``"contact_geometry"``, ``"convlstm_intensity"`` and
        ``"contact_profile"``, and ``"loading_compliance"`` where every press
        has force and position. The leading steps that turn each press into
        its row by that press alone (frame selection, frozen features, the
        peak change) run once over all presses, not once per fold, shared by
        the pipelines that start with them: the same scores for less work.
    cv : int, default=5
        Number of folds. Every class needs at least ``cv`` objects.
    n_repeats : int, default=1
        Times the object-disjoint split is repeated with other assignments
        of objects to folds. The means and intervals run over the
        ``n_repeats * cv`` fold scores, with the ``cv - 1`` degrees of freedom
        of one repetition (every repetition reuses the same objects). More
        objects narrow the intervals; repetitions little.
    baseline : bool, default=True
        Add the one-number baseline as ``"peak_change"``.
    roi : tuple (top, bottom, left, right) or None, default=None
        The region of the frames that the baseline and the pipelines given
        by name read (fractions of height and width): the ``roi`` of their
        feature transformers and frame selectors. For sensors whose frame
        shows more than the gel (a GelSight Wedge grasp shows the housing and
        the other finger). Estimators given in a dict are left as they are.
    error_score : "raise" or float, default="raise"
        What a failing pipeline gives: raise, or warn and score the fold as
        this value (e.g. ``np.nan``); the table names the error.
    n_jobs : int or None, default=None
        Folds run in parallel through joblib, one fit to a task.
    random_state : int, RandomState instance or None, default=0
        Seed of the fold assignment, of a simulated dataset and of the nets
        of the pipelines given by name (so a run repeats exactly; pass
        seeded estimators in a dict to control them yourself).
    verbose : int, default=1
        Progress on stderr: one line per finished fit with an estimate of
        the time left. ``0`` is silent.

    Returns
    -------
    result : :class:`~sklearn.utils.Bunch`
        table : list of dict
            One dict per pipeline: ``pipeline``, ``balanced_accuracy``,
            ``vs_baseline`` (margin over the baseline, paired by fold), ``mae``,
            ``object_balanced_accuracy`` and ``object_vs_baseline`` (scored per
            test object, from the mean of its presses' probabilities), each
            with a 95% interval ``*_ci`` (None where it does not apply); ``recall`` (class
            name -> out-of-fold recall), ``fit_predict_seconds``, ``n_folds``,
            ``n_repeats``, ``predict_proba_samples`` and ``error``.
        fold_scores, object_fold_scores : dict of name -> ndarray of shape (n_repeats * cv,)
            Balanced accuracy per fold, per press and per object.
        predictions : dict of name -> ndarray of shape (n_samples,)
            Out-of-fold predictions of the first repetition.
        confusion : dict of name -> ndarray of shape (n_classes, n_classes)
            Confusion matrix of the out-of-fold predictions of all repetitions.
        recommended : str or None
            The best pipeline whose margin's interval lies above 0; None when
            none does or without the baseline.
        recommended_with_samples : str or None
            The same among pipelines with ``predict_proba_samples``.
        notes : list of str
            What the per-press steps found (presses without contact, lost
            flow tracks, failed presses...) that the folds' warnings would say.
        target, target_names, groups, folds, n_repeats, chance
            The labels, class names, object of each press, the folds' test
            indices, the number of repetitions and ``1 / n_classes``.

    Raises
    ------
    ValueError
        A class with fewer objects than ``cv``, an unknown pipeline name,
        a dataset without ``object_id``, or ``"loading_compliance"`` without
        force and position for every press. Also, before any fit, videos
        that cannot be read and (with ``error_score="raise"``) presses on
        which a pipeline's per-press steps fail, each listed.

    See Also
    --------
    format_evaluation, plot_confusion_matrices

    Examples
    --------
    >>> from sklearn_hardness.datasets import make_presses
    >>> from sklearn_hardness.model_selection import evaluate_pipelines
    >>> data = make_presses("everyday", n_per_class=2, n_objects=9, class_ratio=[1, 1, 1],
    ...                     image_size=(32, 40), codec=None, random_state=0)
    >>> result = evaluate_pipelines(data, pipelines=[], cv=3)
    >>> result.table[0]["pipeline"], result.confusion["peak_change"].shape
    ('peak_change', (3, 3))
    """
    roi = check_roi(roi)
    data = _load_dataset(dataset, random_state)
    X, y = data.videos, np.asarray(data.target)
    groups = getattr(data, "object_id", None)
    if groups is None:
        raise ValueError("the dataset has no object_id: object-disjoint folds need to know which "
                         "object each press is of (add an object_id column to the manifest).")
    groups = np.asarray(groups)
    if pipelines is None:
        pipelines = _default_pipelines(data)
    if isinstance(pipelines, dict):
        named = {str(k): v for k, v in pipelines.items()}
    else:
        unknown = [p for p in pipelines if p not in PIPELINE_NAMES]
        if unknown:
            raise ValueError(f"unknown pipeline(s) {unknown}; choose among {list(PIPELINE_NAMES)} "
                             "or pass a dict {name: estimator}.")
        seed = int_seed(random_state)
        named = {p: _pipeline_by_name(p, seed, roi) for p in pipelines}
    if baseline and "peak_change" not in named:
        named = {"peak_change": _pipeline_by_name("peak_change", roi=roi), **named}
    if not named:
        raise ValueError("no pipelines to evaluate.")
    names = np.asarray(data.target_names)
    n_classes = len(names)
    objects_per_class = [len(np.unique(groups[y == c])) for c in range(n_classes)]
    counts = dict(zip(names.tolist(), objects_per_class))
    if min(objects_per_class) < 2:
        nameless = np.array_equal(groups.astype(str), names[y].astype(str))
        raise ValueError(
            f"object-disjoint folds need at least 2 objects of every class; the dataset has {counts}"
            + ("; it names no objects (a manifest without an object_id column counts every label as one "
               "object): add an object_id column saying which physical object each press is of."
               if nameless else ": record more objects of those classes.")
        )
    short = [str(names[c]) for c in range(n_classes) if objects_per_class[c] < cv]
    if short:
        raise ValueError(f"classes {short} have fewer than cv={cv} objects ({counts}); lower cv to at most "
                         f"{min(objects_per_class)}.")
    # one stream for all repetitions, as scikit-learn's _RepeatedSplits: the first repetition's
    # folds are those of StratifiedGroupKFold(random_state=random_state) alone
    rng = check_random_state(random_state)
    folds = [fold for _ in range(n_repeats)
             for fold in StratifiedGroupKFold(n_splits=cv, shuffle=True, random_state=rng).split(
                 np.zeros(len(y)), y, groups)]
    hardness = getattr(data, "hardness", None)
    log = ProgressLog(0, desc="evaluate", verbose=verbose)  # messages; the fits get their own below
    repeats = f" x {n_repeats} repetitions" if n_repeats > 1 else ""
    log.write(f"{len(named)} pipeline(s) ({', '.join(named)}) x {cv} object-disjoint folds{repeats} on "
              f"{len(y)} presses of {len(np.unique(groups))} objects")
    reads_force = [name for name, est in named.items() if _takes_force_position(est)]
    force_position_rows = force_position(data, reads_force) if reads_force else None
    inputs, rests, seconds_once, notes = _per_press_inputs(
        {name: est for name, est in named.items() if name not in reads_force}, X, n_jobs, log, error_score,
        getattr(data, "paths", None))
    for name in reads_force:
        inputs[name], rests[name], seconds_once[name] = force_position_rows, named[name], 0.0
        note = _loading_phase_note(named[name], force_position_rows, name)
        if note is not None:
            notes.append(note)
            log.write(note)
    # fold by fold, so that each pipeline's first fit ends early and times the rest of its fits
    jobs = [(name, rests[name], k) for k in range(len(folds)) for name in named]
    progress = ProgressLog(len(jobs), desc="evaluate", verbose=verbose, unit="fits")
    fit_seconds, n_workers = {name: [] for name in named}, effective_n_jobs(n_jobs)
    outs = [None] * len(jobs)
    calls = (delayed(_indexed)(j, _fit_fold, name, est, inputs[name], y, groups, folds[k][0], folds[k][1],
                               hardness, error_score) for j, (name, est, k) in enumerate(jobs))
    # one fit a batch: joblib's automatic batching, timed on the quick fits of the baseline, would
    # otherwise queue several slow fits (a net's) in one batch on one worker while the others wait
    for j, out in Parallel(n_jobs=n_jobs, return_as="generator_unordered", batch_size=1)(calls):
        outs[j] = out
        fit_seconds[jobs[j][0]].append(out["time"])
        seconds, untimed = _seconds_left(fit_seconds, len(folds), n_workers)
        progress.update(1, seconds, f"not counting {', '.join(untimed)} (no fit finished yet)" if untimed else None)
    test_train_ratio = float(np.mean([len(test) / len(train) for train, test in folds]))
    table, fold_scores, object_fold_scores, predictions, confusion = [], {}, {}, {}, {}
    for name in named:
        rows = [o for (n, _, _), o in zip(jobs, outs) if n == name]
        errors = sorted({o["error"] for o in rows if o["error"]})
        pred = np.full((n_repeats, len(y)), -1)
        for k, ((train, test), o) in enumerate(zip(folds, rows)):
            if o["pred"] is not None:
                pred[k // cv, test] = o["pred"]
        scores = np.array([o.get("balanced_accuracy", error_score) for o in rows], dtype=float)
        ba, ba_ci = _interval(scores, test_train_ratio, cv - 1, bounds=(0.0, 1.0))
        maes = [o.get("mae") for o in rows]
        mae, mae_ci = (None, None) if hardness is None else _interval(maes, test_train_ratio, cv - 1,
                                                                  bounds=(0.0, np.inf))
        fold_scores[name], predictions[name] = scores, pred[0]
        object_fold_scores[name] = np.array([o.get("object_balanced_accuracy", error_score) for o in rows],
                                            dtype=float)
        object_ba, object_ba_ci = _interval(object_fold_scores[name], test_train_ratio, cv - 1, bounds=(0.0, 1.0))
        ok = pred >= 0
        confusion[name] = (confusion_matrix(np.broadcast_to(y, pred.shape)[ok], pred[ok],
                                            labels=np.arange(n_classes)) if ok.any()
                           else np.zeros((n_classes, n_classes), dtype=int))
        support = confusion[name].sum(axis=1)
        recall = {str(names[c]): (float(confusion[name][c, c] / support[c]) if support[c] else None)
                  for c in range(n_classes)}
        table.append(dict(pipeline=name, balanced_accuracy=ba, balanced_accuracy_ci=ba_ci, mae=mae,
                          mae_ci=mae_ci, recall=recall, object_balanced_accuracy=object_ba,
                          object_balanced_accuracy_ci=object_ba_ci,
                          fit_predict_seconds=seconds_once[name] + float(sum(o["time"] for o in rows)),
                          n_folds=cv, n_repeats=n_repeats,
                          predict_proba_samples=hasattr(named[name], "predict_proba_samples"),
                          error="; ".join(errors) or None))
    base, object_base = fold_scores.get("peak_change"), object_fold_scores.get("peak_change")
    for row in table:
        own = row["pipeline"] == "peak_change"
        row["vs_baseline"], row["vs_baseline_ci"] = paired_difference(
            fold_scores[row["pipeline"]], None if own else base, test_train_ratio, cv - 1)
        row["object_vs_baseline"], row["object_vs_baseline_ci"] = paired_difference(
            object_fold_scores[row["pipeline"]], None if own else object_base, test_train_ratio, cv - 1)
    recommended, with_samples = _recommend(table)
    return Bunch(table=table, fold_scores=fold_scores, object_fold_scores=object_fold_scores,
                 predictions=predictions, confusion=confusion,
                 recommended=recommended, recommended_with_samples=with_samples,
                 target=y, target_names=names, groups=groups, folds=[test for _, test in folds],
                 n_repeats=n_repeats, chance=1.0 / n_classes, hardness_unit=getattr(data, "hardness_unit", None),
                 notes=notes)


def _recommend(table):
    """The best pipeline above the baseline (paired interval above 0), overall and with predict_proba_samples."""
    above = [r for r in table if r["vs_baseline_ci"] is not None and r["vs_baseline_ci"][0] > 0]
    best = max(above, key=lambda r: r["balanced_accuracy"], default=None)
    sampled = max((r for r in above if r["predict_proba_samples"]), key=lambda r: r["balanced_accuracy"],
                  default=None)
    return (None if best is None else best["pipeline"]), (None if sampled is None else sampled["pipeline"])


