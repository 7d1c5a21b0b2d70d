"""What training the initial model once per (test object, seed) saves.

Runs the paired strategies of one (test object, seed) either as the
experiment does now (``shared``: one initial training, deep-copied into every
strategy) or as before (``separate``: every strategy trains its own initial
model), with the same records either way (``tests/test_experiments_paired.py``).
Time the two modes as whole processes side by side, e.g. with
``/usr/bin/time -v python benchmarks/bench_paired_sharing.py shared``.

Usage::

    python benchmarks/bench_paired_sharing.py {shared,separate} [--quick] [--test-class 0] [--seed 0]
"""

import argparse
import time

import torch

from sklearn_hardness.experiments import STRATEGIES, run_active_sampling
from sklearn_hardness.experiments._run import _active_run
from sklearn_hardness.experiments._config import check_config, get_config, resolve_convergence_threshold
from sklearn_hardness.experiments._data import prepare_inputs


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("mode", choices=["shared", "separate"])
    ap.add_argument("--quick", action="store_true", help="the reproduce --quick settings")
    ap.add_argument("--test-class", type=int, default=0)
    ap.add_argument("--seed", type=int, default=0)
    ap.add_argument("--threads", type=int, default=1)
    args = ap.parse_args()
    torch.set_num_threads(args.threads)
    cfg = check_config(get_config("silicone5", quick=args.quick))
    inputs = prepare_inputs("silicone5", cfg, cfg["model"], verbose=0)  # disk-cached
    resolve_convergence_threshold(cfg, inputs.n_classes)
    t = time.perf_counter()
    if args.mode == "shared":
        res = run_active_sampling("silicone5", strategies=STRATEGIES, test_classes=[args.test_class],
                                  seeds=[args.seed], quick=args.quick, n_jobs=1, verbose=0)
        acc = [r["accuracy"][-1] for r in res.records]
    else:
        acc = [_active_run(inputs.X, inputs.y, inputs.hardness, cfg, cfg["model"], inputs.n_classes,
                           list(inputs.target_names), s, args.test_class, args.seed, None)["accuracy"][-1]
               for s in STRATEGIES]
    print(f"{args.mode}: {len(STRATEGIES)} strategies in {time.perf_counter() - t:.1f} s; final accuracy {acc}")


if __name__ == "__main__":
    main()
