"""make_contact_profile_pipeline and ContactProfileNNClassifier (issue 20).

The features of the loading phase with an MC-dropout head: the pipeline must
separate what the one-number baseline cannot, give Monte-Carlo samples for
active sampling, and run under its name in ``evaluate``.
"""

import numpy as np
import pytest
from sklearn.base import clone
from sklearn.linear_model import LogisticRegression
from sklearn.model_selection import StratifiedKFold, cross_val_score

from sklearn_hardness.model_selection import evaluate_pipelines
from sklearn_hardness.models import (
    ContactProfileNNClassifier,
    LaplaceLogisticRegression,
    MCDropoutPipeline,
    make_contact_profile_pipeline,
    make_peak_change_baseline,
)

from ._synthetic import growing_disc_press


def _press(rise, radius, rng):
    return growing_disc_press(rise, radius, rng, n=50, start=12)


@pytest.fixture(scope="module")
def slow_and_fast():
    """Soft presses load slowly, hard ones fast, at the same peak change (what one number cannot see)."""
    rng = np.random.default_rng(1)
    X, y = [], []
    for i in range(36):
        soft = i % 2
        X.append(_press(int(rng.integers(25, 36)) if soft else int(rng.integers(2, 6)),
                        float(rng.uniform(5, 9)), rng))
        y.append(soft)
    return X, np.array(y)


def test_nn_head_separates_what_the_peak_change_cannot(slow_and_fast):
    X, y = slow_and_fast
    cv = StratifiedKFold(3, shuffle=True, random_state=0)
    pipe = make_contact_profile_pipeline(head="nn", random_state=0)
    assert isinstance(pipe, MCDropoutPipeline)
    assert isinstance(pipe.named_steps["clf"], ContactProfileNNClassifier)
    assert pipe.named_steps["clf"].class_weight == "balanced"
    assert cross_val_score(pipe, X, y, cv=cv).mean() >= 0.9
    assert cross_val_score(make_contact_profile_pipeline(head="logistic"), X, y, cv=cv).mean() >= 0.9
    assert cross_val_score(make_peak_change_baseline(), X, y, cv=cv).mean() <= 0.75


def test_both_heads_give_samples_mc_dropout_and_laplace(slow_and_fast):
    X, y = slow_and_fast
    pipe = make_contact_profile_pipeline(head="nn", random_state=0).fit(X, y)
    samples = pipe.predict_proba_samples(X[:6], n_samples=20, random_state=0)
    assert samples.shape == (20, 6, 2)
    np.testing.assert_allclose(samples.sum(axis=-1), 1.0, rtol=1e-5)
    assert samples.std(axis=0).max() > 1e-3  # dropout is on: the passes differ
    np.testing.assert_allclose(pipe.predict_proba_samples(X[:6], n_samples=20, random_state=0), samples)
    logistic = make_contact_profile_pipeline(head="logistic").fit(X, y)
    clf = logistic.named_steps["clf"]
    assert isinstance(clf, LaplaceLogisticRegression) and isinstance(clf, LogisticRegression)
    assert (clf.max_iter, clf.class_weight) == (2000, "balanced")
    # the fit is scikit-learn's: the same probabilities as a plain LogisticRegression
    plain = make_contact_profile_pipeline(head="logistic")
    plain.steps[-1] = ("clf", LogisticRegression(max_iter=2000, class_weight="balanced"))
    np.testing.assert_allclose(logistic.predict_proba(X), plain.fit(X, y).predict_proba(X))
    laplace = logistic.predict_proba_samples(X[:6], n_samples=20, random_state=0)
    assert laplace.shape == (20, 6, 2) and laplace.std(axis=0).max() > 1e-3


def test_parameters_reach_their_steps_and_clone():
    pipe = make_contact_profile_pipeline(head="nn", max_side=40, hidden_units=8, dropout=0.5, class_weight=None)
    assert pipe.named_steps["features"].max_side == 40
    clf = pipe.named_steps["clf"]
    assert (clf.hidden_units, clf.dropout, clf.class_weight) == (8, 0.5, None)
    assert clone(pipe).get_params()["clf__hidden_units"] == 8
    defaults = ContactProfileNNClassifier()
    assert (defaults.hidden_units, defaults.lr, defaults.max_epochs) == (64, 3e-3, 100)
    with pytest.raises(ValueError, match="head must be 'logistic' or 'nn'"):
        make_contact_profile_pipeline(head="svm")


def test_default_head_is_the_logistic_one_and_misplaced_parameters_are_named():
    """The default is the head measured on real recordings; a parameter of the other head gets a clear error."""
    pipe = make_contact_profile_pipeline(C=0.5, random_state=0)
    assert isinstance(pipe.named_steps["clf"], LaplaceLogisticRegression)
    assert (pipe.named_steps["clf"].C, pipe.named_steps["clf"].class_weight) == (0.5, "balanced")
    assert pipe.get_params()["clf__C"] == 0.5
    with pytest.raises(TypeError, match=r"head='logistic' .* \['max_epochs'\]; \['max_epochs'\] belong to head='nn'"):
        make_contact_profile_pipeline(max_epochs=20)
    with pytest.raises(TypeError, match=r"head='nn' .* \['C'\]; \['C'\] belong to head='logistic'"):
        make_contact_profile_pipeline(head="nn", C=1.0)
    with pytest.raises(TypeError, match=r"takes no parameter\(s\) \['hidden_unit'\]\.$"):
        make_contact_profile_pipeline(head="nn", hidden_unit=8)
    # skorch's routed parameters pass through to the net, which checks them itself
    net = make_contact_profile_pipeline(head="nn", optimizer__weight_decay=1e-3).named_steps["clf"]
    assert net.optimizer__weight_decay == 1e-3


@pytest.mark.slow
def test_contact_profile_nn_runs_by_name_in_evaluate():
    from sklearn_hardness.datasets import make_presses

    d = make_presses("everyday", n_per_class=2, n_objects=9, class_ratio=[1, 1, 1], image_size=(32, 40),
                     codec=None, random_state=0)
    result = evaluate_pipelines(["contact_profile", "contact_profile_nn"], d.videos, d.target, groups=d.object_id,
                                cv=3, target_names=d.target_names, error_score="raise", random_state=0)
    assert result.pipelines == ["peak_change", "contact_profile", "contact_profile_nn"]
    assert np.all(np.isfinite(result.summary["balanced_accuracy"]))
    assert (result.out_of_fold_predictions("contact_profile_nn") >= 0).all()
    # the longer name keeps the table's columns: accuracies start in one column
    names = result.pipelines
    lines = str(result).splitlines()
    first = next(i for i, line in enumerate(lines) if line.split(" ")[0] == names[0])
    rows = lines[first:first + len(names)]
    assert [row.split(" ")[0] for row in rows] == names
    assert len({row.index(" 0.") if " 0." in row else row.index(" 1.") for row in rows}) == 1


@pytest.mark.parametrize("head, n_per_object, learner_params", [
    # the presses differ only in loading speed: the other features are standardised pixel noise, and 9
    # presses are one Adam step per epoch; 60 steps train the head on any of seeds 0-3 (30 did on two)
    ("nn", 12, {"initial_epochs": 60, "epochs_per_query": 10}),
    # refitted per query; its queries read the samples of its Laplace posterior
    ("logistic", 12, {}),
])
def test_active_learner_runs_on_the_pipeline_from_videos(head, n_per_object, learner_params):
    """Active sampling (Algorithm 1) with the contact-profile pipeline: videos in, a right decision out.

    12 presses per object leave 5 of the test object's speed after its 4 test and 3 initial presses:
    enough for both queries to ask for it. Which objects they ask for depends on the CPU's floats (with
    10, a float path without AVX asked for the test object's speed twice, which 3 presses left could not
    hold), so the pool holds any choice.
    """
    from sklearn_hardness.active import ActiveLearner, PressOracle

    rng = np.random.default_rng(0)
    y = np.repeat([0, 1, 2], n_per_object)  # three loading speeds
    X = np.stack([growing_disc_press([3, 15, 30][c], 7, rng, n=45, start=10) for c in y])
    oracle = PressOracle(X, y, random_state=0)
    X_test, y_test = oracle.press(2, 4)
    pipe = make_contact_profile_pipeline(head=head, random_state=0)
    learner = ActiveLearner(pipe, "entropy", n_samples=8, random_state=0, **learner_params)
    learner.fit(*oracle.initial(3))
    for _ in range(2):
        idx, scores = learner.query(X_test)
        assert scores.shape == (3,) and np.ptp(scores) > 0  # the samples tell the objects apart
        learner.teach(*oracle.press(learner.classes_[idx[0]], 2))
    assert learner.n_presses_ == 4
    assert learner.score(X_test, y_test) == 1.0
