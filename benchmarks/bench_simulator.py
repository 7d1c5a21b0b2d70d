"""Benchmark: simulating and materialising the whole silicone5 set.

Times ``make_presses("silicone5")`` (455 presses) and rendering every video
at 240x320 (iterating over the lazy sequence, as a pipeline's ``fit`` does),
with peak RSS (``ru_maxrss``) side by side. The "error" column is the
realism check of issue 3: 5-fold accuracy of a logistic regression on one
scalar (the peak of the contact curve) against the same model on the four
frames ContactFrameSelector picks (at 48x64 for speed; ``--no-check`` skips it).

    python benchmarks/bench_simulator.py [--image-size 240 320] [--n-jobs 1] [--no-check]
    python benchmarks/bench_simulator.py --preset everyday [--codec mp4v|none]
    python benchmarks/bench_simulator.py --smoke [--preset everyday]   # a few small presses (what CI runs)

Targets (issue 3): under 30 s and under 3 GB peak RSS on 2 cores.

With ``--preset everyday`` it times the preset (168 presses, rendered and passed
through the codec), prints its contact statistics per rank against the real
GelSight Mini figures of issue 10, and the object-disjoint 5-fold balanced
accuracy of the one-number baseline and of ContactProfileFeatures + logistic
regression (``evaluate_pipelines``).
"""

import argparse
import time

import _harness  # noqa: F401 - puts the repository root on sys.path
import numpy as np
from joblib import Parallel, delayed
from threadpoolctl import threadpool_limits

from harness.memory import peak_rss_mb
from harness.smoke import add_smoke_argument, parse_args, tiny_presses


def _frames(videos):
    return sum(len(v) for v in videos)


def _check(seed=0, smoke=False):
    from sklearn.linear_model import LogisticRegression
    from sklearn.model_selection import StratifiedKFold, cross_val_score
    from sklearn.pipeline import make_pipeline
    from sklearn.preprocessing import StandardScaler

    from sklearn_hardness.datasets import make_presses
    from sklearn_hardness.preprocessing import ContactFrameSelector

    data = make_presses("silicone5", **dict(tiny_presses("silicone5", smoke), image_size=(48, 64)), random_state=seed)
    sel = ContactFrameSelector(frame_size=(12, 16))
    X = sel.fit_transform(data.videos).reshape(len(data.videos), -1)
    peak = np.array([[c.max()] for c in sel.selection_.curves])
    force = np.array([[f.max()] for f in data.force])
    cv = StratifiedKFold(5, shuffle=True, random_state=0)
    clf = make_pipeline(StandardScaler(), LogisticRegression(max_iter=500))
    with threadpool_limits(1):
        out = {name: cross_val_score(clf, feats, data.target, cv=cv).mean()
               for name, feats in [("peak intensity change", peak), ("peak force", force),
                                   ("4 selected frames", X)]}
    return out, bool(sel.selection_.contact_found.all())


def main(argv=None):
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--image-size", type=int, nargs=2, default=(240, 320))
    parser.add_argument("--n-jobs", type=int, default=1, help="render in parallel (joblib) when > 1")
    parser.add_argument("--seed", type=int, default=0)
    parser.add_argument("--no-check", action="store_true", help="skip the classification check")
    parser.add_argument("--preset", default="silicone5", choices=["silicone5", "everyday"])
    parser.add_argument("--codec", default="auto", help="everyday only: mp4v (auto), mjpg or none")
    add_smoke_argument(parser)
    args = parse_args(parser, argv, image_size=(48, 64), codec="none")
    if args.preset == "everyday":
        return _everyday(args)

    from sklearn_hardness.datasets import make_presses

    rss_import = peak_rss_mb()
    t0 = time.perf_counter()
    data = make_presses("silicone5", **dict(tiny_presses("silicone5", args.smoke), image_size=tuple(args.image_size)),
                        random_state=args.seed)
    t_make = time.perf_counter() - t0
    rss_make = peak_rss_mb()
    t0 = time.perf_counter()
    if args.n_jobs > 1:
        chunks = np.array_split(np.arange(len(data.videos)), 4 * args.n_jobs)
        n_frames = sum(Parallel(n_jobs=args.n_jobs)(delayed(_frames)(data.videos[c]) for c in chunks))
    else:
        n_frames = _frames(data.videos)
    t_render = time.perf_counter() - t0
    rss_render = peak_rss_mb()
    h, w = args.image_size
    print(f"silicone5: {len(data.videos)} presses, {n_frames} frames at {h}x{w}, n_jobs={args.n_jobs} "
          f"(RSS after imports {rss_import:.0f} MB)")
    print(f"{'step':<34}{'time (s)':>10}{'ms/video':>10}{'peak RSS (MB)':>15}")
    n = len(data.videos)
    print(f"{'make_presses (mechanics)':<34}{t_make:>10.2f}{1000 * t_make / n:>10.1f}{rss_make:>15.0f}")
    print(f"{'render all videos (iterate)':<34}{t_render:>10.2f}{1000 * t_render / n:>10.1f}{rss_render:>15.0f}")
    total = t_make + t_render
    print(f"{'total':<34}{total:>10.2f}{1000 * total / n:>10.1f}{rss_render:>15.0f}"
          f"   target: < 30 s, < 3000 MB")
    if not args.no_check:
        t0 = time.perf_counter()
        acc, found = _check(args.seed, args.smoke)
        dt = time.perf_counter() - t0
        print(f"\nclassification check (silicone5 at 48x64, {len(data.videos)} presses, 5-fold logistic regression; "
              f"chance 0.20; {dt:.1f} s); contact found on every press: {found}")
        for name, a in acc.items():
            print(f"  {name:<24} accuracy {a:.3f}")
        print("result: accuracy " + ", ".join(f"{name} {a:.2f}" for name, a in acc.items()))


def _everyday(args):
    from sklearn_hardness.datasets import make_presses
    from sklearn_hardness.model_selection import evaluate_pipelines
    from sklearn_hardness.preprocessing import contact_curve

    codec = None if args.codec == "none" else args.codec
    t0 = time.perf_counter()
    data = make_presses("everyday", **dict(tiny_presses("everyday", args.smoke), image_size=tuple(args.image_size),
                                           codec=codec), random_state=args.seed)
    t_make = time.perf_counter() - t0
    # contact_curve and ContactProfileFeatures look at every 4th pixel of a 240x320 frame (80 px on the
    # long side): keeping just those pixels gives the same numbers in 1/16 of the memory.
    stride = max(1, max(args.image_size) // 80)
    t0 = time.perf_counter()
    videos = [np.ascontiguousarray(v[:, ::stride, ::stride]) for v in data.videos]
    t_render = time.perf_counter() - t0
    n = len(videos)
    print(f"everyday: {n} presses of {len(data.objects)} objects, {sum(len(v) for v in videos)} frames "
          f"at {args.image_size[0]}x{args.image_size[1]}, codec {data.params.get('codec', codec)}")
    print(f"make_presses {t_make:.2f} s; render all {t_render:.1f} s ({1000 * t_render / n:.0f} ms/video); "
          f"peak RSS {peak_rss_mb():.0f} MB")
    curves = [contact_curve(v) for v in videos]
    full = data.press_params["n_frames"] == data.params["video_length"]
    pre = np.array([c[:30] for c, f in zip(curves, full) if f])
    print(f"pre-contact (full videos): frame 1 {np.median(pre[:, 1]):.2f}, frames 18-23 "
          f"{np.median(pre[:, 18:24]):.2f} grey levels (real: jump on frame 1, ~1.0 after ~20 frames)")
    real = {"hard": "2.5-3", "moderate": "-", "soft": "1.5-1.8"}
    for c, name in enumerate(data.target_names):
        peak = np.array([curves[i].max() for i in np.flatnonzero(full & (data.target == c))])
        q = np.percentile(peak, [10, 50, 90])
        print(f"  {name:<9} peak change median {q[1]:.2f} [10-90%: {q[0]:.2f}-{q[2]:.2f}]  real {real[name]}")
    data.videos = videos  # rendered once, shared by every fold
    t0 = time.perf_counter()
    result = evaluate_pipelines(["contact_profile"], data.videos, data.target, groups=data.object_id, cv=5,
                                target_names=data.target_names, hardness=data.hardness, n_jobs=args.n_jobs,
                                random_state=0)
    print(result)
    print(f"evaluation {time.perf_counter() - t0:.1f} s")


if __name__ == "__main__":
    main()
