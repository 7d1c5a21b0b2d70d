"""Study: ContactFrameSelector on weak compressed presses, no-contact videos and silicone5.

Four parts, each printing what it measured:

1. weak contacts in compressed marker-less videos (``tests/_weak_contact.py``:
   240x320, 126 frames, a real ``mp4v`` round trip, contacts calibrated to
   real GelSight Mini presses of everyday objects: a mean-curve rise of a
   fraction of a grey level to ~2 levels over a codec floor of ~1 level):
   contact found, |start error|, |peak error|, by contact kind and by
   peak-to-pre-contact ratio of the contact curve;
2. the same videos without contact: the false-contact rate;
3. the weak presses truncated to 3-7 frames: the outcomes;
4. simulated ``silicone5`` presses: |start error| and |peak error| against
   the simulator's mechanics (start: first frame with approach > 0; peak:
   frame of maximum approach), and time per video.

    python studies/scripts/contact_selection.py [--n-weak 150] [--n-none 50] [--n-silicone 20] [--smoke]
"""

import argparse
import sys
import time
import warnings
from collections import Counter
from pathlib import Path

import _harness  # noqa: F401 - puts the repository root on sys.path
import numpy as np
from joblib import Parallel, delayed

sys.path.insert(0, str(Path(__file__).resolve().parents[2] / "tests"))
from _weak_contact import KINDS, weak_press  # noqa: E402

from harness.smoke import add_smoke_argument, parse_args  # noqa: E402
from sklearn_hardness.datasets import make_presses  # noqa: E402
from sklearn_hardness.preprocessing import ContactFrameSelector, contact_curve  # noqa: E402


def _select(videos):
    """Selection on ``videos`` with warnings silenced, and the seconds per video."""
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        t0 = time.perf_counter()
        sel = ContactFrameSelector().select(videos)
        per_video = (time.perf_counter() - t0) / len(videos)
    if "status" not in sel:  # releases before the weak-contact test: for A/B runs
        sel.status = np.where(sel.contact_found, "contact", "no contact")
    return sel, per_video


def _weak(i, contact=True):
    """Make one press, select on it and on its truncation; keep only the numbers (bounds RAM)."""
    rng = np.random.default_rng(i)
    kind = KINDS[i % len(KINDS)]
    # fabric spreads its change over the pad and the codec smooths it: it needs more
    strength = rng.uniform(1.5, 3.5) if kind == "fabric" else rng.uniform(0.4, 1.5)
    video, start, peak = weak_press(kind, strength=strength, contact=contact, seed=(1000 if contact else 5000) + i)
    sel, seconds = _select([video])
    short, _ = _select([video[: rng.integers(3, 8)]])
    ratio = np.nan
    if contact:
        curve = contact_curve(video)
        ratio = curve[peak : peak + 10].mean() / curve[5:start].mean()
    return dict(kind=kind, start=start, peak=peak, ratio=ratio, found=sel.contact_found[0],
                status=str(sel.status[0]), found_start=sel.contact_start[0], found_peak=sel.contact_peak[0],
                seconds=seconds, short_status=str(short.status[0]))


def _errors(found, err):
    """Mean absolute error over the videos where contact was found."""
    return f"{np.abs(err[found]).mean():6.2f}" if found.any() else "   nan"


def main(argv=None):
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--n-weak", type=int, default=150)
    parser.add_argument("--n-none", type=int, default=50)
    parser.add_argument("--n-silicone", type=int, default=20, help="presses per silicone5 object")
    parser.add_argument("--n-jobs", type=int, default=2, help="processes making the videos")
    add_smoke_argument(parser)
    args = parse_args(parser, argv, n_weak=3, n_none=1, n_silicone=1, n_jobs=1)

    t0 = time.perf_counter()
    weak = Parallel(n_jobs=args.n_jobs)(delayed(_weak)(i) for i in range(args.n_weak))
    none = Parallel(n_jobs=args.n_jobs)(delayed(_weak)(i, False) for i in range(args.n_none))
    print(f"made and selected on {len(weak)} weak and {len(none)} no-contact 126x240x320 mp4v "
          f"videos in {time.perf_counter() - t0:.0f} s")

    def column(rows, key):
        return np.array([r[key] for r in rows])

    kinds, ratio, found = column(weak, "kind"), column(weak, "ratio"), column(weak, "found")
    start_err = column(weak, "found_start") - column(weak, "start")
    peak_err = column(weak, "found_peak") - column(weak, "peak")
    print(f"\n1. weak compressed presses: contact found in {found.sum()} of {len(found)} "
          f"({100 * found.mean():.1f}%), {1000 * column(weak, 'seconds').mean():.1f} ms/video")
    print(f"   contact-curve peak / pre-contact level: median {np.median(ratio):.2f}, "
          f"range {ratio.min():.2f}-{ratio.max():.2f}")
    print(f"   {'group':<22}{'n':>5}{'found %':>9}{'|start err|':>13}{'|peak err|':>12}")
    groups = [(f"kind={k}", kinds == k) for k in KINDS]
    groups += [("ratio < 1.5", ratio < 1.5), ("1.5 <= ratio < 2", (ratio >= 1.5) & (ratio < 2)),
               ("ratio >= 2", ratio >= 2)]
    for label, mask in groups:
        if mask.any():
            f = found & mask
            print(f"   {label:<22}{mask.sum():>5}{100 * found[mask].mean():>9.1f}"
                  f"{_errors(f, start_err):>13}{_errors(f, peak_err):>12}")
    print(f"   outcomes: {dict(Counter(column(weak, 'status').tolist()))}")

    found = column(none, "found")
    print(f"\n2. no-contact compressed videos: reported as contact in {found.sum()} of {len(none)} "
          f"(false-contact rate {100 * found.mean():.1f}%), {1000 * column(none, 'seconds').mean():.1f} "
          f"ms/video; outcomes {dict(Counter(column(none, 'status').tolist()))}")
    print(f"\n3. the weak presses truncated to 3-7 frames: outcomes "
          f"{dict(Counter(column(weak, 'short_status').tolist()))}")

    size = (48, 64) if args.smoke else (240, 320)
    data = make_presses("silicone5", n_per_class=args.n_silicone, image_size=size, return_mechanics=True,
                        random_state=0)
    true_start = np.array([int(np.flatnonzero(m["approach"] > 0)[0]) for m in data.mechanics])
    true_peak = np.array([int(np.argmax(m["approach"])) for m in data.mechanics])
    videos = data.videos
    sel, per_video = _select(videos)
    f = sel.contact_found
    print(f"\n4. silicone5 ({len(videos)} presses, {size[0]}x{size[1]}): contact found in {f.sum()}; "
          f"mean |start err| {_errors(f, sel.contact_start - true_start).strip()} frames, "
          f"|peak err| {_errors(f, sel.contact_peak - true_peak).strip()}; {1000 * per_video:.1f} ms/video")


if __name__ == "__main__":
    main()
