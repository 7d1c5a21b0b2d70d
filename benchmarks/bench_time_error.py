"""Benchmark: run time and memory against error for the knobs of an active-sampling run.

Each configuration changes one knob of the paper's ``silicone5`` ConvLSTM
setup (s0 = s = 5, N = 5, e0 = 100, e = 50, M = 40, dropout 0.2, 50 MC
passes, 18x24 grey frames, 2 frames between contact start and peak) and runs
the ``variance`` strategy once per test object and seed in a fresh process
(``--n-jobs`` runs at a time, one torch thread each unless the configuration
says otherwise), after the frames are prepared and cached (not timed). Each
run holds out 5 presses of every reference object (``n_holdout=5``), so the
error is measured on 25 presses of all objects, not only on the test object's
5. Printed side by side, per configuration:

* wall seconds per run (median over runs) and the whole sweep step's wall,
* peak resident memory of the largest process,
* error of the initial model (the model baseline: 1 - held-out accuracy at
  iteration 0) and after the N queries (the protocol), with the hardness MAE,
* the number of runs that passed the paper's convergence rule,

then the configurations on the Pareto front of (seconds per run, protocol
error). ``--out`` writes the table (``.txt``, ``.csv``) and a plot (``.png``).
Configurations ``"2 threads per run"`` and ``"glibc malloc"`` keep every
setting and change how the run is executed::

    python benchmarks/bench_time_error.py                       # every configuration, 1 seed
    python benchmarks/bench_time_error.py --seeds 2 --configs paper "frames 12x16"
    python benchmarks/bench_time_error.py --out time_error

"Skip what a press does not need": ``early stopping 5`` stops each training call
after the initial one once the training loss has not improved for 5 epochs
(``early_stopping=5``; the initial training runs in full, as the convergence
rule is about it);
``crop 0.5`` cuts each press to a window of half its height and width centred on
its contact before resizing (``crop_contact=0.5``)::

    python benchmarks/bench_time_error.py --configs paper "frames 12x16" "early stopping 5" \
        "crop 0.5" "crop 0.5, frames 12x16" "frames 12x16, early stopping 5" \
        --out time_error_skip

``--smoke`` runs the ``paper`` configuration alone on a tiny simulated copy of
``silicone5`` with tiny settings and no cache (what CI runs).
"""

import argparse
import csv
import json
import os
import subprocess
import sys
import time

import _harness  # noqa: F401 - puts the repository root on sys.path
import numpy as np

from harness.memory import peak_rss_mb
from harness.smoke import TINY_ACTIVE, add_smoke_argument, parse_args, tiny_presses

#: The paper's settings, from which every configuration changes one knob: 18x24 frames (the
#: library's default before 12x16) and every epoch trained (the default is early_stopping=5,
#: the row "frames 12x16, early stopping 5").
PAPER = {"frame_size": (18, 24), "early_stopping": None}

#: name -> (configuration overrides of PAPER, torch threads per run, environment changes)
CONFIGS = {
    "paper": ({}, 1, {}),
    "frames 12x16": ({"frame_size": (12, 16)}, 1, {}),
    "frames 36x48": ({"frame_size": (36, 48)}, 1, {}),
    "1 frame between": ({"n_between": 1}, 1, {}),
    "20 MC passes": ({"n_samples": 20}, 1, {}),
    "e=25": ({"epochs_per_query": 25}, 1, {}),
    "e0=50, e=25": ({"initial_epochs": 50, "epochs_per_query": 25}, 1, {}),
    "early stopping 5": ({"early_stopping": 5}, 1, {}),
    "crop 0.5": ({"crop_contact": 0.5}, 1, {}),
    "crop 0.5, frames 12x16": ({"crop_contact": 0.5, "frame_size": (12, 16)}, 1, {}),
    "frames 12x16, early stopping 5": ({"frame_size": (12, 16), "early_stopping": 5}, 1, {}),
    "2 threads per run": ({}, 2, {}),
    "glibc malloc": ({}, 1, {"LD_PRELOAD": None}),
}


def prepare(dataset, memory, model=None, quick=False, **overrides):
    """Cache the dataset's prepared inputs in ``memory`` (a one-iteration run of one epoch)."""
    from sklearn_hardness.experiments import run_active_sampling

    short = dict(overrides, initial_epochs=1, epochs_per_query=1, n_iterations=1)
    kwargs = {} if model is None else {"model": model}
    run_active_sampling(dataset, strategies=("random",), test_classes=[0], seeds=[0], quick=quick,
                        n_jobs=1, memory=memory, verbose=0, **kwargs, **short)


def one_config(name, seeds, n_jobs, cache, smoke=False):
    """Run one configuration in this process; print a JSON line with its figures."""
    import torch
    from joblib.externals.loky import get_reusable_executor

    from sklearn_hardness.datasets import make_presses
    from sklearn_hardness.experiments import run_active_sampling

    overrides, threads, _ = CONFIGS[name]
    overrides = dict(PAPER, **overrides, n_holdout=5)
    dataset = "silicone5"
    if smoke:  # a tiny simulated silicone5 with room for one held-out press per object
        dataset = make_presses("silicone5", random_state=0, **dict(tiny_presses("silicone5"), n_per_class=6))
        overrides.update(TINY_ACTIVE, n_holdout=1)
    torch.set_num_threads(threads)
    n_jobs = max(1, n_jobs // threads)
    prepare(dataset, cache, **overrides)  # cached, not timed
    t = time.perf_counter()
    res = run_active_sampling(dataset, strategies=("variance",), seeds=range(seeds), n_jobs=n_jobs,
                              memory=cache, verbose=0, **overrides)
    wall = time.perf_counter() - t
    if n_jobs > 1:
        get_reusable_executor().shutdown(wait=True)  # reap the workers: their peak RSS is counted
    recs = res.records
    ok = [r for r in recs if r["converged"]] or recs

    def err(field, i):
        return float(1 - np.mean([r[field][i] for r in ok]))

    print(json.dumps({
        "config": name, "runs": len(recs), "converged": sum(r["converged"] for r in recs),
        "s_per_run": float(np.median([r["wall_time"] for r in recs])), "wall": wall,
        "peak_mib": max(peak_rss_mb(), peak_rss_mb(children=True)),
        "baseline_error": err("holdout_accuracy", 0), "protocol_error": err("holdout_accuracy", -1),
        "protocol_error_sd": float(np.std([1 - r["holdout_accuracy"][-1] for r in ok])),
        "test_error": err("accuracy", -1),
        "protocol_mae": float(np.mean([r["holdout_mae"][-1] for r in ok])),
        "threads": threads, "n_jobs": n_jobs,
    }))


def pareto(rows, x="s_per_run", y="protocol_error"):
    """Names of the rows no other row beats on both ``x`` and ``y`` (lower is better)."""
    front = []
    for r in rows:
        dominated = any(
            o[x] <= r[x] and o[y] <= r[y] and (o[x] < r[x] or o[y] < r[y]) for o in rows if o is not r
        )
        if not dominated:
            front.append(r["config"])
    return front


def format_rows(rows, front):
    head = (f"{'configuration':<20}{'s/run':>7}{'wall s':>8}{'peak MiB':>10}{'baseline err':>14}"
            f"{'protocol err':>14}{'+- sd':>7}{'test err':>10}{'MAE':>7}{'conv.':>7}  front")
    lines = [head, "-" * len(head)]
    for r in rows:
        lines.append(
            f"{r['config']:<20}{r['s_per_run']:>7.1f}{r['wall']:>8.0f}{r['peak_mib']:>10.0f}"
            f"{r['baseline_error']:>14.3f}{r['protocol_error']:>14.3f}{r['protocol_error_sd']:>7.3f}"
            f"{r['test_error']:>10.3f}{r['protocol_mae']:>7.3f}{r['converged']:>4}/{r['runs']:<2}"
            f"  {'*' if r['config'] in front else ''}"
        )
    return "\n".join(lines)


def plot(rows, front, path):
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    fig, ax = plt.subplots(figsize=(6.4, 4.2))
    for i, r in enumerate(rows):
        on = r["config"] in front
        ax.errorbar(r["s_per_run"], r["protocol_error"], yerr=r["protocol_error_sd"], fmt="o",
                    color="tab:red" if on else "tab:gray", capsize=2)
        ax.annotate(r["config"], (r["s_per_run"], r["protocol_error"]), textcoords="offset points",
                    xytext=(4, 4 if i % 2 == 0 else -11), fontsize=8)  # alternate: close points
    pts = sorted((r["s_per_run"], r["protocol_error"]) for r in rows if r["config"] in front)
    ax.plot(*zip(*pts), color="tab:red", lw=1, label="Pareto front")
    ax.set_xlabel("wall seconds per active-sampling run (median)")
    ax.set_ylabel("error after N queries (1 - held-out accuracy)")
    ax.set_title("silicone5, ConvLSTM, variance strategy")
    ax.legend()
    fig.tight_layout()
    fig.savefig(path, dpi=110)


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--configs", nargs="+", default=list(CONFIGS), choices=list(CONFIGS))
    ap.add_argument("--seeds", type=int, default=1, help="seeds per test object (5 runs per seed)")
    ap.add_argument("--n-jobs", type=int, default=2)
    ap.add_argument("--cache", default=os.path.join(".cache", "bench_time_error"))
    ap.add_argument("--out", default=None, help="path prefix of the .txt, .csv and .png written")
    ap.add_argument("--one", default=None, help=argparse.SUPPRESS)  # internal: run one configuration
    add_smoke_argument(ap)
    args = parse_args(ap, argv, configs=["paper"], n_jobs=1, cache=False)
    if args.one:
        one_config(args.one, args.seeds, args.n_jobs, args.cache, args.smoke)
        return
    rows = []
    for name in args.configs:
        env = dict(os.environ)
        for k, v in CONFIGS[name][2].items():
            if v is None:
                env.pop(k, None)
            else:
                env[k] = v
        where = ["--smoke"] if args.smoke else ["--cache", args.cache]  # --smoke: no cache
        out = subprocess.run(
            [sys.executable, __file__, "--one", name, "--seeds", str(args.seeds), "--n-jobs", str(args.n_jobs),
             *where],
            env=env, capture_output=True, text=True,
        )
        if out.returncode:
            sys.exit(f"configuration {name!r} failed:\n{out.stderr[-3000:]}")
        rows.append(json.loads(out.stdout.strip().splitlines()[-1]))
        print(f"done: {name} ({rows[-1]['wall']:.0f} s)", file=sys.stderr, flush=True)
    front = pareto(rows)
    allocator = "tcmalloc" if "tcmalloc" in os.environ.get("LD_PRELOAD", "") else "glibc malloc"
    text = (
        f"silicone5, ConvLSTM, variance strategy; {args.seeds} seed(s) x 5 test objects per configuration, "
        f"{args.n_jobs} runs at a time, {allocator} unless named; errors on 5 held-out presses of every "
        f"object (mean over converged runs); * = Pareto front of (s/run, protocol error)\n"
        + format_rows(rows, front)
    )
    print(text)
    if args.out:
        os.makedirs(os.path.dirname(os.path.abspath(args.out)), exist_ok=True)
        with open(args.out + ".txt", "w") as f:
            f.write(text + "\n")
        with open(args.out + ".csv", "w", newline="") as f:
            writer = csv.DictWriter(f, fieldnames=list(rows[0]))
            writer.writeheader()
            writer.writerows(rows)
        plot(rows, front, args.out + ".png")
        print(f"wrote {args.out}.txt, .csv, .png", file=sys.stderr)


if __name__ == "__main__":
    main()
