"""Query strategies on a real (tiny) MC-dropout net, plain and in a Pipeline."""

import numpy as np
import pytest
from sklearn.pipeline import Pipeline, make_pipeline
from sklearn.preprocessing import StandardScaler

from sklearn_hardness.active import (
    bald_sampling,
    class_uncertainty,
    entropy_sampling,
    get_strategy,
    random_sampling,
    variance_sampling,
)
from sklearn_hardness.active._strategies import _predict_proba_samples

from ._active_net import MCDropoutNet, make_blobs, make_net

STRATEGIES = [entropy_sampling, variance_sampling, bald_sampling, random_sampling]
UNCERTAIN = {"entropy": entropy_sampling, "variance": variance_sampling, "bald": bald_sampling}


@pytest.fixture(scope="module")
def blobs():
    return make_blobs(n_per_class=30, seed=0)


@pytest.fixture(scope="module")
def net(blobs):
    import torch

    torch.manual_seed(0)
    X, y = blobs
    return make_net(max_epochs=15).fit(X, y)


@pytest.mark.parametrize("strategy", STRATEGIES)
def test_return_shape_order_and_scores(strategy, net, blobs):
    X, _ = blobs
    idx, scores = strategy(net, X[:12], n_instances=2, n_samples=20, random_state=0)
    assert idx.shape == (2,) and np.issubdtype(idx.dtype, np.integer)
    assert len(set(idx.tolist())) == 2
    assert scores.shape == (3,) and scores.dtype == np.float64
    # highest score first, and nothing left out scores higher
    assert scores[idx[0]] >= scores[idx[1]]
    rest = np.setdiff1d(np.arange(3), idx)
    assert np.all(scores[rest] <= scores[idx[1]])


@pytest.mark.parametrize("kind", sorted(UNCERTAIN))
def test_scores_are_class_uncertainty_of_the_same_passes(kind, net, blobs):
    X, _ = blobs
    idx, scores = UNCERTAIN[kind](net, X[:10], n_samples=15, random_state=3)
    # the strategy draws its MC seed from random_state; replay it
    rng = np.random.RandomState(3)
    seed = int(rng.randint(np.iinfo(np.int32).max))
    p = net.predict_proba_samples(X[:10], n_samples=15, random_state=seed)
    np.testing.assert_allclose(scores, class_uncertainty(p, kind))


@pytest.mark.parametrize("strategy", STRATEGIES)
def test_seeded_is_reproducible(strategy, net, blobs):
    X, _ = blobs
    a = strategy(net, X[:8], n_instances=3, n_samples=10, random_state=7)
    b = strategy(net, X[:8], n_instances=3, n_samples=10, random_state=7)
    np.testing.assert_array_equal(a[0], b[0])
    np.testing.assert_array_equal(a[1], b[1])


def test_picks_the_confused_classes():
    """Classes 0 and 1 overlap, class 2 is far away: on presses from the
    overlap, the uncertain classes are 0 and 1, never 2."""
    import torch

    torch.manual_seed(0)
    rng = np.random.default_rng(0)
    X = np.concatenate([
        rng.normal(0.0, 1.0, (40, 4)),
        rng.normal(0.3, 1.0, (40, 4)),
        rng.normal(0.0, 1.0, (40, 4)) + np.array([8.0, 8.0, 0.0, 0.0]),
    ]).astype(np.float32)
    y = np.repeat([0, 1, 2], 40)
    net = make_net(max_epochs=20).fit(X, y)
    X_test = X[:20]  # presses of object 0, which is confused with object 1
    for strategy in (entropy_sampling, variance_sampling, bald_sampling):
        idx, scores = strategy(net, X_test, n_instances=2, n_samples=30, random_state=0)
        assert set(idx.tolist()) == {0, 1}, strategy.__name__
        assert scores[2] < min(scores[0], scores[1])


def test_random_sampling_is_uniform(net, blobs):
    X, _ = blobs
    picks = [random_sampling(net, X[:2], random_state=s)[0][0] for s in range(600)]
    counts = np.bincount(picks, minlength=3)
    assert counts.min() > 150  # expected 200 each
    # it runs no forward pass
    before = MCDropoutNet.n_mc_calls
    random_sampling(net, X[:2], random_state=0)
    assert MCDropoutNet.n_mc_calls == before


def test_ties_are_broken_by_the_seed_not_always_class_0():
    class Uniform:
        classes_ = np.arange(4)

        def predict_proba_samples(self, X, n_samples=50, random_state=None):
            return np.full((n_samples, len(X), 4), 0.25)

    firsts = {entropy_sampling(Uniform(), np.zeros((2, 1)), random_state=s)[0][0] for s in range(40)}
    assert firsts == {0, 1, 2, 3}


def test_through_pipeline(blobs):
    import torch

    torch.manual_seed(0)
    X, y = blobs
    X_shifted = X * 10 + 100  # the scaler matters
    pipe = make_pipeline(StandardScaler(), make_net(max_epochs=10)).fit(X_shifted, y)
    Xt = pipe[:-1].transform(X_shifted[:9])
    p_direct = pipe[-1].predict_proba_samples(Xt, n_samples=12, random_state=5)
    p_pipe = _predict_proba_samples(pipe, X_shifted[:9], n_samples=12, random_state=5)
    np.testing.assert_allclose(p_pipe, p_direct)
    idx, scores = variance_sampling(pipe, X_shifted[:9], n_samples=12, random_state=0)
    assert idx.shape == (1,) and scores.shape == (3,)
    idx, _ = random_sampling(pipe, X_shifted[:9], random_state=0)
    assert 0 <= idx[0] < 3


def test_passthrough_step_is_skipped(net, blobs):
    X, _ = blobs
    pipe = Pipeline([("nothing", "passthrough"), ("net", net)])
    np.testing.assert_allclose(
        _predict_proba_samples(pipe, X[:3], n_samples=4, random_state=1),
        net.predict_proba_samples(X[:3], n_samples=4, random_state=1),
    )


def test_get_strategy():
    assert get_strategy("entropy") is entropy_sampling
    assert get_strategy("variance") is variance_sampling
    assert get_strategy("bald") is bald_sampling
    assert get_strategy("random") is random_sampling
    with pytest.raises(ValueError, match="unknown query strategy 'margin'"):
        get_strategy("margin")
    with pytest.raises(TypeError, match="name or a callable"):
        get_strategy(3)


# ---------------------------------------------------------------- bad input
@pytest.mark.parametrize("strategy", STRATEGIES)
def test_empty_test_set(strategy, net):
    with pytest.raises(ValueError, match="X_test is empty"):
        strategy(net, np.zeros((0, 4), dtype=np.float32))
    with pytest.raises(ValueError, match="X_test is empty"):
        strategy(net, [])


@pytest.mark.parametrize("strategy", STRATEGIES)
@pytest.mark.parametrize("n_instances", [0, -1, 4, 1.5, True])
def test_bad_n_instances(strategy, n_instances, net, blobs):
    X, _ = blobs
    with pytest.raises(ValueError, match="n_instances"):
        strategy(net, X[:3], n_instances=n_instances, n_samples=3)


@pytest.mark.parametrize("kind", sorted(UNCERTAIN))
def test_bad_n_samples(kind, net, blobs):
    X, _ = blobs
    with pytest.raises(ValueError, match="n_samples must be a positive int"):
        UNCERTAIN[kind](net, X[:3], n_samples=0)


def test_estimator_without_mc_dropout(blobs):
    from sklearn.linear_model import LogisticRegression

    X, y = blobs
    lr = LogisticRegression().fit(X, y)
    with pytest.raises(TypeError, match="no predict_proba_samples"):
        entropy_sampling(lr, X[:3])
    with pytest.raises(TypeError, match="no predict_proba_samples"):
        entropy_sampling(make_pipeline(StandardScaler(), lr).fit(X, y), X[:3])
