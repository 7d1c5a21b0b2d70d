"""The public set's own object-disjoint split, fitted on the development objects, scored once.

Usage::

    python studies/scripts/anchor_split.py --data DATA [--pipelines NAME ...] [--out OUT] [--smoke]

``DATA`` is a local copy of the public PhysiCLeAR set (its ``dataset/`` and
``utils/constants.py``), read with the development objects alone
(``_physiclear.py``). The set ships a split (``utils/constants.py``:
``TRAIN_OBJECTS``, ``VAL_OBJECTS``, ``TEST_OBJECTS``); all seven test objects are
development objects, and 42 of its train and val objects are (the other train
and val objects are kept aside and never read). Every named pipeline is built
with ``make_named_pipeline(name, random_state=0)``, fitted once on the presses of
those 42 objects and scored once on the 39 presses of the 7 test objects:
accuracy per video (the metric the set's authors report), balanced accuracy per
video, and objects right (an object's class: the argmax of the mean of its
presses' probabilities). Beside them: always answering the training presses'
most frequent class, always "moderate", and the published figures of the set's
authors (Octopi, RSS 2024) on the same 7 objects.

The final choice is pre-registered in
``studies/preregistration/anchor_split.md``; the other rows are listed because
every pipeline tried is listed, not to choose among them.
"""

from __future__ import annotations

import argparse
import time
import warnings

import _harness  # noqa: F401 - puts the repository root on sys.path
import numpy as np
from _physiclear import load_development
from sklearn.dummy import DummyClassifier
from sklearn.metrics import accuracy_score, balanced_accuracy_score

from harness.memory import peak_rss_mb
from harness.provenance import report
from harness.smoke import add_smoke_argument, parse_args
from sklearn_hardness.models import make_named_pipeline, pipeline_names

#: Published per-video hardness accuracy on the split's 7 test objects (Octopi, RSS 2024, read
#: from a copy of the paper's tables): its fine-tuned CLIP ViT-L/14 tactile encoder and its 7b and
#: 13b tactile-language models.
PUBLISHED = {"Octopi CLIP ViT-L/14 encoder (published)": 0.8684,
             "Octopi-7b (published)": 0.7105,
             "Octopi-13b (published)": 0.7368}

#: Pipelines that cannot run on these presses: no force was recorded; no DINOv2 weights can be fetched.
NOT_RUN = {"loading_compliance": "needs the press's force and position, which the public set lacks",
           "dinov2nn": "needs DINOv2 weights (dinov2_model=...), which cannot be fetched on our machines"}

#: The pre-registered final choice (studies/preregistration/anchor_split.md).
CHOSEN = "contact_geometry"


def objects_right(object_id, y_true, proba, classes):
    """How many objects are classed right by the mean of their presses' probabilities."""
    right = 0
    objects = np.unique(object_id)
    for obj in objects:
        rows = object_id == obj
        right += int(classes[np.argmax(proba[rows].mean(axis=0))] == y_true[rows][0])
    return right, len(objects)


def score(name, y_true, y_pred, object_id, proba, classes, seconds=None):
    """One row of the table."""
    right, n = objects_right(object_id, y_true, proba, classes)
    return {"pipeline": name, "acc": accuracy_score(y_true, y_pred),
            "bal": balanced_accuracy_score(y_true, y_pred), "objects": f"{right}/{n}", "seconds": seconds}


def constant_rows(train, test, classes):
    """Always the training presses' most frequent class, and always "moderate"."""
    rows = []
    majority = DummyClassifier(strategy="most_frequent").fit(np.zeros((len(train.target), 1)), train.target)
    label = train.target_names[majority.predict(np.zeros((1, 1)))[0]]
    for name, rank in ((f'always "{label}" (training majority)', majority.predict(np.zeros((1, 1)))[0]),
                       ('always "moderate"', list(train.target_names).index("moderate"))):
        pred = np.full(len(test.target), rank)
        proba = np.eye(len(classes))[pred]
        rows.append(score(name, test.target, pred, test.object_id, proba, classes))
    return rows


def subset(data, mask):
    """The presses of ``data`` where ``mask``, as a bunch of the fields this study reads."""
    index = np.flatnonzero(mask)
    return type(data)(videos=data.videos[index], target=data.target[index], object_id=data.object_id[index],
                      target_names=data.target_names)


def format_table(rows):
    lines = [f"{'pipeline':44s} {'per video':>9s} {'balanced':>9s} {'objects':>8s} {'fit+predict s':>14s}"]
    for r in rows:
        acc = "" if r["acc"] is None else f"{r['acc']:.3f}"
        bal = "" if r["bal"] is None else f"{r['bal']:.3f}"
        sec = "" if r["seconds"] is None else f"{r['seconds']:.0f}"
        mark = " (pre-registered choice)" if r["pipeline"] == CHOSEN else ""
        lines.append(f"{r['pipeline'] + mark:44s} {acc:>9s} {bal:>9s} {r['objects']:>8s} {sec:>14s}")
    return "\n".join(lines)


def main(argv=None):
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("--data", required=True, help="a local copy of the public set")
    parser.add_argument("--pipelines", nargs="+", default=None,
                        help="named pipelines (default: every one that can run on these presses)")
    parser.add_argument("--out", help="write the table here too, under the harness's header")
    add_smoke_argument(parser)
    args = parse_args(parser, argv, pipelines=["peak_change", "contact_geometry"])
    names = args.pipelines or [n for n in pipeline_names() if n not in NOT_RUN]

    data = load_development(args.data)
    if "split" not in data:
        raise SystemExit("--data must be the public set's folder (its split is read from utils/constants.py).")
    fit_part = np.isin(data.split, ["train", "val"])
    test_part = data.split == "test"
    train, test = subset(data, fit_part), subset(data, test_part)
    classes = np.arange(len(data.target_names))
    counts = np.bincount(test.target, minlength=len(classes))

    rows = []
    for name in names:
        start = time.perf_counter()
        pipe = make_named_pipeline(name, random_state=0)
        with warnings.catch_warnings():
            warnings.simplefilter("ignore")  # contact-not-found warnings are counted by `sklearn-hardness select`
            pipe.fit(train.videos, train.target)
            proba = pipe.predict_proba(test.videos)
        pred = pipe.classes_[np.argmax(proba, axis=1)]
        rows.append(score(name, test.target, pred, test.object_id, proba, classes, time.perf_counter() - start))
        print(format_table(rows[-1:]).split("\n")[1], flush=True)
    rows += constant_rows(train, test, classes)
    rows += [{"pipeline": k, "acc": v, "bal": None, "objects": "", "seconds": None} for k, v in PUBLISHED.items()]

    text = "\n".join([
        f"the public set's split: fitted on {int(fit_part.sum())} presses of {len(np.unique(train.object_id))} "
        f"development train+val objects, scored once on {int(test_part.sum())} presses of "
        f"{len(np.unique(test.object_id))} test objects ({', '.join(sorted(np.unique(test.object_id)))}); "
        "test presses " + ", ".join(f"{c} {n}" for n, c in zip(data.target_names, counts)),
        format_table(rows),
        "per video: accuracy (the set's authors' metric); balanced: mean recall of the three ranks (chance 0.333); "
        "objects: objects whose mean probability over their presses picks their rank",
        "not run: " + "; ".join(f"{k} ({v})" for k, v in NOT_RUN.items() if k not in names),
        f"peak memory {peak_rss_mb() / 1024:.2f} GB",
    ])
    report(text, args.out)


if __name__ == "__main__":
    main()
