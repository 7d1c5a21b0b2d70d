"""Per-press steps of a pipeline, computed once for all folds of a cross-validation.

Contact-frame selection, the contact-profile features, optical flow, frozen
DINOv2 features and the one-number peak change each turn one press into its
row by that press alone, and their ``fit`` learns nothing from the presses
(it checks parameters and shapes, or loads a frozen backbone). Fitting them
on a fold's training presses and transforming its test presses then gives,
press for press, what transforming every press once gives. Object-disjoint
cross-validation (:func:`~sklearn_hardness.model_selection.evaluate_pipelines`)
runs them once over all presses instead of once per fold and cross-validates
the rest of each pipeline on their output: the same scores, a ``cv``-th of
the work in these steps, which is most of the work of every pipeline
without a net.
"""

from __future__ import annotations

import time
import warnings

import joblib
import numpy as np
from joblib import Parallel, delayed
from sklearn.base import clone
from sklearn.pipeline import Pipeline
from sklearn.preprocessing import FunctionTransformer
from sklearn.utils import _safe_indexing

from ..features import (
    ContactGeometryFeatures,
    ContactProfileFeatures,
    DINOv2Features,
    ImprintTextureFeatures,
    OpticalFlowFeatures,
)
from ..models import peak_contact_change
from ..preprocessing import ContactFrameSelector
from ..utils._feature_names import CONTACT_PROFILE_FEATURE_NAMES, feature_columns
from ..utils._validation import names_a_video, rename_videos

__all__ = ["FailingPressesError", "all_columns", "describe", "prefix_key", "split_per_press",
           "transform_per_press"]

#: Exact classes (not subclasses, whose ``fit`` may learn) that map each press by itself.
_PER_PRESS_TYPES = (ContactFrameSelector, ContactProfileFeatures, ContactGeometryFeatures, ImprintTextureFeatures,
                    OpticalFlowFeatures, DINOv2Features)


def _is_per_press(step):
    if type(step) in _PER_PRESS_TYPES:
        return True
    return type(step) is FunctionTransformer and step.func is peak_contact_change and step.inverse_func is None


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
        The longest run of leading steps that map each press by itself (the
        last step is never part of it), or None when there is none.
    rest : estimator
        The remaining steps (``estimator`` itself when ``prefix`` is None).
    """
    if not isinstance(estimator, Pipeline) or len(estimator.steps) < 2:
        return None, estimator
    k = 0
    while k < len(estimator.steps) - 1 and _is_per_press(estimator.steps[k][1]):
        k += 1
    if k == 0:
        return None, estimator
    return estimator[:k], estimator[k:]


def describe(prefix):
    """The steps of ``prefix`` by name, e.g. ``"ContactFrameSelector -> OpticalFlowFeatures"``."""
    return " -> ".join(step.func.__name__ if type(step) is FunctionTransformer else type(step).__name__
                       for _, step in prefix.steps)


def all_columns(prefix):
    """``prefix`` with its closing contact-profile step giving all its columns, and the columns it gave.

    :class:`~sklearn_hardness.features.ContactProfileFeatures` computes all
    its features and outputs those ``features`` names, so prefixes that
    differ only in that choice can share one pass and each take its
    columns. Returns ``(prefix, None)`` unchanged where the last step is not
    that class, outputs all columns already, or names features the step's
    own check refuses (its pass then fails as it would have).
    """
    step = prefix.steps[-1][1]
    if type(step) is not ContactProfileFeatures or isinstance(step.features, str):
        return prefix, None
    try:
        columns = feature_columns(step.features, CONTACT_PROFILE_FEATURE_NAMES)
    except (TypeError, ValueError):
        return prefix, None
    every = clone(prefix)
    every.steps[-1][1].set_params(features="all")
    return every, columns


def prefix_key(prefix):
    """One key for prefixes with the same steps and parameters (they give the same rows)."""
    return joblib.hash([(type(step).__qualname__, step.get_params(deep=False)) for _, step in prefix.steps])


class FailingPressesError(ValueError):
    """Per-press steps that fail on some presses, each by itself.

    ``failures`` lists ``(press, message)``: the index of each failing press
    among all presses of the pass, and what its steps raised on it alone
    (the ``X[0]`` an error names there is rewritten as ``the press``). The message lists them all,
    as a user mending a manifest wants them, where a pass over chunks of
    presses would name the first failing press by its index in its chunk.
    """

    def __init__(self, message, failures=()):
        super().__init__(message)
        self.failures = list(failures)

    def __reduce__(self):  # joblib's workers send it back pickled
        return type(self), (self.args[0], self.failures)


def _transform_chunk(prefix, X, rows):
    """The chunk's rows through a clone of ``prefix``, and what its steps found on each press."""
    fitted = clone(prefix)
    found = {}
    Xt = _safe_indexing(X, rows)
    with warnings.catch_warnings():
        # as the folds ignore them (weak contacts, lost tracks, ...); ``found`` says what they would
        warnings.simplefilter("ignore", UserWarning)
        for _, step in fitted.steps:  # as Pipeline.fit_transform, keeping the flow's tracks
            if type(step) is OpticalFlowFeatures:
                tracks = step.fit(Xt).track(Xt)
                Xt = step._rows_of(tracks)
                found.setdefault("flow_corners", tracks.n_corners)
                found.setdefault("flow_tracks_lost", tracks.n_lost)
                continue
            Xt = step.fit_transform(Xt)
            if isinstance(step, ContactFrameSelector):
                found.setdefault("contact_status", np.asarray(step.selection_.status, dtype=object))
    return Xt, found


def _fit_transform_chunk(prefix, X, rows):
    """``(rows, found, None)`` of the chunk (see :func:`transform_per_press`), or ``(None, None, failures)``.

    Where the chunk fails, each of its presses runs alone (the steps map each
    press by itself, so a press fails alone where it fails in the chunk) and
    ``failures`` lists those that fail, ``(index among all presses,
    message)``. The chunk's error is raised as it is where no press fails
    alone, and where the first press fails alone with the very same error
    naming no press (a parameter, weights that cannot be loaded: an error of
    the steps, not of the presses, which every press would repeat).
    """
    try:
        Xt, found = _transform_chunk(prefix, X, rows)
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
    return Xt, found, None


def transform_per_press(prefix, X, n_jobs=None):
    """The rows of every press through ``prefix``, in chunks run in parallel.

    Parameters
    ----------
    prefix : Pipeline
        Per-press steps (the ``prefix`` of :func:`split_per_press`).
    X : sequence
        The presses (a list or lazy sequence of videos).
    n_jobs : int or None, default=None
        Chunks of presses run in parallel through joblib.

    Returns
    -------
    Xt : ndarray
        The rows, press by press, as ``prefix`` fitted on any presses would
        transform them.
    seconds : float
        Wall time of the pass.
    found : dict of str to ndarray of shape (n_presses,)
        What the first step of each kind found on every press, for the
        warnings the pass silences: ``"contact_status"`` where ``prefix`` has
        a :class:`~sklearn_hardness.preprocessing.ContactFrameSelector` (the
        ``status`` it gave each press: ``"contact"``, ``"weak contact"``,
        ``"no contact"``, ``"too short"``); ``"flow_corners"`` and
        ``"flow_tracks_lost"`` where it has
        :class:`~sklearn_hardness.features.OpticalFlowFeatures` (the corners
        found in each press's first frame, and how many of their tracks were
        lost before its last frame). Empty where it has neither.

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
    found = {key: np.concatenate([part[key] for _, part, _ in parts]) for key in parts[0][1]}
    return np.concatenate([Xt for Xt, _, _ in parts]), time.perf_counter() - t0, found
