"""``sklearn-hardness cache``: how much the cache of per-press rows holds, or clear it."""

from __future__ import annotations

import os

from ._common import _add_quiet, _UsageError


def _add_cache(sub):
    p = sub.add_parser(
        "cache",
        help="show or clear the cache of per-press rows (selected frames, features)",
        description="The per-press steps (frame selection, features, the peak change) cache each press's "
        "rows, keyed by the step's parameters, the code that computes them and the press (a video file by "
        "its path, size and modification time). reproduce caches in OUT/cache; the functions default to "
        "$SKLEARN_HARDNESS_CACHE or ~/.cache/sklearn_hardness. A press's entry is under 1 kB of features, "
        "or its selected frames (12 kB at 18x24 pixels). Without --clear, say how much the cache holds.",
    )
    p.add_argument("--out", default=None,
                   help="the --out folder of reproduce (its cache is OUT/cache); default: the functions' cache")
    p.add_argument("--clear", action="store_true", help="delete the cached rows")
    _add_quiet(p, "listing")
    return p


def _run_cache(args):
    from ..utils import clear_cache, default_cache_dir
    from ..utils._per_press import cache_size

    folder = os.path.join(args.out, "cache") if args.out is not None else default_cache_dir()
    if args.out is not None and not os.path.isdir(args.out):
        raise _UsageError(f"--out {args.out!r} is not a folder")
    if args.clear:
        n_rows, _ = cache_size(folder)
        clear_cache(folder)
        if not args.quiet:
            print(f"removed {n_rows} cached press row(s) from {folder}")
        return 0
    if not args.quiet:
        n_rows, n_bytes = cache_size(folder)
        print(f"{folder}: {n_rows} cached press row(s), {n_bytes / 2**20:.1f} MiB")
    return 0
