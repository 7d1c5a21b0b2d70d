import numpy as np
import pytest
import torch


@pytest.fixture(autouse=True)
def _few_threads():
    # CI has 2 cores; keep torch from oversubscribing when pytest runs alongside joblib.
    torch.set_num_threads(2)
    yield


@pytest.fixture
def rng():
    return np.random.default_rng(0)
