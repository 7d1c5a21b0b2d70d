"""``sklearn-hardness cache``: list or clear the cached inputs of the experiments."""

from __future__ import annotations

import os

from ._common import _add_quiet, _UsageError


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
    from ..experiments import clear_cache, default_cache_dir

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
