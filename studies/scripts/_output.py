"""``--out`` of the study scripts: the printed text under a short header.

The header says how the file was made: the command (a data folder named by its
role, ``--data EXAMPLE_DATA``, never by a path of one machine), the commit, the
date and the machine with its one-thread float32 matmul rate, so that times
and digits can be read against the machine that made them.
"""

import datetime
import os
import platform
import shlex
import subprocess
import sys
import time

import numpy as np

#: Options whose value is where output goes, not what was computed.
_WHERE = {"--out", "--cache"}


def _command(argv):
    args, skip = [], False
    for i, arg in enumerate(argv):
        if skip:
            skip = False
            continue
        if arg in _WHERE:
            skip = True
            continue
        if i > 0 and argv[i - 1] in ("--data", "--manifest"):
            arg = "EXAMPLE_DATA" if os.path.basename(arg.rstrip("/")) == "example_data" else "DATA"
        args.append(arg)
    script = os.path.basename(argv[0])
    return shlex.join(["python", f"studies/scripts/{script}", *args[1:]])


def _commit():
    here = os.path.dirname(os.path.abspath(__file__))
    try:
        out = subprocess.run(["git", "-C", here, "rev-parse", "--short=10", "HEAD"],
                             capture_output=True, text=True, check=True).stdout.strip()
        dirty = subprocess.run(["git", "-C", here, "status", "--porcelain", "--untracked-files=no"],
                               capture_output=True, text=True, check=True).stdout.strip()
    except (OSError, subprocess.CalledProcessError):
        return "unknown"
    return out + (" (uncommitted changes)" if dirty else "")


def matmul_gflops(n=512, repeats=5):
    """One-thread float32 matmul rate of this machine, GFLOP/s (best of ``repeats``)."""
    from threadpoolctl import threadpool_limits

    a = np.random.default_rng(0).standard_normal((n, n), dtype=np.float32)
    best = float("inf")
    with threadpool_limits(1):
        for _ in range(repeats):
            start = time.perf_counter()
            a @ a
            best = min(best, time.perf_counter() - start)
    return 2 * n**3 / best / 1e9


def header(argv=None):
    """The three header lines of an output made by ``argv`` (default ``sys.argv``)."""
    import torch

    argv = sys.argv if argv is None else argv
    cpu = platform.processor() or platform.machine()
    machine = (f"{cpu}, {os.cpu_count()} cores, torch {torch.__version__}, numpy {np.__version__}, "
               f"Python {platform.python_version()}, matmul {matmul_gflops():.0f} GFLOP/s (one thread)")
    date = datetime.datetime.now(datetime.timezone.utc).strftime("%Y-%m-%dT%H:%MZ")
    return (f"# command: {_command(argv)}\n# commit: {_commit()}, {date}\n# machine: {machine}")


def write_output(path, text):
    """Write ``text`` to ``path`` after :func:`header`."""
    with open(path, "w") as f:
        f.write(header() + "\n" + text + "\n")


def report(text, out=None):
    """Print ``text``; with ``out``, also write it there after the header (:func:`write_output`)."""
    print(text)
    if out:
        write_output(out, text)
