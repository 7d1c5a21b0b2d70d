"""``sklearn-hardness simulate``: simulated press videos written with a manifest."""

from __future__ import annotations

from ._common import (
    _SIM_PRESETS,
    _add_quiet,
    _check_out_dir,
    _n_jobs,
    _n_jobs_help,
    _nonnegative_int,
    _positive_int,
    _user_errors,
)

_SIM_FORMATS = {"avi": ".avi", "mp4": ".mp4", "png": "", "npy": ".npy"}


def _add_simulate(sub):
    p = sub.add_parser(
        "simulate",
        help="simulate GelSight press videos and write them with a manifest",
        description="Simulate a press dataset with sklearn_hardness.datasets.make_presses and write "
        "one video per press, per-frame force, timestamps and sensor position (.npy) and a manifest.csv that "
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
    from ..io import write_video

    for i, name in zip(range(len(videos)), names):
        write_video(root / "videos" / f"{name}{ext}", videos[i], fps=fps)


def _run_simulate(args):
    import csv
    from pathlib import Path

    import numpy as np
    from joblib import Parallel, delayed

    from ..datasets import make_presses
    from ..utils._progress import progress_bar

    _check_out_dir(args.out)
    codec = None if args.codec.lower() == "none" else args.codec
    with _user_errors():  # an unknown preset, codec or size: before any folder is made
        data = make_presses(args.preset, args.n_per_class, markers=False if args.no_markers else None,
                            image_size=tuple(args.image_size), codec=codec, random_state=args.seed)
    root = Path(args.out)
    for sub in ("videos", "force", "timestamps", "position"):
        (root / sub).mkdir(parents=True, exist_ok=True)
    n = len(data.videos)
    names = [f"press_{i:04d}" for i in range(n)]
    ext = _SIM_FORMATS[args.format]
    chunks = [c for c in np.array_split(np.arange(n), max(1, min(n, 4 * max(args.n_jobs, 1)))) if len(c)]
    jobs = Parallel(n_jobs=args.n_jobs, return_as="generator")(
        delayed(_write_presses)(data.videos[c], [names[i] for i in c], root, ext, data.fps)
        for c in chunks
    )
    with progress_bar(total=n, unit="video", desc=f"simulate {args.preset}", enabled=not args.quiet) as bar:
        for c, _ in zip(chunks, jobs):
            bar.update(len(c))
    pp = data.press_params
    extra = ["F_push", "v_push", "compliance_object", "force_peak"]
    with open(root / "manifest.csv", "w", newline="") as f:
        w = csv.writer(f)
        w.writerow(["path", "label", "hardness", "hardness_unit", "object_id", "force_path",
                    "timestamps_path", "position_path", "fps"] + extra)
        for i, name in enumerate(names):
            np.save(root / "force" / f"{name}.npy", data.force[i])
            np.save(root / "timestamps" / f"{name}.npy", data.timestamps[i])
            np.save(root / "position" / f"{name}.npy", data.position[i])
            t = data.target[i]
            w.writerow([f"videos/{name}{ext}", data.target_names[t], repr(float(data.hardness[t])),
                        data.hardness_unit, data.object_id[i], f"force/{name}.npy",
                        f"timestamps/{name}.npy", f"position/{name}.npy", f"{data.fps:g}"]
                       + [f"{pp[k][i]:.6g}" for k in extra])
    codec = {"avi": "FFV1, lossless", "mp4": "mp4v, lossy", "png": "PNG, lossless", "npy": "raw"}
    if not args.quiet:
        print(f"wrote {n} videos ({codec[args.format]}) and {root / 'manifest.csv'}")
    return 0
