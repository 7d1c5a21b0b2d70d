"""Puts the repository root on ``sys.path``: the scripts beside this file import the development harness.

``import _harness`` comes before ``from harness.<module> import ...`` (``harness/`` at
the repository root: provenance, machine reference, peak memory).
"""

import os
import sys

_ROOT = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))  # studies/scripts/..
if _ROOT not in sys.path:
    sys.path.insert(0, _ROOT)
