"""Public names of a subpackage imported when first asked for (PEP 562), so that importing it stays light."""

from __future__ import annotations

import importlib

__all__ = ["lazy_names"]


def lazy_names(package, namespace, modules):
    """The ``__getattr__`` and ``__dir__`` of ``package`` that import each name of ``modules`` on first use.

    Parameters
    ----------
    package : str
        The package's ``__name__``.
    namespace : dict
        The package's ``globals()``: a name once imported is kept there, so later look-ups find it directly.
    modules : dict of str to str
        Each lazy name and the module (relative to ``package``) that defines it.

    Returns
    -------
    getattr, dir : callable
    """

    def __getattr__(name):
        if name in modules:
            value = getattr(importlib.import_module(modules[name], package), name)
            namespace[name] = value
            return value
        raise AttributeError(f"module {package!r} has no attribute {name!r}")

    def __dir__():
        return sorted(set(namespace) | set(namespace.get("__all__", ())))

    return __getattr__, __dir__
