"""ActiveLearner: Algorithm 1 (fit / query / teach on a capped reservoir)."""

import numpy as np
import pytest
from sklearn.base import BaseEstimator, ClassifierMixin, TransformerMixin, clone
from sklearn.exceptions import NotFittedError
from sklearn.pipeline import Pipeline, make_pipeline
from sklearn.preprocessing import StandardScaler

from sklearn_hardness.active import (
    ActiveLearner,
    PressOracle,
    class_uncertainty,
    entropy_sampling,
    variance_decomposition,
    variance_sampling,
)
from sklearn_hardness.active._rows import concat_rows as _concat_rows
from sklearn_hardness.metrics import hardness_mae
from sklearn_hardness.utils._param_validation import InvalidParameterError

from ._active_net import MCDropoutNet, make_blobs, make_net


class CountingScaler(TransformerMixin, BaseEstimator):
    """StandardScaler that counts fits and transformed rows (class-level counters)."""

    n_fit = 0
    n_rows_transformed = 0

    def fit(self, X, y=None):
        type(self).n_fit += 1
        X = np.asarray(X, dtype=np.float32)
        self.mean_, self.scale_ = X.mean(axis=0), X.std(axis=0) + 1e-6
        return self

    def transform(self, X):
        X = np.asarray(X, dtype=np.float32)
        type(self).n_rows_transformed += X.shape[0]
        return (X - self.mean_) / self.scale_


@pytest.fixture(scope="module")
def data():
    X, y = make_blobs(n_per_class=40, spread=1.2, seed=1)
    oracle = PressOracle(X, y, random_state=0)
    X0, y0 = oracle.initial(3)
    X_test, y_test = oracle.press([0, 1, 2], 8)
    return X0, y0, X_test, y_test, oracle


def _pool(data, seed=1):
    X, y = make_blobs(n_per_class=40, spread=1.2, seed=seed)
    return PressOracle(X, y, random_state=seed)


def test_algorithm_1_loop(data):
    X0, y0, X_test, y_test, _ = data
    oracle = _pool(data, seed=2)
    learner = ActiveLearner(
        make_net(), "variance", initial_epochs=6, epochs_per_query=3,
        max_reservoir=12, n_samples=10, random_state=0,
    ).fit(X0, y0)
    assert learner.initial_train_loss_ is not None and np.isfinite(learner.initial_train_loss_)
    np.testing.assert_array_equal(learner.classes_, [0, 1, 2])
    accs = [learner.score(X_test, y_test)]
    for it in range(4):
        idx, scores = learner.query(X_test)
        assert idx.shape == (1,) and scores.shape == (3,)
        X_new, y_new = oracle.press(learner.classes_[idx[0]], 3)
        learner.teach(X_new, y_new)
        accs.append(learner.score(X_test, y_test))
    assert learner.n_iterations_ == 4
    assert len(learner.reservoir_y_) == 9 + 4 * 3
    events = [h["event"] for h in learner.history_]
    assert events == ["fit"] + ["query", "teach"] * 4
    teach = [h for h in learner.history_ if h["event"] == "teach"]
    assert [h["reservoir_size"] for h in teach] == [12, 15, 18, 21]
    assert [h["train_size"] for h in teach] == [12, 12, 12, 12]  # capped at M
    assert all(np.isfinite(h["train_loss"]) for h in teach)
    queries = [h for h in learner.history_ if h["event"] == "query"]
    for h in queries:
        # the strategy's scores are the recorded variance of the same MC passes
        np.testing.assert_allclose(h["scores"], h["variance"])
        assert h["entropy"].shape == h["bald"].shape == (3,)
        # ... and its two parts (law of total variance)
        assert h["variance_mc"].shape == h["variance_between"].shape == (3,)
        np.testing.assert_allclose(h["variance_mc"] + h["variance_between"], h["variance"])
    assert learner.uncertainty_history("entropy").shape == (4,)
    assert learner.uncertainty_history("variance", reduce=None).shape == (4, 3)
    np.testing.assert_allclose(
        learner.uncertainty_history("variance_mc", reduce=None)
        + learner.uncertainty_history("variance_between", reduce=None),
        learner.uncertainty_history("variance", reduce=None),
    )
    with pytest.raises(InvalidParameterError, match="'kind' parameter"):
        learner.uncertainty_history("margin")
    with pytest.raises(InvalidParameterError, match="'reduce' parameter"):
        learner.uncertainty_history("variance", reduce="sum")
    # the experiments' metrics can be read off directly
    mae = hardness_mae(y_test, learner.predict(X_test), [1.13, 1.02, 0.79])
    assert accs[-1] >= 0.8  # separable blobs: the loop trains a useful model
    assert mae < 0.1


def test_warm_start_and_training_subset_size(data):
    X0, y0, X_test, _, oracle = data
    learner = ActiveLearner(
        make_net(batch_size=4), "entropy", initial_epochs=4, epochs_per_query=2,
        max_reservoir=10, n_samples=5, random_state=1,
    ).fit(X0, y0)
    net = learner.estimator_
    assert len(net.history) == 4
    first_weight = net.module_.net[0].weight.detach().clone()
    X_new, y_new = make_blobs(n_per_class=2, seed=9)
    learner.teach(X_new, y_new)  # reservoir 9 + 6 = 15 > M = 10
    # partial_fit: the skorch history continues (a refit would restart it) ...
    assert len(net.history) == 6
    assert learner.estimator_ is net
    # ... and the weights moved on from where they were
    assert not np.allclose(net.module_.net[0].weight.detach(), first_weight)
    # each of the 2 epochs saw exactly M = 10 samples
    for epoch in net.history[-2:]:
        assert sum(b["train_batch_size"] for b in epoch["batches"]) == 10
    learner.teach(X_new[:3], y_new[:3])  # 18 > 10
    assert sum(b["train_batch_size"] for b in net.history[-1]["batches"]) == 10


def test_no_cap_trains_on_whole_reservoir(data):
    X0, y0, _, _, _ = data
    learner = ActiveLearner(make_net(batch_size=50), initial_epochs=2, epochs_per_query=1,
                            random_state=0).fit(X0, y0)
    X_new, y_new = make_blobs(n_per_class=4, seed=5)
    learner.teach(X_new, y_new)
    assert sum(b["train_batch_size"] for b in learner.estimator_.history[-1]["batches"]) == 21


def test_estimator_is_cloned_not_modified(data):
    X0, y0, _, _, _ = data
    net = make_net()
    learner = ActiveLearner(net, initial_epochs=2).fit(X0, y0)
    assert learner.estimator_ is not net
    assert not hasattr(net, "module_")
    assert clone(learner).get_params()["initial_epochs"] == 2


def test_random_state_makes_runs_reproducible(data):
    X0, y0, X_test, _, _ = data

    def run():
        learner = ActiveLearner(make_net(), "bald", initial_epochs=3, epochs_per_query=2,
                                max_reservoir=10, n_samples=6, random_state=42).fit(X0, y0)
        out = []
        for _ in range(2):
            idx, scores = learner.query(X_test)
            X_new, y_new = make_blobs(n_per_class=1, seed=int(idx[0]))
            learner.teach(X_new, y_new)
            out.append((idx, scores, learner.history_[-1]["train_loss"]))
        return out, learner.predict_proba(X_test)

    (a, pa), (b, pb) = run(), run()
    for (ia, sa, la), (ib, sb, lb) in zip(a, b):
        np.testing.assert_array_equal(ia, ib)
        np.testing.assert_allclose(sa, sb)
        assert la == lb
    np.testing.assert_allclose(pa, pb)


def test_query_runs_mc_passes_once_and_strategy_reuses_them(data):
    X0, y0, X_test, _, _ = data
    learner = ActiveLearner(make_net(), entropy_sampling, initial_epochs=2, n_samples=7,
                            random_state=0).fit(X0, y0)
    before = MCDropoutNet.n_mc_calls
    idx, scores = learner.query(X_test, n_instances=2)
    assert MCDropoutNet.n_mc_calls == before + 1
    assert idx.shape == (2,)
    np.testing.assert_allclose(scores, learner.history_[-1]["entropy"])


def test_string_and_custom_strategies(data):
    X0, y0, X_test, _, _ = data
    for name in ["entropy", "variance", "bald", "margin", "mc_variance", "thompson", "random"]:
        learner = ActiveLearner(make_net(), name, initial_epochs=1, n_samples=3,
                                random_state=0).fit(X0, y0)
        idx, scores = learner.query(X_test)
        assert 0 <= idx[0] < 3

    seen = []

    def always_last(proba_samples, n_instances=1):  # indices only, no random_state
        seen.append(proba_samples.shape)
        return np.arange(proba_samples.shape[-1])[-n_instances:]

    learner = ActiveLearner(make_net(), always_last, initial_epochs=1, n_samples=3).fit(X0, y0)
    idx, scores = learner.query(X_test)
    assert idx.tolist() == [2] and scores is None
    assert seen == [(3, len(X_test), 3)]  # the MC passes on the test presses
    assert learner.history_[-1]["variance"].shape == (3,)  # still recorded

    def bad(proba_samples, n_instances=1):
        return np.array([5])

    learner.set_params(query_strategy=bad)
    with pytest.raises(ValueError, match=r"class indices in \[0, 3\)"):
        learner.query(X_test)


def test_pipeline_fits_features_once_and_caches_them(data):
    X0, y0, X_test, y_test, _ = data
    shift = lambda X: X * 5 + 50  # noqa: E731  (the scaler matters)
    X0s, X_tests = shift(X0), shift(X_test)
    CountingScaler.n_fit = CountingScaler.n_rows_transformed = 0
    pipe = Pipeline([("scale", CountingScaler()), ("net", make_net())])
    learner = ActiveLearner(pipe, "variance", initial_epochs=3, epochs_per_query=2,
                            max_reservoir=100, n_samples=4, random_state=0).fit(X0s, y0)
    assert CountingScaler.n_fit == 1
    scaler = learner.estimator_.named_steps["scale"]
    mean0 = scaler.mean_.copy()
    # the reservoir holds features, not raw input
    np.testing.assert_allclose(learner.reservoir_X_, scaler.transform(X0s), rtol=1e-6)
    n0 = CountingScaler.n_rows_transformed
    for _ in range(2):
        learner.query(X_tests)
        learner.score(X_tests, y_test)
        learner.predict_proba_samples(X_tests, n_samples=2)
    # the test presses went through the feature steps once
    assert CountingScaler.n_rows_transformed - n0 == len(X_tests)
    X_new, y_new = make_blobs(n_per_class=2, seed=3)
    n1 = CountingScaler.n_rows_transformed
    learner.teach(shift(X_new), y_new)
    learner.teach(shift(X_new), y_new)
    # new presses are transformed once each; the reservoir is never recomputed
    assert CountingScaler.n_rows_transformed - n1 == 2 * len(X_new)
    assert CountingScaler.n_fit == 1
    np.testing.assert_array_equal(scaler.mean_, mean0)
    assert learner.reservoir_X_.shape == (9 + 12, 4)
    # predictions agree with the pipeline's own
    np.testing.assert_array_equal(learner.predict(X_tests), learner.estimator_.predict(X_tests))


def test_feature_cache_can_be_disabled(data):
    X0, y0, X_test, y_test, _ = data
    CountingScaler.n_rows_transformed = 0
    learner = ActiveLearner(make_pipeline(CountingScaler(), make_net()), initial_epochs=1,
                            n_samples=2, cache_test_features=False).fit(X0, y0)
    n0 = CountingScaler.n_rows_transformed
    learner.score(X_test, y_test)
    learner.score(X_test, y_test)
    assert CountingScaler.n_rows_transformed - n0 == 2 * len(X_test)


def test_sequence_input_through_pipeline(data):
    """X as a list of per-press arrays (like videos), stacked by the first step."""
    from sklearn.preprocessing import FunctionTransformer

    X0, y0, X_test, y_test, _ = data
    stack = FunctionTransformer(lambda X: np.stack(list(X)).astype(np.float32))
    learner = ActiveLearner(make_pipeline(stack, make_net()), initial_epochs=2,
                            epochs_per_query=1, max_reservoir=10, n_samples=3,
                            random_state=0)
    learner.fit(list(X0), y0)
    idx, _ = learner.query(list(X_test))
    X_new, y_new = make_blobs(n_per_class=1, seed=4)
    learner.teach(list(X_new), y_new)
    assert learner.predict(list(X_test)).shape == (len(X_test),)


def test_concat_rows_kinds():
    import torch

    a, b = np.zeros((2, 3)), np.ones((1, 3))
    assert _concat_rows(a, b).shape == (3, 3)
    assert _concat_rows(torch.zeros(2, 3), torch.ones(1, 3)).shape == (3, 3)
    out = _concat_rows([a[0], a[1]], (b[0],))
    assert isinstance(out, list) and len(out) == 3
    with pytest.raises(ValueError, match="per sample"):
        _concat_rows(a, np.ones((1, 4)))
    import scipy.sparse as sp

    assert _concat_rows(sp.csr_matrix(a), sp.csr_matrix(b)).shape == (3, 3)


def test_concat_rows_keeps_lazy_videos_lazy():
    from sklearn_hardness.utils._lazy import LazyVideoSequence

    loaded = []

    def loader(k):
        loaded.append(k)
        return np.full((2 + k, 4, 4, 3), k, np.uint8)  # ragged lengths

    videos = LazyVideoSequence(loader, range(6))
    out = _concat_rows(videos[[0, 1]], videos[[4]])
    assert isinstance(out, LazyVideoSequence) and loaded == []
    assert [int(v[0, 0, 0, 0]) for v in out] == [0, 1, 4]
    other = LazyVideoSequence(loader, [5])  # a different sequence object, same loader
    assert isinstance(_concat_rows(videos[[0]], other), LazyVideoSequence)
    mixed = _concat_rows(videos[[0]], [np.zeros((3, 4, 4, 3), np.uint8)])
    assert isinstance(mixed, list) and len(mixed) == 2
    # the public method behind it refuses what it cannot keep lazy
    with pytest.raises(ValueError, match="same loader"):
        videos.concatenate(LazyVideoSequence(lambda k: loader(k), [1]))
    with pytest.raises(ValueError, match="same loader"):
        videos.concatenate([np.zeros((3, 4, 4, 3), np.uint8)])


class ForestMC(BaseEstimator):
    """A non-skorch probabilistic model: the trees of a random forest play the
    role of MC-dropout passes."""

    def __init__(self, n_estimators=20):
        self.n_estimators = n_estimators

    def fit(self, X, y):
        from sklearn.ensemble import RandomForestClassifier

        self.n_fit_ = getattr(self, "n_fit_", 0) + 1
        self.forest_ = RandomForestClassifier(self.n_estimators, random_state=0).fit(X, y)
        self.classes_ = self.forest_.classes_
        self.n_train_ = len(y)
        return self

    def predict_proba(self, X):
        return self.forest_.predict_proba(X)

    def predict_proba_samples(self, X, n_samples=50, random_state=None):
        rng = np.random.default_rng(random_state)
        trees = rng.choice(self.forest_.estimators_, n_samples)
        return np.stack([t.predict_proba(X) for t in trees])


def test_non_skorch_estimator_is_refit_and_string_labels(data):
    X0, y0, X_test, y_test, _ = data
    names = np.array(["hard", "medium", "soft"])
    learner = ActiveLearner(ForestMC(), "entropy", max_reservoir=12, n_samples=8,
                            random_state=0).fit(X0, names[y0])
    np.testing.assert_array_equal(learner.classes_, ["hard", "medium", "soft"])
    assert learner.initial_train_loss_ is None
    idx, scores = learner.query(X_test)
    X_new, y_new = make_blobs(n_per_class=2, seed=3)
    learner.teach(X_new, names[y_new])
    assert learner.estimator_.n_fit_ == 2 and learner.estimator_.n_train_ == 12
    assert set(learner.predict(X_test)) <= set(names)
    assert learner.score(X_test, names[y_test]) > 0.7


# ---------------------------------------------------------------- bad input
def test_unknown_strategy(data):
    X0, y0, X_test, _, _ = data
    with pytest.raises(InvalidParameterError, match="'query_strategy' parameter of ActiveLearner"):
        ActiveLearner(make_net(), "uncertainty").fit(X0, y0)
    learner = ActiveLearner(make_net(), initial_epochs=1).fit(X0, y0)
    learner.set_params(query_strategy="uncertainty")
    with pytest.raises(InvalidParameterError, match="'query_strategy' parameter"):
        learner.query(X_test)


def test_max_reservoir_smaller_than_batch(data):
    X0, y0, _, _, _ = data
    learner = ActiveLearner(make_net(), initial_epochs=1, max_reservoir=4).fit(X0, y0)
    X_new, y_new = make_blobs(n_per_class=2, seed=5)  # 6 new presses
    with pytest.raises(ValueError, match="max_reservoir=4 is smaller than the batch of 6"):
        learner.teach(X_new, y_new)
    assert len(learner.reservoir_y_) == 9  # nothing was added


def test_empty_test_set(data):
    X0, y0, _, _, _ = data
    learner = ActiveLearner(make_net(), initial_epochs=1).fit(X0, y0)
    with pytest.raises(ValueError, match="X_test is empty"):
        learner.query(np.zeros((0, 4), dtype=np.float32))


def test_classes_missing_from_initial_set(data):
    X0, y0, _, _, _ = data
    keep = y0 != 1
    with pytest.raises(ValueError, match=r"classes \[1\] are missing from the initial"):
        ActiveLearner(make_net(), initial_epochs=1).fit(X0[keep], y0[keep])
    with pytest.raises(ValueError, match=r"classes \[3\] are missing"):
        ActiveLearner(make_net(), initial_epochs=1, classes=[0, 1, 2, 3]).fit(X0, y0)
    # the net's own `classes` parameter declares them too
    with pytest.raises(ValueError, match=r"classes \[3\] are missing"):
        ActiveLearner(make_net(classes=[0, 1, 2, 3]), initial_epochs=1).fit(X0, y0)
    with pytest.raises(ValueError, match=r"labels \[7\] that are not among"):
        ActiveLearner(make_net(), initial_epochs=1, classes=[0, 1, 2]).fit(
            X0, np.where(y0 == 2, 7, y0))


def test_model_output_mismatch(data):
    X0, y0, X_test, _, _ = data
    learner = ActiveLearner(make_net(n_classes=4), initial_epochs=1).fit(X0, y0)
    with pytest.raises(ValueError, match="outputs 4 class probabilities but there are 3"):
        learner.query(X_test)


def test_teach_before_fit_and_bad_teach(data):
    X0, y0, _, _, _ = data
    with pytest.raises(NotFittedError, match="before fit"):
        ActiveLearner(make_net()).teach(X0, y0)
    with pytest.raises(NotFittedError):
        ActiveLearner(make_net()).query(X0)
    learner = ActiveLearner(make_net(), initial_epochs=1).fit(X0, y0)
    with pytest.raises(ValueError, match=r"labels \[5\] that are not among"):
        learner.teach(X0[:2], [0, 5])
    with pytest.raises(ValueError, match="X_new has 2 samples but y_new has 3"):
        learner.teach(X0[:2], [0, 1, 1])
    with pytest.raises(ValueError, match="X_new is empty"):
        learner.teach(X0[:0], [])


@pytest.mark.parametrize(
    "param, value",
    [("initial_epochs", 0), ("epochs_per_query", -1), ("n_samples", 0),
     ("max_reservoir", 0), ("initial_epochs", 2.5), ("cache_test_features", "yes"),
     ("random_state", "seed"), ("classes", 3), ("estimator", "net"), ("query_strategy", 3)],
)
def test_bad_params(param, value, data):
    X0, y0, _, _, _ = data
    params = {"estimator": make_net(), param: value}
    with pytest.raises(InvalidParameterError, match=f"'{param}' parameter of ActiveLearner"):
        ActiveLearner(**params).fit(X0, y0)


def test_bad_query_and_sampling_arguments(data):
    X0, y0, X_test, _, _ = data
    learner = ActiveLearner(make_net(), initial_epochs=1, n_samples=3).fit(X0, y0)
    with pytest.raises(InvalidParameterError, match="'n_instances' parameter"):
        learner.query(X_test, n_instances=0)
    with pytest.raises(ValueError, match="n_instances=4 is larger than the number of classes"):
        learner.query(X_test, n_instances=4)
    with pytest.raises(InvalidParameterError, match="'n_samples' parameter"):
        learner.predict_proba_samples(X_test, n_samples=0)
    with pytest.raises(ValueError, match="X_test is None"):
        learner.query(None)


def test_estimator_without_mc_dropout(data):
    from sklearn.linear_model import LogisticRegression

    X0, y0, _, _, _ = data
    with pytest.raises(TypeError, match="LogisticRegression has no predict_proba_samples"):
        ActiveLearner(make_pipeline(StandardScaler(), LogisticRegression())).fit(X0, y0)


def test_bad_fit_input(data):
    X0, y0, _, _, _ = data
    with pytest.raises(ValueError, match="X has 9 samples but y has 8"):
        ActiveLearner(make_net()).fit(X0, y0[:-1])
    with pytest.raises(ValueError, match="X is empty"):
        ActiveLearner(make_net()).fit(X0[:0], y0[:0])


def test_estimator_classes_must_match(data):
    X0, y0, _, _, _ = data

    class Shifted(MCDropoutNet):
        @property
        def classes_(self):
            return np.array([1, 2, 3])

    net = Shifted(**make_net().get_params())
    with pytest.raises(ValueError, match=r"classes_ \[1, 2, 3\] differ from the learner's classes \[0, 1, 2\]"):
        ActiveLearner(net, initial_epochs=1).fit(X0, y0)


def test_strategy_on_the_learners_own_samples(data):
    X0, y0, X_test, _, _ = data
    learner = ActiveLearner(make_net(), initial_epochs=2, n_samples=5).fit(X0, y0)
    p = learner.predict_proba_samples(X_test, n_samples=6, random_state=2)
    assert p.shape == (6, len(X_test), 3)
    idx, scores = variance_sampling(p)
    np.testing.assert_allclose(scores, class_uncertainty(p, "variance"))
    assert learner.predict_proba_samples(X_test).shape[0] == 5  # default n_samples


def test_pickle_round_trip_drops_feature_cache(data):
    import pickle

    X0, y0, X_test, y_test, _ = data
    learner = ActiveLearner(make_pipeline(StandardScaler(), make_net()), initial_epochs=2,
                            n_samples=3, random_state=0).fit(X0, y0)
    p = learner.predict_proba(X_test)
    assert learner._feature_cache is not None
    restored = pickle.loads(pickle.dumps(learner))
    assert getattr(restored, "_feature_cache", None) is None
    np.testing.assert_allclose(restored.predict_proba(X_test), p)
    restored.teach(X0[:2], y0[:2])  # still usable


class LogitRowsMC(ClassifierMixin, BaseEstimator):
    """Deterministic MC model: the first n_classes columns of a row are its logits,
    and pass j adds a fixed per-pass offset (so passes differ, reproducibly)."""

    def fit(self, X, y):
        self.classes_ = np.unique(y)
        return self

    def predict_proba_samples(self, X, n_samples=50, random_state=None):
        m = len(self.classes_)
        offsets = np.sin(np.arange(n_samples)[:, None] + np.arange(m)[None])  # (n, m)
        z = np.asarray(X, dtype=np.float64)[None, :, :m] + offsets[:, None, :]
        e = np.exp(z - z.max(axis=2, keepdims=True))
        return e / e.sum(axis=2, keepdims=True)

    def predict_proba(self, X):
        return self.predict_proba_samples(X, n_samples=1)[0]


@pytest.mark.parametrize("strategy", ["entropy", "variance", "bald", "margin", "mc_variance"])
@pytest.mark.parametrize("in_pipeline", [False, True])
def test_query_scores_the_presses_it_was_given(strategy, in_pipeline):
    """Everything query records and decides comes from the MC passes on X_test:
    computed on any other presses (the initial training set, the reservoir) the
    scores and the choice differ."""
    from sklearn.preprocessing import FunctionTransformer

    from sklearn_hardness.active._strategies import get_strategy

    X0 = np.repeat(np.eye(3) * 6.0, 2, axis=0)  # confident training presses
    y0 = np.repeat([0, 1, 2], 2)
    X_test = np.array([[2.0, 0.0, 1.5], [0.5, 0.0, 2.5], [3.0, 0.2, 0.0]])  # 0 or 2?
    model = LogitRowsMC()
    double = FunctionTransformer(lambda X: 2 * np.asarray(X))  # the feature step matters
    est = make_pipeline(double, model) if in_pipeline else model
    learner = ActiveLearner(est, strategy, n_samples=7, random_state=0).fit(X0, y0)
    idx, scores = learner.query(X_test)
    features = double.transform(X_test) if in_pipeline else X_test
    p = model.fit(X0, y0).predict_proba_samples(features, n_samples=7)
    expected_idx, expected_scores = get_strategy(strategy)(p)
    np.testing.assert_allclose(scores, expected_scores)
    np.testing.assert_array_equal(idx, expected_idx)
    entry = learner.history_[-1]
    assert entry["n_test"] == 3
    for kind in ("entropy", "variance", "bald"):
        np.testing.assert_allclose(entry[kind], class_uncertainty(p, kind))
    parts = variance_decomposition(p)
    np.testing.assert_allclose(entry["variance_mc"], parts["mc"])
    np.testing.assert_allclose(entry["variance_between"], parts["between"])
    # the test can tell: on the training presses the same strategy scores otherwise
    X0_features = double.transform(X0) if in_pipeline else X0
    p_train = model.predict_proba_samples(X0_features, n_samples=7)
    assert not np.allclose(get_strategy(strategy)(p_train)[1], scores)


def test_thompson_query_draws_from_the_test_presses_belief():
    """The learner's thompson query presses class i with the mean MC probability of i on
    X_test (not on the training presses, whose belief is different)."""
    X0 = np.repeat(np.eye(3) * 6.0, 2, axis=0)
    y0 = np.repeat([0, 1, 2], 2)
    X_test = np.array([[2.0, 0.0, 1.5], [0.5, 0.0, 2.5], [3.0, 0.2, 0.0]])
    model = LogitRowsMC()
    learner = ActiveLearner(model, "thompson", n_samples=7, random_state=0).fit(X0, y0)
    firsts = np.array([learner.query(X_test)[0][0] for _ in range(1500)])
    freq = np.bincount(firsts, minlength=3) / len(firsts)
    model.fit(X0, y0)
    mu_test = model.predict_proba_samples(X_test, n_samples=7).mean(axis=(0, 1))
    mu_train = model.predict_proba_samples(X0, n_samples=7).mean(axis=(0, 1))
    np.testing.assert_allclose(freq, mu_test, atol=0.04)
    assert np.abs(mu_test - mu_train).max() > 0.15  # the wrong presses would show


def test_history_epochs_are_the_epochs_run_also_in_the_initial_training():
    from skorch.callbacks import EarlyStopping

    from sklearn_hardness.models import OFNNClassifier

    X, y = make_blobs(n_per_class=10, seed=0)
    net = OFNNClassifier(random_state=0, callbacks=[EarlyStopping(monitor="train_loss", patience=1)])
    learner = ActiveLearner(net, "random", initial_epochs=300, epochs_per_query=300, n_samples=3,
                            random_state=0).fit(X, y)
    first = learner.history_[0]["epochs"]
    assert first == len(learner._final().history) < 300  # stopped early, and said so
    learner.teach(X[:3], y[:3])
    assert learner.history_[-1]["epochs"] == len(learner._final().history) - first < 300


# --- the capped training subset keeps every class of the reservoir ----------------------


def _old_training_subset_indices(size, max_size, seed):
    """The draw before the class repair: max_size rows uniformly without replacement."""
    rng = np.random.RandomState(seed)
    return rng.choice(size, max_size, replace=False), rng


def test_training_subset_unchanged_when_the_draw_covers_every_class():
    from sklearn_hardness.active._rows import training_subset

    y = np.repeat(np.arange(4), [3, 5, 7, 25])
    X = np.arange(y.shape[0])[:, None]  # row i holds i: recovers the indices
    n_same = 0
    for seed in range(200):
        old, old_rng = _old_training_subset_indices(y.shape[0], 12, seed)
        if np.unique(y[old]).shape[0] < 4:
            continue
        rng = np.random.RandomState(seed)
        X_t, y_t = training_subset(X, y, 12, rng)
        np.testing.assert_array_equal(X_t[:, 0], old)
        np.testing.assert_array_equal(y_t, y[old])
        # ... and the RandomState consumed the same random numbers
        assert rng.randint(2**31) == old_rng.randint(2**31)
        n_same += 1
    assert n_same > 50
    # no cap, or a reservoir within it: returned as it is, nothing drawn
    rng = np.random.RandomState(0)
    assert training_subset(X, y, None, rng)[1] is y
    assert training_subset(X, y, 40, rng)[1] is y
    assert rng.randint(2**31) == np.random.RandomState(0).randint(2**31)


def test_training_subset_repairs_a_draw_that_lost_a_class():
    from sklearn_hardness.active._rows import training_subset

    y = np.array(["a"] * 2 + ["b"] * 2 + ["c"] * 30)  # any labels, not only 0..k-1
    X = np.arange(y.shape[0])[:, None]
    n_repaired = 0
    for seed in range(100):
        old, _ = _old_training_subset_indices(y.shape[0], 6, seed)
        X_t, y_t = training_subset(X, y, 6, np.random.RandomState(seed))
        idx = X_t[:, 0]
        assert idx.shape == (6,) and np.unique(idx).shape[0] == 6  # no row twice
        np.testing.assert_array_equal(y_t, y[idx])
        assert set(y_t) == {"a", "b", "c"}
        if set(y[old]) != {"a", "b", "c"}:
            n_repaired += 1
            # only rows of the most represented class were replaced, in place
            changed = idx != old
            assert np.all(y[old][changed] == "c")
            np.testing.assert_array_equal(idx[~changed], old[~changed])
        else:
            np.testing.assert_array_equal(idx, old)
    assert n_repaired > 50
    # reproducible for a fixed seed
    a = training_subset(X, y, 6, np.random.RandomState(3))[0]
    np.testing.assert_array_equal(a, training_subset(X, y, 6, np.random.RandomState(3))[0])
    # nets are told every class (partial_fit's classes=): their draws stay the plain uniform ones
    for seed in range(100):
        old, old_rng = _old_training_subset_indices(y.shape[0], 6, seed)
        rng = np.random.RandomState(seed)
        np.testing.assert_array_equal(training_subset(X, y, 6, rng, keep_classes=False)[0][:, 0], old)
        assert rng.randint(2**31) == old_rng.randint(2**31)

    # a cap below the number of classes cannot cover them all: no class is displaced
    # below one row, and the subset keeps its size
    y3 = np.repeat([0, 1, 2], [1, 1, 10])
    for seed in range(20):
        X_t, y_t = training_subset(np.arange(12)[:, None], y3, 2, np.random.RandomState(seed))
        assert y_t.shape == (2,) and np.unique(X_t[:, 0]).shape[0] == 2
        assert np.unique(y_t).shape[0] == 2


def test_a_net_in_the_learner_gets_the_plain_draw(monkeypatch):
    """The learner repairs the reservoir draw for models refitted from scratch only."""
    import sklearn_hardness.active._learner as learner_module
    from sklearn_hardness.models import LaplaceLogisticRegression

    seen = []

    def spy(X, y, max_size, rng, *, keep_classes=True):
        seen.append(keep_classes)
        return X, y

    monkeypatch.setattr(learner_module, "training_subset", spy)
    rng = np.random.RandomState(0)
    X0, y0 = rng.normal(size=(12, 3)).astype(np.float32), np.repeat([0, 1, 2], 4)
    X1, y1 = rng.normal(size=(3, 3)).astype(np.float32), np.array([0, 0, 0])
    from sklearn_hardness.models import OFNNClassifier

    nets = [OFNNClassifier(max_epochs=1, hidden_units=4, random_state=0), LaplaceLogisticRegression()]
    for est in nets:
        learner = ActiveLearner(est, initial_epochs=1, epochs_per_query=1, max_reservoir=10, random_state=0)
        learner.fit(X0, y0).teach(X1, y1)
    assert seen == [False, True]


@pytest.mark.slow
def test_refit_estimator_keeps_every_class_under_a_small_cap():
    """A refit-from-scratch estimator (plain fit(X, y)) trained on a capped subset kept
    every class: a subset that lost one made the next query crash."""
    import warnings

    from sklearn_hardness.models import LaplaceLogisticRegression

    rng = np.random.default_rng(0)
    y0 = np.repeat(np.arange(5), 5)
    X0 = rng.normal(size=(25, 2)) + y0[:, None]
    lost = 0
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        for seed in range(30):  # 3 of these 30 runs lost a class before the repair
            learner = ActiveLearner(LaplaceLogisticRegression(), "variance", max_reservoir=40,
                                    random_state=seed).fit(X0, y0)
            for _ in range(9):  # 5 presses of class 0 each time: reservoir 30 .. 70
                learner.teach(rng.normal(size=(5, 2)), [0] * 5)
                if len(learner._final().classes_) < 5:
                    lost += 1
                    break
        assert lost == 0
        # a cap as small as the number of classes: the query no longer crashes
        rng = np.random.default_rng(0)
        y0 = np.repeat([0, 1, 2, 3], 2)
        X0 = rng.normal(size=(8, 2)) + np.eye(4)[y0][:, :2] * 3
        X_test = rng.normal(size=(3, 2))
        for seed in range(6):
            learner = ActiveLearner(LaplaceLogisticRegression(), "variance", max_reservoir=4,
                                    n_samples=5, random_state=seed).fit(X0, y0)
            learner.teach(rng.normal(size=(2, 2)), [1, 1])
            idx, scores = learner.query(X_test)
            np.testing.assert_array_equal(learner._final().classes_, [0, 1, 2, 3])
            assert scores.shape == (4,)
