"""The ``sklearn-hardness`` command line.

Each subcommand lives in its own ``_add_<name>`` / ``_run_<name>`` pair and is
registered in :data:`_SUBCOMMANDS`.

Building the parser imports nothing heavy (no torch, skorch or scikit-learn):
``--help`` and ``--version`` answer at once, and help texts that name values of
the experiments (strategies, ``--set`` keys) are filled in only when shown.
A user error is one line ``sklearn-hardness <command>: error: ...`` on stderr
with exit status 2, found before anything is written.
"""

from __future__ import annotations

import argparse
import contextlib
import json
import math
import os
import shlex
import signal
import sys
import textwrap

from . import __version__
from ._experiment_names import DEFAULT_PIPELINES, MODEL_NAMES, PIPELINE_NAMES


class _UsageError(Exception):
    """A wrong invocation found after parsing: reported like argparse's own errors."""


class _Parser(argparse.ArgumentParser):
    """``ArgumentParser`` with one-line errors and help texts computed when shown.

    A callable ``help`` (of an argument) or ``epilog`` is called by
    :meth:`format_help`, so texts that need the experiments module cost
    nothing unless ``--help`` asks for them.
    """

    def error(self, message):
        message = " ".join(line.strip() for line in str(message).splitlines() if line.strip())
        self.exit(2, f"{self.prog}: error: {message}\n")

    def format_help(self):
        for action in self._actions:
            if callable(action.help):
                action.help = action.help()
        if callable(self.epilog):
            self.epilog = self.epilog()
        return super().format_help()


@contextlib.contextmanager
def _user_errors():
    """Turn the library's errors about the user's input into :class:`_UsageError`."""
    try:
        yield
    except (ValueError, OSError) as exc:  # FileNotFoundError is an OSError
        raise _UsageError(str(exc)) from exc


def _int_type(low=None, *, nonzero=False, what="an integer"):
    def convert(text):
        try:
            value = int(text)
        except ValueError:
            raise argparse.ArgumentTypeError(f"expected {what}, got {text!r}") from None
        if (low is not None and value < low) or (nonzero and value == 0):
            raise argparse.ArgumentTypeError(f"expected {what}, got {value}")
        return value

    return convert


def _float_type(low=0.0, what="a positive number"):
    def convert(text):
        try:
            value = float(text)
        except ValueError:
            raise argparse.ArgumentTypeError(f"expected {what}, got {text!r}") from None
        if not math.isfinite(value) or value <= low:
            raise argparse.ArgumentTypeError(f"expected {what}, got {text!r}")
        return value

    return convert


_positive_int = _int_type(1, what="a positive integer")
_nonnegative_int = _int_type(0, what="an integer >= 0")
#: joblib's n_jobs: a positive count, or -1 (all cores), -2 (all but one), ...; 0 means nothing
_n_jobs = _int_type(nonzero=True, what="a non-zero integer (joblib: -1 is all cores)")


def _check_out_dir(path):
    """A usage error unless ``path`` is a folder or can become one."""
    if os.path.exists(path) and not os.path.isdir(path):
        raise _UsageError(f"--out {path!r} exists and is not a folder")


def _add_quiet(p, what="progress and messages on stderr"):
    p.add_argument("--quiet", action="store_true", help=f"no {what}; results still go to stdout and files")


def _n_jobs_help(default):
    return f"parallel jobs (joblib; -1: all cores, -2: all but one). Default: {default}"


def _threshold(text):
    if text == "auto":
        return text
    return _float_type(0.0, "'auto' or a positive number")(text)


_SELECT_FORMATS = ("table", "csv", "json")


def _add_select(sub):
    p = sub.add_parser(
        "select",
        help="run contact-frame selection on the videos of a manifest and report what was chosen",
        description="Run ContactFrameSelector on the videos listed in a manifest CSV and print, "
        "per video, the contact start, peak and the selected frame indices (a table, or CSV or "
        "JSON with --format / --output).",
    )
    p.add_argument("manifest", help="CSV manifest (see sklearn_hardness.datasets.load_press_videos)")
    p.add_argument("--n-between", type=_nonnegative_int, default=2,
                   help="frames kept between first and last (default 2)")
    p.add_argument("--threshold", type=_threshold, default="auto",
                   help="contact threshold: 'auto' (default) or a positive number")
    p.add_argument("--plot", default=None, help="write a PNG of the intensity curves here")
    p.add_argument("--format", choices=_SELECT_FORMATS, default=None,
                   help="table (default on stdout), csv or json (one record per video: path, label, "
                   "object_id, n_frames, start, peak, selected, status, contact_found)")
    p.add_argument("--output", default=None, metavar="FILE",
                   help="write the records to FILE instead of stdout (format from --format, else from "
                   "the suffix .csv or .json)")
    _add_quiet(p, "summary line and warnings")
    return p


def _select_format(args):
    """The output format of ``select``, checked before anything runs."""
    fmt = args.format
    if args.output is not None:
        suffix = os.path.splitext(args.output)[1].lower().lstrip(".")
        if fmt is None:
            if suffix not in ("csv", "json"):
                raise _UsageError(f"cannot tell the format of {args.output!r}; pass --format csv or json")
            fmt = suffix
        elif fmt == "table":
            raise _UsageError("--output writes csv or json; pass --format csv or json")
    for path in (args.output, args.plot):
        folder = os.path.dirname(os.path.abspath(path)) if path else None
        if folder and not os.path.isdir(folder):
            raise _UsageError(f"the folder of {path!r} does not exist")
    return fmt or "table"


def _write_records(records, fmt, path):
    """Write ``records`` (dicts with the same keys) as CSV or JSON to ``path`` or stdout."""
    import csv
    import io
    import json

    if fmt == "json":
        text = json.dumps(records, indent=1) + "\n"
    else:
        buf = io.StringIO()
        writer = csv.DictWriter(buf, list(records[0]), lineterminator="\n")
        writer.writeheader()
        writer.writerows({k: " ".join(map(str, v)) if isinstance(v, list) else v for k, v in r.items()}
                         for r in records)
        text = buf.getvalue()
    if path is None:
        sys.stdout.write(text)
    else:
        with open(path, "w", newline="", encoding="utf-8") as f:
            f.write(text)


def _run_select(args):
    import warnings

    import numpy as np

    from .datasets import load_press_videos
    from .preprocessing import ContactFrameSelector

    fmt = _select_format(args)
    with _user_errors():
        data = load_press_videos(args.manifest)
    selector = ContactFrameSelector(n_between=args.n_between, threshold=args.threshold, on_no_contact="fallback")
    with warnings.catch_warnings():
        if args.quiet:
            warnings.simplefilter("ignore")
        selection = selector.select(data.videos)
    records = [
        {"video": i, "path": str(data.paths[i]), "label": str(data.target_names[data.target[i]]),
         "object_id": str(data.object_id[i]), "n_frames": len(selection.curves[i]),
         "start": int(selection.contact_start[i]), "peak": int(selection.contact_peak[i]),
         "selected": np.asarray(idx).tolist(), "status": str(selection.status[i]),
         "contact_found": bool(selection.contact_found[i])}
        for i, idx in enumerate(selection.indices)
    ]
    if fmt != "table":
        _write_records(records, fmt, args.output)
    else:
        print(f"{'video':>5}  {'label':<12} {'frames':>6}  {'start':>5}  {'peak':>4}  selected")
        for r in records:
            flag = "" if r["status"] == "contact" else \
                f"  ({r['status']}{'' if r['contact_found'] else ': fallback'})"
            print(f"{r['video']:>5}  {r['label']:<12} {r['n_frames']:>6}  {r['start']:>5}  {r['peak']:>4}  "
                  f"{r['selected']}{flag}")
    info = sys.stdout if fmt == "table" else sys.stderr  # stdout stays machine-readable
    if not args.quiet:
        print(f"contact found in {selection.contact_found.sum()} of {len(selection.indices)} videos", file=info)
    if args.plot:
        from .preprocessing import plot_contact_selection

        fig = plot_contact_selection(selection, labels=[data.target_names[t] for t in data.target])
        fig.savefig(args.plot, dpi=120)
        if not args.quiet:
            print(f"wrote {args.plot}", file=info)
    return 0


def _add_record(sub):
    p = sub.add_parser(
        "record",
        help="record one press from a tactile camera and add it to a manifest",
        description="Record one press from a camera (GelSight Mini, DIGIT or any UVC camera; a video "
        "file or stream URL also works), write it to OUT/videos/ and append a row to OUT/manifest.csv "
        "(created with a header when missing) in the format load_press_videos reads. Then report "
        "whether contact selection finds the contact in it.",
    )
    p.add_argument("--source", default="0", help="camera index (default 0), video file or stream URL")
    p.add_argument("--label", required=True, help="class label of the pressed object (e.g. soft)")
    p.add_argument("--out", required=True, help="folder of the recordings and manifest.csv")
    p.add_argument("--object-id", default="", help="which physical object was pressed (default: the label)")
    p.add_argument("--n-frames", type=_positive_int, default=None,
                   help="frames to record (default 126, 5 s at 25 fps, like GelSight Mini recordings)")
    p.add_argument("--duration", type=_float_type(), default=None, help="seconds to record instead of --n-frames")
    p.add_argument("--fps", type=_float_type(), default=None, help="frame rate to ask of the camera")
    p.add_argument("--size", type=_int_type(2, what="an integer >= 2"), nargs=2, default=None,
                   metavar=("HEIGHT", "WIDTH"), help="frame size (resized if the camera gives another)")
    p.add_argument("--warmup", type=_nonnegative_int, default=0,
                   help="frames dropped first while exposure settles")
    p.add_argument("--hardness", default="", help="the label's hardness value, if known")
    p.add_argument("--hardness-unit", default="", help="e.g. 'Shore 00' or 'mm/N'")
    p.add_argument("--format", default="avi", choices=["avi", "mp4", "npy"],
                   help="avi (FFV1, lossless; default), mp4 (mp4v, lossy) or npy")
    _add_quiet(p, "report of the contact selection")
    return p


_MANIFEST_COLUMNS = ["path", "label", "hardness", "hardness_unit", "object_id", "fps"]


def _read_manifest(manifest):
    """Columns and rows of an existing manifest (empty lists when there is none)."""
    import csv

    if not manifest.exists() or manifest.stat().st_size == 0:
        return [], []
    with open(manifest, newline="", encoding="utf-8-sig") as f:
        reader = csv.DictReader(f)
        rows = [{k.strip(): (v or "").strip() for k, v in r.items() if k is not None} for r in reader]
        return [c.strip() for c in reader.fieldnames or []], rows


def _manifest_row(manifest, row):
    """``row`` completed and checked against the manifest, before anything is recorded.

    The hardness of a label is the same on all its rows, and given on all rows or on
    none (as load_press_videos requires): an omitted value is taken from the label's
    earlier rows; a conflicting or missing one is an error.
    """
    columns, rows = _read_manifest(manifest)
    same = [r for r in rows if r.get("label") == row["label"]]
    for key in ("hardness", "hardness_unit"):
        known = {r.get(key, "") for r in same} - {""}
        if not row[key] and known:
            row[key] = known.pop()
        elif row[key] and known and known != {row[key]}:
            raise ValueError(f"{manifest}: label '{row['label']}' has {key} {sorted(known)}, not '{row[key]}'.")
    if rows and not row["hardness"] and any(r.get("hardness") for r in rows):
        raise ValueError(f"{manifest} gives the hardness of its other labels: pass --hardness for "
                         f"'{row['label']}' too.")
    if rows and row["hardness"] and any(not r.get("hardness") for r in rows):
        raise ValueError(f"{manifest} has rows without hardness: record without --hardness, or add it there.")
    missing = [k for k, v in row.items() if v and columns and k not in columns]
    if missing:
        raise ValueError(f"{manifest} has no column(s) {missing} for this recording; "
                         f"its columns are {columns}. Add them or record into another folder.")
    return columns or _MANIFEST_COLUMNS, row


def _append_manifest_row(manifest, columns, row):
    """Append ``row`` to ``manifest``, writing the header first when the file is new."""
    import csv

    new = not manifest.exists() or manifest.stat().st_size == 0
    if not new:
        with open(manifest, "rb") as f:
            f.seek(-1, 2)
            new_line = f.read(1) not in (b"\n", b"\r")
    with open(manifest, "a", newline="", encoding="utf-8") as f:
        writer = csv.DictWriter(f, columns, restval="", extrasaction="ignore")
        if new:
            writer.writeheader()
        elif new_line:
            f.write("\n")
        writer.writerow(row)


def _run_record(args):
    import warnings
    from pathlib import Path

    import cv2

    from .io import record_video
    from .preprocessing import ContactFrameSelector

    if args.n_frames is not None and args.duration is not None:
        raise _UsageError("pass --n-frames or --duration, not both")
    source = int(args.source) if args.source.isdigit() else args.source
    n_frames = args.n_frames if args.n_frames is not None or args.duration is not None else 126
    out = Path(args.out)
    stem = "".join(c if c.isalnum() or c in "-_" else "_" for c in f"{args.label}_{args.object_id or args.label}")
    number = 0
    while list((out / "videos").glob(f"{stem}_{number:04d}.*")):
        number += 1
    video_path = out / "videos" / f"{stem}_{number:04d}.{args.format}"
    row = {"path": video_path.relative_to(out).as_posix(), "label": args.label, "hardness": args.hardness,
           "hardness_unit": args.hardness_unit, "object_id": args.object_id or args.label,
           "fps": f"{args.fps:g}" if args.fps else ""}
    with _user_errors():
        columns, row = _manifest_row(out / "manifest.csv", row)  # before recording: no orphan video
    cv2.utils.logging.setLogLevel(cv2.utils.logging.LOG_LEVEL_ERROR)  # the error below says it in one line
    created = [d for d in (out, out / "videos") if not d.exists()]
    video_path.parent.mkdir(parents=True, exist_ok=True)
    try:
        with _user_errors():
            frames = record_video(source, n_frames=n_frames, duration=args.duration, fps=args.fps,
                                  size=tuple(args.size) if args.size else None, path=video_path,
                                  warmup=args.warmup)
    except BaseException:
        for folder in reversed(created):  # a missing camera leaves nothing behind
            with contextlib.suppress(OSError):
                folder.rmdir()
        raise
    _append_manifest_row(out / "manifest.csv", columns, row)
    print(f"recorded {len(frames)} frames of {frames.shape[2]}x{frames.shape[1]} to {video_path}")
    print(f"appended to {out / 'manifest.csv'}: {row}")
    if args.quiet:
        return 0
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        s = ContactFrameSelector().select([frames])
    if s.contact_found[0]:
        print(f"contact selection: {s.status[0]} from frame {s.contact_start[0]} to {s.contact_peak[0]}")
    else:
        print(f"contact selection: {s.status[0]} -- check the press (sklearn-hardness select {out / 'manifest.csv'} --plot curves.png)")
    return 0


def _quick_help():
    from ._experiment_names import QUICK_OVERRIDES  # no torch: --help stays fast

    return ("a first look in a few minutes on 2 cores; changes: "
            + ", ".join(f"{k}={v}" for k, v in QUICK_OVERRIDES.items())
            + " (smaller simulated images and frames, fewer epochs, MC passes and runs)")


def _strategies_help():
    from ._experiment_names import STRATEGIES

    return f"strategies to compare (default: {' '.join(STRATEGIES)})"


def _config_keys_epilog():
    """The ``--set`` keys with their meaning, from the table that also writes get_config's docstring."""
    from ._experiment_names import KEY_HELP

    width = max(map(len, KEY_HELP))
    return "configuration keys for --set (sklearn_hardness.experiments.get_config):\n" + "\n".join(
        f"  {key:<{width}}  {meaning}" for key, meaning in KEY_HELP.items())


_README_START = "<!-- reproduce-quick-table: start -->"
_README_END = "<!-- reproduce-quick-table: end -->"
_README_PROVENANCE = ("command", "config_hash", "code_fingerprint")


def _readme_block(path):
    """The text of ``path`` and the offsets of its table markers (a usage error if it has none)."""
    try:
        with open(path) as f:
            text = f.read()
    except OSError as exc:
        raise _UsageError(f"cannot read --readme {path!r}: {exc.strerror or exc}") from exc
    start, end = text.find(_README_START), text.find(_README_END)
    if start < 0 or end < start:
        raise _UsageError(f"{path} has no '{_README_START}' ... '{_README_END}' block to write the table into")
    return text, start, end


def _write_readme_table(path, table, provenance=None):
    """Replace the block between the README markers by ``table`` (in a code fence).

    ``provenance`` (a dict: command, config hash, code fingerprint) goes on an HTML
    comment line above the fence; machine and date stay out, so rerunning unchanged
    code with the same table leaves the file alone.
    """
    text, start, end = _readme_block(path)
    comment = f"\n<!-- provenance {json.dumps(provenance)} -->" if provenance else ""
    new = text[: start + len(_README_START)] + comment + "\n```\n" + table + "\n```\n" + text[end:]
    if new != text:
        with open(path, "w") as f:
            f.write(new)
    return new != text


def _add_reproduce(sub):
    p = sub.add_parser(
        "reproduce",
        help="run the paper's active-sampling experiment and print its comparison table",
        description=textwrap.fill(
            "Run the active-sampling experiment of the paper (Algorithm 1, Sec. III) on the "
            "built-in simulator (or on your recordings with --dataset), print the comparison table "
            "(no resampling, variance, entropy, random, BALD, and the paper's human accuracy) and write "
            "figures and the results file to --out. Every finished run is appended to "
            "OUT/results.jsonl: rerun the same command to resume after an interruption (SIGINT or "
            "SIGTERM stops the workers and keeps every finished run).", 78),
        epilog=_config_keys_epilog,
        formatter_class=argparse.RawDescriptionHelpFormatter,
    )
    p.add_argument("--preset", default="silicone5", choices=["silicone5", "shore9"],
                   help="the paper's setup: silicone5 (robot data, ConvLSTM, e0=100, e=50, M=40) or "
                   "shore9 (Yuan's data, DINOv2NN, e0=50, e=25, M=80). Default silicone5.")
    p.add_argument("--dataset", default=None,
                   help="manifest CSV of real recordings (see load_press_videos; with an object_id "
                   "column and several objects per class the runs are object-disjoint) or 'everyday' "
                   "(simulated everyday objects); default: the simulator with the preset's objects")
    p.add_argument("--model", default=None, choices=MODEL_NAMES,
                   help="classifier (default: the preset's)")
    p.add_argument("--dinov2-model", default=None,
                   help="DINOv2 weights for dinov2nn: a Hugging Face id in the local cache or a local "
                   "directory (default facebook/dinov2-small)")
    p.add_argument("--out", default="hardness_results", help="output folder (default ./hardness_results)")
    p.add_argument("--quick", action="store_true", help=_quick_help)
    p.add_argument("--n-runs", type=_positive_int, default=None,
                   help="seeds per test object (default: the preset's)")
    p.add_argument("--seeds", type=_nonnegative_int, nargs="+", default=None, metavar="SEED",
                   help="explicit seeds per test object instead of 0..n_runs-1, e.g. --seeds $(seq 100 159) "
                   "for runs on splits never run before")
    p.add_argument("--test-objects", nargs="+", default=None, metavar="OBJECT_ID",
                   help="object-disjoint datasets (everyday, a manifest with object_id): the objects that "
                   "serve as test object (default: every object of a class with two or more)")
    p.add_argument("--n-jobs", type=_n_jobs, default=None, help=_n_jobs_help(1))
    p.add_argument("--strategies", nargs="+", default=None, help=_strategies_help)
    p.add_argument("--epochs", type=_positive_int, nargs=2, default=None, metavar=("E0", "E"),
                   help="initial epochs and epochs per iteration (override)")
    p.add_argument("--set", nargs="+", default=[], metavar="KEY=VALUE",
                   help="override any configuration key, e.g. --set n_iterations=3 max_reservoir=60 "
                   "frame_size=(24,32); the keys are listed below")
    p.add_argument("--protocol", default="active", choices=["active", "paper"],
                   help="active (default): the active-sampling experiment of --preset. paper: the whole "
                   "protocol, resumable into --out: model baselines, the dropout sweep and active sampling "
                   "with every strategy at the paper's settings with the ConvLSTM, on silicone5 (10 seeds x "
                   "5 objects) and shore9 (5 seeds x 9 objects; DINOv2NN baseline too with --dinov2-model), "
                   "with 95%% paired "
                   "intervals and p-values against random and accuracy on held-out presses of every "
                   "object; writes OUT/summary.txt")
    p.add_argument("--readme", default=None, metavar="PATH",
                   help="write the comparison table into PATH (a README) between the lines "
                   f"'{_README_START}' and '{_README_END}'; README.md's table is made with "
                   "'reproduce --quick --n-jobs 2 --readme README.md'")
    _add_quiet(p, "progress (by default a line per finished run with elapsed time and an estimate of "
               "the rest goes to stderr)")
    return p


def _run_paper_protocol(args, config):
    import time

    from .experiments._protocol import run_paper_protocol

    t0 = time.time()
    text = run_paper_protocol(args.out, strategies=args.strategies, n_runs=args.n_runs, quick=args.quick,
                              n_jobs=args.n_jobs, verbose=0 if args.quiet else 1,
                              dinov2_model=args.dinov2_model, **config)
    print(text)
    print(f"wrote results.jsonl and summary.txt to {args.out} ({time.time() - t0:.0f} s)")
    return 0


def _parse_set(items):
    """``--set`` items as a dict; values are Python literals where they parse, else strings."""
    import ast

    out = {}
    for item in items:
        key, sep, value = item.partition("=")
        if not sep or not key:
            raise _UsageError(f"--set expects KEY=VALUE, got {item!r}")
        try:
            out[key] = ast.literal_eval(value)
        except (ValueError, SyntaxError):
            out[key] = value  # a plain string
    return out


def _reproduce_config(args):
    """The configuration overrides of ``reproduce``, every input checked before anything is written."""
    from .datasets import load_press_videos
    from .experiments import STRATEGIES
    from .experiments._active import _check_strategies
    from .experiments._config import check_config, get_config
    from .experiments._data import load_dataset

    if args.protocol == "paper" and (args.dataset or args.model):
        raise _UsageError("--protocol paper runs the simulator presets with their models; it takes no "
                          "--dataset or --model (use --protocol active for those)")
    if args.protocol == "paper" and args.test_objects:
        raise _UsageError("--protocol paper runs the simulator presets; it takes no --test-objects")
    if args.protocol == "paper" and args.seeds:
        raise _UsageError("--protocol paper runs seeds 0..n_runs-1; it takes no --seeds (use --protocol active)")
    if args.strategies is None:
        args.strategies = list(STRATEGIES)
    config = _parse_set(args.set)
    if args.epochs:
        config["initial_epochs"], config["epochs_per_query"] = args.epochs
    if args.readme:
        _readme_block(args.readme)
    _check_out_dir(args.out)
    presets = ["silicone5", "shore9"] if args.protocol == "paper" else [args.preset]
    with _user_errors():
        _check_strategies(args.strategies)
        for preset in presets:
            overrides = dict(config, model=args.model) if args.model else config
            check_config(get_config(preset, quick=args.quick, **overrides))
        if args.dataset and args.dataset not in _SIM_PRESETS:
            load_press_videos(args.dataset)  # reads the manifest and checks its files, no video
        if args.test_objects:
            # object ids only: the videos of a preset or manifest are loaded lazily
            cfg = get_config(args.preset, quick=args.quick, **config)
            ids = load_dataset(args.dataset or args.preset, cfg).get("object_id")
            unknown = sorted(set(args.test_objects) - set(map(str, [] if ids is None else ids)))
            if unknown:
                raise _UsageError(f"--test-objects {unknown} are not object ids of the dataset")
    if args.dinov2_model and args.protocol != "paper":
        config["dinov2_model"] = args.dinov2_model
    return config



_NOT_RESULTS = {"--out": 1, "--readme": 1, "--quiet": 0}  # options that do not change a table


def _reproduce_command(argv):
    """The command as a user would type it, less where its output goes."""
    kept, skip = [], 0
    for a in argv:
        if skip:
            skip -= 1
        elif a.split("=", 1)[0] in _NOT_RESULTS:
            skip = 0 if "=" in a else _NOT_RESULTS[a]
        else:
            kept.append(a)
    return shlex.join(["sklearn-hardness", *kept])


def _reproduce_config_hash(args):
    """The config hash of a ``reproduce --protocol active`` command (None for the whole protocol)."""
    from .experiments import planned_config_hash

    if args.protocol != "active":
        return None
    config = _reproduce_config(args)
    return planned_config_hash(args.dataset or args.preset, preset=args.preset, model=args.model,
                               n_runs=args.n_runs, quick=args.quick, **config)


def _run_reproduce(args):
    import time

    from .experiments import (
        comparison_table,
        format_paired_table,
        format_presses_to_reach,
        format_table,
        paired_table,
        parse_provenance,
        presses_to_reach,
        provenance_header,
        run_active_sampling,
        save_figures,
    )

    config = _reproduce_config(args)
    if args.protocol == "paper":
        return _run_paper_protocol(args, config)
    os.makedirs(args.out, exist_ok=True)
    results_path = os.path.join(args.out, "results.jsonl")
    t0 = time.time()
    result = run_active_sampling(
        args.dataset if args.dataset else args.preset,
        preset=args.preset,
        model=args.model,
        strategies=args.strategies,
        n_runs=args.n_runs,
        seeds=args.seeds,
        test_objects=args.test_objects,
        quick=args.quick,
        n_jobs=args.n_jobs,
        results_path=results_path,
        memory=os.path.join(args.out, "cache"),
        verbose=0 if args.quiet else 1,
        **config,
    )
    cfg = result.config
    rows = comparison_table(result)
    n_it = cfg["n_iterations"]
    table = format_table(rows, mae_unit=cfg.get("hardness_unit"))
    header = (
        f"{cfg['dataset']} ({cfg['preset']} settings, {cfg['protocol']} protocol): {cfg['model']}, "
        f"s0={cfg['n_initial']}, s={cfg['n_per_query']}, N={n_it}, "
        f"e0={cfg['initial_epochs']}, e={cfg['epochs_per_query']}, M={cfg['max_reservoir']}, "
        f"dropout={cfg['dropout']}, n_test={cfg['n_test']}, MC passes={cfg['n_mc_samples']}"
        + (f", frames={cfg['frame_size'][0]}x{cfg['frame_size'][1]}" if cfg.get("frame_size") else "")
        + (f", early stopping={cfg['early_stopping']}" if cfg.get("early_stopping") else ", every epoch")
        + (" [quick]" if args.quick else "")
    )
    note = (
        f"Accuracy and MAE after {n_it} iterations (no resampling: after the initial training), mean +- "
        "std over converged runs; runs = converged/total. Humans: the paper's study (Sec. III-G), "
        "a constant reference, not measured here."
    )
    print(header)
    print(table)
    print(note)
    command = _reproduce_command(getattr(args, "argv", None) or sys.argv[1:])
    provenance = provenance_header(command, config_hash=cfg["config_hash"])
    with open(os.path.join(args.out, "table.txt"), "w") as f:
        f.write(provenance + "\n" + header + "\n" + table + "\n" + note + "\n")
    if "random" in cfg["strategies"] and len(cfg["strategies"]) > 1:
        # strategies on the same (test object, seed) pairs, against random; what a robot user
        # wants first: presses to reach random's accuracy, then presses and accuracy at the stop
        paired = format_presses_to_reach(presses_to_reach(result)) + (
            "\nPresses to reach random's final accuracy: the first press count at which a strategy's mean "
            "test accuracy over the pairs is at least random's mean final accuracy (experiments."
            "presses_to_reach; 95% bootstrap intervals over the pairs; never: not within the budget)."
        ) + "\n\n" + format_paired_table(paired_table(result)) + (
            "\nConverged runs; differences and p-values over the pairs where both runs converged. "
            "presses_at_stop / accuracy_at_stop: reference presses used and test accuracy when the "
            "vote of the test presses is settled (experiments.decision_stop: 80% agree, 2 iterations); "
            "accuracy: on the test object's presses after the budget; holdout_accuracy: on held-out "
            "presses of other objects."
        )
        print(paired)
        with open(os.path.join(args.out, "paired.txt"), "w") as f:
            f.write(provenance + "\n" + header + "\n" + paired + "\n")
    if args.readme:
        record = parse_provenance(provenance)
        changed = _write_readme_table(args.readme, table, {k: record[k] for k in _README_PROVENANCE})
        print(f"{'updated' if changed else 'unchanged'}: the table in {args.readme}")
    with open(os.path.join(args.out, "config.json"), "w") as f:
        json.dump({k: v for k, v in cfg.items()}, f, indent=2, default=repr)
    paths = save_figures(result, args.out)
    extra = "paired.txt, " if os.path.exists(os.path.join(args.out, "paired.txt")) else ""
    print(f"wrote {results_path}, table.txt, {extra}config.json and {len(paths)} figures to {args.out} "
          f"({time.time() - t0:.0f} s)")
    return 0


#: Names the parser offers without importing the library (tests check them against it); the
#: experiments' model and pipeline names come from _experiment_names, which the library imports too.
_SIM_PRESETS = ("everyday", "shore9", "silicone5")  # datasets.make_presses

_SIM_FORMATS = {"avi": ".avi", "mp4": ".mp4", "png": "", "npy": ".npy"}


def _add_simulate(sub):
    p = sub.add_parser(
        "simulate",
        help="simulate GelSight press videos and write them with a manifest",
        description="Simulate a press dataset with sklearn_hardness.datasets.make_presses and write "
        "one video per press, per-frame force and timestamps (.npy) and a manifest.csv that "
        "sklearn_hardness.datasets.load_press_videos reads back. Default format: lossless FFV1 "
        "in .avi (bit-exact round trip); mp4 uses the lossy MPEG-4 'mp4v' codec.",
    )
    p.add_argument("--preset", default="silicone5", choices=_SIM_PRESETS,
                   help="silicone5 (default), shore9 or everyday")
    p.add_argument("--out", required=True, help="output folder (created)")
    p.add_argument("--n-per-class", type=_positive_int, default=None,
                   help="presses per object (default: the preset's)")
    p.add_argument("--seed", type=_nonnegative_int, default=0, help="random seed (default 0)")
    p.add_argument("--image-size", type=_positive_int, nargs=2, metavar=("H", "W"), default=(240, 320),
                   help="frame height and width (default 240 320)")
    p.add_argument("--format", choices=sorted(_SIM_FORMATS), default="avi",
                   help="avi: lossless FFV1 (default); mp4: lossy mp4v; png: a folder of PNGs per "
                   "press; npy: raw arrays")
    p.add_argument("--no-markers", action="store_true", help="simulate a gel without markers "
                   "(everyday is marker-less anyway)")
    p.add_argument("--codec", default="auto", help="pass frames through a lossy codec before writing: "
                   "mp4v, avc1 (H.264, where OpenCV has it), mjpg, none; default auto (mp4v for everyday)")
    p.add_argument("--n-jobs", type=_n_jobs, default=1, help=_n_jobs_help("1") + " (video writers)")
    _add_quiet(p, "progress bar and summary line")
    return p


def _write_presses(videos, names, root, ext, fps):
    from .io import write_video

    for i, name in zip(range(len(videos)), names):
        write_video(root / "videos" / f"{name}{ext}", videos[i], fps=fps)


def _run_simulate(args):
    import csv
    from pathlib import Path

    import numpy as np
    from joblib import Parallel, delayed
    from tqdm.auto import tqdm

    from .datasets import make_presses

    _check_out_dir(args.out)
    codec = None if args.codec.lower() == "none" else args.codec
    with _user_errors():  # an unknown preset, codec or size: before any folder is made
        data = make_presses(args.preset, args.n_per_class, markers=False if args.no_markers else None,
                            image_size=tuple(args.image_size), codec=codec, random_state=args.seed)
    root = Path(args.out)
    for sub in ("videos", "force", "timestamps"):
        (root / sub).mkdir(parents=True, exist_ok=True)
    n = len(data.videos)
    names = [f"press_{i:04d}" for i in range(n)]
    ext = _SIM_FORMATS[args.format]
    chunks = [c for c in np.array_split(np.arange(n), max(1, min(n, 4 * max(args.n_jobs, 1)))) if len(c)]
    jobs = Parallel(n_jobs=args.n_jobs, return_as="generator")(
        delayed(_write_presses)(data.videos[c], [names[i] for i in c], root, ext, data.fps)
        for c in chunks
    )
    with tqdm(total=n, unit="video", desc=f"simulate {args.preset}", disable=True if args.quiet else None) as bar:
        for c, _ in zip(chunks, jobs):
            bar.update(len(c))
    pp = data.press_params
    extra = ["F_push", "v_push", "compliance_object", "force_peak"]
    with open(root / "manifest.csv", "w", newline="") as f:
        w = csv.writer(f)
        w.writerow(["path", "label", "hardness", "hardness_unit", "object_id", "force_path",
                    "timestamps_path", "fps"] + extra)
        for i, name in enumerate(names):
            np.save(root / "force" / f"{name}.npy", data.force[i])
            np.save(root / "timestamps" / f"{name}.npy", data.timestamps[i])
            t = data.target[i]
            w.writerow([f"videos/{name}{ext}", data.target_names[t], repr(float(data.hardness[t])),
                        data.hardness_unit, data.object_id[i], f"force/{name}.npy",
                        f"timestamps/{name}.npy", f"{data.fps:g}"]
                       + [f"{pp[k][i]:.6g}" for k in extra])
    codec = {"avi": "FFV1, lossless", "mp4": "mp4v, lossy", "png": "PNG, lossless", "npy": "raw"}
    if not args.quiet:
        print(f"wrote {n} videos ({codec[args.format]}) and {root / 'manifest.csv'}")
    return 0


def _add_evaluate(sub):
    p = sub.add_parser(
        "evaluate",
        help="object-disjoint cross-validation of pipelines on your recordings or a preset",
        description="Cross-validate pipelines with folds grouped by object_id (no test object is "
        "seen in training), print balanced accuracy and hardness MAE per pipeline beside the "
        "one-number baseline (peak change to the first frame + balanced logistic regression), and "
        "save a confusion-matrix figure.",
    )
    p.add_argument("dataset", help="a manifest.csv (or its folder), or a simulator preset "
                   f"({', '.join(_SIM_PRESETS)})")
    p.add_argument("--pipelines", nargs="*", default=list(DEFAULT_PIPELINES), choices=PIPELINE_NAMES,
                   metavar="NAME", help=f"among {', '.join(PIPELINE_NAMES)} (default: {' '.join(DEFAULT_PIPELINES)}); "
                   "the peak_change baseline is always added")
    p.add_argument("--cv", type=_int_type(2, what="an integer >= 2"), default=5,
                   help="number of object-disjoint folds (default 5)")
    p.add_argument("--out", default="hardness_evaluation",
                   help="folder for evaluation.json and confusion_matrices.png (default ./hardness_evaluation)")
    p.add_argument("--seed", type=_nonnegative_int, default=0, help="seed of the folds and of a preset (default 0)")
    p.add_argument("--n-jobs", type=_n_jobs, default=None, help=_n_jobs_help(1) + " (folds in parallel)")
    _add_quiet(p, "start line and summary of the files written")
    return p


def _run_evaluate(args):
    import json
    from pathlib import Path

    import numpy as np

    from .experiments import (
        evaluate_pipelines,
        format_evaluation,
        parse_provenance,
        plot_confusion_matrices,
        provenance_header,
    )

    _check_out_dir(args.out)
    if args.dataset not in _SIM_PRESETS and not os.path.exists(args.dataset):
        raise _UsageError(f"dataset {args.dataset!r} is neither a simulator preset ({', '.join(_SIM_PRESETS)}) "
                          "nor an existing manifest (a .csv file, or a folder holding manifest.csv)")
    if not args.quiet:
        print(f"evaluating {', '.join(args.pipelines) or 'the baseline'} on {args.dataset} "
              f"({args.cv} object-disjoint folds) ...", file=sys.stderr, flush=True)
    with _user_errors():
        result = evaluate_pipelines(args.dataset, args.pipelines, cv=args.cv, error_score=np.nan,
                                    n_jobs=args.n_jobs, random_state=args.seed)
    table = format_evaluation(result)
    print(table)
    out = Path(args.out)
    out.mkdir(parents=True, exist_ok=True)
    # what made the table: the command (less where its output goes), code fingerprint, machine
    provenance = provenance_header(_reproduce_command(getattr(args, "argv", None) or sys.argv[1:]))
    (out / "evaluation.txt").write_text(provenance + "\n" + table + "\n")
    plot_confusion_matrices(result, out / "confusion_matrices.png")
    rows = [{k: (list(v) if isinstance(v, tuple) else v) for k, v in r.items()} for r in result.table]
    (out / "evaluation.json").write_text(json.dumps(
        {"table": rows, "fold_scores": {k: v.tolist() for k, v in result.fold_scores.items()},
         "target_names": result.target_names.tolist(), "provenance": parse_provenance(provenance)}, indent=1))
    if not args.quiet:
        print(f"wrote {out / 'evaluation.txt'}, {out / 'confusion_matrices.png'} and {out / 'evaluation.json'}",
              file=sys.stderr)
    return 0


def _add_benchmark(sub):
    p = sub.add_parser(
        "benchmark",
        help="time one active-sampling run (wall, CPU, peak memory, accuracy)",
        description="Prepare the frames of all presses of a preset, then run one active-sampling run "
        "with the preset's hyperparameters and print its wall time, CPU time, peak memory and accuracy "
        "per iteration. benchmarks/bench_active_sampling.py has more (paired seeds, confidence intervals).",
    )
    p.add_argument("--preset", default="silicone5", choices=["silicone5", "shore9"],
                   help="the paper's setup whose presses and hyperparameters are used (default silicone5)")
    p.add_argument("--model", default=None, choices=MODEL_NAMES,
                   help="classifier (default: the preset's)")
    p.add_argument("--strategy", default="variance",
                   help="query strategy: variance (default), entropy, random or bald")
    p.add_argument("--quick", action="store_true", help="the reproduce --quick settings")
    p.add_argument("--threads", type=_positive_int, default=None, help="torch threads (default: torch's)")
    p.add_argument("--set", nargs="+", default=[], metavar="KEY=VALUE",
                   help="configuration overrides, as for reproduce (its --help lists the keys)")
    _add_quiet(p, "messages (benchmark prints only its report)")
    return p


def _run_benchmark(args):
    from .experiments._active import _check_strategies
    from .experiments._benchmark import time_active_sampling_run
    from .experiments._config import check_config, get_config

    config = _parse_set(args.set)
    with _user_errors():
        _check_strategies([args.strategy])
        overrides = dict(config, model=args.model) if args.model else config
        check_config(get_config(args.preset, quick=args.quick, **overrides))
    rep = time_active_sampling_run(args.preset, model=args.model, strategy=args.strategy, quick=args.quick,
                                   n_threads=args.threads, **config)
    cfg, r = rep["config"], rep["record"]
    print(f"{args.preset}: {cfg['model']}, strategy {args.strategy}, e0={cfg['initial_epochs']} "
          f"e={cfg['epochs_per_query']} M={cfg['max_reservoir']} N={cfg['n_iterations']} "
          f"MC={cfg['n_mc_samples']}, torch threads {rep['torch_threads']}" + (" [quick]" if args.quick else ""))
    print(f"prepare all presses  {rep['prepare_s']:8.1f} s")
    print(f"one run              {rep['run_wall_s']:8.1f} s wall, {rep['run_cpu_s']:.1f} s CPU; "
          f"peak RSS {rep['peak_rss_mib']:.0f} MiB")
    print(f"converged {r['converged']} (initial loss {r['initial_train_loss']:.3f}); accuracy per iteration "
          f"{[round(a, 2) for a in r['accuracy']]}; queried {r['queried']}")
    return 0


def _add_cache(sub):
    p = sub.add_parser(
        "cache",
        help="show or clear the cache of prepared inputs (selected frames, features)",
        description="The experiments cache the selected frames and frozen features of a dataset as "
        "inputs-*.npz files, keyed by the dataset (for a manifest: the manifest and the size and "
        "modification time of every video it lists), the transform parameters and the code. reproduce "
        "caches in OUT/cache; the functions default to $SKLEARN_HARDNESS_CACHE or "
        "~/.cache/sklearn_hardness. Without --clear, list the cached files.",
    )
    p.add_argument("--out", default=None,
                   help="the --out folder of reproduce (its cache is OUT/cache); default: the functions' cache")
    p.add_argument("--clear", action="store_true", help="delete the cached inputs")
    _add_quiet(p, "listing")
    return p


def _run_cache(args):
    from .experiments._data import clear_cache, default_cache_dir

    folder = os.path.join(args.out, "cache") if args.out is not None else default_cache_dir()
    if args.out is not None and not os.path.isdir(args.out):
        raise _UsageError(f"--out {args.out!r} is not a folder")
    if args.clear:
        removed = clear_cache(folder)
        if not args.quiet:
            print(f"removed {len(removed)} cached input file(s) from {folder}")
        return 0
    names = sorted(n for n in os.listdir(folder) if n.startswith("inputs-")) if os.path.isdir(folder) else []
    if not args.quiet:
        size = sum(os.path.getsize(os.path.join(folder, n)) for n in names)
        print(f"{folder}: {len(names)} cached input file(s), {size / 2**20:.1f} MiB")
        for name in names:
            print(f"  {name}")
    return 0


_SUBCOMMANDS = {
    "select": (_add_select, _run_select),
    "record": (_add_record, _run_record),
    "simulate": (_add_simulate, _run_simulate),
    "reproduce": (_add_reproduce, _run_reproduce),
    "benchmark": (_add_benchmark, _run_benchmark),
    "evaluate": (_add_evaluate, _run_evaluate),
    "cache": (_add_cache, _run_cache),
}


def build_parser():
    """Return the argument parser of the ``sklearn-hardness`` command."""
    parser = _Parser(
        prog="sklearn-hardness",
        description="Hardness classification from vision-based tactile sensor videos.",
    )
    parser.add_argument("--version", action="version", version=f"%(prog)s {__version__}")
    sub = parser.add_subparsers(dest="command", metavar="COMMAND")
    for name, (add, _) in _SUBCOMMANDS.items():
        add(sub).set_defaults(_command_parser=sub.choices[name])
    return parser


def _raise_interrupt(signum, frame):
    raise KeyboardInterrupt(signal.Signals(signum).name)


@contextlib.contextmanager
def _sigterm_as_interrupt():
    """SIGTERM raises KeyboardInterrupt, like SIGINT: joblib then stops its workers and the
    results file keeps every finished run (each is one fsync-ed line)."""
    try:
        previous = signal.signal(signal.SIGTERM, _raise_interrupt)
    except ValueError:  # not the main thread: leave signals alone
        yield
        return
    try:
        yield
    finally:
        signal.signal(signal.SIGTERM, previous)


def main(argv=None):
    """Entry point of the ``sklearn-hardness`` console script."""
    parser = build_parser()
    args = parser.parse_args(argv)
    args.argv = list(sys.argv[1:] if argv is None else argv)  # for the provenance of what it writes
    if args.command is None:
        parser.print_help()
        return 2
    _, run = _SUBCOMMANDS[args.command]
    try:
        with _sigterm_as_interrupt():
            return run(args)
    except _UsageError as exc:
        args._command_parser.error(str(exc))
    except KeyboardInterrupt as exc:
        name = str(exc) or "SIGINT"
        print(f"{args._command_parser.prog}: interrupted ({name}); finished work is kept, rerun the same "
              "command to resume", file=sys.stderr)
        return 128 + int(getattr(signal, name, signal.SIGINT))


if __name__ == "__main__":  # pragma: no cover
    sys.exit(main())
