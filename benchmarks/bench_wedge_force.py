"""Benchmark: what a robot's force and gripper width tell of softness, on the real GelSight Wedge grasps.

The simulator says that force with the sensor's approach into the object tells
hardness almost outright (balanced accuracy 0.92-0.96 on ``everyday``, where the
video's contact-profile features reach about 0.66:
``benchmarks/bench_contact_profile_features.py``). The real grasps of
``GelSight-lab/EstimateModulus`` record both: the gripper's force (N) and width
(m) per frame (``--data``: its ``example_data`` folder, kept locally, never
committed; ``benchmarks/_estimate_modulus.py``). This checks the simulator's claim
on them, with no training at all: per grasp, the loading phase runs from the
first frame whose force exceeds ``--onset`` times the grasp's peak force to the
peak, and

- the stiffness is the least-squares slope of force against the gripper's
  closing (its width at the onset minus its width) over that phase, N/mm;
- the secant is the peak force over the closing at the peak, N/mm;
- beside them, each of its two parts alone: the peak force (the gripper stops
  near a set force, so it says little) and the closing at the peak (the softer
  object closes further, at the same force).

An object's figure is the mean over its grasps. Reported per object family
(balls: golf ball > purple > green > orange; foam bricks: blue > red > yellow;
9 within-family pairs), the pairs ordered right (the harder object's figure
strictly higher), as ``bench_sim_to_real.py`` reports the video pipelines trained
on simulated presses (best: 8 of 9).

    python benchmarks/bench_wedge_force.py --data .../example_data [--onset 0.05 0.1 0.2] [--out FILE]

Prints the table per object, the pairs right per onset (the closing alone at
the table's onset) and the time;
``--out`` writes the same text with a provenance line.
"""

import argparse
import time

import numpy as np

from _estimate_modulus import FAMILIES, family_pairs, load_grasp_forces
from _output import report


def grasp_figures(force, width, onset):
    """(stiffness, secant, peak force, closing at peak in mm) of one grasp; NaN stiffness under 3 loading frames."""
    peak = int(np.argmax(force))
    start = int(np.argmax(force > onset * force[peak]))
    closing = (width[start] - width[start:peak + 1]) * 1000.0  # mm
    stiffness = (float(np.polyfit(closing, force[start:peak + 1], 1)[0])
                 if peak - start >= 2 and np.ptp(closing) > 0 else np.nan)
    secant = force[peak] / closing[-1] if closing[-1] > 0 else np.nan
    return stiffness, secant, float(force[peak]), float(closing[-1])


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--data", required=True, help="EstimateModulus example_data folder")
    ap.add_argument("--onset", type=float, nargs="+", default=[0.05, 0.1, 0.2],
                    help="loading starts where the force first exceeds this share of its peak")
    ap.add_argument("--out", default=None, help="write the text here, with a provenance line")
    args = ap.parse_args(argv)
    t0 = time.perf_counter()
    grasps = load_grasp_forces(args.data)
    names = np.array([g[0] for g in grasps])
    members = [m for fam in FAMILIES.values() for m in fam]
    lines = [f"real GelSight Wedge grasps: {len(grasps)} of {len(set(names))} objects; force and gripper width "
             "per frame, no training", ""]
    figures = {}
    for onset in args.onset:
        figures[onset] = np.array([grasp_figures(f, w, onset) for _, f, w in grasps])
    main_onset = 0.1 if 0.1 in figures else args.onset[0]
    fig = figures[main_onset]
    lines += [f"Per object (onset {main_onset:g} of the peak force; mean [min, max] over its grasps)", "",
              "| object | grasps | peak force N | closing at peak mm | stiffness N/mm | secant N/mm |",
              "|---|---|---|---|---|---|"]
    for m in members:
        r = fig[names == m]

        def cell(col, digits=1):
            return f"{np.nanmean(r[:, col]):.{digits}f} [{np.nanmin(r[:, col]):.{digits}f}, {np.nanmax(r[:, col]):.{digits}f}]"

        lines.append(f"| {m} | {len(r)} | {cell(2)} | {cell(3)} | {cell(0, 2)} | {cell(1, 2)} |")
    lines += ["", "Within-family pairs ordered right (of 9: balls 6, foam bricks 3)", "",
              "| figure (onset) | balls | foam bricks | all |", "|---|---|---|---|"]

    def pairs_row(label, scores):
        fams = family_pairs(names, scores)
        right = sum(r for r, _, _ in fams.values())
        return f"| {label} | {fams['balls'][0]}/6 | {fams['foam bricks'][0]}/3 | **{right}/9** |"

    for col, label in ((0, "stiffness"), (1, "secant")):
        lines += [pairs_row(f"{label} ({onset:g})", fig[:, col]) for onset, fig in figures.items()]
    base = figures[main_onset]
    lines += [pairs_row("peak force alone", base[:, 2]),
              pairs_row(f"closing at peak alone ({main_onset:g}; less closing: harder)", -base[:, 3])]
    lines += ["", f"{time.perf_counter() - t0:.2f} s"]
    report("\n".join(lines), args.out)


if __name__ == "__main__":
    main()
