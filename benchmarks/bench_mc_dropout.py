"""Benchmark: batched Monte-Carlo dropout against a loop of forward calls.

For ConvLSTMClassifier and the MLP head (OFNN/DINOv2NN, on cached features)
this times ``predict_proba_samples(X, n_samples=50)`` (all passes batched
along the batch axis), a loop of 50 dropout-on forward calls of the module in
``predict_proba``-sized batches, the same loop through skorch's
DataLoader and ``infer`` (as ``predict_proba`` runs), and one deterministic
``predict_proba``. Columns:
best-of-``--repeat`` wall time, peak RSS of the process during the call
(VmHWM, reset before each method), and the check: the largest difference
between the MC mean of the method and of the batched samples (MC noise
only), and with dropout 0 the largest difference to ``predict_proba``
(should be ~1e-7).

    python benchmarks/bench_mc_dropout.py [--n-test 10] [--size 60x80] [--frames 4]
    LD_PRELOAD=/usr/lib/x86_64-linux-gnu/libtcmalloc_minimal.so.4 python benchmarks/bench_mc_dropout.py

Targets (issue 4): ConvLSTM batched >= 3x faster than the loop; MLP batched
at most 2x one deterministic predict_proba.
"""

import argparse
import os
import time

import numpy as np
import torch

from sklearn_hardness.models import ConvLSTMClassifier, DINOv2NNClassifier, MCDropout
from _memory import peak_rss_mb, reset_peak  # benchmarks/_memory.py (the script's folder is on sys.path)


def loop_module(net, X, n_samples, batch_size):
    """50 separate dropout-on forward passes, each over X in predict_proba batches."""
    module = net.module_
    module.eval()
    for m in module.modules():
        if isinstance(m, MCDropout):
            m.train()
    out = []
    with torch.inference_mode():
        for _ in range(n_samples):
            parts = [torch.softmax(module(torch.as_tensor(X[i : i + batch_size])), -1)
                     for i in range(0, len(X), batch_size)]
            out.append(torch.cat(parts).numpy())
    module.eval()
    return np.stack(out)


def loop_skorch(net, X, n_samples):
    """50 passes the way predict_proba runs: skorch dataset, DataLoader, infer."""
    module = net.module_
    module.eval()
    for m in module.modules():
        if isinstance(m, MCDropout):
            m.train()
    out = []
    with torch.inference_mode():
        for _ in range(n_samples):
            loader = net.get_iterator(net.get_dataset(X), training=False)
            out.append(torch.cat([torch.softmax(net.infer(xb), -1) for xb, _ in loader]).numpy())
    module.eval()
    return np.stack(out)


def timed(fn, repeat):
    best, result, peak = float("inf"), None, 0.0
    for _ in range(repeat):
        reset_peak()
        t0 = time.perf_counter()
        result = fn()
        best = min(best, time.perf_counter() - t0)
        peak = max(peak, peak_rss_mb())
    return best, peak, result


def report(title, net, X, n_samples, repeat, batch_size):
    print(f"\n{title}: X {X.shape}, n_samples={n_samples}")
    print(f"{'method':<36}{'time (ms)':>11}{'vs batched':>11}{'peak RSS (MB)':>15}{'max|mean diff|':>16}{'MC std':>9}")
    t_b, p_b, ref = timed(lambda: net.predict_proba_samples(X, n_samples=n_samples, random_state=0), repeat)
    rows = [("batched predict_proba_samples", t_b, p_b, ref)]
    t, p, r = timed(lambda: loop_module(net, X, n_samples, batch_size), repeat)
    rows.append((f"loop of {n_samples} module calls", t, p, r))
    t, p, r = timed(lambda: loop_skorch(net, X, n_samples), repeat)
    rows.append((f"loop of {n_samples} skorch infer", t, p, r))
    t, p, r = timed(lambda: net.predict_proba(X), repeat)
    rows.append(("one deterministic predict_proba", t, p, None))
    for name, t, p, r in rows:
        err = "" if r is None else f"{np.abs(r.mean(0) - ref.mean(0)).max():.4f}"
        spread = "" if r is None else f"{r.std(0).mean():.4f}"
        print(f"{name:<36}{1e3 * t:>11.1f}{t / t_b:>10.2f}x{p:>15.0f}{err:>16}{spread:>9}")
    net.set_params(dropout=0.0)
    exact = np.abs(net.predict_proba_samples(X, n_samples=3, random_state=0) - net.predict_proba(X)).max()
    # with dropout 0 the batched path is skipped; check the replicated forward itself too
    for m in net.module_.modules():
        if isinstance(m, MCDropout):
            m.p = 1e-12
    replicated = np.abs(net.predict_proba_samples(X, n_samples=3, random_state=0) - net.predict_proba(X)).max()
    net.set_params(dropout=0.2)
    print(f"check with dropout 0: max|samples - predict_proba| = {exact:.2e}; "
          f"replicated forward (p=1e-12) = {replicated:.2e}")
    return t_b, rows


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--n-samples", type=int, default=50)
    parser.add_argument("--n-test", type=int, default=10, help="test presses (the paper's l)")
    parser.add_argument("--frames", type=int, default=4)
    parser.add_argument("--size", default="60x80", help="HxW of the ConvLSTM frames")
    parser.add_argument("--channels", type=int, default=3)
    parser.add_argument("--mlp-dim", type=int, default=4 * 384, help="DINOv2-S features of 4 frames")
    parser.add_argument("--mlp-n", default="45,1000", help="sizes of the cached feature sets")
    parser.add_argument("--repeat", type=int, default=3)
    parser.add_argument("--threads", type=int, default=1)
    parser.add_argument("--skip-convlstm", action="store_true")
    args = parser.parse_args()
    torch.set_num_threads(args.threads)
    H, W = (int(s) for s in args.size.split("x"))
    print(f"torch {torch.__version__}, {args.threads} thread(s), "
          f"LD_PRELOAD={os.environ.get('LD_PRELOAD', '') or '-'}")

    rng = np.random.default_rng(0)
    shape = (args.frames, H, W, args.channels)
    X_train = rng.normal(scale=0.3, size=(10,) + shape).astype(np.float32)
    y_train = np.arange(10) % 5
    X_test = rng.normal(scale=0.3, size=(args.n_test,) + shape).astype(np.float32)
    if not args.skip_convlstm:
        net = ConvLSTMClassifier(max_epochs=1, random_state=0).fit(X_train, y_train)
        t_b, rows = report("ConvLSTM", net, X_test, args.n_samples, args.repeat, net.batch_size)
        print(f"ConvLSTM target: batched >= 3x faster than the loop of module calls -> "
              f"{rows[1][1] / t_b:.2f}x")

    for n in (int(s) for s in args.mlp_n.split(",")):
        F_train = rng.normal(size=(45, args.mlp_dim)).astype(np.float32)
        mlp = DINOv2NNClassifier(max_epochs=1, random_state=0).fit(F_train, np.arange(45) % 9)
        F = rng.normal(size=(n, args.mlp_dim)).astype(np.float32)
        t_b, rows = report(f"MLP head (DINOv2NN/OFNN) on cached features, n={n}", mlp, F,
                           args.n_samples, args.repeat, mlp.batch_size)
        print(f"MLP target: batched <= 2x one predict_proba -> {t_b / rows[3][1]:.2f}x")


if __name__ == "__main__":
    main()
