"""Study: what the simulated ``everyday`` objects let a pipeline learn besides hardness.

On the ``everyday`` preset the ConvLSTM ranks first of the pipelines
(object-disjoint), on the real GelSight Mini presses of unseen objects kept
aside it scores below the one-number peak-change baseline
(``real_presses_stats.md``). The preset gives each hardness rank its own kinds
of object (foams and fabrics soft, pen tips and screws hard) and its own
texture depth, so the shape and texture of a contact tell its rank; among 74
real objects they do not. This benchmark runs ``evaluate_pipelines`` (the
default pipelines and the baseline, object-disjoint 5-fold) on variants of
the preset:

- ``preset``: the preset as it is;
- ``kind_disjoint``: the same presses, folds grouped by kind of object (a test
  kind is never seen in training, as a new real object's look);
- ``kinds_shared``: ``kinds_by_rank=False``: every rank draws from all kinds;
- ``kinds_shared_even_texture``: that, and one texture depth for every rank;
- ``kinds_shared_conforming``: kinds shared, and a compliant object's imprint
  smoothed with its share of the deformation (``conformity=0.1``);
- ``kinds_shared_calibrated``: kinds shared, with press force, press speed,
  conformity and the soft rank's compliance fitted to the contact statistics
  of the real held-out presses (``sim_vs_real_stats.py``, seeds 0-2):
  ``force_range=(0.8, 4.8)``, speeds x 0.6, ``conformity=0.05``,
  ``soft_compliance_range=(0.4, 1.6)``;
- ``kinds_shared_gel_spread``: kinds shared and conforming (``conformity=0.1``),
  with the gel's own spreading of every imprint (``gel_spread=0.4`` mm) and
  firmer soft objects (``soft_compliance_range=(0.7, 2.8)``), fitted to the
  per-rank median and interquartile range of the real peak change.

The variants are defined in ``_sim_variants.py``; the other simulator
benchmarks take the same names (``--variant``).

    python studies/scripts/sim_confounds.py [--variants ...] [--seed 0] [--n-jobs 2]
        [--out studies/outputs/sim_confounds.txt] [--smoke]

Prints one table (balanced accuracy [95% CI over folds] per pipeline and
variant), the time and peak memory; ``--out`` writes it with a provenance line.
"""

import argparse
import sys
import time

import _harness  # noqa: F401 - puts the repository root on sys.path
import numpy as np
from _evaluate_dataset import evaluate_dataset, table_rows
from _sim_variants import VARIANTS

from harness.memory import peak_rss_mb
from harness.provenance import report
from harness.smoke import add_smoke_argument, parse_args, tiny_presses
from sklearn_hardness.datasets import make_presses


def recall_per_rank(confusion):
    """``"0.72 / 0.46 / 0.54"``: the recall of each class (row) of a confusion matrix, in its order."""
    cm = np.asarray(confusion, dtype=float)
    return " / ".join(f"{r:.2f}" for r in np.diag(cm) / np.maximum(cm.sum(axis=1), 1))


def kind_of(object_id):
    """``everyday-34-fruit`` -> ``fruit``."""
    return "-".join(str(object_id).split("-")[2:])


def run_variant(name, seed, n_jobs, **sim):
    overrides, groups = VARIANTS[name]
    data = make_presses("everyday", random_state=seed, **dict(sim, **overrides))
    # grouped by kind, the per-object scores class each kind (its presses' mean probabilities)
    groups = np.array([kind_of(o) for o in data.object_id]) if groups == "kind" else data.object_id
    t0 = time.perf_counter()
    result = evaluate_dataset(data, groups=groups, n_jobs=n_jobs, random_state=seed, verbose=0)
    return result, time.perf_counter() - t0, len(np.unique(groups))


def main(argv=None):
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--variants", nargs="+", default=list(VARIANTS), choices=list(VARIANTS))
    parser.add_argument("--seed", type=int, default=0, help="seed of the simulated presses, folds and nets")
    parser.add_argument("--n-jobs", type=int, default=2)
    parser.add_argument("--out", default=None, help="write the table here, with a provenance line")
    add_smoke_argument(parser)
    args = parse_args(parser, argv, variants=["preset", "kind_disjoint"], n_jobs=1)

    results, lines = {}, []
    for name in args.variants:
        result, seconds, n_groups = run_variant(name, args.seed, args.n_jobs, **tiny_presses("everyday", args.smoke))
        results[name] = result
        lines.append(f"{name}: {n_groups} groups, {len(result.target)} presses, {seconds:.0f} s")
        print(lines[-1], file=sys.stderr, flush=True)
    pipelines = results[args.variants[0]].pipelines
    width = max(len(p) for p in pipelines)
    header = f"{'pipeline':<{width}}  " + "  ".join(f"{v:>24}" for v in args.variants)
    rows = [header]
    for p in pipelines:
        cells = []
        for v in args.variants:
            row = table_rows(results[v])[p]
            lo, hi = row["balanced_accuracy_ci"]
            cells.append(f"{row['balanced_accuracy']:.2f} [{lo:.2f}, {hi:.2f}]".rjust(24))
        rows.append(f"{p:<{width}}  " + "  ".join(cells))
    recall_rows = []
    for v in args.variants:
        recall_rows.append(f"recall per rank ({' / '.join(map(str, results[v].target_names))}):")
        for p in pipelines:
            recall_rows.append(f"{v}  {p:<{width}}  {recall_per_rank(results[v].confusion_matrix(p))}")
    text = "\n".join([
        f"everyday preset variants, balanced accuracy [95% CI over 5 object-disjoint folds], seed {args.seed}, "
        "chance 0.33",
        *rows,
        *recall_rows,
        *lines,
        f"peak RSS of the main process {peak_rss_mb():.0f} MB",
    ])
    report(text, args.out)


if __name__ == "__main__":
    main()
