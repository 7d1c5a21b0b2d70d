"""Study: what a robot's force and gripper width tell of softness, on the real GelSight Wedge grasps.

The simulator says that force with the sensor's approach into the object tells
hardness almost outright (balanced accuracy 0.92-0.96 on ``everyday``, where the
video's contact-profile features reach about 0.66:
``studies/scripts/contact_profile_features.py``). The real grasps of
``GelSight-lab/EstimateModulus`` record both: the gripper's force (N) and width
(m) per frame (``--data``: its ``example_data`` folder, kept locally, never
committed; ``studies/scripts/_estimate_modulus.py``). This checks the simulator's claim
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
strictly higher), as ``sim_to_real.py`` reports the video pipelines trained
on simulated presses (best: 8 of 9).

Then the library's pipeline for such data, trained only on the simulator:
``make_loading_compliance_pipeline`` (``LoadingCompliance``: the Hertz
compliance, position against force^(2/3) over the loading phase) is fitted on
the force and sensor position of ``make_presses("everyday", random_state=s)``
for each ``--sim-seeds`` ``s`` (videos unused), and predicts every grasp from
its force and closing (width at the first frame minus width, mm). Reported per
input: the object-disjoint balanced accuracy on the preset (5 folds, its 42
objects; the single inputs are scalars, peak force alone the simplest), the
pairs ordered right by the expected hardness rank (hard 3, moderate 2, soft 1)
per seed, and the expected rank of every object. The preset makes 60% of its
presses by hand, whose position only motion capture would record; the default
input is also scored on its robot presses alone.

    python studies/scripts/wedge_force.py --data EXAMPLE_DATA [--onset 0.05 0.1 0.2]
        [--sim-seeds 0 1 2 3 4] [--out FILE] [--smoke]

Prints the table per object, the pairs right per onset (the closing alone at
the table's onset), the pipeline trained on the simulator, and the time;
``--out`` writes the same text with a provenance line.
"""

import argparse
import time
import warnings

import _harness  # noqa: F401 - puts the repository root on sys.path
import numpy as np
from _estimate_modulus import FAMILIES, expected_rank, family_pairs, load_grasp_forces

from harness.provenance import report
from harness.smoke import add_smoke_argument, parse_args, tiny_presses


def grasp_figures(force, width, onset):
    """(stiffness, secant, peak force, closing at peak in mm) of one grasp; NaN stiffness under 3 loading frames."""
    peak = int(np.argmax(force))
    start = int(np.argmax(force > onset * force[peak]))
    closing = (width[start] - width[start:peak + 1]) * 1000.0  # mm
    stiffness = (float(np.polyfit(closing, force[start:peak + 1], 1)[0])
                 if peak - start >= 2 and np.ptp(closing) > 0 else np.nan)
    secant = force[peak] / closing[-1] if closing[-1] > 0 else np.nan
    return stiffness, secant, float(force[peak]), float(closing[-1])


#: Inputs of the pipeline trained on the simulator (``LoadingCompliance`` features); the first is its default.
SIM_INPUTS = {
    "Hertz compliance (default)": ("hertz_compliance",),
    "linear compliance": ("linear_compliance",),
    "all four figures": "all",
    "travel alone": ("travel",),
    "peak force alone": ("peak_force",),
}

#: Hardness rank of each ``everyday`` class name, for the expected rank.
RANK = {"soft": 1.0, "moderate": 2.0, "hard": 3.0}


def simulated_force_position(seed, **sim):
    """(X, target, object_id, target_names, hand) of ``make_presses("everyday")``: force and sensor position."""
    from sklearn_hardness.datasets import make_presses

    data = make_presses("everyday", random_state=seed, **sim)  # videos are lazy: never rendered here
    X = [np.column_stack([f, z]) for f, z in zip(data.force, data.position)]
    return (X, np.asarray(data.target), np.asarray(data.object_id), np.asarray(data.target_names),
            np.asarray(data.press_params["hand"], dtype=bool))


def sim_trained(grasps, names, seeds, **sim):
    """Markdown lines: the pipeline trained on each simulated seed, scored there and on the grasps."""
    from sklearn.model_selection import GroupKFold, cross_val_score

    from sklearn_hardness.features import LoadingCompliance
    from sklearn_hardness.models import make_loading_compliance_pipeline

    X_real = [np.column_stack([f, (w[0] - w) * 1000.0]) for _, f, w in grasps]  # closing, mm
    acc = {k: [] for k in SIM_INPUTS}
    robot_acc = []
    right = {k: [] for k in SIM_INPUTS}
    ranks = {k: [] for k in SIM_INPUTS}
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", UserWarning)  # the preset's cut-short videos: NaN, imputed
        for seed in seeds:
            X, y, groups, target_names, hand = simulated_force_position(seed, **sim)
            hardness = np.array([RANK[n] for n in target_names])
            robot = np.flatnonzero(~hand)  # a hand's position is recorded only by motion capture
            robot_acc.append(cross_val_score(make_loading_compliance_pipeline(), [X[i] for i in robot], y[robot],
                                             groups=groups[robot], cv=GroupKFold(5),
                                             scoring="balanced_accuracy").mean())
            for label, features in SIM_INPUTS.items():
                pipe = make_loading_compliance_pipeline(features=features)
                acc[label].append(cross_val_score(pipe, X, y, groups=groups, cv=GroupKFold(5),
                                                  scoring="balanced_accuracy").mean())
                pipe.fit(X, y)
                scores = expected_rank(pipe.predict_proba(X_real), pipe.classes_, hardness)
                fams = family_pairs(names, scores)
                right[label].append(sum(r for r, _, _ in fams.values()))
                ranks[label].append({m: mean for _, _, means in fams.values() for m, mean in means.items()})
    seeds_txt = " ".join(map(str, seeds))
    lines = ["", f"Trained on the simulator only: make_loading_compliance_pipeline on make_presses(\"everyday\") "
             f"force and sensor position, seeds {seeds_txt}; grasps given as force and closing", "",
             "| input | balanced accuracy on the preset, new objects (mean [min, max]) "
             "| pairs ordered right on the grasps, per seed | seeds with 9/9 |", "|---|---|---|---|"]
    for label in SIM_INPUTS:
        a = np.array(acc[label])
        lines.append(f"| {label} | {a.mean():.2f} [{a.min():.2f}, {a.max():.2f}] "
                     f"| {', '.join(f'{r}/9' for r in right[label])} "
                     f"| {sum(r == 9 for r in right[label])} of {len(seeds)} |")
    a = np.array(robot_acc)
    lines.append(f"| {next(iter(SIM_INPUTS))}, the preset's robot presses only | {a.mean():.2f} "
                 f"[{a.min():.2f}, {a.max():.2f}] | | |")
    members = [m for fam in FAMILIES.values() for m in fam]
    default = next(iter(SIM_INPUTS))
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", UserWarning)
        real_c = LoadingCompliance(features=["hertz_compliance"]).fit_transform(X_real)[:, 0]
        sim_c = LoadingCompliance(features=["hertz_compliance"]).fit_transform(X)[:, 0]
    lines += ["", f"Per object: its grasps' Hertz compliance (mm/N^(2/3); mean [min, max]) and expected hardness "
              f"rank ({default}; hard 3, soft 1; mean [min, max] over the seeds)", "",
              "| object | Hertz compliance | expected rank |", "|---|---|---|"]
    for m in members:
        r = np.array([per_seed[m] for per_seed in ranks[default]])
        c = real_c[names == m]
        lines.append(f"| {m} | {np.nanmean(c):.2f} [{np.nanmin(c):.2f}, {np.nanmax(c):.2f}] "
                     f"| {r.mean():.4f} [{r.min():.4f}, {r.max():.4f}] |")
    lines += ["", f"Simulated presses (seed {seeds[-1]}), Hertz compliance per class, median [min, max]: " + "; ".join(
        f"{n} {np.nanmedian(sim_c[y == k]):.2f} [{np.nanmin(sim_c[y == k]):.2f}, {np.nanmax(sim_c[y == k]):.2f}]"
        for k, n in enumerate(target_names))]
    return lines


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--data", required=True, help="EstimateModulus example_data folder")
    ap.add_argument("--onset", type=float, nargs="+", default=[0.05, 0.1, 0.2],
                    help="loading starts where the force first exceeds this share of its peak")
    ap.add_argument("--sim-seeds", type=int, nargs="+", default=[0, 1, 2, 3, 4],
                    help="seeds of the simulated presses the pipeline is trained on")
    ap.add_argument("--out", default=None, help="write the text here, with a provenance line")
    add_smoke_argument(ap)
    args = parse_args(ap, argv, sim_seeds=[0])
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
            lo, mid, hi = np.nanmin(r[:, col]), np.nanmean(r[:, col]), np.nanmax(r[:, col])
            return f"{mid:.{digits}f} [{lo:.{digits}f}, {hi:.{digits}f}]"

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
    lines += sim_trained(grasps, names, args.sim_seeds, **tiny_presses("everyday", args.smoke))
    lines += ["", f"{time.perf_counter() - t0:.2f} s"]
    report("\n".join(lines), args.out)


if __name__ == "__main__":
    main()
