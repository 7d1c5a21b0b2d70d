"""Study: how often the ConvLSTM's initial training converges by the paper's rule.

The paper's settings: simulated ``silicone5``, 5 training presses per object,
18x24 grey difference frames (2 between contact start and peak), 100 epochs,
dropout 0.2, lr 1e-3, batch 8. A run converges when the training loss of the
last epoch is <= 1 (:func:`sklearn_hardness.models.is_converged`). Each seed
draws its own training presses and initial weights. Configurations:

* ``raw``: no input standardisation (``standardize=False``);
* ``std``: built-in standardisation (the default);
* ``std+clip``: and ``GradientNormClipping(1.0)``;
* ``std+cosine``: and a cosine learning-rate schedule to 0 over the epochs;
* ``std+lr3e-3``: and lr 3e-3.

    python studies/scripts/convergence.py [--seeds 20] [--configs std,std+clip] [--placement head] [--n-jobs 2]
        [--smoke]
"""

import argparse
import time

import _harness  # noqa: F401 - puts the repository root on sys.path
import numpy as np
import torch
from joblib import Parallel, delayed
from mc_share import silicone5_frames, split  # the script's folder is on sys.path
from skorch.callbacks import GradientNormClipping, LRScheduler

from harness.smoke import add_smoke_argument, parse_args
from sklearn_hardness.models import ConvLSTMClassifier, is_converged


def make_net(config, placement, epochs, seed):
    kw = dict(dropout=0.2, dropout_placement=placement, max_epochs=epochs, lr=1e-3, batch_size=8,
              random_state=seed)
    callbacks = []
    if config == "raw":
        kw["standardize"] = False
    if config.endswith("+clip"):
        callbacks.append(("clip", GradientNormClipping(1.0)))
    if config.endswith("+cosine"):
        callbacks.append(("lr_schedule", LRScheduler(torch.optim.lr_scheduler.CosineAnnealingLR, T_max=epochs)))
    if config.endswith("+lr3e-3"):
        kw["lr"] = 3e-3
    return ConvLSTMClassifier(callbacks=callbacks or None, **kw)


def one_run(X, y, config, placement, epochs, seed):
    torch.set_num_threads(1)
    train, _ = split(y, 5, seed)
    t0 = time.perf_counter()
    net = make_net(config, placement, epochs, seed).fit(X[train], y[train])
    return config, seed, net.final_train_loss_, time.perf_counter() - t0


def main(argv=None):
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--seeds", type=int, default=20)
    parser.add_argument("--configs", default="raw,std,std+clip,std+cosine,std+lr3e-3")
    parser.add_argument("--placement", default="head")
    parser.add_argument("--epochs", type=int, default=100)
    parser.add_argument("--n-jobs", type=int, default=1)
    add_smoke_argument(parser)
    args = parse_args(parser, argv, seeds=1, configs="std,std+clip", epochs=2)
    X, y = silicone5_frames(6, image_size=(48, 64)) if args.smoke else silicone5_frames(15)
    configs = args.configs.split(",")
    print(f"silicone5 frames {X.shape}; placement {args.placement}; {args.epochs} epochs; {args.seeds} seeds")
    # seed-major order and one line per finished run, so a cut-short run still reports
    runs = []
    for run in Parallel(n_jobs=args.n_jobs, return_as="generator")(
        delayed(one_run)(X, y, c, args.placement, args.epochs, s) for s in range(args.seeds) for c in configs
    ):
        runs.append(run)
        print(f"run {run[0]:<14} seed {run[1]:>3} loss {run[2]:.3f} {run[3]:.0f} s", flush=True)
    print(f"{'config':<14}{'converged':>10}{'share':>8}{'median loss':>13}{'max loss':>10}{'s/fit':>7}")
    for c in configs:
        loss = np.array([r[2] for r in runs if r[0] == c])
        secs = np.array([r[3] for r in runs if r[0] == c])
        ok = sum(is_converged(v) for v in loss)
        print(f"{c:<14}{ok:>6}/{len(loss):<3}{ok / len(loss):>8.2f}{np.median(loss):>13.3f}{loss.max():>10.3f}"
              f"{secs.mean():>7.1f}")


if __name__ == "__main__":
    main()
