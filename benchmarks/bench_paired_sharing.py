"""What training the initial model once per (test object, seed) saves.

Runs the paired strategies of one (test object, seed) either as the
experiment does (``shared``: one initial training, deep-copied into every
strategy) or one strategy per call (``separate``: every strategy trains its own
initial model), with the same records either way (``tests/test_experiments_paired.py``).
The dataset's inputs are prepared and cached first, untimed.
Time the two modes as whole processes side by side, e.g. with
``/usr/bin/time -v python benchmarks/bench_paired_sharing.py shared``.

Usage::

    python benchmarks/bench_paired_sharing.py {shared,separate} [--quick] [--test-class 0] [--seed 0] [--smoke]
"""

import argparse
import os
import time

import _harness  # noqa: F401 - puts the repository root on sys.path
import torch

from harness.smoke import TINY_ACTIVE, add_smoke_argument, parse_args, tiny_presses
from sklearn_hardness.datasets import make_presses
from sklearn_hardness.experiments import run_active_sampling

#: run_active_sampling's default strategies (the paper's three and BALD).
STRATEGIES = ("variance", "entropy", "random", "bald")


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("mode", choices=["shared", "separate"])
    ap.add_argument("--quick", action="store_true", help="the reproduce --quick settings")
    ap.add_argument("--test-class", type=int, default=0)
    ap.add_argument("--seed", type=int, default=0)
    ap.add_argument("--threads", type=int, default=1)
    add_smoke_argument(ap)
    args = parse_args(ap, argv, quick=True)
    torch.set_num_threads(args.threads)
    # --smoke: a tiny simulated silicone5, tiny settings, no cache
    dataset = make_presses("silicone5", random_state=0, **tiny_presses("silicone5")) if args.smoke else "silicone5"
    cache = False if args.smoke else os.path.join(".cache", "bench_paired_sharing")
    tiny = TINY_ACTIVE if args.smoke else {}
    run = dict(test_classes=[args.test_class], seeds=[args.seed], quick=args.quick, n_jobs=1, memory=cache,
               verbose=0)
    run_active_sampling(dataset, strategies=("random",), **run,
                        **dict(tiny, initial_epochs=1, epochs_per_query=1, n_iterations=1))  # prepare, untimed
    t = time.perf_counter()
    if args.mode == "shared":
        res = run_active_sampling(dataset, strategies=STRATEGIES, **run, **tiny)
        acc = [r["accuracy"][-1] for r in res.records]
    else:
        acc = [run_active_sampling(dataset, strategies=(s,), **run, **tiny).records[0]["accuracy"][-1]
               for s in STRATEGIES]
    print(f"{args.mode}: {len(STRATEGIES)} strategies in {time.perf_counter() - t:.1f} s; final accuracy {acc}")
    print(f"result: mean final accuracy {sum(acc) / len(acc):.2f}")


if __name__ == "__main__":
    main()
