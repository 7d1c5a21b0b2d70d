"""Tests of LoadingCompliance and make_loading_compliance_pipeline (force and position per frame)."""

import pickle
import warnings

import numpy as np
import pytest
from sklearn.base import clone
from sklearn.model_selection import GroupKFold, cross_val_score

from sklearn_hardness.datasets import make_presses
from sklearn_hardness.features import LoadingCompliance
from sklearn_hardness.models import make_loading_compliance_pipeline
from sklearn_hardness.models._pipelines import _log_positive

from ._synthetic import hertz_press

#: Hertz compliance (mm per N^(2/3)) of the three classes: hard, moderate, soft.
COMPLIANCE = np.array([0.5, 1.0, 2.0])


def presses(n, forces, seed=0, spread=0.1):
    """``n`` presses, classes cycling hard-moderate-soft, peak force ~ U[forces], compliance spread ~ 10%."""
    rng = np.random.default_rng(seed)
    y = np.arange(n) % 3
    X = [hertz_press(COMPLIANCE[k] * np.exp(spread * rng.standard_normal()), rng.uniform(*forces),
                     n_load=int(rng.integers(8, 30)), offset=rng.uniform(-5, 5), c_drive=0.05)
         for k in y]
    return X, y


def test_recovers_the_hertz_compliance_of_a_noise_free_press():
    X = [hertz_press(c, f) for c, f in [(0.5, 3.0), (2.0, 3.0), (1.0, 25.0)]]
    F = LoadingCompliance().fit_transform(X)
    np.testing.assert_allclose(F[:, 0], [0.5, 2.0, 1.0], rtol=1e-10)
    np.testing.assert_allclose(F[:, 3], [3.0, 3.0, 25.0])
    # travel: from the first frame above 10% of the peak force to the peak
    for row, press in zip(F, X):
        force, pos = press[:, 0], press[:, 1]
        start, peak = np.argmax(force > 0.1 * force.max()), np.argmax(force)
        assert row[2] == pytest.approx(pos[peak] - pos[start])


def test_hertz_compliance_does_not_depend_on_the_force_reached_but_the_linear_slope_does():
    """The reason it is the default: one object pushed to 2 N and to 25 N."""
    light, firm = LoadingCompliance().fit_transform([hertz_press(1.0, 2.0), hertz_press(1.0, 25.0)])
    assert light[0] == pytest.approx(firm[0], rel=1e-10)
    assert firm[1] < 0.5 * light[1]  # the linear compliance stiffens with force: (25/2)^(-1/3) = 0.43


def test_a_drive_spring_and_an_offset_add_nothing_to_the_hertz_compliance():
    base = LoadingCompliance(features=["hertz_compliance"]).fit_transform([hertz_press(1.0, 4.0)])
    shifted = LoadingCompliance(features=["hertz_compliance"]).fit_transform([hertz_press(1.0, 4.0, offset=-40.0)])
    np.testing.assert_allclose(shifted, base, rtol=1e-10)
    stiff_drive, soft_drive = LoadingCompliance(features=["linear_compliance"]).fit_transform(
        [hertz_press(1.0, 4.0, c_drive=0.0), hertz_press(1.0, 4.0, c_drive=0.2)])
    assert soft_drive[0] == pytest.approx(stiff_drive[0] + 0.2, rel=0.05)


def test_features_select_and_order_the_output_columns():
    X = [hertz_press(1.0, 4.0)]
    full = LoadingCompliance().fit(X)
    assert full.get_feature_names_out().tolist() == ["hertz_compliance", "linear_compliance", "travel",
                                                     "peak_force"]
    two = LoadingCompliance(features=("peak_force", "hertz_compliance")).fit(X)
    assert two.get_feature_names_out().tolist() == ["peak_force", "hertz_compliance"]
    np.testing.assert_array_equal(two.transform(X), full.transform(X)[:, [3, 0]])
    assert two.n_features_out_ == 2


def test_a_short_loading_phase_gives_nan_with_a_warning_that_names_the_press():
    X = [hertz_press(1.0, 4.0), hertz_press(1.0, 4.0, n_load=1), np.zeros((5, 2))]
    est = LoadingCompliance().fit(X)
    with pytest.warns(UserWarning, match=r"2 of 3 presses \(X\[1, 2\]\)"):
        F = est.transform(X)
    assert np.isfinite(F[0]).all()
    assert np.isnan(F[1, :2]).all() and F[1, 3] == 4.0  # one loading frame: no slope, but a peak
    assert np.isnan(F[2, :3]).all() and F[2, 3] == 0.0  # no force at all


@pytest.mark.parametrize("X, error, match", [
    ("presses", TypeError, "sequence of \\(T, 2\\) arrays"),
    (None, TypeError, "sequence of \\(T, 2\\) arrays"),
    (np.zeros((10, 2)), ValueError, "For one press, pass \\[press\\]"),
    ([], ValueError, "no presses"),
    ([np.zeros((10, 2)), np.zeros((10, 3))], ValueError, "X\\[1\\] must have shape \\(T, 2\\)"),
    ([np.zeros((0, 2))], ValueError, "X\\[0\\] must have shape"),
    ([np.array([[0.0, 1.0], [np.nan, 2.0]])], ValueError, "X\\[0\\] has values that are not finite"),
    ([np.array([["a", "b"]])], TypeError, "X\\[0\\] must be numeric"),
])
def test_bad_input_is_an_error_that_names_it(X, error, match):
    with pytest.raises(error, match=match):
        LoadingCompliance().fit(X)


@pytest.mark.parametrize("params, match", [
    (dict(features=["hertz_compliance", "stiffness"]), "unknown \\['stiffness'\\]"),
    (dict(features=[]), "got none"),
    (dict(features=["travel", "travel"]), "got \\[.travel.\\] more than once"),
    (dict(onset=1.0), "onset"),
    (dict(min_loading_frames=1), "min_loading_frames"),
    (dict(drive_compliance=-0.1), "drive_compliance"),
])
def test_bad_parameters_are_errors_at_fit(params, match):
    est = LoadingCompliance(**params)  # __init__ only stores
    with pytest.raises(ValueError, match=match):
        est.fit([hertz_press(1.0, 4.0)])


def test_the_log_step_keeps_nan_for_the_imputer():
    out = _log_positive(np.array([[np.nan], [0.0], [-1.0], [np.e]]))
    assert np.isnan(out[0, 0])
    np.testing.assert_allclose(out[1:, 0], [np.log(1e-3), np.log(1e-3), 1.0])


def test_trained_at_a_few_newtons_the_pipeline_classifies_grasps_of_tens_of_newtons():
    """The effect of the Hertz compliance: the force scale of training need not be the user's."""
    X_train, y_train = presses(60, forces=(1.0, 6.0), seed=0)
    X_test, y_test = presses(30, forces=(20.0, 25.0), seed=1)
    hertz = make_loading_compliance_pipeline().fit(X_train, y_train)
    assert (hertz.predict(X_test) == y_test).mean() >= 0.9
    linear = make_loading_compliance_pipeline(features=["linear_compliance"]).fit(X_train, y_train)
    assert (linear.predict(X_test) == y_test).mean() <= 0.7  # stiffer at 25 N: softer classes read harder
    assert (linear.predict(X_test) <= y_test).all()


def test_short_presses_are_imputed_and_leave_the_others_classified():
    X, y = presses(60, forces=(1.0, 6.0), seed=0)
    X = list(X)
    for i in range(0, 60, 10):  # one press in ten cut to a single loading frame
        X[i] = hertz_press(COMPLIANCE[y[i]], 4.0, n_load=1)
    pipe = make_loading_compliance_pipeline()
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", UserWarning)
        pipe.fit(X, y)
        pred = pipe.predict(X)
    full = np.ones(60, bool)
    full[::10] = False
    assert (pred[full] == y[full]).mean() >= 0.95


def test_pipeline_gives_posterior_samples_and_pickles():
    X, y = presses(30, forces=(1.0, 6.0))
    pipe = make_loading_compliance_pipeline(C=0.5).fit(X, y)
    assert [name for name, _ in pipe.steps] == ["features", "log", "impute", "scale", "clf"]
    samples = pipe.predict_proba_samples(X[:4], n_samples=7, random_state=0)
    assert samples.shape == (7, 4, 3)
    np.testing.assert_allclose(samples.sum(axis=-1), 1.0)
    np.testing.assert_allclose(pickle.loads(pickle.dumps(pipe)).predict_proba(X), pipe.predict_proba(X))
    assert clone(pipe).get_params()["clf__C"] == 0.5
    assert make_loading_compliance_pipeline(drive_compliance=0.3).get_params()["features__drive_compliance"] == 0.3
    with pytest.raises(TypeError, match="max_epochs"):
        make_loading_compliance_pipeline(max_epochs=5)


def test_on_simulated_presses_of_new_objects_it_beats_the_peak_force_alone():
    """Object-disjoint on the ``everyday`` preset (its force and the sensor's position; videos unused)."""
    data = make_presses("everyday", random_state=0)
    X = [np.column_stack([f, z]) for f, z in zip(data.force, data.position)]
    cv = GroupKFold(5)
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", UserWarning)  # the preset's cut-short videos
        scores = {
            name: cross_val_score(make_loading_compliance_pipeline(features=[name]), X, data.target,
                                  groups=data.object_id, cv=cv, scoring="balanced_accuracy").mean()
            for name in ("hertz_compliance", "peak_force")
        }
    assert scores["hertz_compliance"] >= 0.75
    assert scores["hertz_compliance"] >= scores["peak_force"] + 0.25


def test_drive_compliance_takes_a_commanded_positions_give_off():
    """An impedance controller's setpoint runs ahead of the sensor by c_drive F; given it, the fit is exact again."""
    commanded = [hertz_press(1.0, f, c_drive=0.3) for f in (2.0, 25.0)]
    raw = LoadingCompliance(features=["hertz_compliance"]).fit_transform(commanded)[:, 0]
    assert raw[1] > raw[0] + 0.3  # left in, the drive's give reads as a softer object at higher force
    fixed = LoadingCompliance(features=["hertz_compliance"], drive_compliance=0.3).fit_transform(commanded)[:, 0]
    np.testing.assert_allclose(fixed, [1.0, 1.0], rtol=1e-10)


def test_trained_on_the_simulator_it_classifies_presses_pushed_four_times_harder():
    """The simulator's own check of the force-scale argument: everyday at 1-6 N against 15-25 N."""
    from sklearn.metrics import balanced_accuracy_score

    def force_position(data):
        return [np.column_stack([f, z]) for f, z in zip(data.force, data.position)]

    train = make_presses("everyday", random_state=0)
    firm = make_presses("everyday", random_state=1, force_range=(15.0, 25.0))
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", UserWarning)
        scores = {name: balanced_accuracy_score(
            firm.target,
            make_loading_compliance_pipeline(features=[name]).fit(force_position(train), train.target)
            .predict(force_position(firm)))
            for name in ("hertz_compliance", "linear_compliance")}
    assert scores["hertz_compliance"] >= 0.85
    assert scores["hertz_compliance"] >= scores["linear_compliance"] + 0.08


def test_active_sampling_runs_on_force_and_position_and_its_uncertainty_shrinks_with_presses():
    """What predict_proba_samples is for: ActiveLearner queries and learns on (T, 2) presses."""
    from sklearn_hardness.active import ActiveLearner

    X, y = presses(90, forces=(1.0, 6.0), seed=2, spread=0.3)
    X_test, _ = presses(12, forces=(1.0, 6.0), seed=3, spread=0.3)
    learner = ActiveLearner(make_loading_compliance_pipeline(), n_samples=200, random_state=0)
    learner.fit(X[:6], y[:6])

    def spread():
        return learner.predict_proba_samples(X_test, n_samples=200, random_state=0).std(axis=0).mean()

    query, uncertainty = learner.query(X_test)
    assert query.shape == (1,) and 0 <= query[0] < 3 and uncertainty.shape == (3,)
    before = spread()
    learner.teach(X[6:], y[6:])
    assert spread() < 0.5 * before  # 15x the presses: the posterior narrows
    assert (learner.predict(X[6:]) == y[6:]).mean() >= 0.7  # classes overlap (30% spread): about 0.8 at best


def test_a_recording_against_the_input_conventions_is_warned_about():
    # a flipped force sign, a position that falls (a gripper's width) or one in metres makes every press
    # alike after the log floor: the warning says what to fix, where most presses break the convention
    from sklearn_hardness.features import ConventionWarning

    presses = [hertz_press(c, 5.0) for c in np.linspace(0.2, 1.5, 12)]
    with warnings.catch_warnings():
        warnings.simplefilter("error", ConventionWarning)
        LoadingCompliance().fit_transform(presses)  # the conventions: no warning
        # one rigid press fitting a compliance below zero is no recording to fix
        LoadingCompliance().fit_transform(presses[1:] + [np.column_stack([presses[0][:, 0], -presses[0][:, 1]])])
    cases = {
        "force mostly below zero: a compressive force must be positive":
            [np.column_stack([-p[:, 0], p[:, 1]]) for p in presses],
        "the position falls as the force rises": [np.column_stack([p[:, 0], -p[:, 1]]) for p in presses],
        "is the position in metres": [np.column_stack([p[:, 0], p[:, 1] / 1000]) for p in presses[:6]],
    }
    for message, flipped in cases.items():
        with pytest.warns(ConventionWarning, match=message):
            LoadingCompliance().fit_transform(flipped)
