"""Choosing a pipeline without fooling ourselves: the choice made inside the training folds.

Usage::

    python studies/scripts/nested_selection.py --data DATA [--n-repeats 5] [--cache DIR] [--out OUT] [--smoke]

``DATA`` is a local copy of the public PhysiCLeAR set (or the development manifest),
read with the 49 development objects alone (``_physiclear.py``).

Picking the best of several pipelines on the same folds that score it overstates
it: with 49 objects a pipeline's fold scores spread by about +-0.14, and the best of
six is the one the folds happened to favour. The honest figure is that of the
*procedure* "pick the best by cross-validation": here it runs inside each outer
training fold (:class:`~sklearn.model_selection.GridSearchCV` over the candidate
pipelines, its own 5 folds grouped by family, balanced accuracy), and only the
picked pipeline, refitted on the outer training fold, is scored on the outer test
fold. Folds: :class:`~sklearn.model_selection.StratifiedGroupKFold` grouped by
``family`` (the parts of one object stay on one side), 5 folds x ``--n-repeats``
repetitions, seeds 0, 1, ... Every candidate's own outer score is printed beside
the nested one, with the one number (``peak_change``), and which candidate each
outer fold picked.

Candidates: every named pipeline whose first step is a feature transformer that
learns nothing in ``fit`` and whose head is a logistic regression (``peak_change``,
``contact_profile``, ``contact_profile_3``, ``contact_geometry``, ``imprint_texture``);
``contact_profile_nn`` (an MLP head: about 35 s a fit here, 175 fits) is left to
``sklearn-hardness evaluate --groups family``, where it scores 0.44. That step's output
is computed once per press and read back by index, so every fold fits exactly the
named pipeline's other steps on exactly its rows: the scores are those of
``make_named_pipeline(name, random_state=0)`` fold by fold. The nets that learn
from frames (``convlstm``, ``ofnn``, ``imprint_cnn``, ...) learn in their first
step and are measured by ``sklearn-hardness evaluate --groups family`` instead.
"""

from __future__ import annotations

import argparse
import time
import warnings

import _harness  # noqa: F401 - puts the repository root on sys.path
import numpy as np
from _physiclear import load_development
from joblib import Memory, Parallel, delayed
from sklearn.base import BaseEstimator, TransformerMixin, clone
from sklearn.metrics import balanced_accuracy_score
from sklearn.model_selection import GridSearchCV, StratifiedGroupKFold
from sklearn.pipeline import Pipeline

from harness.provenance import report
from harness.smoke import add_smoke_argument, parse_args
from sklearn_hardness.model_selection import corrected_interval
from sklearn_hardness.models import make_named_pipeline

#: Named pipelines with a first step that learns nothing in fit and a logistic head, the one number first.
CANDIDATES = ("peak_change", "contact_profile", "contact_profile_3", "contact_geometry", "imprint_texture")


class PrecomputedRows(TransformerMixin, BaseEstimator):
    """Rows of ``table`` at the given indices: a stateless first step computed once per press.

    Parameters
    ----------
    table : ndarray of shape (n_presses, n_features)
        The first step's output for every press, in the dataset's order.
    """

    def __init__(self, table=None):
        self.table = table

    def fit(self, X, y=None):
        return self

    def transform(self, X):
        return self.table[np.asarray(X, dtype=int).ravel()]


def first_step(name):
    """The named pipeline's first step (it learns nothing in fit)."""
    return make_named_pipeline(name, random_state=0).steps[0][1]


def first_step_rows(name, paths, videos, n_jobs):
    """The first step of ``name`` applied to every press (``paths`` key the cache; ``videos`` are read)."""
    step = first_step(name)

    def one(i):
        with warnings.catch_warnings():
            warnings.simplefilter("ignore")  # contact-not-found warnings: counted by `sklearn-hardness select`
            return clone(step).fit_transform(videos[np.array([i])])[0]

    return np.asarray(Parallel(n_jobs=n_jobs)(delayed(one)(i) for i in range(len(videos))), dtype=float)


def candidate(name, table):
    """``make_named_pipeline(name)`` with its first step read from ``table``."""
    steps = make_named_pipeline(name, random_state=0).steps
    return Pipeline([("rows", PrecomputedRows(table))] + steps[1:])


def outer_fold(train, test, y, family, tables, names, inner_seed):
    """Every candidate's score on one outer fold, and the nested choice's."""
    idx = np.arange(len(y))[:, None]
    own = {}
    for name in names:
        pipe = candidate(name, tables[name]).fit(idx[train], y[train])
        own[name] = balanced_accuracy_score(y[test], pipe.predict(idx[test]))
    search = GridSearchCV(
        Pipeline([("model", candidate(names[0], tables[names[0]]))]),
        {"model": [candidate(n, tables[n]) for n in names]},
        scoring="balanced_accuracy",
        cv=StratifiedGroupKFold(5, shuffle=True, random_state=inner_seed),
        error_score="raise",
    )
    search.fit(idx[train], y[train], groups=family[train])
    picked = names[search.best_index_]
    nested = balanced_accuracy_score(y[test], search.predict(idx[test]))
    return own, picked, nested


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--data", required=True, help="a local copy of the public set (or the development manifest)")
    ap.add_argument("--n-repeats", type=int, default=5)
    ap.add_argument("--n-jobs", type=int, default=2)
    ap.add_argument("--cache", help="a folder for the first steps' rows (computed once per press)")
    ap.add_argument("--out", help="write the tables here too, under the harness's header")
    add_smoke_argument(ap)
    args = parse_args(ap, argv, n_repeats=1, n_jobs=1)
    candidates = CANDIDATES[:3] if args.smoke else CANDIDATES  # --smoke: the three cheapest

    start = time.perf_counter()
    data = load_development(args.data)
    y, family = np.asarray(data.target), np.asarray(data.family)
    rows = Memory(args.cache, verbose=0).cache(first_step_rows, ignore=["videos", "n_jobs"]) if args.cache \
        else first_step_rows
    paths = tuple(str(p) for p in data.paths) if "paths" in data else None
    tables = {}
    for name in candidates:  # pipelines that share a first step share its rows
        same = next((other for other in tables if repr(first_step(other)) == repr(first_step(name))), None)
        tables[name] = tables[same] if same else rows(name, paths, data.videos, args.n_jobs)
    features_s = time.perf_counter() - start

    folds = [(r, train, test) for r in range(args.n_repeats)
             for train, test in StratifiedGroupKFold(5, shuffle=True, random_state=r).split(y, y, family)]
    results = Parallel(n_jobs=args.n_jobs)(
        delayed(outer_fold)(train, test, y, family, tables, candidates, 1000 + r) for r, train, test in folds)
    ratio = float(np.mean([len(test) / len(train) for _, train, test in folds]))

    own = {name: np.array([res[0][name] for res in results]) for name in candidates}
    nested = np.array([res[2] for res in results])
    picked = [res[1] for res in results]
    base = own["peak_change"]
    lines = [f"{len(np.unique(data.object_id))} development objects ({len(np.unique(family))} families), "
             f"{len(y)} presses; outer: StratifiedGroupKFold(5) by family x {args.n_repeats} repetitions "
             f"(seeds 0-{args.n_repeats - 1}); inner: GridSearchCV over the {len(candidates)} candidates, "
             "StratifiedGroupKFold(5) by family within the outer training fold; balanced accuracy per press, "
             "corrected 95% t-intervals (Nadeau-Bengio), clipped to the score's range",
             f"{'pipeline':38s} {'bal. accuracy [95% CI]':24s} {'vs peak_change [95% CI]':26s} {'picked':>7s}"]
    for name in candidates:
        m, (lo, hi) = corrected_interval(own[name], ratio, bounds=(0, 1))
        d, (dlo, dhi) = corrected_interval(own[name], ratio, baseline=base, bounds=(-1, 1))
        vs = "" if name == "peak_change" else f"{d:+.3f} [{dlo:+.2f}, {dhi:+.2f}]"
        lines.append(f"{name:38s} {m:.3f} [{lo:.2f}, {hi:.2f}]{'':6s} {vs:26s} {picked.count(name):>4d}/{len(folds)}")
    m, (lo, hi) = corrected_interval(nested, ratio, bounds=(0, 1))
    d, (dlo, dhi) = corrected_interval(nested, ratio, baseline=base, bounds=(-1, 1))
    lines.append(f"{'nested: the inner folds pick one':38s} {m:.3f} [{lo:.2f}, {hi:.2f}]{'':6s} "
                 f"{d:+.3f} [{dlo:+.2f}, {dhi:+.2f}]")
    best = max(candidates, key=lambda n: own[n].mean())
    lines += [f"best single candidate on these outer folds: {best} {own[best].mean():.3f}; the nested figure is "
              f"what choosing by cross-validation is worth on new objects ({nested.mean() - own[best].mean():+.3f})",
              "picked per outer fold: " + " ".join(picked),
              f"first steps computed once per press: {features_s:.0f} s; total {time.perf_counter() - start:.0f} s"]
    report("\n".join(lines), args.out)


if __name__ == "__main__":
    main()
