"""Run the performance benchmarks and print one table: time, peak memory and error side by side.

Each case runs ``python benchmarks/bench_<name>.py ARGS`` in its own process;
the runner measures its wall time and the peak resident memory of the process
and its children (``harness.memory.TreePeak``, sampled every 0.2 s, and the
process's own maximum), and reads the error or accuracy from the last
``result: ...`` line the benchmark printed ("-" where it has none).
The benchmarks' own output goes to ``--log`` (default ``benchmarks.log``).

    python benchmarks/run.py --quick              # every benchmark, small cases (a few minutes on 2 cores)
    python benchmarks/run.py                      # the benchmarks' own defaults (an hour or more)
    python benchmarks/run.py --quick convlstm mc_dropout
    python benchmarks/run.py --smoke                      # every benchmark's --smoke run (what CI runs)
    python benchmarks/run.py --list

No benchmark imports another, nor a private module of the package; their shared helpers
(peak memory, the matmul reference) are the development harness's (``harness/``).
"""

import argparse
import os
import subprocess
import sys
import time

import _harness  # noqa: F401 - puts the repository root on sys.path

from harness.memory import TreePeak
from harness.smoke import SMOKE_HELP

HERE = os.path.dirname(os.path.abspath(__file__))

#: name -> cases: (case, quick arguments or None to skip in --quick, full arguments, needs)
BENCHMARKS = {
    "simulator": [
        ("silicone5 render", ["--image-size", "96", "128", "--no-check"], [], None),
    ],
    "features": [
        ("optical flow", ["--n-videos", "20", "--skip-dinov2"], [], None),
    ],
    "convlstm": [
        ("epoch vs input size", ["--sizes", "12x16,30x40", "--colors", "gray", "--n-train", "20",
                                 "--n-test", "20", "--epochs", "10"], [], None),
    ],
    "flops": [
        ("ConvLSTM step", ["--sizes", "12x16,18x24", "--repeat", "3", "--matmul", "1024"], [], None),
    ],
    "mc_dropout": [
        ("batched vs loop", ["--size", "12x16", "--n-test", "5", "--repeat", "1", "--mlp-n", "45"], [], None),
    ],
    "stacked": [
        ("K nets vs stacked", ["--k", "1", "5", "--steps", "2", "--repeat", "1"], [], None),
    ],
    "active_sampling": [
        ("one run (--quick settings)", ["--quick"], [], None),
    ],
    "paired_sharing": [
        ("shared initial model", ["shared", "--quick"], ["shared"], None),
        ("one initial model per strategy", ["separate", "--quick"], ["separate"], None),
    ],
    "time_error": [
        ("paper vs 12x16 frames", None, ["--configs", "paper", "frames 12x16"], None),
    ],
    "fit_predict": [
        ("contact_geometry, 240x320 presses", ["--n-presses", "40", "--n-predict", "3"], [], None),
    ],
    "cross_val": [
        ("contact_geometry: cross_val_score, memory, evaluate",
         ["--n-per-class", "1", "--image-size", "120", "160"], [], None),
    ],
    "device": [
        ("GPU beside CPU", ["--n-per-class", "4", "--epochs", "2"], [], "cuda"),
    ],
}


def _has_cuda():
    try:
        import torch
    except ImportError:
        return False
    return torch.cuda.is_available()


def run_case(name, args, log):
    """Wall seconds, peak RSS in MB (process tree) and the last ``result:`` line of one case."""
    cmd = [sys.executable, os.path.join(HERE, f"bench_{name}.py"), *args]
    log.write(f"\n$ {' '.join(cmd)}\n")
    log.flush()
    start = time.perf_counter()
    proc = subprocess.Popen(cmd, stdout=subprocess.PIPE, stderr=subprocess.STDOUT, text=True, bufsize=1)
    result = "-"
    with TreePeak(proc.pid) as tree:  # joblib's workers count too
        for line in proc.stdout:
            log.write(line)
            if line.startswith("result: "):
                result = line[len("result: "):].strip()
        _, status, usage = os.wait4(proc.pid, 0)  # the child's own peak, with the children it waited for
    proc.returncode = os.waitstatus_to_exitcode(status)
    wall = time.perf_counter() - start
    peak_mb = max(tree.peak_mb, usage.ru_maxrss / 1024)  # Linux reports ru_maxrss in KiB
    if proc.returncode:
        result = f"FAILED (exit {proc.returncode}; see the log)"
    return wall, peak_mb, result


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("names", nargs="*", help="benchmarks to run (default: all)")
    ap.add_argument("--quick", action="store_true", help="small cases, a few minutes on 2 cores")
    ap.add_argument("--smoke", action="store_true",
                    help="each case with its benchmark's --smoke (" + SMOKE_HELP.split(":")[0] + ")")
    ap.add_argument("--log", default="benchmarks.log", help="where the benchmarks' own output goes")
    ap.add_argument("--list", action="store_true", help="list the benchmarks and their cases")
    args = ap.parse_args(argv)
    unknown = sorted(set(args.names) - set(BENCHMARKS))
    if unknown:
        ap.error(f"unknown benchmark(s) {unknown}; choose from {sorted(BENCHMARKS)}")
    names = args.names or list(BENCHMARKS)
    if args.list:
        for name in names:
            for case, quick, full, needs in BENCHMARKS[name]:
                print(f"{name:<16} {case:<32} quick: {' '.join(quick) if quick is not None else '(skipped)'}"
                      f"{'  needs ' + needs if needs else ''}")
        return 0
    cuda = _has_cuda()
    header = f"{'benchmark':<16}{'case':<34}{'wall s':>9}{'peak MB':>9}  error / accuracy"
    print(header)
    print("-" * len(header))
    failed = 0
    with open(args.log, "w") as log:
        for name in names:
            for case, quick, full, needs in BENCHMARKS[name]:
                case_args = [*full, "--smoke"] if args.smoke else quick if args.quick else full
                if case_args is None:
                    print(f"{name:<16}{case:<34}{'':>9}{'':>9}  skipped (not in --quick)")
                    continue
                if needs == "cuda" and not cuda:
                    print(f"{name:<16}{case:<34}{'':>9}{'':>9}  skipped (no CUDA device)")
                    continue
                wall, peak, result = run_case(name, case_args, log)
                failed += result.startswith("FAILED")
                print(f"{name:<16}{case:<34}{wall:>9.1f}{peak:>9.0f}  {result}", flush=True)
    print(f"\nthe benchmarks' output: {args.log}")
    return 1 if failed else 0


if __name__ == "__main__":
    sys.exit(main())
