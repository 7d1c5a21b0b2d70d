"""Benchmark: fit a named pipeline on a development-sized set of presses and predict one press.

The issue's targets for the pipeline chosen for real presses of new objects
(``contact_geometry``): fit the 270 development presses in <= 2 min and predict a
press in <= 0.2 s on 2 cores. The presses are the simulator's ``everyday`` preset
at the real recordings' size (GelSight Mini, 240x320, mostly 126 frames, passed
through the mp4v codec) by default; ``--data`` reads the real development presses
instead (a local copy of the public PhysiCLeAR set, development objects alone).
Real videos are decoded inside the timed calls, as a user's fit on the files decodes
them (``--in-memory`` decodes them before the clock starts: about 29 MB a press);
simulated ones are rendered before the clock starts (rendering is not the pipeline's
cost) and held in memory.

Printed side by side: fit seconds, predict seconds per press (the mean over
``--n-predict`` single-press calls), peak resident memory, and the balanced
accuracy on presses of objects the fit did not see (a group-disjoint 80/20 split),
so speed is never read without the error it buys.

    python benchmarks/bench_fit_predict.py [--pipeline contact_geometry] [--n-presses 270]   # ~8 GB in memory
    python benchmarks/bench_fit_predict.py --data DATA      # the real development presses
    python benchmarks/bench_fit_predict.py --smoke [--data DATA]   # a few tiny presses (what CI runs)
"""

import argparse
import os
import sys
import time
import warnings

import _harness  # noqa: F401 - puts the repository root on sys.path
import numpy as np
from sklearn.metrics import balanced_accuracy_score
from sklearn.model_selection import GroupShuffleSplit

from harness.memory import peak_rss_mb
from harness.smoke import add_smoke_argument, parse_args, tiny_presses
from sklearn_hardness.datasets import load_physiclear, make_presses
from sklearn_hardness.models import make_named_pipeline

DEVELOPMENT_OBJECTS = os.path.join(os.path.dirname(os.path.dirname(os.path.abspath(__file__))),
                                   "studies", "real_development_objects.txt")


def load(args):
    """Videos, labels and object ids: the real development presses or simulated ones of their size."""
    if args.data:
        data = load_physiclear(args.data, objects=DEVELOPMENT_OBJECTS)
        n = min(args.n_presses, len(data.target))
        videos = [data.videos[i] for i in range(n)] if args.in_memory else data.videos[np.arange(n)]
        return videos, data.target[:n], data.object_id[:n]
    tiny = tiny_presses("everyday", args.smoke)  # --smoke: a few small presses
    n_objects = tiny.get("n_objects", 42)  # the everyday preset's objects
    data = make_presses("everyday", **dict(tiny, n_per_class=max(1, -(-args.n_presses // n_objects))),
                        random_state=0)
    n = min(args.n_presses, len(data.target))
    videos = [data.videos[i] for i in range(n)]
    return videos, data.target[:n], data.object_id[:n]


def _take(videos, index):
    """The videos at ``index``: a lazy sequence stays lazy."""
    return [videos[i] for i in index] if isinstance(videos, list) else videos[np.asarray(index)]


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--pipeline", default="contact_geometry", help="a name of make_named_pipeline")
    ap.add_argument("--n-presses", type=int, default=270)
    ap.add_argument("--n-predict", type=int, default=10, help="single-press predictions to time")
    ap.add_argument("--data", help="a local copy of the public PhysiCLeAR set (development objects alone)")
    ap.add_argument("--in-memory", action="store_true", help="with --data: decode the videos before the clock")
    add_smoke_argument(ap)
    args = parse_args(ap, argv, n_presses=20, n_predict=1)

    t0 = time.perf_counter()
    videos, y, groups = load(args)
    load_s = time.perf_counter() - t0
    train, test = next(GroupShuffleSplit(1, test_size=0.2, random_state=0).split(np.zeros(len(y)), y, groups))

    with warnings.catch_warnings():
        warnings.simplefilter("ignore")  # contact-not-found warnings: counted by `sklearn-hardness select`
        pipe = make_named_pipeline(args.pipeline, random_state=0)
        t0 = time.perf_counter()
        pipe.fit(videos, y)
        fit_s = time.perf_counter() - t0
        t0 = time.perf_counter()
        for i in test[:args.n_predict]:
            pipe.predict(_take(videos, [i]))
        predict_s = (time.perf_counter() - t0) / min(args.n_predict, len(test))
        held_out = make_named_pipeline(args.pipeline, random_state=0).fit(_take(videos, train), y[train])
        bal = balanced_accuracy_score(y[test], held_out.predict(_take(videos, test)))

    source = "real development presses" if args.data else "simulated everyday presses, 240x320"
    print(f"{args.pipeline} on {len(y)} {source} (loading {load_s:.0f} s, not timed below)")
    print(f"{'fit s':>8}{'predict s/press':>17}{'peak MB':>9}  balanced accuracy (unseen objects)")
    print(f"{fit_s:>8.1f}{predict_s:>17.3f}{peak_rss_mb():>9.0f}  {bal:.3f}")
    print(f"result: fit {fit_s:.0f} s, predict {predict_s:.3f} s/press, balanced accuracy {bal:.2f}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
