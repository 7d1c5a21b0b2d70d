"""Study: the ready-made pipelines' inputs against the paper's, in the paper's own setting.

``make_ofnn_pipeline`` summarises the optical flow by magnitude quantiles
(``OpticalFlowFeatures(output="magnitude_quantiles")``) and
``make_convlstm_pipeline`` appends intensity channels (``IntensityChannels``)
because they carry over to unseen objects (``sklearn-hardness evaluate
everyday``). This checks what they do where the paper trains and tests:
presses of the *same* objects, 5 training presses per object, all other
presses for testing, several seeds. Each preset's frames are selected once
(the pipelines' own selectors); each seed draws its own training presses and
initial weights. Prints test accuracy (mean and std over seeds), time for all
seeds and peak memory side by side.

    python studies/scripts/pipeline_inputs.py [--presets silicone5 shore9] [--seeds 5] [--out FILE]
    python studies/scripts/pipeline_inputs.py --smoke   # tiny sets, 2 training presses per object, one epoch

``--out FILE`` also writes the printed text there after a provenance header.
"""

import argparse
import sys
import time
import warnings
from pathlib import Path

import numpy as np
from sklearn.metrics import accuracy_score

sys.path.insert(0, str(Path(__file__).resolve().parent))
import _harness  # noqa: E402,F401 - puts the repository root on sys.path

from harness.memory import peak_rss_mb, reset_peak  # noqa: E402
from harness.provenance import write_output  # noqa: E402
from harness.smoke import add_smoke_argument, parse_args, tiny_presses  # noqa: E402
from sklearn_hardness.datasets import make_presses  # noqa: E402
from sklearn_hardness.features import OpticalFlowFeatures  # noqa: E402
from sklearn_hardness.models import (  # noqa: E402
    ConvLSTMClassifier,
    OFNNClassifier,
    make_convlstm_pipeline,
    make_ofnn_pipeline,
)


def _train_test(y, n_train, seed):
    rng = np.random.default_rng(seed)
    train = np.concatenate([rng.choice(np.flatnonzero(y == k), n_train, replace=False) for k in np.unique(y)])
    return train, np.setdiff1d(np.arange(len(y)), train)


def _variants(videos, max_epochs=None):
    """(name, input X, classifier factory) of each compared variant (``max_epochs``: the nets', None: theirs)."""
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        raw = make_ofnn_pipeline().named_steps["frames"].set_params(n_jobs=2).fit_transform(videos)
        frames = make_convlstm_pipeline().named_steps["frames"].set_params(n_jobs=2).fit_transform(videos)
        tracks = OpticalFlowFeatures(output="tracks", n_jobs=2).fit_transform(raw)
        quantiles = OpticalFlowFeatures(output="magnitude_quantiles", n_jobs=2).fit_transform(raw)
    convlstm = make_convlstm_pipeline(intensity_channels=True)  # its FrameScaler and IntensityChannels steps
    scaled = convlstm.named_steps["scale"].fit_transform(frames)
    channels = convlstm.named_steps["intensity"].fit_transform(scaled)
    epochs = {} if max_epochs is None else {"max_epochs": max_epochs}
    ofnn_epochs = {"max_epochs": 50, **epochs}
    return [
        ("ofnn, tracks (paper)", tracks, lambda s: OFNNClassifier(**ofnn_epochs, random_state=s)),
        ("ofnn, magnitude quantiles", quantiles, lambda s: OFNNClassifier(**ofnn_epochs, random_state=s)),
        ("convlstm 12x16, frames (paper)", scaled, lambda s: ConvLSTMClassifier(**epochs, random_state=s)),
        ("convlstm 12x16, + intensity", channels, lambda s: ConvLSTMClassifier(**epochs, random_state=s)),
    ]


def main(argv=None):
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--presets", nargs="+", default=["silicone5", "shore9"])
    parser.add_argument("--seeds", type=int, default=5)
    parser.add_argument("--n-train", type=int, default=5, help="training presses per object")
    parser.add_argument("--out", default=None, help="also write the printed text there, after a provenance header")
    add_smoke_argument(parser)
    args = parse_args(parser, argv, seeds=1, n_train=2)
    printed = []

    def say(line):
        print(line, flush=True)
        printed.append(line)

    for preset in args.presets:
        data = make_presses(preset, random_state=0, **tiny_presses(preset, args.smoke))
        y = np.asarray(data.target)
        t0 = time.perf_counter()
        variants = _variants(data.videos, 1 if args.smoke else None)
        say(f"\n{preset}: {len(y)} presses of {len(np.unique(y))} objects, {args.n_train} training presses "
              f"per object, the rest for testing, {args.seeds} seeds (frames selected in "
              f"{time.perf_counter() - t0:.0f} s)")
        say(f"{'input':<34}{'accuracy':>18}{'time (s)':>10}{'peak RSS (MB)':>15}")
        for name, X, make in variants:
            reset_peak()
            t0 = time.perf_counter()
            acc = []
            for seed in range(args.seeds):
                train, test = _train_test(y, args.n_train, seed)
                clf = make(seed).fit(X[train], y[train])
                acc.append(accuracy_score(y[test], clf.predict(X[test])))
            dt = time.perf_counter() - t0
            text = f"{100 * np.mean(acc):.1f}% +- {100 * np.std(acc):.1f}%"
            say(f"{name:<34}{text:>18}{dt:>10.1f}{peak_rss_mb():>15.0f}")
    if args.out:
        write_output(args.out, "\n".join(printed).lstrip("\n"))


if __name__ == "__main__":
    main()
