"""Benchmark: K separate ConvLSTM nets against one K-stacked net (``StackedConvLSTMNet``).

Trains K independently seeded ``ConvLSTMNet`` on K data streams (member k
its own batch of ``--batch`` presses of ``--frames`` frames at ``--size``
each step), once as K nets with K Adam optimisers stepped one after another
and once as one ``StackedConvLSTMNet`` with one Adam over the stacked
parameters (the same computation: ``tests/test_models_stacked.py``). Printed
per K: training steps per second of all K members for both, their ratio,
the achieved GFLOP/s (K times one net's forward and backward counted by
``torch.utils.flop_counter``, the Adam update excluded, as ``bench_flops.py``;
the counter overcounts the backward of vmap's grouped convolutions, so the
stacked call itself is not counted) and its share of the float32
matrix-product rate of the device (on CPU timed with torch, as
``bench_flops.py`` does; on CUDA the same product timed
on the GPU, TF32 off), and the peak memory (resident set on CPU, reset per
measurement; ``torch.cuda.max_memory_allocated`` on CUDA).

``--ensemble`` adds the estimator-level figure: ``EnsembleClassifier`` of 5
``ConvLSTMClassifier`` members against one ``ConvLSTMClassifier``, fit on
``--presses`` tiny presses, with ``stacked=False`` and ``stacked=True``. It
uses the skorch classifiers.

    python benchmarks/bench_stacked.py --k 1 5 20 --device cpu --threads 1
    python benchmarks/bench_stacked.py --device cuda --k 1 5 20 50 --size 18x24
    python benchmarks/bench_stacked.py --k 1 5 --ensemble
    python benchmarks/bench_stacked.py --smoke      # K 1 and 2, one step, a tiny ensemble (what CI runs)
"""

import argparse
import os
import sys
import time

import _harness  # noqa: F401 - puts the repository root on sys.path
import numpy as np
import torch

from harness.machine import matmul_gflops
from harness.memory import peak_rss_mb, reset_peak
from harness.smoke import add_smoke_argument, parse_args
from sklearn_hardness.models._stacked import StackedConvLSTMNet


def matmul_reference(device, n, repeat):
    """Float32 matrix-product GFLOP/s on ``device``."""
    if device.type == "cpu":
        return matmul_gflops(n, repeat, threads=None)  # on the threads the nets train on
    torch.backends.cuda.matmul.allow_tf32 = False
    gen = torch.Generator(device=device).manual_seed(0)
    a = torch.randn(n, n, device=device, generator=gen)
    b = torch.randn(n, n, device=device, generator=gen)
    a @ b
    torch.cuda.synchronize(device)
    times = []
    for _ in range(repeat):
        t = time.perf_counter()
        a @ b
        torch.cuda.synchronize(device)
        times.append(time.perf_counter() - t)
    return 2 * n**3 / float(np.median(times)) / 1e9


def _sync(device):
    if device.type == "cuda":
        torch.cuda.synchronize(device)


def time_steps(step, device, steps, repeat):
    """Median seconds per call of ``step`` over ``repeat`` runs of ``steps`` calls (2 warm-up)."""
    for _ in range(2):
        step()
    _sync(device)
    times = []
    for _ in range(repeat):
        t = time.perf_counter()
        for _ in range(steps):
            step()
        _sync(device)
        times.append((time.perf_counter() - t) / steps)
    return float(np.median(times))


def count_flops(fn):
    from torch.utils.flop_counter import FlopCounterMode

    with FlopCounterMode(display=False) as counter:
        fn()
    return counter.get_total_flops()


def _reset_memory(device):
    if device.type == "cuda":
        torch.cuda.empty_cache()
        torch.cuda.reset_peak_memory_stats(device)
    else:
        reset_peak()


def _peak_mb(device):
    if device.type == "cuda":
        return torch.cuda.max_memory_allocated(device) / 2**20
    return peak_rss_mb()


def bench_k(K, args, device):
    """Seconds per step and FLOP per step of K separate nets and of one K-stacked net."""
    h, w = args.hw
    kw = dict(in_channels=1, n_classes=args.classes, dropout=args.dropout, input_shape=(args.frames, h, w, 1))
    gen = torch.Generator().manual_seed(K)
    X = torch.randn(K, args.batch, args.frames, h, w, 1, generator=gen).to(device)
    y = torch.randint(0, args.classes, (K, args.batch), generator=gen).to(device)
    out = {}

    stacked = StackedConvLSTMNet.from_seeds(K, list(range(K)), **kw).to(device).train()
    nets = stacked.unstack()  # the same initial weights, as K separate nets
    opts = [torch.optim.Adam(n.parameters(), lr=3e-3) for n in nets]

    def one_grad():
        opts[0].zero_grad()
        torch.nn.functional.cross_entropy(nets[0](X[0]), y[0]).backward()

    def separate_step():
        for k in range(K):
            opts[k].zero_grad()
            torch.nn.functional.cross_entropy(nets[k](X[k]), y[k]).backward()
            opts[k].step()

    s_opt = torch.optim.Adam(stacked.parameters(), lr=3e-3)

    def stacked_step():
        s_opt.zero_grad()
        stacked.member_losses(stacked(X), y).sum().backward()
        s_opt.step()

    # the useful arithmetic of both: K times one net's (FlopCounterMode counts the grouped
    # convolutions' backward under vmap about 3x too high, so the stacked call is not counted)
    flops = K * count_flops(one_grad)
    for name, step in (("separate", separate_step), ("stacked", stacked_step)):
        if K > args.max_separate and name == "separate":
            out[name] = None
            continue
        _reset_memory(device)
        t = time_steps(step, device, args.steps, args.repeat)
        out[name] = (t, flops, _peak_mb(device))
    return out  # the nets and optimisers go with this call's frame (the step closures hold them until then)


def bench_ensemble(args):
    """Fit times of EnsembleClassifier (5 ConvLSTM members) stacked and not, and of one net."""
    import inspect

    from sklearn_hardness.models import ConvLSTMClassifier, EnsembleClassifier

    h, w = args.hw
    rng = np.random.default_rng(0)
    n = args.presses
    X = rng.normal(size=(n, args.frames, h, w, 1)).astype(np.float32)
    y = np.arange(n) % args.classes
    X += y[:, None, None, None, None].astype(np.float32) * 0.3  # something to learn
    base = ConvLSTMClassifier(max_epochs=args.epochs, random_state=0, device=args.device)
    stacked_options = [None]
    if "stacked" in inspect.signature(EnsembleClassifier).parameters:
        stacked_options = [False, True]
    else:
        print("EnsembleClassifier has no 'stacked' parameter in this version: timing it as it is")
    rows = []

    def timed(make):
        est = make()
        _reset_memory(torch.device(args.device))
        t = time.perf_counter()
        est.fit(X, y)
        _sync(torch.device(args.device))
        return time.perf_counter() - t, _peak_mb(torch.device(args.device)), est

    t1, m1, one = timed(lambda: base)
    rows.append(("1 ConvLSTMClassifier", t1, m1, float(one.final_train_loss_)))
    for st in stacked_options:
        extra = {} if st is None else {"stacked": st}
        t, m, ens = timed(lambda: EnsembleClassifier(base, n_estimators=5, random_state=0, **extra))
        loss = float(np.mean([e.final_train_loss_ for e in ens.estimators_]))
        rows.append((f"Ensemble of 5, stacked={st}", t, m, loss))
    print(f"\nEnsembleClassifier, {n} presses of {args.frames}x{h}x{w}, {args.epochs} epochs, batch 8, "
          f"device {args.device}:")
    print(f"{'what':<30}{'fit s':>8}{'x one':>8}{'peak MB':>9}{'mean final loss':>17}")
    for name, t, m, loss in rows:
        print(f"{name:<30}{t:>8.2f}{t / t1:>8.2f}{m:>9.0f}{loss:>17.3f}")


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--k", type=int, nargs="+", default=[1, 5, 20, 50], help="numbers of members")
    ap.add_argument("--device", choices=["cpu", "cuda"], default="cpu")
    ap.add_argument("--size", default="12x16", help="frame size HxW")
    ap.add_argument("--frames", type=int, default=4)
    ap.add_argument("--batch", type=int, default=8, help="presses per batch per member")
    ap.add_argument("--classes", type=int, default=5)
    ap.add_argument("--dropout", type=float, default=0.2)
    ap.add_argument("--threads", type=int, default=1, help="torch CPU threads")
    ap.add_argument("--steps", type=int, default=5, help="steps per timed run")
    ap.add_argument("--repeat", type=int, default=3, help="timed runs; the median is printed")
    ap.add_argument("--max-separate", type=int, default=10**9,
                    help="skip the separate nets above this K (they are slow on CPU)")
    ap.add_argument("--matmul", type=int, default=0, help="matrix size of the reference (0: 2048 CPU, 8192 CUDA)")
    ap.add_argument("--ensemble", action="store_true", help="also time EnsembleClassifier (needs skorch)")
    ap.add_argument("--presses", type=int, default=40, help="training presses of the ensemble timing")
    ap.add_argument("--epochs", type=int, default=30, help="epochs of the ensemble timing")
    add_smoke_argument(ap)
    args = parse_args(ap, argv, k=[1, 2], steps=1, repeat=1, matmul=128, ensemble=True, presses=10, epochs=1)
    args.hw = tuple(int(s) for s in args.size.lower().split("x"))
    torch.set_num_threads(args.threads)
    device = torch.device(args.device)
    if device.type == "cuda" and not torch.cuda.is_available():
        ap.error("--device cuda but torch sees no GPU")
    n = args.matmul or (8192 if device.type == "cuda" else 2048)
    peak = matmul_reference(device, n, 5)
    name = torch.cuda.get_device_name(device) if device.type == "cuda" else f"{args.threads} CPU thread(s)"
    print(f"torch {torch.__version__}, {name}, "
          f"LD_PRELOAD={os.environ.get('LD_PRELOAD', '') or '-'}")
    print(f"float32 matmul {n}^3 on {device.type}: {peak:.1f} GFLOP/s (the reference); "
          f"load average {os.getloadavg()[0]:.1f} on {os.cpu_count()} CPUs")
    print(f"ConvLSTMNet (4, 8, 14, 16), {args.frames} frames of {args.size}, batch {args.batch} per member, "
          f"dropout {args.dropout}, Adam; steps/s = training steps of all K members per second")
    mem = "peak MB" + (" (alloc)" if device.type == "cuda" else " (RSS)")
    print(f"{'K':>4}{'sep steps/s':>13}{'stk steps/s':>13}{'stk/sep':>9}{'GFLOP/step':>12}"
          f"{'sep GFLOP/s':>13}{'stk GFLOP/s':>13}{'sep %peak':>10}{'stk %peak':>10}"
          f"{'sep ' + mem:>22}{'stk ' + mem:>22}")
    for K in args.k:
        r = bench_k(K, args, device)
        t_st, f_st, m_st = r["stacked"]
        if r["separate"] is None:
            sep = ["-"] * 5
            ratio = "-"
        else:
            t_se, f_se, m_se = r["separate"]
            sep = [f"{1 / t_se:.2f}", f"{f_se / t_se / 1e9:.1f}", f"{f_se / t_se / 1e9 / peak:.1%}", f"{m_se:.0f}"]
            ratio = f"{t_se / t_st:.2f}"
        print(f"{K:>4}{(sep[0]):>13}{1 / t_st:>13.2f}{ratio:>9}{f_st / 1e9:>12.3f}"
              f"{sep[1]:>13}{f_st / t_st / 1e9:>13.1f}{sep[2]:>10}{f_st / t_st / 1e9 / peak:>10.1%}"
              f"{sep[3]:>22}{m_st:>22.0f}")
        sys.stdout.flush()
    if args.ensemble:
        bench_ensemble(args)


if __name__ == "__main__":
    main()
