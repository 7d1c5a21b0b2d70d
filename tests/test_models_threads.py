"""Seeded nets give the same weights when built in parallel threads.

Initialisation seeds torch's process-wide generator; without a lock, threads
(joblib's threading backend, a Dask cluster of threads) reseed it under each
other and a seeded run stops being reproducible.
"""

from concurrent.futures import ThreadPoolExecutor

import numpy as np
import pytest
import torch

from sklearn_hardness.models import ConvLSTMClassifier


def _weights(seed):
    X = np.random.default_rng(0).normal(size=(6, 2, 6, 8, 1)).astype(np.float32)
    y = np.arange(6) % 3
    net = ConvLSTMClassifier(random_state=seed, max_epochs=1, batch_size=6)
    net.fit(X, y)
    return torch.cat([p.detach().flatten() for p in net.module_.parameters()]).numpy()


@pytest.mark.torch_threads(1)
def test_seeded_fits_in_threads_match_sequential_fits():
    seeds = [0, 1, 2, 3] * 6
    expected = {s: _weights(s) for s in set(seeds)}
    with ThreadPoolExecutor(max_workers=4) as pool:
        results = list(pool.map(_weights, seeds))
    for seed, w in zip(seeds, results):
        np.testing.assert_array_equal(w, expected[seed])


@pytest.mark.torch_threads(1)
def test_conftest_sets_the_marked_thread_count():
    assert torch.get_num_threads() == 1
