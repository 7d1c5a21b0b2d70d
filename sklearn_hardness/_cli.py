"""The ``sklearn-hardness`` command line.

Each subcommand lives in its own ``_add_<name>`` / ``_run_<name>`` pair and is
registered in :data:`_SUBCOMMANDS`.
"""

from __future__ import annotations

import argparse
import sys

from . import __version__


def _add_select(sub):
    p = sub.add_parser(
        "select",
        help="run contact-frame selection on the videos of a manifest and report what was chosen",
        description="Run ContactFrameSelector on the videos listed in a manifest CSV and print, "
        "per video, the contact start, peak and the selected frame indices.",
    )
    p.add_argument("manifest", help="CSV manifest (see sklearn_hardness.datasets.load_press_videos)")
    p.add_argument("--n-between", type=int, default=2, help="frames kept between first and last (default 2)")
    p.add_argument("--threshold", default="auto", help="'auto' (default) or a number")
    p.add_argument("--plot", default=None, help="write a PNG of the intensity curves here")
    return p


def _run_select(args):
    import numpy as np

    from .datasets import load_press_videos
    from .preprocessing import ContactFrameSelector

    data = load_press_videos(args.manifest)
    threshold = args.threshold if args.threshold == "auto" else float(args.threshold)
    selector = ContactFrameSelector(n_between=args.n_between, threshold=threshold, on_no_contact="fallback")
    selection = selector.select(data.videos)
    print(f"{'video':>5}  {'label':<12} {'frames':>6}  {'start':>5}  {'peak':>4}  selected")
    for i, idx in enumerate(selection.indices):
        status = selection.status[i]
        flag = "" if status == "contact" else f"  ({status}{'' if selection.contact_found[i] else ': fallback'})"
        print(
            f"{i:>5}  {data.target_names[data.target[i]]:<12} {len(selection.curves[i]):>6}  "
            f"{selection.contact_start[i]:>5}  {selection.contact_peak[i]:>4}  {np.asarray(idx).tolist()}{flag}"
        )
    print(f"contact found in {selection.contact_found.sum()} of {len(selection.indices)} videos")
    if args.plot:
        from .preprocessing import plot_contact_selection

        fig = plot_contact_selection(selection, labels=[data.target_names[t] for t in data.target])
        fig.savefig(args.plot, dpi=120)
        print(f"wrote {args.plot}")
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
    p.add_argument("--n-frames", type=int, default=None,
                   help="frames to record (default 126, 5 s at 25 fps, like GelSight Mini recordings)")
    p.add_argument("--duration", type=float, default=None, help="seconds to record instead of --n-frames")
    p.add_argument("--fps", type=float, default=None, help="frame rate to ask of the camera")
    p.add_argument("--size", type=int, nargs=2, default=None, metavar=("HEIGHT", "WIDTH"),
                   help="frame size (resized if the camera gives another)")
    p.add_argument("--warmup", type=int, default=0, help="frames dropped first while exposure settles")
    p.add_argument("--hardness", default="", help="the label's hardness value, if known")
    p.add_argument("--hardness-unit", default="", help="e.g. 'Shore 00' or 'mm/N'")
    p.add_argument("--format", default="avi", choices=["avi", "mp4", "npy"],
                   help="avi (FFV1, lossless; default), mp4 (mp4v, lossy) or npy")
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

    from .io import record_video
    from .preprocessing import ContactFrameSelector

    source = int(args.source) if args.source.isdigit() else args.source
    n_frames = args.n_frames if args.n_frames is not None or args.duration is not None else 126
    out = Path(args.out)
    (out / "videos").mkdir(parents=True, exist_ok=True)
    stem = "".join(c if c.isalnum() or c in "-_" else "_" for c in f"{args.label}_{args.object_id or args.label}")
    number = 0
    while list((out / "videos").glob(f"{stem}_{number:04d}.*")):
        number += 1
    video_path = out / "videos" / f"{stem}_{number:04d}.{args.format}"
    row = {"path": video_path.relative_to(out).as_posix(), "label": args.label, "hardness": args.hardness,
           "hardness_unit": args.hardness_unit, "object_id": args.object_id or args.label,
           "fps": f"{args.fps:g}" if args.fps else ""}
    columns, row = _manifest_row(out / "manifest.csv", row)  # before recording: no orphan video
    frames = record_video(source, n_frames=n_frames, duration=args.duration, fps=args.fps,
                          size=tuple(args.size) if args.size else None, path=video_path,
                          warmup=args.warmup)
    _append_manifest_row(out / "manifest.csv", columns, row)
    print(f"recorded {len(frames)} frames of {frames.shape[2]}x{frames.shape[1]} to {video_path}")
    print(f"appended to {out / 'manifest.csv'}: {row}")
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        s = ContactFrameSelector().select([frames])
    if s.contact_found[0]:
        print(f"contact selection: {s.status[0]} from frame {s.contact_start[0]} to {s.contact_peak[0]}")
    else:
        print(f"contact selection: {s.status[0]} -- check the press (sklearn-hardness select {out / 'manifest.csv'} --plot curves.png)")
    return 0


def _quick_help():
    from .experiments import QUICK_OVERRIDES

    return ", ".join(f"{k}={v}" for k, v in QUICK_OVERRIDES.items())


_README_START = "<!-- reproduce-quick-table: start -->"
_README_END = "<!-- reproduce-quick-table: end -->"


def _write_readme_table(path, table):
    """Replace the block between the README markers by ``table`` (in a code fence)."""
    with open(path) as f:
        text = f.read()
    start, end = text.find(_README_START), text.find(_README_END)
    if start < 0 or end < start:
        raise SystemExit(f"{path} has no '{_README_START}' ... '{_README_END}' block to write the table into.")
    new = text[: start + len(_README_START)] + "\n```\n" + table + "\n```\n" + text[end:]
    if new != text:
        with open(path, "w") as f:
            f.write(new)
    return new != text


def _add_reproduce(sub):
    from .experiments import STRATEGIES

    p = sub.add_parser(
        "reproduce",
        help="run the paper's active-sampling experiment and print its comparison table",
        description="Run the active-sampling experiment of the paper (Algorithm 1, Sec. III) on the "
        "built-in simulator (or on your recordings with --dataset), print the comparison table "
        "(no resampling, variance, entropy, random, BALD, and the paper's human accuracy) and write "
        "figures and the results file to --out. Every finished run is appended to "
        "OUT/results.jsonl: rerun the same command to resume after an interruption.",
    )
    p.add_argument("--preset", default="silicone5", choices=["silicone5", "shore9"],
                   help="the paper's setup: silicone5 (robot data, ConvLSTM, e0=100, e=50, M=40) or "
                   "shore9 (Yuan's data, DINOv2NN, e0=50, e=25, M=80). Default silicone5.")
    p.add_argument("--dataset", default=None,
                   help="manifest CSV of real recordings (see load_press_videos); default: the "
                   "simulator with the preset's objects")
    p.add_argument("--model", default=None, choices=["convlstm", "ofnn", "dinov2nn"],
                   help="classifier (default: the preset's)")
    p.add_argument("--dinov2-model", default=None,
                   help="DINOv2 weights for dinov2nn: a Hugging Face id in the local cache or a local "
                   "directory (default facebook/dinov2-small)")
    p.add_argument("--out", default="hardness_results", help="output folder (default ./hardness_results)")
    p.add_argument("--quick", action="store_true",
                   help=f"a first look in a few minutes on 2 cores; changes: {_quick_help()} "
                   "(smaller simulated images and frames, fewer epochs, MC passes and runs)")
    p.add_argument("--n-runs", type=int, default=None, help="seeds per test object (default: the preset's)")
    p.add_argument("--seeds", type=int, nargs="+", default=None, metavar="SEED",
                   help="explicit seeds per test object instead of 0..n_runs-1, e.g. --seeds $(seq 100 159) "
                   "for runs on splits never run before")
    p.add_argument("--n-jobs", type=int, default=None,
                   help="parallel runs (joblib; -1: all cores). Default: 1")
    p.add_argument("--strategies", nargs="+", default=list(STRATEGIES),
                   help=f"strategies to compare (default: {' '.join(STRATEGIES)})")
    p.add_argument("--epochs", type=int, nargs=2, default=None, metavar=("E0", "E"),
                   help="initial epochs and epochs per iteration (override)")
    p.add_argument("--set", nargs="+", default=[], metavar="KEY=VALUE",
                   help="override any configuration key, e.g. --set n_iterations=3 max_reservoir=60 "
                   "frame_size=(24,32) (see sklearn_hardness.experiments.get_config)")
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
    p.add_argument("--quiet", action="store_true",
                   help="no progress (by default a line per finished run with elapsed time and an estimate "
                   "of the rest goes to stderr)")
    return p


def _run_paper_protocol(args, config):
    import time

    from .experiments._protocol import run_paper_protocol

    if args.dataset or args.model:
        raise SystemExit("--protocol paper runs the simulator presets with their models; it takes no "
                         "--dataset or --model (use --protocol active for those).")
    if args.seeds:
        raise SystemExit("--protocol paper runs seeds 0..n_runs-1; it takes no --seeds (use --protocol active).")
    t0 = time.time()
    text = run_paper_protocol(args.out, strategies=args.strategies, n_runs=args.n_runs, quick=args.quick,
                              n_jobs=args.n_jobs, verbose=0 if args.quiet else 1,
                              dinov2_model=args.dinov2_model, **config)
    print(text)
    print(f"wrote results.jsonl and summary.txt to {args.out} ({time.time() - t0:.0f} s)")
    return 0


def _parse_set(items):
    import ast

    out = {}
    for item in items:
        key, sep, value = item.partition("=")
        if not sep or not key:
            raise SystemExit(f"--set expects KEY=VALUE, got {item!r}")
        try:
            out[key] = ast.literal_eval(value)
        except (ValueError, SyntaxError):
            out[key] = value  # a plain string
    return out


def _run_reproduce(args):
    import json
    import os
    import time

    from .experiments import (
        comparison_table,
        format_paired_table,
        format_presses_to_reach,
        format_table,
        paired_table,
        presses_to_reach,
        run_active_sampling,
        save_figures,
    )

    config = _parse_set(args.set)
    if args.epochs:
        config["initial_epochs"], config["epochs_per_query"] = args.epochs
    if args.protocol == "paper":
        return _run_paper_protocol(args, config)
    if args.dinov2_model:
        config["dinov2_model"] = args.dinov2_model
    # check the strategies and the configuration before anything is written
    from .experiments._active import _check_strategies
    from .experiments._config import check_config, get_config

    _check_strategies(args.strategies)
    check_config(get_config(args.preset or "silicone5", quick=args.quick, **config))
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
        f"{cfg['preset']}: {cfg['model']}, s0={cfg['n_initial']}, s={cfg['n_per_query']}, N={n_it}, "
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
    with open(os.path.join(args.out, "table.txt"), "w") as f:
        f.write(header + "\n" + table + "\n" + note + "\n")
    if "random" in cfg["strategies"] and len(cfg["strategies"]) > 1:
        # strategies on the same (test object, seed) pairs, against random
        paired = format_paired_table(paired_table(result)) + (
            "\nConverged runs; differences and p-values over the pairs where both runs converged. "
            "presses_at_stop / accuracy_at_stop: reference presses used and test accuracy when the "
            "vote of the test presses is settled (experiments.decision_stop: 80% agree, 2 iterations)."
        ) + "\n\n" + format_presses_to_reach(presses_to_reach(result)) + (
            "\nPresses to reach random's final accuracy: the first press count at which a strategy's mean "
            "test accuracy over the pairs is at least random's mean final accuracy (experiments."
            "presses_to_reach; 95% bootstrap intervals over the pairs; never: not within the budget)."
        )
        print(paired)
        with open(os.path.join(args.out, "paired.txt"), "w") as f:
            f.write(header + "\n" + paired + "\n")
    if args.readme:
        changed = _write_readme_table(args.readme, table)
        print(f"{'updated' if changed else 'unchanged'}: the table in {args.readme}")
    with open(os.path.join(args.out, "config.json"), "w") as f:
        json.dump({k: v for k, v in cfg.items()}, f, indent=2, default=repr)
    paths = save_figures(result, args.out)
    extra = "paired.txt, " if os.path.exists(os.path.join(args.out, "paired.txt")) else ""
    print(f"wrote {results_path}, table.txt, {extra}config.json and {len(paths)} figures to {args.out} "
          f"({time.time() - t0:.0f} s)")
    return 0


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
    p.add_argument("--preset", default="silicone5", help="silicone5 (default), shore9 or everyday")
    p.add_argument("--out", required=True, help="output folder (created)")
    p.add_argument("--n-per-class", type=int, default=None, help="presses per object (default: the preset's)")
    p.add_argument("--seed", type=int, default=0, help="random seed (default 0)")
    p.add_argument("--image-size", type=int, nargs=2, metavar=("H", "W"), default=(240, 320),
                   help="frame height and width (default 240 320)")
    p.add_argument("--format", choices=sorted(_SIM_FORMATS), default="avi",
                   help="avi: lossless FFV1 (default); mp4: lossy mp4v; png: a folder of PNGs per "
                   "press; npy: raw arrays")
    p.add_argument("--no-markers", action="store_true", help="simulate a gel without markers "
                   "(everyday is marker-less anyway)")
    p.add_argument("--codec", default="auto", help="pass frames through a lossy codec before writing: "
                   "mp4v, avc1 (H.264, where OpenCV has it), mjpg, none; default auto (mp4v for everyday)")
    p.add_argument("--n-jobs", type=int, default=1, help="parallel writers (joblib; default 1)")
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

    codec = None if args.codec.lower() == "none" else args.codec
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
    with tqdm(total=n, unit="video", desc=f"simulate {args.preset}") as bar:
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
                   "(everyday, silicone5, shore9)")
    p.add_argument("--pipelines", nargs="*", default=["convlstm", "ofnn"],
                   help="among peak_change, contact_profile, convlstm, ofnn, dinov2nn (default: "
                   "convlstm ofnn); "
                   "the peak_change baseline is always added")
    p.add_argument("--cv", type=int, default=5, help="number of object-disjoint folds (default 5)")
    p.add_argument("--out", default=None, help="folder for confusion_matrices.png and evaluation.json")
    p.add_argument("--seed", type=int, default=0, help="seed of the folds and of a preset (default 0)")
    p.add_argument("--n-jobs", type=int, default=None, help="folds in parallel (joblib)")
    return p


def _run_evaluate(args):
    import json
    from pathlib import Path

    import numpy as np

    from .experiments import evaluate_pipelines, format_evaluation, plot_confusion_matrices

    try:
        result = evaluate_pipelines(args.dataset, args.pipelines, cv=args.cv, error_score=np.nan,
                                    n_jobs=args.n_jobs, random_state=args.seed)
    except (ValueError, FileNotFoundError) as exc:
        print(f"sklearn-hardness evaluate: error: {exc}", file=sys.stderr)
        return 2
    print(format_evaluation(result))
    if args.out is not None:
        out = Path(args.out)
        out.mkdir(parents=True, exist_ok=True)
        plot_confusion_matrices(result, out / "confusion_matrices.png")
        rows = [{k: (list(v) if isinstance(v, tuple) else v) for k, v in r.items()} for r in result.table]
        (out / "evaluation.json").write_text(json.dumps(
            {"table": rows, "fold_scores": {k: v.tolist() for k, v in result.fold_scores.items()},
             "target_names": result.target_names.tolist()}, indent=1))
        print(f"wrote {out / 'confusion_matrices.png'} and {out / 'evaluation.json'}")
    return 0


def _add_benchmark(sub):
    p = sub.add_parser(
        "benchmark",
        help="time one active-sampling run (wall, CPU, peak memory, accuracy)",
        description="Prepare the frames of all presses of a preset, then run one active-sampling run "
        "with the preset's hyperparameters and print its wall time, CPU time, peak memory and accuracy "
        "per iteration. benchmarks/bench_active_sampling.py has more (paired seeds, confidence intervals).",
    )
    p.add_argument("--preset", default="silicone5", choices=["silicone5", "shore9"])
    p.add_argument("--model", default=None, choices=["convlstm", "ofnn", "dinov2nn"])
    p.add_argument("--strategy", default="variance")
    p.add_argument("--quick", action="store_true", help="the reproduce --quick settings")
    p.add_argument("--threads", type=int, default=None, help="torch threads (default: torch's)")
    p.add_argument("--set", nargs="+", default=[], metavar="KEY=VALUE", help="configuration overrides")
    return p


def _run_benchmark(args):
    from .experiments._benchmark import time_active_sampling_run

    rep = time_active_sampling_run(args.preset, model=args.model, strategy=args.strategy, quick=args.quick,
                                   n_threads=args.threads, **_parse_set(args.set))
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


_SUBCOMMANDS = {
    "select": (_add_select, _run_select),
    "record": (_add_record, _run_record),
    "simulate": (_add_simulate, _run_simulate),
    "reproduce": (_add_reproduce, _run_reproduce),
    "benchmark": (_add_benchmark, _run_benchmark),
    "evaluate": (_add_evaluate, _run_evaluate),
}


def build_parser():
    """Return the argument parser of the ``sklearn-hardness`` command."""
    parser = argparse.ArgumentParser(
        prog="sklearn-hardness",
        description="Hardness classification from vision-based tactile sensor videos.",
    )
    parser.add_argument("--version", action="version", version=f"%(prog)s {__version__}")
    sub = parser.add_subparsers(dest="command", metavar="COMMAND")
    for name, (add, _) in _SUBCOMMANDS.items():
        add(sub)
    return parser


def main(argv=None):
    """Entry point of the ``sklearn-hardness`` console script."""
    parser = build_parser()
    args = parser.parse_args(argv)
    if args.command is None:
        parser.print_help()
        return 2
    _, run = _SUBCOMMANDS[args.command]
    return run(args)


if __name__ == "__main__":  # pragma: no cover
    sys.exit(main())
