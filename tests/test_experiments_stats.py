"""Paired statistics of strategies against random, and the paper protocol's command."""

import numpy as np
import pytest
from scipy import stats

from sklearn_hardness.experiments import ExperimentResult


def _result(rng, n_pairs=12, gain=0.1, converged_fail=()):
    recs = []
    for k in range(n_pairs):
        base = rng.uniform(0.2, 0.7)
        for s, g in (("random", 0.0), ("variance", gain), ("entropy", 0.0)):
            noise = rng.normal(0, 0.05)
            acc = [0.2, base + g / 2 + noise, base + g + noise]
            recs.append({"key": {"strategy": s, "test_class": k % 3, "seed": k}, "accuracy": acc,
                         "mae": [0.3, 0.2, 0.1 - g / 2], "converged": (s, k) not in converged_fail,
                         "holdout_accuracy": [0.2, 0.3, 0.4 + g]})
    return ExperimentResult(recs)


def test_paired_table_matches_scipy_and_finds_a_real_gain():
    res = _result(np.random.default_rng(0))
    rows = {(r["strategy"], r["metric"]): r for r in res.paired_table()}
    assert {m for _, m in rows} == {"accuracy", "mae", "auc", "holdout_accuracy"}
    v = rows[("variance", "accuracy")]
    d = np.array([a["accuracy"][-1] - b["accuracy"][-1] for a, b in zip(
        res.select(strategy="variance"), res.select(strategy="random"))])
    assert v["n_pairs"] == 12 and v["diff"] == pytest.approx(d.mean())
    lo, hi = stats.t.interval(0.95, len(d) - 1, loc=d.mean(), scale=stats.sem(d))
    assert (v["diff_low"], v["diff_high"]) == (pytest.approx(lo), pytest.approx(hi))
    assert v["p_ttest"] == pytest.approx(stats.ttest_rel(
        [r["accuracy"][-1] for r in res.select(strategy="variance")],
        [r["accuracy"][-1] for r in res.select(strategy="random")]).pvalue)
    # the effect: a gain of 0.1 is found (interval above 0), no gain is not
    assert v["diff_low"] > 0 and v["p_wilcoxon"] < 0.01
    e = rows[("entropy", "accuracy")]
    assert e["diff_low"] < 0 < e["diff_high"] and e["p_ttest"] > 0.05
    # auc is the trapezoid mean of the curve
    r0 = res.select(strategy="variance")[0]["accuracy"]
    assert rows[("variance", "auc")]["n"] == 12
    assert np.mean([np.trapezoid(r["accuracy"]) / 2 for r in res.select(strategy="variance")]) == pytest.approx(
        rows[("variance", "auc")]["mean"])
    assert r0  # the reference row has no difference
    assert "diff" not in rows[("random", "accuracy")]
    text = res.format_paired_table(res.paired_table())
    assert "(reference)" in text and "p (Wilcoxon)" in text and "12 pairs" in text


def test_paired_table_uses_converged_pairs_only_and_rejects_bad_input():
    res = _result(np.random.default_rng(1), converged_fail=(("random", 0), ("variance", 5)))
    v = [r for r in res.paired_table(metrics=["accuracy"]) if r["strategy"] == "variance"][0]
    assert v["n"] == 11 and v["n_pairs"] == 10
    # identical strategies: p = 1, not NaN
    same = _result(np.random.default_rng(2), gain=0.0)
    for r in same.records:
        if r["key"]["strategy"] == "entropy":
            r["accuracy"] = next(x["accuracy"] for x in same.records if x["key"]["strategy"] == "random"
                                 and x["key"]["seed"] == r["key"]["seed"])
    e = [r for r in same.paired_table(metrics=["accuracy"]) if r["strategy"] == "entropy"][0]
    assert e["diff"] == 0 and e["p_ttest"] == 1.0 and e["p_wilcoxon"] == 1.0
    with pytest.raises(ValueError, match="reference"):
        res.paired_table(reference="bald")
    with pytest.raises(ValueError, match="unknown metrics"):
        res.paired_table(metrics=["f1"])
    with pytest.raises(ValueError, match="no active-sampling"):
        ExperimentResult([]).paired_table()


def test_reproduce_protocol_paper_passes_its_arguments(tmp_path, capsys, monkeypatch):
    from sklearn_hardness import experiments
    from sklearn_hardness._cli import main
    from sklearn_hardness.experiments import _protocol

    seen = {}
    # the command line takes the public name: patch it there (the real one runs the whole protocol)
    monkeypatch.setattr(experiments, "run_paper_protocol", lambda out, **kw: seen.update(kw, out=out) or "SUMMARY")
    assert main(["reproduce", "--protocol", "paper", "--out", str(tmp_path), "--n-runs", "3", "--quiet",
                 "--strategies", "variance", "random", "--set", "n_samples=7"]) == 0
    assert "SUMMARY" in capsys.readouterr().out
    assert seen["out"] == str(tmp_path) and seen["n_runs"] == 3 and seen["verbose"] == 0
    assert seen["strategies"] == ["variance", "random"] and seen["n_samples"] == 7
    with pytest.raises(SystemExit, match="2"):
        main(["reproduce", "--protocol", "paper", "--out", str(tmp_path), "--model", "ofnn"])
    assert "no --dataset or --model" in capsys.readouterr().err
    assert _protocol.PAPER_PROTOCOL[0][:3] == ("silicone5", "convlstm", 10)  # >= 50 paired runs per strategy
    assert _protocol.PAPER_PROTOCOL[1][:3] == ("shore9", "convlstm", 5)  # a model that learns; 45 pairs


def test_protocol_entry_configuration_reaches_its_experiments(tmp_path, monkeypatch):
    from sklearn_hardness.experiments import _protocol

    assert _protocol.PAPER_PROTOCOL[1][4] == {"lr": 3e-3}  # shore9's ConvLSTM converges at 3e-3
    seen = []

    class Stop(Exception):
        pass

    def baselines(preset, **kw):
        seen.append(kw)
        raise Stop

    monkeypatch.setattr(_protocol, "run_model_baselines", baselines)
    entry = (("shore9", "convlstm", 5, ("ofnn",), {"lr": 3e-3, "n_samples": 7}),)
    with pytest.raises(Stop):
        _protocol.run_paper_protocol(tmp_path, protocol=entry, verbose=0)
    with pytest.raises(Stop):
        _protocol.run_paper_protocol(tmp_path, protocol=entry, verbose=0, lr=1e-2)  # the caller's keys win
    assert [(kw["lr"], kw["n_samples"]) for kw in seen] == [(3e-3, 7), (1e-2, 7)]


@pytest.mark.slow
def test_paper_protocol_runs_everything_and_resumes(tmp_path, capsys):
    from sklearn_hardness.experiments._protocol import run_paper_protocol

    out = tmp_path / "paper"
    kw = dict(strategies=("variance", "random"), n_runs=2, quick=True, dropouts=(0.1, 0.3),
              protocol=(("silicone5", "ofnn", 10, ("ofnn",)),), image_size=(32, 40), frame_size=(16, 20),
              initial_epochs=2, epochs_per_query=1, n_iterations=1, n_samples=2)
    text = run_paper_protocol(out, **kw)
    err = capsys.readouterr().err
    for part in ("== silicone5: ofnn", "model baselines", "dropout sweep", "paired against random",
                 "holdout_accuracy", "p (Wilcoxon)", "2 seeds x every test object",
                 "presses to reach random's final accuracy"):
        assert part in text
    assert "runs," in err and "left" in err  # a progress line per finished run
    lines = (out / "results.jsonl").read_text().splitlines()
    # (1 baseline model + 2 dropout rates) x 2 seeds + 5 test objects x 2 seeds x 2 strategies
    assert len(lines) == 3 * 2 + 5 * 2 * 2
    assert (out / "summary.txt").read_text() == text + "\n"
    # rerun: everything is resumed, nothing recomputed, and verbose=0 prints no progress
    assert run_paper_protocol(out, verbose=0, **kw) == text
    assert (out / "results.jsonl").read_text().splitlines() == lines and capsys.readouterr().err == ""


def _stop_record(predictions, test_class=1, per_query=5, n_initial=25):
    return {
        "key": {"strategy": "variance", "test_class": test_class, "seed": 0},
        "initial_indices": list(range(n_initial)),
        "drawn_indices": [list(range(per_query))] * (len(predictions) - 1),
        "predictions": predictions,
    }


def test_decision_stop_counts_presses_to_a_settled_decision():
    from sklearn_hardness.experiments._stats import decision_stop

    rec = _stop_record([[0, 0, 1, 2, 0], [1, 1, 1, 0, 1], [1, 1, 1, 1, 1], [1, 1, 1, 1, 1], [2, 2, 2, 2, 2]])
    # 4 of 5 agree on class 1 at t=1 and t=2: settled at t=2 after two queries of 5 presses
    assert decision_stop(rec) == {"iteration": 2, "presses": 35, "accuracy": 1.0, "settled": True}
    # patience 1: the first iteration whose votes agree enough (4 of 5 at t=1) ...
    assert decision_stop(rec, patience=1)["iteration"] == 1
    # ... unless all 5 must agree: then t=2
    assert decision_stop(rec, threshold=1.0, patience=1)["iteration"] == 2
    assert decision_stop(rec, patience=1)["accuracy"] == 0.8
    # a decision that keeps changing runs to the budget and says so
    flip = _stop_record([[0] * 5, [1] * 5, [0] * 5, [1] * 5])
    assert decision_stop(flip) == {"iteration": 3, "presses": 40, "accuracy": 1.0, "settled": False}
    with pytest.raises(ValueError, match="threshold"):
        decision_stop(rec, threshold=0)
    with pytest.raises(ValueError, match="patience"):
        decision_stop(rec, patience=0)
    with pytest.raises(ValueError, match="predictions"):
        decision_stop({"key": {"test_class": 0}})


def test_paired_table_reports_presses_and_accuracy_at_the_stop():
    from sklearn_hardness.experiments import ExperimentResult

    settled_early = [[1] * 5, [1] * 5, [1] * 5, [1] * 5]
    wandering = [[0] * 5, [2] * 5, [1] * 5, [1] * 5]
    recs = []
    for seed in range(3):
        for strategy, preds in (("variance", settled_early), ("random", wandering)):
            r = _stop_record(preds)
            r["key"] = {"strategy": strategy, "test_class": 1, "seed": seed}
            r["accuracy"] = [float(np.mean(np.asarray(p) == 1)) for p in preds]
            recs.append(r)
    rows = {(r["strategy"], r["metric"]): r for r in ExperimentResult(recs).paired_table()}
    assert rows["variance", "presses_at_stop"]["mean"] == 30  # 25 initial + 1 query of 5
    assert rows["random", "presses_at_stop"]["mean"] == 40  # settles at t=3
    assert rows["variance", "presses_at_stop"]["diff"] == -10
    assert rows["variance", "accuracy_at_stop"]["mean"] == 1.0


def _curve_result(rng, n_pairs=40, early=("fast",), never=("flat",), converged_fail=()):
    """Runs of 25 initial + 5 x 5 presses; "fast" reaches random's final level two iterations sooner."""
    recs = []
    for k in range(n_pairs):
        for s in ("random", "fast", "flat"):
            if s == "random":
                mean = [0.4, 0.45, 0.5, 0.6, 0.7, 0.8]
            elif s in early:
                mean = [0.4, 0.6, 0.9, 0.9, 0.9, 0.9]
            else:
                mean = [0.4, 0.4, 0.45, 0.45, 0.5, 0.5]
            acc = np.clip(np.array(mean) + rng.normal(0, 0.1, 6), 0, 1)
            acc[0] = 0.4  # the shared initial model
            recs.append({"key": {"strategy": s, "test_class": k % 5, "seed": k // 5},
                         "converged": (s, k) not in converged_fail, "accuracy": acc.tolist(),
                         "initial_indices": list(range(25)), "drawn_indices": [list(range(5))] * 5})
    return ExperimentResult(recs)


def test_presses_to_reach_finds_the_strategy_that_gets_there_sooner():

    rows = {r["strategy"]: r for r in _curve_result(np.random.default_rng(0)).presses_to_reach(n_boot=500)}
    assert rows["random"]["presses"] == [25, 30, 35, 40, 45, 50]
    assert rows["random"]["presses_to_reach"] == 50  # random's own final accuracy, at its last press
    assert rows["fast"]["presses_to_reach"] == 35
    assert rows["fast"]["diff"] == -15 and rows["fast"]["diff_high"] < 0  # fewer presses, interval below 0
    assert rows["fast"]["p_reached"] == 1.0
    assert rows["flat"]["presses_to_reach"] == np.inf and rows["flat"]["p_reached"] < 0.05
    assert rows["flat"]["ci_high"] == np.inf and rows["flat"]["diff"] == np.inf
    text = ExperimentResult.format_presses_to_reach(list(rows.values()))
    assert "never" in text and "-15 [" in text
    # the target is the reference's mean final accuracy over the same pairs
    finals = [r["accuracy"][-1] for r in _curve_result(np.random.default_rng(0)).records
              if r["key"]["strategy"] == "random"]
    assert rows["fast"]["target"] == pytest.approx(np.mean(finals))


def test_presses_to_reach_pairs_converged_runs_and_is_seeded():

    res = _curve_result(np.random.default_rng(1), converged_fail={("fast", 0), ("random", 1)})
    rows = {r["strategy"]: r for r in res.presses_to_reach(n_boot=300, random_state=3)}
    assert rows["fast"]["n_pairs"] == 38 and rows["flat"]["n_pairs"] == 39
    again = {r["strategy"]: r for r in res.presses_to_reach(n_boot=300, random_state=3)}
    assert again["fast"]["ci_low"] == rows["fast"]["ci_low"] and again["fast"]["diff_low"] == rows["fast"]["diff_low"]
    with pytest.raises(ValueError, match="reference strategy 'bald'"):
        res.presses_to_reach(reference="bald")
    with pytest.raises(ValueError, match="n_boot"):
        res.presses_to_reach(n_boot=0)
    with pytest.raises(ValueError, match="level"):
        res.presses_to_reach(level=1.5)
