"""Benchmark: how close a ConvLSTM training step comes to the machine's arithmetic limit.

Counts the floating-point operations of one training step (forward, backward,
Adam update excluded) of ``ConvLSTMNet`` with ``torch.utils.flop_counter`` and
times the step; divides one by the other and compares the result with the
rate of a large float32 matrix product on the same threads (the practical
peak of these cores, ``harness.machine.matmul_gflops``). Printed per input size: batch, GFLOP per step, ms per
step (median of ``--repeat``), achieved GFLOP/s and its share of the
matrix-product peak; and the same for 50 MC-dropout passes over 5 test
presses as ``predict_proba_samples`` runs them (the recurrent stack once,
the head per pass, dropout on the pooled features).

    LD_PRELOAD=/usr/lib/x86_64-linux-gnu/libtcmalloc_minimal.so.4 python benchmarks/bench_flops.py
    python benchmarks/bench_flops.py --threads 2 --sizes 18x24,60x80,120x160
    python benchmarks/bench_flops.py --smoke      # one small size, one repetition (what CI runs)
"""

import argparse
import os
import time

import _harness  # noqa: F401 - puts the repository root on sys.path
import numpy as np
import torch
from torch.utils.flop_counter import FlopCounterMode

from harness.machine import matmul_gflops
from harness.smoke import add_smoke_argument, parse_args
from sklearn_hardness.models import ConvLSTMClassifier

#: The net ConvLSTMClassifier trains (its public ``module`` parameter's default), reached
#: without importing the private module that defines it; built below as before.
ConvLSTMNet = ConvLSTMClassifier().get_params()["module"]


def median_time(fn, repeat, warmup=2):
    for _ in range(warmup):
        fn()
    times = []
    for _ in range(repeat):
        t = time.perf_counter()
        fn()
        times.append(time.perf_counter() - t)
    return float(np.median(times))


def count_flops(fn):
    with FlopCounterMode(display=False) as counter:
        fn()
    return counter.get_total_flops()


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--threads", type=int, default=1)
    ap.add_argument("--sizes", default="12x16,18x24,60x80,120x160")
    ap.add_argument("--batch", type=int, default=8, help="presses per training batch (the nets' default)")
    ap.add_argument("--frames", type=int, default=4)
    ap.add_argument("--repeat", type=int, default=7)
    ap.add_argument("--matmul", type=int, default=2048)
    add_smoke_argument(ap)
    args = parse_args(ap, argv, sizes="12x16", repeat=1, matmul=128)
    torch.set_num_threads(args.threads)
    torch.manual_seed(0)
    peak = matmul_gflops(args.matmul, args.repeat, threads=None) * 1e9  # on --threads
    print(f"torch {torch.__version__}, {args.threads} thread(s), "
          f"LD_PRELOAD={os.environ.get('LD_PRELOAD', '') or '-'}")
    print(f"float32 matmul {args.matmul}^3: {peak / 1e9:.1f} GFLOP/s (the reference peak)")
    print(f"{'input':<10}{'what':<24}{'batch':>6}{'GFLOP':>9}{'ms':>9}{'GFLOP/s':>9}{'of peak':>9}")
    for size in args.sizes.split(","):
        h, w = (int(s) for s in size.split("x"))
        net = ConvLSTMNet(1, 5, dropout=0.2, input_shape=(args.frames, h, w, 1))
        opt = torch.optim.Adam(net.parameters(), lr=3e-3)
        x = torch.randn(args.batch, args.frames, h, w, 1)
        y = torch.randint(0, 5, (args.batch,))

        def step():
            opt.zero_grad()
            loss = torch.nn.functional.cross_entropy(net(x), y)
            loss.backward()

        def train_step():
            step()
            opt.step()

        net.train()
        flops = count_flops(step)
        t = median_time(train_step, args.repeat)
        print(f"{size:<10}{'training step':<24}{args.batch:>6}{flops / 1e9:>9.3f}{1e3 * t:>9.1f}"
              f"{flops / t / 1e9:>9.1f}{flops / t / peak:>9.1%}")
        x5 = torch.randn(5, args.frames, h, w, 1)  # 5 test presses, 50 passes as the library runs them
        net.eval()
        for m in net.dropouts:
            m.train()

        def mc():
            with torch.inference_mode():
                net(x5, n_replicas=50)

        flops = count_flops(mc)
        t = median_time(mc, args.repeat)
        print(f"{size:<10}{'50 MC passes, 5 presses':<24}{5:>6}{flops / 1e9:>9.3f}{1e3 * t:>9.1f}"
              f"{flops / t / 1e9:>9.1f}{flops / t / peak:>9.1%}")


if __name__ == "__main__":
    main()
