"""``sklearn-hardness select``: contact-frame selection on the videos of a manifest."""

from __future__ import annotations

import os
import sys

from ._common import _add_quiet, _add_roi, _nonnegative_int, _threshold, _UsageError, _user_errors

_SELECT_FORMATS = ("table", "csv", "json")


def _add_select(sub):
    p = sub.add_parser(
        "select",
        help="run contact-frame selection on the videos of a manifest and report what was chosen",
        description="Run ContactFrameSelector on the videos listed in a manifest CSV and print, "
        "per video, the contact start, peak and the selected frame indices (a table, or CSV or "
        "JSON with --format / --output).",
    )
    p.add_argument("manifest", help="CSV manifest, or a folder holding manifest.csv "
                   "(see sklearn_hardness.datasets.load_press_videos)")
    p.add_argument("--n-between", type=_nonnegative_int, default=2,
                   help="frames kept between first and last (default 2)")
    p.add_argument("--threshold", type=_threshold, default="auto",
                   help="contact threshold: 'auto' (default) or a positive number")
    _add_roi(p, "in contact selection")
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

    from ..datasets import load_press_videos
    from ..preprocessing import ContactFrameSelector
    from ..utils._unreadable import raise_unreadable
    from ..utils._validation import check_roi, rename_videos
    from ._manifest import manifest_file

    fmt = _select_format(args)
    with _user_errors():
        roi = check_roi(args.roi)
        data = load_press_videos(manifest_file(args.manifest))  # or a folder holding it, as evaluate takes
    selector = ContactFrameSelector(n_between=args.n_between, threshold=args.threshold, roi=roi,
                                    on_no_contact="fallback")
    with warnings.catch_warnings():
        if args.quiet:
            warnings.simplefilter("ignore")
        try:
            selection = selector.select(data.videos)
        except (ValueError, TypeError, OSError) as exc:
            with _user_errors():  # every video that cannot be read, in one error
                raise_unreadable(data.videos, exc)
                if isinstance(exc, ValueError):  # a press the selection cannot take: name its file
                    raise ValueError(rename_videos(str(exc), lambda i: f"X[{i}] ({data.paths[i]})")) from exc
            raise
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
        from ..preprocessing import plot_contact_selection

        fig = plot_contact_selection(selection, labels=[data.target_names[t] for t in data.target])
        fig.savefig(args.plot, dpi=120)
        if not args.quiet:
            print(f"wrote {args.plot}", file=info)
    return 0
