"""Query strategies as functions of MC-dropout probabilities, on a real (tiny) net."""

import numpy as np
import pytest

from sklearn_hardness.active import (
    bald_sampling,
    class_uncertainty,
    entropy_sampling,
    margin_sampling,
    mc_variance_sampling,
    random_sampling,
    thompson_sampling,
    variance_decomposition,
    variance_sampling,
)
from sklearn_hardness.active._strategies import get_strategy
from sklearn_hardness.utils._param_validation import InvalidParameterError

from ._active_net import make_blobs, make_net

STRATEGIES = [entropy_sampling, variance_sampling, bald_sampling, margin_sampling,
              mc_variance_sampling, thompson_sampling, random_sampling]
UNCERTAIN = {"entropy": entropy_sampling, "variance": variance_sampling, "bald": bald_sampling}


@pytest.fixture(scope="module")
def blobs():
    return make_blobs(n_per_class=30, seed=0)


@pytest.fixture(scope="module")
def proba(blobs):
    import torch

    torch.manual_seed(0)
    X, y = blobs
    net = make_net(max_epochs=15).fit(X, y)
    return net.predict_proba_samples(X[:12], n_samples=20, random_state=0)


@pytest.mark.parametrize("strategy", STRATEGIES)
def test_return_shape_order_and_scores(strategy, proba):
    idx, scores = strategy(proba, n_instances=2, random_state=0)
    assert idx.shape == (2,) and np.issubdtype(idx.dtype, np.integer)
    assert len(set(idx.tolist())) == 2
    assert scores.shape == (3,) and scores.dtype == np.float64
    # highest score first, and nothing left out scores higher
    assert scores[idx[0]] >= scores[idx[1]]
    rest = np.setdiff1d(np.arange(3), idx)
    assert np.all(scores[rest] <= scores[idx[1]])


@pytest.mark.parametrize("kind", sorted(UNCERTAIN))
def test_scores_are_class_uncertainty(kind, proba):
    _, scores = UNCERTAIN[kind](proba, random_state=3)
    np.testing.assert_allclose(scores, class_uncertainty(proba, kind))


def test_mc_variance_scores_are_the_mc_part_of_eq2(proba):
    _, scores = mc_variance_sampling(proba)
    np.testing.assert_allclose(scores, variance_decomposition(proba)["mc"])
    assert np.all(scores <= class_uncertainty(proba, "variance") + 1e-15)


@pytest.mark.parametrize("strategy", STRATEGIES)
def test_seeded_is_reproducible(strategy, proba):
    a = strategy(proba, n_instances=3, random_state=7)
    b = strategy(proba, n_instances=3, random_state=7)
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
    p = net.predict_proba_samples(X[:20], n_samples=30, random_state=0)  # presses of object 0
    for strategy in (entropy_sampling, variance_sampling, bald_sampling, mc_variance_sampling):
        idx, scores = strategy(p, n_instances=2, random_state=0)
        assert set(idx.tolist()) == {0, 1}, strategy.__name__
        assert scores[2] < min(scores[0], scores[1])
    # margin presses the competitor of the decision, never the far class first
    idx, scores = margin_sampling(p, n_instances=2, random_state=0)
    decision = p.mean(axis=(0, 1)).argmax()
    assert idx[0] == 1 - decision and idx[1] == 2


def test_random_sampling_is_uniform(proba):
    picks = [random_sampling(proba, random_state=s)[0][0] for s in range(600)]
    counts = np.bincount(picks, minlength=3)
    assert counts.min() > 150  # expected 200 each


@pytest.mark.parametrize("strategy", STRATEGIES)
def test_ties_are_broken_by_the_seed_not_always_class_0(strategy):
    uniform = np.full((3, 2, 4), 0.25)
    firsts = {strategy(uniform, random_state=s)[0][0] for s in range(60)}
    assert firsts == {0, 1, 2, 3}


# ------------------------------------------------ constructed cases: what each picks
def _case():
    """Three classes on two test presses, four passes, each class uncertain in one way.

    - class 0 (the decision): the presses disagree (0.9 vs 0.3), the passes agree;
    - class 1: the runner-up, its probability varies between the passes;
    - class 2: stable and small.
    """
    p = np.empty((4, 2, 3))
    wobble = np.array([-0.1, 0.1, -0.1, 0.1])
    p[:, 0] = [0.9, 0.05, 0.05]
    p[:, 1, 0] = 0.3
    p[:, 1, 1] = 0.55 + wobble
    p[:, 1, 2] = 0.15 - wobble
    p[:, 0, 1] = 0.05
    return p


def test_constructed_case_variance_follows_press_disagreement():
    p = _case()
    assert variance_sampling(p)[0][0] == 0  # Eq. 2: the decision class, from press disagreement
    d = variance_decomposition(p)
    assert d["between"][0] > d["mc"][0] == 0  # ... none of it from the model


def test_constructed_case_mc_variance_follows_the_passes():
    p = _case()
    idx, scores = mc_variance_sampling(p, n_instances=3, random_state=0)
    assert scores[0] == 0  # the passes agree on class 0
    assert set(idx[:2].tolist()) == {1, 2}  # classes 1 and 2 wobble together


def test_constructed_case_margin_presses_the_runner_up():
    p = _case()
    idx, scores = margin_sampling(p, n_instances=3)
    mu = p.mean(axis=(0, 1))
    assert mu.argmax() == 0
    assert idx.tolist() == [1, 2, 0]  # runner-up first, the decision last
    np.testing.assert_allclose(scores, [-1.0, mu[1] - mu[0], mu[2] - mu[0]])


def test_variance_reinforces_itself_mc_variance_does_not():
    """The self-reinforcing query: class 1 is confused with the test object.
    After its presses are added the model is sure on some test presses and
    unsure on others, so its probability moves towards 0.5 on average and
    Eq. 2 rises, while the MC part (the model's own uncertainty) falls."""
    n = 8
    before = np.empty((n, 4, 2))
    before[..., 1] = 0.2 + 0.1 * np.sin(np.arange(n))[:, None]  # unsure everywhere
    after = np.empty((n, 4, 2))
    after[..., 1] = np.array([0.95, 0.9, 0.1, 0.05])  # sure, but presses disagree
    for p in (before, after):
        p[..., 0] = 1 - p[..., 1]
    v_before, v_after = (class_uncertainty(p, "variance")[1] for p in (before, after))
    mc_before, mc_after = (variance_decomposition(p)["mc"][1] for p in (before, after))
    assert v_after > v_before  # Eq. 2 asks for class 1 again, and more urgently
    assert mc_after < mc_before  # the model's own uncertainty about class 1 fell
    assert mc_after == pytest.approx(0, abs=1e-20)


def test_get_strategy():
    assert get_strategy("entropy") is entropy_sampling
    assert get_strategy("variance") is variance_sampling
    assert get_strategy("bald") is bald_sampling
    assert get_strategy("margin") is margin_sampling
    assert get_strategy("mc_variance") is mc_variance_sampling
    assert get_strategy("random") is random_sampling

    def custom(proba_samples, n_instances=1):
        return np.arange(n_instances)

    assert get_strategy(custom) is custom
    with pytest.raises(InvalidParameterError, match="'strategy' parameter of get_strategy"):
        get_strategy("uncertainty")
    with pytest.raises(TypeError, match="'strategy' parameter of get_strategy"):
        get_strategy(3)


# ---------------------------------------------------------------- bad input
@pytest.mark.parametrize("strategy", STRATEGIES)
@pytest.mark.parametrize("n_instances", [0, -1, 1.5, "2", None])
def test_bad_n_instances(strategy, n_instances, proba):
    with pytest.raises(InvalidParameterError, match="'n_instances' parameter"):
        strategy(proba, n_instances=n_instances)


@pytest.mark.parametrize("strategy", STRATEGIES)
def test_more_instances_than_classes(strategy, proba):
    with pytest.raises(ValueError, match="n_instances=4 is larger than the number of classes"):
        strategy(proba, n_instances=4)


@pytest.mark.parametrize("strategy", STRATEGIES)
@pytest.mark.parametrize(
    "bad, err, match",
    [
        (None, TypeError, "'proba_samples' parameter"),
        ("p", TypeError, "'proba_samples' parameter"),
        (np.full((3, 2), 0.5), ValueError, "3-D"),
        (np.zeros((2, 0, 3)), ValueError, "at least one MC pass and one test input"),
        (np.ones((2, 2, 1)), ValueError, "at least 2 classes"),
        (np.array([[[0.5, np.nan]]]), ValueError, "NaN"),
        (np.array([[[2.0, -1.0]]]), ValueError, "logits"),
    ],
)
def test_bad_proba_samples(strategy, bad, err, match):
    with pytest.raises(err, match=match):
        strategy(bad)


@pytest.mark.parametrize("strategy", STRATEGIES)
def test_bad_random_state(strategy, proba):
    with pytest.raises(InvalidParameterError, match="'random_state' parameter"):
        strategy(proba, random_state="seed")


def test_thompson_draws_the_first_class_with_its_mean_probability(proba):
    mu = proba.astype(np.float64).mean(axis=(0, 1))
    firsts = np.array([thompson_sampling(proba, random_state=s)[0][0] for s in range(3000)])
    freq = np.bincount(firsts, minlength=3) / len(firsts)
    np.testing.assert_allclose(freq, mu, atol=0.03)  # 3000 draws: binomial sd <= 0.009
    # a class the model rules out is never drawn first, and all classes come back with n_instances=3
    p = np.tile([0.6, 0.4, 0.0], (5, 2, 1))
    for s in range(50):
        idx, scores = thompson_sampling(p, n_instances=3, random_state=s)
        assert idx[2] == 2 and scores[2] == 0.0
    # same seed, same draw
    first, again = thompson_sampling(proba, 2, random_state=7), thompson_sampling(proba, 2, random_state=7)
    assert first[0].tolist() == again[0].tolist()


def test_thompson_presses_the_believed_class_and_spreads_with_doubt():
    # the effect that sets it apart from the uncertainty scores: they press the confused
    # class, Thompson presses the believed one most often and the competitor in proportion
    sure = np.tile([0.05, 0.9, 0.05], (10, 5, 1))
    unsure = np.tile([0.45, 0.1, 0.45], (10, 5, 1))
    first = lambda p: np.bincount([thompson_sampling(p, random_state=s)[0][0] for s in range(500)], minlength=3)
    assert first(sure)[1] > 400
    c = first(unsure)
    assert c[0] > 180 and c[2] > 180 and c[1] < 90


# --- margin: the decision class comes last, also when the model is saturated ------------


def _old_margin(p, n_instances, seed):
    """margin_sampling as it ranked before: the decision scored -1 in the ranking too."""
    from sklearn.utils import check_random_state

    from sklearn_hardness.active._strategies import _top_classes

    mu = np.asarray(p, dtype=np.float64).mean(axis=(0, 1))
    rng = check_random_state(seed)
    top = _top_classes(mu, 1, rng)[0]
    scores = mu - mu[top]
    scores[top] = -1.0
    return _top_classes(scores, n_instances, rng), scores, rng


def test_margin_saturated_model_puts_the_decision_class_last():
    p = np.zeros((10, 4, 3))
    p[..., 0] = 1.0  # saturated softmax: decision class 0 with mu = 1, the others 0
    for s in range(50):
        idx, scores = margin_sampling(p, n_instances=3, random_state=s)
        assert idx[-1] == 0 and sorted(idx[:2].tolist()) == [1, 2]
        np.testing.assert_array_equal(scores, [-1.0, -1.0, -1.0])  # returned scores as before
        assert margin_sampling(p, random_state=s)[0][0] != 0
    # both other classes are still drawn first, by the random tie-break
    firsts = {margin_sampling(p, random_state=s)[0][0] for s in range(50)}
    assert firsts == {1, 2}


def test_margin_unchanged_when_the_decision_is_not_tied_at_minus_one():
    rng = np.random.default_rng(0)
    for trial in range(60):
        p = rng.dirichlet(np.full(4, 0.4), size=(5, 3))
        if trial % 3 == 0:
            p = np.round(p, 1)  # exact ties of the decision and of the others
            p /= p.sum(axis=-1, keepdims=True)
        for n in (1, 4):
            seed = np.random.RandomState(trial)
            idx, scores = margin_sampling(p, n_instances=n, random_state=seed)
            old_idx, old_scores, old_rng = _old_margin(p, n, trial)
            np.testing.assert_array_equal(idx, old_idx)
            np.testing.assert_array_equal(scores, old_scores)
            assert seed.randint(2**31) == old_rng.randint(2**31)  # same draws consumed


# --- thompson: later draws stay weighted when the priorities underflow ------------------


def _mu(p):
    mu = np.asarray(p, dtype=np.float64).mean(axis=(0, 1))
    return mu / mu.sum()


def _old_thompson(p, n_instances, seed):
    """thompson_sampling as it ranked before: on exp(log(u) / mu) alone."""
    from sklearn.utils import check_random_state

    from sklearn_hardness.active._strategies import _top_classes

    mu = _mu(p)
    rng = check_random_state(seed)
    u = rng.random_sample(mu.shape[0])
    with np.errstate(divide="ignore", under="ignore"):
        scores = np.where(mu > 0, np.exp(np.log(u) / np.where(mu > 0, mu, 1.0)), 0.0)
    return _top_classes(scores, n_instances, rng), scores, rng


def test_thompson_rare_classes_are_drawn_in_the_order_of_their_log_keys():
    """Efraimidis-Spirakis in log space: the order is that of log(u_i) / mu_i, exactly
    (here exp underflows to 0 for both rare classes, so the old ranking fell to the
    uniform tie-break for the second and third draws)."""
    p = np.tile([0.998, 0.0013, 0.0007], (2, 1, 1))
    mu = _mu(p)
    seconds = []
    n_differs = 0
    for s in range(400):
        idx, scores = thompson_sampling(p, n_instances=3, random_state=s)
        u = np.random.RandomState(s).random_sample(3)
        keys = np.log(u) / mu
        np.testing.assert_array_equal(idx, np.argsort(-keys))
        old_idx, old_scores, _ = _old_thompson(p, 3, s)
        np.testing.assert_array_equal(scores, old_scores)  # the returned priorities
        assert idx[0] == old_idx[0]  # the first draw is the same
        n_differs += not np.array_equal(idx, old_idx)
        seconds.append(idx[1])
    assert n_differs > 20  # the case the old ranking got wrong does occur
    # P(class 1 second) = 0.0013 / 0.002 = 0.65 given class 0 first (fixed seeds)
    assert 0.58 < np.mean(np.array(seconds) == 1) < 0.72


def test_thompson_unchanged_when_nothing_underflows():
    rng = np.random.default_rng(1)
    cases = [np.tile(row, (3, 2, 1)) for row in ([0.5, 0.3, 0.2], [0.25] * 4, [0.7, 0.3, 0.0])]
    cases += [rng.dirichlet(np.ones(5), size=(4, 3)) for _ in range(5)]
    for p in cases:
        for s in range(100):
            seed = np.random.RandomState(s)
            n = p.shape[-1]
            idx, scores = thompson_sampling(p, n_instances=n, random_state=seed)
            old_idx, old_scores, old_rng = _old_thompson(p, n, s)
            np.testing.assert_array_equal(idx, old_idx)
            np.testing.assert_array_equal(scores, old_scores)
            assert seed.randint(2**31) == old_rng.randint(2**31)  # same draws consumed
