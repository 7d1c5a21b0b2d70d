"""Study: does pretraining the ConvLSTM on hundreds of simulated objects help it learn from a few dozen?

``training_objects.py`` found that the ConvLSTM needs a few hundred
training objects to beat the one number, where a recording holds a few dozen.
The route that leaves open is the usual one of robot learning: pretrain on the
simulator, fine-tune on one's own presses. This benchmark measures it where the
truth is known. The ConvLSTM of ``evaluate`` is trained on the presses of the
simulated ``everyday`` sets of ``--source-seeds`` pooled (42 objects each);
then, for each fine-tuning setting of ``--fine-tune`` (``LR:EPOCHS``), a copy
goes on training (skorch's ``warm_start``) on the 42 objects of one *target*
set (``--target-seed``), and is scored on the target sets of ``--test-seeds``
(objects neither training has seen). Beside it: the same ConvLSTM trained on
the target set only, the pretrained net without fine-tuning, and the
``peak_change`` and ``contact_profile`` pipelines trained on the target set.

The target sets come from each simulator variant of ``--variants``
(``_sim_variants.py``) while the source is always the preset: ``preset`` asks
whether fine-tuning keeps what pretraining learnt when the simulator matches
the lab; another variant (e.g. ``kinds_shared_calibrated``: other forces,
speeds and compliances) asks the question that matters for real presses,
which never match the simulator: does it still help under a shift?

With ``--data`` (the ``example_data`` folder of ``GelSight-lab/EstimateModulus``,
kept locally, never committed; ``--roi``: also its gel region) every model also
orders the real GelSight Wedge grasps (within-family pairs ordered right of 9,
as ``sim_to_real.py``). They carry no labels to fine-tune on, so they say
what the simulated training carries to a real sensor, not what fine-tuning
on real presses would do.

    python studies/scripts/sim_pretraining.py [--source-seeds 11 12 ... 19] [--target-seed 10]
        [--test-seeds 0 1 2 3 4] [--variants preset kinds_shared_calibrated]
        [--fine-tune 3e-4:30 1e-3:30 3e-3:100] [--net-seeds 0 1]
        [--data EXAMPLE_DATA [--roi]] [--cache DIR] [--n-jobs 2] [--out FILE] [--smoke]

The per-press steps run once per simulated set (their rows kept in
``--cache``, shared with ``training_objects.py``). Times and the
workers' peak memory are printed beside the figures.
"""

import argparse
import copy
import os
import sys
import time
import warnings

import _harness  # noqa: F401 - puts the repository root on sys.path
import numpy as np
from _estimate_modulus import GEL_ROI
from _press_rows import split_per_press
from _sim_variants import VARIANTS, variant_params
from joblib import Parallel, delayed, effective_n_jobs
from sim_to_real import named_pipeline
from training_objects import add_run_arguments, margin_cell, scores, simulated_rows, wedge_rows, with_settings

from harness.memory import peak_rss_mb, reset_peak
from harness.provenance import report
from harness.smoke import parse_args, tiny_presses

PIPELINES = ("peak_change", "contact_profile", "convlstm_intensity")


def parse_fine_tune(text):
    """``LR:EPOCHS`` -> (lr, epochs), e.g. ``3e-4:30``."""
    try:
        lr, epochs = text.split(":")
        lr, epochs = float(lr), int(epochs)
    except ValueError:
        raise argparse.ArgumentTypeError(f"--fine-tune takes LR:EPOCHS (e.g. 3e-4:30), got {text!r}") from None
    if lr <= 0 or epochs < 1:
        raise argparse.ArgumentTypeError(f"--fine-tune needs LR > 0 and EPOCHS >= 1, got {text!r}")
    return lr, epochs


def fine_tune_label(setting):
    lr, epochs = setting
    return f"pretrained, fine-tuned (lr {lr:g}, {epochs} epochs)"


def pretrain(net_seed, train, threads, settings=()):
    """The ConvLSTM's rest (after frame selection) fitted on the pooled source presses (``settings``: its own)."""
    import torch

    torch.set_num_threads(threads)
    rest = with_settings(split_per_press(named_pipeline("convlstm_intensity", net_seed))[1], dict(settings))
    reset_peak()
    t0 = time.perf_counter()
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", UserWarning)
        rest.fit(*train)
    return net_seed, rest, time.perf_counter() - t0, peak_rss_mb()


def fit_and_score(variant, model, name, net_seed, start, setting, train, tests, real, hardness, threads, settings=()):
    """Fit ``name``'s rest on ``train`` (from ``start``, a pretrained rest, when given) and score it.

    ``setting``: None trains from scratch (``start`` None; ``settings``: the rest's own) or scores ``start`` as
    it is; ``(lr, epochs)`` continues training a copy of ``start`` with that learning rate and number of epochs.
    """
    import torch

    torch.set_num_threads(threads)
    reset_peak()
    t0 = time.perf_counter()
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", UserWarning)
        if start is None:
            est = with_settings(split_per_press(named_pipeline(name, net_seed))[1], dict(settings))
            est.fit(*train)
        elif setting is None:
            est = start
        else:
            est = copy.deepcopy(start)
            lr, epochs = setting
            est.set_params(clf__warm_start=True, clf__lr=lr, clf__max_epochs=epochs)
            est.fit(*train)
        accs, pairs = scores(est, tests, real, hardness)
    return variant, model, net_seed, accs, pairs, time.perf_counter() - t0, peak_rss_mb()


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--source-seeds", type=int, nargs="+", default=list(range(11, 20)),
                    help="everyday sets (preset) the ConvLSTM is pretrained on, pooled")
    ap.add_argument("--target-seed", type=int, default=10, help="the target set trained or fine-tuned on")
    ap.add_argument("--test-seeds", type=int, nargs="+", default=[0, 1, 2, 3, 4])
    ap.add_argument("--variants", nargs="+", default=["preset", "kinds_shared_calibrated"], choices=sorted(VARIANTS),
                    help="simulator variants the target and test sets are drawn from")
    ap.add_argument("--fine-tune", type=parse_fine_tune, nargs="+", default=[(3e-4, 30), (1e-3, 30), (3e-3, 100)],
                    metavar="LR:EPOCHS", help="fine-tuning settings (the ConvLSTM trains at lr 3e-3 for 100 epochs)")
    ap.add_argument("--net-seeds", type=int, nargs="+", default=[0, 1])
    add_run_arguments(ap)
    # --smoke: one tiny set each to pretrain on, to fine-tune on and to test; the nets one epoch
    args = parse_args(ap, argv, source_seeds=[11], test_seeds=[0], variants=["preset"], fine_tune=[(1e-3, 1)],
                      net_seeds=[0], n_jobs=1)
    sim = tiny_presses("everyday", args.smoke)
    settings = {"clf__max_epochs": 1} if args.smoke else {}
    if {args.target_seed, *args.test_seeds} & set(args.source_seeds) or args.target_seed in args.test_seeds:
        ap.error("the source, target and test seeds must be distinct")
    t0 = time.perf_counter()
    prefixes = {name: split_per_press(named_pipeline(name, 0))[0] for name in PIPELINES}
    source = simulated_rows(args.source_seeds, prefixes, sim, args.n_jobs, args.cache)
    targets = {v: simulated_rows([args.target_seed, *args.test_seeds], prefixes, dict(sim, **variant_params(v)),
                                 args.n_jobs, args.cache) for v in args.variants}
    hardness = source[args.source_seeds[0]][1]
    real = {}
    if args.data:
        views = {"full frame": None, **({"gel region": GEL_ROI} if args.roi else {})}
        real = {view: wedge_rows(args.data, roi, prefixes, args.n_jobs, args.cache) for view, roi in views.items()}
    prepared = time.perf_counter() - t0
    n_workers = effective_n_jobs(args.n_jobs)
    threads = max(1, (os.cpu_count() or 1) // n_workers)

    train = (np.concatenate([source[s][2]["convlstm_intensity"] for s in args.source_seeds]),
             np.concatenate([source[s][0] for s in args.source_seeds]))
    pretrained, pretrain_s, rss = {}, [], []
    for net_seed, rest, seconds, peak in Parallel(n_jobs=args.n_jobs)(
            delayed(pretrain)(s, train, threads, settings) for s in args.net_seeds):
        print(f"pretrained seed {net_seed} on {len(train[1])} presses: {seconds:.0f} s", file=sys.stderr, flush=True)
        pretrained[net_seed] = rest
        pretrain_s.append(seconds)
        rss.append(peak)

    models = ["peak_change", "contact_profile", "convlstm, target set only", "convlstm, pretrained only",
              *map(fine_tune_label, args.fine_tune)]
    jobs = []
    for v in args.variants:
        tgt = targets[v]
        tests = {name: [(tgt[s][2][name], tgt[s][0]) for s in args.test_seeds] for name in PIPELINES}
        on = {name: (tgt[args.target_seed][2][name], tgt[args.target_seed][0]) for name in PIPELINES}
        views = {name: {view: rows[name] for view, rows in real.items()} for name in PIPELINES}
        for name in ("peak_change", "contact_profile"):  # no seed to vary
            jobs.append((v, name, name, 0, None, None, on[name], tests[name], views[name]))
        for s in args.net_seeds:
            c = "convlstm_intensity"
            jobs.append((v, "convlstm, target set only", c, s, None, None, on[c], tests[c], views[c]))
            jobs.append((v, "convlstm, pretrained only", c, s, pretrained[s], None, on[c], tests[c], views[c]))
            for setting in args.fine_tune:
                jobs.append((v, fine_tune_label(setting), c, s, pretrained[s], setting, on[c], tests[c], views[c]))
    by, seconds_by = {}, {}
    for v, model, net_seed, accs, pairs, seconds, peak in Parallel(n_jobs=args.n_jobs, return_as="generator_unordered")(
            delayed(fit_and_score)(*job, hardness, threads, settings) for job in jobs):
        print(f"{v}: {model} seed {net_seed}: balanced accuracy per test set {', '.join(f'{a:.3f}' for a in accs)}; "
              f"Wedge pairs {pairs}; {seconds:.0f} s", file=sys.stderr, flush=True)
        by.setdefault((v, model), []).append((net_seed, accs, pairs))
        seconds_by.setdefault(model, []).append(seconds)
        rss.append(peak)

    n_source = sum(source[s][3] for s in args.source_seeds)
    lines = [f"ConvLSTM (evaluate's: intensity channels, lr 3e-3, 100 epochs) pretrained on {n_source} simulated "
             f"objects (everyday preset, seeds {args.source_seeds} pooled, {len(train[1])} presses), then trained on "
             f"the {targets[args.variants[0]][args.target_seed][3]} objects of the target set (seed "
             f"{args.target_seed}); balanced accuracy on the presses of new objects of the target variant (test sets: "
             f"seeds {args.test_seeds}; mean over them, s.d. in brackets); nets' seeds {args.net_seeds} (mean); "
             "chance 0.33. Margins: per test set, mean over the nets' seeds, 95% t-interval over the test sets."]
    for v in args.variants:
        overrides = variant_params(v)
        what = f" (overrides {overrides})" if overrides else " (the source simulator)"
        lines += ["", f"Target variant {v}{what}", "",
                  "| model | balanced accuracy | - convlstm, target set only | - peak_change | "
                  + " | ".join(f"Wedge pairs ({view})" for view in real) + " |",
                  "|---|---|---|---|" + "---|" * len(real)]
        mean = {m: np.mean([r[1] for r in by[(v, m)]], axis=0) for m in models}
        for m in models:
            acc = mean[m]
            vs_scratch = "" if m in ("peak_change", "contact_profile", "convlstm, target set only") else \
                margin_cell(acc - mean["convlstm, target set only"])
            vs_peak = "" if m == "peak_change" else margin_cell(acc - mean["peak_change"])
            wedge = [", ".join(str(r[2][view]) for r in sorted(by[(v, m)], key=lambda r: r[0])) for view in real]
            cells = [m, f"{acc.mean():.3f} (s.d. {acc.std(ddof=1):.3f})", vs_scratch, vs_peak, *wedge]
            lines.append("| " + " | ".join(cells) + " |")
    lines += ["", "| step | mean s per fit | fits |", "|---|---|---|",
              f"| pretraining ({len(train[1])} presses) | {np.mean(pretrain_s):.0f} | {len(pretrain_s)} |"]
    for m in models:
        lines.append(f"| {m} | {np.mean(seconds_by[m]):.1f} | {len(seconds_by[m])} |")
    lines += ["", f"per-press passes {prepared:.0f} s; peak RSS {max(rss):.0f} MB (worker); total "
              f"{time.perf_counter() - t0:.0f} s on {n_workers} worker(s) of {threads} thread(s)"]
    report("\n".join(lines), args.out)


if __name__ == "__main__":
    main()
