"""``sklearn-hardness record``: one press from a camera into a folder and its manifest."""

from __future__ import annotations

import contextlib

from ._common import _add_quiet, _float_type, _int_type, _nonnegative_int, _positive_int, _UsageError, _user_errors


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
    p.add_argument("--object-id", default="",
                   help="which physical object was pressed: an id of its own, not reused under another label "
                        "(default: the label)")
    p.add_argument("--n-frames", type=_positive_int, default=None,
                   help="frames to record (default 126, 5 s at 25 fps, like GelSight Mini recordings)")
    p.add_argument("--duration", type=_float_type(), default=None, help="seconds to record instead of --n-frames")
    p.add_argument("--fps", type=_float_type(), default=None, help="frame rate to ask of the camera")
    p.add_argument("--image-size", type=_int_type(2, what="an integer >= 2"), nargs=2, default=None,
                   metavar=("HEIGHT", "WIDTH"), help="frame size (resized if the camera gives another)")
    p.add_argument("--warmup", type=_nonnegative_int, default=0,
                   help="frames dropped first while exposure settles")
    p.add_argument("--hardness", default="", help="the label's hardness value, if known")
    p.add_argument("--hardness-unit", default="", help="e.g. 'Shore 00' or 'mm/N'")
    p.add_argument("--format", default="avi", choices=["avi", "mp4", "npy"],
                   help="avi (FFV1, lossless; default), mp4 (mp4v, lossy) or npy")
    _add_quiet(p, "report of the contact selection")
    return p


def _run_record(args):
    import warnings
    from pathlib import Path

    import cv2

    from ..io import record_video
    from ..preprocessing import ContactFrameSelector
    from ._manifest import append_manifest_row, complete_manifest_row

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
        columns, row = complete_manifest_row(out / "manifest.csv", row)  # before recording: no orphan video
    cv2.utils.logging.setLogLevel(cv2.utils.logging.LOG_LEVEL_ERROR)  # the error below says it in one line
    created = [d for d in (out, out / "videos") if not d.exists()]
    video_path.parent.mkdir(parents=True, exist_ok=True)
    try:
        with _user_errors():
            frames = record_video(source, n_frames=n_frames, duration=args.duration, fps=args.fps,
                                  image_size=tuple(args.image_size) if args.image_size else None, path=video_path,
                                  warmup=args.warmup)
    except BaseException:
        for folder in reversed(created):  # a missing camera leaves nothing behind
            with contextlib.suppress(OSError):
                folder.rmdir()
        raise
    if len(frames) < 2:  # no press: contact selection needs two frames; nothing goes into the manifest
        with contextlib.suppress(OSError):
            video_path.unlink()
        raise _UsageError(f"recorded {len(frames)} frame(s) from {args.source!r}: a press needs at least 2 "
                          "(the source ended early?); nothing was added to the manifest")
    append_manifest_row(out / "manifest.csv", columns, row)
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
        print(f"contact selection: {s.status[0]} -- check the press "
              f"(sklearn-hardness select {out / 'manifest.csv'} --plot curves.png)")
    return 0
