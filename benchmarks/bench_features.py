"""Benchmark: OpticalFlowFeatures and DINOv2Features on silicone5-sized inputs.

Input: selected frames as ContactFrameSelector gives them, k = 4 frames of
240x320 RGB float32 per press (455 presses: the size of the paper's robot set).
The frames are synthetic: a GelSight-like image (colour gradient, dark marker
dots, fine texture) translated by a known random shift per frame, so the
optical-flow error against the truth can be printed next to time and memory.

DINOv2Features runs with RANDOMLY INITIALISED backbones (no weights can be
downloaded here): a tiny one and one with the size of DINOv2-S/14 (384 wide,
12 layers, 6 heads), so the timings are those of the real model but the
features are meaningless. Its error column is the largest difference of
bfloat16 to float32 features, relative to the float32 feature scale.

Peak memory is the largest resident set size (sampled every 5 ms from
/proc/self/statm) during the call, minus the resident size before it: the
extra memory the transform needs on top of its input.

    python benchmarks/bench_features.py [--n-videos 455] [--n-dino 16] [--threads 2] [--smoke]
"""

import argparse
import os
import threading
import time
import warnings

import _harness  # noqa: F401 - puts the repository root on sys.path
import cv2
import numpy as np
import torch

from harness.smoke import add_smoke_argument, parse_args
from sklearn_hardness.features import DINOv2Features, OpticalFlowFeatures

PAGE_MB = os.sysconf("SC_PAGE_SIZE") / 2**20


def rss_mb():
    with open("/proc/self/statm") as f:
        return int(f.read().split()[1]) * PAGE_MB


class PeakRSS:
    """Context manager sampling the resident set size in a thread."""

    def __enter__(self):
        self.base = self.peak = rss_mb()
        self._stop = threading.Event()
        self._thread = threading.Thread(target=self._run, daemon=True)
        self._thread.start()
        self.t0 = time.perf_counter()
        return self

    def _run(self):
        while not self._stop.is_set():
            self.peak = max(self.peak, rss_mb())
            time.sleep(0.005)

    def __exit__(self, *exc):
        self.seconds = time.perf_counter() - self.t0
        self._stop.set()
        self._thread.join()
        self.peak = max(self.peak, rss_mb())
        self.extra = self.peak - self.base


def gelsight_like(rng, size=(240, 320)):
    """A GelSight-like background: colour gradient, dark markers, fine texture (float32 RGB)."""
    H, W = size
    yy, xx = np.mgrid[0:H, 0:W].astype(np.float32)
    img = np.stack([0.45 + 0.2 * xx / W, 0.5 + 0.15 * yy / H, 0.55 - 0.1 * xx / W], axis=-1)
    noise = cv2.GaussianBlur(rng.random((H, W)).astype(np.float32), (0, 0), 1.2)
    img += 0.15 * (noise - noise.mean())[..., None]
    for y in np.arange(12, H, 24):
        for x in np.arange(12, W, 24):
            cv2.circle(img, (int(x + rng.normal(0, 1)), int(y + rng.normal(0, 1))), 3, (0.1, 0.1, 0.1), -1)
    return np.clip(cv2.GaussianBlur(img, (0, 0), 0.7), 0, 1)


def make_frames(n, k, size, rng, n_distinct=20):
    """(n, k, H, W, 3) float32 frames; frame t of press i is its image shifted by t * shift_i."""
    H, W = size
    pad = 16
    bases = [gelsight_like(rng, (H + 2 * pad, W + 2 * pad)) for _ in range(n_distinct)]
    shifts = rng.uniform(-1.5, 1.5, (n, 2)).astype(np.float32)
    X = np.empty((n, k, H, W, 3), np.float32)
    for i in range(n):
        base = bases[i % n_distinct]
        for t in range(k):
            M = np.float32([[1, 0, t * shifts[i, 0]], [0, 1, t * shifts[i, 1]]])
            moved = cv2.warpAffine(base, M, base.shape[1::-1], flags=cv2.INTER_CUBIC, borderMode=cv2.BORDER_REFLECT)
            X[i, t] = moved[pad:pad + H, pad:pad + W]
    return np.clip(X, 0, 1, out=X), shifts


def bench_optical_flow(X, shifts, n_jobs_list):
    n, k = X.shape[:2]
    print(f"\nOpticalFlowFeatures on {n} x {k} frames of {X.shape[2]}x{X.shape[3]}x{X.shape[4]} float32 "
          f"({X.nbytes / 2**20:.0f} MB input)")
    print(f"{'setting':<34}{'time (s)':>9}{'ms/video':>10}{'extra RSS (MB)':>16}"
          f"{'corners/video':>15}{'tracked %':>11}{'med |err| px':>14}{'p95 |err| px':>14}")
    for label, params in [(f"n_features=500, n_jobs={j}", {"n_jobs": j}) for j in n_jobs_list] + [
        ("n_features=100, n_jobs=1", {"n_features": 100, "n_jobs": 1}),
    ]:
        of = OpticalFlowFeatures(**params).fit(X[:1])
        with warnings.catch_warnings():
            warnings.simplefilter("ignore", UserWarning)
            with PeakRSS() as m:
                out = of.transform(X)
            tr = of.track(X)
        m_feat = of.n_features
        disp = out.reshape(n, m_feat, k - 1, 2)
        truth = np.arange(1, k)[None, None, :, None] * shifts[:, None, None, :]
        ok = tr.valid[:, :, 1:]
        err = np.abs(disp - truth)[ok].ravel()
        print(f"{label:<34}{m.seconds:>9.2f}{1000 * m.seconds / n:>10.2f}{m.extra:>16.0f}"
              f"{tr.n_corners.mean():>15.0f}{100 * ok.sum() / max(1, tr.valid[:, :, 0].sum() * (k - 1)):>11.1f}"
              f"{np.median(err):>14.3f}{np.quantile(err, 0.95):>14.3f}")


def dinov2_random(hidden, layers, heads, mlp):
    from transformers import Dinov2Config, Dinov2Model

    torch.manual_seed(0)
    cfg = Dinov2Config(hidden_size=hidden, num_hidden_layers=layers, num_attention_heads=heads,
                       intermediate_size=mlp, image_size=518, patch_size=14)
    return Dinov2Model(cfg).eval()


def bench_dinov2(X, batch_size):
    n, k = X.shape[:2]
    print(f"\nDINOv2Features (RANDOM weights) on {n} x {k} frames, resized to 224x224, "
          f"batch_size={batch_size}, torch threads={torch.get_num_threads()}")
    print(f"{'backbone':<44}{'time (s)':>9}{'ms/video':>10}{'ms/frame':>10}{'extra RSS (MB)':>16}{'bf16 rel err':>14}")
    for label, (hidden, layers, heads, mlp) in [
        ("tiny (32 wide, 1 layer)", (32, 1, 2, 64)),
        ("DINOv2-S/14-sized (384 wide, 12 layers)", (384, 12, 6, 1536)),
    ]:
        backbone = dinov2_random(hidden, layers, heads, mlp)
        dino = DINOv2Features(model=backbone, token="cls", batch_size=batch_size).fit(X[:1])
        with PeakRSS() as m:
            out = dino.transform(X)
        bf16 = dino.set_params(dtype="bfloat16").fit(X[:1]).transform(X[: max(1, n // 4)])
        rel = np.abs(bf16 - out[: len(bf16)]).max() / np.abs(out).max()
        print(f"{label:<44}{m.seconds:>9.2f}{1000 * m.seconds / n:>10.1f}{1000 * m.seconds / (n * k):>10.1f}"
              f"{m.extra:>16.0f}{rel:>14.3f}")


def main(argv=None):
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--n-videos", type=int, default=455, help="presses for OpticalFlowFeatures")
    parser.add_argument("--n-dino", type=int, default=16, help="presses for DINOv2Features")
    parser.add_argument("--frames", type=int, default=4, help="selected frames per press (k)")
    parser.add_argument("--threads", type=int, default=2, help="torch and OpenCV threads")
    parser.add_argument("--batch-size", type=int, default=32)
    parser.add_argument("--skip-dinov2", action="store_true")
    add_smoke_argument(parser)
    args = parse_args(parser, argv, n_videos=4, n_dino=1, threads=1)
    torch.set_num_threads(args.threads)
    cv2.setNumThreads(args.threads)

    rng = np.random.default_rng(0)
    t0 = time.perf_counter()
    X, shifts = make_frames(args.n_videos, args.frames, (48, 64) if args.smoke else (240, 320), rng)
    print(f"made {args.n_videos} synthetic presses in {time.perf_counter() - t0:.1f} s; "
          f"RSS {rss_mb():.0f} MB; {os.cpu_count()} CPU(s), threads={args.threads}")
    bench_optical_flow(X, shifts, n_jobs_list=sorted({1, args.threads}))
    if not args.skip_dinov2:
        bench_dinov2(X[: args.n_dino], args.batch_size)


if __name__ == "__main__":
    main()
