"""sklearn_hardness.experiments (work in progress)."""
