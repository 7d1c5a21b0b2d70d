import json
import os

import numpy as np
import pytest
from sklearn.utils import Bunch

from sklearn_hardness.experiments import (
    ExperimentResult,
    get_config,
    run_active_sampling,
    run_dropout_sweep,
    run_model_baselines,
)
from sklearn_hardness.experiments._config import config_hash
from sklearn_hardness.experiments._results import ResultsStore
from sklearn_hardness.experiments._tables import HUMAN_ACCURACY

from ._exp_data import TINY, tiny_presses


# ----------------------------------------------------------------- config
def test_preset_configs_are_the_papers():
    s5 = get_config("silicone5")
    assert (s5["model"], s5["initial_epochs"], s5["epochs_per_query"], s5["max_reservoir"]) == (
        "convlstm", 100, 50, 40)
    assert (s5["n_initial"], s5["n_per_query"], s5["n_iterations"], s5["dropout"], s5["n_between"]) == (
        5, 5, 5, 0.2, 2)
    y9 = get_config("shore9")
    assert (y9["model"], y9["initial_epochs"], y9["epochs_per_query"], y9["max_reservoir"], y9["n_between"]) == (
        "dinov2nn", 50, 25, 80, 1)
    q = get_config("silicone5", quick=True)
    assert q["initial_epochs"] < s5["initial_epochs"] and q["n_runs"] < s5["n_runs"]
    assert get_config("silicone5", max_reservoir=60)["max_reservoir"] == 60


def test_config_hash_is_stable_and_sensitive():
    a = get_config("silicone5")
    assert config_hash(a) == config_hash(get_config("silicone5"))
    assert config_hash(a) != config_hash(get_config("silicone5", dropout=0.3))


def test_bad_config():
    with pytest.raises(ValueError, match="unknown preset"):
        get_config("yuan")
    with pytest.raises(ValueError, match="unknown configuration key"):
        get_config("silicone5", epochs=3)


def test_renamed_config_key_is_a_clear_error_and_keeps_the_hash():
    # n_mc_samples became n_samples (the name of predict_proba_samples and ActiveLearner)
    with pytest.raises(ValueError, match="'n_mc_samples' is now 'n_samples'"):
        get_config("silicone5", n_mc_samples=10)
    cfg = get_config("silicone5", n_samples=10)
    assert cfg["n_samples"] == 10 and "n_mc_samples" not in cfg
    written_before = {("n_mc_samples" if k == "n_samples" else k): v for k, v in cfg.items()}
    assert config_hash(cfg) == config_hash(written_before)  # results files stay resumable
    # the hash a results file written before the rename holds for the default silicone5 config
    assert config_hash(get_config("silicone5")) == "805d7dc6513b"
    assert config_hash(cfg) != config_hash(get_config("silicone5"))


# ----------------------------------------------------------------- store
def test_results_store_roundtrip_torn_line_and_duplicates(tmp_path):
    path = tmp_path / "r.jsonl"
    store = ResultsStore(path)
    with store.writing():
        store.append({"key": {"a": 1}, "acc": [0.5, np.float32(0.75)], "x": np.arange(2)})
        store.append({"key": {"a": 2}, "acc": [1.0], "loss": float("nan")})
        with pytest.raises(ValueError, match="already"):
            store.append({"key": {"a": 2}})
    again = ResultsStore(path)
    assert [r["key"]["a"] for r in again.records] == [1, 2]
    assert again.records[0]["acc"] == [0.5, 0.75] and again.records[1]["loss"] is None
    good = path.read_bytes()
    # a torn last line (interrupted write) is ignored, reported and removed
    with open(path, "ab") as f:
        f.write(b'{"key": {"a": 3}, "acc": [0.')
    with pytest.warns(UserWarning, match="torn"):
        torn = ResultsStore(path)
    assert len(torn) == 2 and torn.n_torn == 1
    assert path.read_bytes() == good
    with torn.writing():
        torn.append({"key": {"a": 3}})
    assert [r["key"]["a"] for r in ResultsStore(path).records] == [1, 2, 3]
    # a complete last record without its newline is kept, and the next one starts on its own line
    path.write_bytes(good.rstrip(b"\n"))
    kept = ResultsStore(path)
    assert len(kept) == 2
    with kept.writing():
        kept.append({"key": {"a": 4}})
    assert [r["key"]["a"] for r in ResultsStore(path).records] == [1, 2, 4]
    # garbage in the middle is not silently skipped
    path.write_bytes(good + b"garbage\n" + good)
    with pytest.raises(ValueError, match="line 3"):
        ResultsStore(path)


def test_results_store_single_writer(tmp_path):
    store = ResultsStore(tmp_path / "r.jsonl")
    with store.writing():
        with pytest.raises(RuntimeError, match="another process"):
            with ResultsStore(tmp_path / "r.jsonl").writing():
                pass


# ----------------------------------------------------------------- active sampling
@pytest.fixture(scope="module")
def active_result(tmp_path_factory):
    path = tmp_path_factory.mktemp("exp") / "runs.jsonl"
    res = run_active_sampling(
        tiny_presses(), model="ofnn", strategies=("variance", "entropy", "random", "bald"),
        test_classes=[0, 3], n_runs=2, results_path=path, n_jobs=1, verbose=0, **TINY)
    return res, path


def test_active_sampling_records(active_result):
    res, path = active_result
    data = tiny_presses()
    y = np.asarray(data.target)
    assert len(res) == 4 * 2 * 2
    keys = {(r["key"]["strategy"], r["key"]["test_class"], r["key"]["seed"]) for r in res.records}
    assert len(keys) == 16
    N, s, s0, l = TINY["n_iterations"], TINY["n_per_query"], TINY["n_initial"], TINY["n_test"]
    for r in res.records:
        tc = r["key"]["test_class"]
        assert r["converged"]  # the convergence rule is the ConvLSTM's only
        for m in ("accuracy", "mae", "entropy", "variance", "bald"):
            assert len(r[m]) == N + 1 and np.all(np.isfinite(r[m]))
        assert np.all((np.asarray(r["accuracy"]) >= 0) & (np.asarray(r["accuracy"]) <= 1))
        assert len(r["queried"]) == N and len(r["entropy_per_class"][0]) == 5
        assert r["reservoir_size"] == [5 * s0 + i * s for i in range(N + 1)]
        test = np.asarray(r["test_indices"])
        assert len(test) == l and np.all(y[test] == tc)
        # reference presses never include the test presses, and never repeat
        used = np.concatenate([r["initial_indices"]] + [np.asarray(d) for d in r["drawn_indices"]])
        assert not np.intersect1d(used, test).size and len(np.unique(used)) == len(used)
        for q, d in zip(r["queried"], r["drawn_indices"]):
            assert np.all(y[np.asarray(d)] == q)
        # accuracy is the fraction of test presses predicted as the test object
        assert r["accuracy"][-1] == pytest.approx(np.mean(np.asarray(r["predictions"][-1]) == tc))
        assert r["test_name"] == str(data.target_names[tc])
    # paired runs: the same (test object, seed) start from the same trained state
    for tc in (0, 3):
        for seed in (0, 1):
            rs = res.select(test_class=tc, seed=seed)
            assert len({tuple(r["test_indices"]) for r in rs}) == 1
            assert len({r["initial_train_loss"] for r in rs}) == 1
            assert len({tuple(r["predictions"][0]) for r in rs}) == 1
    # variance queries the class of highest variance
    for r in res.select(strategy="variance"):
        for it, q in enumerate(r["queried"]):
            assert q == int(np.argmax(r["variance_per_class"][it]))
    assert res.curves("accuracy", strategy="random").shape == (4, N + 1)
    # every run is in the file, one line each
    lines = path.read_text().splitlines()
    assert len(lines) == 16 and all(json.loads(x)["key"]["config"] == res.records[0]["key"]["config"] for x in lines)


def test_active_sampling_resumes_without_recomputing(active_result):
    res, path = active_result
    before = path.read_bytes()
    again = run_active_sampling(
        tiny_presses(), model="ofnn", strategies=("variance", "entropy", "random", "bald"),
        test_classes=[0, 3], n_runs=2, results_path=path, n_jobs=1, verbose=0, **TINY)
    assert path.read_bytes() == before  # nothing recomputed or appended
    assert [r["key"] for r in again.records] == [r["key"] for r in res.records]
    # a new seed computes only the new runs
    more = run_active_sampling(
        tiny_presses(), model="ofnn", strategies=("variance",), test_classes=[0], seeds=[1, 5],
        results_path=path, n_jobs=1, verbose=0, **TINY)
    after = path.read_bytes()
    assert after.startswith(before) and len(after.splitlines()) == 17
    assert {r["key"]["seed"] for r in more.records} == {1, 5}


def test_comparison_table_and_figures(active_result, tmp_path):
    res, _ = active_result
    rows = res.comparison_table()
    assert [r["name"] for r in rows] == ["no resampling", "variance", "entropy", "random", "bald",
                                         "humans (paper)"]
    base = rows[0]
    assert base["n_runs"] == 4  # one per (test object, seed), not per strategy
    acc0 = np.mean([r["accuracy"][0] for r in res.select(strategy="variance")])
    assert base["accuracy_mean"] == pytest.approx(acc0)
    accN = [r["accuracy"][-1] for r in res.select(strategy="entropy")]
    assert rows[2]["accuracy_mean"] == pytest.approx(np.mean(accN))
    assert rows[2]["accuracy_std"] == pytest.approx(np.std(accN))
    assert rows[-1]["accuracy_mean"] == HUMAN_ACCURACY[0] == 0.48
    text = ExperimentResult.format_table(rows, mae_unit="mm/N")
    assert "humans (paper)" in text and "48.00% +- 22.27%" in text and "MAE (mm/N)" in text
    paths = res.save_figures(tmp_path)
    assert {os.path.basename(p) for p in paths} == {"accuracy.png", "mae.png", "entropy.png", "variance.png"}
    for p in paths:
        with open(p, "rb") as f:
            assert f.read(8) == b"\x89PNG\r\n\x1a\n"


def test_active_sampling_bad_input():
    data = tiny_presses()
    kw = dict(model="ofnn", n_runs=1, test_classes=[0], verbose=0, **TINY)
    with pytest.raises(ValueError, match="strategy"):
        run_active_sampling(data, strategies=("variance", "uncertainty"), **kw)
    with pytest.raises(ValueError, match="max_reservoir"):
        run_active_sampling(data, **dict(kw, max_reservoir=1))
    with pytest.raises(ValueError, match="n_test"):
        run_active_sampling(data, **dict(kw, n_test=0))
    with pytest.raises(ValueError, match="n_initial"):
        run_active_sampling(data, **dict(kw, n_initial=0))
    with pytest.raises(ValueError, match="unknown model"):
        run_active_sampling(data, **dict(kw, model="resnet"))
    with pytest.raises(ValueError, match="unknown preset"):
        run_active_sampling(data, preset="yuan", **kw)
    with pytest.raises(ValueError, match="presses, but a run may need"):
        run_active_sampling(data, **dict(kw, n_iterations=5))
    with pytest.raises(ValueError, match="test_classes"):
        run_active_sampling(data, **dict(kw, test_classes=[7]))
    with pytest.raises(ValueError, match="neither a simulator preset"):
        run_active_sampling("no_such_manifest.csv", **kw)
    # a class without presses cannot be in the initial set
    mask = np.asarray(data.target) != 2
    holed = Bunch(videos=data.videos[mask], target=np.asarray(data.target)[mask],
                  target_names=data.target_names, hardness=data.hardness)
    with pytest.raises(ValueError, match=r"classes \[2\] have no presses"):
        run_active_sampling(holed, **kw)


@pytest.mark.slow
def test_convlstm_convergence_rule():
    data = tiny_presses()
    kw = dict(model="convlstm", strategies=("variance", "random"), test_classes=[1], n_runs=1,
              verbose=0, **dict(TINY, initial_epochs=2, epochs_per_query=1, n_samples=3,
                                frame_size=(8, 10)))
    never = run_active_sampling(data, convergence_threshold=0.0, **kw)
    assert all(not r["converged"] for r in never.records)
    assert all(len(r["accuracy"]) == 1 and r["queried"] == [] for r in never.records)
    rows = never.comparison_table()
    assert rows[0]["converged_fraction"] == 0.0 and rows[1]["n_runs"] == 0
    always = run_active_sampling(data, convergence_threshold=100.0, **kw)
    assert all(r["converged"] and len(r["accuracy"]) == 3 for r in always.records)
    assert np.isfinite(always.records[0]["initial_train_loss"])


# ----------------------------------------------------------------- baselines and dropout
@pytest.mark.slow
def test_model_baselines_and_dropout_sweep(tmp_path):
    data = tiny_presses()
    kw = dict(n_train_per_class=3, n_test_per_class=2, n_runs=2, verbose=0, initial_epochs=3,
              frame_size=(16, 20))
    base = run_model_baselines(data, models=("ofnn", "convlstm"), results_path=tmp_path / "b.jsonl", **kw)
    assert [(r["key"]["model"], r["key"]["seed"]) for r in base.records] == [
        ("ofnn", 0), ("ofnn", 1), ("convlstm", 0), ("convlstm", 1)]
    for r in base.records:
        assert 0 <= r["accuracy"] <= 1 and 0 <= r["train_accuracy"] <= 1 and r["mae"] >= 0
        assert len(r["train_loss_curve"]) == 3 and len(r["test_indices"]) == 10
    # the same seed gives both models the same split
    assert base.records[0]["test_indices"] == base.records[2]["test_indices"]
    rows = base.baseline_table()
    assert [r["name"] for r in rows] == ["ofnn", "convlstm"]
    sweep = run_dropout_sweep(data, model="ofnn", dropouts=(0.1, 0.3, 0.5), results_path=tmp_path / "d.jsonl", **kw)
    assert [r["key"]["dropout"] for r in sweep.records] == [0.1, 0.1, 0.3, 0.3, 0.5, 0.5]
    assert [r["name"] for r in sweep.baseline_table()] == ["0.1", "0.3", "0.5"]
    names = {os.path.basename(p) for p in base.save_figures(tmp_path) + sweep.save_figures(tmp_path)}
    assert names == {"baselines.png", "dropout_accuracy.png", "dropout_mae.png"}
    with pytest.raises(ValueError, match="dropout rates"):
        run_dropout_sweep(data, model="ofnn", dropouts=(0.1, 1.2), **kw)
    with pytest.raises(ValueError, match="fewer than"):
        run_model_baselines(data, models=("ofnn",), **dict(kw, n_train_per_class=7))
    with pytest.raises(ValueError, match="duplicate"):
        run_model_baselines(data, models=("ofnn", "ofnn"), **kw)


def test_model_baselines_scale_inputs_on_each_run_s_training_presses(monkeypatch, tmp_path):
    # the factory's scale step (FrameScaler for the ConvLSTM), fitted on the run's training presses only
    import sklearn_hardness.experiments._baselines as baselines
    from sklearn_hardness.experiments._config import check_config, get_config
    from sklearn_hardness.experiments._data import prepare_inputs
    from sklearn_hardness.models._pipelines import FrameScaler

    fitted = []

    class Recording(FrameScaler):
        def fit(self, X, y=None):
            fitted.append(np.array(X, copy=True))
            return super().fit(X, y)

    orig = baselines.input_scaler
    monkeypatch.setattr(baselines, "input_scaler", lambda model, cfg: (
        Recording() if isinstance(orig(model, cfg), FrameScaler) else orig(model, cfg)))
    data = tiny_presses()
    kw = dict(n_train_per_class=3, n_test_per_class=2, n_runs=1, verbose=0, initial_epochs=2, frame_size=(8, 10))
    res = run_model_baselines(data, models=("convlstm",), results_path=tmp_path / "b.jsonl", **kw)
    assert len(fitted) == 1 and fitted[0].shape[0] == 3 * len(np.unique(data.target))
    raw = prepare_inputs(data, check_config(dict(get_config("silicone5", frame_size=(8, 10)), model="convlstm")),
                         "convlstm", verbose=0).X
    test_rows = raw[np.asarray(res.records[0]["test_indices"])]
    assert not any(np.array_equal(row, fit_row) for row in test_rows for fit_row in fitted[0])
    assert orig("convlstm", dict(get_config("silicone5"), input_scale=None)) is None
    assert orig("ofnn", get_config("silicone5")) is None


def test_experiment_result_helpers():
    recs = [{"key": {"strategy": "a", "seed": 0}, "accuracy": [0.0, 1.0], "converged": True},
            {"key": {"strategy": "a", "seed": 1}, "accuracy": [0.5], "converged": False},
            {"key": {"strategy": "b", "seed": 0}, "accuracy": [1.0, 1.0], "converged": True}]
    res = ExperimentResult(recs)
    assert res.groups("strategy") == ["a", "b"]
    assert res.converged_fraction(strategy="a") == 0.5
    np.testing.assert_array_equal(res.curves("accuracy", strategy="a"), [[0.0, 1.0]])
    full = res.curves("accuracy", converged_only=False, strategy="a")
    assert full.shape == (2, 2) and np.isnan(full[1, 1])
    assert res.to_frame().shape[0] == 3


def test_custom_estimator_and_dinov2nn_preset():
    from sklearn.pipeline import Pipeline

    from sklearn_hardness.features import OpticalFlowFeatures
    from sklearn_hardness.models import OFNNClassifier

    data = tiny_presses()
    pipe = Pipeline([("of", OpticalFlowFeatures(n_features=20)), ("clf", OFNNClassifier(random_state=123))])
    res = run_active_sampling(data, model=pipe, strategies=("entropy",), test_classes=[2], n_runs=1,
                              verbose=0, **TINY)
    assert res.config["model"].startswith("sklearn.pipeline.Pipeline(")
    assert len(res.records[0]["accuracy"]) == TINY["n_iterations"] + 1
    with pytest.raises(TypeError, match="estimator"):
        run_active_sampling(data, model=object(), verbose=0, **TINY)

    transformers = pytest.importorskip("transformers")
    cfg = transformers.Dinov2Config(hidden_size=16, num_hidden_layers=1, num_attention_heads=2,
                                    intermediate_size=32, image_size=28, patch_size=14)
    backbone = transformers.Dinov2Model(cfg).eval()
    # shore9 hyperparameters (one frame between, DINOv2NN), scaled down, on the tiny set
    res = run_active_sampling(data, preset="shore9", strategies=("variance",), test_classes=[0], n_runs=1,
                              verbose=0, dinov2_model=backbone, **TINY)
    assert res.config["model"] == "dinov2nn" and res.config["n_between"] == 1
    assert res.config["convergence_threshold"] is None
    assert all(np.isfinite(res.records[0]["variance"]))


def test_device_key_reaches_the_named_models_and_keeps_old_hashes():
    from sklearn_hardness.experiments import get_config
    from sklearn_hardness.experiments._config import config_hash
    from sklearn_hardness.experiments._models import make_estimator

    cfg = get_config("silicone5")
    without = {k: v for k, v in cfg.items() if k != "device"}
    assert config_hash(cfg) == config_hash(without)  # results from before the key stay resumable
    assert config_hash(cfg) != config_hash(dict(cfg, device="cuda"))
    assert make_estimator("convlstm", dict(cfg, device="cuda"), 0, 5).get_params()["device"] == "cuda"
    assert make_estimator("ofnn", cfg, 0, 5).get_params()["device"] == "cpu"
    from sklearn_hardness.experiments._config import check_config

    with pytest.raises(ValueError, match="device"):
        check_config(dict(cfg, device=0))


@pytest.mark.slow
def test_early_stopping_cuts_epochs_and_is_recorded():
    from sklearn_hardness.experiments import get_config, run_active_sampling
    from sklearn_hardness.experiments._config import config_hash

    from ._exp_data import TINY, tiny_presses

    cfg = get_config("silicone5")
    assert cfg["early_stopping"] == 5  # the default (front of time against error)
    paper = dict(cfg, early_stopping=None)  # every epoch: hashed as before the key existed
    assert config_hash(paper) == config_hash({k: v for k, v in cfg.items() if k != "early_stopping"})
    assert config_hash(cfg) != config_hash(paper)
    kw = dict(TINY, initial_epochs=60, epochs_per_query=40)
    runs = {}
    for es in (None, 1):
        res = run_active_sampling(tiny_presses(), model="ofnn", strategies=("random",), test_classes=[0],
                                  n_runs=1, n_jobs=1, verbose=0, early_stopping=es, **kw)
        runs[es] = res.records[0]["epochs"]
    assert runs[None] == [60] + [40] * TINY["n_iterations"]  # every configured epoch, recorded
    assert len(runs[1]) == len(runs[None])
    assert runs[1][0] == 60  # the initial training runs in full (the convergence rule is about it)
    assert sum(runs[1]) < sum(runs[None])  # patience 1 stops at the first epoch without progress
    with pytest.raises(ValueError, match="early_stopping"):
        run_active_sampling(tiny_presses(), model="ofnn", verbose=0, early_stopping=0, **TINY)


def test_frame_size_is_written_out_and_old_results_stay_resumable():
    from sklearn_hardness.experiments import get_config
    from sklearn_hardness.experiments._config import check_config, config_hash

    new = check_config(get_config("silicone5"))
    assert new["frame_size"] == (12, 16)  # the default, written out (config.json, hash)
    assert config_hash(new) == config_hash(check_config(get_config("silicone5", frame_size=[12, 16])))
    # before: frame_size=None meant 18x24 and early stopping did not exist
    old = {k: v for k, v in check_config(get_config("silicone5", early_stopping=None)).items()
           if k != "early_stopping"}
    old["frame_size"] = None
    paper = check_config(get_config("silicone5", frame_size=(18, 24), early_stopping=None))
    assert config_hash(paper) == config_hash(old)  # results of the old default resume as 18x24
    assert config_hash(new) != config_hash(dict(new, frame_size=(18, 24)))  # never as 12x16
    assert check_config(get_config("shore9", model="ofnn"))["frame_size"] == (120, 160)
    # an estimator gets the ConvLSTM's frames: written out too, and its old results resume the same way
    custom = check_config(get_config("silicone5", model="MyPipeline()"))
    assert custom["frame_size"] == (12, 16)
    assert config_hash(dict(custom, frame_size=(18, 24))) == config_hash(dict(custom, frame_size=None))
    assert config_hash(custom) != config_hash(dict(custom, frame_size=None))
    frame_size_error = "'frame_size' parameter of the experiment configuration must be None or a pair"
    with pytest.raises(ValueError, match=frame_size_error):
        check_config(get_config("silicone5", frame_size=(12, 0)))
    with pytest.raises(ValueError, match=frame_size_error):
        check_config(get_config("silicone5", frame_size="12x16"))
