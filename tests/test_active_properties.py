"""Hypothesis property tests over the per-class scores, the strategies and the learner.

Extreme inputs: float16, probabilities exactly 0 or 1, one MC pass, one test
press, identical predictions, two classes; for the learner, classes missing
from the initial set and a reservoir cap below the batch.
"""

import numpy as np
import pytest
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st
from hypothesis.extra import numpy as hnp

from sklearn_hardness.active import (
    ActiveLearner,
    class_uncertainty,
    margin_sampling,
    random_sampling,
    variance_decomposition,
)
from sklearn_hardness.active._strategies import get_strategy

from ._active_net import CentroidMC

NAMES = ("entropy", "variance", "bald", "margin", "mc_variance", "thompson", "random")
FAST = settings(max_examples=150, deadline=None, suppress_health_check=[HealthCheck.too_slow])


def _proba_arrays(dtype, min_classes=2, max_classes=6):
    shapes = hnp.array_shapes(min_dims=3, max_dims=3, min_side=1, max_side=6).filter(
        lambda s: min_classes <= s[2] <= max_classes
    )

    @st.composite
    def build(draw):
        shape = draw(shapes)
        kind = draw(st.sampled_from(["dirichlet", "onehot", "zeros", "uniform", "same_passes"]))
        seed = draw(st.integers(0, 2**32 - 1))
        rng = np.random.default_rng(seed)
        n, l, m = shape
        if kind in ("dirichlet", "same_passes"):
            alpha = draw(st.sampled_from([1e-3, 0.01, 0.1, 1.0, 100.0]))
            p = rng.dirichlet(np.full(m, alpha), size=(n, l))
            p = np.nan_to_num(p / p.sum(axis=-1, keepdims=True))
            if kind == "same_passes":  # identical predictions in every pass
                p = np.repeat(p[:1], n, axis=0)
        elif kind == "onehot":  # probabilities exactly 0 and 1
            p = np.eye(m)[rng.integers(0, m, size=(n, l))]
        elif kind == "zeros":  # exact zeros mixed with positive values
            p = rng.random(shape) * (rng.random(shape) < 0.5)
            p[..., 0] += 1e-3
            p = p / p.sum(axis=-1, keepdims=True)
        else:
            p = np.full(shape, 1.0 / m)
        return p.astype(dtype)

    return build()


ANY_PROBA = st.one_of(_proba_arrays(np.float64), _proba_arrays(np.float32), _proba_arrays(np.float16))


@FAST
@given(p=ANY_PROBA)
def test_class_uncertainty_properties(p):
    m = p.shape[2]
    h = class_uncertainty(p, "entropy")
    v = class_uncertainty(p, "variance")
    b = class_uncertainty(p, "bald")
    for s in (h, v, b):
        assert s.shape == (m,) and s.dtype == np.float64
        assert np.all(np.isfinite(s))
        assert np.all(s >= 0)
    assert np.all(h <= 1 / np.e + 1e-12)
    assert np.all(v <= 0.25 + 1e-12)
    assert np.all(b <= 1 / np.e + 1e-12)
    # the total BALD score is a mutual information, bounded by log(n_classes)
    assert b.sum() <= np.log(m) + 1e-9
    if p.shape[0] == 1:
        assert np.all(b == 0)


@FAST
@given(p=ANY_PROBA)
def test_variance_decomposition_properties(p):
    d = variance_decomposition(p)
    for part in ("total", "mc", "between", "mc_share"):
        assert d[part].shape == (p.shape[2],) and np.all(np.isfinite(d[part]))
        assert np.all(d[part] >= 0)
    np.testing.assert_allclose(d["mc"] + d["between"], d["total"], atol=1e-15)
    np.testing.assert_allclose(d["total"], class_uncertainty(p, "variance"), atol=1e-15)
    assert np.all(d["mc_share"] <= 1 + 1e-12)
    p64 = p.astype(np.float64)
    if p.shape[0] == 1 or np.all(p64 == p64[:1]):  # one pass, or all passes agree
        np.testing.assert_allclose(d["mc"], 0, atol=1e-15)
    if p.shape[1] == 1:  # one test press: nothing between presses
        np.testing.assert_allclose(d["between"], 0, atol=1e-15)


@FAST
@given(p=ANY_PROBA, name=st.sampled_from(NAMES), data=st.data())
def test_strategy_properties(p, name, data):
    m = p.shape[2]
    n_instances = data.draw(st.integers(1, m))
    seed = data.draw(st.integers(0, 2**31 - 2))
    idx, scores = get_strategy(name)(p, n_instances, random_state=seed)
    assert idx.shape == (n_instances,) and np.issubdtype(idx.dtype, np.integer)
    assert len(set(idx.tolist())) == n_instances and np.all((0 <= idx) & (idx < m))
    assert scores.shape == (m,) and scores.dtype == np.float64 and np.all(np.isfinite(scores))
    # the chosen classes are the best-scoring ones, best first
    assert np.all(np.diff(scores[idx]) <= 0)
    rest = np.setdiff1d(np.arange(m), idx)
    assert np.all(scores[rest] <= scores[idx].min())
    if name not in ("random", "thompson"):  # seeded tie-breaking aside, the scores depend only on p
        perm = np.random.default_rng(seed).permutation(m)
        _, permuted = get_strategy(name)(p[:, :, perm], n_instances, random_state=seed)
        if name == "margin":  # the decision may move between exactly tied classes
            mu = p.astype(np.float64).mean(axis=(0, 1))
            if np.sum(mu == mu.max()) > 1:
                return
        np.testing.assert_allclose(permuted, scores[perm], atol=1e-15)


@FAST
@given(p=ANY_PROBA)
def test_margin_properties(p):
    idx, scores = margin_sampling(p, n_instances=p.shape[2], random_state=0)
    mu = p.astype(np.float64).mean(axis=(0, 1))
    assert np.all((scores >= -1) & (scores <= 0))
    decision = int(np.flatnonzero(scores == -1)[0]) if np.sum(scores == -1) == 1 else None
    if decision is not None:
        assert mu[decision] == mu.max()
    # the runner-up comes first: its score is minus the gap between the two best classes
    top2 = np.sort(mu)[-2:]
    assert scores[idx[0]] == pytest.approx(top2[0] - top2[1], abs=1e-12)


@FAST
@given(p=st.one_of(_proba_arrays(np.float64, max_classes=2), _proba_arrays(np.float16, max_classes=2)))
def test_two_classes_share_their_variance(p):
    # with two classes p_1 = 1 - p_0, so both have the same variance (and parts),
    # up to the rounding of float16 rows (sums off by up to ~1e-3)
    tol = 2e-3 if p.dtype == np.float16 else 1e-12
    d = variance_decomposition(p)
    for part in ("total", "mc", "between"):
        assert d[part][0] == pytest.approx(d[part][1], abs=tol)


@FAST
@given(p=ANY_PROBA, seed=st.integers(0, 2**31 - 2))
def test_random_sampling_ignores_the_probabilities(p, seed):
    a = random_sampling(p, random_state=seed)
    b = random_sampling(np.full_like(p, 1.0 / p.shape[2]), random_state=seed)
    np.testing.assert_array_equal(a[0], b[0])


# ------------------------------------------------------------- the learner
@settings(max_examples=60, deadline=None)
@given(
    counts=st.lists(st.integers(0, 3), min_size=2, max_size=4),
    batch=st.integers(1, 5),
    cap=st.one_of(st.none(), st.integers(1, 8)),
    strategy=st.sampled_from(NAMES),
    string_labels=st.booleans(),
    seed=st.integers(0, 1000),
)
def test_learner_properties(counts, batch, cap, strategy, string_labels, seed):
    rng = np.random.default_rng(seed)
    names = np.array([f"obj{c}" for c in range(len(counts))]) if string_labels else np.arange(len(counts))
    y0 = np.repeat(names, counts)
    X0 = rng.normal(size=(len(y0), 3)) + np.repeat(np.arange(len(counts)), counts)[:, None]
    learner = ActiveLearner(CentroidMC(), strategy, max_reservoir=cap, n_samples=4,
                            classes=names, random_state=seed)
    missing = [c for c, n in zip(names.tolist(), counts) if n == 0]
    if not len(y0):
        with pytest.raises(ValueError, match="X is empty"):
            learner.fit(X0, y0)
        return
    if missing:
        # a class without initial presses: a clear error naming it, nothing fitted
        with pytest.raises(ValueError, match=r"classes \[.*\] are missing from the initial"):
            learner.fit(X0, y0)
        assert not hasattr(learner, "estimator_")
        return
    learner.fit(X0, y0)
    X_test = rng.normal(size=(3, 3))
    idx, scores = learner.query(X_test)
    assert 0 <= idx[0] < len(counts) and learner.history_[-1]["n_test"] == 3
    X_new = rng.normal(size=(batch, 3))
    y_new = np.full(batch, learner.classes_[idx[0]])
    size_before = len(learner.reservoir_y_)
    if cap is not None and cap < batch:
        # reservoir cap below the batch: a clear error, the reservoir untouched
        with pytest.raises(ValueError, match=f"max_reservoir={cap} is smaller than the batch of {batch}"):
            learner.teach(X_new, y_new)
        assert len(learner.reservoir_y_) == size_before and learner.n_iterations_ == 0
        return
    learner.teach(X_new, y_new)
    size = size_before + batch
    assert len(learner.reservoir_y_) == size
    assert learner.estimator_.n_train_ == (size if cap is None else min(cap, size))
    assert learner.history_[-1]["train_size"] == learner.estimator_.n_train_
