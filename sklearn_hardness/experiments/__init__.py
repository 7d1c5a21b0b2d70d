"""The paper's experiments as functions, with tables and figures.

- :func:`run_active_sampling`: strategies compared over (test object, seed)
  runs (Sec. III-F, Algorithm 1), resumable from a JSON Lines results file.
- :func:`run_model_baselines`: the three classifiers on ``s0`` presses per
  object (Sec. III-D).
- :func:`run_dropout_sweep`: accuracy and MAE against the dropout rate
  (Sec. III-E).
- :class:`ExperimentResult`: what each of them returns, the records of its
  runs, with the tables and figures as methods: ``comparison_table`` (the
  paper's Table I), ``baseline_table``, ``paired_table`` (strategies against
  random over paired runs, with 95% intervals and p-values),
  ``presses_to_reach`` (presses each strategy needs to reach random's final
  accuracy), their ``format_*`` text, and the paper's figures
  (``plot_active_sampling``, ``plot_uncertainty``, ``plot_dropout_sweep``,
  ``plot_model_baselines``, ``save_figures``; matplotlib, the ``plot`` extra).
- :func:`get_config`: the paper's hyperparameters per preset;
  :func:`check_config` checks one.
- :func:`run_paper_protocol`: all of the above, as ``sklearn-hardness reproduce --protocol paper``.
- :func:`load_dataset`: the data an experiment's ``dataset`` names. The
  prepared inputs are the per-press steps' rows, cached in
  :func:`sklearn_hardness.utils.default_cache_dir` by default
  (:func:`sklearn_hardness.utils.clear_cache` deletes them).

Object-disjoint evaluation of pipelines on new objects is
:mod:`sklearn_hardness.model_selection`.

Constants, importable without torch (the command line's ``--help`` reads
them): :data:`EXPERIMENT_MODELS`, the named pipelines the experiments run;
:data:`STRATEGIES`, the strategies compared by default; :data:`QUICK_OVERRIDES`,
what ``quick=True`` changes; :data:`CONFIG_KEYS`, one line on each key of a
configuration. The functions import their modules when first asked for.
"""

from ..utils._lazy_names import lazy_names
from ._names import CONFIG_KEYS as CONFIG_KEYS  # the constants: documented above, not functions of __all__
from ._names import EXPERIMENT_MODELS as EXPERIMENT_MODELS
from ._names import QUICK_OVERRIDES as QUICK_OVERRIDES
from ._names import STRATEGIES as STRATEGIES

#: Each public name and the module it is imported from when first asked for.
_LAZY = {
    "run_active_sampling": "._active",
    "run_model_baselines": "._baselines",
    "run_dropout_sweep": "._baselines",
    "get_config": "._config",
    "check_config": "._config",
    "run_paper_protocol": "._protocol",
    "load_dataset": "._data",
    "ExperimentResult": "._results",
}

__all__ = list(_LAZY)


__getattr__, __dir__ = lazy_names(__name__, globals(), _LAZY)
