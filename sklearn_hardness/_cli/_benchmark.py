"""``sklearn-hardness benchmark``: the time, memory and accuracy of one active-sampling run."""

from __future__ import annotations

from .._registry import EXPERIMENT_MODELS
from ._common import _add_quiet, _parse_set, _positive_int, _user_errors

def _add_benchmark(sub):
    p = sub.add_parser(
        "benchmark",
        help="time one active-sampling run (wall, CPU, peak memory, accuracy)",
        description="Prepare the frames of all presses of a preset, then run one active-sampling run "
        "with the preset's hyperparameters and print its wall time, CPU time, peak memory and accuracy "
        "per iteration. benchmarks/bench_active_sampling.py has more (paired seeds, confidence intervals).",
    )
    p.add_argument("--preset", default="silicone5", choices=["silicone5", "shore9"],
                   help="the paper's setup whose presses and hyperparameters are used (default silicone5)")
    p.add_argument("--model", default=None, choices=EXPERIMENT_MODELS,
                   help="classifier (default: the preset's)")
    p.add_argument("--strategy", default="variance",
                   help="query strategy: variance (default), entropy, random or bald")
    p.add_argument("--quick", action="store_true", help="the reproduce --quick settings")
    p.add_argument("--threads", type=_positive_int, default=None, help="torch threads (default: torch's)")
    p.add_argument("--set", nargs="+", default=[], metavar="KEY=VALUE",
                   help="configuration overrides, as for reproduce (its --help lists the keys)")
    _add_quiet(p, "messages (benchmark prints only its report)")
    return p


def _run_benchmark(args):
    from ..active._strategies import check_strategies
    from ..experiments._benchmark import time_active_sampling_run
    from ..experiments._config import check_config, get_config

    config = _parse_set(args.set)
    with _user_errors():
        check_strategies([args.strategy])
        overrides = dict(config, model=args.model) if args.model else config
        check_config(get_config(args.preset, quick=args.quick, **overrides))
    rep = time_active_sampling_run(args.preset, model=args.model, strategy=args.strategy, quick=args.quick,
                                   n_threads=args.threads, **config)
    cfg, r = rep["config"], rep["record"]
    print(f"{args.preset}: {cfg['model']}, strategy {args.strategy}, e0={cfg['initial_epochs']} "
          f"e={cfg['epochs_per_query']} M={cfg['max_reservoir']} N={cfg['n_iterations']} "
          f"MC={cfg['n_samples']}, torch threads {rep['torch_threads']}" + (" [quick]" if args.quick else ""))
    print(f"prepare all presses  {rep['prepare_s']:8.1f} s")
    print(f"one run              {rep['run_wall_s']:8.1f} s wall, {rep['run_cpu_s']:.1f} s CPU; "
          f"peak RSS {rep['peak_rss_mib']:.0f} MiB")
    print(f"converged {r['converged']} (initial loss {r['initial_train_loss']:.3f}); accuracy per iteration "
          f"{[round(a, 2) for a in r['accuracy']]}; queried {r['queried']}")
    return 0
