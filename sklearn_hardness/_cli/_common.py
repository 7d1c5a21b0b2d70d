"""What the subcommands of the command line share: the parser, usage errors and argument types.

Nothing here imports more than the standard library: building the parser
must stay fast (``--help`` in well under a second).
"""

from __future__ import annotations

import argparse
import contextlib
import math
import os
import shlex


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


def _add_roi(p, where):
    """``--roi TOP BOTTOM LEFT RIGHT``: the region of the frames read ``where`` (checked by ``check_roi``)."""
    p.add_argument("--roi", nargs=4, type=float, default=None, metavar=("TOP", "BOTTOM", "LEFT", "RIGHT"),
                   help=f"read only this region of the frames {where}, as fractions of height and width (e.g. "
                   "0.18 0.88 0.08 0.70): for sensors whose frame shows more than the gel (default: the "
                   "whole frame)")


def _n_jobs_help(default):
    return f"parallel jobs (joblib; -1: all cores, -2: all but one). Default: {default}"


def _threshold(text):
    if text == "auto":
        return text
    return _float_type(0.0, "'auto' or a positive number")(text)


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


_NOT_RESULTS = {"--out": 1, "--quiet": 0}  # options that do not change a table


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


#: Presets the parser offers without importing the library (a test checks them against it).
_SIM_PRESETS = ("everyday", "shore9", "silicone5")  # datasets.make_presses
