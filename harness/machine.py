"""The machine a figure was measured on: its one-thread matmul rate, BLAS kernels and versions.

Times and last digits depend on the CPU and the library builds that computed
them. :func:`matmul_gflops` is the speed reference every timing of the studies and
benchmarks is read against; :func:`machine_reference` names the rest.

    python -m harness.machine               # this machine as JSON
    python -m harness.machine --no-matmul   # without the 0.5 s measurement
"""

from __future__ import annotations

import argparse
import json
import os
import platform
import subprocess
import sys
import time

__all__ = ["matmul_gflops", "blas_kernels", "machine_reference", "describe"]

#: Environment variables that steer OpenBLAS's kernels and blocking, recorded where set.
_OPENBLAS_VARIABLES = ("OPENBLAS_CORETYPE", "OPENBLAS_L2_SIZE")


def matmul_gflops(n=2048, repeat=3, threads=1):
    """The float32 matrix-product rate of this machine: the speed reference of timings.

    Times ``a @ b`` of two ``n x n`` float32 torch tensors (one warm-up, median
    of ``repeat``): the practical peak of ``threads`` cores.

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

    Examples
    --------
    >>> from harness.machine import matmul_gflops
    >>> matmul_gflops(n=64, repeat=1) > 0
    True
    """
    import numpy as np
    import torch

    previous = torch.get_num_threads()
    if threads is not None:
        torch.set_num_threads(int(threads))
    try:
        gen = torch.Generator().manual_seed(0)
        a, b = torch.randn(n, n, generator=gen), torch.randn(n, n, generator=gen)
        a @ b  # warm-up
        times = []
        for _ in range(repeat):
            start = time.perf_counter()
            a @ b
            times.append(time.perf_counter() - start)
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


def blas_kernels(environ=None):
    """The BLAS libraries loaded, each with the kernels it runs: e.g. ``"openblas 0.3.31 Haswell"``.

    OpenBLAS picks its kernels for the CPU when it loads, unless the
    environment variable ``OPENBLAS_CORETYPE`` names others (some machine
    images set it, with ``OPENBLAS_L2_SIZE``); kernels round sums differently,
    so a run whose choices follow its floats gives the same digits where the
    same kernels ran. Those variables, where set in ``environ``
    (``os.environ`` when None), follow in brackets.

    Parameters
    ----------
    environ : mapping or None, default=None
        Where to read the OpenBLAS variables from.

    Returns
    -------
    blas : str or None
        None where ``threadpoolctl`` finds no BLAS.
    """
    import numpy  # noqa: F401 - numpy's and scipy's BLAS are loaded
    import scipy.linalg  # noqa: F401
    from threadpoolctl import threadpool_info

    environ = os.environ if environ is None else environ
    found = {" ".join(str(lib[key]) for key in ("internal_api", "version", "architecture") if lib.get(key))
             for lib in threadpool_info() if lib.get("user_api") == "blas"}
    if not found:
        return None
    steered = [f"{name}={environ[name]}" for name in _OPENBLAS_VARIABLES if environ.get(name)]
    return "; ".join(sorted(found)) + (f" ({', '.join(steered)})" if steered else "")


def machine_reference(matmul=True, env=None):
    """A short description of this machine, with its matrix-product rate as speed reference.

    Parameters
    ----------
    matmul : bool, default=True
        Measure :func:`matmul_gflops` on one thread (four 2048x2048 products).
    env : mapping or None, default=None
        Measure in a fresh Python process with this environment instead of this
        one: OpenBLAS picks its kernels when it loads, so the kernels a child
        process ran under ``OPENBLAS_CORETYPE`` are only seen there.

    Returns
    -------
    machine : dict
        ``cpu`` (model name), ``cores`` (``os.cpu_count()``), ``torch_threads``,
        ``torch``, ``numpy``, ``python`` (versions), ``blas``
        (:func:`blas_kernels`), ``matmul_gflops`` (one thread, float32, 2048^3;
        None without ``matmul``) and ``load`` (the 1-minute load average, None
        where the system does not give it: a rate measured on a busy machine is
        lower).

    Examples
    --------
    >>> from harness.machine import machine_reference
    >>> machine_reference(matmul=False)["matmul_gflops"] is None
    True
    """
    if env is not None:
        argv = [sys.executable, "-m", "harness.machine"] + ([] if matmul else ["--no-matmul"])
        root = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
        done = subprocess.run(argv, cwd=root, env=dict(env), capture_output=True, text=True, check=True)
        return json.loads(done.stdout)
    import numpy as np
    import torch

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
        "blas": blas_kernels(),
        "matmul_gflops": round(matmul_gflops(), 1) if matmul else None,
        "load": load,
    }


def describe(machine):
    """One line of :func:`machine_reference`'s fields, for a header.

    Examples
    --------
    >>> from harness.machine import describe
    >>> describe({"cpu": "Xeon", "cores": 2, "matmul_gflops": 80.0, "torch": "2.1", "numpy": "2.0",
    ...           "python": "3.11.7", "blas": "openblas 0.3.31 Haswell"})
    'Xeon, 2 cores, matmul 80 GFLOP/s (one thread), torch 2.1, numpy 2.0, Python 3.11.7, BLAS openblas 0.3.31 Haswell'
    """
    rate = machine.get("matmul_gflops")
    return (f"{machine['cpu']}, {machine['cores']} cores, "
            + (f"matmul {rate:.0f} GFLOP/s (one thread), " if rate is not None else "")
            + f"torch {machine['torch']}, numpy {machine['numpy']}, Python {machine['python']}, "
            f"BLAS {machine.get('blas')}")


def main(argv=None):
    ap = argparse.ArgumentParser(description="Print this machine's reference as JSON.")
    ap.add_argument("--no-matmul", action="store_true", help="skip the matmul rate (0.5 s)")
    args = ap.parse_args(argv)
    print(json.dumps(machine_reference(matmul=not args.no_matmul)))


if __name__ == "__main__":
    main()
