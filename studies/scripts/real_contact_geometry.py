"""Contact-geometry pipelines beside the one number, on real hand presses of development objects.

Usage::

    python studies/scripts/real_contact_geometry.py --data DATA [--n-repeats 5] [--n-jobs 1] [--smoke]

``DATA``: a copy of the public PhysiCLeAR set (its ``dataset/`` and
``utils/constants.py``), read with the development objects alone
(``_physiclear.py``), or a manifest of their presses.

Every variant is measured by the same object-disjoint cross-validation
(:func:`~sklearn_hardness.model_selection.evaluate_pipelines`, ``cv=5``,
``n_repeats`` repetitions, seed 0, corrected Nadeau-Bengio intervals) beside
``peak_change`` (the one number) and ``contact_profile``. The variants were
fixed before this script was written (see the docstring of ``VARIANTS``);
none was chosen by its score.

To keep the run short, each video is decoded once: the geometry rows are
computed by :class:`~sklearn_hardness.features.ContactGeometryFeatures` on the
decoded video itself, and the folds read them back from a table (the
transformer learns nothing in ``fit``, so this gives the scores of the
pipeline of :func:`~sklearn_hardness.models.make_contact_geometry_pipeline`
fold by fold, with one pass of its feature step). The one number and the
contact profile read the frames strided by 4 (the pixels they read from the
full frames anyway: both stride a 240x320 frame to 60x80), kept in memory.
"""

from __future__ import annotations

import argparse
import hashlib
import sys
import time

import _harness  # noqa: F401 - puts the repository root on sys.path
import numpy as np
from _evaluate_dataset import table_rows
from _physiclear import load_development
from sklearn.base import BaseEstimator, TransformerMixin
from sklearn.preprocessing import StandardScaler

from harness.provenance import header
from harness.smoke import add_smoke_argument, parse_args
from sklearn_hardness.features import ContactGeometryFeatures, ContactProfileFeatures
from sklearn_hardness.model_selection import evaluate_pipelines
from sklearn_hardness.models import (
    ContactProfileNNClassifier,
    LaplaceLogisticRegression,
    MCDropoutPipeline,
    make_contact_profile_pipeline,
)


def _feature_names(transformer):
    """The output columns' names of a feature transformer (fitted on a blank video: neither learns in fit)."""
    return tuple(transformer.fit([np.zeros((3, 8, 8, 3), np.uint8)]).get_feature_names_out())


#: Every geometry feature, in output order; the twelve scale-free ones; the twelve contact-profile ones.
FEATURE_NAMES = _feature_names(ContactGeometryFeatures(features="all"))
SCALE_FREE = _feature_names(ContactGeometryFeatures(features="scale_free"))
PROFILE_NAMES = _feature_names(ContactProfileFeatures())

#: name -> (feature columns, head). Declared before measuring: the local depth alone (a one-number
#: rival of the peak change), all geometry features, the scale-free ones (shapes, ratios, growth slopes
#: that do not grow with how hard the hand presses), the scale-free ones with the depth (shape and
#: strength), geometry with the twelve contact-profile features, and all geometry with the MLP head.
VARIANTS = {
    "geom_depth": (("log_depth",), "logistic"),
    "geom_all": (FEATURE_NAMES, "logistic"),
    "geom_scalefree": (SCALE_FREE, "logistic"),
    "geom_scalefree_depth": (("log_depth",) + SCALE_FREE, "logistic"),
    "geom_profile": (FEATURE_NAMES + tuple("profile_" + n for n in PROFILE_NAMES), "logistic"),
    "geom_all_nn": (FEATURE_NAMES, "nn"),
}


def _key(video):
    """A cheap fingerprint of a (strided) video: its shape and a sparse sample of its bytes."""
    v = np.ascontiguousarray(video[::3, ::5, ::5])
    return hashlib.blake2b(v.tobytes() + str(video.shape).encode(), digest_size=16).hexdigest()


class RowLookup(TransformerMixin, BaseEstimator):
    """The precomputed rows of the videos (by fingerprint), these columns."""

    def __init__(self, table=None, columns=None):
        self.table = table
        self.columns = columns

    def fit(self, X, y=None):
        return self

    def transform(self, X):
        return np.array([self.table[_key(v)] for v in X])[:, list(self.columns)]


def _pipeline(table, names, columns, head, seed):
    cols = [names.index(c) for c in columns]
    clf = (LaplaceLogisticRegression(class_weight="balanced", max_iter=2000) if head == "logistic"
           else ContactProfileNNClassifier(class_weight="balanced", random_state=seed))
    return MCDropoutPipeline([("features", RowLookup(table, cols)), ("scale", StandardScaler()), ("clf", clf)])


def main(argv=None):
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--data", required=True, help="copy of the public PhysiCLeAR set (dataset/, utils/constants.py)"
                        " or a manifest CSV of the development objects' presses")
    parser.add_argument("--n-repeats", type=int, default=5)
    parser.add_argument("--n-jobs", type=int, default=1)
    add_smoke_argument(parser)
    args = parse_args(parser, argv, n_repeats=1)
    print(header(sys.argv if argv is None else [sys.argv[0], *argv]), flush=True)

    data = load_development(args.data)
    geometry = ContactGeometryFeatures(features="all").fit([np.zeros((3, 8, 8, 3), np.uint8)])
    strided, rows, t_geom, t_read = [], [], 0.0, 0.0
    for i in range(len(data.videos)):
        t0 = time.perf_counter()
        video = np.asarray(data.videos[i])
        t1 = time.perf_counter()
        rows.append(geometry.transform([video])[0])
        t_geom += time.perf_counter() - t1
        t_read += t1 - t0
        strided.append(np.ascontiguousarray(video[:, ::4, ::4]))
    t0 = time.perf_counter()
    profile = ContactProfileFeatures().fit_transform(strided)
    t_profile = time.perf_counter() - t0
    print(f"{len(strided)} presses: decoding {t_read:.1f} s, ContactGeometryFeatures {t_geom:.1f} s "
          f"({1000 * t_geom / len(strided):.0f} ms a press), ContactProfileFeatures {t_profile:.1f} s", flush=True)
    names = list(FEATURE_NAMES) + ["profile_" + n for n in PROFILE_NAMES]
    keys = [_key(v) for v in strided]
    if len(set(keys)) != len(keys):
        raise RuntimeError("two presses share a fingerprint; the row table cannot tell them apart.")
    table = dict(zip(keys, np.hstack([np.vstack(rows), profile])))

    pipelines = {"contact_profile": make_contact_profile_pipeline()}
    pipelines.update({name: _pipeline(table, names, cols, head, 0) for name, (cols, head) in VARIANTS.items()})
    result = evaluate_pipelines(pipelines, strided, data.target, groups=data.object_id, cv=5,
                                n_repeats=args.n_repeats, target_names=data.target_names,
                                hardness=data.get("hardness"), error_score="raise", n_jobs=args.n_jobs,
                                random_state=0, verbose=0)
    print(result)
    print()
    print("| pipeline | features | per press [95% CI] | vs peak [95% CI] | per object [95% CI] | "
          "vs peak per object [95% CI] | fit+predict s |")
    print("|---|---|---|---|---|---|---|")
    fmt = lambda m, ci: "-" if m is None else f"{m:+.2f} [{ci[0]:+.2f}, {ci[1]:+.2f}]"  # noqa: E731
    for r in table_rows(result).values():
        n = r["pipeline"]
        nf = len(VARIANTS[n][0]) if n in VARIANTS else {"peak_change": 1, "contact_profile": 12}.get(n, "")
        ci, oci = r["balanced_accuracy_ci"], r["object_balanced_accuracy_ci"]
        print(f"| {n} | {nf} | {r['balanced_accuracy']:.2f} [{ci[0]:.2f}, {ci[1]:.2f}] | "
              f"{fmt(r['vs_baseline'], r['vs_baseline_ci'])} | {r['object_balanced_accuracy']:.2f} "
              f"[{oci[0]:.2f}, {oci[1]:.2f}] | {fmt(r['object_vs_baseline'], r['object_vs_baseline_ci'])} | "
              f"{r['fit_predict_seconds']:.1f} |")
    return result


if __name__ == "__main__":
    main()
