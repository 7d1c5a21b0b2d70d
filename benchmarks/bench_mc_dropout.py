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

``--pipelines`` times every ready-made pipeline at its defaults instead
(``make_convlstm_pipeline``, ``make_ofnn_pipeline``, ``make_dinov2nn_pipeline``
with a tiny randomly initialised DINOv2 backbone, as no weights can be
downloaded here) on simulated ``silicone5`` presses: one ``predict_proba`` and
``predict_proba_samples(n_samples=50)`` on the same ``--n-test`` presses, end to
end (videos in) and for the net alone (its prepared input), with the ratios.
Target (issue 9): 50 passes <= 5x one predict_proba.

    python benchmarks/bench_mc_dropout.py --pipelines [--n-test 10]

``--smoke`` (with or without ``--pipelines``): tiny inputs, few passes, one repetition (what CI runs).
"""

import argparse
import os
import time

import _harness  # noqa: F401 - puts the repository root on sys.path
import numpy as np
import torch

from harness.memory import peak_rss_mb, reset_peak
from harness.smoke import add_smoke_argument, parse_args
from sklearn_hardness.models import ConvLSTMClassifier, DINOv2NNClassifier


def dropout_layers(module):
    """The net's dropout layers: its submodules with a float drop probability ``p``.

    The classifiers' MC-dropout layer is not a ``torch.nn.Dropout`` and its class is private;
    in ConvLSTMNet and the MLP head these are exactly its instances (the modules that
    ``set_params(dropout=...)`` updates), which ``check_dropout_layers`` checks.
    """
    return [m for m in module.modules() if m is not module and isinstance(getattr(m, "p", None), float)]


def check_dropout_layers(net):
    """Fail loudly if :func:`dropout_layers` misses the layers ``set_params(dropout=...)`` sets."""
    layers = dropout_layers(net.module_)
    p = net.dropout
    net.set_params(dropout=0.125)
    changed = [m for m in net.module_.modules() if getattr(m, "p", None) == 0.125]
    net.set_params(dropout=p)
    if not layers or [id(m) for m in layers] != [id(m) for m in changed]:
        raise RuntimeError(f"dropout_layers found {len(layers)} layer(s); set_params changes {len(changed)}.")
    return layers


def loop_module(net, X, n_samples, batch_size):
    """50 separate dropout-on forward passes, each over X in predict_proba batches."""
    module = net.module_
    module.eval()
    for m in dropout_layers(module):
        m.train()
    out = []
    device = next(module.parameters()).device
    with torch.inference_mode():
        for _ in range(n_samples):
            parts = [torch.softmax(module(torch.as_tensor(X[i : i + batch_size], device=device)), -1)
                     for i in range(0, len(X), batch_size)]
            out.append(torch.cat(parts).cpu().numpy())
    module.eval()
    return np.stack(out)


def loop_skorch(net, X, n_samples):
    """50 passes the way predict_proba runs: skorch dataset, DataLoader, infer."""
    module = net.module_
    module.eval()
    for m in dropout_layers(module):
        m.train()
    out = []
    with torch.inference_mode():
        for _ in range(n_samples):
            loader = net.get_iterator(net.get_dataset(X), training=False)
            out.append(torch.cat([torch.softmax(net.infer(xb), -1) for xb, _ in loader]).cpu().numpy())
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
    check_dropout_layers(net)
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
    for m in dropout_layers(net.module_):
        m.p = 1e-12
    replicated = np.abs(net.predict_proba_samples(X, n_samples=3, random_state=0) - net.predict_proba(X)).max()
    net.set_params(dropout=0.2)
    print(f"check with dropout 0: max|samples - predict_proba| = {exact:.2e}; "
          f"replicated forward (p=1e-12) = {replicated:.2e}")
    print(f"result: max|samples - predict_proba| {exact:.1e} at dropout 0")
    return t_b, rows


def tiny_dinov2():
    import transformers

    torch.manual_seed(0)
    cfg = transformers.Dinov2Config(hidden_size=32, num_hidden_layers=1, num_attention_heads=2,
                                    intermediate_size=64, image_size=28, patch_size=14)
    return transformers.Dinov2Model(cfg).eval()


def bench_pipelines(n_test, repeat, device="cpu", image_size=(240, 320)):
    """One predict_proba against 50 MC passes for each ready-made pipeline at its defaults."""
    from sklearn_hardness.datasets import make_presses
    from sklearn_hardness.models import make_convlstm_pipeline, make_dinov2nn_pipeline, make_ofnn_pipeline

    data = make_presses("silicone5", n_per_class=5 + -(-n_test // 5), image_size=image_size, random_state=0)
    y = np.asarray(data.target)
    train = np.concatenate([np.flatnonzero(y == c)[:5] for c in np.unique(y)])
    test = np.setdiff1d(np.arange(len(y)), train)[:n_test]
    videos = list(data.videos)
    train_v, test_v = [videos[i] for i in train], [videos[i] for i in test]
    pipes = {
        "make_convlstm_pipeline": make_convlstm_pipeline(max_epochs=2, random_state=0, device=device),
        "make_ofnn_pipeline": make_ofnn_pipeline(max_epochs=2, random_state=0, device=device),
        "make_dinov2nn_pipeline (tiny backbone)": make_dinov2nn_pipeline(model=tiny_dinov2(), max_epochs=2,
                                                                         random_state=0, device=device),
    }
    print(f"\nready-made pipelines at their defaults, {len(test)} test presses, 50 MC passes "
          f"(best of {repeat})")
    print(f"{'pipeline':<40}{'part':<10}{'predict_proba ms':>17}{'50 passes ms':>14}{'ratio':>7}")
    for name, pipe in pipes.items():
        pipe.fit(train_v, y[train])
        Xt = pipe[:-1].transform(test_v)
        net = pipe[-1]
        for part, model, X in (("end2end", pipe, test_v), ("net", net, Xt)):
            t_pp, _, _ = timed(lambda: model.predict_proba(X), repeat)
            t_mc, _, _ = timed(lambda: model.predict_proba_samples(X, n_samples=50, random_state=0), repeat)
            print(f"{name:<40}{part:<10}{1e3 * t_pp:>17.1f}{1e3 * t_mc:>14.1f}{t_mc / t_pp:>7.2f}")


def main(argv=None):
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
    parser.add_argument("--pipelines", action="store_true", help="time the ready-made pipelines instead")
    parser.add_argument("--device", default="cpu", help="torch device of the nets (cpu, cuda)")
    add_smoke_argument(parser)
    args = parse_args(parser, argv, n_samples=3, n_test=2, size="12x16", mlp_dim=8, mlp_n="5", repeat=1)
    torch.set_num_threads(args.threads)
    if args.pipelines:
        bench_pipelines(args.n_test, args.repeat, args.device, (48, 64) if args.smoke else (240, 320))
        return
    H, W = (int(s) for s in args.size.split("x"))
    print(f"torch {torch.__version__}, device {args.device}, {args.threads} thread(s), "
          f"LD_PRELOAD={os.environ.get('LD_PRELOAD', '') or '-'}")

    rng = np.random.default_rng(0)
    shape = (args.frames, H, W, args.channels)
    X_train = rng.normal(scale=0.3, size=(10,) + shape).astype(np.float32)
    y_train = np.arange(10) % 5
    X_test = rng.normal(scale=0.3, size=(args.n_test,) + shape).astype(np.float32)
    if not args.skip_convlstm:
        net = ConvLSTMClassifier(max_epochs=1, random_state=0, device=args.device).fit(X_train, y_train)
        t_b, rows = report("ConvLSTM", net, X_test, args.n_samples, args.repeat, net.batch_size)
        print(f"ConvLSTM target: batched >= 3x faster than the loop of module calls -> "
              f"{rows[1][1] / t_b:.2f}x")

    for n in (int(s) for s in args.mlp_n.split(",")):
        F_train = rng.normal(size=(45, args.mlp_dim)).astype(np.float32)
        mlp = DINOv2NNClassifier(max_epochs=1, random_state=0, device=args.device).fit(F_train, np.arange(45) % 9)
        F = rng.normal(size=(n, args.mlp_dim)).astype(np.float32)
        t_b, rows = report(f"MLP head (DINOv2NN/OFNN) on cached features, n={n}", mlp, F,
                           args.n_samples, args.repeat, mlp.batch_size)
        print(f"MLP target: batched <= 2x one predict_proba -> {t_b / rows[3][1]:.2f}x")


if __name__ == "__main__":
    main()
