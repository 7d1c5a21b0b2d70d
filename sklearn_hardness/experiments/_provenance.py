"""Provenance of generated outputs: the command, commit, date and machine that made them (private).

A table's floats depend on the CPU and the library builds that computed them. Each
output of the command line starts with one line naming the command, the
configuration hash where it has one, the git commit, the machine (with the
single-thread float32 matrix-product rate as its speed reference, and the kernels
its BLAS runs) and the date. It records what made the output; no test compares it
with the current code (an output is rerun when its question is revisited).
"""

from __future__ import annotations

import datetime
import json
import os
import platform
import subprocess
import time

import numpy as np
import torch

__all__ = ["machine_reference", "matmul_gflops", "provenance_header", "parse_provenance"]

_PACKAGE_ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
_PREFIX = "# provenance "


def matmul_gflops(n=2048, repeat=3, threads=1):
    """The float32 matrix-product rate of this machine: the speed reference of timings.

    Times ``a @ b`` of two ``n x n`` float32 tensors (one warm-up, median of
    ``repeat``) on ``threads`` torch threads: the practical peak of a core.

    Parameters
    ----------
    n : int, default=2048
        Matrix size.
    repeat : int, default=3
        Timed products; the median is used.
    threads : int or None, default=1
        Torch threads during the measurement (restored after); None: as set.

    Returns
    -------
    gflops : float
        ``2 n^3 / t`` in GFLOP/s.
    """
    previous = torch.get_num_threads()
    if threads is not None:
        torch.set_num_threads(int(threads))
    try:
        gen = torch.Generator().manual_seed(0)
        a, b = torch.randn(n, n, generator=gen), torch.randn(n, n, generator=gen)
        a @ b  # warm-up
        times = []
        for _ in range(repeat):
            t = time.perf_counter()
            a @ b
            times.append(time.perf_counter() - t)
    finally:
        torch.set_num_threads(previous)
    return 2 * n**3 / float(np.median(times)) / 1e9


def _cpu_model():
    try:
        with open("/proc/cpuinfo") as f:
            for line in f:
                if line.startswith("model name"):
                    return line.split(":", 1)[1].strip()
    except OSError:
        pass
    return platform.processor() or platform.machine()


#: Environment variables that steer OpenBLAS's kernels and blocking, recorded where set.
_OPENBLAS_VARIABLES = ("OPENBLAS_CORETYPE", "OPENBLAS_L2_SIZE")


def _blas(environ=None):
    """The BLAS libraries loaded, each with the kernels it runs: e.g. ``"openblas 0.3.31 Haswell"``.

    OpenBLAS picks its kernels for the CPU when it loads, unless the
    environment variable ``OPENBLAS_CORETYPE`` names others (some machine
    images set it, with ``OPENBLAS_L2_SIZE``, where older builds fail with
    their own choice); kernels round sums differently. A run whose choices
    follow its floats (posterior samples of a refitted model) gives the same
    digits where the same kernels ran, and can differ in the last digits
    elsewhere. Those variables, where set in ``environ`` (``os.environ`` when
    None), follow in brackets. None where ``threadpoolctl`` finds no BLAS.
    """
    import scipy.linalg  # noqa: F401 - scipy's BLAS is loaded too
    from threadpoolctl import threadpool_info

    environ = os.environ if environ is None else environ
    found = {" ".join(str(lib[key]) for key in ("internal_api", "version", "architecture") if lib.get(key))
             for lib in threadpool_info() if lib.get("user_api") == "blas"}
    if not found:
        return None
    steered = [f"{name}={environ[name]}" for name in _OPENBLAS_VARIABLES if environ.get(name)]
    return "; ".join(sorted(found)) + (f" ({', '.join(steered)})" if steered else "")


def machine_reference(matmul=True):
    """A short description of this machine, with its matrix-product rate as speed reference.

    Parameters
    ----------
    matmul : bool, default=True
        Measure :func:`matmul_gflops` on one thread (four 2048x2048 products).

    Returns
    -------
    machine : dict
        ``cpu`` (model name), ``cores`` (``os.cpu_count()``), ``torch_threads``,
        ``torch``, ``numpy``, ``python`` (versions), ``blas`` (the BLAS
        libraries and the kernels they run, e.g. ``"openblas 0.3.31.188.0
        Haswell (OPENBLAS_CORETYPE=Haswell, OPENBLAS_L2_SIZE=512)"``, with the
        environment variables that chose them where set: runs that refit a
        model between choices give the same digits where the same kernels
        ran), ``matmul_gflops`` (one
        thread, float32, 2048^3; None without ``matmul``) and ``load`` (the
        1-minute load average when measured, None where the system does not
        give it: a rate measured on a busy machine is lower).
    """
    try:
        load = round(os.getloadavg()[0], 1)
    except (AttributeError, OSError):
        load = None
    return {
        "cpu": _cpu_model(),
        "cores": os.cpu_count(),
        "torch_threads": torch.get_num_threads(),
        "torch": torch.__version__,
        "numpy": np.__version__,
        "python": platform.python_version(),
        "blas": _blas(),
        "matmul_gflops": round(matmul_gflops(), 1) if matmul else None,
        "load": load,
    }


def _git_commit(root=_PACKAGE_ROOT):
    """HEAD of the repository holding ``root`` (``+dirty`` if its code has uncommitted changes), or None."""
    try:
        run = dict(cwd=root, capture_output=True, text=True, timeout=10, check=True)
        commit = subprocess.run(["git", "rev-parse", "--short=10", "HEAD"], **run).stdout.strip()
        dirty = subprocess.run(["git", "status", "--porcelain", "--", "."], **run).stdout.strip()
    except (OSError, subprocess.SubprocessError):
        return None
    return commit + ("+dirty" if dirty else "") if commit else None


def provenance_header(command, *, config_hash=None, machine=None, date=None, commit=None):
    """One line naming what made an output: command, config hash, commit, machine, date.

    Parameters
    ----------
    command : str
        The command that made the table, as a user would type it.
    config_hash : str or None, default=None
        Its :func:`config_hash`, where it has one.
    machine : dict or None, default=None
        :func:`machine_reference` (measured when None).
    date : str or None, default=None
        ISO date and time in UTC (now when None).
    commit : str or None, default=None
        Git commit (HEAD of the package's repository when None, if any).

    Returns
    -------
    line : str
        ``"# provenance "`` followed by one line of JSON with the keys
        ``command``, ``config_hash``, ``commit``, ``machine`` and ``date``;
        read back with :func:`parse_provenance`.

    Examples
    --------
    >>> from sklearn_hardness.experiments._provenance import parse_provenance, provenance_header
    >>> line = provenance_header("sklearn-hardness reproduce --quick", machine={}, date="2026-01-01T00:00Z")
    >>> parse_provenance(line)["command"]
    'sklearn-hardness reproduce --quick'
    """
    if not isinstance(command, str) or not command.strip() or "\n" in command:
        raise ValueError(f"command must be a non-empty one-line string, got {command!r}.")
    record = {
        "command": command,
        "config_hash": config_hash,
        "commit": _git_commit() if commit is None else commit,
        "machine": machine_reference() if machine is None else machine,
        "date": date or datetime.datetime.now(datetime.timezone.utc).strftime("%Y-%m-%dT%H:%MZ"),
    }
    return _PREFIX + json.dumps(record)


def parse_provenance(text):
    """The provenance record of a text (the first :func:`provenance_header` line in it), or None.

    Parameters
    ----------
    text : str
        A generated file's text, or one line.

    Returns
    -------
    record : dict or None
        The header's fields; None when the text has no provenance line.
    """
    for line in text.splitlines():
        if line.startswith(_PREFIX):
            return json.loads(line[len(_PREFIX):])
    return None
