"""sklearn_hardness.metrics (work in progress)."""
