"""Study: does augmenting the ConvLSTM's training batches carry it to new objects, simulated and real?

The ConvLSTM of ``evaluate`` (``make_convlstm_pipeline(intensity_channels=True)``)
is trained with and without :class:`~sklearn_hardness.models.FrameAugmenter`
(random mirroring, gain, drift, noise of each training batch) and measured
two ways per seed:

- simulated, object-disjoint: ``evaluate_pipelines`` (5 folds by object) on
  ``make_presses("everyday", **params)`` (the preset, or e.g. ``--param
  kinds_by_rank=false --param conformity=0.1``: kinds shared by the ranks,
  the variant whose ranking of the pipelines is nearest the real one), with the
  one-number baseline beside;
- real (``--data``: the ``example_data`` folder of ``GelSight-lab/EstimateModulus``,
  kept locally, never committed): trained on all presses of the same
  simulated set, the share of the 9 within-family pairs of GelSight Wedge
  grasps ordered by softness (``sim_to_real.py``; ``--roi`` crops to the gel).

    python studies/scripts/augmentation.py [--seeds 0 1 2] [--param NAME=VALUE ...]
        [--augmenters none flip,gain=0.2 ...] [--data EXAMPLE_DATA [--roi]] [--cache DIR] [--n-jobs 2] [--out FILE]
        [--smoke]

An augmenter is ``none`` or comma-separated ``FrameAugmenter`` settings
(``flip``, ``noflip``, ``gain=G``, ``drift=D``, ``noise=N``; unnamed ones
are 0 and no flip). Prints one row per seed and augmenter, the means over
seeds, time and peak memory.
"""

import argparse
import time

import _harness  # noqa: F401 - puts the repository root on sys.path
import numpy as np
from _estimate_modulus import GEL_ROI, expected_rank, family_pairs, load_estimate_modulus
from _evaluate_dataset import evaluate_dataset, table_rows
from sim_confounds import recall_per_rank
from sim_to_real import simulated
from sim_vs_real_stats import parse_param

from harness.memory import peak_rss_mb
from harness.provenance import write_output
from harness.smoke import add_smoke_argument, parse_args, tiny_presses
from sklearn_hardness.datasets import make_presses
from sklearn_hardness.models import make_convlstm_pipeline


def parse_augmenter(spec):
    """``"flip,gain=0.2"`` -> FrameAugmenter settings (None for ``"none"``)."""
    if spec == "none":
        return None
    kw = {"flip": False, "gain": 0.0, "drift": 0.0, "noise": 0.0}
    for part in spec.split(","):
        if part == "flip":
            kw["flip"] = True
        elif part == "noflip":
            kw["flip"] = False
        else:
            key, value = part.split("=")
            if key not in ("gain", "drift", "noise"):
                raise argparse.ArgumentTypeError(f"unknown augmenter setting {key!r} in {spec!r}")
            kw[key] = float(value)
    return kw


def pipeline(spec, seed, **params):
    """The ConvLSTM of ``evaluate``; its factory's augmenter (log channels set) with ``spec``'s settings."""
    kw = parse_augmenter(spec)
    pipe = make_convlstm_pipeline(intensity_channels=True, augment=kw is not None, random_state=seed, **params)
    return pipe if kw is None else pipe.set_params(**{f"clf__augment__{k}": v for k, v in kw.items()})


def main(argv=None):
    out = []

    def say(text):
        out.append(text)
        print(text, flush=True)

    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--seeds", type=int, nargs="+", default=[0])
    parser.add_argument("--param", action="append", default=[], type=parse_param,
                        help="override an everyday parameter, NAME=VALUE or NAME=LO,HI")
    parser.add_argument("--augmenters", nargs="+", default=["none", "flip,gain=0.2"])
    parser.add_argument("--data", default=None, help="EstimateModulus example_data folder (real grasps)")
    parser.add_argument("--roi", action="store_true", help="crop the real grasps to the gel")
    parser.add_argument("--cache", default=None, help="folder to keep the rendered simulated sets in")
    parser.add_argument("--n-jobs", type=int, default=2)
    parser.add_argument("--out", default=None, help="also write the output here, after a provenance line")
    add_smoke_argument(parser)
    args = parse_args(parser, argv, n_jobs=1)
    for spec in args.augmenters:
        parse_augmenter(spec)
    variant = dict(args.param)
    sim = dict(tiny_presses("everyday", args.smoke), **variant)  # --smoke: a tiny set
    net = {"max_epochs": 1} if args.smoke else {}

    t0 = time.perf_counter()
    real = None
    if args.data:
        real = load_estimate_modulus(args.data, roi=GEL_ROI if args.roi else None, stride=2)
    say(f"everyday {variant or '(preset)'}; ConvLSTM with intensity channels; seeds {args.seeds}"
        + (f"; real Wedge grasps {'gel ROI' if args.roi else 'full frame'}" if real is not None else ""))
    header = "| seed | augmenter | sim balanced accuracy [95% CI] | recall per rank | baseline |"
    header += " real pairs right (of 9) |" if real is not None else ""
    say(header)
    rows = {spec: [] for spec in args.augmenters}
    for seed in args.seeds:
        data = make_presses("everyday", random_state=seed, **sim)
        named = {spec: pipeline(spec, seed, **net) for spec in args.augmenters}
        res = evaluate_dataset(data, named, n_jobs=args.n_jobs, random_state=seed, verbose=0)
        table = table_rows(res)
        base = table["peak_change"]["balanced_accuracy"]
        if real is not None:  # every 2nd pixel, as sim_to_real trains
            videos, target, hardness, _, _ = simulated(seed, cache=args.cache, **sim)
        for spec in args.augmenters:
            bal = table[spec]["balanced_accuracy"]
            lo, hi = table[spec]["balanced_accuracy_ci"]
            recall = recall_per_rank(res.confusion_matrix(spec))
            right = None
            if real is not None:
                est = pipeline(spec, seed, **net).fit(videos, target)
                proba = np.asarray(est.predict_proba(real.videos))
                fams = family_pairs(real.object_name, expected_rank(proba, est.classes_, hardness))
                right = sum(r for r, _, _ in fams.values())
            rows[spec].append((bal, base, right))
            line = f"| {seed} | {spec} | {bal:.2f} [{lo:.2f}, {hi:.2f}] | {recall} | {base:.2f} |"
            line += f" {right} |" if real is not None else ""
            say(line)
    say("\nmeans over seeds:")
    for spec, r in rows.items():
        a = np.asarray([x[0] for x in r])
        line = f"  {spec:<24} sim {a.mean():.3f} (s.d. {a.std():.3f})"
        if real is not None:
            line += f", real pairs right {np.mean([x[2] for x in r]):.2f} of 9 ({[x[2] for x in r]})"
        say(line)
    say(f"baseline sim {np.mean([x[1] for x in rows[args.augmenters[0]]]):.3f}")
    say(f"\n{time.perf_counter() - t0:.0f} s, peak RSS of the main process {peak_rss_mb():.0f} MB")
    if args.out:
        write_output(args.out, "\n".join(out))


if __name__ == "__main__":
    main()
