"""Provenance of generated tables: the command, configuration, code and machine that made them.

A table's floats depend on the CPU and the library builds that computed them, so
they cannot be checked on another machine; what made them can. A provenance line
names the command, the configuration hash, a fingerprint of the code (its syntax
tree without docstrings or comments, so rewording the documentation changes
nothing while any change of code does), the git commit, the machine (with the
single-thread float32 matrix-product rate of ``benchmarks/bench_flops.py`` as its
speed reference, and the kernels its BLAS runs) and the date. Tests then compare
the fingerprint and the configuration hash with the current code's, on any machine.
"""

from __future__ import annotations

import ast
import datetime
import hashlib
import json
import os
import platform
import subprocess
import time

import numpy as np
import torch

__all__ = ["code_fingerprint", "machine_reference", "matmul_gflops", "provenance_header", "parse_provenance"]

_PACKAGE_ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
_PREFIX = "# provenance "


def _strip_docstrings(tree):
    for node in ast.walk(tree):
        if isinstance(node, (ast.Module, ast.ClassDef, ast.FunctionDef, ast.AsyncFunctionDef)):
            body = node.body
            if body and isinstance(body[0], ast.Expr) and isinstance(body[0].value, ast.Constant) \
                    and isinstance(body[0].value.value, str):
                node.body = body[1:] or [ast.Pass()]
    return tree


def _stable_dump(node):
    """``ast.dump`` without the fields that are empty or None.

    Python versions add fields with empty defaults (3.12's ``type_params``)
    and 3.13 leaves empty ones out of ``ast.dump``; some 3.12 releases also end
    an f-string's parts with an empty string. Dropping both gives one text per
    program on Python 3.10 to 3.13.
    """
    if isinstance(node, ast.AST):
        fields = []
        for name in node._fields:
            value = getattr(node, name, None)
            if isinstance(node, ast.JoinedStr) and name == "values":
                value = [v for v in value if not (isinstance(v, ast.Constant) and v.value == "")]
            if value is None or (isinstance(value, list) and not value):
                continue
            fields.append(f"{name}={_stable_dump(value)}")
        return f"{type(node).__name__}({', '.join(fields)})"
    if isinstance(node, list):
        return "[" + ", ".join(_stable_dump(v) for v in node) + "]"
    return repr(node)


def code_fingerprint(root=None, *, legacy=False):
    """A fingerprint of the Python code under ``root``, blind to docstrings and comments.

    SHA-256 over the syntax tree of every ``.py`` file (sorted by relative
    path, docstrings removed; comments and layout never reach the syntax
    tree), so any change that can alter what the code computes changes it,
    while rewording documentation does not. Fields a Python version leaves
    empty are not part of the text hashed, so the fingerprint is the same on
    Python 3.10 to 3.13.

    Parameters
    ----------
    root : str or path-like or None, default=None
        Folder to fingerprint; None: the installed ``sklearn_hardness`` package.
    legacy : bool, default=False
        The fingerprint as written before 2026-11-24 (plain ``ast.dump``),
        which differs between Python versions (3.10 and 3.11 agree; 3.12 and
        3.13 each give another): only to check files made then.

    Returns
    -------
    fingerprint : str
        The first 16 hexadecimal digits of the SHA-256.

    Examples
    --------
    >>> from sklearn_hardness.experiments import code_fingerprint
    >>> len(code_fingerprint())
    16
    """
    root = os.path.abspath(_PACKAGE_ROOT if root is None else os.fspath(root))
    if not os.path.isdir(root):
        raise ValueError(f"root {root!r} is not a folder.")
    paths = []
    for folder, dirs, files in os.walk(root):
        dirs[:] = sorted(d for d in dirs if d != "__pycache__" and not d.startswith("."))
        paths += [os.path.join(folder, f) for f in files if f.endswith(".py")]
    dump = ast.dump if legacy else _stable_dump
    h = hashlib.sha256()
    for path in sorted(paths, key=lambda p: os.path.relpath(p, root).replace(os.sep, "/")):
        with open(path, "rb") as f:
            tree = _strip_docstrings(ast.parse(f.read(), filename=path))
        h.update(os.path.relpath(path, root).replace(os.sep, "/").encode() + b"\0")
        h.update(dump(tree).encode() + b"\0")
    return h.hexdigest()[:16]


def matmul_gflops(n=2048, repeat=3, threads=1):
    """The float32 matrix-product rate of this machine: the speed reference of timings.

    Times ``a @ b`` of two ``n x n`` float32 tensors (one warm-up, median of
    ``repeat``) on ``threads`` torch threads; ``benchmarks/bench_flops.py``
    uses it as the practical peak of the cores. About 1 s at the defaults on
    a core doing 75-100 GFLOP/s.

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
        Measure :func:`matmul_gflops` on one thread (about 1 s).

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
    """One line naming what made a table: command, config hash, code, commit, machine, date.

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
        ``command``, ``config_hash``, ``code_fingerprint`` (of the installed
        package), ``commit``, ``machine`` and ``date``; read back with
        :func:`parse_provenance`.

    Examples
    --------
    >>> from sklearn_hardness.experiments import parse_provenance, provenance_header
    >>> line = provenance_header("sklearn-hardness reproduce --quick", machine={}, date="2026-01-01T00:00Z")
    >>> parse_provenance(line)["command"]
    'sklearn-hardness reproduce --quick'
    """
    if not isinstance(command, str) or not command.strip() or "\n" in command:
        raise ValueError(f"command must be a non-empty one-line string, got {command!r}.")
    record = {
        "command": command,
        "config_hash": config_hash,
        "code_fingerprint": code_fingerprint(),
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
