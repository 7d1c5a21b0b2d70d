"""``sklearn-hardness evaluate``: object-disjoint cross-validation of pipelines."""

from __future__ import annotations

import argparse
import os
import sys

from .._registry import DEFAULT_PIPELINES, PIPELINE_NAMES, pipeline_info
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
    width = max(map(len, PIPELINE_NAMES))
    return "pipelines (sklearn_hardness.models.pipeline_names):\n" + "\n".join(
        f"  {name:<{width}}  {pipeline_info(name).summary}" for name in PIPELINE_NAMES)


def _add_evaluate(sub):
    p = sub.add_parser(
        "evaluate",
        help="object-disjoint cross-validation of pipelines on your recordings or a preset",
        description="Cross-validate pipelines with folds grouped by object_id (no test object is "
        "seen in training), print balanced accuracy and hardness MAE per pipeline beside the "
        "one-number baseline (peak change to the first frame + balanced logistic regression) with "
        "each pipeline's margin over it paired by fold, name the pipeline to choose (the best one "
        "whose margin's 95% interval lies above 0; and the best with predict_proba_samples, for "
        "active sampling) or say that none beats the one number, and save a confusion-matrix figure.",
        epilog=_pipelines_epilog(),
        formatter_class=argparse.RawDescriptionHelpFormatter,
    )
    p.add_argument("dataset", help="a manifest.csv (or its folder), or a simulator preset "
                   f"({', '.join(_SIM_PRESETS)})")
    p.add_argument("--pipelines", nargs="*", default=None, choices=PIPELINE_NAMES,
                   metavar="NAME", help=f"among {', '.join(PIPELINE_NAMES)} (default: {' '.join(DEFAULT_PIPELINES)}, "
                   "and loading_compliance where every press has force and position); "
                   "the peak_change baseline is always added")
    p.add_argument("--cv", type=_int_type(2, what="an integer >= 2"), default=5,
                   help="number of object-disjoint folds (default 5)")
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


def _run_evaluate(args):
    from pathlib import Path

    import numpy as np

    from ._header import output_header, read_header
    from ..model_selection import evaluate_pipelines, format_evaluation, plot_confusion_matrices
    from ..utils._validation import check_roi

    _check_out_dir(args.out)
    if args.dataset not in _SIM_PRESETS and not os.path.exists(args.dataset):
        raise _UsageError(f"dataset {args.dataset!r} is neither a simulator preset ({', '.join(_SIM_PRESETS)}) "
                          "nor an existing manifest (a .csv file, or a folder holding manifest.csv)")
    with _user_errors():
        roi = check_roi(args.roi)
    if not args.quiet:
        repeats = f" x {args.n_repeats} repetitions" if args.n_repeats > 1 else ""
        names = "the default pipelines" if args.pipelines is None else ", ".join(args.pipelines) or "the baseline"
        print(f"evaluating {names} on {args.dataset} "
              f"({args.cv} object-disjoint folds{repeats}) ...", file=sys.stderr, flush=True)
    with _user_errors():
        result = evaluate_pipelines(args.dataset, args.pipelines, cv=args.cv, n_repeats=args.n_repeats,
                                    roi=roi, error_score=np.nan,
                                    n_jobs=args.n_jobs, random_state=args.seed, verbose=0 if args.quiet else 1)
    table = format_evaluation(result)
    print(table)
    out = Path(args.out)
    out.mkdir(parents=True, exist_ok=True)
    # what made the table: the command (less where its output goes), version, date, platform
    provenance = output_header(_reproduce_command(getattr(args, "argv", None) or sys.argv[1:]))
    (out / "evaluation.txt").write_text(provenance + "\n" + table + "\n")
    plot_confusion_matrices(result, out / "confusion_matrices.png")
    rows = [{k: (list(v) if isinstance(v, tuple) else v) for k, v in r.items()} for r in result.table]
    (out / "evaluation.json").write_text(_json_text(
        {"table": rows, "fold_scores": {k: v.tolist() for k, v in result.fold_scores.items()},
         "object_fold_scores": {k: v.tolist() for k, v in result.object_fold_scores.items()},
         "n_repeats": result.n_repeats, "notes": result.notes,
         "recommended": result.recommended, "recommended_with_samples": result.recommended_with_samples,
         "target_names": result.target_names.tolist(), "provenance": read_header(provenance)}))
    if not args.quiet:
        print(f"wrote {out / 'evaluation.txt'}, {out / 'confusion_matrices.png'} and {out / 'evaluation.json'}",
              file=sys.stderr)
    return 0


def _json_text(obj):
    """``obj`` as JSON that strict parsers read: NaN and infinities (a fold that failed) become null."""
    import json

    from ..experiments._results import _to_json  # as results.jsonl is written

    return json.dumps(_to_json(obj), indent=1, allow_nan=False)
