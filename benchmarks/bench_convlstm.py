"""Benchmark: ConvLSTMClassifier training cost and accuracy against input size.

One training epoch on 40 presses (4 selected frames each, the paper's robot
setting: first + 2 between + peak) at several frame sizes, grey and RGB:
wall time, peak RSS (VmHWM, reset before each run) and, for the smaller sizes,
the held-out accuracy after ``--epochs`` epochs on a synthetic
hardness-like task (the error column).

The synthetic task imitates what the selected frames of a press show: a
contact blob whose brightness grows with the gel's own indentation
(F * c_gel) and whose radius grows with the total approach
(sqrt(F * (c_gel + c_object))). The push force F ~ U[1, 5] N varies per
press, so brightness alone is confounded with force and the class (object
compliance 1.13, 1.02, 0.79, 0.68, 0.44 mm/N, as the paper's silicone set,
+-3% per press) must be read from the blob's size relative to its
brightness. Frames are made at 240x320 (GelSight Mini) and downsized with
cv2.INTER_AREA, as ``ContactFrameSelector(frame_size=...)`` does.

    python benchmarks/bench_convlstm.py [--sizes 30x40,60x80,120x160,240x320] [--epochs 60] [--lr 3e-3]
    LD_PRELOAD=/usr/lib/x86_64-linux-gnu/libtcmalloc_minimal.so.4 python benchmarks/bench_convlstm.py --no-accuracy
"""

import argparse
import os
import time

import _harness  # noqa: F401 - puts the repository root on sys.path
import cv2
import numpy as np
import torch

from harness.memory import peak_rss_mb, reset_peak
from harness.smoke import add_smoke_argument, parse_args
from sklearn_hardness.models import ConvLSTMClassifier

COMPLIANCE = np.array([1.13, 1.02, 0.79, 0.68, 0.44])  # mm/N, the paper's objects
C_GEL = 0.3  # mm/N


def synthetic_selected_frames(n, k=4, size=(240, 320), seed=0):
    """(n, k, H, W, 3) float32 differences to the first frame, and labels."""
    rng = np.random.default_rng(seed)
    h, w = size
    y = np.arange(n) % len(COMPLIANCE)
    force = rng.uniform(1, 5, n)
    comp = COMPLIANCE[y] * rng.normal(1, 0.03, n)
    radius = 25.0 * np.sqrt(force * (C_GEL + comp)) * (h / 240)
    depth = 0.12 * force  # brightness of the full press (gel indentation F * c_gel), <= 0.6
    yy, xx = np.mgrid[:h, :w].astype(np.float32)
    colour = np.array([1.0, 0.6, 0.3], np.float32)
    X = np.empty((n, k, h, w, 3), np.float32)
    for i in range(n):
        cy, cx = h / 2 + rng.uniform(-10, 10), w / 2 + rng.uniform(-10, 10)
        r2 = (yy - cy) ** 2 + (xx - cx) ** 2
        for j in range(k):
            frac = j / (k - 1) if k > 1 else 1.0  # contact start ... peak
            r = max(radius[i] * np.sqrt(max(frac, 1e-3)), 0.5)
            blob = np.clip(1.0 - r2 / r**2, 0, None)
            X[i, j] = (depth[i] * frac * blob)[..., None] * colour
        X[i] += rng.standard_normal(X[i].shape, dtype=np.float32) * 0.01
    return X, y


def resize(X, size, color):
    n, k, H, W, C = X.shape
    h, w = size
    if (h, w) == (H, W):
        out = X
    else:
        out = np.stack([cv2.resize(f, (w, h), interpolation=cv2.INTER_AREA) for f in X.reshape(n * k, H, W, C)])
        out = out.reshape(n, k, h, w, C)
    if color == "gray":
        out = (out @ np.array([0.299, 0.587, 0.114], np.float32))[..., None]
    return np.ascontiguousarray(out, dtype=np.float32)


def main(argv=None):
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--n-train", type=int, default=40)
    parser.add_argument("--n-test", type=int, default=100)
    parser.add_argument("--sizes", default="30x40,60x80,120x160,240x320")
    parser.add_argument("--colors", default="gray,rgb")
    parser.add_argument("--epochs", type=int, default=60, help="epochs for the accuracy column")
    parser.add_argument("--lr", type=float, default=3e-3)
    parser.add_argument("--accuracy-max-pixels", type=int, default=60 * 80,
                        help="measure accuracy only up to this frame size (H*W)")
    parser.add_argument("--no-accuracy", action="store_true")
    parser.add_argument("--threads", type=int, default=1)
    add_smoke_argument(parser)
    args = parse_args(parser, argv, n_train=10, n_test=5, sizes="12x16", colors="gray", epochs=3)
    torch.set_num_threads(args.threads)
    print(f"torch {torch.__version__}, {args.threads} thread(s), "
          f"LD_PRELOAD={os.environ.get('LD_PRELOAD', '') or '-'}")
    size = (48, 64) if args.smoke else (240, 320)  # --smoke: frames made at 48x64
    X_full, y = synthetic_selected_frames(args.n_train + args.n_test, size=size, seed=0)
    print(f"{args.n_train} training presses, {args.n_test} held out, 4 frames, 5 classes "
          f"(chance 20%), batch_size=8, Adam lr={args.lr}; RSS with the {size[0]}x{size[1]} data in memory: "
          f"{peak_rss_mb():.0f} MB")
    print(f"{'input':<18}{'epoch (s)':>10}{'ms/press':>10}{'peak RSS (MB)':>15}{'+MB':>7}"
          f"{'acc (held out)':>16}{'train loss':>12}")
    for size in args.sizes.split(","):
        h, w = (int(s) for s in size.split("x"))
        for color in args.colors.split(","):
            X = resize(X_full, (h, w), color)
            X_train, y_train = X[: args.n_train], y[: args.n_train]
            X_test, y_test = X[args.n_train :], y[args.n_train :]
            net = ConvLSTMClassifier(max_epochs=1, lr=args.lr, random_state=0).fit(X_train, y_train)  # warm-up
            reset_peak()
            base = peak_rss_mb()
            t0 = time.perf_counter()
            net.partial_fit(X_train, y_train, epochs=1)
            dt = time.perf_counter() - t0
            peak = peak_rss_mb()
            acc, loss = "", ""
            if not args.no_accuracy and h * w <= args.accuracy_max_pixels:
                net.partial_fit(X_train, y_train, epochs=args.epochs - 2)
                acc = f"{net.score(X_test, y_test):.2f}"
                loss = f"{net.final_train_loss_:.3f}"
            print(f"{f'{h}x{w} {color}':<18}{dt:>10.2f}{1e3 * dt / args.n_train:>10.0f}{peak:>15.0f}{peak - base:>7.0f}"
                  f"{acc:>16}{loss:>12}")
            if acc:
                print(f"result: accuracy {acc} at {h}x{w} {color}")


if __name__ == "__main__":
    main()
