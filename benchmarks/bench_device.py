"""Benchmark: every net on a GPU beside the CPU, and its pickle read back where no GPU is seen.

Nothing requires a GPU, and CI has none, so the paths that run only on one
(``device="cuda"``, :class:`~sklearn_hardness.models.EnsembleClassifier`
stacking its members there by default, generators and weights saved from the
GPU) are checked by running this script on a machine that has one. Each net
is fitted twice on the same simulated ``silicone5`` presses with the same
seed, on ``--device`` and on the CPU, after one pass of its per-press steps
(frame selection, optical flow, a tiny randomly initialised DINOv2 backbone,
since no weights can be downloaded, the contact-profile features):

- the ConvLSTM as ``evaluate`` trains it for new objects (intensity channels)
  with ``augment=True`` (random flips and gains drawn on the CPU, applied on
  the device), and the paper's frames alone;
- the OFNN (flow magnitude quantiles), the DINOv2NN and the contact-profile
  MLP (``ContactProfileNNClassifier``);
- an ensemble of five ConvLSTMs (``stacked="auto"``: stacked on a GPU, one by
  one on the CPU).

Per net, side by side: fit time on each device, accuracy on held-out
presses (the two fits differ by their float order, not by much), the
largest difference between the device net's ``predict_proba`` and the same
weights on the CPU, whether ``predict_proba_samples`` with one seed gives the
same samples twice on the device, and the largest difference between the
device net's ``predict_proba`` and that of its pickle loaded in a process
that sees no GPU (``CUDA_VISIBLE_DEVICES=""``).

    python benchmarks/bench_device.py [--device cuda] [--n-per-class 16] [--epochs 30] [--out FILE]

``--smoke`` runs both fits on the CPU, on a few small presses, one epoch (what CI runs: it has no GPU).
"""

import argparse
import copy
import os
import pickle
import subprocess
import sys
import tempfile
import time
import warnings

import _harness  # noqa: F401 - puts the repository root on sys.path
import numpy as np
import torch

from harness.smoke import add_smoke_argument, parse_args

LOAD_ON_CPU = """
import pickle, sys, warnings
import numpy as np
warnings.simplefilter("ignore")
with open(sys.argv[1], "rb") as f:
    nets = pickle.load(f)
X = dict(np.load(sys.argv[2]))
import torch
assert not torch.cuda.is_available()
np.savez(sys.argv[3], **{name: net.predict_proba(X[name]) for name, net in nets.items()})
"""


def tiny_dinov2():
    """A randomly initialised one-layer DINOv2 backbone (no download)."""
    import transformers

    torch.manual_seed(0)
    cfg = transformers.Dinov2Config(hidden_size=32, num_hidden_layers=1, num_attention_heads=2,
                                    intermediate_size=64, image_size=28, patch_size=14)
    return transformers.Dinov2Model(cfg).eval()


def inputs(n_per_class, seed, image_size=(120, 160)):
    """Per net: its input rows of every press (per-press steps run once, on the CPU), and the labels."""
    from sklearn_hardness.datasets import make_presses
    from sklearn_hardness.features import ContactProfileFeatures
    from sklearn_hardness.models import make_convlstm_pipeline, make_dinov2nn_pipeline, make_ofnn_pipeline

    data = make_presses("silicone5", n_per_class=n_per_class, image_size=image_size, random_state=seed)
    videos = [data.videos[i] for i in range(len(data.target))]
    backbone = tiny_dinov2()  # 28x28 input, random weights
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", UserWarning)
        rows = {"convlstm": make_convlstm_pipeline(intensity_channels=True)[:-1].fit_transform(videos),
                "convlstm_frames": make_convlstm_pipeline()[:-1].fit_transform(videos),
                "ofnn": make_ofnn_pipeline()[:-1].fit_transform(videos),
                "dinov2nn": make_dinov2nn_pipeline(model=backbone, frame_size=(28, 28))[:-1].fit_transform(videos),
                "contact_profile_nn": ContactProfileFeatures().fit_transform(videos)}
    rows["contact_profile_nn"] = ((rows["contact_profile_nn"] - rows["contact_profile_nn"].mean(0))
                                  / (rows["contact_profile_nn"].std(0) + 1e-9)).astype(np.float32)
    return rows, np.asarray(data.target)


def nets(device, epochs, seed):
    """name -> unfitted net on ``device``."""
    from sklearn_hardness.models import (
        ContactProfileNNClassifier,
        ConvLSTMClassifier,
        DINOv2NNClassifier,
        EnsembleClassifier,
        FrameAugmenter,
        OFNNClassifier,
    )

    common = dict(max_epochs=epochs, device=device, random_state=seed, class_weight="balanced")
    return {
        "convlstm": ConvLSTMClassifier(augment=FrameAugmenter(log_channels=(1, 2, 3)), **common),
        "convlstm_frames": ConvLSTMClassifier(**common),
        "ofnn": OFNNClassifier(**common),
        "dinov2nn": DINOv2NNClassifier(**common),
        "contact_profile_nn": ContactProfileNNClassifier(**common),
        "ensemble of 5 convlstm": EnsembleClassifier(ConvLSTMClassifier(**common), n_estimators=5,
                                                     random_state=seed),
    }


def input_of(name):
    return "convlstm" if name.startswith("ensemble") else name


def on_cpu(net):
    """A deep copy of a fitted net whose weights are on the CPU (an ensemble: each member)."""
    net = copy.deepcopy(net)
    for member in getattr(net, "estimators_", [net]):
        member.set_params(device="cpu")
        member.module_.to("cpu")
    return net


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--device", default="cuda")
    ap.add_argument("--n-per-class", type=int, default=16)
    ap.add_argument("--epochs", type=int, default=30)
    ap.add_argument("--seed", type=int, default=0)
    ap.add_argument("--out", default=None)
    add_smoke_argument(ap)
    args = parse_args(ap, argv, device="cpu", n_per_class=2, epochs=1)
    if torch.device(args.device).type == "cuda" and not torch.cuda.is_available():
        ap.error(f"--device {args.device}, but torch sees no GPU")

    rows, y = inputs(args.n_per_class, args.seed, (48, 64) if args.smoke else (120, 160))
    rng = np.random.default_rng(args.seed)
    test = np.zeros(len(y), bool)
    for c in np.unique(y):
        test[rng.choice(np.flatnonzero(y == c), max(1, (y == c).sum() // 4), replace=False)] = True
    lines = [f"{int((~test).sum())} training and {int(test.sum())} test presses of silicone5, {args.epochs} epochs; "
             f"device {args.device} ({torch.cuda.get_device_name(args.device) if torch.cuda.is_available() else 'cpu'})"
             f", torch {torch.__version__}", "",
             "| net | fit s (device) | fit s (cpu) | accuracy (device) | accuracy (cpu) "
             "| same weights on cpu: max diff "
             "| samples repeat on device | pickle on a GPU-less process: max diff |",
             "|---|---|---|---|---|---|---|---|"]
    fitted = {}
    results = {}
    for name in nets("cpu", args.epochs, args.seed):
        X = rows[input_of(name)]
        timing, acc = {}, {}
        for device in (args.device, "cpu"):
            net = nets(device, args.epochs, args.seed)[name]
            t0 = time.perf_counter()
            with warnings.catch_warnings():
                warnings.simplefilter("ignore", UserWarning)
                net.fit(X[~test], y[~test])
            if torch.cuda.is_available():
                torch.cuda.synchronize()
            timing[device] = time.perf_counter() - t0
            acc[device] = float((net.predict(X[test]) == y[test]).mean())
            if device == args.device:
                fitted[name] = net
        dev = fitted[name]
        proba = dev.predict_proba(X[test])
        same_weights = float(np.abs(on_cpu(dev).predict_proba(X[test]) - proba).max())
        s1 = dev.predict_proba_samples(X[test], n_samples=10, random_state=3)
        s2 = dev.predict_proba_samples(X[test], n_samples=10, random_state=3)
        results[name] = [timing[args.device], timing["cpu"], acc[args.device], acc["cpu"], same_weights,
                         bool(np.array_equal(s1, s2)), proba]
        if hasattr(dev, "stacked_"):
            print(f"{name}: stacked_={dev.stacked_}", file=sys.stderr, flush=True)
        print(f"{name}: done", file=sys.stderr, flush=True)
    with tempfile.TemporaryDirectory() as tmp:
        nets_path, x_path, out_path = (os.path.join(tmp, f) for f in ("nets.pkl", "x.npz", "p.npz"))
        with open(nets_path, "wb") as f:
            pickle.dump(fitted, f)
        np.savez(x_path, **{name: rows[input_of(name)][test] for name in fitted})
        env = dict(os.environ, CUDA_VISIBLE_DEVICES="")
        done = subprocess.run([sys.executable, "-c", LOAD_ON_CPU, nets_path, x_path, out_path], env=env,
                              capture_output=True, text=True)
        loaded = dict(np.load(out_path)) if done.returncode == 0 else {}
    for name, (t_dev, t_cpu, a_dev, a_cpu, same, repeat, proba) in results.items():
        pickled = f"{np.abs(loaded[name] - proba).max():.1e}" if name in loaded else "failed"
        lines.append(f"| {name} | {t_dev:.1f} | {t_cpu:.1f} | {a_dev:.2f} | {a_cpu:.2f} | {same:.1e} | {repeat} "
                     f"| {pickled} |")
    if done.returncode != 0:
        lines += ["", "loading the pickle where no GPU is seen failed:", done.stderr[-2000:]]
    text = "\n".join(lines)
    print(text)
    if args.out:
        with open(args.out, "w") as f:
            f.write(text + "\n")


if __name__ == "__main__":
    main()
