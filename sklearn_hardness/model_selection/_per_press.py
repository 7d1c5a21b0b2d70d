"""The per-press steps of the evaluated pipelines, run once over all presses instead of once per fold.

A per-press step (one that carries
:class:`~sklearn_hardness.utils.PerPressTransformerMixin`: frame selection,
the contact profile and geometry, texture, optical flow, frozen DINOv2
features, the peak change, a robot's loading figures; nested in a
:class:`~sklearn.pipeline.FeatureUnion` too) turns one press into its row by
that press alone, and its ``fit`` learns nothing from the presses. Fitting
such steps on a fold's training presses and transforming its test presses
gives, press for press, what transforming every press once gives. So
:func:`~sklearn_hardness.model_selection.evaluate_pipelines` runs the leading
per-press steps of each pipeline once over all presses and cross-validates
the rest of the pipeline on their rows: the same scores, a ``cv``-th of the
work in these steps, which is most of the work of every pipeline without a
net. Pipelines that start with the same steps share one pass.
"""

from __future__ import annotations

import time
import warnings

import joblib
import numpy as np
from sklearn.base import BaseEstimator, clone
from sklearn.pipeline import FeatureUnion, Pipeline
from sklearn.utils import _safe_indexing
from sklearn.utils.parallel import Parallel, delayed

from ..utils._per_press import PerPressTransformerMixin, is_per_press
from ..utils._validation import names_a_video, rename_videos

__all__ = ["FailingPressesError", "describe", "first_input", "per_press_inputs", "prefix_key", "split_per_press",
           "transform_per_press"]


def split_per_press(estimator):
    """Split a pipeline into its leading per-press steps and the rest.

    Parameters
    ----------
    estimator : estimator
        Any estimator; only a :class:`~sklearn.pipeline.Pipeline` of more
        than one step can be split.

    Returns
    -------
    prefix : Pipeline or None
        The longest run of leading per-press steps (the last step is never
        part of it), or None when there is none.
    rest : estimator
        The remaining steps (``estimator`` itself when ``prefix`` is None).
    """
    if not isinstance(estimator, Pipeline) or len(estimator.steps) < 2:
        return None, estimator
    k = 0
    while k < len(estimator.steps) - 1 and is_per_press(estimator.steps[k][1]):
        k += 1
    if k == 0:
        return None, estimator
    return estimator[:k], estimator[k:]


def first_input(estimator):
    """What one press is to ``estimator``: its first per-press step's ``_per_press_input`` (``"videos"`` where
    it has none)."""
    step = estimator
    while isinstance(step, (Pipeline, FeatureUnion)):
        parts = step.steps if isinstance(step, Pipeline) else step.transformer_list
        parts = [s for _, s in parts if not isinstance(s, str) and s is not None]
        if not parts:
            return "videos"
        step = parts[0]
    return getattr(step, "_per_press_input", "videos")


def _steps(estimator):
    """The per-press steps in ``estimator``, nested ones included, in order."""
    if isinstance(estimator, PerPressTransformerMixin):
        return [estimator]
    if isinstance(estimator, Pipeline):
        return [s for _, step in estimator.steps for s in _steps(step)]
    if isinstance(estimator, FeatureUnion):
        return [s for _, step in estimator.transformer_list for s in _steps(step)]
    return []


def describe(prefix):
    """The per-press steps of ``prefix`` by class, e.g. ``"ContactFrameSelector -> OpticalFlowFeatures"``."""
    return " -> ".join(_describe(step) for _, step in prefix.steps)


def _describe(step):
    if isinstance(step, FeatureUnion):
        return "(" + " + ".join(_describe(t) for _, t in step.transformer_list if t != "drop") + ")"
    if isinstance(step, Pipeline):
        return " -> ".join(_describe(s) for _, s in step.steps)
    return type(step).__name__


def _shared(prefix):
    """``prefix`` with its closing step replaced by one whose rows hold its own (the step's ``_shared_pass``),
    and the columns that give its own rows; ``(prefix, None)`` where the step has no such superset."""
    step = prefix.steps[-1][1]
    shared = step._shared_pass() if isinstance(step, PerPressTransformerMixin) else None
    if shared is None:
        return prefix, None
    superset, columns = shared
    every = clone(prefix)
    every.steps[-1] = (every.steps[-1][0], superset)
    return every, columns


def prefix_key(prefix):
    """One key for prefixes with the same steps and parameters (they give the same rows)."""
    return joblib.hash(_key_parts(prefix))


def _key_parts(step):
    if isinstance(step, (Pipeline, FeatureUnion)):
        parts = step.steps if isinstance(step, Pipeline) else step.transformer_list
        extra = step.transformer_weights if isinstance(step, FeatureUnion) else None
        return (type(step).__qualname__, [(name, _key_parts(s)) for name, s in parts], extra)
    if isinstance(step, str) or step is None:
        return step
    return type(step).__qualname__, step.get_params(deep=False)


class FailingPressesError(ValueError):
    """Per-press steps that fail on some presses, each by itself.

    ``failures`` lists ``(press, message)``: the index of each failing press
    among all presses of the pass, and what its steps raised on it alone
    (the ``X[0]`` an error names there is rewritten as ``the press``). The
    message lists them all, as a user mending a manifest wants them, where a
    pass over chunks of presses would name the first failing press by its
    index in its chunk.
    """

    def __init__(self, message, failures=()):
        super().__init__(message)
        self.failures = list(failures)

    def __reduce__(self):  # joblib's workers send it back pickled
        return type(self), (self.args[0], self.failures)


def _transform_chunk(prefix, X, rows):
    """The chunk's rows through a clone of ``prefix`` and what its per-press steps found on each press."""
    fitted = clone(prefix)
    with warnings.catch_warnings():
        # as the folds ignore them (weak contacts, lost tracks, ...); the steps' notes say what they would
        warnings.simplefilter("ignore", UserWarning)
        Xt = fitted.fit_transform(_safe_indexing(X, rows))
    return Xt, [getattr(step, "_press_info", {}) for step in _steps(fitted)]


def _fit_transform_chunk(prefix, X, rows):
    """``(rows, infos, None)`` of the chunk (see :func:`transform_per_press`), or ``(None, None, failures)``.

    Where the chunk fails, each of its presses runs alone (the steps map each
    press by itself, so a press fails alone where it fails in the chunk) and
    ``failures`` lists those that fail, ``(index among all presses,
    message)``. The chunk's error is raised as it is where no press fails
    alone, and where the first press fails alone with the very same error
    naming no press (a parameter, weights that cannot be loaded: an error of
    the steps, not of the presses, which every press would repeat).
    """
    try:
        Xt, infos = _transform_chunk(prefix, X, rows)
    except Exception as chunk_exc:
        failures = []
        for k, i in enumerate(rows):
            try:
                _transform_chunk(prefix, X, [i])
            except Exception as exc:  # noqa: BLE001 - reported with the press it failed on
                if k == 0 and type(exc) is type(chunk_exc) and str(exc) == str(chunk_exc) \
                        and not names_a_video(str(exc)):
                    raise chunk_exc from None
                message = rename_videos(str(exc), lambda _: "the press")  # X[0]: it ran alone
                failures.append((int(i), f"{type(exc).__name__}: {message}"))
        if not failures:
            raise
        return None, None, failures
    return Xt, infos, None


def transform_per_press(prefix, X, n_jobs=None):
    """The rows of every press through ``prefix``, in chunks run in parallel.

    Parameters
    ----------
    prefix : Pipeline
        Per-press steps (the ``prefix`` of :func:`split_per_press`).
    X : sequence
        The presses (a list or lazy sequence of videos, or force and
        position series).
    n_jobs : int or None, default=None
        Chunks of presses run in parallel
        (:class:`sklearn.utils.parallel.Parallel`).

    Returns
    -------
    Xt : ndarray
        The rows, press by press, as ``prefix`` fitted on any presses would
        transform them.
    seconds : float
        Wall time of the pass.
    found : list of (step, dict)
        Each per-press step of ``prefix`` (nested ones included, in order)
        with what it found on every press (its ``info``, one entry per press
        of ``X``), for its note (the step's ``_press_note``).

    Raises
    ------
    FailingPressesError
        Where presses fail by themselves: every such press, by its index in
        ``X``. An error no press raises alone is raised as it is.
    """
    t0 = time.perf_counter()
    n_chunks = max(1, min(len(X), joblib.effective_n_jobs(n_jobs)))
    chunks = [rows for rows in np.array_split(np.arange(len(X)), n_chunks) if len(rows)]
    parts = Parallel(n_jobs=n_jobs)(delayed(_fit_transform_chunk)(prefix, X, rows) for rows in chunks)
    failures = [failure for _, _, part in parts if part for failure in part]
    if failures:
        raise FailingPressesError(
            f"{describe(prefix)} fails on {len(failures)} of {len(X)} presses, each by itself:\n  "
            + "\n  ".join(f"press {i}: {message}" for i, message in failures), failures)
    steps = _steps(prefix)
    found = [(step, {key: _concatenate([infos[s][key] for _, infos, _ in parts]) for key in parts[0][1][s]})
             for s, step in enumerate(steps)]
    return np.concatenate([Xt for Xt, _, _ in parts]), time.perf_counter() - t0, found


def _concatenate(values):
    if all(isinstance(v, np.ndarray) and v.dtype != object for v in values):
        return np.concatenate(values)
    out = np.empty(sum(len(v) for v in values), dtype=object)
    out[:] = [item for v in values for item in v]
    return out


class _FailedPerPress(BaseEstimator):
    """Stands in for a pipeline whose per-press steps fail on some presses: every fold fails at once.

    Each fold has every press in its training or its test presses, so each
    would meet the failing presses (after training a net, where they are
    among the test presses); this one fails at once with ``message``.
    """

    def __init__(self, message=""):
        self.message = message

    def fit(self, X, y=None, **params):
        raise FailingPressesError(self.message)


def _failing_presses(prefix, failures, names, n_presses, paths, lines):
    """The presses on which the pass of ``prefix`` failed, by index and file, for ``names``' users.

    One press a line (for an error) where ``lines``, else all on one line (a note).
    """
    presses = [f"press {i}" + (f" ({paths[i]})" if paths is not None else "") + f": {message}"
               for i, message in failures]
    head = f"{', '.join(names)}: {describe(prefix)} fails on {len(presses)} of {n_presses} presses, each by itself:"
    return head + ("\n  " + "\n  ".join(presses) if lines else " " + "; ".join(presses))


def per_press_inputs(named, inputs, n_jobs, log, error_score="raise", paths=None, check_readable=None):
    """Run each pipeline's leading per-press steps once over all presses.

    Parameters
    ----------
    named : dict of str to estimator
    inputs : dict of str to sequence
        Each pipeline's presses (the videos, or the force and position
        series of the pipelines that read them).
    n_jobs : int or None
    log : ProgressLog
    error_score : "raise" or float
    paths : list of str or None
        The videos' files, to name failing presses.
    check_readable : callable or None
        Called with the videos and an exception where a pass fails: raises
        one error listing every video that cannot be read, if any.

    Returns
    -------
    inputs : dict of str to array-like
        What each pipeline's folds get: the rows of its per-press steps, or
        its presses.
    rests : dict of str to estimator
        What the folds fit: the rest of the pipeline, or the whole pipeline.
    prefixes : dict of str to Pipeline or None
        Each pipeline's per-press steps (None where it has none or their
        pass failed).
    seconds : dict of str to float
        The seconds of each pipeline's pass (counted in full for every
        pipeline that uses its rows: what the pipeline would take alone).
    notes : list of str
        What the per-press steps found on the presses (one note per step,
        shared by the pipelines whose steps found the same), then the
        presses on which a pass failed.

    Notes
    -----
    Pipelines with the same leading steps share one pass, and so do steps
    that differ only in the columns they output (their ``_shared_pass``:
    each pipeline takes its columns). Where a pass fails on videos that
    cannot be read, one error lists them all (``check_readable``); where
    presses fail it by themselves (a one-frame video), one error lists them
    by index and ``paths`` (a :class:`FailingPressesError`), or, with a
    numeric ``error_score``, a note does and every fold of its pipelines
    fails at once; where it fails otherwise, its pipelines run whole in
    every fold, where ``error_score`` decides.
    """
    rests, prefixes, seconds = dict(named), dict.fromkeys(named), dict.fromkeys(named, 0.0)
    inputs = dict(inputs)
    passes = {}
    for name, est in named.items():
        prefix, rest = split_per_press(est)
        if prefix is not None:
            shared, columns = _shared(prefix)
            key = (id(inputs[name]), prefix_key(shared))
            passes.setdefault(key, (shared, inputs[name], []))[2].append((name, prefix, rest, columns))
    found_by_note, failed_notes = {}, []
    checked = False  # whether every video was found readable
    for shared, X, users in passes.values():
        names = [name for name, _, _, _ in users]
        log.write(f"{describe(shared)} of every press, once for all folds ({', '.join(names)})")
        try:
            Xt, once, found = transform_per_press(shared, X, n_jobs=n_jobs)
        except Exception as exc:  # noqa: BLE001 - the folds run the whole pipelines and report it
            if not checked and check_readable is not None:  # else every pipeline would fail on every fold
                check_readable(X, exc)
                checked = True
            if isinstance(exc, FailingPressesError):  # every fold would fail: say on which presses, now
                if error_score == "raise":
                    raise FailingPressesError(
                        _failing_presses(shared, exc.failures, names, len(X), paths, lines=True)
                        + "\nRemove their rows from the manifest or record them again; with error_score=np.nan, "
                        "evaluate_pipelines gives these pipelines an error and scores the others.",
                        exc.failures) from exc
                note = _failing_presses(shared, exc.failures, names, len(X), paths, lines=False)
                failed_notes.append(note)
                log.write(note)
                for name in names:
                    rests[name] = _FailedPerPress(f"{describe(shared)} fails on {len(exc.failures)} of "
                                                  f"{len(X)} presses (the notes name them)")
            continue
        for name, prefix, rest, columns in users:
            inputs[name] = Xt if columns is None else Xt[:, columns]
            rests[name], prefixes[name], seconds[name] = rest, prefix, once
        for step, info in found:
            key = (type(step), step._press_note(info, []))
            if key[1] is not None:
                found_by_note.setdefault(key, (step, info, []))[2].extend(n for n in names
                                                                          if n not in found_by_note[key][2])
    notes = [step._press_note(info, users) for step, info, users in _by_kind(found_by_note)]
    for note in notes:
        log.write(note)
    return inputs, rests, prefixes, seconds, notes + failed_notes


def _by_kind(found_by_note):
    """The notes' entries, those of each kind of step together, kinds in the order they first came."""
    kinds = list(dict.fromkeys(kind for kind, _ in found_by_note))
    return [entry for kind in kinds for (k, _), entry in found_by_note.items() if k is kind]
