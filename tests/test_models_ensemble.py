"""EnsembleClassifier: seeded copies of a net as the source of predict_proba_samples."""

import numpy as np
import pytest
from sklearn.base import clone
from sklearn.datasets import make_blobs
from sklearn.exceptions import NotFittedError

from sklearn_hardness.active import ActiveLearner, PressOracle, class_uncertainty
from sklearn_hardness.experiments import get_config, run_active_sampling
from sklearn_hardness.experiments._config import config_hash
from sklearn_hardness.models import EnsembleClassifier, OFNNClassifier

from ._exp_data import TINY, tiny_presses


def _data():
    X, y = make_blobs(90, n_features=4, centers=3, cluster_std=2.0, random_state=0)
    return X.astype(np.float32), y


def _ofnn(**kw):
    return OFNNClassifier(hidden_units=8, max_epochs=15, lr=0.05, dropout=0.2, **kw)


def test_members_are_seeded_apart_and_their_spread_is_the_samples():
    X, y = _data()
    ens = EnsembleClassifier(_ofnn(), n_estimators=4, random_state=0).fit(X, y)
    assert len(ens.estimators_) == 4 and len(set(ens.seeds_.tolist())) == 4
    assert [m.random_state for m in ens.estimators_] == ens.seeds_.tolist()
    assert ens.estimator.random_state is None  # the template is not touched
    p = ens.predict_proba_samples(X[:10])
    assert p.shape == (4, 10, 3)
    for k, m in enumerate(ens.estimators_):  # one row per member, its own predict_proba
        np.testing.assert_allclose(p[k], m.predict_proba(X[:10]), rtol=1e-6)
    assert class_uncertainty(p, "variance").max() > 0  # the members disagree somewhere
    np.testing.assert_allclose(ens.predict_proba(X[:10]), p.mean(axis=0), rtol=1e-6)
    np.testing.assert_array_equal(ens.predict(X[:10]), ens.classes_[p.mean(axis=0).argmax(axis=1)])
    # a fixed number of "passes" cycles through the members: same mean and variance
    p8 = ens.predict_proba_samples(X[:10], n_samples=8, random_state=3)
    np.testing.assert_allclose(p8.mean(axis=0), p.mean(axis=0), rtol=1e-5)
    np.testing.assert_allclose(class_uncertainty(p8, "variance"), class_uncertainty(p, "variance"), atol=1e-7)
    # same random_state, same ensemble
    again = clone(ens).fit(X, y)
    np.testing.assert_allclose(again.predict_proba_samples(X[:10]), p, rtol=1e-6)


def test_bad_use_raises():
    X, y = _data()
    with pytest.raises(NotFittedError):
        EnsembleClassifier(_ofnn()).predict_proba_samples(X)
    with pytest.raises(ValueError, match="n_estimators"):
        EnsembleClassifier(_ofnn(), n_estimators=0).fit(X, y)
    ens = EnsembleClassifier(_ofnn(), n_estimators=2, random_state=0).fit(X, y)
    with pytest.raises(ValueError, match="n_samples"):
        ens.predict_proba_samples(X, n_samples=0)


def test_active_learner_warm_starts_every_member():
    X, y = _data()
    oracle = PressOracle(X, y, random_state=0)
    X_test, _ = oracle.press(1, 4)
    learner = ActiveLearner(EnsembleClassifier(_ofnn(), n_estimators=3, random_state=0), "variance",
                            initial_epochs=6, epochs_per_query=4, n_samples=6, random_state=0)
    learner.fit(*oracle.initial(5))
    before = [len(m.history_) for m in learner.estimator_.estimators_]
    idx, _ = learner.query(X_test)
    learner.teach(*oracle.press(learner.classes_[idx[0]], 5))
    after = [len(m.history_) for m in learner.estimator_.estimators_]
    assert before == [6, 6, 6] and after == [10, 10, 10]  # continued, not refit from scratch
    assert learner.initial_train_loss_ is not None


def test_experiments_use_an_ensemble_when_asked():
    cfg = get_config("silicone5")
    assert config_hash(cfg) == config_hash(dict(cfg, n_ensemble=0))  # the default keeps old hashes
    assert config_hash(cfg) != config_hash(dict(cfg, n_ensemble=3))
    res = run_active_sampling(tiny_presses(), model="ofnn", strategies=("variance", "random"), test_classes=[0],
                              n_runs=1, n_jobs=1, verbose=0, n_ensemble=3, **TINY)
    assert len(res) == 2
    for r in res.records:
        assert len(r["accuracy"]) == TINY["n_iterations"] + 1
        assert max(r["variance"]) > 0  # the spread of the members drove the queries
    with pytest.raises(ValueError, match="n_ensemble"):
        run_active_sampling(tiny_presses(), model="ofnn", n_ensemble=1, verbose=0, **TINY)


def _frames():
    rng = np.random.default_rng(0)
    X = rng.normal(size=(12, 3, 6, 8, 1)).astype(np.float32)
    y = np.arange(12) % 3
    return X + 0.5 * y[:, None, None, None, None].astype(np.float32), y


def test_stacked_members_equal_separately_trained_ones():
    from sklearn_hardness.models import ConvLSTMClassifier

    X, y = _frames()
    base = ConvLSTMClassifier(filters=(2, 3), max_epochs=2, dropout=0.0, batch_size=4, class_weight="balanced")
    fitted = {}
    for st in (False, True):
        ens = EnsembleClassifier(base, n_estimators=3, random_state=0, stacked=st).fit(X, y)
        assert ens.stacked_ is st and ens.get_params()["stacked"] is st
        first = ens.predict_proba_samples(X[:5])
        ens.partial_fit(X, y, epochs=1)  # a warm start continues each member's own Adam moments
        fitted[st] = (ens, first, ens.predict_proba_samples(X[:5]))
    (sep, sep1, sep2), (stk, stk1, stk2) = fitted[False], fitted[True]
    np.testing.assert_allclose(stk1, sep1, atol=1e-5)
    np.testing.assert_allclose(stk2, sep2, atol=1e-5)
    assert class_uncertainty(stk2, "variance").max() > 1e-4  # the members differ (own seeds, own batches)
    for a, b in zip(sep.estimators_, stk.estimators_):
        assert len(b.history_) == 3 and b.history_[-1, "train_batch_count"] == 3
        np.testing.assert_allclose(b.history_[:, "train_loss"], a.history_[:, "train_loss"], rtol=1e-5)
        np.testing.assert_array_equal(b.class_weight_, a.class_weight_)
        opt_a, opt_b = a.optimizer_.state_dict()["state"], b.optimizer_.state_dict()["state"]
        for i in opt_a:
            np.testing.assert_allclose(opt_b[i]["exp_avg_sq"], opt_a[i]["exp_avg_sq"], rtol=1e-3, atol=1e-12)
    # members trained stacked continue separately (and pickle) like any member
    import pickle

    again = pickle.loads(pickle.dumps(stk)).set_params(stacked=False)
    again.partial_fit(X, y, epochs=1)
    assert not again.stacked_ and len(again.estimators_[0].history_) == 4


def test_stacked_with_dropout_auto_and_bad_members():
    from sklearn_hardness.models import ConvLSTMClassifier

    X, y = _frames()
    base = ConvLSTMClassifier(filters=(2, 3), max_epochs=2, dropout=0.5, batch_size=4)
    ens = EnsembleClassifier(base, n_estimators=3, random_state=0, stacked=True).fit(X, y)
    again = clone(ens).fit(X, y)  # seeded masks: the same ensemble
    np.testing.assert_allclose(again.predict_proba_samples(X[:4]), ens.predict_proba_samples(X[:4]), rtol=1e-6)
    assert all(np.isfinite(m.final_train_loss_) for m in ens.estimators_)
    # "auto" stacks on CUDA only; OFNN members and callbacks cannot stack
    assert EnsembleClassifier(base, n_estimators=2, random_state=0).fit(X, y).stacked_ is False
    Xb, yb = _data()
    with pytest.raises(ValueError, match="not ConvLSTMClassifier"):
        EnsembleClassifier(_ofnn(), n_estimators=2, stacked=True).fit(Xb, yb)
    from skorch.callbacks import PrintLog

    with pytest.raises(ValueError, match="callbacks"):
        EnsembleClassifier(clone(base).set_params(callbacks=[("log", PrintLog())]), stacked=True).fit(X, y)
    with pytest.raises(ValueError, match="stacked"):
        EnsembleClassifier(base, stacked="yes").fit(X, y)
    assert EnsembleClassifier(_ofnn(), n_estimators=2, random_state=0).fit(Xb, yb).stacked_ is False
