"""sklearn_hardness.preprocessing (work in progress)."""
