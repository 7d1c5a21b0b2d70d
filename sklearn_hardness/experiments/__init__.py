"""The paper's experiments as functions, with tables and figures.

- :func:`run_active_sampling`: strategies compared over (test object, seed)
  runs (Sec. III-F, Algorithm 1), resumable from a JSON Lines results file.
- :func:`run_model_baselines`: the three classifiers on ``s0`` presses per
  object (Sec. III-D).
- :func:`run_dropout_sweep`: accuracy and MAE against the dropout rate
  (Sec. III-E).
- :func:`comparison_table`, :func:`format_table`: the paper's Table I.
- :func:`paired_table`, :func:`format_paired_table`: strategies against
  random over paired runs, with 95% intervals and p-values;
  :func:`presses_to_reach`: presses each strategy needs to reach random's final accuracy.
- :func:`plot_active_sampling`, :func:`plot_uncertainty`,
  :func:`plot_model_baselines`,
  :func:`save_figures`: the paper's figures (matplotlib, PNG).
- :func:`get_config`: the paper's hyperparameters per preset;
  :func:`check_config` checks one.
- :func:`run_paper_protocol`: all of the above, as ``sklearn-hardness reproduce --protocol paper``.
- :func:`load_dataset`: the data an experiment's ``dataset`` names. The
  prepared inputs are the per-press steps' rows, cached in
  :func:`sklearn_hardness.utils.default_cache_dir` by default
  (:func:`sklearn_hardness.utils.clear_cache` deletes them).

Object-disjoint evaluation of pipelines on new objects is
:mod:`sklearn_hardness.model_selection`.
"""

from ._active import run_active_sampling
from ._baselines import run_dropout_sweep, run_model_baselines
from ._config import check_config, get_config
from ._data import load_dataset
from ._plotting import plot_active_sampling, plot_model_baselines, plot_uncertainty, save_figures
from ._protocol import run_paper_protocol
from ._results import ExperimentResult
from ._stats import format_paired_table, format_presses_to_reach, paired_table, presses_to_reach
from ._tables import baseline_table, comparison_table, format_table

__all__ = [
    "run_active_sampling",
    "run_model_baselines",
    "run_dropout_sweep",
    "comparison_table",
    "baseline_table",
    "format_table",
    "paired_table",
    "format_paired_table",
    "presses_to_reach",
    "format_presses_to_reach",
    "plot_active_sampling",
    "plot_uncertainty",
    "plot_model_baselines",
    "save_figures",
    "get_config",
    "check_config",
    "run_paper_protocol",
    "load_dataset",
    "ExperimentResult",
]
