"""Utilities: the mark of per-press steps and their cache, and the common checks of estimators.

- :class:`PerPressTransformerMixin`: the mark of a transformer that maps
  each press by itself and learns nothing from the presses in ``fit`` (the
  package's frame selection, features and peak change carry it). The
  machinery reads it: ``evaluate_pipelines`` runs such steps once over all
  presses, and their ``memory`` caches each press's rows. Inherit it to
  give your own step the same.
- :func:`clear_cache`, :func:`default_cache_dir`: the one cache of those
  rows (the steps' ``memory``, the experiments', ``sklearn-hardness
  reproduce``'s). How much it holds: ``sklearn-hardness cache``.
- :mod:`sklearn_hardness.utils.estimator_checks`: the common checks of
  estimators that take press videos or selected frames.
"""

from ._lazy_names import lazy_names

#: Each public name and its module, imported when first asked for: the helpers the other subpackages import
#: from utils (this light one among them) do not import scikit-learn through this file.
_LAZY = {"PerPressTransformerMixin": "._per_press", "clear_cache": "._per_press", "default_cache_dir": "._per_press"}

__all__ = list(_LAZY)

__getattr__, __dir__ = lazy_names(__name__, globals(), _LAZY)
