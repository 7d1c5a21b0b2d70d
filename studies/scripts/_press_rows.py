"""A pipeline's per-press steps, run once over a set's presses, for the studies that refit the rest many times.

Per-press steps (the package marks them with
:class:`~sklearn_hardness.utils.PerPressTransformerMixin`: frame selection, the
contact-profile, contact-geometry, imprint-texture, optical-flow and frozen
DINOv2 features, the one-number peak change) each turn one press into its row
by that press alone: their ``fit`` learns nothing from the presses.
``training_objects.py`` and ``sim_pretraining.py`` run them once per simulated
set (and cache the rows) and fit only the rest of each pipeline per training
set, which gives, press for press, what fitting the whole pipeline gives.
``evaluate_pipelines`` does the same inside the package; this is the studies'
own, reading the package's public mark.
"""

import warnings

import joblib
import numpy as np
from joblib import Parallel, delayed
from sklearn.base import clone
from sklearn.pipeline import Pipeline

from sklearn_hardness.utils import PerPressTransformerMixin


def is_per_press(step):
    """Whether ``step`` maps each press by itself: it carries the package's per-press mark."""
    return isinstance(step, PerPressTransformerMixin)


def split_per_press(estimator):
    """``(prefix, rest)``: the longest run of leading per-press steps (never the last step), and the other steps.

    ``prefix`` is None (and ``rest`` is ``estimator``) where the estimator is
    no pipeline of two steps or more, or its first step learns from the presses.
    """
    if not isinstance(estimator, Pipeline) or len(estimator.steps) < 2:
        return None, estimator
    k = 0
    while k < len(estimator.steps) - 1 and is_per_press(estimator.steps[k][1]):
        k += 1
    if k == 0:
        return None, estimator
    return estimator[:k], estimator[k:]


def prefix_key(prefix):
    """One key for prefixes with the same steps and parameters (they give the same rows): the cache files' names."""
    return joblib.hash([(type(step).__qualname__, step.get_params(deep=False)) for _, step in prefix.steps])


def _chunk_rows(prefix, videos, index):
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", UserWarning)  # weak contacts, lost tracks: the folds ignore them too
        return clone(prefix).fit_transform(videos[index])


def transform_per_press(prefix, videos, n_jobs=None):
    """The rows of every press of ``videos`` (a sequence with array indexing) through ``prefix``, in parallel chunks."""
    n_chunks = max(1, min(len(videos), joblib.effective_n_jobs(n_jobs)))
    chunks = [index for index in np.array_split(np.arange(len(videos)), n_chunks) if len(index)]
    return np.concatenate(Parallel(n_jobs=n_jobs)(delayed(_chunk_rows)(prefix, videos, index) for index in chunks))
