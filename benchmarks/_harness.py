"""Puts the repository root on ``sys.path``: the benchmarks import the development harness; not a benchmark.

``import _harness`` comes before ``from harness.<module> import ...`` (``harness/`` at
the repository root: peak memory, the matmul reference).
"""

import os
import sys

_ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))  # benchmarks/..
if _ROOT not in sys.path:
    sys.path.insert(0, _ROOT)
