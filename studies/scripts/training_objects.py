"""Study: how many training objects each pipeline needs to tell the hardness of new objects.

Every seed of ``make_presses("everyday")`` draws 42 objects of its own (4
presses each, 168 presses). Each pipeline of ``evaluate`` (by its name:
``peak_change``, ``contact_profile``, ``convlstm_intensity``, ...) is trained on the
presses of the first ``k`` simulated sets of ``--pool-seeds`` pooled, for each
``k`` of ``--sizes`` (42 ``k`` objects), and scored on the presses of every
set of ``--test-seeds``: objects it has never seen, as in ``evaluate``'s
object-disjoint folds, where a fold trains on about 34 objects. The table gives
the balanced accuracy per training size (mean over the test sets, with their
standard deviation) and each pipeline's margin over the one number on the
same test sets (a 95% t-interval over the test sets: it holds the training
set fixed, so it says how sure the margin is for that training set, not over
training sets). ``--net-seeds`` repeats the nets' fits with other seeds
(the table then averages over them; the deterministic pipelines run once).

With ``--data`` (the ``example_data`` folder of ``GelSight-lab/EstimateModulus``,
kept locally, never committed; ``--roi``: its gel region), each fit also
predicts the real GelSight Wedge grasps and the table counts the
within-family pairs ordered right by expected hardness rank, as
``sim_to_real.py`` does for one simulated set.

    python studies/scripts/training_objects.py [--pipelines peak_change contact_profile convlstm_intensity]
        [--test-seeds 0 1 2 3 4] [--pool-seeds 10 11 ... 18] [--sizes 1 2 4 9] [--net-seeds 0]
        [--set NAME=VALUE ...] [--param NAME=VALUE ...] [--data EXAMPLE_DATA [--roi]]
        [--cache DIR] [--n-jobs 2] [--out FILE] [--smoke]

The per-press steps of each pipeline (frame selection, features, the peak
change) run once per simulated set, their rows kept in ``--cache`` when
given; only the rest of each pipeline is fitted per training size. ``--set``
sets a parameter of every pipeline that has it (e.g. ``clf__batch_size=32``;
the others are left as they are); ``--param`` overrides an ``everyday``
parameter. Time per fit and peak memory are printed beside the figures.
"""

import argparse
import ast
import os
import sys
import time
import warnings
from pathlib import Path

import _harness  # noqa: F401 - puts the repository root on sys.path
import numpy as np
from _estimate_modulus import GEL_ROI, expected_rank, family_pairs, load_estimate_modulus
from _press_rows import prefix_key, split_per_press, transform_per_press
from joblib import Parallel, delayed, effective_n_jobs
from scipy import stats
from sim_to_real import named_pipeline
from sim_vs_real_stats import parse_param
from sklearn.metrics import balanced_accuracy_score

from harness.memory import peak_rss_mb, reset_peak
from harness.provenance import report
from harness.smoke import add_smoke_argument, parse_args, tiny_presses
from sklearn_hardness.models import pipeline_info


def parse_set(item):
    """``NAME=VALUE`` -> (name, value) as the command line's ``--set`` reads it: a Python literal, else a string."""
    key, sep, value = item.partition("=")
    if not sep or not key:
        raise argparse.ArgumentTypeError(f"--set expects KEY=VALUE, got {item!r}")
    try:
        return key, ast.literal_eval(value)
    except (ValueError, SyntaxError):
        return key, value  # a plain string


def press_rows(prefix, videos, n_jobs, path=None):
    """The rows of every press through ``prefix`` (per-press steps), read from or written to ``path``."""
    if path is not None and path.exists():
        return np.load(path)
    rows = transform_per_press(prefix, videos, n_jobs=n_jobs)
    if path is not None:
        path.parent.mkdir(parents=True, exist_ok=True)
        np.save(path, rows)
    return rows


def simulated_rows(seeds, prefixes, params, n_jobs, cache):
    """Per seed: (target, hardness, {pipeline: rows}, objects); each prefix runs once per set, shared by equal
    prefixes."""
    from sklearn_hardness.datasets import make_presses

    tag = "_".join(f"{k}={v}" for k, v in sorted(params.items())).replace(" ", "")
    out = {}
    for seed in seeds:
        data = make_presses("everyday", random_state=seed, **params)  # lazy: rendered on access
        rows, done = {}, {}
        for name, prefix in prefixes.items():
            key = prefix_key(prefix)
            if key not in done:
                path = None if cache is None else Path(cache) / f"everyday_seed{seed}{tag}_{key}.npy"
                done[key] = press_rows(prefix, data.videos, n_jobs, path)
            rows[name] = done[key]
        out[seed] = (np.asarray(data.target), np.asarray(data.hardness), rows, len(np.unique(data.object_id)))
    return out


def wedge_rows(data, roi, prefixes, n_jobs, cache):
    """{pipeline: (rows, object names)} of the real grasps (full frame for ``roi=None``), cached like the sets.

    With every row in ``cache``, the videos are not read (the folder need not be there).
    """
    view = "gel" if roi is not None else "full"
    folder = None if cache is None else Path(cache)
    paths = {name: None if folder is None else folder / f"wedge_{view}_{prefix_key(prefix)}.npy"
             for name, prefix in prefixes.items()}
    names_path = None if folder is None else folder / f"wedge_{view}_object_names.npy"
    cached = names_path is not None and names_path.exists() and all(p.exists() for p in paths.values())
    grasps = None if cached else load_estimate_modulus(data, roi=roi, stride=2)
    if not cached and names_path is not None:
        names_path.parent.mkdir(parents=True, exist_ok=True)
        np.save(names_path, grasps.object_name)
    names = np.load(names_path) if cached else grasps.object_name
    return {name: (press_rows(prefix, None if cached else grasps.videos, n_jobs, paths[name]), names)
            for name, prefix in prefixes.items()}


def with_settings(est, settings):
    """``est`` with those of ``settings`` (``{name: value}``) that are its parameters set; the others left out."""
    return est.set_params(**{k: v for k, v in settings.items() if k in est.get_params()})


def fit_and_score(name, net_seed, size, train, tests, real, hardness, settings, threads):
    """Fit ``name``'s rest on ``train`` rows; balanced accuracy per test set and Wedge pairs right per view."""
    import torch

    torch.set_num_threads(threads)
    _, rest = split_per_press(named_pipeline(name, net_seed))
    with_settings(rest, settings)
    reset_peak()
    t0 = time.perf_counter()
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", UserWarning)
        rest.fit(*train)
        accs, pairs = scores(rest, tests, real, hardness)
    return name, net_seed, size, accs.tolist(), pairs, time.perf_counter() - t0, peak_rss_mb()


def scores(est, tests, real, hardness):
    """Balanced accuracy per test set, and within-family Wedge pairs ordered right per view."""
    accs = np.array([balanced_accuracy_score(y, est.predict(X)) for X, y in tests])
    pairs = {}
    for view, (X, names) in real.items():
        fams = family_pairs(names, expected_rank(est.predict_proba(X), est.classes_, hardness))
        pairs[view] = sum(right for right, _, _ in fams.values())
    return accs, pairs


def add_run_arguments(ap):
    """``--data``, ``--roi``, ``--cache``, ``--n-jobs`` and ``--out``, as this benchmark and its kin read them."""
    ap.add_argument("--data", default=None, help="EstimateModulus example_data folder (real Wedge grasps)")
    ap.add_argument("--roi", action="store_true", help="also the grasps' gel region (GEL_ROI)")
    ap.add_argument("--cache", default=None, help="folder to keep each simulated set's per-press rows in")
    ap.add_argument("--n-jobs", type=int, default=2)
    ap.add_argument("--out", default=None, help="write the text here, with a provenance line")
    add_smoke_argument(ap)


def margin_cell(diffs):
    """``+0.100 [+0.050, +0.150]``: the mean of ``diffs`` (one per test set) and its 95% t-interval."""
    d = np.asarray(diffs, dtype=float)
    if len(d) < 2:
        return f"{d.mean():+.3f}"
    half = stats.t.ppf(0.975, len(d) - 1) * d.std(ddof=1) / np.sqrt(len(d))
    return f"{d.mean():+.3f} [{d.mean() - half:+.3f}, {d.mean() + half:+.3f}]"


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--pipelines", nargs="+", default=["peak_change", "contact_profile", "convlstm_intensity"])
    ap.add_argument("--test-seeds", type=int, nargs="+", default=[0, 1, 2, 3, 4])
    ap.add_argument("--pool-seeds", type=int, nargs="+", default=list(range(10, 19)))
    ap.add_argument("--sizes", type=int, nargs="+", default=[1, 2, 4, 9],
                    help="training sets: the first k of --pool-seeds pooled, for each k")
    ap.add_argument("--net-seeds", type=int, nargs="+", default=[0])
    ap.add_argument("--set", dest="settings", type=parse_set, action="append", default=[],
                    help="a parameter of every pipeline that has it, NAME=VALUE as the command line's --set "
                         "(e.g. clf__batch_size=32)")
    ap.add_argument("--param", type=parse_param, action="append", default=[],
                    help="override an everyday parameter, NAME=VALUE or NAME=LO,HI")
    add_run_arguments(ap)
    # --smoke: two tiny sets to train on, one to test, the nets one epoch
    args = parse_args(ap, argv, test_seeds=[0], pool_seeds=[10, 11], sizes=[1, 2], n_jobs=1,
                      settings=[("clf__max_epochs", 1)])
    if "peak_change" not in args.pipelines:
        args.pipelines = ["peak_change", *args.pipelines]  # the margins are over it
    if max(args.sizes) > len(args.pool_seeds) or set(args.pool_seeds) & set(args.test_seeds):
        ap.error("--sizes may not exceed the number of --pool-seeds, and no pool seed may be a test seed")
    settings = dict(args.settings)  # the command line's --set: Python literals, else strings
    params = dict(tiny_presses("everyday", args.smoke), **dict(args.param))
    t0 = time.perf_counter()
    prefixes = {name: split_per_press(named_pipeline(name, 0))[0] for name in args.pipelines}
    pool = args.pool_seeds[:max(args.sizes)]
    sim = simulated_rows([*args.test_seeds, *pool], prefixes, params, args.n_jobs, args.cache)
    hardness = sim[pool[0]][1]
    real = {}
    if args.data:
        views = {"full frame": None, **({"gel region": GEL_ROI} if args.roi else {})}
        for view, roi in views.items():
            real[view] = wedge_rows(args.data, roi, prefixes, args.n_jobs, args.cache)
    prepared = time.perf_counter() - t0
    jobs = []
    for name in args.pipelines:
        seeds = args.net_seeds if pipeline_info(name).random else [0]  # nothing random: no seed to vary
        for net_seed in seeds:
            for size in sorted(args.sizes, reverse=True):  # the longest fits first
                train = (np.concatenate([sim[s][2][name] for s in pool[:size]]),
                         np.concatenate([sim[s][0] for s in pool[:size]]))
                tests = [(sim[s][2][name], sim[s][0]) for s in args.test_seeds]
                jobs.append((name, net_seed, size, train, tests,
                             {view: rows[name] for view, rows in real.items()}, hardness, settings))
    n_workers = effective_n_jobs(args.n_jobs)
    threads = max(1, (os.cpu_count() or 1) // n_workers)
    by = {}
    fits = Parallel(n_jobs=args.n_jobs, return_as="generator_unordered")(
        delayed(fit_and_score)(*job, threads) for job in jobs)
    for name, net_seed, size, scores, pairs, seconds, rss in fits:
        # one line per fit as it ends, so that a run stopped early keeps what it measured
        print(f"{name} k={size} seed {net_seed}: balanced accuracy per test set "
              f"{', '.join(f'{v:.3f}' for v in scores)}; Wedge pairs {pairs}; {seconds:.0f} s",
              file=sys.stderr, flush=True)
        by.setdefault((name, size), []).append((scores, pairs, seconds, rss))

    sizes = sorted(args.sizes)
    n_objects = {size: sum(sim[s][3] for s in pool[:size]) for size in sizes}
    test_objects = ", ".join(str(sim[s][3]) for s in args.test_seeds)
    lines = [f"everyday preset{f', overrides {params}' if params else ''}: balanced accuracy on the presses of "
             f"new objects (test sets: seeds {args.test_seeds}, of {test_objects} objects), trained on the first k "
             f"simulated sets of seeds {pool} pooled; nets' seeds {args.net_seeds}"
             f"{f'; settings {settings}' if settings else ''}; chance 0.33", "",
             "| pipeline | " + " | ".join(f"k={k} ({n_objects[k]} objects)" for k in sizes) + " |",
             "|---|" + "---|" * len(sizes)]
    mean_scores = {}
    for name in args.pipelines:
        cells = []
        for k in sizes:
            per_test = np.mean([r[0] for r in by[(name, k)]], axis=0)  # over net seeds
            mean_scores[(name, k)] = per_test
            spread = f" (s.d. {per_test.std(ddof=1):.3f})" if len(per_test) > 1 else ""
            cells.append(f"{per_test.mean():.3f}{spread}")
        lines.append(f"| {name} | " + " | ".join(cells) + " |")
    lines += ["", "Margin over peak_change on the same test sets (mean, 95% t-interval over the test sets)", "",
              "| pipeline | " + " | ".join(f"k={k}" for k in sizes) + " |", "|---|" + "---|" * len(sizes)]
    for name in args.pipelines[1:]:
        cells = [margin_cell(mean_scores[(name, k)] - mean_scores[("peak_change", k)]) for k in sizes]
        lines.append(f"| {name} | " + " | ".join(cells) + " |")
    for view in real:
        lines += ["", f"Real Wedge grasps ({view}): within-family pairs ordered right (of 9), per net seed", "",
                  "| pipeline | " + " | ".join(f"k={k}" for k in sizes) + " |", "|---|" + "---|" * len(sizes)]
        for name in args.pipelines:
            lines.append(f"| {name} | " + " | ".join(
                ", ".join(str(r[1][view]) for r in by[(name, k)]) for k in sizes) + " |")
    lines += ["", "| pipeline | " + " | ".join(f"k={k}: fit + predict s" for k in sizes) + " | peak RSS MB (worker) |",
              "|---|" + "---|" * (len(sizes) + 1)]
    for name in args.pipelines:
        lines.append(f"| {name} | " + " | ".join(f"{np.mean([r[2] for r in by[(name, k)]]):.1f}" for k in sizes)
                     + f" | {max(r[3] for k in sizes for r in by[(name, k)]):.0f} |")
    lines += ["", f"per-press passes {prepared:.0f} s; total {time.perf_counter() - t0:.0f} s on {n_workers} "
              f"worker(s) of {threads} thread(s)"]
    report("\n".join(lines), args.out)


if __name__ == "__main__":
    main()
