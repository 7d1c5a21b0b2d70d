"""Benchmark: a user's ``cross_val_score`` of a feature pipeline, with and without ``memory``, beside evaluate.

A new user cross-validates a named pipeline with scikit-learn's own tools;
without a cache every fold reads its presses' videos and extracts their
features again (fit on the training presses, score on the test presses), where
:func:`~sklearn_hardness.model_selection.evaluate_pipelines` runs the per-press
steps once. ``make_named_pipeline(name, memory=...)`` caches each press's row
(keyed by the press's file, not its frames), so the folds share them. The
presses are simulated (the ``everyday`` preset, mp4v like the real recordings)
and written with a manifest as ``sklearn-hardness simulate`` writes them, then
read back lazily by :func:`~sklearn_hardness.datasets.load_press_videos`: a
fold decodes the files it uses, as on real recordings. Writing them is not timed.

A net's pipeline (``ofnn_quantiles``: frames, optical flow, an MLP) is seeded
the same in every case, so the scores agree. ``--param KEY=VALUE`` passes a
builder parameter (``--param with_profile=True``: ``contact_geometry`` as a
FeatureUnion of geometry and profile features). Timed
on the same ``GroupKFold(5)`` folds (grouped by object), each printed with its
peak resident memory and balanced accuracy:

- ``cross_val_score`` of ``make_named_pipeline(name)``;
- the same with ``memory=`` a fresh folder (cold), then again (warm);
- ``evaluate_pipelines([name], ..., cv=GroupKFold(5), baseline=None)``.

    python benchmarks/bench_cross_val.py [--pipeline contact_geometry] [--param with_profile=True]
        [--n-per-class 6] [--image-size 240 320] [--smoke]
"""

import argparse
import ast
import os
import sys
import tempfile
import time
import warnings

import _harness  # noqa: F401 - puts the repository root on sys.path
import numpy as np
from sklearn.model_selection import GroupKFold, cross_val_score

from harness.cli import run_sklearn_hardness
from harness.memory import peak_rss_mb, reset_peak
from harness.smoke import add_smoke_argument, parse_args
from sklearn_hardness.datasets import load_press_videos
from sklearn_hardness.model_selection import evaluate_pipelines
from sklearn_hardness.models import make_named_pipeline


def simulate(folder, n_per_class, image_size, n_jobs=2):
    """Write simulated ``everyday`` presses and their manifest with ``sklearn-hardness simulate``."""
    run_sklearn_hardness(["simulate", "--preset", "everyday", "--out", folder, "--n-per-class", str(n_per_class),
                          "--image-size", *map(str, image_size), "--format", "mp4", "--n-jobs", str(n_jobs),
                          "--quiet"])
    return load_press_videos(os.path.join(folder, "manifest.csv"))


def timed(run):
    """Seconds, peak resident MB and balanced accuracy of ``run()``."""
    reset_peak()
    t0 = time.perf_counter()
    score = run()
    return time.perf_counter() - t0, peak_rss_mb(), score


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--pipeline", default="contact_geometry", help="a name of make_named_pipeline")
    ap.add_argument("--param", action="append", default=[], metavar="KEY=VALUE",
                    help="a parameter of the pipeline's builder (a Python literal), e.g. with_profile=True")
    ap.add_argument("--n-per-class", type=int, default=6, help="presses per object (42 objects)")
    ap.add_argument("--image-size", type=int, nargs=2, default=(240, 320), metavar=("H", "W"))
    add_smoke_argument(ap)
    args = parse_args(ap, argv, n_per_class=1, image_size=(48, 64))
    params = {key: ast.literal_eval(value) for key, value in (item.split("=", 1) for item in args.param)}

    with tempfile.TemporaryDirectory() as tmp:
        t0 = time.perf_counter()
        data = simulate(os.path.join(tmp, "presses"), args.n_per_class, args.image_size, 1 if args.smoke else 2)
        write_s = time.perf_counter() - t0
        X, y, groups, cv = data.videos, data.target, data.object_id, GroupKFold(5)

        def cross_val(memory=None):
            pipe = make_named_pipeline(args.pipeline, memory=memory, random_state=0, **params)  # nets: one seed
            return float(np.mean(cross_val_score(pipe, X, y, groups=groups, cv=cv, scoring="balanced_accuracy")))

        def evaluate():
            pipe = make_named_pipeline(args.pipeline, random_state=0, **params)
            result = evaluate_pipelines({args.pipeline: pipe}, X, y, groups=groups, cv=cv, baseline=None)
            return float(result.summary["balanced_accuracy"][0])

        cache = os.path.join(tmp, "cache")
        with warnings.catch_warnings():
            warnings.simplefilter("ignore")  # weak contacts, classes missing from a test fold
            cases = [("cross_val_score", timed(cross_val)),
                     ("cross_val_score, memory (cold)", timed(lambda: cross_val(cache))),
                     ("cross_val_score, memory (warm)", timed(lambda: cross_val(cache))),
                     ("evaluate_pipelines", timed(evaluate))]

    h, w = args.image_size
    name = args.pipeline + "".join(f" {k}={v!r}" for k, v in params.items())
    print(f"{name}, GroupKFold(5) on {len(y)} simulated everyday presses ({h}x{w}, mp4v, read from "
          f"files; writing them {write_s:.0f} s, not timed)")
    print(f"{'case':<32}{'seconds':>9}{'peak MB':>9}  balanced accuracy")
    for name, (seconds, peak, score) in cases:
        print(f"{name:<32}{seconds:>9.1f}{peak:>9.0f}  {score:.3f}")
    seconds = {name: s for name, (s, _, _) in cases}
    evaluate_s = seconds["evaluate_pipelines"]
    print(f"result: cross_val_score {seconds['cross_val_score'] / evaluate_s:.1f}x evaluate's time, with memory "
          f"{seconds['cross_val_score, memory (cold)'] / evaluate_s:.1f}x cold and "
          f"{seconds['cross_val_score, memory (warm)'] / evaluate_s:.2f}x warm; balanced accuracy "
          f"{cases[0][1][2]:.2f} (evaluate {cases[3][1][2]:.2f})")
    return 0


if __name__ == "__main__":
    sys.exit(main())
