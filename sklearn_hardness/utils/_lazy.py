"""A lazy, indexable sequence of videos: the base of ``datasets``' loaders, read by ``active`` too."""

from __future__ import annotations

import numbers
import os
import pickle
from collections import OrderedDict
from collections.abc import Sequence

import joblib
import numpy as np

__all__ = ["LazyVideoSequence"]


class LazyVideoSequence(Sequence):
    """Videos that are loaded (or rendered) only when accessed.

    A read-only sequence that supports ``len``, integer indexing, slicing and
    indexing with integer or boolean arrays, so that
    :func:`sklearn.model_selection.train_test_split`,
    :func:`~sklearn.model_selection.cross_val_score` and every estimator that
    indexes ``X`` with :func:`sklearn.utils._safe_indexing` work without
    holding all frames in memory. Indexing with a slice or an array returns a
    new :class:`LazyVideoSequence` over the same loader.

    Parameters
    ----------
    loader : callable
        ``loader(key)`` returns the video of ``key`` as a ``(T, H, W, 3)``
        ``uint8`` array. It must be picklable for use with joblib's process
        backends.
    keys : sequence
        One key per video (a file path, a seed, ...).
    cache_size : int, default=0
        How many most recently used videos are kept in memory.

    Examples
    --------
    >>> import numpy as np
    >>> from sklearn_hardness.utils._lazy import LazyVideoSequence
    >>> videos = LazyVideoSequence(lambda k: np.full((3, 4, 4, 3), k, np.uint8), [1, 2, 3])
    >>> len(videos), int(videos[1][0, 0, 0, 0]), len(videos[[0, 2]])
    (3, 2, 2)
    """

    def __init__(self, loader, keys, cache_size=0):
        # not an estimator: a container checks its arguments when it is built
        if not callable(loader):
            raise TypeError(f"loader must be callable (key -> video), got {type(loader).__name__}.")
        if isinstance(keys, (str, bytes)):
            raise TypeError(f"keys must be a sequence of keys (paths, seeds, ...), not a single {type(keys).__name__}.")
        if isinstance(cache_size, (bool, np.bool_)) or not isinstance(cache_size, numbers.Integral) or cache_size < 0:
            raise ValueError(f"cache_size must be an integer >= 0, got {cache_size!r}.")
        self.loader = loader
        self.keys = list(keys)
        self.cache_size = int(cache_size)
        self._cache = OrderedDict()
        self._loader_hash = [None]  # of cache_keys, one holder shared with subsets (a simulation's takes ~0.1 s)

    def __len__(self):
        return len(self.keys)

    def _load(self, key):
        if self.cache_size <= 0:
            return self.loader(key)
        try:
            hashable = hash(key) is not None
        except TypeError:
            hashable = False
        if not hashable:
            return self.loader(key)
        if key in self._cache:
            self._cache.move_to_end(key)
            return self._cache[key]
        video = self.loader(key)
        self._cache[key] = video
        while len(self._cache) > self.cache_size:
            self._cache.popitem(last=False)
        return video

    @property
    def shape(self):
        """``(n_videos,)``: lets scikit-learn index this sequence lazily.

        :func:`sklearn.utils._safe_indexing` indexes objects with a ``shape``
        through ``__getitem__`` (returning a new lazy sequence) instead of
        building a list of loaded videos.
        """
        return (len(self.keys),)

    def __getitem__(self, index):
        if isinstance(index, tuple):
            # scikit-learn indexes "arrays" as X[key, ...]
            if len(index) == 2 and index[1] is Ellipsis:
                index = index[0]
            else:
                raise IndexError(f"videos support one index, got {index!r}")
        if isinstance(index, numbers.Integral) and not isinstance(index, (bool, np.bool_)):
            n = len(self.keys)
            if not -n <= index < n:
                raise IndexError(f"video index {index} out of range for {n} videos")
            return self._load(self.keys[index])
        if isinstance(index, slice):
            return self._subset(self.keys[index])
        idx = np.asarray(index)
        if idx.dtype == bool:
            if idx.shape != (len(self.keys),):
                raise IndexError(
                    f"boolean index of shape {idx.shape} does not match {len(self.keys)} videos"
                )
            idx = np.flatnonzero(idx)
        if idx.ndim != 1 or not np.issubdtype(idx.dtype, np.integer):
            raise IndexError(
                "videos can be indexed with an int, a slice, or a 1-D array of ints or bools; "
                f"got {type(index).__name__} {idx.dtype} of shape {idx.shape}"
            )
        return self._subset([self.keys[i] for i in idx.tolist()])

    def _subset(self, keys):
        subset = type(self)(self.loader, keys, cache_size=self.cache_size)
        subset._loader_hash = getattr(self, "_loader_hash", subset._loader_hash)
        return subset

    def cache_keys(self):
        """One string per video that names its frames without loading them.

        The hash of the ``loader`` and the video's key, and, where the key
        names a file, the file's size and modification time (a file written
        again gets a new string). The same video of two sequences (a subset,
        a fold of a cross-validation, another run) gets the same string: the
        feature steps given a ``memory`` key each press's cached row by it,
        so that a cache hit decodes no video.

        Returns
        -------
        keys : list of str or None
            One per video, in order; None where the loader cannot be pickled
            (a lambda, a local function), so that it names nothing stable.

        Examples
        --------
        >>> import numpy as np
        >>> from sklearn_hardness.utils._lazy import LazyVideoSequence
        >>> videos = LazyVideoSequence(np.zeros, [(2, 4, 4, 3), (3, 4, 4, 3)])
        >>> videos[[1]].cache_keys() == videos.cache_keys()[1:]
        True
        """
        holder = self.__dict__.setdefault("_loader_hash", [None])  # (absent from sequences pickled before it)
        if holder[0] is None:
            try:
                holder[0] = joblib.hash(self.loader)
            except (pickle.PicklingError, TypeError, AttributeError):
                return None
        return [joblib.hash((holder[0], key, _file_stamp(key))) for key in self.keys]

    def concatenate(self, other):
        """The videos of ``self`` followed by those of ``other``, still lazy.

        Parameters
        ----------
        other : LazyVideoSequence
            A sequence with the same ``loader`` (e.g. two subsets of one
            dataset).

        Returns
        -------
        videos : LazyVideoSequence
            Only the keys are concatenated; nothing is loaded.
        """
        if not isinstance(other, LazyVideoSequence) or other.loader is not self.loader:
            raise ValueError(
                "concatenate needs a LazyVideoSequence with the same loader; got "
                f"{type(other).__name__}. Concatenate loaded videos as lists instead."
            )
        return self._subset(list(self.keys) + list(other.keys))

    def __iter__(self):
        for key in self.keys:
            yield self._load(key)

    def __repr__(self):
        return f"{type(self).__name__}(n_videos={len(self)})"

    def __getstate__(self):
        state = self.__dict__.copy()
        state["_cache"] = OrderedDict()
        return state


def _file_stamp(key):
    """``(size, mtime_ns)`` of the file a key names, or None where it names none."""
    if not isinstance(key, (str, os.PathLike)):
        return None
    try:
        stat = os.stat(key)
    except (OSError, ValueError):
        return None
    return stat.st_size, stat.st_mtime_ns
