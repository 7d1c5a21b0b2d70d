"""Study: the robot's force and position against the video, on simulated presses of new objects.

Two questions, on the ``everyday`` preset (``make_presses("everyday", random_state=S)``):

1. **Beside the video pipelines, on the same folds.** For each ``--seeds`` ``S``,
   ``evaluate_pipelines`` (``sklearn-hardness evaluate everyday --seed S
   --pipelines loading_compliance contact_profile``: object-disjoint, 5 folds)
   scores the one-number baseline (``peak_change``), the contact-profile
   pipeline and ``loading_compliance`` (``make_loading_compliance_pipeline``:
   the Hertz compliance from each press's force and the sensor's position),
   with each one's margin over the one number and what ``evaluate`` recommends.
2. **Across forces.** The pipeline is trained on seed ``S``'s presses (the
   preset's 1-6 N) and predicts a fresh draw of the preset's objects and
   presses pushed to ``--firm-force`` (default 15-25 N, as the real GelSight
   Wedge grasps of ``wedge_force.py`` reach; seed ``S + 1000``), by each
   input of ``LoadingCompliance`` alone: the Hertz compliance (position against
   force^(2/3), the default), the linear compliance (position against force),
   all four figures, and peak force alone. Then the same with the drive's
   *commanded* position (``mechanics[i]["position"]``, what an impedance
   controller's setpoint gives) instead of the sensor's, without and with
   ``drive_compliance`` set to the preset's.

    python studies/scripts/loading_compliance.py [--seeds 0 1 2 3 4] [--firm-force 15 25]
        [--n-jobs 2] [--out FILE] [--smoke]

Prints both tables (mean over seeds, and the sd of the first, beside each seed), the time and the peak
memory; ``--out`` writes the same text with a provenance line. The video
pipelines render every press (about 1 min per seed on 2 cores); the force
pipeline alone takes well under a second per seed.
"""

import argparse
import time
import warnings

import _harness  # noqa: F401 - puts the repository root on sys.path
import numpy as np

from harness.memory import peak_rss_mb, reset_peak
from harness.smoke import add_smoke_argument, parse_args, tiny_presses

#: Inputs compared across forces: label -> (``features``, position source, ``drive_compliance`` from the preset).
ACROSS = {
    "Hertz compliance (default)": (("hertz_compliance",), "sensor", False),
    "linear compliance": (("linear_compliance",), "sensor", False),
    "all four figures": ("all", "sensor", False),
    "peak force alone": (("peak_force",), "sensor", False),
    "Hertz, commanded position": (("hertz_compliance",), "commanded", False),
    "Hertz, commanded position, drive_compliance given": (("hertz_compliance",), "commanded", True),
}


def force_position(data, source):
    """Per press, (T, 2) force and position: the sensor's (``data.position``) or the commanded one."""
    if source == "sensor":
        return [np.column_stack([f, z]) for f, z in zip(data.force, data.position)]
    return [np.column_stack([f, m["position"]]) for f, m in zip(data.force, data.mechanics)]


def across_forces(seed, firm_force, **sim):
    """Balanced accuracy per ``ACROSS`` input: trained on seed's presses, tested on presses pushed harder."""
    from sklearn.metrics import balanced_accuracy_score

    from sklearn_hardness.datasets import make_presses
    from sklearn_hardness.models import make_loading_compliance_pipeline

    train = make_presses("everyday", random_state=seed, return_mechanics=True, **sim)
    firm = make_presses("everyday", random_state=seed + 1000, force_range=tuple(firm_force), return_mechanics=True,
                        **sim)
    out = {}
    for label, (features, source, give) in ACROSS.items():
        pipe = make_loading_compliance_pipeline(
            features=features, drive_compliance=train.params["drive_compliance"] if give else 0.0)
        pipe.fit(force_position(train, source), train.target)
        out[label] = balanced_accuracy_score(firm.target, pipe.predict(force_position(firm, source)))
    return out


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--seeds", type=int, nargs="+", default=[0, 1, 2, 3, 4])
    ap.add_argument("--firm-force", type=float, nargs=2, default=[15.0, 25.0], metavar=("LO", "HI"),
                    help="force range (N) of the presses pushed harder")
    ap.add_argument("--n-jobs", type=int, default=2)
    ap.add_argument("--out", default=None, help="write the text here, with a provenance line")
    add_smoke_argument(ap)
    args = parse_args(ap, argv, seeds=[0], n_jobs=1)
    sim = tiny_presses("everyday", args.smoke)  # --smoke: tiny sets
    from _evaluate_dataset import evaluate_dataset, table_rows

    from harness.provenance import report
    from sklearn_hardness.datasets import make_presses

    t0 = time.perf_counter()
    reset_peak()
    names = ("peak_change", "contact_profile", "loading_compliance")
    rows, across = [], []
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", UserWarning)  # the preset's cut-short presses: NaN figures, imputed
        for seed in args.seeds:
            result = evaluate_dataset(make_presses("everyday", random_state=seed, **sim),
                                      ["contact_profile", "loading_compliance"], random_state=seed,
                                      n_jobs=args.n_jobs, verbose=0)
            table = table_rows(result)
            rows.append((seed, table, result.recommended))
            across.append(across_forces(seed, args.firm_force, **sim))

    def cell(row):
        lo, hi = row["balanced_accuracy_ci"]
        return f"{row['balanced_accuracy']:.2f} [{lo:.2f}, {hi:.2f}]"

    def margin(row):
        lo, hi = row["vs_baseline_ci"]
        return f"{row['vs_baseline']:+.2f} [{lo:+.2f}, {hi:+.2f}]"

    lines = ["Simulated presses of new objects (everyday, object-disjoint 5 folds, evaluate_pipelines): balanced "
             "accuracy [corrected 95% CI]; loading_compliance reads force and the sensor's position, the others "
             "the video", "",
             "| seed | peak_change (one number) | contact_profile | loading_compliance | loading_compliance vs "
             "one number | recommended |", "|---|---|---|---|---|---|"]
    for seed, table, recommended in rows:
        lines.append(f"| {seed} | " + " | ".join(cell(table[n]) for n in names)
                     + f" | {margin(table['loading_compliance'])} | {recommended} |")
    scores = {n: np.array([t[n]["balanced_accuracy"] for _, t, _ in rows]) for n in names}
    sd = {n: scores[n].std(ddof=1) if len(rows) > 1 else 0 for n in names}
    lines.append("| mean (sd) | " + " | ".join(f"{scores[n].mean():.2f} ({sd[n]:.2f})" for n in names)
                 + f" | {scores['loading_compliance'].mean() - scores['peak_change'].mean():+.2f} | |")
    lo, hi = args.firm_force
    lines += ["", f"Across forces: trained on the seed's presses (1-6 N), tested on a fresh draw pushed to "
              f"{lo:g}-{hi:g} N (seed + 1000); balanced accuracy", "",
              "| input | " + " | ".join(f"seed {s}" for s in args.seeds) + " | mean |",
              "|---|" + "---|" * (len(args.seeds) + 1)]
    for label in ACROSS:
        vals = [a[label] for a in across]
        lines.append(f"| {label} | " + " | ".join(f"{v:.2f}" for v in vals) + f" | {np.mean(vals):.2f} |")
    lines += ["", f"{time.perf_counter() - t0:.0f} s, peak memory {peak_rss_mb():.0f} MB"]
    report("\n".join(lines), args.out)


if __name__ == "__main__":
    main()
