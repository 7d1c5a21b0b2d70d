"""Study: model baselines on simulated silicone5 (issue 4's accuracy target).

Each model is trained on 5 presses per object and tested on all the other
presses (86 per object), over several seeds, with the paper's epochs
(``initial_epochs=100``). Prints accuracy (mean and std over seeds), hardness
MAE, wall time and peak memory side by side, next to the paper's numbers on
its robot data. DINOv2NN needs pretrained weights that cannot be downloaded
here: pass ``--dinov2-model DIR`` with a local copy of facebook/dinov2-small,
otherwise it is left out.

    python studies/scripts/model_baselines.py [--n-runs 10] [--convlstm-sizes 18x24 36x48]
    python studies/scripts/model_baselines.py --smoke   # 2 + 2 presses per object of a tiny set, one epoch
"""

import argparse
import time

import _harness  # noqa: F401 - puts the repository root on sys.path

from harness.memory import peak_rss_mb
from harness.smoke import add_smoke_argument, parse_args, tiny_presses
from sklearn_hardness.experiments import run_model_baselines

PAPER = {"convlstm": "42%", "dinov2nn": "38%", "ofnn": "27%"}


def _size(text):
    h, w = text.lower().split("x")
    return int(h), int(w)


def main(argv=None):
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--n-runs", type=int, default=10)
    parser.add_argument("--n-jobs", type=int, default=2)
    parser.add_argument("--models", nargs="+", default=["ofnn", "convlstm"])
    parser.add_argument("--convlstm-sizes", nargs="+", type=_size, default=[(18, 24)])
    parser.add_argument("--dinov2-model", default=None, help="local DINOv2 directory (adds dinov2nn)")
    add_smoke_argument(parser)
    args = parse_args(parser, argv, n_runs=1, n_jobs=1, convlstm_sizes=[(12, 16)])
    models = list(args.models) + (["dinov2nn"] if args.dinov2_model else [])
    dataset, n_train, n_test, short = "silicone5", 5, 86, {}
    if args.smoke:  # a tiny simulated silicone5: 2 training and 2 test presses per object, one epoch
        from sklearn_hardness.datasets import make_presses

        dataset = make_presses("silicone5", random_state=0, **tiny_presses("silicone5"))
        n_train, n_test, short = 2, 2, {"initial_epochs": 1}

    print(f"silicone5, {n_train} train presses per object, {n_test} test presses per object, {args.n_runs} seeds, "
          f"initial_epochs={short.get('initial_epochs', 100)}, n_jobs={args.n_jobs}")
    print(f"{'model':<22}{'accuracy':>18}{'MAE (mm/N)':>18}{'paper':>8}{'time (s)':>10}{'peak RSS (MB)':>15}")
    runs = [(m, {}) for m in models if m != "convlstm"]
    if "convlstm" in models:
        runs += [("convlstm", {"frame_size": size}) for size in args.convlstm_sizes]
    for name, extra in runs:
        config = dict(extra, **short)
        if name == "dinov2nn":
            config["dinov2_model"] = args.dinov2_model
        t0 = time.perf_counter()
        result = run_model_baselines(
            dataset, models=(name,), n_train_per_class=n_train, n_test_per_class=n_test, n_runs=args.n_runs,
            n_jobs=args.n_jobs, verbose=0, **config,
        )
        dt = time.perf_counter() - t0
        rss = peak_rss_mb()  # over the process's life: the runs so far
        row = result.baseline_table()[0]
        label = name + (f" {extra['frame_size'][0]}x{extra['frame_size'][1]}" if extra else "")
        acc = f"{100 * row['accuracy_mean']:.1f}% +- {100 * row['accuracy_std']:.1f}%"
        mae = f"{row['mae_mean']:.3f} +- {row['mae_std']:.3f}"
        print(f"{label:<22}{acc:>18}{mae:>18}{PAPER[name]:>8}{dt:>10.1f}{rss:>15.0f}", flush=True)


if __name__ == "__main__":
    main()
