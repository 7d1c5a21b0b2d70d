"""Model selection on new objects: group-disjoint cross-validation with corrected intervals.

* :func:`evaluate_pipelines`: cross-validation of several pipelines on the
  same folds, grouped by object (no test object is seen in training), each
  beside the one-number baseline, its margin paired by fold, and the
  pipeline to choose; an :class:`EvaluationResult`.
* :class:`RepeatedStratifiedGroupKFold`: the folds an integer ``cv`` stands for.
* :func:`corrected_interval`: the t-interval of fold scores (or of a paired
  difference) corrected for the folds' overlapping training sets.
* :func:`format_evaluation`, :class:`ConfusionMatricesDisplay`: the result as
  text and as a figure.
"""

from ._evaluate import evaluate_pipelines
from ._intervals import corrected_interval
from ._plot import ConfusionMatricesDisplay
from ._report import format_evaluation
from ._result import EvaluationResult, SummaryTable
from ._split import RepeatedStratifiedGroupKFold

__all__ = ["evaluate_pipelines", "EvaluationResult", "SummaryTable", "RepeatedStratifiedGroupKFold",
           "corrected_interval", "format_evaluation", "ConfusionMatricesDisplay"]
