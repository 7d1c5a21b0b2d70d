"""The header of a study's output: the command, the commit, the date and the machine.

    python -m harness.provenance OUT/table.txt ...   # stamp command-line outputs for the studies
    python -m harness.provenance --note "ran with --cache DIR" studies/outputs/x.txt   # a note beside it
    python -m harness.provenance --restore COMMIT:PATH studies/outputs/NAME   # a superseded output back

A figure is read against what made it: the command (a data folder named by its
role, ``--data EXAMPLE_DATA``, never by a path of one machine), the commit it ran
at and the machine with its one-thread matmul rate (:mod:`harness.machine`). The
header records; nothing compares it with the current code (an output is rerun when
its question is revisited).
"""

from __future__ import annotations

import datetime
import json
import os
import shlex
import subprocess
import sys

from . import ROOT
from .machine import describe, machine_reference

__all__ = ["git_commit", "script_command", "header", "write_output", "report", "stamp", "provenance_record",
           "SIDECAR", "add_note", "restore"]

#: Options whose value is where output goes, not what was computed.
_WHERE = {"--out", "--cache"}
#: Options whose value is a data folder: named by its role in the command.
_DATA = {"--data", "--manifest"}
#: How ``sklearn-hardness evaluate`` and ``reproduce`` start the header line of what they write: one line of JSON
#: follows (command, version, date, platform, ...).
_PROVENANCE = "# provenance "


def git_commit(path=ROOT):
    """HEAD of the repository holding ``path``, with ``" (uncommitted changes)"`` where tracked files changed.

    Parameters
    ----------
    path : str, default=ROOT
        A folder inside the repository.

    Returns
    -------
    commit : str or None
        Ten hex digits (and the note); None outside a git checkout or without git.
    """
    run = dict(capture_output=True, text=True, check=True, timeout=10)
    try:
        commit = subprocess.run(["git", "-C", path, "rev-parse", "--short=10", "HEAD"], **run).stdout.strip()
        dirty = subprocess.run(["git", "-C", path, "status", "--porcelain", "--untracked-files=no"],
                               **run).stdout.strip()
    except (OSError, subprocess.SubprocessError):
        return None
    return commit + (" (uncommitted changes)" if dirty else "") if commit else None


def script_command(argv):
    """A script's command line as a reader would type it from the repository root.

    Where output goes (``--out``, ``--cache``) is left out; data folders
    (``--data``, ``--manifest``) are named by their role.

    Parameters
    ----------
    argv : list of str
        ``sys.argv`` of the script.

    Returns
    -------
    command : str

    Examples
    --------
    >>> import os
    >>> from harness import ROOT
    >>> from harness.provenance import script_command
    >>> script_command([os.path.join(ROOT, "studies", "scripts", "s.py"), "--data", "/x/example_data",
    ...                 "--out", "o.txt", "--seed", "1"])
    'python studies/scripts/s.py --data EXAMPLE_DATA --seed 1'
    """
    args, skip = [], False
    for i, arg in enumerate(argv[1:], 1):
        if skip:
            skip = False
            continue
        if arg in _WHERE:
            skip = True
            continue
        if argv[i - 1] in _DATA:
            arg = "EXAMPLE_DATA" if os.path.basename(arg.rstrip("/")) == "example_data" else "DATA"
        args.append(arg)
    script = os.path.relpath(os.path.abspath(argv[0]), ROOT)
    if script.startswith(".."):
        script = os.path.basename(argv[0])
    return shlex.join(["python", script.replace(os.sep, "/"), *args])


def header(argv=None, *, machine=None, commit=None, date=None, command=None):
    """The three header lines of an output made by ``argv`` (default ``sys.argv``).

    Parameters
    ----------
    argv : list of str or None, default=None
        The script's command line.
    command : str or None, default=None
        The command as a reader types it, in place of ``argv``'s (for a command
        that is not a script of this repository; data folders named by role).
    machine : dict or None, default=None
        :func:`~harness.machine.machine_reference` (measured when None).
    commit : str or None, default=None
        :func:`git_commit` when None.
    date : str or None, default=None
        ISO date and time in UTC (now when None).

    Returns
    -------
    lines : str
        ``# command: ...``, ``# commit: ..., DATE`` and ``# machine: ...``.

    Examples
    --------
    >>> from harness.provenance import header
    >>> machine = {"cpu": "Xeon", "cores": 2, "matmul_gflops": 80.0, "torch": "2.1", "numpy": "2.0",
    ...            "python": "3.11.7", "blas": None}
    >>> print(header(["s.py", "--seed", "1"], machine=machine, commit="f00", date="2026-01-01T00:00Z"))
    # command: python s.py --seed 1
    # commit: f00, 2026-01-01T00:00Z
    # machine: Xeon, 2 cores, matmul 80 GFLOP/s (one thread), torch 2.1, numpy 2.0, Python 3.11.7, BLAS None
    """
    command = script_command(sys.argv if argv is None else argv) if command is None else command
    commit = (git_commit() or "unknown") if commit is None else commit
    date = date or datetime.datetime.now(datetime.timezone.utc).strftime("%Y-%m-%dT%H:%MZ")
    return f"# command: {command}\n# commit: {commit}, {date}\n{_machine_line(machine)}"


def write_output(path, text):
    """Write ``text`` to ``path`` after :func:`header`."""
    with open(path, "w") as f:
        f.write(header() + "\n" + text + "\n")


def report(text, out=None):
    """Print ``text``; with ``out``, also write it there after the header (:func:`write_output`)."""
    print(text)
    if out:
        write_output(out, text)


def provenance_record(text):
    """The record of the first ``# provenance {...}`` line of an output of ``sklearn-hardness``, or None.

    Examples
    --------
    >>> from harness.provenance import provenance_record
    >>> provenance_record('# provenance {"command": "sklearn-hardness reproduce --quick"}\\ntable')["command"]
    'sklearn-hardness reproduce --quick'
    """
    for line in text.splitlines():
        if line.startswith(_PROVENANCE):
            return json.loads(line[len(_PROVENANCE):])
    return None


def _machine_line(machine):
    return f"# machine: {describe(machine_reference() if machine is None else machine)}"


def stamp(path, *, machine=None, commit=None):
    """Add the commit and the machine to an output of ``sklearn-hardness`` kept for the studies.

    ``evaluate`` and ``reproduce`` head what they write with a cheap line
    (command, version, date, platform); run right after the command, this adds
    ``# commit: ...`` and ``# machine: ...`` (with the one-thread matmul rate)
    below it.

    Parameters
    ----------
    path : str or path-like
        ``table.txt``, ``paired.txt`` or ``evaluation.txt``.
    machine, commit
        As in :func:`header`.

    Returns
    -------
    changed : bool
        False where the file has its commit line already.
    """
    with open(path) as f:
        lines = f.read().split("\n")
    if not lines[0].startswith(_PROVENANCE):
        raise ValueError(f"{path} does not start with the header line of sklearn-hardness evaluate or reproduce.")
    if len(lines) > 1 and lines[1].startswith("# commit: "):
        return False
    commit = (git_commit() or "unknown") if commit is None else commit
    lines[1:1] = [f"# commit: {commit}", _machine_line(machine)]
    with open(path, "w") as f:
        f.write("\n".join(lines))
    return True


#: The suffix of the note kept beside an output: what its header does not say (an output is never edited).
SIDECAR = ".provenance"


def add_note(path, note, *, date=None):
    """Add a dated line ``# note: ...`` to the sidecar ``path + ".provenance"``, never to the output itself.

    Parameters
    ----------
    path : str or path-like
        The output the note is about.
    note : str
        One line: what the output's header leaves out (an option it ran with,
        the command of a file that cannot hold a header, a later edit of its plan).
    date : str or None, default=None
        The note's date (today, UTC, when None).

    Returns
    -------
    sidecar : str
        The sidecar's path.

    Examples
    --------
    >>> import os, tempfile
    >>> from harness.provenance import add_note
    >>> out = os.path.join(tempfile.mkdtemp(), "x.txt")
    >>> print(open(add_note(out, "ran with --cache DIR", date="2026-01-01")).read(), end="")
    # note (2026-01-01): ran with --cache DIR
    """
    if not isinstance(note, str) or not note.strip() or "\n" in note:
        raise ValueError(f"a note is one non-empty line, got {note!r}.")
    date = date or datetime.datetime.now(datetime.timezone.utc).strftime("%Y-%m-%d")
    sidecar = os.fspath(path) + SIDECAR
    with open(sidecar, "a") as f:
        f.write(f"# note ({date}): {note.strip()}\n")
    return sidecar


def restore(spec, path, *, date=None):
    """Write the committed version ``spec`` (``COMMIT:PATH``) of an output to ``path``, byte for byte.

    An output superseded by a rerun stays in git; a page that quotes it gets it
    back under a new name, with its own header, and a sidecar note saying where
    it came from.

    Parameters
    ----------
    spec : str
        ``COMMIT:PATH`` as ``git show`` takes it.
    path : str or path-like
        Where to write it (a new name in ``studies/outputs``).
    date : str or None, default=None
        The note's date (today, UTC, when None).
    """
    commit, sep, source = spec.partition(":")
    if not sep or not commit or not source:
        raise ValueError(f"spec is COMMIT:PATH, got {spec!r}.")
    if os.path.exists(path):
        raise FileExistsError(f"{path} exists; a restored output takes a new name.")
    blob = subprocess.run(["git", "-C", ROOT, "show", spec], capture_output=True, check=True, timeout=30).stdout
    full = subprocess.run(["git", "-C", ROOT, "rev-parse", "--short=10", commit], capture_output=True, text=True,
                          check=True, timeout=10).stdout.strip()
    with open(path, "wb") as f:
        f.write(blob)
    add_note(path, f"restored verbatim from git: git show {full}:{source}", date=date)


def main(argv=None):
    import argparse

    ap = argparse.ArgumentParser(description="Add the commit and the machine to outputs of sklearn-hardness; "
                                             "keep notes beside outputs; restore superseded outputs from git.")
    ap.add_argument("paths", nargs="+", help="files headed by the command line's provenance line (with --note "
                                             "or --restore: the output the note is about, or the name to restore to)")
    ap.add_argument("--commit", help="the commit the run started at, where HEAD has moved since (default: HEAD)")
    ap.add_argument("--note", help="write this line to each path's sidecar (PATH.provenance) instead of stamping")
    ap.add_argument("--restore", metavar="COMMIT:PATH", help="write this committed file to the one path given")
    args = ap.parse_args(argv)
    if args.restore:
        if len(args.paths) != 1:
            ap.error("--restore writes one path.")
        restore(args.restore, args.paths[0])
        print(f"restored: {args.paths[0]} ({args.restore})")
        return
    if args.note:
        for path in args.paths:
            print(f"noted: {add_note(path, args.note)}")
        return
    machine = machine_reference()
    for path in args.paths:
        print(f"{'stamped' if stamp(path, machine=machine, commit=args.commit) else 'already stamped'}: {path}")


if __name__ == "__main__":
    main()
