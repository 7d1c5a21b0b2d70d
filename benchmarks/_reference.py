"""The machine's reference rate for the benchmarks' GFLOP/s figures; a helper, not a benchmark."""

import time

import numpy as np
import torch


def matmul_gflops(n=2048, repeat=3):
    """Float32 ``n x n`` matrix-product rate on the current torch threads, GFLOP/s (median of ``repeat``)."""
    gen = torch.Generator().manual_seed(0)
    a, b = torch.randn(n, n, generator=gen), torch.randn(n, n, generator=gen)
    a @ b  # warm-up
    times = []
    for _ in range(repeat):
        start = time.perf_counter()
        a @ b
        times.append(time.perf_counter() - start)
    return 2 * n**3 / float(np.median(times)) / 1e9
