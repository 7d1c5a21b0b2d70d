"""Per-press steps: the one mark they carry and the one cache of their rows.

A per-press step turns each press into its row by that press alone (contact
frames, a contact profile, optical flow, frozen DINOv2 features, the peak
change, a robot's loading figures), and its ``fit`` learns nothing from the
presses: it checks parameters and shapes, or loads a frozen backbone. Such a
step inherits :class:`PerPressTransformerMixin`, and the machinery reads that
mark, as scikit-learn's reads an estimator's tags:

* :func:`~sklearn_hardness.model_selection.evaluate_pipelines` runs the
  leading per-press steps of a pipeline once over all presses, not once per
  fold (the same rows, a ``cv``-th of the work);
* a per-press step's ``memory`` (what
  :func:`~sklearn_hardness.models.make_named_pipeline` gives each of them)
  caches every press's row, so that the folds of any cross-validation, a grid
  search or a later run that meet a press again read its row;
* the experiments' inputs are these rows too, cached the same way.

One cache format (a :class:`joblib.Memory`, validated as scikit-learn's
:func:`~sklearn.utils.validation.check_memory` validates a pipeline's
``memory``), one key per press: the step's class and the parameters that
change a row, the fingerprint of the code that computes rows
(:func:`code_fingerprint`) and the press (:func:`press_tokens`: a video of a
lazy sequence by its loader and key, without decoding it; anything else by a
hash of its values). With each row the cache keeps what the step found on
that press (its ``info``: the contact status, the corners found), so that a
press read from the cache gives the same warnings and notes as one computed.
"""

from __future__ import annotations

import functools
import hashlib
import os
import re
import shutil
import sys
from pathlib import Path

import joblib
import numpy as np
from sklearn.base import TransformerMixin
from sklearn.utils import _safe_indexing
from sklearn.utils.parallel import Parallel, delayed
from sklearn.utils.validation import check_memory

__all__ = ["PerPressTransformerMixin", "cache_size", "clear_cache", "code_fingerprint", "default_cache_dir",
           "is_per_press",
           "map_presses", "press_tokens", "transform_presses"]

#: The subpackages whose code computes per-press rows: a change to any of them invalidates every cached row.
_ROW_CODE = ("io", "datasets", "preprocessing", "features", "utils")


class PerPressTransformerMixin(TransformerMixin):
    """Mixin of transformers that map each press by itself and learn nothing from the presses in ``fit``.

    The mark that :func:`~sklearn_hardness.model_selection.evaluate_pipelines`,
    the ``memory`` cache and the experiments read (nested in a
    :class:`~sklearn.pipeline.FeatureUnion` or a
    :class:`~sklearn.pipeline.Pipeline` too). A subclass computes the rows of
    a batch of presses in its method ``_transform_presses(X)``; the mixin's
    :meth:`transform` calls it for the presses that the step's ``memory``
    cache (where it has such a parameter) does not hold yet, and reads and
    writes that cache.

    ``fit_transform`` keeps what the step found on each press (its
    ``info``) for :func:`~sklearn_hardness.model_selection.evaluate_pipelines`'
    notes; a step that finds something implements
    ``_transform_and_info(videos)``.

    Class attributes
    ----------------
    _per_press_input : {"videos", "frames", "force_position"}
        What one press is to the step: a video ``(T, H, W, C)``, selected
        frames ``(k, H, W, C)`` of an array ``(n, k, H, W, C)``, or a robot's
        force and position per frame ``(T, 2)``.
    _per_press_ignored : tuple of str
        Parameters that do not change a row (parallelism, the cache itself):
        left out of each press's cache key.

    Examples
    --------
    A step of one's own that maps each press by itself gets the shared pass of
    :func:`~sklearn_hardness.model_selection.evaluate_pipelines` and the cache of its ``memory``:

    >>> import tempfile
    >>> import numpy as np
    >>> from sklearn.base import BaseEstimator
    >>> from sklearn_hardness.utils import PerPressTransformerMixin
    >>> class PeakBrightness(PerPressTransformerMixin, BaseEstimator):
    ...     def __init__(self, memory=None):
    ...         self.memory = memory
    ...     def fit(self, X, y=None):
    ...         return self
    ...     def _transform_presses(self, X):
    ...         return np.array([[float(np.max(v))] for v in X]), {}
    >>> videos = [np.full((3, 8, 8, 3), k, np.uint8) for k in (10, 200)]
    >>> PeakBrightness(memory=tempfile.mkdtemp()).fit_transform(videos).ravel().tolist()
    [10.0, 200.0]
    """

    _per_press_input = "videos"
    _per_press_ignored = ("memory", "n_jobs")

    def transform(self, X):
        """Each press's row: from the ``memory`` cache, or computed by ``_transform_presses``.

        Parameters
        ----------
        X : sequence of presses

        Returns
        -------
        Xt : ndarray
            One row (or entry) per press, in the order of ``X``.
        """
        return transform_presses(self, X)[0]

    def fit_transform(self, X, y=None, **fit_params):
        """Fit to ``X``, then transform it: each press's row, as :meth:`transform` gives it.

        Parameters
        ----------
        X : sequence of presses
        y : ignored
        **fit_params : dict
            Passed to ``fit``.

        Returns
        -------
        Xt : ndarray
        """
        self.fit(X, y, **fit_params)
        Xt, self._press_info = self._transform_and_info(X)
        return Xt

    def _transform_and_info(self, X):
        """``(transform(X), info)``: with what the step found on each press (see ``_transform_presses``)."""
        return self.transform(X), {}

    def _transform_presses(self, X):
        """``(Xt, info)``: the rows of the presses ``X`` and what the step found on each.

        ``Xt`` has one entry per press along its first axis; ``info`` maps a
        name to one value per press (empty where the step reports nothing).
        Called on a fitted step, on the presses the cache lacks.
        """
        raise NotImplementedError(f"{type(self).__name__} must implement _transform_presses(X)")

    def _press_note(self, info, users):
        """One line on what the step found on every press of an evaluation (``info`` of all presses), or None.

        ``users`` names the pipelines that share the step. The folds of
        :func:`~sklearn_hardness.model_selection.evaluate_pipelines` fit with
        the steps' warnings silenced (each fold would repeat them); this line
        says it once.
        """
        return None

    def _shared_pass(self):
        """``(step, columns)``: a step whose rows hold this one's as ``columns``, so that steps differing only
        in the columns they output share one pass over the presses; None where there is none."""
        return None


def is_per_press(step):
    """Whether ``step`` maps each press by itself: a per-press step, or a union or pipeline of them only.

    Parameters
    ----------
    step : estimator, "drop" or "passthrough"

    Returns
    -------
    bool
    """
    from sklearn.pipeline import FeatureUnion, Pipeline

    if isinstance(step, PerPressTransformerMixin):
        return True
    if isinstance(step, FeatureUnion):
        parts = [t for _, t in step.transformer_list if t != "drop"]
        return bool(parts) and all(t != "passthrough" and is_per_press(t) for t in parts)
    if isinstance(step, Pipeline):
        parts = [s for _, s in step.steps if s not in (None, "passthrough")]
        return bool(parts) and all(is_per_press(s) for s in parts)
    return False


def _source_hash(paths):
    h = hashlib.sha256()
    for path in paths:
        h.update(str(path.name).encode() + path.read_bytes())
    return h.hexdigest()[:16]


@functools.cache
def _package_fingerprint():
    root = Path(__file__).resolve().parent.parent
    return _source_hash(sorted(p for sub in _ROW_CODE for p in (root / sub).rglob("*.py")))


@functools.cache
def _module_fingerprint(filename):
    return _source_hash([Path(filename)])


def code_fingerprint(step=None):
    """Hash of the code that computes per-press rows: a change to it invalidates every cached row.

    The package's reading, simulation, selection, feature and validation
    code (its ``io``, ``datasets``, ``preprocessing``, ``features`` and
    ``utils``), and, for a step defined outside the package, the file of its
    class.

    Parameters
    ----------
    step : estimator or None, default=None

    Returns
    -------
    fingerprint : str
    """
    fingerprint = _package_fingerprint()
    module = sys.modules.get(type(step).__module__) if step is not None else None
    filename = getattr(module, "__file__", None)
    if filename is not None and not type(step).__module__.startswith("sklearn_hardness."):
        fingerprint += _module_fingerprint(filename)
    return fingerprint


def press_tokens(X):
    """One string per press of ``X`` that identifies its values, as cheaply as it can.

    Parameters
    ----------
    X : sequence of presses
        A sequence with a ``cache_keys()`` method (the lazy sequences of
        :mod:`sklearn_hardness.datasets`: nothing is loaded) or any other
        sequence of arrays (each press is hashed, values included).

    Returns
    -------
    tokens : list of str
    """
    keys = getattr(X, "cache_keys", None)
    if callable(keys):
        tokens = keys()
        if tokens is not None:
            return list(tokens)
    return [joblib.hash(np.asarray(X[i])) for i in range(len(X))]


def _step_key(step):
    """The part of every press's key that the step gives: its class, the parameters that change a row, the code."""
    ignored = set(getattr(step, "_per_press_ignored", ()))
    params = {k: v for k, v in step.get_params(deep=False).items() if k not in ignored}
    return joblib.hash((type(step).__module__, type(step).__qualname__, params, code_fingerprint(step)))


def _stored(step_key, token, value):
    """What the cache keeps of one press: ``value``, ``(row, info)``, keyed by the step and the press alone."""
    return value


def _stack(rows):
    shapes = {np.shape(r) for r in rows}
    if len(shapes) > 1:
        first = np.shape(rows[0])
        other = next(i for i, r in enumerate(rows) if np.shape(r) != first)
        raise ValueError(f"the presses give rows of different shapes: {first} for press 0, {np.shape(rows[other])} "
                         f"for press {other}; a step that resizes (e.g. frame_size) makes them equal.")
    return np.stack(rows) if rows else np.empty((0,))


def transform_presses(step, X):
    """``step._transform_presses(X)`` through the cache of ``step.memory``: only the presses it lacks are computed.

    Parameters
    ----------
    step : PerPressTransformerMixin
        A fitted per-press step; its ``memory`` (None where it has none) is
        validated as :func:`~sklearn.utils.validation.check_memory` does.
    X : sequence of presses

    Returns
    -------
    Xt : ndarray
        One row per press, in the order of ``X``.
    info : dict of str to ndarray of shape (n_presses,)
        What the step found on each press (object arrays where the values
        are not scalars).
    """
    memory = check_memory(getattr(step, "memory", None))
    if getattr(memory, "location", True) is None:  # joblib.Memory(None): caches nothing
        Xt, info = _transform_missing(step, X, range(len(X)))
        return np.asarray(Xt), {k: _per_press_array(v) for k, v in info.items()}
    store = memory.cache(_stored, ignore=["value"])
    key, tokens = _step_key(step), press_tokens(X)
    cached = [store.check_call_in_cache(key, token, None) for token in tokens]
    values = [store(key, token, None) if hit else None for token, hit in zip(tokens, cached)]
    missing = [i for i, hit in enumerate(cached) if not hit]
    if missing:
        Xt, info = _transform_missing(step, X, missing)
        Xt = np.asarray(Xt)
        for j, i in enumerate(missing):
            values[i] = store(key, tokens[i], (Xt[j], {k: v[j] for k, v in info.items()}))
    names = values[0][1].keys() if values else ()
    info = {name: _per_press_array([v[1][name] for v in values]) for name in names}
    return _stack([v[0] for v in values]), info


#: How the steps name a press in their errors: ``X[i]`` (the selector) or ``video i`` (the feature steps).
_PRESS_NAME = re.compile(r"\b(X\[|video )(\d+)(\]?)")


def _transform_missing(step, X, missing):
    """The rows of the presses ``missing``; an error names a press by its index in ``X``, not in the subset."""
    if len(missing) == len(X):
        return step._transform_presses(X)
    try:
        return step._transform_presses(_safe_indexing(X, missing))
    except Exception as exc:
        if exc.args and isinstance(exc.args[0], str):
            renamed = _PRESS_NAME.sub(lambda m: f"{m[1]}{missing[int(m[2])]}{m[3]}", exc.args[0])
            exc.args = (renamed, *exc.args[1:])
        raise


def map_presses(function, X, params, *, n_jobs=None):
    """``function(X[i], name=f"video {i}", **params)`` for every press, stacked: one row per press.

    Parameters
    ----------
    function : callable
        A function of one press (keyword ``name``: how its errors call the
        press) and ``params`` that returns its row.
    X : sequence of presses
    params : dict
    n_jobs : int or None, default=None
        Presses processed in parallel (threads: OpenCV and NumPy release the
        GIL).

    Returns
    -------
    rows : ndarray of shape (n_presses, n_columns)
    """
    rows = Parallel(n_jobs=n_jobs, prefer="threads")(
        delayed(function)(X[i], name=f"video {i}", **params) for i in range(len(X)))
    return np.vstack(rows)


def _per_press_array(values):
    """``values`` (one per press) as an array of one entry per press: an object array where they are not scalars."""
    if isinstance(values, np.ndarray) and values.dtype != object:
        return values
    values = list(values)
    if all(np.ndim(v) == 0 for v in values):
        return np.asarray(values)
    out = np.empty(len(values), dtype=object)
    out[:] = values
    return out


def default_cache_dir():
    """Where the experiments and the command line cache the rows of per-press steps by default.

    Returns
    -------
    folder : str
        ``$SKLEARN_HARDNESS_CACHE`` where set, else ``~/.cache/sklearn_hardness``.

    Examples
    --------
    >>> import os
    >>> from sklearn_hardness.utils import default_cache_dir
    >>> os.path.basename(default_cache_dir()) in ("sklearn_hardness", os.path.basename(
    ...     os.environ.get("SKLEARN_HARDNESS_CACHE", "")))
    True
    """
    return os.environ.get("SKLEARN_HARDNESS_CACHE") or os.path.join(
        os.path.expanduser("~"), ".cache", "sklearn_hardness")


def _store(folder):
    return os.path.join(os.fspath(folder), "joblib", *__name__.split("."), _stored.__name__)


def cache_size(folder=None):
    """How many press rows ``folder``'s cache holds, and their size on disk in bytes.

    Parameters
    ----------
    folder : str or path-like or None, default=None
        The ``memory`` location the steps were given; None:
        :func:`default_cache_dir`.

    Returns
    -------
    n_rows : int
    n_bytes : int
    """
    root = _store(default_cache_dir() if folder is None else folder)
    n_rows = n_bytes = 0
    for path, _, files in os.walk(root):
        n_rows += "output.pkl" in files
        n_bytes += sum(os.path.getsize(os.path.join(path, f)) for f in files)
    return n_rows, n_bytes


def clear_cache(folder=None):
    """Delete the cached rows of every per-press step in ``folder``, and nothing else.

    The one cache of the package: what the per-press steps' ``memory``
    (:func:`~sklearn_hardness.models.make_named_pipeline`'s ``memory``, a
    user's own pipelines), the experiments and ``sklearn-hardness
    reproduce`` wrote there.

    Parameters
    ----------
    folder : str or path-like or None, default=None
        The ``memory`` location the steps were given (a
        :class:`joblib.Memory`'s ``location``); None:
        :func:`default_cache_dir`.

    Returns
    -------
    removed : list of str
        The folders removed (none where ``folder`` holds no rows).

    Examples
    --------
    >>> import tempfile
    >>> import numpy as np
    >>> from sklearn_hardness.features import PeakContactChange
    >>> from sklearn_hardness.utils import clear_cache
    >>> folder = tempfile.mkdtemp()
    >>> _ = PeakContactChange(memory=folder).fit_transform([np.zeros((3, 8, 8, 3), np.uint8)])
    >>> len(clear_cache(folder)), clear_cache(folder)
    (1, [])
    """
    root = _store(default_cache_dir() if folder is None else folder)
    if not os.path.isdir(root):
        return []
    shutil.rmtree(root)
    return [root]
