"""Benchmark of the active-sampling experiment: time, memory and accuracy side by side.

One run (default)
    One ConvLSTM active-sampling run with the paper's robot-data
    hyperparameters on the simulated ``silicone5`` set (s0 = s = 5, N = 5,
    e0 = 100, e = 50, M = 40, dropout 0.2, 50 MC passes) at the library's
    defaults (12x16 grey frames, ``early_stopping=5``; ``--paper``: 18x24
    frames and every epoch, the settings of the measurements below):
    wall time, CPU time and peak memory of the run, after the frames of all
    455 presses are prepared (timed separately)::

        python benchmarks/bench_active_sampling.py [--paper]

Paired seeds
    Variance, entropy, BALD and random on the same (test object, seed) pairs
    (same test presses, initial presses, initial weights): final accuracy with
    95% t-intervals and the paired differences to random::

        python benchmarks/bench_active_sampling.py --paired-seeds 30 --model convlstm --quick --n-jobs 2
        python benchmarks/bench_active_sampling.py --paired-seeds 30 --model ofnn --n-jobs 2

    Pairs cycle through the test objects (30 pairs = 5 objects x 6 seeds).
    Results go to a resumable JSON Lines file (``--results``).

``--smoke`` runs either on a tiny simulated copy of ``silicone5`` with tiny
settings, caching and writing nothing (what CI runs).

Measured (shared 2-core VM, load 5-8, so wall times are inflated; CPU times are the guide)
    One ConvLSTM run, paper settings, 1 torch thread: 71 s CPU (159 s wall
    under load), peak RSS 564 MiB; preparing the 455 presses: 140 s wall
    (once; cached on disk with ``memory=``). Converged (loss 0.98).

    30 pairs, ConvLSTM with the ``--quick`` settings (a full-setting ConvLSTM
    at 120 runs x 71 s CPU did not fit): 22/30 converged (73%; paper 81%).
    Final accuracy [95% CI]: no resampling 56.4% [40.3, 72.5], variance 63.6%
    [46.0, 81.3], entropy 79.1% [67.3, 90.9], BALD 60.9% [44.4, 77.4], random
    62.7% [44.7, 80.7]; paired differences to random: entropy +16.4%
    [+0.7, +32.0] (p = 0.04), variance +0.9% [-17.1, +19.0], BALD -1.8%
    [-17.0, +13.4].

    30 pairs, OFNN (paper settings): it does not learn from 5 presses per
    object on the simulator (no resampling 14.0%, random 22.7%, variance
    20.7%, entropy 19.3%, BALD 16.7%; no strategy differs from random), as
    in the paper, where OFNN is the weakest model (27%). (Measured before
    OFNN got raw frames instead of differences; see experiments._models.PAPER_CHOICES.)

    10 pairs, ConvLSTM with the paper's settings, idle 2-core machine,
    ``--n-jobs 2``: 1212 s wall; 6 of 10 pairs converged in every strategy.
    Final accuracy [95% t-interval, n = 6]: no resampling 63.3% [27.2, 99.5],
    variance 60.0% [12.1, 107.9], entropy 96.7% [88.1, 105.2], BALD 70.0%
    [26.5, 113.5], random 83.3% [55.4, 111.2]; no paired difference to
    random is significant at this n (p = 0.20, 0.24, 0.56).
"""

import argparse
import math
import os
import time

import _harness  # noqa: F401 - puts the repository root on sys.path
import numpy as np

from harness.memory import peak_rss_mb
from harness.smoke import TINY_ACTIVE, add_smoke_argument, parse_args, tiny_presses


def _overrides(args):
    out = {"frame_size": (18, 24), "early_stopping": None} if args.paper else {}
    if args.frame_size is not None:
        out["frame_size"] = tuple(args.frame_size)
    return dict(TINY_ACTIVE, **out) if args.smoke else out


def _dataset(args):
    """``"silicone5"``, or with ``--smoke`` a tiny simulated copy of it."""
    if not args.smoke:
        return "silicone5"
    from sklearn_hardness.datasets import make_presses

    return make_presses("silicone5", random_state=0, **tiny_presses("silicone5"))


def prepare(dataset, memory, model=None, quick=False, **overrides):
    """Cache the dataset's prepared inputs in ``memory`` (a one-iteration run of one epoch)."""
    from sklearn_hardness.experiments import run_active_sampling

    short = dict(overrides, initial_epochs=1, epochs_per_query=1, n_iterations=1)
    kwargs = {} if model is None else {"model": model}
    run_active_sampling(dataset, strategies=("random",), test_classes=[0], seeds=[0], quick=quick,
                        n_jobs=1, memory=memory, verbose=0, **kwargs, **short)


def one_run(args):
    import torch

    from sklearn_hardness.experiments import run_active_sampling

    torch.set_num_threads(args.threads)
    overrides = _overrides(args)
    dataset = _dataset(args)
    t = time.perf_counter()
    prepare(dataset, args.cache, model=args.model, quick=args.quick, **overrides)
    prep = time.perf_counter() - t
    rss_prep = peak_rss_mb()
    t, c = time.perf_counter(), time.process_time()
    res = run_active_sampling(dataset, model=args.model, strategies=(args.strategy,), test_classes=[0],
                              seeds=[args.seed], quick=args.quick, n_jobs=1, memory=args.cache, verbose=0,
                              **overrides)
    wall, cpu = time.perf_counter() - t, time.process_time() - c
    r = res.records[0]
    cfg = res.config
    print(f"one {args.model} active-sampling run, silicone5, strategy={args.strategy}, test object 0, "
          f"seed {args.seed}, torch threads={args.threads}")
    print(f"  e0={cfg['initial_epochs']} e={cfg['epochs_per_query']} M={cfg['max_reservoir']} "
          f"s0=s={cfg['n_initial']} N={cfg['n_iterations']} MC={cfg['n_samples']} "
          f"frames={cfg['frame_size'] or 'model default'} lr={cfg['lr']}")
    print(f"{'stage':<28}{'wall s':>9}{'cpu s':>9}{'peak RSS MiB':>14}  result")
    print(f"{'prepare 455 presses (+1 epoch)':<28}{prep:>9.1f}{'':>9}{rss_prep:>14.0f}")
    print(f"{'active-sampling run':<28}{wall:>9.1f}{cpu:>9.1f}{peak_rss_mb():>14.0f}  "
          f"converged={r['converged']} (loss {r['initial_train_loss']:.3f}), accuracy per iteration "
          f"{[round(a, 2) for a in r['accuracy']]}, queried {r['queried']}")
    if r["converged"]:
        print(f"result: test accuracy {r['accuracy'][-1]:.2f} after {len(r['accuracy']) - 1} queries")
    else:
        print(f"result: initial training did not converge (loss {r['initial_train_loss']:.2f}); no queries")


def paired(args):
    from scipy import stats

    from sklearn_hardness.experiments import run_active_sampling

    strategies = ("variance", "entropy", "bald", "random")
    n_seeds = math.ceil(args.paired_seeds / 5)
    overrides = _overrides(args)
    t = time.perf_counter()
    tiny = {"test_classes": [0]} if args.smoke else {}  # one of the five test objects
    res = run_active_sampling(_dataset(args), model=args.model, strategies=strategies, seeds=range(n_seeds),
                              quick=args.quick, n_jobs=args.n_jobs, results_path=args.results,
                              memory=args.cache, verbose=1, **tiny, **overrides)
    wall = time.perf_counter() - t
    # pairs (test object, seed), first args.paired_seeds of them in seed-major order
    pairs = sorted({(r["key"]["seed"], r["key"]["test_class"]) for r in res.records})[: args.paired_seeds]
    final = {s: {} for s in strategies}
    first = {}
    for r in res.records:
        p = (r["key"]["seed"], r["key"]["test_class"])
        if p in pairs and r["converged"]:
            final[r["key"]["strategy"]][p] = r["accuracy"][-1]
            first[p] = r["accuracy"][0]
    common = sorted(set.intersection(*(set(v) for v in final.values())))
    cfg = res.config
    print(f"\nsilicone5, {cfg['model']}, {len(pairs)} paired (test object, seed) runs, "
          f"{len(common)} converged in all strategies; e0={cfg['initial_epochs']} e={cfg['epochs_per_query']} "
          f"M={cfg['max_reservoir']} frames={cfg['frame_size'] or 'default'} lr={cfg['lr']} "
          f"MC={cfg['n_samples']}{' [quick]' if args.quick else ''}; wall {wall:.0f} s, "
          f"peak RSS {peak_rss_mb():.0f} MiB (parent)")

    def ci(v):
        v = np.asarray(v, float)
        m = v.mean()
        if len(v) < 2 or v.std() == 0:
            return m, m, m
        lo, hi = stats.t.interval(0.95, len(v) - 1, loc=m, scale=stats.sem(v))
        return m, lo, hi

    print(f"{'':<16}{'final accuracy':>16}{'95% CI':>20}{'diff vs random':>16}{'95% CI':>20}{'p (paired t)':>14}")
    base = [first[p] for p in common]
    m, lo, hi = ci(base)
    print(f"{'no resampling':<16}{100 * m:>15.1f}%{f'[{100 * lo:.1f}, {100 * hi:.1f}]':>20}")
    rnd = np.array([final["random"][p] for p in common])
    for s in strategies:
        v = np.array([final[s][p] for p in common])
        m, lo, hi = ci(v)
        line = f"{s:<16}{100 * m:>15.1f}%{f'[{100 * lo:.1f}, {100 * hi:.1f}]':>20}"
        if s != "random":
            d = v - rnd
            dm, dlo, dhi = ci(d)
            p = stats.ttest_rel(v, rnd).pvalue if np.any(d != 0) else 1.0
            line += f"{100 * dm:>+15.1f}%{f'[{100 * dlo:+.1f}, {100 * dhi:+.1f}]':>20}{p:>14.3f}"
        print(line)


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--model", default="convlstm", choices=["convlstm", "ofnn"])
    ap.add_argument("--quick", action="store_true", help="the reproduce --quick settings")
    ap.add_argument("--frame-size", type=int, nargs=2, default=None)
    ap.add_argument("--paper", action="store_true",
                    help="18x24 frames and every epoch (early_stopping=None), the defaults before 12x16")
    ap.add_argument("--strategy", default="variance")
    ap.add_argument("--seed", type=int, default=0)
    ap.add_argument("--threads", type=int, default=2, help="torch threads of the single run")
    ap.add_argument("--paired-seeds", type=int, default=0, help="number of paired (test object, seed) runs")
    ap.add_argument("--n-jobs", type=int, default=2)
    ap.add_argument("--results", default="bench_active_sampling.jsonl")
    ap.add_argument("--cache", default=os.path.join(".cache", "bench_active_sampling"))
    add_smoke_argument(ap)
    args = parse_args(ap, argv, quick=True, threads=1, n_jobs=1, results=None, cache=False)
    if args.paired_seeds:
        paired(args)
    else:
        one_run(args)


if __name__ == "__main__":
    main()
