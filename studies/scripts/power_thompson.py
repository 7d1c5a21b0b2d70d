"""Sample size of the pre-registered replication of ``thompson`` against ``random`` (paired t-test).

The paired standard deviation of the test-object accuracy difference (thompson minus
random, percentage points) is backed out of the 95% paired t-intervals of the committed
tables in ``studies/outputs`` (``experiments.ExperimentResult.paired_table``: half-width = t(0.975, n-1) * s / sqrt(n)),
pooled over the silicone5 runs, and fed into the exact power of a two-sided paired t-test
(noncentral t). The plan is ``studies/preregistration/thompson_vs_random.md``.

    python studies/scripts/power_thompson.py [--effect 5] [--sd SD] [--power 0.8] [--alpha 0.05] [--objects 5]

It reads three small tables and takes a second: ``--smoke`` (what CI runs) runs it as it is.
"""

import argparse
import math
import os
import re

import _harness  # noqa: F401 - puts the repository root on sys.path
from scipy import stats

from harness.smoke import add_smoke_argument, parse_args

OUTPUT = os.path.join(os.path.dirname(os.path.abspath(__file__)), os.pardir, "outputs")
# the silicone5 tables with a thompson row (the paper's settings; the fast setting; its fresh seeds)
TABLES = ("paper_silicone5_paired.txt", "fast_silicone5_paired.txt", "fast_silicone5_fresh_seeds_paired.txt")
# "thompson  accuracy %  50 (50 pairs)  90.0 [83.7, 96.3]  +14.0 [2.6, 25.4] ..."
ROW = re.compile(r"^thompson\s+accuracy %\s+\d+ \((\d+) pairs\)\s+\S+ \[\S+, \S+\]\s+"
                 r"([+-]?[\d.]+) \[([+-]?[\d.]+), ([+-]?[\d.]+)\]")


def paired_sd(path):
    """(pairs, mean difference, paired s.d.) of thompson - random from one table."""
    with open(path) as f:
        for line in f:
            m = ROW.match(line)
            if m:
                n, diff, lo, hi = int(m[1]), float(m[2]), float(m[3]), float(m[4])
                return n, diff, (hi - lo) / 2 * math.sqrt(n) / stats.t.ppf(0.975, n - 1)
    raise ValueError(f"no 'thompson accuracy %' row in {path}")


def power(n, effect, sd, alpha):
    """Power of the two-sided paired t-test with n pairs (exact, noncentral t)."""
    df = n - 1
    crit = stats.t.ppf(1 - alpha / 2, df)
    nc = effect / sd * math.sqrt(n)
    return stats.nct.sf(crit, df, nc) + stats.nct.cdf(-crit, df, nc)


def pairs_needed(effect, sd, target, alpha):
    n = 3
    while power(n, effect, sd, alpha) < target:
        n += 1
    return n


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--effect", type=float, default=5.0, help="difference to detect, points (default 5)")
    ap.add_argument("--sd", type=float, default=None, help="paired s.d., points (default: pooled from the tables)")
    ap.add_argument("--power", type=float, default=0.8)
    ap.add_argument("--alpha", type=float, default=0.05)
    ap.add_argument("--objects", type=int, default=5, help="test objects per seed (silicone5: 5)")
    add_smoke_argument(ap)
    args = parse_args(ap, argv)
    ss = dof = 0.0
    for name in TABLES:
        n, diff, sd = paired_sd(os.path.join(OUTPUT, name))
        print(f"{name}: {n} pairs, thompson - random {diff:+.1f} points, paired s.d. {sd:.1f}")
        ss, dof = ss + (n - 1) * sd**2, dof + n - 1
    pooled = math.sqrt(ss / dof)
    print(f"pooled paired s.d.: {pooled:.1f} points")
    sd = pooled if args.sd is None else args.sd
    n = pairs_needed(args.effect, sd, args.power, args.alpha)
    seeds = math.ceil(n / args.objects)
    print(f"effect {args.effect} points, s.d. {sd:.1f}, two-sided alpha {args.alpha}, power {args.power}: "
          f"{n} pairs = {seeds} seeds x {args.objects} test objects ({seeds * args.objects} pairs)")
    for s in (25.0, 30.0, 35.0):
        print(f"  at s.d. {s:.0f}: {pairs_needed(args.effect, s, args.power, args.alpha)} pairs; "
              f"300 pairs give power {power(300, args.effect, s, args.alpha):.2f}")


if __name__ == "__main__":
    main()
