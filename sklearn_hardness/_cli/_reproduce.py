"""``sklearn-hardness reproduce``: the paper's active-sampling experiment and its tables."""

from __future__ import annotations

import argparse
import json
import os
import sys
import textwrap

from ..experiments import EXPERIMENT_MODELS
from ..models import pipeline_info
from ._common import (
    _SIM_PRESETS,
    _add_quiet,
    _check_out_dir,
    _n_jobs,
    _n_jobs_help,
    _nonnegative_int,
    _parse_set,
    _positive_int,
    _reproduce_command,
    _UsageError,
    _user_errors,
)


def _quick_help():
    from ..experiments import QUICK_OVERRIDES  # no torch: --help stays fast

    return ("a first look in a few minutes on 2 cores; changes: "
            + ", ".join(f"{k}={v}" for k, v in QUICK_OVERRIDES.items())
            + " (smaller simulated images and frames, fewer epochs, MC passes and runs)")


def _strategies_help():
    from ..experiments import STRATEGIES

    return f"strategies to compare (default: {' '.join(STRATEGIES)})"


def _config_keys_epilog():
    """The ``--set`` keys with their meaning, from the table that also writes get_config's docstring."""
    from ..experiments import CONFIG_KEYS

    width = max(map(len, CONFIG_KEYS))
    return "configuration keys for --set (sklearn_hardness.experiments.get_config):\n" + "\n".join(
        f"  {key:<{width}}  {meaning}" for key, meaning in CONFIG_KEYS.items())


def _add_reproduce(sub):
    p = sub.add_parser(
        "reproduce",
        help="run the paper's active-sampling experiment and print its comparison table",
        description=textwrap.fill(
            "Run the active-sampling experiment of the paper (Algorithm 1, Sec. III) on the "
            "built-in simulator (or on your recordings with --dataset), print the comparison table "
            "(no resampling, variance, entropy, random, BALD, and the paper's human accuracy) and write "
            "figures and the results file to --out. Every finished run is appended to "
            "OUT/results.jsonl: rerun the same command to resume after an interruption (SIGINT or "
            "SIGTERM stops the workers and keeps every finished run).", 78),
        epilog=_config_keys_epilog,
        formatter_class=argparse.RawDescriptionHelpFormatter,
    )
    p.add_argument("--preset", default="silicone5", choices=["silicone5", "shore9"],
                   help="the paper's setup: silicone5 (robot data, ConvLSTM, e0=100, e=50, M=40) or "
                   "shore9 (Yuan's data, DINOv2NN, e0=50, e=25, M=80). Default silicone5.")
    p.add_argument("--dataset", default=None,
                   help="manifest CSV of real recordings (see load_press_videos; with an object_id "
                   "column and several objects per class the runs are object-disjoint) or 'everyday' "
                   "(simulated everyday objects); default: the simulator with the preset's objects")
    p.add_argument("--model", default=None, choices=EXPERIMENT_MODELS,
                   help="classifier (default: the preset's)")
    p.add_argument("--dinov2-model", default=None,
                   help="DINOv2 weights for dinov2nn: a Hugging Face id in the local cache or a local "
                   "directory (default facebook/dinov2-small)")
    p.add_argument("--out", default="hardness_results", help="output folder (default ./hardness_results)")
    p.add_argument("--quick", action="store_true", help=_quick_help)
    p.add_argument("--n-runs", type=_positive_int, default=None,
                   help="seeds per test object (default: the preset's)")
    p.add_argument("--seeds", type=_nonnegative_int, nargs="+", default=None, metavar="SEED",
                   help="explicit seeds per test object instead of 0..n_runs-1, e.g. --seeds $(seq 100 159) "
                   "for runs on splits never run before")
    p.add_argument("--test-objects", nargs="+", default=None, metavar="OBJECT_ID",
                   help="object-disjoint datasets (everyday, a manifest with object_id): the objects that "
                   "serve as test object (default: every object of a class with two or more)")
    p.add_argument("--n-jobs", type=_n_jobs, default=None, help=_n_jobs_help(1))
    p.add_argument("--strategies", nargs="+", default=None, help=_strategies_help)
    p.add_argument("--epochs", type=_positive_int, nargs=2, default=None, metavar=("E0", "E"),
                   help="initial epochs and epochs per iteration (override)")
    p.add_argument("--set", nargs="+", default=[], metavar="KEY=VALUE",
                   help="override any configuration key, e.g. --set n_iterations=3 max_reservoir=60 "
                   "frame_size=(24,32); the keys are listed below")
    p.add_argument("--protocol", default="active", choices=["active", "paper"],
                   help="active (default): the active-sampling experiment of --preset. paper: the whole "
                   "protocol, resumable into --out: model baselines, the dropout sweep and active sampling "
                   "with every strategy at the paper's settings with the ConvLSTM, on silicone5 (10 seeds x "
                   "5 objects) and shore9 (5 seeds x 9 objects; DINOv2NN baseline too with --dinov2-model), "
                   "with 95%% paired "
                   "intervals and p-values against random and accuracy on held-out presses of every "
                   "object; writes OUT/summary.txt")
    _add_quiet(p, "progress (by default a line per finished run with elapsed time and an estimate of "
               "the rest goes to stderr)")
    return p


def _run_paper_protocol(args, config):
    import time

    from ..experiments import run_paper_protocol

    t0 = time.time()
    text = run_paper_protocol(args.out, strategies=args.strategies, n_runs=args.n_runs, quick=args.quick,
                              n_jobs=args.n_jobs, verbose=0 if args.quiet else 1,
                              dinov2_model=args.dinov2_model, **config)
    print(text)
    print(f"wrote results.jsonl and summary.txt to {args.out} ({time.time() - t0:.0f} s)")
    return 0


def _reproduce_config(args):
    """The configuration overrides of ``reproduce``, every input checked before anything is written."""
    from ..active import check_strategies
    from ..datasets import load_press_videos
    from ..experiments import STRATEGIES, check_config, get_config, load_dataset

    if args.protocol == "paper" and (args.dataset or args.model):
        raise _UsageError("--protocol paper runs the simulator presets with their models; it takes no "
                          "--dataset or --model (use --protocol active for those)")
    if args.protocol == "paper" and args.test_objects:
        raise _UsageError("--protocol paper runs the simulator presets; it takes no --test-objects")
    if args.protocol == "paper" and args.seeds:
        raise _UsageError("--protocol paper runs seeds 0..n_runs-1; it takes no --seeds (use --protocol active)")
    if args.strategies is None:
        args.strategies = list(STRATEGIES)
    config = _parse_set(args.set)
    if args.epochs:
        config["initial_epochs"], config["epochs_per_query"] = args.epochs
    _check_out_dir(args.out)
    presets = ["silicone5", "shore9"] if args.protocol == "paper" else [args.preset]
    with _user_errors():
        check_strategies(args.strategies)
        for preset in presets:
            overrides = dict(config, model=args.model) if args.model else config
            check_config(get_config(preset, quick=args.quick, **overrides))
        if args.dataset and args.dataset not in _SIM_PRESETS:
            load_press_videos(args.dataset)  # reads the manifest and checks its files, no video
        if args.test_objects:
            # object ids only: the videos of a preset or manifest are loaded lazily
            cfg = get_config(args.preset, quick=args.quick, **config)
            ids = load_dataset(args.dataset or args.preset, cfg).get("object_id")
            unknown = sorted(set(args.test_objects) - set(map(str, [] if ids is None else ids)))
            if unknown:
                raise _UsageError(f"--test-objects {unknown} are not object ids of the dataset")
    if args.dinov2_model and args.protocol != "paper":
        config["dinov2_model"] = args.dinov2_model
    return config


def _run_reproduce(args):
    import time

    from ..experiments import run_active_sampling
    from ..utils._unreadable import UnreadableVideosError
    from ._header import output_header

    config = _reproduce_config(args)
    if args.protocol == "paper":
        return _run_paper_protocol(args, config)
    os.makedirs(args.out, exist_ok=True)
    results_path = os.path.join(args.out, "results.jsonl")
    t0 = time.time()
    try:  # the first pass over the videos finds those that cannot be read, before any run
        result = run_active_sampling(
            args.dataset if args.dataset else args.preset,
            preset=args.preset,
            model=args.model,
            strategies=args.strategies,
            n_runs=args.n_runs,
            seeds=args.seeds,
            test_objects=args.test_objects,
            quick=args.quick,
            n_jobs=args.n_jobs,
            results_path=results_path,
            memory=os.path.join(args.out, "cache"),
            verbose=0 if args.quiet else 1,
            **config,
        )
    except UnreadableVideosError as exc:
        raise _UsageError(str(exc)) from exc
    cfg = result.config
    rows = result.comparison_table()
    n_it = cfg["n_iterations"]
    table = result.format_table(rows, mae_unit=cfg.get("hardness_unit"))
    if cfg["model"] in EXPERIMENT_MODELS and not pipeline_info(cfg["model"]).random:  # a logistic regression
        # refitted per iteration
        training = (f"M={cfg['max_reservoir']}, refitted per iteration, n_test={cfg['n_test']}, "
                    f"Laplace posterior samples={cfg['n_samples']}")
    else:
        training = (
            f"e0={cfg['initial_epochs']}, e={cfg['epochs_per_query']}, M={cfg['max_reservoir']}, "
            f"dropout={cfg['dropout']}, n_test={cfg['n_test']}, MC passes={cfg['n_samples']}"
            + (f", frames={cfg['frame_size'][0]}x{cfg['frame_size'][1]}" if cfg.get("frame_size") else "")
            + (f", early stopping={cfg['early_stopping']}" if cfg.get("early_stopping") else ", every epoch"))
    header = (
        f"{cfg['dataset']} ({cfg['preset']} settings, {cfg['protocol']} protocol): {cfg['model']}, "
        f"s0={cfg['n_initial']}, s={cfg['n_per_query']}, N={n_it}, " + training
        + (" [quick]" if args.quick else "")
    )
    note = (
        f"Accuracy and MAE after {n_it} iterations (no resampling: after the initial training), mean +- "
        "std over converged runs; runs = converged/total. Humans: the paper's study (Sec. III-G), "
        "a constant reference, not measured here."
    )
    print(header)
    print(table)
    print(note)
    command = _reproduce_command(getattr(args, "argv", None) or sys.argv[1:])
    provenance = output_header(command, config_hash=cfg["config_hash"])  # the runs' key in results.jsonl
    with open(os.path.join(args.out, "table.txt"), "w") as f:
        f.write(provenance + "\n" + header + "\n" + table + "\n" + note + "\n")
    if "random" in cfg["strategies"] and len(cfg["strategies"]) > 1:
        # strategies on the same (test object, seed) pairs, against random; what a robot user
        # wants first: presses to reach random's accuracy, then presses and accuracy at the stop
        paired = result.format_presses_to_reach(result.presses_to_reach()) + (
            "\nPresses to reach random's final accuracy: the first press count at which a strategy's mean "
            "test accuracy over the pairs is at least random's mean final accuracy (ExperimentResult."
            "presses_to_reach; 95% bootstrap intervals over the pairs; never: not within the budget)."
        ) + "\n\n" + result.format_paired_table(result.paired_table()) + (
            "\nConverged runs; differences and p-values over the pairs where both runs converged. "
            "presses_at_stop / accuracy_at_stop: reference presses used and test accuracy when the "
            "vote of the test presses is settled (80% of them agree for 2 iterations); "
            "accuracy: on the test object's presses after the budget; holdout_accuracy: on held-out "
            "presses of other objects."
        )
        print(paired)
        with open(os.path.join(args.out, "paired.txt"), "w") as f:
            f.write(provenance + "\n" + header + "\n" + paired + "\n")
    with open(os.path.join(args.out, "config.json"), "w") as f:
        json.dump(dict(cfg), f, indent=2, default=repr)
    paths = result.save_figures(args.out)
    extra = "paired.txt, " if os.path.exists(os.path.join(args.out, "paired.txt")) else ""
    print(f"wrote {results_path}, table.txt, {extra}config.json and {len(paths)} figures to {args.out} "
          f"({time.time() - t0:.0f} s)")
    return 0
