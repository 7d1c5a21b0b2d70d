import os

import numpy as np
import pytest

from tests._threads import torch_threads

# SKLEARN_HARDNESS_TEST_THREADS changes the float path (.ci/run runs the fast tests once with 1).
_TORCH_THREADS = int(os.environ.get("SKLEARN_HARDNESS_TEST_THREADS", "2"))


def pytest_configure(config):
    config.addinivalue_line("markers", "torch_threads(n): torch threads during the test (default 2)")


@pytest.fixture(autouse=True)
def _few_threads(request):
    # CI has 2 cores; keep torch from oversubscribing when pytest runs alongside joblib. Tiny nets
    # are fastest on one thread: their modules say pytestmark = pytest.mark.torch_threads(1).
    # Module-scoped fixtures are set up before this one: they use tests._threads.torch_threads.
    marker = request.node.get_closest_marker("torch_threads")
    with torch_threads(marker.args[0] if marker else _TORCH_THREADS):
        yield


@pytest.fixture
def rng():
    return np.random.default_rng(0)


def pytest_collection_modifyitems(config, items):
    # sklearn's array-API check skips itself unless SCIPY_ARRAY_API is set; array-API
    # dispatch does not apply to sequences of videos, so it is deselected rather than
    # reported as a skip.
    keep = [item for item in items if "check_array_api_input" not in item.nodeid]
    if len(keep) != len(items):
        config.hook.pytest_deselected(items=[i for i in items if i not in keep])
        items[:] = keep
