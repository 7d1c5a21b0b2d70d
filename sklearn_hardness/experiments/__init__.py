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
  :func:`decision_stop`: where a run would have stopped (presses to decision);
  :func:`presses_to_reach`: presses each strategy needs to reach random's final accuracy.
- :func:`plot_active_sampling`, :func:`plot_uncertainty`,
  :func:`plot_dropout_sweep`, :func:`plot_model_baselines`,
  :func:`save_figures`: the paper's figures (matplotlib, PNG).
- :func:`get_config`: the paper's hyperparameters per preset.
- :func:`provenance_header`, :func:`code_fingerprint`, :func:`machine_reference`:
  what made a generated table (command, config hash, code, machine).
"""

from ._active import STRATEGIES, planned_config_hash, run_active_sampling
from ._baselines import run_dropout_sweep, run_model_baselines
from ._plotting import (
    plot_active_sampling,
    plot_dropout_sweep,
    plot_model_baselines,
    plot_uncertainty,
    save_figures,
)
from ._stats import (
    PAIRED_METRICS,
    decision_stop,
    format_paired_table,
    format_presses_to_reach,
    paired_table,
    presses_to_reach,
)
from ._tables import HUMAN_ACCURACY, baseline_table, comparison_table, format_table
from ._config import MODEL_NAMES, PRESET_CONFIGS, QUICK_OVERRIDES, config_hash, get_config
from ._provenance import code_fingerprint, machine_reference, matmul_gflops, parse_provenance, provenance_header
from ._results import ExperimentResult, ResultsStore

__all__ = [
    "run_active_sampling",
    "run_model_baselines",
    "run_dropout_sweep",
    "comparison_table",
    "baseline_table",
    "format_table",
    "paired_table",
    "format_paired_table",
    "PAIRED_METRICS",
    "decision_stop",
    "presses_to_reach",
    "format_presses_to_reach",
    "HUMAN_ACCURACY",
    "plot_active_sampling",
    "plot_uncertainty",
    "plot_dropout_sweep",
    "plot_model_baselines",
    "save_figures",
    "STRATEGIES",
    "get_config",
    "config_hash",
    "planned_config_hash",
    "code_fingerprint",
    "machine_reference",
    "matmul_gflops",
    "provenance_header",
    "parse_provenance",
    "PRESET_CONFIGS",
    "QUICK_OVERRIDES",
    "MODEL_NAMES",
    "ExperimentResult",
    "ResultsStore",
]
