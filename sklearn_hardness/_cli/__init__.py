"""The ``sklearn-hardness`` command line.

Each subcommand lives in its own module (``_select``, ``_record``,
``_reproduce``, ``_simulate``, ``_evaluate``, ``_cache``) as an ``_add_<name>`` /
``_run_<name>`` pair registered in :data:`_SUBCOMMANDS`; what they share is in
``_common``, the header line of their outputs in ``_header``.

Building the parser imports nothing heavy (no torch, skorch or scikit-learn):
``--help`` and ``--version`` answer at once, and help texts that name values of
the experiments (strategies, ``--set`` keys) are filled in only when shown.
A user error is one line ``sklearn-hardness <command>: error: ...`` on stderr
with exit status 2, found before anything is written.
"""

from __future__ import annotations

import contextlib
import signal
import sys

from .. import __version__
from ._cache import _add_cache, _run_cache
from ._common import _Parser, _UsageError
from ._evaluate import _add_evaluate, _run_evaluate
from ._record import _add_record, _run_record
from ._reproduce import _add_reproduce, _run_reproduce
from ._select import _add_select, _run_select
from ._simulate import _add_simulate, _run_simulate

__all__ = ["build_parser", "main"]

_SUBCOMMANDS = {
    "select": (_add_select, _run_select),
    "record": (_add_record, _run_record),
    "simulate": (_add_simulate, _run_simulate),
    "reproduce": (_add_reproduce, _run_reproduce),
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
