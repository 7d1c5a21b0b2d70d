"""Run a command and keep what it printed with its time, as an output with a provenance header.

    python -m harness.timed OUT.txt --as "sklearn-hardness evaluate DATA/manifest.csv --n-jobs 2" \
        -- sklearn-hardness evaluate /path/to/manifest.csv --n-jobs 2

A time a page quotes is a figure like any other: it needs an output that names
the command, the commit and the date. ``OUT.txt`` starts with that header
(:func:`harness.provenance.header`, the machine with its one-thread matmul rate
and load), then the command's standard output, then one line: wall time, CPU
time of the command's whole process tree (user + system, children waited for
included) and the peak resident memory of the tree, sampled. ``--as`` gives the
command as a reader types it (data folders by their role), where the command run
names a path of one machine.
"""

from __future__ import annotations

import os
import resource
import subprocess
import sys
import time

from .memory import TreePeak
from .provenance import header

__all__ = ["run_timed", "main"]


def run_timed(command, *, env=None):
    """Run ``command`` (a list of words) and measure it.

    Parameters
    ----------
    command : list of str
        The command, as ``subprocess`` takes it.
    env : dict or None, default=None
        Its environment (this process's when None).

    Returns
    -------
    stdout : str
        What it printed on its standard output.
    timing : dict
        ``wall_s``, ``cpu_s`` (user + system of the command and its children),
        ``peak_mb`` (the tree's resident memory, sampled every 0.2 s) and
        ``returncode``.

    Examples
    --------
    >>> import sys
    >>> from harness.timed import run_timed
    >>> out, timing = run_timed([sys.executable, "-c", "print(6 * 7)"])
    >>> out, timing["returncode"], timing["wall_s"] > 0
    ('42\\n', 0, True)
    """
    before = resource.getrusage(resource.RUSAGE_CHILDREN)
    start = time.perf_counter()
    proc = subprocess.Popen(command, stdout=subprocess.PIPE, text=True, env=env)
    with TreePeak(proc.pid) as tree:
        stdout, _ = proc.communicate()
    wall = time.perf_counter() - start
    after = resource.getrusage(resource.RUSAGE_CHILDREN)
    cpu = (after.ru_utime - before.ru_utime) + (after.ru_stime - before.ru_stime)
    return stdout, {"wall_s": wall, "cpu_s": cpu, "peak_mb": tree.peak_mb, "returncode": proc.returncode}


def main(argv=None):
    import argparse
    import shlex

    argv = sys.argv[1:] if argv is None else list(argv)
    if "--" not in argv:
        raise SystemExit("usage: python -m harness.timed OUT.txt [--as COMMAND] -- COMMAND [ARGS ...]")
    split = argv.index("--")
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("out", help="the output to write")
    ap.add_argument("--as", dest="typed", help="the command as a reader types it (default: the command run)")
    args = ap.parse_args(argv[:split])
    command = argv[split + 1:]
    if not command:
        ap.error("no command after --")
    stdout, timing = run_timed(command)
    print(stdout, end="")
    if timing["returncode"]:
        raise SystemExit(f"the command failed (exit {timing['returncode']}); {args.out} not written.")
    typed = args.typed or shlex.join([os.path.basename(command[0]), *command[1:]])
    line = (f"wall {timing['wall_s']:.1f} s, CPU {timing['cpu_s']:.1f} s (user + system, the whole process tree), "
            f"peak memory {timing['peak_mb'] / 1024:.2f} GB (sampled)")
    with open(args.out, "w") as f:
        f.write(header(command=typed) + "\n" + stdout.rstrip("\n") + "\n" + line + "\n")
    print(line)


if __name__ == "__main__":
    main()
