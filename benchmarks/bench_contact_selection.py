"""Benchmark: ContactFrameSelector on a silicone5-sized set of videos.

455 videos of 60 frames at 240x320 (the size of the paper's robot set and of
GelSight Mini's stream). Prints wall time, peak memory and, as the error
column, how far the found contact start and peak are from the truth of the
synthetic presses.

    python benchmarks/bench_contact_selection.py [--n-videos 455] [--n-jobs 2]
"""

import argparse
import resource
import sys
import time
from pathlib import Path

import numpy as np

sys.path.insert(0, str(Path(__file__).resolve().parents[1] / "tests"))
from _synthetic import synthetic_press  # noqa: E402

from sklearn_hardness.datasets import LazyVideoSequence  # noqa: E402
from sklearn_hardness.preprocessing import ContactFrameSelector  # noqa: E402


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--n-videos", type=int, default=455)
    parser.add_argument("--n-distinct", type=int, default=40, help="distinct videos, cycled (bounds RAM)")
    parser.add_argument("--n-jobs", type=int, default=2)
    args = parser.parse_args()

    rng = np.random.default_rng(0)
    starts = rng.integers(10, 25, args.n_distinct)
    lengths = rng.integers(3, 15, args.n_distinct)
    distinct = [
        synthetic_press(n_frames=60, size=(240, 320), contact_start=s, peak=s + n, radius=60,
                        drift=0.2, gain_drift=0.001, seed=i)
        for i, (s, n) in enumerate(zip(starts, lengths))
    ]
    keys = [i % args.n_distinct for i in range(args.n_videos)]
    videos = LazyVideoSequence(lambda k: distinct[k], keys)
    true_start, true_peak = starts[keys], (starts + lengths)[keys]
    rss0 = resource.getrusage(resource.RUSAGE_SELF).ru_maxrss / 1024
    print(f"{args.n_videos} videos of 60x240x320x3 uint8 ({len(distinct)} distinct, cycled); "
          f"n_jobs={args.n_jobs}; RSS after making them: {rss0:.0f} MB")
    print(f"{'output':<22}{'time (s)':>10}{'ms/video':>10}{'peak RSS (MB)':>15}{'|start err|':>13}{'|peak err|':>12}")
    for label, params in [
        ("240x320 rgb (native)", {}),
        ("120x160 rgb", {"output_size": (120, 160)}),
        ("60x80 gray", {"output_size": (60, 80), "color": "gray"}),
    ]:
        sel = ContactFrameSelector(n_between=2, n_jobs=args.n_jobs, **params)
        t0 = time.perf_counter()
        out = sel.fit_transform(videos)
        dt = time.perf_counter() - t0
        rss = resource.getrusage(resource.RUSAGE_SELF).ru_maxrss / 1024
        s = sel.selection_
        start_err = np.abs(s.contact_start - true_start).mean()
        peak_err = np.abs(s.contact_peak - true_peak).mean()
        print(f"{label:<22}{dt:>10.2f}{1000 * dt / len(videos):>10.1f}{rss:>15.0f}{start_err:>13.2f}{peak_err:>12.2f}")
        del out


if __name__ == "__main__":
    main()
