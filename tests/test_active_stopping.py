"""The optional stopping rule of ActiveLearner: settled decision or press budget."""

import numpy as np
import pytest

from sklearn_hardness.active import ActiveLearner, PressOracle
from sklearn_hardness.utils._param_validation import InvalidParameterError

from ._active_net import CentroidMC, make_blobs, make_net


def _run(learner, oracle, X_test, n_per_query=3, max_iterations=8):
    """Algorithm 1 with the stop check: query, stop if told to, else teach."""
    for _ in range(max_iterations):
        idx, _ = learner.query(X_test)
        if learner.stop_reason_ is not None:
            break
        learner.teach(*oracle.press(learner.classes_[idx[0]], n_per_query))
    return learner


def _pool(separation, seed=0):
    X, y = make_blobs(n_per_class=40, spread=1.0, seed=seed)
    X = X * separation / 3.0  # centres at separation * e_c
    oracle = PressOracle(X, y, random_state=seed)
    X_test, _ = oracle.press(0, 5)  # the test object is object 0
    return oracle, X_test


def test_stops_early_on_an_easy_case_and_is_right():
    oracle, X_test = _pool(separation=6.0)
    learner = ActiveLearner(CentroidMC(), "variance", n_samples=20, stop_threshold=0.9,
                            stop_patience=2, max_presses=30, random_state=0)
    _run(learner.fit(*oracle.initial(3)), oracle, X_test)
    assert learner.stop_reason_ == "settled"
    # settled at the second query (patience 2): one teach, 3 presses instead of 8 x 3
    assert learner.stop_iteration_ == learner.n_iterations_ == 1 and learner.n_presses_ == 3
    queries = [h for h in learner.history_ if h["event"] == "query"]
    assert [h["stop"] for h in queries] == [None, "settled"]
    assert all(h["decision"] == 0 and h["confidence"] >= 0.9 for h in queries)


def test_hard_case_runs_to_the_budget_and_never_beyond():
    oracle, X_test = _pool(separation=0.3)  # the objects overlap: never sure
    learner = ActiveLearner(CentroidMC(), "entropy", n_samples=20, stop_threshold=0.9,
                            max_presses=9, random_state=0)
    _run(learner.fit(*oracle.initial(3)), oracle, X_test)
    assert learner.stop_reason_ == "budget"
    assert learner.n_presses_ == 9 and learner.n_iterations_ == 3
    assert max(h["confidence"] for h in learner.history_ if h["event"] == "query") < 0.9
    size = len(learner.reservoir_y_)
    with pytest.raises(ValueError, match=r"exceed the press budget max_presses=9 \(9 used\)"):
        learner.teach(*oracle.press(1, 1))
    assert len(learner.reservoir_y_) == size and learner.n_presses_ == 9


def test_budget_counts_presses_not_teaches():
    oracle, X_test = _pool(separation=0.3)
    learner = ActiveLearner(CentroidMC(), max_presses=5, random_state=0).fit(*oracle.initial(2))
    learner.teach(*oracle.press(1, 4))
    with pytest.raises(ValueError, match="teaching 2 presses would exceed"):
        learner.teach(*oracle.press(1, 2))
    learner.teach(*oracle.press(2, 1))
    learner.query(X_test)
    assert learner.stop_reason_ == "budget" and learner.stop_iteration_ == 2


def test_patience_waits_for_an_unchanged_decision():
    oracle, X_test = _pool(separation=6.0)
    learner = ActiveLearner(CentroidMC(), n_samples=20, stop_threshold=0.9, stop_patience=3,
                            random_state=0).fit(*oracle.initial(3))
    X_other, _ = oracle.press(2, 5)  # presses that the model decides as object 2
    learner.query(X_test)
    learner.query(X_other)  # the decision changes: the count starts again
    learner.query(X_test)
    learner.query(X_test)
    assert learner.stop_reason_ is None
    learner.query(X_test)
    assert learner.stop_reason_ == "settled"
    assert [h["decision"] for h in learner.history_ if h["event"] == "query"] == [0, 2, 0, 0, 0]


def test_default_off_and_the_rule_changes_no_query():
    """Algorithm 1 is unchanged: without the rule nothing stops, and with a rule
    that never fires every query, score and training step is the same."""
    X, y = make_blobs(n_per_class=30, spread=1.5, seed=3)

    def run(**stop):
        oracle = PressOracle(X, y, random_state=0)
        X_test, _ = oracle.press(1, 4)
        learner = ActiveLearner(make_net(), "variance", initial_epochs=3, epochs_per_query=2,
                                max_reservoir=12, n_samples=6, random_state=0, **stop)
        learner.fit(*oracle.initial(3))
        return _run(learner, oracle, X_test, max_iterations=4)

    off = run()
    assert off.stop_reason_ is None and off.n_iterations_ == 4
    assert all(h["stop"] is None for h in off.history_ if h["event"] == "query")
    never = run(stop_threshold=1.0, stop_patience=5, max_presses=100)
    assert never.stop_reason_ is None
    for a, b in zip(off.history_, never.history_):
        if a["event"] == "query":
            np.testing.assert_array_equal(a["queried"], b["queried"])
            np.testing.assert_allclose(a["scores"], b["scores"])
        else:
            assert a["train_loss"] == b["train_loss"]


@pytest.mark.parametrize(
    "param, value",
    [("stop_threshold", 0.0), ("stop_threshold", 1.5), ("stop_threshold", "high"),
     ("stop_patience", 0), ("stop_patience", None), ("max_presses", 0), ("max_presses", 2.5)],
)
def test_bad_stopping_params(param, value):
    X, y = make_blobs(n_per_class=3, seed=0)
    with pytest.raises(InvalidParameterError, match=f"'{param}' parameter of ActiveLearner"):
        ActiveLearner(CentroidMC(), **{param: value}).fit(X, y)
