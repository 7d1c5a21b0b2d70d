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
        flag = "" if selection.contact_found[i] else "  (no contact: fallback)"
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


_SUBCOMMANDS = {
    "select": (_add_select, _run_select),
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
