"""Optional dependencies: imported where a function needs them, with an error that names the extra to install."""

from __future__ import annotations

import importlib

__all__ = ["import_optional"]

#: The optional dependencies by extra (``pip install "sklearn-hardness[EXTRA]"``).
EXTRAS = {"plot": "matplotlib", "texture": "scikit-image", "dinov2": "transformers"}


def import_optional(module, extra, caller):
    """``module`` imported, or an ImportError saying that ``caller`` needs it and which extra installs it.

    Parameters
    ----------
    module : str
        The module to import, e.g. ``"matplotlib.pyplot"``.
    extra : str
        The extra of sklearn-hardness that installs it (a key of ``EXTRAS``).
    caller : str
        What needs it, as the user called it.

    Returns
    -------
    module : module

    Raises
    ------
    ImportError
        Where ``module`` cannot be imported.

    Examples
    --------
    >>> from sklearn_hardness.utils._optional import import_optional
    >>> import_optional("math", "plot", "f").sqrt(4.0)
    2.0
    """
    try:
        return importlib.import_module(module)
    except ImportError as exc:
        raise ImportError(
            f"{caller} needs {EXTRAS[extra]}, an optional dependency of sklearn-hardness: "
            f'pip install "sklearn-hardness[{extra}]" (or pip install {EXTRAS[extra]}).') from exc
