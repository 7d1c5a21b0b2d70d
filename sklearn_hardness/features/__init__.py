"""sklearn_hardness.features (work in progress)."""
