"""``--out`` of the benchmarks: the printed text, written with a provenance line first."""

import os
import shlex
import sys


def write_output(path, text):
    """Write ``text`` to ``path`` after the provenance line of this run's command.

    The command is ``python benchmarks/<script> <arguments>``, from ``sys.argv``,
    as ``docs/_output/index.json`` records it.
    """
    from sklearn_hardness.experiments import provenance_header

    script = os.path.basename(sys.argv[0])
    command = shlex.join(["python", f"benchmarks/{script}", *sys.argv[1:]])
    with open(path, "w") as f:
        f.write(provenance_header(command) + "\n" + text + "\n")


def report(text, out=None):
    """Print ``text``; with ``out``, also write it there after the provenance line (:func:`write_output`)."""
    print(text)
    if out:
        write_output(out, text)
