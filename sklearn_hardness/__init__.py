"""sklearn-hardness: hardness classification from vision-based tactile sensor videos.

Submodules
----------
io
    Reading and writing press videos.
datasets
    The physics-based press simulator and a loader for real recordings.
preprocessing
    Contact-frame selection.
features
    Optical-flow and DINOv2 feature transformers.
models
    Monte-Carlo-dropout classifiers (skorch nets).
active
    Uncertainty-based choice of the reference object to press next.
metrics
    Hardness-aware metrics.
model_selection
    Object-disjoint evaluation of pipelines on new objects, with corrected intervals.
experiments
    The paper's experiments as functions.
"""

import importlib

__version__ = "0.1.0"

_SUBMODULES = [
    "io",
    "datasets",
    "preprocessing",
    "features",
    "models",
    "active",
    "metrics",
    "model_selection",
    "experiments",
    "utils",
]

__all__ = _SUBMODULES + ["__version__"]


def __getattr__(name):
    if name in _SUBMODULES:
        return importlib.import_module(f"{__name__}.{name}")
    raise AttributeError(f"module {__name__!r} has no attribute {name!r}")


def __dir__():
    return __all__
