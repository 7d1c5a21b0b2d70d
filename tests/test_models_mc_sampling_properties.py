"""Hypothesis property tests over the MC-dropout sampler.

Extreme logits (float16, +-1e4, all equal), one pass, one input, chunk sizes
from one row to all rows, and a net with dropout 0.
"""

import functools

import numpy as np
import torch
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st
from hypothesis.extra import numpy as hnp
from sklearn.datasets import make_blobs

from sklearn_hardness.models import OFNNClassifier
from sklearn_hardness.models._mc_sampling import softmax

FAST = settings(max_examples=60, deadline=None, suppress_health_check=[HealthCheck.too_slow])


@functools.lru_cache(maxsize=2)
def _net(dropout):
    X, y = make_blobs(60, n_features=5, centers=4, cluster_std=3.0, random_state=0)
    X = X.astype(np.float32)
    net = OFNNClassifier(hidden_units=16, max_epochs=5, lr=0.05, dropout=dropout, random_state=0).fit(X, y)
    return net, X


@FAST
@given(
    logits=hnp.arrays(
        dtype=st.sampled_from([np.float16, np.float32, np.float64]),
        shape=hnp.array_shapes(min_dims=1, max_dims=3, min_side=1, max_side=7),
        elements=st.floats(-1e4, 1e4, width=16),
    )
)
def test_softmax_is_a_distribution_even_for_extreme_logits(logits):
    p = softmax(torch.from_numpy(logits)).numpy()
    assert p.dtype in (np.float32, np.float64)
    assert np.all(np.isfinite(p)) and np.all(p >= 0) and np.all(p <= 1)
    np.testing.assert_allclose(p.sum(axis=-1), 1.0, rtol=1e-5)
    ref = torch.softmax(torch.from_numpy(logits.astype(np.float64)), dim=-1).numpy()
    np.testing.assert_allclose(p, ref, atol=1e-5)


@FAST
@given(
    n_samples=st.integers(1, 6),
    n_rows=st.integers(1, 12),
    batch_size=st.integers(1, 80),
    seed=st.integers(0, 2**31 - 2),
)
def test_samples_are_distributions_and_seeded_per_chunking(n_samples, n_rows, batch_size, seed):
    net, X = _net(0.3)
    before = torch.get_rng_state()
    flags = [m.training for m in net.module_.modules()]
    a = net.predict_proba_samples(X[:n_rows], n_samples=n_samples, random_state=seed, batch_size=batch_size)
    b = net.predict_proba_samples(X[:n_rows], n_samples=n_samples, random_state=seed, batch_size=batch_size)
    assert torch.equal(before, torch.get_rng_state())  # torch's global generator is untouched
    assert a.shape == (n_samples, n_rows, 4) and a.dtype == np.float32
    assert np.all(np.isfinite(a)) and np.all(a >= 0)
    np.testing.assert_allclose(a.sum(axis=-1), 1.0, rtol=1e-5)
    np.testing.assert_array_equal(a, b)
    assert [m.training for m in net.module_.modules()] == flags  # training flags restored


@FAST
@given(n_samples=st.integers(1, 5), n_rows=st.integers(1, 12), batch_size=st.integers(1, 40))
def test_without_dropout_every_pass_is_the_deterministic_prediction(n_samples, n_rows, batch_size):
    net, X = _net(0.0)
    p = net.predict_proba_samples(X[:n_rows], n_samples=n_samples, random_state=0, batch_size=batch_size)
    det = net.predict_proba(X[:n_rows])
    for k in range(n_samples):
        np.testing.assert_allclose(p[k], det, atol=1e-6)
