"""Tests of object-disjoint evaluation (``evaluate_pipelines``) and the ``evaluate`` CLI."""

import json

import numpy as np
import pytest
from scipy import stats
from sklearn.base import BaseEstimator, ClassifierMixin, clone
from sklearn.dummy import DummyClassifier
from sklearn.pipeline import Pipeline, make_pipeline
from sklearn.preprocessing import FunctionTransformer
from sklearn.utils import Bunch

from sklearn_hardness._cli import main
from sklearn_hardness.datasets import force_and_position, make_presses
from sklearn_hardness.experiments import run_model_baselines
from sklearn_hardness.features import PeakContactChange
from sklearn_hardness.model_selection import (
    ConfusionMatricesDisplay,
    EvaluationResult,
    corrected_interval,
    evaluate_pipelines,
)
from sklearn_hardness.model_selection._per_press import first_input
from sklearn_hardness.model_selection._report import fold_scores
from sklearn_hardness.models import (
    make_contact_profile_pipeline,
    make_named_pipeline,
    make_peak_change_baseline,
    pipeline_info,
    pipeline_names,
)


def _run(data, pipelines=None, *, baseline=True, roi=None, random_state=0, error_score="raise", verbose=1,
         **kwargs):
    """``evaluate_pipelines`` on a dataset Bunch, as the CLI calls it (the old dataset-first call, in one place)."""
    if pipelines is None:
        pipelines = ["contact_geometry", "convlstm_intensity", "contact_profile"] + (
            [] if force_and_position(data, missing="none") is None else ["loading_compliance"])
    if not isinstance(pipelines, dict):
        def video(name):
            return {"roi": roi} if roi is not None and pipeline_info(name).input == "video" else {}

        pipelines = {name: make_named_pipeline(name, random_state=random_state, **video(name)) for name in pipelines}
    reads = [n for n, e in pipelines.items() if first_input(e) == "force_position"]
    groups = getattr(data, "object_id", None)
    return evaluate_pipelines(
        pipelines, data.videos, data.target, groups=groups,
        baseline=("peak_change", make_named_pipeline("peak_change", roi=roi)) if baseline else None,
        target_names=data.target_names, hardness=getattr(data, "hardness", None),
        force_position=force_and_position(data) if reads else None, random_state=random_state,
        error_score=error_score, verbose=verbose, **kwargs)


def _scores(result, name, score="balanced_accuracy"):
    """The fold scores of ``name`` in the folds' order."""
    return fold_scores(result.cv_results_, name, score)


def _rows(result):
    """The summary's rows by pipeline name, each a dict of its columns."""
    summary = result.summary
    return {name: {key: values[i] for key, values in summary.items()} for i, name in enumerate(summary["pipeline"])}


def _folds(result):
    """The test indices of every fold, in the folds' order (the first pipeline's rows: every pipeline has them)."""
    cv = result.cv_results_
    return list(cv["test_indices"][cv["pipeline"] == result.pipelines[0]])


def _oof(result, name):
    return result.out_of_fold_predictions(name)


def _peak(videos, roi=None):
    return PeakContactChange(roi=roi).fit_transform(videos)


@pytest.fixture(scope="module")
def tiny():
    return make_presses("everyday", n_per_class=2, n_objects=12, class_ratio=[1, 1, 1],
                       image_size=(32, 40), codec=None, random_state=0)


class _Fails(BaseEstimator, ClassifierMixin):
    def fit(self, X, y):
        raise RuntimeError("boom")


def test_folds_are_object_disjoint_and_table_is_complete(tiny):
    result = _run(tiny, {"dummy": DummyClassifier(strategy="most_frequent")}, cv=3)
    assert result.pipelines == ["peak_change", "dummy"]
    tests = np.concatenate(_folds(result))
    assert np.array_equal(np.sort(tests), np.arange(len(tiny.target)))  # every press tested once
    cv = result.cv_results_
    for train, test in zip(cv["train_indices"], cv["test_indices"]):
        assert not set(tiny.object_id[test]) & set(tiny.object_id[train])
        assert np.array_equal(np.sort(np.concatenate([train, test])), np.arange(len(tiny.target)))
    assert np.all(cv["fit_time"] > 0) and np.all(cv["score_time"] > 0)
    for name, row in _rows(result).items():
        assert row["balanced_accuracy_low"] <= row["balanced_accuracy"] <= row["balanced_accuracy_high"]
        assert np.isfinite(row["neg_hardness_mae"]) and row["time"] > 0
        assert result.confusion_matrix(name).sum() == len(tiny.target)
    # a constant prediction scores chance exactly on every fold
    np.testing.assert_allclose(_scores(result, "dummy"), 1 / 3)
    text = str(result)
    assert "object-disjoint 3-fold CV, 12 objects" in text and "dummy" in text


class _KnowsTheLabels(BaseEstimator, ClassifierMixin):
    """Predicts each video's true class (looked up by its bytes): a pipeline far above any baseline."""

    def __init__(self, labels=None):
        self.labels = labels

    def fit(self, X, y):
        self.classes_ = np.unique(y)
        return self

    def predict(self, X):
        return np.array([self.labels[np.asarray(v).tobytes()] for v in X])


class _KnowsTheLabelsWithSamples(_KnowsTheLabels):
    def predict_proba_samples(self, X, n_samples=2):
        return np.zeros((n_samples, len(X), len(self.classes_)))


def test_recommendation_names_the_best_pipeline_above_the_baseline(tiny):
    labels = {np.asarray(v).tobytes(): int(c) for v, c in zip(tiny.videos, tiny.target)}
    pipes = {"dummy": DummyClassifier(strategy="most_frequent"), "oracle": _KnowsTheLabels(labels)}
    # 4 folds: with 3 folds of 12 objects the corrected interval of even a perfect pipeline holds 0
    result = _run(tiny, pipes, cv=4, verbose=0)
    rows = _rows(result)
    base = _scores(result, "peak_change")
    for name in ("dummy", "oracle"):  # paired over the same folds
        margin = rows[name]["balanced_accuracy_vs_baseline"]
        assert margin == pytest.approx(np.mean(_scores(result, name) - base))
        assert rows[name]["balanced_accuracy_vs_baseline_low"] <= margin <= rows[name][
            "balanced_accuracy_vs_baseline_high"]
    assert np.isnan(rows["peak_change"]["balanced_accuracy_vs_baseline"])
    assert rows["oracle"]["balanced_accuracy"] == 1.0 and rows["oracle"]["balanced_accuracy_vs_baseline_low"] > 0
    assert result.recommended == "oracle" and result.recommended_with_samples is None
    text = str(result)
    assert "Choose oracle" in text and "No pipeline above the baseline has predict_proba_samples" in text
    # with predict_proba_samples it is also the choice for active sampling
    pipes["oracle"] = _KnowsTheLabelsWithSamples(labels)
    result = _run(tiny, pipes, cv=4, verbose=0)
    assert result.recommended == result.recommended_with_samples == "oracle"
    assert dict(zip(result.summary["pipeline"], result.summary["predict_proba_samples"])) == {
        "peak_change": False, "dummy": False, "oracle": True}
    # nothing above the baseline: no recommendation, and the text says the one number does as well
    result = _run(tiny, {"dummy": DummyClassifier(strategy="most_frequent")}, cv=3, verbose=0)
    assert result.recommended is None and result.recommended_with_samples is None
    assert "No pipeline is above the one-number baseline" in str(result)
    # without the baseline, no comparison and no recommendation line
    result = _run(tiny, {"dummy": DummyClassifier()}, cv=3, baseline=False, verbose=0)
    assert np.isnan(result.summary["balanced_accuracy_vs_baseline"][0]) and result.recommended is None
    assert "Choose" not in str(result) and "vs peak:" not in str(result)


def test_margin_interval_is_corrected_for_overlapping_training_sets(tiny):
    # Nadeau and Bengio: var(d) * (1/k + n_test/n_train) instead of var(d) / k; wider than the plain
    # t-interval over folds, which is too narrow when the training sets overlap
    labels = {np.asarray(v).tobytes(): int(c) for v, c in zip(tiny.videos, tiny.target)}
    pipes = {"dummy": DummyClassifier(strategy="stratified", random_state=0), "oracle": _KnowsTheLabels(labels)}
    result = _run(tiny, pipes, cv=3, verbose=0)
    n = len(tiny.target)
    ratio = np.mean([len(test) / (n - len(test)) for test in _folds(result)])
    rows = _rows(result)
    for name in ("dummy", "oracle"):
        row = rows[name]
        diff = _scores(result, name) - _scores(result, "peak_change")
        t = stats.t.ppf(0.975, len(diff) - 1)
        half = t * np.sqrt(diff.var(ddof=1) * (1 / len(diff) + ratio))
        interval = (row["balanced_accuracy_vs_baseline_low"], row["balanced_accuracy_vs_baseline_high"])
        assert interval == pytest.approx((max(diff.mean() - half, -1), min(diff.mean() + half, 1)))
        plain = t * diff.std(ddof=1) / np.sqrt(len(diff))
        assert half > plain * 1.5  # 3 folds: sqrt(1 + 3 * 0.5) = 1.58
        # the public function gives the table's interval
        assert corrected_interval(_scores(result, name), ratio, baseline=_scores(result, "peak_change"),
                                  bounds=(-1, 1)) == (row["balanced_accuracy_vs_baseline"], interval)


def test_corrected_interval_of_scores_and_of_paired_differences():
    scores, base = np.array([0.6, 0.7, 0.65, 0.8, 0.75]), np.full(5, 0.5)
    mean, (lo, hi) = corrected_interval(scores, 0.25)
    half = stats.t.ppf(0.975, 4) * np.sqrt(scores.var(ddof=1) * (1 / 5 + 0.25))
    assert mean == pytest.approx(0.7) and (lo, hi) == pytest.approx((0.7 - half, 0.7 + half))
    assert corrected_interval(scores, 0.25, baseline=base)[1] == pytest.approx((0.2 - half, 0.2 + half))
    assert corrected_interval([0.9, 1.0, 0.95], 0.5, bounds=(0, 1))[1][1] == 1.0  # clipped to the score's range
    one_fold = corrected_interval([0.9, np.nan], 0.5)  # one finite fold: its mean, no interval
    assert one_fold[0] == 0.9 and np.isnan(one_fold[1]).all()
    wider = corrected_interval(scores, 0.25, df=2)[1]
    assert wider[0] < lo and wider[1] > hi  # fewer degrees of freedom (repeated folds)
    with pytest.raises(ValueError, match="same folds"):
        corrected_interval(scores, 0.25, baseline=base[:3])


def test_repeated_folds_reuse_the_objects_in_other_assignments(tiny):
    pipes = {"dummy": DummyClassifier(strategy="stratified", random_state=0)}
    once = _run(tiny, pipes, cv=3, verbose=0)
    result = _run(tiny, pipes, cv=3, n_repeats=3, verbose=0)
    n = len(tiny.target)
    folds = _folds(result)
    assert result.n_repeats == 3 and result.n_splits == 3 and len(folds) == 9
    assert result.cv_results_["repeat"].tolist() == [0, 0, 0, 1, 1, 1, 2, 2, 2] * 2
    assignments = []
    for r in range(3):
        tests = folds[3 * r: 3 * r + 3]
        assert np.array_equal(np.sort(np.concatenate(tests)), np.arange(n))  # each repetition tests every press once
        for test in tests:
            train = np.setdiff1d(np.arange(n), test)
            assert not set(tiny.object_id[test]) & set(tiny.object_id[train])
        assignments.append({frozenset(tiny.object_id[test]) for test in tests})
    assert len({frozenset(a) for a in assignments}) > 1  # the repetitions assign objects differently
    # the first repetition is the single run: same folds, scores and out-of-fold predictions
    for a, b in zip(_folds(once), folds[:3]):
        np.testing.assert_array_equal(a, b)
    for name in ("peak_change", "dummy"):
        np.testing.assert_array_equal(_scores(result, name)[:3], _scores(once, name))
        np.testing.assert_array_equal(_oof(result, name), _oof(once, name))
        assert _scores(result, name).shape == _scores(result, name, "object_balanced_accuracy").shape == (9,)
        np.testing.assert_array_equal(_scores(result, name, "object_balanced_accuracy")[:3],
                                      _scores(once, name, "object_balanced_accuracy"))
        assert result.confusion_matrix(name).sum() == 3 * n  # every press once per repetition
    rows = _rows(result)
    # every interval runs over the 9 fold scores with the corrected variance, and keeps the 2 degrees of
    # freedom of one repetition's 3 folds: the repetitions reuse the objects (with 8, equal pipelines were
    # recommended 1.5x as often as promised, studies/scripts/margin_interval.py --n-repeats 5)
    ratio = np.mean([len(test) / (n - len(test)) for test in folds])
    t = stats.t.ppf(0.975, 2)
    for values, bound, key in [  # bound: each interval is clipped to its score's range
        (_scores(result, "dummy"), 0, "balanced_accuracy"),
        (_scores(result, "dummy") - _scores(result, "peak_change"), -1, "balanced_accuracy_vs_baseline"),
        (_scores(result, "dummy", "object_balanced_accuracy"), 0, "object_balanced_accuracy"),
    ]:
        half = t * np.sqrt(values.var(ddof=1) * (1 / 9 + ratio))
        got = (rows["dummy"][key], rows["dummy"][f"{key}_low"], rows["dummy"][f"{key}_high"])
        assert got == pytest.approx((values.mean(), max(values.mean() - half, bound), min(values.mean() + half, 1)))
    assert "object-disjoint 3-fold CV x 3 repetitions, 12 objects" in str(result)
    with pytest.raises(ValueError, match="n_repeats"):  # InvalidParameterError
        _run(tiny, [], cv=3, n_repeats=0)


def test_accuracy_interval_is_corrected_too(tiny):
    # the interval of the mean balanced accuracy has the same overlapping training sets as the margin's
    result = _run(tiny, {"dummy": DummyClassifier(strategy="stratified", random_state=0)}, cv=3, verbose=0)
    n = len(tiny.target)
    ratio = np.mean([len(test) / (n - len(test)) for test in _folds(result)])
    for name, row in _rows(result).items():
        scores = _scores(result, name)
        half = stats.t.ppf(0.975, 2) * np.sqrt(scores.var(ddof=1) * (1 / 3 + ratio))
        assert (row["balanced_accuracy_low"], row["balanced_accuracy_high"]) == pytest.approx(
            (max(scores.mean() - half, 0), min(scores.mean() + half, 1)))


class _KnowsTheLabelsButOneObject(_KnowsTheLabels):
    """The oracle, wrong on every press of one object: perfect on all folds but one."""

    def __init__(self, labels=None, wrong=None):
        super().__init__(labels)
        self.wrong = wrong

    def predict(self, X):
        pred = super().predict(X)
        return np.array([(p + 1) % 3 if np.asarray(v).tobytes() in self.wrong else p for v, p in zip(X, pred)])


def test_intervals_are_clipped_to_the_range_of_the_score(tiny):
    # near a bound the symmetric t-interval reaches past it (a mean of 0.92 gave [0.79, 1.04] on the
    # everyday preset); no value past it can be true, so the interval stops there
    labels = {np.asarray(v).tobytes(): int(c) for v, c in zip(tiny.videos, tiny.target)}
    first = tiny.object_id[0]
    wrong = {np.asarray(v).tobytes() for v, o in zip(tiny.videos, tiny.object_id) if o == first}
    result = _run(tiny, {"almost": _KnowsTheLabelsButOneObject(labels, wrong)}, cv=4, verbose=0)
    row = _rows(result)["almost"]
    scores = _scores(result, "almost")
    assert (scores == 1).sum() == 3 and scores.min() < 1  # perfect on every fold but the one
    half = stats.t.ppf(0.975, 3) * np.sqrt(scores.var(ddof=1) * (1 / 4 + 1 / 3))
    assert scores.mean() + half > 1.1  # unclipped, the interval would reach well past 1
    assert (row["balanced_accuracy_low"], row["balanced_accuracy_high"]) == pytest.approx((scores.mean() - half, 1.0))
    assert row["balanced_accuracy_high"] == 1.0
    # 4 folds: the table says in words that they are too few for an interval, rather than print it
    assert "4 folds: too few for an interval" in str(result)
    assert f"[{scores.mean() - half:.2f}, 1.00]" not in str(result)
    for r in _rows(result).values():  # every interval within the range of its score
        assert 0 <= r["balanced_accuracy_low"] <= r["balanced_accuracy_high"] <= 1
        assert r["neg_hardness_mae_high"] <= 0
        if np.isfinite(r["balanced_accuracy_vs_baseline"]):
            assert -1 <= r["balanced_accuracy_vs_baseline_low"] <= r["balanced_accuracy_vs_baseline_high"] <= 1


def test_recall_per_class_says_which_ranks_a_pipeline_misses(tiny):
    labels = {np.asarray(v).tobytes(): int(c) for v, c in zip(tiny.videos, tiny.target)}
    pipes = {"dummy": DummyClassifier(strategy="constant", constant=1), "oracle": _KnowsTheLabels(labels)}
    result = _run(tiny, pipes, cv=3, verbose=0)
    names = [str(n) for n in tiny.target_names]
    np.testing.assert_allclose(np.diag(result.confusion_matrix("oracle", normalize="true")), 1.0)
    np.testing.assert_allclose(np.diag(result.confusion_matrix("dummy", normalize="true")), [0, 1, 0])
    text = str(result)
    assert f"recall per class, out of fold ({' / '.join(names)}):" in text
    assert "oracle" in text and "1.00 / 1.00 / 1.00" in text and "0.00 / 1.00 / 0.00" in text
    cm = result.confusion_matrix("peak_change")
    recall = " / ".join(f"{v:.2f}" for v in np.diag(cm) / cm.sum(axis=1))
    assert f"peak_change      {recall}" in text


class _SureOnceUnsureOnce(_KnowsTheLabels):
    """``labels`` maps each video's bytes to its class probabilities; ``predict`` is their argmax."""

    def predict_proba(self, X):
        return np.array([self.labels[np.asarray(v).tobytes()] for v in X])

    def predict(self, X):
        return np.argmax(self.predict_proba(X), axis=1)


class _SureOnceUnsureOnceVotes(_SureOnceUnsureOnce):
    """The same predictions without ``predict_proba``: per object, the presses' votes decide."""

    predict_proba = property(doc="no probabilities")  # hasattr(...) is False

    def predict(self, X):
        return np.array([np.argmax(self.labels[np.asarray(v).tobytes()]) for v in X])


def test_per_object_figures_class_each_object_by_its_presses_mean_probabilities(tiny):
    # each object's first press is sure and right, its second unsure and wrong: half the presses are
    # wrong, but the mean of an object's two presses' probabilities picks its class every time
    proba, seen = {}, set()
    for video, c, obj in zip(tiny.videos, tiny.target, tiny.object_id):
        p = np.zeros(3)
        if obj not in seen:
            p[c], p[(c + 1) % 3], p[(c + 2) % 3] = 0.9, 0.05, 0.05
        else:
            p[(c + 1) % 3], p[c], p[(c + 2) % 3] = 0.5, 0.3, 0.2
        seen.add(obj)
        proba[np.asarray(video).tobytes()] = p
    assert np.bincount(np.unique(tiny.object_id, return_counts=True)[1]).tolist() == [0, 0, 12]
    pipes = {"mean": _SureOnceUnsureOnce(proba), "votes": _SureOnceUnsureOnceVotes(proba)}
    result = _run(tiny, pipes, cv=3, verbose=0)
    rows = _rows(result)
    np.testing.assert_allclose(_scores(result, "mean"), 0.5)
    np.testing.assert_allclose(_scores(result, "votes"), 0.5)
    np.testing.assert_allclose(_scores(result, "mean", "object_balanced_accuracy"), 1.0)
    # without probabilities each object's two votes tie and the lower class wins: right for the objects of
    # classes 0 and 1 (0 against 1, 1 against 2), wrong for those of class 2 (2 against 0)
    np.testing.assert_allclose(_scores(result, "votes", "object_balanced_accuracy"), 2 / 3)
    assert rows["mean"]["object_balanced_accuracy"] == 1.0 and rows["mean"]["balanced_accuracy"] == 0.5
    lo, hi = rows["votes"]["object_balanced_accuracy_low"], rows["votes"]["object_balanced_accuracy_high"]
    assert rows["votes"]["object_balanced_accuracy"] == pytest.approx(2 / 3) and lo <= 2 / 3 + 1e-12 <= hi + 2e-12
    base = _scores(result, "peak_change", "object_balanced_accuracy")
    assert rows["mean"]["object_balanced_accuracy_vs_baseline"] == pytest.approx(np.mean(1.0 - base))
    assert np.isnan(rows["peak_change"]["object_balanced_accuracy_vs_baseline"])
    text = str(result)
    assert "per object: each test object classed by the mean of its presses' predicted probabilities" in text
    assert "12 objects, median 2 presses each" in text
    block = text.split("per object:")[1].split("recall per class")[0]
    lines = {line.split()[0]: line.split(maxsplit=1)[1] for line in block.splitlines()[1:]}
    # 3 folds: the means, the intervals said in words (too few folds for one)
    assert lines["mean"].startswith("1.00 ") and lines["votes"].startswith("0.67 ")
    assert "+" not in lines["peak_change"]  # no margin over itself
    assert "3 folds: too few for an interval" in text


def test_failing_pipeline_is_reported_not_dropped(tiny):
    from sklearn.exceptions import FitFailedWarning

    with pytest.warns(FitFailedWarning, match="(?s)3 fits failed out of a total of 6.*RuntimeError: boom"):
        result = _run(tiny, {"bad": _Fails()}, cv=3, error_score=np.nan)
    row = _rows(result)["bad"]
    assert np.isnan(row["balanced_accuracy"]) and "boom" in row["error"]
    assert list(result.cv_results_["error"][result.cv_results_["pipeline"] == "bad"]) == ["RuntimeError: boom"] * 3
    assert "error: RuntimeError: boom" in str(result)
    with pytest.raises(RuntimeError, match="boom"):
        _run(tiny, {"bad": _Fails()}, cv=3)
    # a numeric error_score scores the failing folds, as cross_validate does
    with pytest.warns(FitFailedWarning):
        result = _run(tiny, {"bad": _Fails()}, cv=3, error_score=0.0)
    np.testing.assert_array_equal(_scores(result, "bad"), 0.0)


class _KnowsTheLabelsOnOneFold(_KnowsTheLabels):
    """The oracle, but its fit fails whenever a given press is among the training presses."""

    def __init__(self, labels=None, fails_with=None):
        super().__init__(labels)
        self.fails_with = fails_with

    def fit(self, X, y):
        if any(np.asarray(v).tobytes() == self.fails_with for v in X):
            raise RuntimeError("the press is in training")
        return super().fit(X, y)


def test_one_fold_does_not_make_a_recommendation(tiny):
    # the oracle fits on the one fold that tests the first press and fails on the others: one fold
    # difference is no evidence, so no interval and no recommendation (before: the point as interval)
    from sklearn.exceptions import FitFailedWarning

    labels = {np.asarray(v).tobytes(): int(c) for v, c in zip(tiny.videos, tiny.target)}
    oracle = _KnowsTheLabelsOnOneFold(labels, np.asarray(tiny.videos[0]).tobytes())
    with pytest.warns(FitFailedWarning, match="the press is in training"):
        result = _run(tiny, {"oracle": oracle}, cv=4, error_score=np.nan, verbose=0)
    row = _rows(result)["oracle"]
    assert np.isfinite(_scores(result, "oracle")).sum() == 1 and row["balanced_accuracy_vs_baseline"] > 0
    assert np.isnan([row["balanced_accuracy_vs_baseline_low"], row["balanced_accuracy_vs_baseline_high"],
                     row["balanced_accuracy_low"], row["balanced_accuracy_high"]]).all()
    assert result.recommended is None
    assert "No pipeline is above the one-number baseline" in str(result)


def test_bad_input(tiny):
    with pytest.raises(ValueError, match="fewer than cv=5 objects .*; lower cv to at most 4"):
        _run(tiny, [], cv=5)
    # what a manifest without an object_id column gives: every label one object; the error says so
    nameless = Bunch(**tiny)
    nameless.object_id = np.asarray(tiny.target_names)[tiny.target]
    with pytest.raises(ValueError, match="at least 2 objects of every class.*names no objects.*add an object_id"):
        _run(nameless, [], cv=3)
    one_hard = Bunch(**tiny)  # objects named, but one class has one object: more objects, not a lower cv
    one_hard.object_id = np.where(tiny.target == 0, "the-hard-one", tiny.object_id)
    with pytest.raises(ValueError, match="'hard': 1.*record more objects of those classes"):
        _run(one_hard, [], cv=3)
    with pytest.raises(ValueError, match="unknown pipeline"):
        _run(tiny, ["resnet"], cv=3)
    no_groups = Bunch(**tiny)
    no_groups.object_id = None
    with pytest.raises(ValueError, match="integer cv makes folds grouped by object: pass groups"):
        _run(no_groups, [], cv=3)
    with pytest.raises(ValueError, match="X has 24 presses but y has 23"):
        evaluate_pipelines([], tiny.videos, tiny.target[1:], groups=tiny.object_id, cv=3)
    with pytest.raises(ValueError, match="cv"):  # InvalidParameterError
        _run(tiny, [], cv=1)


def test_peak_change_baseline_uses_the_contact_signal(tiny):
    feature = _peak(tiny.videos)
    assert feature.shape == (len(tiny.target), 1) and np.all(np.isfinite(feature))
    still = np.full((5, 16, 16, 3), 90, np.uint8)
    pressed = still.copy()
    pressed[2:, 4:12, 4:12] = 140
    assert _peak([pressed])[0, 0] > _peak([still])[0, 0] + 2
    base = make_peak_change_baseline()
    assert base[-1].class_weight == "balanced"
    # on the shuffled feature (no signal) the same pipeline drops to about chance
    rng = np.random.default_rng(0)
    shuffled = make_pipeline(FunctionTransformer(lambda X: rng.permutation(_peak(X))),
                             *[s for _, s in base.steps[1:]])
    real = _run(tiny, {}, cv=3).summary["balanced_accuracy"][0]
    noise = _run(tiny, {"shuffled": shuffled}, cv=3, baseline=False).summary["balanced_accuracy"][0]
    assert real > noise


def test_run_model_baselines_grouped_cv(tiny):
    result = run_model_baselines(tiny, models=[("dummy", DummyClassifier())], cv=3)
    assert result.pipelines == ["peak_change", "dummy"]


@pytest.mark.slow
def test_cli_evaluate_on_a_manifest(tmp_path, capsys, monkeypatch):
    root = tmp_path / "presses"
    assert main(["simulate", "--preset", "everyday", "--out", str(root), "--n-per-class", "1",
                 "--image-size", "32", "40", "--format", "avi", "--codec", "none"]) == 0
    monkeypatch.chdir(tmp_path)
    out = tmp_path / "hardness_evaluation"  # written without --out
    assert main(["evaluate", str(root / "manifest.csv"), "--pipelines", "--cv", "3"]) == 0
    text = capsys.readouterr().out
    assert "object-disjoint 3-fold CV, 42 objects, 42 presses" in text and "peak_change" in text
    assert (out / "confusion_matrices.png").stat().st_size > 1000
    saved = json.loads((out / "evaluation.json").read_text())
    cv = saved["cv_results"]
    assert saved["target_names"] == ["hard", "moderate", "soft"] and cv["pipeline"] == ["peak_change"] * 3
    assert saved["recommended"] is None and saved["recommended_with_samples"] is None  # the baseline alone
    # one press per object: the figures per object are those per press, and the table leaves them out
    assert cv["test_object_balanced_accuracy"] == cv["test_balanced_accuracy"] and "per object" not in text
    assert saved["summary"]["pipeline"] == ["peak_change"] and len(cv["test_indices"]) == 3
    # the saved table says what made it: the command less --out, the version, the date, the platform
    from sklearn_hardness import __version__
    from sklearn_hardness._cli._header import read_header

    record = read_header((out / "evaluation.txt").read_text())
    assert record["command"] == f"sklearn-hardness evaluate {root / 'manifest.csv'} --pipelines --cv 3"
    assert record["version"] == __version__ and saved["provenance"] == record
    assert "object-disjoint 3-fold CV" in (out / "evaluation.txt").read_text()
    # --n-repeats: the folds of every repetition, saved and named in the table
    assert main(["evaluate", str(root / "manifest.csv"), "--pipelines", "--cv", "3", "--n-repeats", "2",
                 "--out", str(tmp_path / "repeated")]) == 0
    assert "object-disjoint 3-fold CV x 2 repetitions" in capsys.readouterr().out
    saved = json.loads((tmp_path / "repeated" / "evaluation.json").read_text())
    assert saved["n_repeats"] == 2 and len(saved["cv_results"]["test_balanced_accuracy"]) == 6
    with pytest.raises(SystemExit, match="2"):
        main(["evaluate", str(root / "manifest.csv"), "--pipelines", "--n-repeats", "0"])
    assert "--n-repeats" in capsys.readouterr().err
    # --quiet silences the start line and the progress on stderr; the table still goes to stdout
    assert main(["evaluate", str(root / "manifest.csv"), "--pipelines", "--cv", "3", "--quiet"]) == 0
    captured = capsys.readouterr()
    assert captured.err == "" and "peak_change" in captured.out
    with pytest.raises(SystemExit, match="2"):
        main(["evaluate", str(tmp_path / "missing.csv"), "--pipelines"])
    assert "neither a simulator preset" in capsys.readouterr().err


def test_named_nets_are_seeded_by_random_state():
    """A run by name repeats exactly: the nets take the evaluation's seed."""
    from sklearn_hardness.model_selection._validation import _named_estimators

    named, base = _named_estimators(["ofnn_quantiles", "convlstm_intensity"], "peak_change", 3, None)
    assert base == "peak_change" and list(named) == ["peak_change", "ofnn_quantiles", "convlstm_intensity"]
    assert named["ofnn_quantiles"][-1].random_state == 3
    assert named["convlstm_intensity"][-1].random_state == 3 and "intensity" in named["convlstm_intensity"].named_steps
    assert _named_estimators(["ofnn_quantiles"], None, None, None)[0]["ofnn_quantiles"][-1].random_state is None


@pytest.mark.slow
def test_a_run_by_name_repeats_exactly(tiny):
    a = _run(tiny, pipelines=["ofnn"], cv=3, random_state=1)
    b = _run(tiny, pipelines=["ofnn"], cv=3, random_state=1)
    np.testing.assert_array_equal(_oof(a, "ofnn"), _oof(b, "ofnn"))


def test_contact_profile_3_is_the_factory_with_three_features(tiny):
    """The name runs what a user builds with ``features=`` (the same folds, predictions and scores)."""
    three = ["log_peak_change", "log_loading_time", "log_contact_spread"]
    named = _run(tiny, pipelines=["contact_profile_3", "contact_profile"], cv=3, verbose=0)
    built = _run(tiny, {"contact_profile_3": make_contact_profile_pipeline(features=three)}, cv=3, verbose=0)
    np.testing.assert_array_equal(_oof(named, "contact_profile_3"), _oof(built, "contact_profile_3"))
    np.testing.assert_array_equal(_scores(named, "contact_profile_3"), _scores(built, "contact_profile_3"))
    # not the twelve: the three give other predictions on these presses
    assert not np.array_equal(_oof(named, "contact_profile_3"), _oof(named, "contact_profile"))


def test_progress_on_stderr_when_verbose(tiny, capsys):
    import re

    dummy = {"dummy": DummyClassifier(strategy="most_frequent")}
    _run(tiny, dummy, cv=3, verbose=1)
    captured = capsys.readouterr()
    lines = captured.err.splitlines()
    assert lines[0].startswith("evaluate: 2 pipeline(s) (peak_change, dummy) x 3 folds on")
    assert lines[1] == "evaluate: PeakContactChange of every press, once for all folds (peak_change)"
    done = [int(m) for m in re.findall(r"^evaluate: (\d)/6 fits, \d+s elapsed, about \d+s left(?:, not counting "
                                       r"dummy \(no fit finished yet\))?$",
                                       captured.err, flags=re.M)]
    assert done == [1, 2, 3, 4, 5, 6] and captured.out == ""
    _run(tiny, dummy, cv=3, verbose=0)
    assert capsys.readouterr().err == ""


def test_peak_change_roi_measures_only_the_region():
    # a press in the left half (the gel) and a bright flicker in the right half (the housing)
    rng = np.random.default_rng(0)
    video = rng.integers(88, 92, size=(8, 16, 32, 3)).astype(np.uint8)
    video[3:, 4:12, 2:10] = 110
    flicker = video.copy()
    flicker[4:, :, 16:] = np.where(np.arange(16) % 2 == 0, 200, 20)[None, None, :, None]
    gel = (0.0, 1.0, 0.0, 0.5)
    whole, left = _peak([flicker]), _peak([flicker], roi=gel)
    np.testing.assert_allclose(left, _peak([video], roi=gel))  # the flicker is ignored
    assert whole[0, 0] > left[0, 0] + 1
    base = make_peak_change_baseline(roi=gel)
    np.testing.assert_allclose(base[0].fit_transform([flicker]), left)
    assert make_peak_change_baseline()[0].roi is None
    for bad in [(0.5, 0.2, 0, 1), (0, 1, 0), (0, 1.5, 0, 1), "top"]:
        with pytest.raises(ValueError, match="roi must be None or"):
            make_peak_change_baseline(roi=bad)


def test_roi_reaches_the_baseline_and_every_named_pipeline():
    """``evaluate --roi``: each pipeline reads the gel only; where the rest of the frame changes, that decides."""
    from sklearn_hardness._cli._evaluate import _estimators

    from ._synthetic import FRAMED_GEL, framed_press, growing_disc_press

    for name in pipeline_names():
        params = _estimators([name], None, FRAMED_GEL, 0)[name].get_params()
        if name == "loading_compliance":  # force and position: no frames to read
            assert not any(k.endswith("__roi") for k in params), name
            continue
        read = [v for k, v in params.items() if k.endswith("__roi")]
        assert read == [FRAMED_GEL], name
    rng = np.random.default_rng(1)
    X, y = [], []
    for i in range(30):  # soft presses load slowly, hard ones fast, beside a change of the housing
        soft = i % 2
        X.append(framed_press(growing_disc_press(int(rng.integers(25, 40)) if soft else int(rng.integers(2, 6)),
                                                 float(rng.uniform(5, 9)), rng), rng))
        y.append(soft)
    data = Bunch(videos=X, target=np.array(y), target_names=np.array(["hard", "soft"]), object_id=np.arange(30))
    on_gel = _run(data, ["contact_profile"], cv=3, roi=FRAMED_GEL, verbose=0)
    whole = _run(data, ["contact_profile"], cv=3, verbose=0)
    assert _rows(on_gel)["contact_profile"]["balanced_accuracy"] >= 0.9 > 0.6 >= _rows(whole)["contact_profile"][
        "balanced_accuracy"]


@pytest.mark.slow
def test_per_press_steps_run_once_for_all_folds_with_the_same_results(tiny, monkeypatch):
    """Selection and features of each press: one pass for every fold and pipeline that shares them."""
    from sklearn_hardness.features import ContactProfileFeatures
    from sklearn_hardness.model_selection import _per_press

    calls = []
    original = ContactProfileFeatures._transform_presses

    def counting(self, X):
        calls.append(len(X))
        return original(self, X)

    monkeypatch.setattr(ContactProfileFeatures, "_transform_presses", counting)
    names = ["contact_profile", "contact_profile_nn", "contact_profile_3", "ofnn"]
    once = _run(tiny, names, cv=3, verbose=0)
    # every press once, for the three contact-profile pipelines (contact_profile_3 takes its three columns
    # of the twelve) and all folds
    assert calls == [len(tiny.target)]
    calls.clear()
    monkeypatch.setattr(_per_press, "split_per_press", lambda est: (None, est))  # each fold computes its own
    per_fold = _run(tiny, names, cv=3, verbose=0)
    assert len(calls) == 27  # per fold and pipeline: fit, predict and predict_proba (the per-object score)
    for name in ["peak_change", *names]:
        np.testing.assert_array_equal(_oof(once, name), _oof(per_fold, name))
        np.testing.assert_array_equal(_scores(once, name), _scores(per_fold, name))


@pytest.mark.slow
def test_per_press_pass_gives_the_nets_the_same_inputs(tiny, monkeypatch):
    """The frame selector and frozen DINOv2 features (a tiny random backbone) once for all folds: the same results."""
    from sklearn_hardness.model_selection import _per_press
    from sklearn_hardness.models import make_convlstm_pipeline, make_dinov2nn_pipeline

    from .test_features_dinov2 import tiny_backbone

    def nets():
        return {"convlstm": make_convlstm_pipeline(intensity_channels=True, frame_size=(8, 10), max_epochs=3,
                                                   random_state=0),
                "dinov2nn": make_dinov2nn_pipeline(model=tiny_backbone(), frame_size=(28, 28), max_epochs=3,
                                                   random_state=0)}

    once = _run(tiny, nets(), cv=3, baseline=False, verbose=0)
    monkeypatch.setattr(_per_press, "split_per_press", lambda est: (None, est))
    per_fold = _run(tiny, nets(), cv=3, baseline=False, verbose=0)
    for name in ("convlstm", "dinov2nn"):
        np.testing.assert_array_equal(_oof(once, name), _oof(per_fold, name))
        np.testing.assert_array_equal(_scores(once, name), _scores(per_fold, name))


def test_split_per_press_stops_at_the_first_step_that_learns():
    from sklearn.pipeline import FeatureUnion
    from sklearn.preprocessing import StandardScaler

    from sklearn_hardness.features import ContactGeometryFeatures, ContactProfileFeatures
    from sklearn_hardness.model_selection._per_press import split_per_press
    from sklearn_hardness.models import (
        make_contact_geometry_pipeline,
        make_convlstm_pipeline,
        make_dinov2nn_pipeline,
        make_loading_compliance_pipeline,
        make_ofnn_pipeline,
    )

    steps = {name: [[n for n, _ in part.steps] if part is not None else None for part in split_per_press(est)]
             for name, est in [("cp", make_contact_profile_pipeline()), ("convlstm", make_convlstm_pipeline()),
                               ("ofnn", make_ofnn_pipeline()), ("dinov2nn", make_dinov2nn_pipeline()),
                               ("peak", make_peak_change_baseline()),
                               ("geometry+profile", make_contact_geometry_pipeline(with_profile=True)),
                               ("loading", make_loading_compliance_pipeline())]}
    assert steps == {"cp": [["features"], ["scale", "clf"]], "convlstm": [["frames"], ["scale", "clf"]],
                     "ofnn": [["frames", "features"], ["clf"]], "dinov2nn": [["frames", "features"], ["clf"]],
                     "peak": [["peakcontactchange"], ["standardscaler", "logisticregression"]],
                     "geometry+profile": [["features"], ["scale", "clf"]],
                     "loading": [["features"], ["log", "impute", "scale", "clf"]]}
    # a transformer that may learn (any function, a union with one) keeps the pipeline whole
    other = make_pipeline(FunctionTransformer(np.log1p), DummyClassifier())
    assert split_per_press(other) == (None, other)
    mixed = make_pipeline(FeatureUnion([("g", ContactGeometryFeatures()), ("s", StandardScaler())]),
                          DummyClassifier())
    assert split_per_press(mixed) == (None, mixed)
    union = make_pipeline(FeatureUnion([("g", ContactGeometryFeatures()), ("p", ContactProfileFeatures())]),
                          DummyClassifier())
    assert [n for n, _ in split_per_press(union)[0].steps] == ["featureunion"]


def test_a_press_no_step_can_read_fails_its_folds_as_before(tiny):
    from sklearn.exceptions import FitFailedWarning

    videos = [tiny.videos[i] for i in range(len(tiny.target))]
    videos[0] = np.zeros((5, 8), dtype=np.uint8)  # not a video
    data = Bunch(videos=videos, target=tiny.target, target_names=tiny.target_names, object_id=tiny.object_id)
    # every fold holds the press: the two folds that train on it fail to fit, the one that tests it to score
    with pytest.warns(FitFailedWarning, match="4 fits failed out of a total of 6"), \
            pytest.warns(UserWarning, match="Scoring failed"):
        result = _run(data, ["contact_profile"], cv=3, error_score=np.nan, verbose=0)
    for name, row in _rows(result).items():
        assert np.isnan(row["balanced_accuracy"]) and "must have shape (T, H, W, C)" in row["error"], name
    assert np.isnan(result.cv_results_["test_balanced_accuracy"]).all()


class _CountsFits(DummyClassifier):
    """A most-frequent classifier that counts its fits on the class."""

    fits = 0

    def fit(self, X, y, sample_weight=None):
        type(self).fits += 1
        return super().fit(X, y, sample_weight)


def test_presses_a_pipeline_cannot_take_are_named_by_dataset_index_and_file(tiny):
    # one-frame videos: the contact-profile features take them, the nets' frame selection needs two
    # frames; the chunks of the per-press pass (and the folds) would name them by their index there
    from sklearn.exceptions import FitFailedWarning

    from sklearn_hardness.model_selection._per_press import FailingPressesError
    from sklearn_hardness.preprocessing import ContactFrameSelector

    data = Bunch(**tiny)
    data.videos = [v[:1] if i in (5, 17) else v for i, v in enumerate(tiny.videos)]
    # a manifest's lazy videos: their keys (the files) name the presses
    from sklearn_hardness.utils._lazy import LazyVideoSequence

    shortened = list(data.videos)
    data.videos = LazyVideoSequence(lambda path: shortened[int(path.split("_")[1].split(".")[0])],
                                    [f"objects/press_{i}.mp4" for i in range(len(shortened))])
    frames = make_pipeline(ContactFrameSelector(frame_size=(8, 10)), FunctionTransformer(
        lambda X: np.asarray(X, dtype=float).reshape(len(X), -1)), _CountsFits())
    _CountsFits.fits = 0
    with pytest.raises(FailingPressesError) as info:
        _run(data, {"profile": make_contact_profile_pipeline(), "frames": frames}, cv=3, n_jobs=2, verbose=0)
    message = str(info.value)
    assert message.startswith("frames: ContactFrameSelector fails on 2 of 24 presses, each by itself:\n")
    assert ("  press 5 (objects/press_5.mp4): ValueError: the press has 1 frame(s); at least 2 are needed.\n"
            "  press 17 (objects/press_17.mp4): ValueError: the press has 1 frame(s)") in message
    assert "Remove their rows from the manifest" in message
    assert [i for i, _ in info.value.failures] == [5, 17] and _CountsFits.fits == 0  # before any fit
    # with a numeric error_score: its folds fail at once (no fit), the notes name the presses, others score
    with pytest.warns(FitFailedWarning, match="3 fits of 'frames' failed"):
        result = _run(data, {"profile": make_contact_profile_pipeline(), "frames": frames}, cv=3,
                      error_score=np.nan, verbose=0)
    rows = _rows(result)
    assert _CountsFits.fits == 0 and np.isnan(rows["frames"]["balanced_accuracy"])
    assert rows["frames"]["error"] == ("FailingPressesError: ContactFrameSelector fails on 2 of 24 presses "
                                       "(the notes name them)")
    assert np.isfinite(rows["profile"]["balanced_accuracy"]) and rows["profile"]["error"] is None
    assert result.notes[-1] == (
        "frames: ContactFrameSelector fails on 2 of 24 presses, each by itself: press 5 (objects/press_5.mp4): "
        "ValueError: the press has 1 frame(s); at least 2 are needed.; press 17 (objects/press_17.mp4): "
        "ValueError: the press has 1 frame(s); at least 2 are needed.")


def test_an_error_of_the_steps_not_the_presses_is_raised_as_it_is(tiny):
    # every press would fail alone with it: a parameter, not the presses (as missing weights would be)
    from sklearn.exceptions import FitFailedWarning

    from sklearn_hardness.model_selection._per_press import FailingPressesError
    from sklearn_hardness.preprocessing import ContactFrameSelector

    bad = make_pipeline(ContactFrameSelector(roi=(0.9, 0.1, 0.0, 1.0)), DummyClassifier())
    with pytest.raises(ValueError, match="roi") as info:
        _run(tiny, {"bad": bad}, cv=3, n_jobs=2, verbose=0)
    assert not isinstance(info.value, FailingPressesError)
    with pytest.warns(FitFailedWarning, match="roi"):
        result = _run(tiny, {"bad": bad}, cv=3, error_score=np.nan, verbose=0)
    error = _rows(result)["bad"]["error"]
    assert "roi" in error and "FailingPressesError" not in error


def test_an_error_no_press_raises_alone_is_raised_as_it_is():
    from sklearn_hardness.model_selection._per_press import _fit_transform_chunk

    class _FailsOnMany(FunctionTransformer):
        def fit_transform(self, X, y=None):
            if len(X) > 1:
                raise MemoryError("too many at once")
            return np.zeros((len(X), 1))

    prefix = Pipeline([("many", _FailsOnMany())])
    with pytest.raises(MemoryError, match="too many at once"):
        _fit_transform_chunk(prefix, [np.zeros((3, 4, 4))] * 4, np.arange(4))
    rows, _, failures = _fit_transform_chunk(prefix, [np.zeros((3, 4, 4))] * 4, np.arange(1))
    assert rows.shape == (1, 1) and failures is None


def test_plot_confusion_matrices_draws_one_row_normalised_matrix_per_pipeline(tmp_path):
    data = make_presses("everyday", n_per_class=2, n_objects=9, class_ratio=[1, 1, 1],
                        image_size=(32, 40), codec=None, random_state=0)
    result = _run(data, pipelines={"dummy": DummyClassifier(strategy="prior")}, cv=3, verbose=0)
    display = ConfusionMatricesDisplay.from_result(result)
    fig = display.figure_
    fig.savefig(tmp_path / "cm.png")
    assert (tmp_path / "cm.png").stat().st_size > 0 and list(display.displays_) == ["peak_change", "dummy"]
    # drawn on the user's axes, as scikit-learn's displays
    import matplotlib.pyplot as plt

    _, axes = plt.subplots(2, 1)
    assert ConfusionMatricesDisplay.from_result(result, ax=axes).figure_ is axes[0].figure
    with pytest.raises(ValueError, match="one per pipeline"):
        ConfusionMatricesDisplay.from_result(result, ax=axes[:1])
    axes = [ax for ax in fig.axes if ax.images]
    assert len(axes) == len(result.pipelines) == 2
    shown = np.asarray(axes[0].images[0].get_array())
    np.testing.assert_allclose(shown.sum(axis=1), 1.0)  # recall per true class


def test_loading_compliance_reads_force_and_position_on_the_same_folds(tiny):
    """By name or in a dict (first step LoadingCompliance), it gets each press's (T, 2) force and position."""
    from sklearn_hardness.features import LoadingCompliance
    from sklearn_hardness.models import make_loading_compliance_pipeline

    seen = []

    class Spy(LoadingCompliance):
        def fit(self, X, y=None):
            seen.append(X)
            return super().fit(X, y)

    spied = make_loading_compliance_pipeline()
    spied.steps[0] = ("features", Spy(features=["hertz_compliance"]))
    result = _run(tiny, {"spied": spied, "named": make_loading_compliance_pipeline()}, cv=3, verbose=0)
    by_name = _rows(result)
    np.testing.assert_array_equal(_scores(result, "spied"), _scores(result, "named"))
    assert all(np.isfinite(_scores(result, "named"))) and by_name["named"]["error"] is None
    assert by_name["named"]["predict_proba_samples"]
    # the one pass over every press's force and position: what the spy saw
    expected = [np.column_stack([tiny.force[i], tiny.position[i]]) for i in range(len(tiny.target))]
    assert len(seen) == 1 and len(seen[0]) == len(expected)
    for got, want in zip(seen[0], expected):
        np.testing.assert_array_equal(got, want)
    # the force and the sensor's position tell new objects apart better than the video's one number
    assert by_name["named"]["balanced_accuracy"] > by_name["peak_change"]["balanced_accuracy"]


def test_loading_compliance_without_position_is_an_error_that_says_what_to_give(tiny):
    no_position = Bunch(**{k: v for k, v in tiny.items() if k != "position"})
    with pytest.raises(ValueError, match="force_path and position_path"):
        _run(no_position, ["loading_compliance"], cv=3, verbose=0)
    cut = Bunch(**tiny)
    cut.position = [p[:-1] if i == 4 else p for i, p in enumerate(tiny.position)]
    with pytest.raises(ValueError, match="press 4 has .* force values but .* positions"):
        _run(cut, ["loading_compliance"], cv=3, verbose=0)
    cut.paths = [f"videos/press_{i}.avi" for i in range(len(cut.target))]  # a manifest's: its video named
    with pytest.raises(ValueError, match=r"press 4 \(videos/press_4.avi\) has .* force values but"):
        _run(cut, ["loading_compliance"], cv=3, verbose=0)


def test_the_loading_phase_note_says_where_the_recording_breaks_the_conventions(tiny):
    # the folds silence LoadingCompliance's warnings; a position that falls (a gripper's width) is said once
    width = Bunch(**tiny)
    width.position = [-z for z in tiny.position]
    notes = _run(width, ["loading_compliance"], cv=3, verbose=0).notes
    assert len(notes) == 1 and "the position falls as the force rises" in notes[0]
    assert "the position falls" not in " ".join(_run(tiny, ["loading_compliance"], cv=3,
                                                                   verbose=0).notes)


def test_cli_evaluates_loading_compliance_on_a_simulated_manifest(tmp_path, capsys):
    root = tmp_path / "presses"
    assert main(["simulate", "--preset", "everyday", "--out", str(root), "--n-per-class", "1",
                 "--image-size", "32", "40", "--format", "npy", "--codec", "none", "--quiet"]) == 0
    assert main(["evaluate", str(root), "--pipelines", "loading_compliance", "--cv", "3", "--quiet",
                 "--out", str(tmp_path / "out")]) == 0
    assert "loading_compliance" in capsys.readouterr().out
    manifest = root / "manifest.csv"  # the same presses without the position column
    lines = manifest.read_text().splitlines()
    drop = lines[0].split(",").index("position_path")
    manifest.write_text("\n".join(",".join(c for j, c in enumerate(line.split(",")) if j != drop)
                                  for line in lines) + "\n")
    with pytest.raises(SystemExit, match="2"):
        main(["evaluate", str(root), "--pipelines", "loading_compliance", "--cv", "3", "--quiet"])
    assert "force_path and position_path" in capsys.readouterr().err


def test_by_default_evaluate_adds_loading_compliance_where_every_press_has_force_and_position(tiny, monkeypatch):
    from sklearn_hardness._cli import build_parser
    from sklearn_hardness._cli._evaluate import _force_position
    DEFAULT_PIPELINES = [n for n in pipeline_names() if pipeline_info(n).default]
    from sklearn_hardness.model_selection import _validation

    assert len(_force_position(tiny, None)) == len(tiny.target)  # the command adds loading_compliance
    assert list(_validation._named_estimators(None, None, 0, _force_position(tiny, None))[0]) == [
        *DEFAULT_PIPELINES, "loading_compliance"]
    no_position = Bunch(**{k: v for k, v in tiny.items() if k != "position"})
    assert _force_position(no_position, None) is None
    assert list(_validation._named_estimators(None, None, 0, None)[0]) == list(DEFAULT_PIPELINES)
    one_lacking = Bunch(**tiny)
    one_lacking.position = [None, *tiny.position[1:]]
    assert _force_position(one_lacking, None) is None
    assert build_parser().parse_args(["evaluate", "everyday"]).pipelines is None


def test_a_multi_axis_force_is_an_error_that_says_which_component_to_give(tiny):
    three_axis = Bunch(**tiny)
    three_axis.force = [np.column_stack([f, f, f]) if i == 2 else f for i, f in enumerate(tiny.force)]
    with pytest.raises(ValueError, match=r"press 2: force must be one number per frame.*shape \(\d+, 3\)"):
        _run(three_axis, ["loading_compliance"], cv=3, verbose=0)
    column = Bunch(**tiny)
    column.position = [z[:, None] for z in tiny.position]  # (T, 1) is one number per frame
    assert _rows(_run(column, ["loading_compliance"], cv=3, verbose=0))["loading_compliance"]["error"] is None


def test_notes_say_once_what_the_folds_warnings_would_have_said(tiny):
    # the folds fit with warnings silenced (each would repeat the same presses); the notes count them
    from sklearn_hardness.features import LoadingCompliance
    from sklearn_hardness.preprocessing import ContactFrameSelector

    data = Bunch(**tiny)
    data.videos = [v[:4] if i == 5 else v for i, v in enumerate(tiny.videos)]  # cut to 4 frames
    data.force = [np.zeros_like(f) if i == 7 else f for i, f in enumerate(tiny.force)]  # never loaded
    with pytest.warns(UserWarning, match="too short to detect contact"):
        status = ContactFrameSelector().select(data.videos).status
    assert status[5] == "too short"
    frames = make_pipeline(ContactFrameSelector(), DummyClassifier())
    result = _run(data, {"frames": frames}, cv=3, verbose=0)
    found = int(np.isin(status, ["contact", "weak contact"]).sum())
    weak, short = int((status == "weak contact").sum()), int((status == "too short").sum())
    assert result.notes[0].startswith(f"contact (frames): found on {found} of {len(status)} presses "
                                      f"({weak} weak); ")
    assert f"too short {short}: their frames are spread" in result.notes[0]
    assert len(result.notes) == 1 and f"data: {result.notes[0]}" in str(result)
    # selections that agree on every press give one line naming their pipelines; others their own
    pipes = {"frames": frames, "more_frames": make_pipeline(ContactFrameSelector(n_between=3), DummyClassifier()),
             "blind": make_pipeline(ContactFrameSelector(threshold=1e6), DummyClassifier())}
    notes = _run(data, pipes, cv=3, verbose=0).notes
    assert len(notes) == 2 and notes[0].startswith("contact (frames, more_frames): found on")
    assert notes[1].startswith(f"contact (blind): found on 0 of {len(status)} presses (0 weak); no contact")

    result = _run(data, ["loading_compliance"], cv=3, verbose=0)
    rows = [np.column_stack([f, z]) for f, z in zip(data.force, data.position)]
    with pytest.warns(UserWarning, match="their figures are NaN"):
        missing = np.flatnonzero(np.isnan(LoadingCompliance().fit_transform(rows)).any(axis=1))
    assert 7 in missing
    assert result.notes == [f"loading phase (loading_compliance): found on {len(rows) - len(missing)} of "
                            f"{len(rows)} presses; none on {len(missing)} (no positive force, or fewer than 3 "
                            "frames from 0.1 of the peak force to the peak): their figures are NaN, for an "
                            "imputer in the pipeline to fill"]
    # pipelines without such steps have nothing to note
    assert _run(tiny, {"dummy": DummyClassifier()}, cv=3, verbose=0).notes == []


def test_flow_note_counts_the_corners_and_lost_tracks_of_every_press(tiny):
    # OpticalFlowFeatures' warnings (few corners, lost tracks) are silenced in the folds too; a blank
    # press has no corner at all, and its row is that of a press without motion
    import warnings

    from sklearn_hardness.features import OpticalFlowFeatures
    from sklearn_hardness.model_selection._per_press import split_per_press, transform_per_press
    from sklearn_hardness.preprocessing import ContactFrameSelector

    data = Bunch(**tiny)
    data.videos = [np.full_like(v, 128) if i == 3 else v for i, v in enumerate(tiny.videos)]
    flow = make_pipeline(ContactFrameSelector(frame_size=(32, 40)), OpticalFlowFeatures(n_features=30),
                         DummyClassifier())
    prefix, _ = split_per_press(flow)
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", UserWarning)
        frames = prefix[0].fit_transform(data.videos)
        tracks = OpticalFlowFeatures(n_features=30).fit(frames).track(frames)
        expected = prefix.fit_transform(data.videos)
    corners = tracks.n_corners
    lost = np.sum(tracks.valid[:, :, 0] & ~tracks.valid[:, :, -1], axis=1)
    assert corners[3] == 0 and corners.max() > 0 and lost.sum() > 0
    # the pass gives the pipeline's rows, and what each per-press step found on each press, in press order
    Xt, _, found = transform_per_press(prefix, data.videos, n_jobs=2)
    np.testing.assert_array_equal(Xt, expected)
    (selector, selected), (steps_flow, flowed) = found
    assert isinstance(selector, ContactFrameSelector) and isinstance(steps_flow, OpticalFlowFeatures)
    np.testing.assert_array_equal(flowed["n_corners"], corners)
    np.testing.assert_array_equal(flowed["n_lost"], lost)
    assert selected["status"][3] == "no contact" and len(selected["status"]) == len(corners)

    # another pass whose tracks are the same (fill_lost changes the rows, not the tracks) shares the line
    same_tracks = clone(flow).set_params(opticalflowfeatures__fill_lost="last")
    result = _run(data, {"flow": flow, "same_flow": same_tracks}, cv=3, verbose=0)
    n = len(corners)
    assert result.notes[1] == (
        f"optical flow (flow, same_flow): corners in a press's first frame {int(np.median(corners))} (median; "
        f"fewest 0, most {corners.max()}, at most n_features=30); none on {(corners == 0).sum()} of {n} presses: "
        f"their rows are those of a press without motion; {lost.sum() / corners.sum():.0%} of the tracks lost "
        f"before the last frame (on {(lost > 0).sum()} of {n} presses)")
    assert len(result.notes) == 2 and f"data: {result.notes[1]}" in str(result)


class _SlowDummy(DummyClassifier):
    """A most-frequent classifier whose fit takes ``seconds`` and leaves a file named by its process."""

    def __init__(self, log_dir=None, seconds=0.3):
        super().__init__(strategy="most_frequent")
        self.log_dir, self.seconds = log_dir, seconds

    def fit(self, X, y):
        import os
        import time
        import uuid
        from pathlib import Path

        time.sleep(self.seconds)
        if self.log_dir is not None:
            (Path(self.log_dir) / f"{os.getpid()}_{uuid.uuid4().hex}").touch()
        return super().fit(X, y)


def test_slow_fits_are_shared_among_the_workers(tiny, tmp_path):
    # 24 quick fits and 6 slow ones on 2 workers: joblib's automatic batching, timed on the quick ones, put
    # four of the six slow fits on one worker in each of three tries; one fit to a task shares them
    quick = {f"quick_{i}": DummyClassifier(strategy="prior") for i in range(3)}
    result = _run(tiny, {**quick, "slow": _SlowDummy(tmp_path)}, cv=3, n_repeats=2, n_jobs=2, verbose=0)
    assert _rows(result)["slow"]["error"] is None
    pids = [p.name.split("_")[0] for p in tmp_path.iterdir()]
    assert len(pids) == 6
    assert max(pids.count(p) for p in set(pids)) <= 3, pids


def test_seconds_left_times_each_pipeline_by_its_own_fits():
    from sklearn_hardness.model_selection._validation import _seconds_left

    # the baseline's 5 fits took 0.01 s each, the net's first of 5 took 70 s: 4 net fits of 70 s on 2 workers
    # (the mean over every finished fit would say 71 s / 6 fits x 4 fits left, under a minute)
    fits = {"peak_change": [0.01] * 5, "convlstm": [70.0]}
    assert _seconds_left(fits, 5, n_workers=2) == (pytest.approx(140.0), [])
    # one fit left: as long as that fit, however many workers
    assert _seconds_left({"convlstm": [70.0] * 4}, 5, n_workers=2) == (pytest.approx(70.0), [])
    # a pipeline with no finished fit has no time: it is named, not guessed
    fits = {"peak_change": [0.01] * 2, "convlstm": [], "ofnn": [3.0]}
    assert _seconds_left(fits, 5, n_workers=2) == (pytest.approx(0.03 / 2 + 12.0 / 2), ["convlstm"])
    assert _seconds_left({"a": [1.0] * 5, "b": []}, 5, n_workers=2) == (0.0, ["b"])


def test_progress_names_the_pipelines_not_timed_yet(tiny, capsys):
    import re

    _run(tiny, {"slow": _SlowDummy(None, seconds=0.0)}, cv=3, verbose=1, n_jobs=1)
    lines = [line for line in capsys.readouterr().err.splitlines() if " fits, " in line]
    # fold by fold: the baseline's first fit ends before any of slow's
    assert re.fullmatch(r"evaluate: 1/6 fits, \d+s elapsed, about \d+s left, not counting slow "
                        r"\(no fit finished yet\)", lines[0])
    assert all(line.endswith(" left") for line in lines[1:]) and len(lines) == 6


def test_evaluation_json_is_strict_json_where_a_fold_failed():
    from sklearn_hardness._cli._evaluate import _json_text

    text = _json_text({"fold_scores": {"ofnn": [0.5, float("nan")]}, "table": [{"ci": (float("inf"), 0.1)}]})
    assert "NaN" not in text and "Infinity" not in text
    assert json.loads(text, parse_constant=lambda c: pytest.fail(f"non-standard JSON {c}")) == {
        "fold_scores": {"ofnn": [0.5, None]}, "table": [{"ci": [None, 0.1]}]}


def test_contact_geometry_features_are_computed_once_per_press():
    """ContactGeometryFeatures learns nothing in fit: evaluate computes its rows once for all folds."""
    from sklearn_hardness.model_selection._per_press import split_per_press
    from sklearn_hardness.models import make_named_pipeline

    prefix, rest = split_per_press(make_named_pipeline("contact_geometry"))
    assert [name for name, _ in prefix.steps] == ["features"]
    assert [name for name, _ in rest.steps] == ["scale", "clf"]


def test_named_pipeline_memory_makes_a_second_fit_of_the_same_steps_a_cache_hit(tiny, tmp_path):
    from joblib import Memory

    from sklearn_hardness.features import ContactGeometryFeatures

    calls = []
    original = ContactGeometryFeatures._transform_presses

    def counting(self, X):
        calls.append(len(X))
        return original(self, X)

    pipe = make_named_pipeline("contact_geometry", memory=Memory(tmp_path, verbose=0))
    # the per-press feature step takes the memory (rows keyed by press); the Pipeline does not hash X
    assert pipe.named_steps["features"].memory is not None and pipe.memory is None
    with pytest.MonkeyPatch.context() as mp:
        mp.setattr(ContactGeometryFeatures, "_transform_presses", counting)
        first = clone(pipe).fit(tiny.videos, tiny.target).predict(tiny.videos[:4])
        n_first = len(calls)
        second = clone(pipe).fit(tiny.videos, tiny.target).predict(tiny.videos[:4])
    assert n_first >= 1 and len(calls) == n_first  # the second fit computed no feature row
    np.testing.assert_array_equal(first, second)


_READS = []


def _load_counted(key):
    _READS.append(key)
    return np.full((3, 4, 4, 3), key, np.uint8)


def test_a_lazy_video_sequence_hashes_by_its_keys_without_reading_a_frame():
    import joblib

    from sklearn_hardness.utils._lazy import LazyVideoSequence

    reads, load = _READS, _load_counted
    reads.clear()
    videos = LazyVideoSequence(load, [1, 2, 3], cache_size=2)
    videos[0]  # a cached frame does not change the hash
    h = joblib.hash(videos)
    assert reads == [1] and h == joblib.hash(LazyVideoSequence(load, [1, 2, 3], cache_size=2))
    assert joblib.hash(videos[[0, 1]]) != h and joblib.hash(videos[[0, 1, 2]]) == h


def test_params_route_the_training_folds_groups_to_an_inner_grid_search(tiny):
    """Nested selection: the inner GridSearchCV(cv=GroupKFold) sees only the training fold's groups."""
    from sklearn.linear_model import LogisticRegression
    from sklearn.model_selection import GridSearchCV, GroupKFold

    seen = []

    class _Recording(GroupKFold):
        def split(self, X, y=None, groups=None):
            seen.append(set(np.asarray(groups).tolist()))
            return super().split(X, y, groups)

    inner = GridSearchCV(make_pipeline(PeakContactChange(), LogisticRegression()),
                         {"logisticregression__C": [0.1, 1.0]}, cv=_Recording(n_splits=2))
    result = evaluate_pipelines({"grid": inner}, tiny.videos, tiny.target, groups=tiny.object_id, cv=3,
                                target_names=tiny.target_names, params={"grid": {"groups": tiny.object_id}},
                                error_score="raise", random_state=0)
    assert len(seen) == 3 and np.all(np.isfinite(_scores(result, "grid")))
    for test, groups in zip(_folds(result), seen):  # one inner search a fold, on its training objects alone
        train = np.setdiff1d(np.arange(len(tiny.target)), test)
        assert groups == set(tiny.object_id[train].tolist())
        assert not groups & set(tiny.object_id[test].tolist())


def test_evaluate_takes_any_splitter_and_returns_a_documented_result(tiny):
    from sklearn.model_selection import GroupKFold, KFold

    result = evaluate_pipelines({"dummy": DummyClassifier()}, tiny.videos, tiny.target, groups=tiny.object_id,
                                cv=GroupKFold(4))
    assert isinstance(result, EvaluationResult) and result.baseline == "peak_change"
    assert result.summary["pipeline"] == ["peak_change", "dummy"] and len(_scores(result, "dummy")) == 4
    assert set(result.summary) >= {"balanced_accuracy_low", "balanced_accuracy_vs_baseline_high"}
    assert "object-disjoint 4-fold CV" in str(result) and "dummy" in repr(result)
    pd = pytest.importorskip("pandas")
    frame = pd.DataFrame(result.cv_results_)  # as scikit-learn's results: the dict of arrays as it is
    assert len(frame) == 8 and frame.groupby("pipeline").size().to_dict() == {"dummy": 4, "peak_change": 4}
    assert isinstance(pd.DataFrame(result.summary).set_index("pipeline"), pd.DataFrame)
    with pytest.warns(UserWarning, match="both sides of a fold"):  # a splitter that ignores the groups
        evaluate_pipelines([], tiny.videos, tiny.target, groups=tiny.object_id, cv=KFold(3))
    # a registry name or a (name, estimator) pair as baseline; names as strings, encoded labels
    names = np.asarray(tiny.target_names)[tiny.target]
    pairs = evaluate_pipelines([("dummy", DummyClassifier())], tiny.videos, names, groups=tiny.object_id, cv=3,
                               baseline=("one", make_peak_change_baseline()))
    assert pairs.pipelines == ["one", "dummy"] and list(pairs.target_names) == sorted(set(names))


def test_family_groups_keep_the_per_object_figures_by_object(tiny):
    # two families a class, each of several objects: folds by family, figures per object
    rank = {}
    for c, o in zip(tiny.target, tiny.object_id):
        rank.setdefault(o, sum(1 for other in rank if tiny.target[tiny.object_id == other][0] == c))
    family = np.array([f"f{int(c)}-{rank[o] % 2}" for c, o in zip(tiny.target, tiny.object_id)])
    result = evaluate_pipelines({"dummy": DummyClassifier()}, tiny.videos, tiny.target, groups=family,
                                objects=tiny.object_id, cv=2, target_names=tiny.target_names)
    for test in _folds(result):
        train = np.setdiff1d(np.arange(len(tiny.target)), test)
        assert not set(family[test]) & set(family[train])
    assert np.array_equal(result.objects, tiny.object_id)  # per-object scoring by object, not by family
    assert "group-disjoint" in str(result)


def test_steps_that_differ_only_in_their_columns_share_one_pass():
    from sklearn_hardness.features import ContactProfileFeatures
    from sklearn_hardness.model_selection._per_press import _shared, prefix_key, split_per_press

    twelve, _ = split_per_press(make_contact_profile_pipeline())
    three, _ = split_per_press(make_contact_profile_pipeline(
        features=["log_contact_spread", "log_peak_change"], max_side=80))
    every, columns = _shared(three)
    assert columns == [11, 0] and prefix_key(every) == prefix_key(twelve)  # its order, from one shared pass
    assert three.steps[-1][1].features == ["log_contact_spread", "log_peak_change"]  # not modified in place
    assert _shared(twelve) == (twelve, None)
    # another max_side is another pass; a name the step refuses keeps its own pass, which fails as before
    other, _ = _shared(split_per_press(make_contact_profile_pipeline(features=["log_peak_change"],
                                                                     max_side=40))[0])
    assert prefix_key(other) != prefix_key(twelve)
    for features in (["no_such_feature"], ["log_peak_change"] * 2):
        refused = Pipeline([("features", ContactProfileFeatures(features=features))])
        assert _shared(refused) == (refused, None)


def test_a_feature_union_pipeline_gets_the_shared_pass_with_the_same_results(tiny, monkeypatch):
    """``make_contact_geometry_pipeline(with_profile=True)``: a FeatureUnion of two per-press steps."""
    from sklearn.model_selection import GroupKFold, cross_val_predict

    from sklearn_hardness.features import ContactGeometryFeatures
    from sklearn_hardness.models import make_contact_geometry_pipeline

    calls = []
    original = ContactGeometryFeatures._transform_presses

    def counting(self, X):
        calls.append(len(X))
        return original(self, X)

    monkeypatch.setattr(ContactGeometryFeatures, "_transform_presses", counting)
    union = make_contact_geometry_pipeline(with_profile=True)
    result = _run(tiny, {"union": union}, cv=GroupKFold(3), verbose=0)
    assert calls == [len(tiny.target)]  # one pass over every press for all three folds
    folds = [(np.asarray(train), np.asarray(test)) for train, test in
             GroupKFold(3).split(tiny.videos, tiny.target, tiny.object_id)]
    # scikit-learn's own cross-validation of the same pipeline (each fold fits and transforms its presses)
    expected = cross_val_predict(union, tiny.videos, tiny.target, cv=folds)
    np.testing.assert_array_equal(_oof(result, "union"), expected)


def test_confusion_matrices_display_normalises_and_passes_through_as_scikit_learn_does():
    import matplotlib.pyplot as plt
    from sklearn.metrics import ConfusionMatrixDisplay

    data = make_presses("everyday", n_per_class=2, n_objects=9, class_ratio=[1, 1, 1],
                        image_size=(32, 40), codec=None, random_state=0)
    result = _run(data, pipelines={"dummy": DummyClassifier(strategy="prior")}, cv=3, verbose=0)
    pred = _oof(result, "peak_change")
    for normalize in ("true", "pred", "all", None):
        display = ConfusionMatricesDisplay.from_result(result, normalize=normalize, cmap="Blues", colorbar=True,
                                                       im_kw={"interpolation": "nearest"},
                                                       text_kw={"fontsize": 7}, values_format=".1f")
        # scikit-learn's display of the same out-of-fold predictions, normalised where its matrix is made
        theirs = ConfusionMatrixDisplay.from_predictions(data.target, pred, labels=[0, 1, 2], normalize=normalize,
                                                         display_labels=data.target_names)
        panel = display.displays_["peak_change"]
        np.testing.assert_allclose(panel.confusion_matrix, theirs.confusion_matrix)
        assert panel.im_.get_cmap().name == "Blues" and panel.im_.get_interpolation() == "nearest"
        assert panel.text_[0, 0].get_fontsize() == 7 and panel.text_[0, 0].get_text() == format(
            panel.confusion_matrix[0, 0], ".1f")
        assert len(display.figure_.axes) == 4  # a colorbar beside each panel
        assert [t.get_text() for t in panel.ax_.get_xticklabels()] == list(data.target_names)
        plt.close("all")
    with pytest.raises(TypeError):  # keyword-only after the data, as scikit-learn's
        ConfusionMatricesDisplay({"a": np.eye(2, dtype=int)}, ["x", "y"])
    with pytest.raises(ValueError, match="normalize must be"):
        ConfusionMatricesDisplay.from_result(result, normalize="rows")
    counts = ConfusionMatricesDisplay({"a": np.array([[3, 1], [0, 4]])}).plot()
    assert counts.displays_["a"].text_[0, 0].get_text() == "3"  # counts in "d" format


def test_estimators_are_validated_the_same_whatever_n_jobs_as_cross_validate_does(tiny):
    """The estimators' own validation runs in every fit, in workers too; where every fit fails the call raises."""
    from sklearn.linear_model import LogisticRegression
    from sklearn.model_selection import GroupKFold, cross_validate

    X = _peak(tiny.videos)  # one number per press: a table a plain LogisticRegression takes
    for n_jobs in (None, 2):
        with pytest.raises(ValueError, match="All the 2 fits failed") as ours:
            evaluate_pipelines({"lr": LogisticRegression(max_iter=-5)}, X, tiny.target, groups=tiny.object_id,
                               cv=GroupKFold(2), baseline=None, n_jobs=n_jobs)
        with pytest.raises(ValueError, match="All the 2 fits failed") as theirs:
            cross_validate(LogisticRegression(max_iter=-5), X, tiny.target, groups=tiny.object_id,
                           cv=GroupKFold(2), n_jobs=n_jobs)
        for error in (ours.value, theirs.value):
            assert "The 'max_iter' parameter of LogisticRegression must be an int in the range [0, inf)" in str(error)


def test_cv_results_are_cross_validates_side_by_side(tiny):
    """Scores, indices, train scores and fitted estimators of one pipeline: those of cross_validate."""
    from sklearn.metrics import make_scorer, recall_score
    from sklearn.model_selection import GroupKFold, cross_validate

    pipe = make_contact_profile_pipeline()
    cv = GroupKFold(3)
    scoring = ["balanced_accuracy", "accuracy"]
    ours = evaluate_pipelines({"cp": pipe}, tiny.videos, tiny.target, groups=tiny.object_id, cv=cv, baseline=None,
                              scoring=scoring, return_train_score=True, return_estimator=True).cv_results_
    theirs = cross_validate(pipe, tiny.videos, tiny.target, groups=tiny.object_id, cv=cv, scoring=scoring,
                            return_train_score=True, return_estimator=True, return_indices=True)
    for key in ("test_balanced_accuracy", "test_accuracy", "train_balanced_accuracy", "train_accuracy"):
        np.testing.assert_allclose(ours[key], theirs[key])
    for which in ("train", "test"):
        for a, b in zip(ours[f"{which}_indices"], theirs["indices"][which]):
            np.testing.assert_array_equal(a, b)
    assert ours["fit_time"].shape == ours["score_time"].shape == theirs["fit_time"].shape == (3,)
    for a, b in zip(ours["estimator"], theirs["estimator"]):  # whole fitted pipelines: they predict new presses
        assert [n for n, _ in a.steps] == [n for n, _ in b.steps]
        np.testing.assert_array_equal(a.predict(tiny.videos[:6]), b.predict(tiny.videos[:6]))
    # a single scorer (a name or a callable) gives test_score; a dict its own names
    recall = make_scorer(recall_score, average="macro")
    single = evaluate_pipelines({"cp": pipe}, tiny.videos, tiny.target, groups=tiny.object_id, cv=cv,
                                baseline=None, scoring=recall)
    np.testing.assert_allclose(single.cv_results_["test_score"],
                               cross_validate(pipe, tiny.videos, tiny.target, groups=tiny.object_id, cv=cv,
                                              scoring=recall)["test_score"])
    assert "score [95% CI]" in str(single) and "test_balanced_accuracy" not in single.cv_results_
    named = evaluate_pipelines({"cp": pipe}, tiny.videos, tiny.target, groups=tiny.object_id, cv=cv,
                               scoring={"bal": "balanced_accuracy", "per_object": "object_balanced_accuracy"})
    np.testing.assert_allclose(fold_scores(named.cv_results_, "cp", "bal"), theirs["test_balanced_accuracy"])
    assert "test_per_object" in named.cv_results_ and named.summary["bal_vs_baseline"][1] == pytest.approx(
        np.mean(fold_scores(named.cv_results_, "cp", "bal") - fold_scores(named.cv_results_, "peak_change", "bal")))
    # an iterable of (train, test) pairs, as check_cv takes it, gives the same folds
    pairs = list(cv.split(tiny.videos, tiny.target, tiny.object_id))
    again = evaluate_pipelines({"cp": pipe}, tiny.videos, tiny.target, groups=tiny.object_id, cv=pairs,
                               baseline=None, scoring=scoring)
    np.testing.assert_allclose(again.cv_results_["test_accuracy"], theirs["test_accuracy"])
    with pytest.raises(ValueError, match="neg_hardness_mae.*needs hardness"):
        evaluate_pipelines({"cp": pipe}, tiny.videos, tiny.target, groups=tiny.object_id, cv=cv,
                           scoring=["neg_hardness_mae"])
    with pytest.raises(ValueError, match="not a valid scoring value"):
        evaluate_pipelines({"cp": pipe}, tiny.videos, tiny.target, groups=tiny.object_id, cv=cv, scoring="nope")


def test_default_scores_are_the_balanced_accuracy_per_press_and_per_object_and_the_mae(tiny):
    from sklearn.metrics import balanced_accuracy_score

    from sklearn_hardness.metrics import hardness_mae

    result = _run(tiny, {"dummy": DummyClassifier(strategy="stratified", random_state=0)}, cv=3, verbose=0)
    cv = result.cv_results_
    assert [k for k in cv if k.startswith("test_") and "_ind" not in k and "_pred" not in k] == [
        "test_balanced_accuracy", "test_object_balanced_accuracy", "test_neg_hardness_mae"]
    for i in range(len(cv["pipeline"])):
        y, pred = tiny.target[cv["test_indices"][i]], cv["test_predictions"][i]
        assert cv["test_balanced_accuracy"][i] == pytest.approx(balanced_accuracy_score(y, pred))
        assert cv["test_neg_hardness_mae"][i] == pytest.approx(-hardness_mae(y, pred, tiny.hardness))
    # the text gives the MAE as a positive error, as before
    mae = -np.mean(_scores(result, "dummy", "neg_hardness_mae"))
    line = next(line for line in str(result).splitlines() if line.startswith("dummy"))
    assert f" {mae:.2f} " in line
