"""sklearn_hardness.models (work in progress)."""
