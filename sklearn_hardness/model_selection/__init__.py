"""Model selection on new objects: group-disjoint cross-validation with corrected intervals.

* :func:`evaluate_pipelines`: :func:`~sklearn.model_selection.cross_validate`
  for several pipelines on the same folds, grouped by object (no test object
  is seen in training), each beside the one-number baseline; an
  :class:`EvaluationResult`, whose ``cv_results_`` give each fold and whose
  ``summary`` the margins paired by fold and the pipeline to choose.
* :class:`RepeatedStratifiedGroupKFold`: the folds an integer ``cv`` stands for.
* :func:`corrected_interval`: the t-interval of fold scores (or of a paired
  difference) corrected for the folds' overlapping training sets.
* :class:`ConfusionMatricesDisplay`: the result as a figure (``print(result)``
  writes it as text).
"""

from ._intervals import corrected_interval
from ._plot import ConfusionMatricesDisplay
from ._result import EvaluationResult
from ._split import RepeatedStratifiedGroupKFold
from ._validation import evaluate_pipelines

__all__ = ["evaluate_pipelines", "EvaluationResult", "RepeatedStratifiedGroupKFold", "corrected_interval",
           "ConfusionMatricesDisplay"]
