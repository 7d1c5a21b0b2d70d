"""sklearn_hardness.active (work in progress)."""
