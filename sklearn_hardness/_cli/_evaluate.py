"""``sklearn-hardness evaluate``: object-disjoint cross-validation of pipelines."""

from __future__ import annotations

import argparse
import os
import sys

from ..models import pipeline_info, pipeline_names
from ._common import (
    _SIM_PRESETS,
    _add_quiet,
    _add_roi,
    _check_out_dir,
    _int_type,
    _n_jobs,
    _n_jobs_help,
    _nonnegative_int,
    _reproduce_command,
    _UsageError,
    _user_errors,
)


def _pipelines_epilog():
    """The pipelines' names with their one-line summaries, from the registry."""
    width = max(map(len, pipeline_names()))
    return "pipelines (sklearn_hardness.models.pipeline_names):\n" + "\n".join(
        f"  {name:<{width}}  {pipeline_info(name).summary}" for name in pipeline_names())


def _defaults():
    """The pipelines evaluate runs by default (beside the baseline)."""
    return [name for name in pipeline_names() if pipeline_info(name).default]


def _add_evaluate(sub):
    p = sub.add_parser(
        "evaluate",
        help="object-disjoint cross-validation of pipelines on your recordings or a preset",
        description="Cross-validate pipelines with folds grouped by object_id, or by the manifest column "
        "--groups names (no test group is seen in training), print balanced accuracy and hardness MAE per "
        "pipeline beside the "
        "one-number baseline (peak change to the first frame + balanced logistic regression) with "
        "each pipeline's margin over it paired by fold, name the pipeline to choose (the best one "
        "whose margin's 95% interval lies above 0; and the best with predict_proba_samples, for "
        "active sampling) or say that none beats the one number, and save a confusion-matrix figure.",
        epilog=_pipelines_epilog(),
        formatter_class=argparse.RawDescriptionHelpFormatter,
    )
    p.add_argument("dataset", help="a manifest.csv (or its folder), or a simulator preset "
                   f"({', '.join(_SIM_PRESETS)})")
    p.add_argument("--pipelines", nargs="*", default=None, choices=pipeline_names(),
                   metavar="NAME", help=f"among {', '.join(pipeline_names())} (default: {' '.join(_defaults())}, "
                   "and loading_compliance where every press has force and position); "
                   "the peak_change baseline is always added")
    p.add_argument("--cv", type=_int_type(2, what="an integer >= 2"), default=5,
                   help="number of object-disjoint folds (default 5)")
    p.add_argument("--groups", default="object_id", metavar="COLUMN",
                   help="the manifest column whose values no fold splits (default object_id; e.g. family, "
                   "so that the parts of one multi-part object stay on one side); the per-object figures "
                   "still class each object_id")
    p.add_argument("--n-repeats", type=_int_type(1, what="an integer >= 1"), default=1,
                   help="repeat the folds with other assignments of objects to folds, at that many times "
                   "the compute (default 1): the figures depend less on one assignment; the intervals "
                   "run over all repetitions' folds, corrected for their overlap, with the degrees of "
                   "freedom of one repetition (more objects narrow them, repetitions little)")
    _add_roi(p, "in the baseline and every video pipeline")
    p.add_argument("--out", default="hardness_evaluation",
                   help="folder for evaluation.json and confusion_matrices.png (default ./hardness_evaluation)")
    p.add_argument("--seed", type=_nonnegative_int, default=0, help="seed of the folds and of a preset (default 0)")
    p.add_argument("--n-jobs", type=_n_jobs, default=None, help=_n_jobs_help(1) + " (folds in parallel)")
    _add_quiet(p, "start line, progress and summary of the files written")
    return p


def _load(args):
    """The dataset of ``args.dataset``: a simulator preset, or a manifest read by ``datasets``."""
    from ..datasets import load_press_videos, make_presses

    if args.dataset in _SIM_PRESETS:
        return make_presses(args.dataset, random_state=args.seed)
    if not os.path.exists(args.dataset):
        raise _UsageError(f"dataset {args.dataset!r} is neither a simulator preset ({', '.join(_SIM_PRESETS)}) "
                          "nor an existing manifest (a .csv file, or a folder holding manifest.csv)")
    path = args.dataset
    return load_press_videos(os.path.join(path, "manifest.csv") if os.path.isdir(path) else path)


def _groups(data, column):
    """The values of manifest column ``column`` per press (``object_id`` or an extra column such as family)."""
    if column == "object_id":
        return data.object_id
    values = getattr(data, "metadata", {}).get(column)
    if values is None:
        extra = sorted(getattr(data, "metadata", {}))
        raise _UsageError(f"--groups {column}: the dataset has no column {column!r} (its extra columns: "
                          f"{', '.join(extra) or 'none'}; object_id is the default)")
    if any(v in ("", None) for v in values):
        raise _UsageError(f"--groups {column}: the column is empty on some rows; give every press its {column}")
    return values


def _estimators(names, force_position, roi, seed):
    """``{name: pipeline}`` of the registry's ``names`` (the defaults where None), ``roi`` to those reading video."""
    from ..models import make_named_pipeline

    if names is None:
        names = _defaults() + (["loading_compliance"] if force_position is not None else [])
    return {name: make_named_pipeline(name, random_state=seed,
                                      **({"roi": roi} if pipeline_info(name).input == "video" else {}))
            for name in names}


def _force_position(data, names):
    """Each press's (T, 2) force and position where ``names`` (None: the defaults) need or can use them."""
    from ..datasets import force_and_position

    if names is None:
        return force_and_position(data, missing="none")
    reads = [n for n in names if pipeline_info(n).input != "video"]
    return force_and_position(data) if reads else None


def _run_evaluate(args):
    from ..model_selection import ConfusionMatricesDisplay, evaluate_pipelines
    from ..models import make_named_pipeline
    from ..utils._validation import check_roi
    from ._header import output_header, read_header

    _check_out_dir(args.out)
    data = _load(args)
    with _user_errors():
        roi = check_roi(args.roi)
        groups = _groups(data, args.groups)
    if not args.quiet:
        repeats = f" x {args.n_repeats} repetitions" if args.n_repeats > 1 else ""
        names = "the default pipelines" if args.pipelines is None else ", ".join(args.pipelines) or "the baseline"
        print(f"evaluating {names} on {args.dataset} ({args.cv} folds by {args.groups}{repeats}) ...",
              file=sys.stderr, flush=True)
    with _user_errors():
        force_position = _force_position(data, args.pipelines)
        estimators = _estimators(args.pipelines, force_position, roi, args.seed)
        result = evaluate_pipelines(
            estimators, data.videos, data.target, groups=groups, objects=data.object_id, cv=args.cv,
            n_repeats=args.n_repeats, baseline=("peak_change", make_named_pipeline("peak_change", roi=roi)),
            target_names=data.target_names, hardness=getattr(data, "hardness", None),
            force_position=force_position, n_jobs=args.n_jobs, random_state=args.seed,
            verbose=0 if args.quiet else 1)
    _write(args, result, str(result), ConfusionMatricesDisplay, output_header, read_header)
    return 0


def _write(args, result, table, display, output_header, read_header):
    """Print the table; write it (with the cheap header), the figure and the JSON in ``args.out``."""
    from pathlib import Path

    print(table)
    out = Path(args.out)
    out.mkdir(parents=True, exist_ok=True)
    # what made the table: the command (less where its output goes), version, date, platform
    provenance = output_header(_reproduce_command(getattr(args, "argv", None) or sys.argv[1:]))
    (out / "evaluation.txt").write_text(provenance + "\n" + table + "\n")
    written = [out / "evaluation.txt"]
    try:
        import matplotlib
    except ImportError:
        print('confusion_matrices.png not written: it needs matplotlib (pip install "sklearn-hardness[plot]")',
              file=sys.stderr)
    else:
        matplotlib.use("Agg", force=False)
        display.from_result(result).figure_.savefig(out / "confusion_matrices.png", dpi=100)
        written.append(out / "confusion_matrices.png")
    cv_results = {key: [_plain(v) for v in values] for key, values in result.cv_results_.items()
                  if key != "estimator"}
    (out / "evaluation.json").write_text(_json_text(
        {"cv_results": cv_results, "summary": result.summary, "n_splits": result.n_splits,
         "n_repeats": result.n_repeats, "baseline": result.baseline, "groups": args.groups, "notes": result.notes,
         "recommended": result.recommended, "recommended_with_samples": result.recommended_with_samples,
         "target_names": result.target_names.tolist(), "provenance": read_header(provenance)}))
    written.append(out / "evaluation.json")
    if not args.quiet:
        print(f"wrote {', '.join(map(str, written[:-1]))} and {written[-1]}", file=sys.stderr)


def _plain(value):
    """A ``cv_results_`` entry as JSON takes it: arrays as lists, NumPy scalars as Python's."""
    import numpy as np

    if isinstance(value, np.ndarray):
        return value.tolist()
    return value.item() if isinstance(value, np.generic) else value


def _json_text(obj):
    """``obj`` as JSON that strict parsers read: NaN and infinities (a fold that failed) become null."""
    import json

    from ..utils._json import to_json  # as results.jsonl is written

    return json.dumps(to_json(obj), indent=1, allow_nan=False)
