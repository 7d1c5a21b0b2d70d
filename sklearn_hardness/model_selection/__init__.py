"""Model selection on new objects: object-disjoint cross-validation with corrected intervals.

* :func:`evaluate_pipelines`: cross-validation grouped by ``object_id`` (no test
  object is seen in training) of named or given pipelines beside the
  one-number baseline, each pipeline's margin over it paired by fold, and the
  pipeline to choose.
* :func:`corrected_interval`: the t-interval of fold scores (or of a paired
  difference) corrected for the folds' overlapping training sets.
* :func:`format_evaluation`, :func:`plot_confusion_matrices`: the result as
  text and as a figure.
"""

from ._evaluate import evaluate_pipelines
from ._intervals import corrected_interval
from ._plot import plot_confusion_matrices
from ._report import format_evaluation

__all__ = ["evaluate_pipelines", "corrected_interval", "format_evaluation", "plot_confusion_matrices"]
