"""Does training the ConvLSTM with augmentation help it on real presses of new objects?

``convlstm_intensity`` (the ConvLSTM with intensity channels, evaluate's net for
unseen objects) with ``augment=True``: every training batch is mirrored, its gain
and drift changed and noise added at random (:class:`~sklearn_hardness.models.FrameAugmenter`),
the nuisances of hand presses on a real sensor. Object-disjoint folds as
``sklearn-hardness evaluate DATA --pipelines convlstm_intensity --n-repeats 5`` (fold
seed 0, net seed 0): the plain net's figures on the same folds are in
``studies/outputs/real_development_objects.txt``.

    python studies/scripts/real_net_augmentation.py --data DATA [--n-repeats 5] [--n-jobs 2] [--out FILE] [--smoke]

``DATA``: a copy of the public PhysiCLeAR set (its ``dataset/`` and
``utils/constants.py``), read with the development objects alone
(``_physiclear.py``), or a manifest of their presses (or its folder).
"""

import argparse
import os
import sys
import time

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))

import _harness  # noqa: E402,F401 - puts the repository root on sys.path
from _evaluate_dataset import evaluate_dataset  # noqa: E402
from _physiclear import load_development  # noqa: E402

from harness.provenance import report  # noqa: E402
from harness.smoke import add_smoke_argument, parse_args  # noqa: E402
from sklearn_hardness.models import make_named_pipeline  # noqa: E402


def main(argv=None):
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--data", required=True, help="copy of the public PhysiCLeAR set (dataset/, utils/constants.py)"
                        " or a manifest.csv of the development objects' presses (or its folder)")
    parser.add_argument("--n-repeats", type=int, default=5)
    parser.add_argument("--n-jobs", type=int, default=2)
    parser.add_argument("--out", help="also write the table here, under a header")
    add_smoke_argument(parser)
    args = parse_args(parser, argv, n_repeats=1, n_jobs=1)
    start = time.perf_counter()
    net = {"max_epochs": 1} if args.smoke else {}  # --smoke: one epoch
    pipelines = {"convlstm_intensity_augment": make_named_pipeline("convlstm_intensity", augment=True,
                                                                   random_state=0, **net)}
    result = evaluate_dataset(load_development(args.data), pipelines, cv=5, n_repeats=args.n_repeats,
                              n_jobs=args.n_jobs, random_state=0, verbose=1)
    text = f"{result}\ntotal {time.perf_counter() - start:.0f} s"
    report(text, args.out)


if __name__ == "__main__":
    main()
