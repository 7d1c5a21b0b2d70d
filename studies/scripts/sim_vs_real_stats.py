"""Study: contact statistics of the ``everyday`` preset beside real recordings.

The statistics of the real-presses statistics of issue 20 (held-out GelSight
Mini presses), computed with the same functions on simulated presses and, with
``--data``, on the public real GelSight Wedge grasps of
``GelSight-lab/EstimateModulus`` (see ``studies/scripts/_estimate_modulus.py``):
per rank (simulated) or per object (real), median [25th, 75th percentile] of
the contact start and loading frames (peak - start) found by the default
:class:`~sklearn_hardness.preprocessing.ContactFrameSelector`, the peak of
:func:`~sklearn_hardness.preprocessing.contact_curve` (grey levels), its
pre-contact level (median over the frames before contact), their ratio, the
changed area at peak (share of pixels whose grey level differs from the first
frame by more than 3), the brightness share of the change at peak (over the
pixels where some channel changed by more than 6: mean absolute change of the
grey level over mean absolute change of a channel; near 0 when the change is
one of hue only, as under three evenly spaced coloured lights, and 1 when all
channels change alike) and the contact status counts. ``--manifest`` computes
the same per rank on recordings listed in a manifest CSV
(:func:`~sklearn_hardness.datasets.load_press_videos`: e.g. the held-out
GelSight Mini presses, which this repository never holds).

    python studies/scripts/sim_vs_real_stats.py [--data EXAMPLE_DATA] [--roi] [--seed 0]
        [--n-objects 42] [--variant NAME] [--param NAME=VALUE ...] [--by-kind]
        [--manifest MANIFEST] [--no-sim] [--features] [--out FILE] [--smoke]

Prints markdown tables, time and peak memory. ``--param`` overrides a preset
parameter (e.g. ``--param ambient_leak=0.5``) to try a calibration;
``--variant`` starts from a named variant of ``_sim_variants.py``.
``--by-kind`` adds, per rank, the median peak change of each shape and the
share of the within-rank variance of the log peak change that the kind of
object explains (between-kind over total): what sets the spread within a rank.
``--features`` adds, per group, the median [IQR] of the contact-profile
features of ``contact_profile_3`` (``log_peak_change``, ``log_loading_time``,
``log_contact_spread``) and of ``area_at_peak``, with the direction each takes
with hardness: Spearman's rho with the rank (simulated presses, a manifest with
a ``hardness`` column or labels soft / moderate / hard), or the within-family
pairs of the Wedge grasps in which it rises with hardness. A feature that
moves one way on the simulator and the other on real presses is one that a
pipeline trained on the simulator, or chosen on it, reads backwards.
``--out FILE`` also writes the printed text there after a provenance line.
"""

import argparse
import time
import warnings
from collections import Counter

import _harness  # noqa: F401 - puts the repository root on sys.path
import numpy as np
from _sim_variants import VARIANTS, variant_params

from harness.memory import peak_rss_mb, reset_peak
from harness.provenance import write_output
from harness.smoke import add_smoke_argument, parse_args, tiny_presses

#: Held-out real GelSight Mini presses (real_presses_stats.md), median per rank.
REAL_MINI = {
    "soft": dict(start=33.0, loading=8.5, peak=2.17, pre=0.79, ratio=2.74, area=0.10),
    "moderate": dict(start=29.0, loading=7.0, peak=2.92, pre=0.78, ratio=3.64, area=0.14),
    "hard": dict(start=27.0, loading=6.0, peak=3.71, pre=0.79, ratio=4.70, area=0.16),
}
COLUMNS = ("start", "loading", "peak", "pre", "ratio", "area", "bright")
HEADERS = ("contact start", "loading frames", "peak change", "pre-contact", "peak / pre", "changed area",
           "brightness share")


def press_stats(video, selection, i):
    """The statistics of press ``i`` of a ``ContactFrameSelector.select`` result."""
    curve = np.asarray(selection.curves[i])
    start, peak_frame = int(selection.contact_start[i]), int(selection.contact_peak[i])
    pre = float(np.median(curve[1:start])) if start > 1 else float("nan")
    peak = float(curve.max())
    diff = np.asarray(video[peak_frame], dtype=np.float32) - np.asarray(video[0], dtype=np.float32)
    if diff.ndim == 2:
        diff = diff[..., None]
    grey = np.abs(diff.mean(axis=-1))
    area = float(np.mean(grey > 3))
    changed = np.abs(diff).max(axis=-1) > 6
    bright = float(grey[changed].mean() / np.abs(diff[changed]).mean()) if changed.any() else float("nan")
    return dict(start=start, loading=peak_frame - start, peak=peak, pre=pre,
                ratio=peak / pre if pre > 0 else float("nan"), area=area, bright=bright,
                status=str(selection.status[i]), frames=len(curve))


def collect(videos):
    """Per-press statistics of a sequence of videos (one pass; no-contact warnings are counted, not printed)."""
    from sklearn_hardness.preprocessing import ContactFrameSelector

    sel = ContactFrameSelector()
    rows = []
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", UserWarning)
        for i in range(len(videos)):
            video = videos[i]
            rows.append(press_stats(video, sel.select([video]), 0))
    return rows


def _q(values):
    values = np.asarray([v for v in values if np.isfinite(v)], dtype=float)
    if not len(values):
        return "-"
    lo, med, hi = np.percentile(values, [25, 50, 75])
    return f"{med:.2f} [{lo:.2f}, {hi:.2f}]"


def table(groups, rows, title, reference=None):
    """Markdown table: one line per group (median [IQR] of each statistic, status counts)."""
    lines = [f"\n{title}\n", "| group | presses | " + " | ".join(HEADERS) + " | status |",
             "|---" * (len(HEADERS) + 3) + "|"]
    groups = np.asarray(groups)
    for g in dict.fromkeys(groups.tolist()):
        sub = [r for r, gg in zip(rows, groups) if gg == g]
        cells = [_q([r[c] for r in sub]) for c in COLUMNS]
        if reference is not None and g in reference:
            cells = [f"{cell} ({reference[g][c]:.2f})" if c in reference[g] else cell
                     for cell, c in zip(cells, COLUMNS)]
        status = ", ".join(f"{k} {v}" for k, v in sorted(Counter(r["status"] for r in sub).items()))
        lines.append(f"| {g} | {len(sub)} | " + " | ".join(cells) + f" | {status} |")
    return "\n".join(lines)


def kind_share(log_peak, kinds):
    """Share of the variance of ``log_peak`` between the groups ``kinds`` (one-way ANOVA's R^2)."""
    log_peak, kinds = np.asarray(log_peak, dtype=float), np.asarray(kinds)
    total = np.sum((log_peak - log_peak.mean()) ** 2)
    between = sum(np.sum(kinds == k) * (log_peak[kinds == k].mean() - log_peak.mean()) ** 2
                  for k in np.unique(kinds))
    return float(between / total) if total > 0 else float("nan")


def press_objects(data):
    """The object dict of each press of an ``everyday`` Bunch (its ``object_id`` is ``everyday-<index>-<kind>``)."""
    return [data.objects[int(str(o).split("-")[1])] for o in data.object_id]


def by_kind(names, rows, data):
    """Markdown table: per rank, the peak change's IQR, the kind's share of its spread, the median by shape."""
    objects = press_objects(data)
    kind = np.array([o["kind"] for o in objects])
    shape = np.array([o["shape"] for o in objects])
    peak = np.array([r["peak"] for r in rows])
    usable = np.isfinite(peak) & (peak > 0) & np.array([r["frames"] > 7 for r in rows])
    shapes = sorted(set(shape.tolist()))
    lines = ["\nPeak change by shape (median, presses) and the kind's share of the within-rank variance of the "
             "log peak change\n", "| rank | presses | peak change IQR | kind's share | " + " | ".join(shapes) + " |",
             "|---" * (len(shapes) + 4) + "|"]
    for g in dict.fromkeys(np.asarray(names).tolist()):
        m = usable & (np.asarray(names) == g)
        lo, hi = np.percentile(peak[m], [25, 75])
        cells = []
        for s_ in shapes:
            ms = m & (shape == s_)
            cells.append(f"{np.median(peak[ms]):.2f} ({ms.sum()})" if ms.any() else "-")
        lines.append(f"| {g} | {m.sum()} | {hi - lo:.2f} | {kind_share(np.log(peak[m]), kind[m]):.2f} | "
                     + " | ".join(cells) + " |")
    return "\n".join(lines)


#: ``--features``: the features of ``contact_profile_3`` and the share of changed pixels at the peak.
FEATURES = ("log_peak_change", "log_loading_time", "log_contact_spread", "area_at_peak")
#: Rank of the labels of a manifest without a ``hardness`` column, where they are these.
RANK_OF_LABEL = {"soft": 1.0, "moderate": 2.0, "hard": 3.0}


def contact_profile(videos):
    """The :data:`FEATURES` columns of ``ContactProfileFeatures`` for each video (rows in video order)."""
    from sklearn_hardness.features import ContactProfileFeatures

    return ContactProfileFeatures(features=FEATURES).fit_transform(videos)


def feature_table(groups, X, title, rank=None, object_names=None):
    """Markdown table: per group, the median [IQR] of each of :data:`FEATURES`, and their direction.

    ``rank`` (per press): the last row gives Spearman's rho of each feature
    with it. ``object_names`` (per press, the Wedge grasps' objects): the last
    row gives the within-family pairs in which the feature's mean over an
    object's presses is higher for the harder object
    (``_estimate_modulus.family_pairs`` with the feature as the score).
    """
    from scipy.stats import spearmanr

    groups = np.asarray(groups)
    lines = [f"\n{title}\n", "| group | presses | " + " | ".join(FEATURES) + " |",
             "|---" * (len(FEATURES) + 2) + "|"]
    for g in dict.fromkeys(groups.tolist()):
        m = groups == g
        lines.append(f"| {g} | {m.sum()} | " + " | ".join(_q(X[m, j]) for j in range(len(FEATURES))) + " |")
    if rank is not None:
        rho = [spearmanr(X[:, j], rank, nan_policy="omit")[0] for j in range(len(FEATURES))]
        lines.append("| Spearman with the rank | | " + " | ".join(f"{r:+.2f}" for r in rho) + " |")
    if object_names is not None:
        from _estimate_modulus import family_pairs

        cells = []
        for j in range(len(FEATURES)):
            fams = family_pairs(object_names, X[:, j]).values()
            cells.append(f"{sum(r for r, _, _ in fams)}/{sum(n for _, n, _ in fams)}")
        lines.append("| pairs in which it rises with hardness | | " + " | ".join(cells) + " |")
    return "\n".join(lines)


def manifest_rank(data):
    """Each press's rank: the manifest's ``hardness``, else soft / moderate / hard as 1 / 2 / 3, else None."""
    target = np.asarray(data.target)
    if data.hardness is not None:
        return np.asarray(data.hardness, dtype=float)[target]
    labels = [str(n).lower() for n in data.target_names]
    if all(n in RANK_OF_LABEL for n in labels):
        return np.array([RANK_OF_LABEL[n] for n in labels])[target]
    return None


def unreadable_videos(videos):
    """``"video i: why"`` for every video of ``videos`` that cannot be read (each read in full)."""
    found = []
    for i in range(len(videos)):
        try:
            videos[i]
        except (ValueError, TypeError, OSError) as exc:  # what read_video raises on a file it cannot read
            found.append(f"video {i}: {exc}")
    return found


def parse_param(text):
    """``NAME=VALUE`` or ``NAME=LO,HI`` -> (name, float or tuple); ``true`` / ``false`` -> bool."""
    name, value = text.split("=", 1)
    if value.lower() in ("true", "false"):
        return name, value.lower() == "true"
    values = [float(v) for v in value.split(",")]
    return name, (values[0] if len(values) == 1 else tuple(values))


def main(argv=None):
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--data", default=None, help="EstimateModulus example_data folder")
    parser.add_argument("--roi", action="store_true", help="crop the real grasps to the gel (GEL_ROI)")
    parser.add_argument("--seed", type=int, default=0)
    parser.add_argument("--n-objects", type=int, default=None)
    parser.add_argument("--param", action="append", default=[], type=parse_param,
                        help="override an everyday parameter, NAME=VALUE or NAME=LO,HI")
    parser.add_argument("--variant", default=None, choices=list(VARIANTS), help="a named variant (_sim_variants.py)")
    parser.add_argument("--by-kind", action="store_true",
                        help="per rank: median peak change by shape, and the share of the spread the kind explains")
    parser.add_argument("--no-sim", action="store_true")
    parser.add_argument("--manifest", default=None,
                        help="a manifest CSV of your recordings (load_press_videos): the same statistics per label")
    parser.add_argument("--features", action="store_true",
                        help="also: the features of contact_profile_3 and the changed area per group, and their "
                             "direction with hardness")
    parser.add_argument("--out", default=None, help="also write the printed text there, after a provenance line")
    add_smoke_argument(parser)
    args = parse_args(parser, argv)
    out = []

    def say(text=""):
        print(text, flush=True)
        out.append(text)

    if not args.no_sim:
        from sklearn_hardness.datasets import make_presses

        reset_peak()
        t0 = time.perf_counter()
        extra = dict(tiny_presses("everyday", args.smoke), **variant_params(args.variant, args.param))
        if args.n_objects:
            extra["n_objects"] = args.n_objects
        data = make_presses("everyday", random_state=args.seed, **extra)
        rows = collect(data.videos)
        names = np.asarray(data.target_names)[np.asarray(data.target)]
        say(table(names, rows, f"Simulated `everyday` (seed {args.seed}, {len(rows)} presses"
                    f"{', ' + str(extra) if extra else ''}); in brackets: real GelSight Mini median",
                    reference=REAL_MINI))
        if args.by_kind:
            say(by_kind(names, rows, data))
        if args.features:
            say(feature_table(names, contact_profile(data.videos), f"Contact-profile features, simulated `everyday` "
                              f"(seed {args.seed})", rank=np.asarray(data.hardness, dtype=float)[data.target]))
        say(f"\n{time.perf_counter() - t0:.1f} s, peak RSS {peak_rss_mb():.0f} MB")

    if args.data:
        from _estimate_modulus import GEL_ROI, load_estimate_modulus

        reset_peak()
        t0 = time.perf_counter()
        real = load_estimate_modulus(args.data, roi=GEL_ROI if args.roi else None)
        rows = collect(real.videos)
        view = f"{', gel ROI ' + str(GEL_ROI) if args.roi else ', full frame'}"
        say(table(real.object_name, rows,
                  f"Real GelSight Wedge grasps (EstimateModulus example_data{view}), per object"))
        if args.features:
            say(feature_table(real.object_name, contact_profile(real.videos), "Contact-profile features, real "
                              f"GelSight Wedge grasps{view}", object_names=real.object_name))
        say(f"\n{time.perf_counter() - t0:.1f} s, peak RSS {peak_rss_mb():.0f} MB")

    if args.manifest:
        from sklearn_hardness.datasets import load_press_videos

        reset_peak()
        t0 = time.perf_counter()
        data = load_press_videos(args.manifest)
        names = np.asarray(data.target_names)[np.asarray(data.target)]
        try:
            rows = collect(data.videos)
        except (ValueError, TypeError, OSError):
            unreadable = unreadable_videos(data.videos)
            if unreadable:  # every video that cannot be read, in one error
                raise SystemExit(f"error: {len(unreadable)} of {len(data.videos)} videos cannot be read:\n  "
                                 + "\n  ".join(unreadable)) from None
            raise
        say(table(names, rows, f"Recordings of {args.manifest} ({len(rows)} presses), per label"))
        if args.features:
            rank = manifest_rank(data)
            say(feature_table(names, contact_profile(data.videos), f"Contact-profile features, {args.manifest}",
                              rank=rank))
            if rank is None:
                say("(no hardness column and labels other than soft / moderate / hard: no direction with hardness)")
        say(f"\n{time.perf_counter() - t0:.1f} s, peak RSS {peak_rss_mb():.0f} MB")
    if args.out:
        write_output(args.out, "\n".join(out))


if __name__ == "__main__":
    main()
