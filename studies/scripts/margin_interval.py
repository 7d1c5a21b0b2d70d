"""Study: does ``evaluate``'s margin interval keep its 95% level?

``evaluate_pipelines`` recommends a pipeline when the lower end of its
margin's interval over the one-number baseline (paired by fold) lies above 0.
Its folds' training sets overlap, so the fold differences are correlated and
the plain t-interval over folds is too narrow (Dietterich 1998); the interval
is corrected as Nadeau and Bengio (2003) propose. This benchmark draws many
small datasets of objects with a known truth and counts how often each
interval's lower end lies above 0:

- *null*: two pipelines equally good on new objects (a balanced logistic
  regression on one of two equally informative features; presses of one
  object share an offset, as presses of one real object share its shape).
  Every lower end above 0 is a false recommendation; a one-sided 2.5% is
  what a 95% interval promises.
- *better*: the second feature carries more of the class (``--effects``,
  its gain against the first's 0.7): the share of draws on which the better
  pipeline is recommended (the power) and its mean margin.
- *family*: ``--family K`` pipelines, each on its own feature, all as good
  as the baseline (``evaluate`` runs four by default): the share of draws on
  which ``evaluate`` recommends any of them (``result.recommended`` not
  None), which the per-pipeline 2.5% does not bound.

Each draw runs ``evaluate_pipelines`` (object-disjoint 5 folds, repeated
``--n-repeats`` times with other assignments of objects to folds) on a fresh
dataset with the same shape as the ``everyday`` preset (42 objects, 4 presses
each, 3 ranks):

    python studies/scripts/margin_interval.py [--draws 400] [--effects 1.0 1.4] [--n-repeats 1]
        [--family 4] [--n-jobs 2] [--out FILE] [--smoke]

With ``--n-repeats R`` the intervals run over the ``R x 5`` fold differences:
the plain one treats them as independent, which they are not (the repetitions
reuse the objects); the corrected one divides the variance by ``R x 5`` only
in its first term, with ``R x 5 - 1`` degrees of freedom as Bouckaert and
Frank (2004) use it, or with the ``5 - 1`` of one repetition, as
``evaluate_pipelines`` does. A last column runs ``evaluate_pipelines`` again on
the same objects with another fold seed and counts how often its
recommendation (lower end above 0) is the same.

Prints, per scenario, the share of draws whose lower ends lie above 0 with a
95% Wilson interval, the share of draws whose recommendation does not depend
on the fold seed, the time and the peak memory.
"""

import argparse
import time

import _harness  # noqa: F401 - puts the repository root on sys.path
import numpy as np
from _evaluate_dataset import evaluate_dataset, fold_scores, table_rows, test_folds
from joblib import Parallel, delayed
from scipy import stats
from sklearn.linear_model import LogisticRegression
from sklearn.pipeline import make_pipeline
from sklearn.preprocessing import FunctionTransformer
from sklearn.utils import Bunch

from harness.memory import peak_rss_mb
from harness.provenance import report
from harness.smoke import add_smoke_argument, parse_args

N_OBJECTS, PER_OBJECT, CV = 42, 4, 5


def make_objects(rng, gains):
    """Presses of ``N_OBJECTS`` objects, one feature per gain: gain x rank + object offset + press noise."""
    rank = np.arange(N_OBJECTS) % 3
    obj = np.repeat(np.arange(N_OBJECTS), PER_OBJECT)
    gains = np.asarray(gains, dtype=float)
    offsets = rng.normal(size=(N_OBJECTS, len(gains)))
    X = gains * rank[obj, None] + offsets[obj] + rng.normal(size=(len(obj), len(gains)))
    return Bunch(videos=X, target=rank[obj], object_id=obj,
                 target_names=np.array(["soft", "moderate", "hard"]))


def on_feature(j):
    return make_pipeline(FunctionTransformer(np.take, kw_args={"indices": [j], "axis": 1}),
                         LogisticRegression(class_weight="balanced"))


def one_draw(seed, gains, n_repeats=1):
    """Margin of the second pipeline over the first, lower ends (plain, corrected with R x 5 - 1 df,
    evaluate's), and whether evaluate's decision is the same with another fold seed."""
    data = make_objects(np.random.default_rng(seed), gains)
    pipes = {"peak_change": on_feature(0), "other": on_feature(1)}
    result = evaluate_dataset(data, pipes, cv=CV, n_repeats=n_repeats, random_state=seed, verbose=0)
    diff = fold_scores(result, "other") - fold_scores(result, "peak_change")
    t = stats.t.ppf(0.975, len(diff) - 1)
    plain = diff.mean() - t * diff.std(ddof=1) / np.sqrt(len(diff))
    n = len(result.target)
    ratio = np.mean([len(test) / (n - len(test)) for test in test_folds(result)])
    all_df = diff.mean() - t * np.sqrt(diff.var(ddof=1) * (1 / len(diff) + ratio))
    low = table_rows(result)["other"]["vs_baseline_ci"][0]
    other = evaluate_dataset(data, pipes, cv=CV, n_repeats=n_repeats, random_state=seed + 500_000, verbose=0)
    same = (low > 0) == (table_rows(other)["other"]["vs_baseline_ci"][0] > 0)
    return diff.mean(), plain, all_df, low, same


def family_draw(seed, k, n_repeats=1):
    """Whether evaluate recommends any of ``k`` pipelines as good as the baseline."""
    data = make_objects(np.random.default_rng(seed), [0.7] * (k + 1))
    pipes = {"peak_change": on_feature(0), **{f"equal{j}": on_feature(j) for j in range(1, k + 1)}}
    result = evaluate_dataset(data, pipes, cv=CV, n_repeats=n_repeats, random_state=seed, verbose=0)
    return result.recommended is not None


def wilson(k, n):
    """95% Wilson interval of a share k / n."""
    z = stats.norm.ppf(0.975)
    p = k / n
    centre = (p + z * z / (2 * n)) / (1 + z * z / n)
    half = z * np.sqrt(p * (1 - p) / n + z * z / (4 * n * n)) / (1 + z * z / n)
    return centre - half, centre + half


def share(k, n):
    """``"0.013 [0.008, 0.020]"``: the share k / n and its 95% Wilson interval."""
    lo, hi = wilson(k, n)
    return f"{k / n:.3f} [{lo:.3f}, {hi:.3f}]"


def main(argv=None):
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--draws", type=int, default=400, help="datasets per scenario")
    parser.add_argument("--effects", type=float, nargs="*", default=[1.0, 1.4],
                        help="gains of the better feature in the 'better' scenarios (the other's is 0.7)")
    parser.add_argument("--n-repeats", type=int, default=1,
                        help="repetitions of the object-disjoint folds (evaluate_pipelines' n_repeats)")
    parser.add_argument("--family", type=int, default=4,
                        help="pipelines as good as the baseline in the family scenario (0: skip it)")
    parser.add_argument("--n-jobs", type=int, default=2)
    parser.add_argument("--out", default=None, help="also write the output here, after a provenance line")
    add_smoke_argument(parser)
    args = parse_args(parser, argv, draws=2, effects=[1.0], family=2, n_jobs=1)

    repeats = f" x {args.n_repeats} repetitions" if args.n_repeats > 1 else ""
    lines = [f"{N_OBJECTS} objects x {PER_OBJECT} presses, 3 ranks, object-disjoint {CV} folds{repeats}, "
             f"{args.draws} draws per scenario; share of draws whose margin's lower end lies above 0 "
             "[95% Wilson interval]"]
    scenarios = {"null (equal pipelines)": (0.7, 0.7),
                 **{f"better (gain {g:g} vs 0.7)": (0.7, g) for g in args.effects}}
    t0 = time.perf_counter()
    for offset, (name, gains) in enumerate(scenarios.items()):
        t1 = time.perf_counter()
        out = np.array(Parallel(n_jobs=args.n_jobs)(
            delayed(one_draw)(1_000_000 * offset + seed, gains, args.n_repeats) for seed in range(args.draws)))
        margin, lows, same = out[:, 0], out[:, 1:4], out[:, 4]
        columns = [("plain t-interval", 0), ("corrected (Nadeau-Bengio)", 2)]
        if args.n_repeats > 1:
            columns = [("plain t-interval", 0),
                       (f"corrected, {args.n_repeats * CV - 1} df (Bouckaert-Frank)", 1),
                       (f"corrected, {CV - 1} df (evaluate)", 2)]
        cells = []
        for label, column in columns:
            cells.append(f"{label} {share(int(np.sum(lows[:, column] > 0)), args.draws)}")
        cells.append(f"evaluate's decision unchanged by another fold seed {share(int(same.sum()), args.draws)}")
        lines.append(f"{name}: mean margin {margin.mean():+.3f}; " + "; ".join(cells)
                     + f" ({time.perf_counter() - t1:.0f} s)")
    if args.family:
        t1 = time.perf_counter()
        any_rec = np.array(Parallel(n_jobs=args.n_jobs)(
            delayed(family_draw)(1_000_000 * len(scenarios) + seed, args.family, args.n_repeats)
            for seed in range(args.draws)))
        lines.append(f"family ({args.family} pipelines as good as the baseline): evaluate recommends one of them on "
                     f"{share(int(any_rec.sum()), args.draws)} of draws ({time.perf_counter() - t1:.0f} s)")
    lines.append(f"a 95% interval's lower end lies above 0 on 0.025 of null draws; total "
                 f"{time.perf_counter() - t0:.0f} s, peak RSS {peak_rss_mb():.0f} MB (main process)")
    report("\n".join(lines), args.out)


if __name__ == "__main__":
    main()
