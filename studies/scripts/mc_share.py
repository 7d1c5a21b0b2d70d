"""Study: how much of the paper's Eq. 2 variance comes from the MC-dropout passes.

For each ConvLSTM ``dropout_placement`` and seed: train on 5 presses per object
of simulated ``silicone5`` (18x24 grey difference frames, 2 frames between
contact start and peak, 100 epochs, dropout 0.2, lr 1e-3, batch 8), draw 50
MC passes on held-out presses of one test object, and split Eq. 2 with
:func:`sklearn_hardness.active.variance_decomposition`. The MC share printed is
the pooled one, ``sum_i mc_i / sum_i total_i``. Beside it: held-out accuracy
on all objects (dropout off) and the final training loss (the paper's
convergence rule is loss <= 1).

    python studies/scripts/mc_share.py [--seeds 3] [--placements layers,channels,head] [--smoke]
"""

import argparse
import time

import _harness  # noqa: F401 - puts the repository root on sys.path
import numpy as np
import torch

from harness.smoke import add_smoke_argument, parse_args
from sklearn_hardness.active import variance_decomposition
from sklearn_hardness.datasets import make_presses
from sklearn_hardness.models import ConvLSTMClassifier
from sklearn_hardness.preprocessing import ContactFrameSelector


def silicone5_frames(n_per_class, random_state=0, image_size=(240, 320)):
    """Selected 18x24 grey difference frames (n, 4, 18, 24, 1) of simulated silicone5, and labels."""
    data = make_presses("silicone5", n_per_class=n_per_class, image_size=image_size, random_state=random_state)
    sel = ContactFrameSelector(n_between=2, frame_size=(18, 24), color="gray")
    return sel.fit_transform(data.videos), np.asarray(data.target)


def split(y, n_train, seed):
    """``n_train`` training presses per class; the rest held out."""
    rng = np.random.default_rng(seed)
    train = np.concatenate([rng.permutation(np.flatnonzero(y == c))[:n_train] for c in np.unique(y)])
    test = np.setdiff1d(np.arange(len(y)), train)
    return train, test


def main(argv=None):
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--seeds", type=int, default=3)
    parser.add_argument("--placements", default="layers,channels,head")
    parser.add_argument("--dropout", type=float, default=0.2)
    parser.add_argument("--epochs", type=int, default=100)
    parser.add_argument("--n-per-class", type=int, default=15, help="presses simulated per object")
    parser.add_argument("--threads", type=int, default=1)
    add_smoke_argument(parser)
    args = parse_args(parser, argv, seeds=1, placements="head", epochs=2, n_per_class=6)
    torch.set_num_threads(args.threads)
    X, y = silicone5_frames(args.n_per_class, image_size=(48, 64) if args.smoke else (240, 320))
    print(f"silicone5 frames {X.shape}, dropout {args.dropout}, {args.epochs} epochs, 50 MC passes")
    print(f"{'placement':<10}{'seed':>5}{'test obj':>9}{'MC share':>10}{'Eq.2 total':>12}{'acc':>7}"
          f"{'loss':>7}{'fit s':>7}{'MC/pp':>7}")
    summary = {}
    for placement in args.placements.split(","):
        for seed in range(args.seeds):
            train, test = split(y, 5, seed)
            obj = seed % len(np.unique(y))
            test_obj = test[y[test] == obj]
            net = ConvLSTMClassifier(dropout=args.dropout, dropout_placement=placement, max_epochs=args.epochs,
                                     random_state=seed)
            t0 = time.perf_counter()
            net.fit(X[train], y[train])
            fit_s = time.perf_counter() - t0
            t0 = time.perf_counter()
            samples = net.predict_proba_samples(X[test_obj], n_samples=50, random_state=seed)
            t_mc = time.perf_counter() - t0
            t0 = time.perf_counter()
            net.predict_proba(X[test_obj])
            t_pp = time.perf_counter() - t0
            dec = variance_decomposition(samples)
            share = float(dec["mc"].sum() / dec["total"].sum())
            acc = float(net.score(X[test], y[test]))
            summary.setdefault(placement, []).append((share, acc, net.final_train_loss_))
            print(f"{placement:<10}{seed:>5}{obj:>9}{share:>10.3f}{dec['total'].sum():>12.5f}{acc:>7.3f}"
                  f"{net.final_train_loss_:>7.3f}{fit_s:>7.1f}{t_mc / t_pp:>7.1f}")
    print("\nmean over seeds:")
    for placement, rows in summary.items():
        share, acc, loss = np.array(rows).T
        print(f"{placement:<10} MC share {share.mean():.3f} (min {share.min():.3f}), acc {acc.mean():.3f}, "
              f"converged {np.sum(loss <= 1)}/{len(loss)}")


if __name__ == "__main__":
    main()
