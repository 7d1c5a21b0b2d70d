"""The package's command line as a user runs it: the ``sklearn-hardness`` console script, on this checkout.

The lab runs ``sklearn-hardness reproduce``, ``simulate`` ... in a process of their
own (README's table, a study that changes the process's environment, a
benchmark that writes presses as a user would). The console script is the
command line's public entry; ``PYTHONPATH`` puts this checkout first, so that
the script runs the code beside the harness, as the lab's own imports do.
"""

from __future__ import annotations

import os
import shutil
import subprocess
import sys

from . import ROOT

__all__ = ["console_script", "run_sklearn_hardness"]


def console_script():
    """The path of the ``sklearn-hardness`` console script: beside this interpreter, else on ``PATH``."""
    beside = os.path.join(os.path.dirname(sys.executable), "sklearn-hardness")
    found = beside if os.path.exists(beside) else shutil.which("sklearn-hardness")
    if found is None:
        raise FileNotFoundError("no sklearn-hardness console script beside this Python nor on PATH: install the "
                                "package into this environment (pip install -e .).")
    return found


def run_sklearn_hardness(args, *, env=None, **kwargs):
    """Run ``sklearn-hardness ARGS`` on this checkout; ``check=True`` unless given.

    Parameters
    ----------
    args : list of str
        The subcommand and its arguments.
    env : dict or None, default=None
        The process's environment (default: this one's), with this checkout
        put first on ``PYTHONPATH``.
    **kwargs
        Passed to :func:`subprocess.run`.

    Returns
    -------
    completed : subprocess.CompletedProcess
    """
    env = dict(os.environ if env is None else env)
    env["PYTHONPATH"] = os.pathsep.join(p for p in (ROOT, env.get("PYTHONPATH")) if p)
    kwargs.setdefault("check", True)
    return subprocess.run([console_script(), *args], env=env, **kwargs)
