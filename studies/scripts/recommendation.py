"""Study: does ``evaluate``'s recommendation carry over to new objects?

``evaluate_pipelines`` pairs each pipeline's balanced accuracy with the
one-number baseline's by fold and recommends the best pipeline whose
margin's 95% interval lies above 0 (None when none does). A user acts on it
for objects that were not in the evaluation. Each seed of
``make_presses("everyday", random_state=seed)`` draws new objects, so this
benchmark evaluates the default pipelines on several draws and, for the
pipeline recommended on one draw, reports its margin over the baseline on
the *other* draws:

    python studies/scripts/recommendation.py [--seeds 0 1 2] [--param NAME=VALUE ...]
        [--n-jobs 2] [--out FILE] [--smoke]

(``--param kinds_by_rank=false --param conformity=0.1``: the variant whose
ranking of the pipelines is nearest the real one, ``docs/simulator.md``.)
Prints, per draw, each pipeline's margin [95% CI], the recommendations and
the time; then, per recommendation, its margins on the other draws; and the
peak memory. ``--out`` also writes the output after a provenance line.
"""

import argparse
import time

import _harness  # noqa: F401 - puts the repository root on sys.path
import numpy as np
from _evaluate_dataset import evaluate_dataset, table_rows
from sim_vs_real_stats import parse_param

from harness.memory import peak_rss_mb
from harness.provenance import report
from harness.smoke import add_smoke_argument, parse_args, tiny_presses
from sklearn_hardness.datasets import make_presses


def margins(result):
    """``{pipeline: (margin, (lo, hi))}`` over the baseline, the baseline left out."""
    return {r["pipeline"]: (r["vs_baseline"], tuple(r["vs_baseline_ci"])) for r in table_rows(result).values()
            if r["vs_baseline"] is not None}


def main(argv=None):
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--seeds", nargs="+", type=int, default=[0, 1, 2],
                        help="simulated draws (objects, folds and nets)")
    parser.add_argument("--param", action="append", default=[], type=parse_param,
                        help="override an everyday parameter, NAME=VALUE or NAME=LO,HI")
    parser.add_argument("--n-jobs", type=int, default=2)
    parser.add_argument("--out", default=None, help="also write the output here, after a provenance line")
    add_smoke_argument(parser)
    args = parse_args(parser, argv, seeds=[0, 1], n_jobs=1)
    if len(args.seeds) < 2:
        parser.error("--seeds needs at least two draws: a recommendation is checked on the others")
    variant = dict(args.param)

    lines = [f"everyday {variant or '(preset)'}; evaluate's default pipelines, object-disjoint 5 folds; "
             "margin = balanced accuracy minus the one-number baseline's, paired by fold [evaluate's 95% interval, "
             "corrected for overlapping training sets]"]
    per_seed, recommended = {}, {}
    for seed in args.seeds:
        t0 = time.perf_counter()
        data = make_presses("everyday", random_state=seed, **dict(tiny_presses("everyday", args.smoke), **variant))
        result = evaluate_dataset(data, n_jobs=args.n_jobs, random_state=seed, verbose=0)
        per_seed[seed] = margins(result)
        recommended[seed] = (result.recommended, result.recommended_with_samples)
        cells = ", ".join(f"{name} {m:+.2f} [{lo:+.2f}, {hi:+.2f}]" for name, (m, (lo, hi)) in per_seed[seed].items())
        lines.append(f"draw {seed}: {cells}; recommended {result.recommended}, with predict_proba_samples "
                     f"{result.recommended_with_samples} ({time.perf_counter() - t0:.0f} s)")
        print(lines[-1], flush=True)
    lines.append("on the other draws (new objects), margin of the pipeline recommended on a draw:")
    for seed in args.seeds:
        for label, name in zip(("recommended", "with predict_proba_samples"), recommended[seed]):
            if name is None:
                lines.append(f"draw {seed} {label}: none")
                continue
            others = [per_seed[s][name] for s in args.seeds if s != seed]
            above = sum(lo > 0 for _, (lo, _) in others)
            lines.append(f"draw {seed} {label} {name}: " + ", ".join(
                f"{m:+.2f} [{lo:+.2f}, {hi:+.2f}]" for m, (lo, hi) in others)
                + f"; mean {np.mean([m for m, _ in others]):+.2f}, interval above 0 on {above} of {len(others)}")
    lines.append(f"peak RSS {peak_rss_mb():.0f} MB")
    text = "\n".join(lines)
    report(text, args.out)


if __name__ == "__main__":
    main()
