"""Study: how much of an experiment's result is the machine's floats (its BLAS kernels)?

OpenBLAS, the BLAS of numpy's and scipy's wheels, picks its kernels for the CPU
when it loads, and kernels round sums differently; ``OPENBLAS_CORETYPE`` makes
it load the kernels of another CPU where this one has their instructions. This
runs one ``sklearn-hardness reproduce`` command once per kernel set, each into a
fresh folder, and compares the runs with those of the first: per strategy, how
many runs pressed other objects (``queried``) or other presses, how many ended
at another accuracy, and at which iteration their choices first parted; then
the lines of ``paired.txt`` that differ. The kernels OpenBLAS ran under each
run's environment (the machine's ``blas``, read by ``harness.machine`` in a
process with that environment) are reported: a kernel set the CPU cannot run is
reported, not compared. ``native`` runs with neither ``OPENBLAS_CORETYPE`` nor
``OPENBLAS_L2_SIZE`` set (OpenBLAS's own choice for the CPU; some machine images
set both, where older builds fail with that choice); a named kernel set keeps
``OPENBLAS_L2_SIZE`` as the environment has it.

    python studies/scripts/blas_kernels.py --coretypes Haswell SkylakeX Sandybridge -- \\
        --dataset everyday --model contact_profile --strategies thompson random \\
        --seeds $(seq 300 319) --n-jobs 2

Everything after ``--`` goes to ``sklearn-hardness reproduce`` (less ``--out``,
which this sets). ``--smoke`` (what CI runs) compares ``native`` with ``Haswell``
on a tiny reproduce command of its own (``SMOKE_REPRODUCE``: two strategies, one
test object, one seed) on a tiny simulated set, unless arguments are given.
"""

import argparse
import csv
import json
import os
import subprocess
import sys
import tempfile
import time
from collections import defaultdict

import _harness  # noqa: F401 - puts the repository root on sys.path

from harness.cli import run_sklearn_hardness
from harness.machine import machine_reference
from harness.provenance import report
from harness.smoke import add_smoke_argument, parse_args, write_presses_manifest

#: ``--smoke``'s reproduce arguments, after ``--dataset MANIFEST`` (a tiny simulated set) and before
#: ``--test-objects`` (its first object).
SMOKE_REPRODUCE = ["--model", "contact_profile", "--strategies", "thompson", "random", "--seeds", "0", "--quick",
                   "--set", "n_initial=1", "n_per_query=1", "n_iterations=2", "n_test=1", "n_samples=2"]


def smoke_reproduce_args(folder):
    """A tiny reproduce command's arguments: :data:`SMOKE_REPRODUCE` on a tiny simulated manifest written in
    ``folder``."""
    manifest = write_presses_manifest(os.path.join(folder, "presses"))
    with open(manifest, newline="") as f:
        first = next(csv.DictReader(f))["object_id"]
    return ["--dataset", str(manifest), *SMOKE_REPRODUCE, "--test-objects", first]


def run_with_kernels(coretype, reproduce_args, out):
    """Run ``reproduce`` with ``OPENBLAS_CORETYPE=coretype`` (or OpenBLAS's own choice) into ``out``.

    Returns its seconds and the kernels OpenBLAS ran in that environment (the machine's ``blas``).
    """
    env = dict(os.environ)
    if coretype == NATIVE:
        env.pop("OPENBLAS_CORETYPE", None)
        env.pop("OPENBLAS_L2_SIZE", None)
    else:
        env["OPENBLAS_CORETYPE"] = coretype
    t0 = time.perf_counter()
    run_sklearn_hardness(["reproduce", *reproduce_args, "--out", out, "--quiet"], env=env, stdout=subprocess.DEVNULL)
    seconds = time.perf_counter() - t0
    return seconds, machine_reference(matmul=False, env=env)["blas"]


#: The kernel set OpenBLAS picks for the CPU by itself.
NATIVE = "native"


def honoured(coretype, blas):
    """Whether OpenBLAS ran the kernels asked for (any, for ``native``), by the run's ``blas``."""
    libraries = [part for part in (blas or "").split(" (")[0].split("; ") if part]
    if not libraries or not all(part.startswith("openblas") for part in libraries):
        return False
    return coretype == NATIVE or all(part.endswith(coretype) for part in libraries)


def active_runs(out):
    """The run records of a finished run's ``results.jsonl`` (one JSON record a line) by (strategy, test object,
    seed)."""
    with open(os.path.join(out, "results.jsonl")) as f:
        records = [json.loads(line) for line in f if line.strip()]
    return {(r["key"]["strategy"], r["key"]["test_object"], r["key"]["seed"]): r for r in records
            if r["key"].get("experiment") == "active_sampling"}


def first_parting(a, b):
    """The first iteration at which two runs pressed other objects, or None."""
    return next((i for i, (x, y) in enumerate(zip(a, b)) if x != y), None)


def compare(reference, other, n_iterations):
    """Rows per strategy: runs, other queries, other presses, other final accuracy, first parting per iteration."""
    rows = []
    by_strategy = defaultdict(list)
    for key in reference:
        by_strategy[key[0]].append(key)
    for strategy, keys in by_strategy.items():
        missing = [k for k in keys if k not in other]
        if missing:
            raise ValueError(f"{len(missing)} runs of {strategy!r} missing from the other folder, e.g. {missing[0]}")
        queried = [k for k in keys if reference[k]["queried"] != other[k]["queried"]]
        drawn = sum(reference[k]["drawn_indices"] != other[k]["drawn_indices"] for k in keys)
        final = sum(reference[k]["accuracy"][-1] != other[k]["accuracy"][-1] for k in keys)
        parted = [first_parting(reference[k]["queried"], other[k]["queried"]) for k in queried]
        rows.append((strategy, len(keys), len(queried), drawn, final,
                     [parted.count(i) for i in range(n_iterations)]))
    return rows


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--coretypes", nargs="+", default=["Haswell", "SkylakeX", "Sandybridge"],
                    help="OPENBLAS_CORETYPE of each run, or native (neither it nor OPENBLAS_L2_SIZE set); "
                         "the first is the reference")
    ap.add_argument("--keep", default=None, help="folder to keep the runs in (default: a temporary one)")
    ap.add_argument("--out", default=None, help="also write the report here, after a provenance line")
    ap.add_argument("reproduce_args", nargs=argparse.REMAINDER,
                    help="after --: the arguments of sklearn-hardness reproduce")
    add_smoke_argument(ap)
    args = parse_args(ap, argv, coretypes=["native", "Haswell"])
    reproduce_args = args.reproduce_args[1:] if args.reproduce_args[:1] == ["--"] else args.reproduce_args
    if not reproduce_args and not args.smoke:
        ap.error("give the reproduce command's arguments after --")
    if any(a == "--out" or a.startswith("--out=") for a in reproduce_args):
        ap.error("leave --out out of the reproduce arguments: each kernel set gets its own folder")
    if len(args.coretypes) < 2:
        ap.error("--coretypes needs at least two kernel sets to compare")
    if args.keep and os.path.isdir(args.keep) and os.listdir(args.keep):
        ap.error(f"--keep {args.keep} is not empty: reproduce would resume the runs in it")

    with tempfile.TemporaryDirectory() as tmp:
        root = args.keep or tmp
        reproduce_args = reproduce_args or smoke_reproduce_args(tmp)
        folders, seconds, ran = {}, {}, {}
        for coretype in args.coretypes:
            folders[coretype] = os.path.join(root, coretype)
            seconds[coretype], ran[coretype] = run_with_kernels(coretype, reproduce_args, folders[coretype])
            print(f"{coretype}: {seconds[coretype]:.0f} s, OpenBLAS ran {ran[coretype]}", file=sys.stderr)
        lines = [f"sklearn-hardness reproduce {' '.join(reproduce_args)}, once per OpenBLAS kernel set "
                 "(OPENBLAS_CORETYPE)", ""]
        compared = []
        for coretype in args.coretypes:
            ok = honoured(coretype, ran[coretype])
            if ok:
                compared.append(coretype)
            lines.append(f"{coretype:<12} {seconds[coretype]:5.0f} s  OpenBLAS ran: {ran[coretype]}"
                         + ("" if ok else "  (not the kernels asked for: left out below)"))
        if len(compared) < 2:
            report("\n".join(lines + ["", "fewer than two kernel sets ran as asked: nothing to compare"]),
                   args.out)
            return
        reference = active_runs(folders[compared[0]])
        n_iterations = max(len(r["queried"]) for r in reference.values())
        lines += ["", f"runs against those with {compared[0]}'s kernels (the same command, seeds and objects):",
                  f"{'kernels':<12} {'strategy':<10} {'runs':>5}  {'other objects pressed':>22}  "
                  f"{'other presses':>13}  {'other final accuracy':>20}  first parted at iteration "
                  + " / ".join(str(i) for i in range(n_iterations))]
        with open(os.path.join(folders[compared[0]], "paired.txt")) as f:
            reference_paired = f.read().splitlines()[1:]
        differing = []
        for coretype in compared[1:]:
            for strategy, n, queried, drawn, final, parted in compare(
                    reference, active_runs(folders[coretype]), n_iterations):
                lines.append(f"{coretype:<12} {strategy:<10} {n:>5}  {f'{queried} ({queried / n:.1%})':>22}  "
                             f"{drawn:>13}  {final:>20}  " + " / ".join(map(str, parted)))
            with open(os.path.join(folders[coretype], "paired.txt")) as f:
                paired = f.read().splitlines()[1:]
            differing.append((coretype, [(a, b) for a, b in zip(reference_paired, paired) if a != b]))
        for coretype, pairs in differing:
            lines += ["", f"paired.txt lines that differ, {compared[0]} then {coretype} "
                      f"({len(pairs)} of {len(reference_paired)}):"]
            for a, b in pairs:
                lines += [f"  {a}", f"  {b}"]
        report("\n".join(lines), args.out)


if __name__ == "__main__":
    main()
