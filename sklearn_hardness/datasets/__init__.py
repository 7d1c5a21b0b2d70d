"""sklearn_hardness.datasets (work in progress)."""
