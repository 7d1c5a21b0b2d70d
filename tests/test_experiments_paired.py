"""Paired runs: one initial training per (test object, seed), copied into every strategy.

And the effect of the protocol's choices: the query sees only the test
object's presses, the input scale is fitted on training presses only.
"""

import numpy as np
import pytest

from sklearn_hardness.experiments import run_active_sampling
from sklearn_hardness.experiments._config import check_config, get_config
from sklearn_hardness.experiments._data import prepare_inputs
from sklearn_hardness.experiments._run import _active_run
from sklearn_hardness.models._pipelines import FrameScaler

from ._exp_data import TINY, tiny_presses

_COMPARED = ("accuracy", "mae", "variance", "entropy", "bald", "queried", "predictions", "train_loss",
             "drawn_indices", "test_indices", "initial_indices", "initial_train_loss", "converged")


def _unshared(model, strategies, tc, seed, **cfg):
    """Records as before the sharing: every strategy trains its own initial model."""
    cfg = check_config(dict(get_config("silicone5", **dict(TINY, **cfg)), model=model))
    inputs = prepare_inputs(tiny_presses(), cfg, model, verbose=0)
    return [_active_run(inputs.X, inputs.y, inputs.hardness, cfg, model, inputs.n_classes,
                        list(inputs.target_names), s, tc, seed, None) for s in strategies]


def _same(a, b):
    for k in _COMPARED:
        va, vb = a[k], b[k]
        if k in ("predictions", "drawn_indices"):
            assert [np.asarray(x).tolist() for x in va] == [np.asarray(x).tolist() for x in vb], k
        else:
            np.testing.assert_array_equal(np.asarray(va, dtype=float), np.asarray(vb, dtype=float), err_msg=k)


@pytest.mark.parametrize("model, extra", [("ofnn", {}), pytest.param(
    "convlstm", dict(frame_size=(8, 10), n_samples=3), marks=pytest.mark.slow)])
def test_shared_initial_model_gives_the_same_records(model, extra):
    strategies = ("variance", "entropy", "random", "bald")
    shared = run_active_sampling(tiny_presses(), model=model, strategies=strategies, test_classes=[1],
                                 seeds=[3], n_jobs=1, verbose=0, **dict(TINY, convergence_threshold=None, **extra))
    alone = _unshared(model, strategies, 1, 3, convergence_threshold=None, **extra)
    assert [r["key"]["strategy"] for r in shared.records] == list(strategies)
    for a, b in zip(shared.records, alone):
        _same(a, b)
    # the strategies really diverge after the shared start (otherwise the test proves little)
    assert len({tuple(r["queried"]) for r in shared.records}) > 1 or len(
        {tuple(np.round(r["variance"], 12)) for r in shared.records}) > 1


def test_paired_strategies_share_initial_model_and_test_presses():
    res = run_active_sampling(tiny_presses(), model="ofnn", strategies=("variance", "random", "bald"),
                              test_classes=[0, 2], seeds=[0, 1], n_jobs=1, verbose=0, **TINY)
    for tc in (0, 2):
        for seed in (0, 1):
            rs = res.select(test_class=tc, seed=seed)
            assert len(rs) == 3
            for r in rs[1:]:
                assert r["test_indices"] == rs[0]["test_indices"]
                assert r["initial_indices"] == rs[0]["initial_indices"]
                # same initial weights: same predictions and the same MC uncertainty before any query
                assert r["initial_train_loss"] == rs[0]["initial_train_loss"]
                assert r["predictions"][0] == rs[0]["predictions"][0]
                assert r["variance_per_class"][0] == rs[0]["variance_per_class"][0]
    # different seeds are different pairs
    a, b = res.select(test_class=0, seed=0)[0], res.select(test_class=0, seed=1)[0]
    assert a["test_indices"] != b["test_indices"] or a["initial_indices"] != b["initial_indices"]


def test_query_is_computed_on_the_test_objects_presses_only(monkeypatch):
    # strategies see only MC probabilities, so the spy sits on the learner's MC sampling:
    # every set of presses the experiment scores must be the test object's
    from sklearn_hardness.active import ActiveLearner

    log = []
    orig = ActiveLearner.predict_proba_samples

    def spying(self, X, *args, **kwargs):
        log.append(np.array(X, copy=True))
        return orig(self, X, *args, **kwargs)

    monkeypatch.setattr(ActiveLearner, "predict_proba_samples", spying)
    res = run_active_sampling(tiny_presses(), model="ofnn", strategies=("variance",), test_classes=[3],
                              seeds=[0], n_jobs=1, verbose=0, **TINY)
    rec = res.records[0]
    cfg = check_config(dict(get_config("silicone5", **TINY), model="ofnn"))
    inputs = prepare_inputs(tiny_presses(), cfg, "ofnn", verbose=0)
    expected = inputs.X[np.asarray(rec["test_indices"])]
    assert len(log) >= TINY["n_iterations"]
    assert np.all(inputs.y[np.asarray(rec["test_indices"])] == 3)
    for seen in log:
        np.testing.assert_array_equal(seen, expected)
    # and the recorded uncertainty is that of the test presses (iteration 0's query)
    assert rec["queried"][0] == int(np.argmax(rec["variance_per_class"][0]))


def test_input_scale_is_fitted_on_training_presses_only(monkeypatch):
    import sklearn_hardness.experiments._run as active

    seen = []
    orig = active._input_scaler

    def recording(X_train, cfg, model):
        seen.append(np.array(X_train, copy=True))
        return orig(X_train, cfg, model)

    monkeypatch.setattr(active, "_input_scaler", recording)
    kw = dict(TINY, frame_size=(8, 10), n_samples=3, initial_epochs=2, epochs_per_query=1,
              convergence_threshold=None)
    res = run_active_sampling(tiny_presses(), model="convlstm", strategies=("random",), test_classes=[0],
                              seeds=[0], n_jobs=1, verbose=0, **kw)
    rec = res.records[0]
    cfg = check_config(dict(get_config("silicone5", **kw), model="convlstm"))
    raw = prepare_inputs(tiny_presses(), cfg, "convlstm", verbose=0).X
    assert len(seen) == 1
    np.testing.assert_array_equal(seen[0], raw[np.asarray(rec["initial_indices"])])
    # the scale is the initial training set's, which differs from the std over all presses (test included)
    scaler = orig(seen[0], cfg, "convlstm")
    assert isinstance(scaler, FrameScaler)  # the factory's own step, as in a user's pipeline
    assert scaler.scale_ == pytest.approx(np.std(raw[np.asarray(rec["initial_indices"])]))
    assert scaler.scale_ != pytest.approx(np.std(raw), rel=1e-3)
    assert orig(seen[0], dict(cfg, input_scale=None), "convlstm") is None
    assert orig(seen[0], cfg, "ofnn") is None


def test_holdout_presses_of_every_class_are_never_trained_on():
    data = tiny_presses(10)
    y = np.asarray(data.target)
    res = run_active_sampling(data, model="ofnn", strategies=("variance", "random"), test_classes=[1],
                              seeds=[0], n_jobs=1, verbose=0, **dict(TINY, n_holdout=2))
    for r in res.records:
        hold = np.asarray(r["holdout_indices"])
        assert np.bincount(y[hold], minlength=5).tolist() == [2] * 5
        used = np.concatenate([r["initial_indices"]] + [np.asarray(d) for d in r["drawn_indices"]])
        assert not np.intersect1d(hold, used).size and not np.intersect1d(hold, r["test_indices"]).size
        assert len(r["holdout_accuracy"]) == len(r["accuracy"]) == TINY["n_iterations"] + 1
        assert all(0 <= a <= 1 for a in r["holdout_accuracy"]) and all(m >= 0 for m in r["holdout_mae"])
    with pytest.raises(ValueError, match="n_holdout"):
        run_active_sampling(data, model="ofnn", test_classes=[1], seeds=[0], verbose=0,
                            **dict(TINY, n_holdout=5))


def test_preparing_inputs_raises_no_deprecation_warning_of_our_own():
    # the cache key names the frame size output_size (cached frames stay valid); the selector must not
    import warnings

    cfg = check_config(dict(get_config("silicone5", **TINY), frame_size=(8, 10), model="convlstm"))
    with warnings.catch_warnings():
        warnings.simplefilter("error", FutureWarning)
        inputs = prepare_inputs(tiny_presses(), cfg, "convlstm", memory=False, verbose=0)
    assert inputs.X.shape[2:4] == (8, 10)
