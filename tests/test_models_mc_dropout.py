"""Behaviour shared by the three MC-dropout classifiers."""

import pickle

import numpy as np
import pytest
import torch
from sklearn.base import clone
from sklearn.exceptions import NotFittedError

from sklearn_hardness.models import ConvLSTMClassifier, DINOv2NNClassifier, OFNNClassifier
from sklearn_hardness.models._mc_sampling import MCDropout
from sklearn_hardness.utils._param_validation import InvalidParameterError
from tests._threads import torch_threads


def _data(kind, n=20, seed=0):
    rng = np.random.default_rng(seed)
    y = np.arange(n) % 3
    if kind == "frames":
        X = rng.normal(scale=0.3, size=(n, 3, 8, 10, 3)).astype(np.float32)
        X += 0.3 * y[:, None, None, None, None]
    else:
        X = rng.normal(size=(n, 12)).astype(np.float32)
        X[:, 0] += 2 * y
    return X, y


CASES = {
    "ofnn": (OFNNClassifier, "features", dict(max_epochs=5)),
    "dinov2nn": (DINOv2NNClassifier, "features", dict(max_epochs=5)),
    "convlstm": (ConvLSTMClassifier, "frames", dict(max_epochs=3)),
}


# These nets are tiny: one thread is fastest, and much faster than two on a busy machine.
pytestmark = pytest.mark.torch_threads(1)


@pytest.fixture(params=list(CASES), scope="module")
def case(request):
    cls, kind, kw = CASES[request.param]
    X, y = _data(kind)
    with torch_threads(1):
        net = cls(random_state=0, **kw).fit(X, y)
    return cls, kind, kw, X, y, net


def test_shapes_and_probabilities(case):
    cls, kind, kw, X, y, net = case
    proba = net.predict_proba(X)
    assert proba.shape == (len(X), 3) and proba.dtype == np.float32
    np.testing.assert_allclose(proba.sum(1), 1, atol=1e-5)
    samples = net.predict_proba_samples(X[:5], n_samples=7, random_state=0)
    assert samples.shape == (7, 5, 3) and samples.dtype == np.float32
    np.testing.assert_allclose(samples.sum(-1), 1, atol=1e-5)
    assert np.all(samples >= 0)
    assert set(net.predict(X)) <= set(y)
    assert np.isfinite(net.final_train_loss_)


def test_variance_positive_with_dropout_and_zero_without(case):
    cls, kind, kw, X, y, net = case
    samples = net.predict_proba_samples(X[:6], n_samples=20, random_state=0)
    assert samples.var(axis=0).max() > 1e-12
    # different replicas of the same input differ (independent masks)
    assert not np.array_equal(samples[0], samples[1])
    assert np.all(samples.var(axis=0).max(axis=-1) > 0)  # every input varies
    net0 = cls(dropout=0.0, random_state=0, **kw).fit(X, y)
    samples0 = net0.predict_proba_samples(X[:6], n_samples=5, random_state=0)
    assert np.ptp(samples0, axis=0).max() == 0.0  # identical passes: zero variance
    np.testing.assert_allclose(samples0[0], net0.predict_proba(X[:6]), atol=1e-6)


def test_state_unchanged_by_mc_sampling(case):
    cls, kind, kw, X, y, net = case
    module = net.module_
    # an unusual mix of modes must survive as it is
    module.train()
    first_dropout = next(m for m in module.modules() if isinstance(m, MCDropout))
    first_dropout.eval()
    flags = [m.training for m in module.modules()]
    params = {k: v.clone() for k, v in module.state_dict().items()}
    rng_state = torch.get_rng_state()
    net.predict_proba_samples(X[:4], n_samples=5, random_state=1)
    assert [m.training for m in module.modules()] == flags
    for k, v in module.state_dict().items():
        assert torch.equal(v, params[k]), k
    assert torch.equal(torch.get_rng_state(), rng_state)
    assert all(m.generator is None for m in module.modules() if isinstance(m, MCDropout))
    module.eval()


def test_predict_proba_deterministic_and_seeded_samples(case):
    cls, kind, kw, X, y, net = case
    net.module_.train()  # predict_proba switches dropout off itself
    np.testing.assert_array_equal(net.predict_proba(X), net.predict_proba(X))
    a = net.predict_proba_samples(X[:5], n_samples=6, random_state=3)
    b = net.predict_proba_samples(X[:5], n_samples=6, random_state=3)
    c = net.predict_proba_samples(X[:5], n_samples=6, random_state=4)
    np.testing.assert_array_equal(a, b)
    assert not np.array_equal(a, c)


def test_chunking_gives_same_result_without_dropout(case):
    cls, kind, kw, X, y, net = case
    net.set_params(dropout=0.0)  # changes the live dropout layers of the fitted net
    try:
        full = net.predict_proba_samples(X, n_samples=4, random_state=0)
        chunked = net.predict_proba_samples(X, n_samples=4, random_state=0, batch_size=3)
        np.testing.assert_allclose(full, chunked, atol=1e-6)
        np.testing.assert_allclose(full[2], net.predict_proba(X), atol=1e-6)
    finally:
        net.set_params(dropout=0.2)
    chunked = net.predict_proba_samples(X[:5], n_samples=9, random_state=0, batch_size=4)
    assert chunked.shape == (9, 5, 3)
    assert chunked.var(axis=0).max() > 0


def test_bad_dropout_via_set_params_is_reported_at_use_not_stored_in_the_module(case):
    # sklearn convention: set_params never raises; the value is checked where it is used.
    from sklearn_hardness.models._mc_sampling import MCDropout
    from sklearn_hardness.utils._param_validation import InvalidParameterError

    cls, kind, kw, X, y, net = case
    before = [m.p for m in net.module_.modules() if isinstance(m, MCDropout)]
    net.set_params(dropout=1.5)
    try:
        assert [m.p for m in net.module_.modules() if isinstance(m, MCDropout)] == before
        with pytest.raises(InvalidParameterError, match="'dropout' parameter"):
            net.predict_proba_samples(X[:2], n_samples=2, random_state=0)
    finally:
        net.set_params(dropout=0.2)
    assert net.predict_proba_samples(X[:2], n_samples=2, random_state=0).shape == (2, 2, 3)


def test_seeded_fit_is_reproducible_and_leaves_global_rng(case):
    cls, kind, kw, X, y, net = case
    rng_state = torch.get_rng_state()
    other = cls(random_state=0, **kw).fit(X, y)
    assert torch.equal(torch.get_rng_state(), rng_state)
    np.testing.assert_array_equal(other.predict_proba(X), net.predict_proba(X))
    assert other.history[:, "train_loss"] == net.history[:, "train_loss"]
    different = cls(random_state=1, **kw).fit(X, y)
    assert not np.array_equal(different.predict_proba(X), net.predict_proba(X))


def test_clone_and_pickle_round_trip(case):
    cls, kind, kw, X, y, net = case
    unfitted = clone(net)
    assert unfitted.get_params()["dropout"] == net.dropout
    assert not unfitted.initialized_
    restored = pickle.loads(pickle.dumps(net))
    np.testing.assert_array_equal(restored.predict_proba(X), net.predict_proba(X))
    np.testing.assert_array_equal(
        restored.predict_proba_samples(X[:3], n_samples=4, random_state=0),
        net.predict_proba_samples(X[:3], n_samples=4, random_state=0),
    )
    np.testing.assert_array_equal(restored.classes_, net.classes_)


def test_pickle_holds_no_torch_generator_and_training_continues_alike(case):
    # a torch.Generator of a CUDA device cannot be unpickled where torch has no CUDA;
    # the seeded generators travel as (device type, seed, state) and are rebuilt on load
    cls, kind, kw, X, y, net = case
    state = net.__getstate__()
    for name in ("shuffle_generator_", "dropout_generator_"):
        assert not isinstance(state[name], torch.Generator)
    restored = pickle.loads(pickle.dumps(net))
    assert isinstance(restored.dropout_generator_, torch.Generator)
    twin = pickle.loads(pickle.dumps(net))
    # generator states restored exactly: both continue training with the same masks and batches
    restored.partial_fit(X, y, epochs=1)
    twin.partial_fit(X, y, epochs=1)
    assert restored.history[-1, "train_loss"] == twin.history[-1, "train_loss"]
    np.testing.assert_array_equal(restored.predict_proba(X), twin.predict_proba(X))


def test_generator_saved_on_another_device_type_is_reseeded():
    from sklearn_hardness.models._persistence import SavedGenerator as _SavedGenerator

    saved = _SavedGenerator("cuda", 7, torch.Generator().manual_seed(3).get_state())
    gen = pickle.loads(pickle.dumps(saved)).restore(torch.device("cpu"))
    assert gen.device.type == "cpu" and gen.initial_seed() == 7
    assert torch.equal(gen.get_state(), torch.Generator().manual_seed(7).get_state())


def test_save_and_load_params_into_fresh_net(case, tmp_path):
    cls, kind, kw, X, y, net = case
    f = tmp_path / "params.pt"
    net.save_params(f_params=str(f))
    fresh = cls(classes=net.classes_, **kw)
    fresh.load_params(f_params=str(f))
    np.testing.assert_array_equal(fresh.predict_proba(X), net.predict_proba(X))
    np.testing.assert_array_equal(fresh.predict(X), net.predict(X))
    # the fitted input shape comes back with the parameters
    with pytest.raises(ValueError):
        fresh.predict_proba(X[:, :2] if kind == "frames" else X[:, :5])
    # loading into a fitted net works as in skorch
    again = cls(random_state=5, **kw).fit(X, y)
    again.load_params(f_params=str(f))
    np.testing.assert_array_equal(again.predict_proba(X), net.predict_proba(X))


def test_partial_fit_continues_training_and_keeps_optimizer(case):
    cls, kind, kw, X, y, _ = case
    net = cls(random_state=0, **kw).fit(X, y)
    n_epochs = len(net.history)
    steps = [s["step"].item() for s in net.optimizer_.state.values()]
    module = net.module_
    net.partial_fit(X[:9], y[:9], epochs=2)
    assert len(net.history) == n_epochs + 2
    assert net.module_ is module  # not re-initialised
    new_steps = [s["step"].item() for s in net.optimizer_.state.values()]
    batches = int(np.ceil(9 / net.batch_size))
    assert new_steps == [s + 2 * batches for s in steps]
    with pytest.raises(ValueError, match="not among the classes"):
        net.partial_fit(X[:3], np.array([0, 1, 7]), epochs=1)


def test_string_labels_and_declared_classes(case):
    cls, kind, kw, X, y, _ = case
    names = np.array(["soft", "medium", "hard"])[y]
    net = cls(random_state=0, **kw).fit(X, names)
    assert set(net.predict(X)) <= {"soft", "medium", "hard"}
    np.testing.assert_array_equal(net.classes_, ["hard", "medium", "soft"])
    # a class declared but missing from y still gets an output
    declared = cls(classes=["soft", "medium", "hard", "rigid"], random_state=0, **kw)
    declared.fit(X, names)
    assert declared.predict_proba(X).shape == (len(X), 4)
    # partial_fit with classes= on the first call
    pf = cls(random_state=0, **kw)
    pf.partial_fit(X[y < 2], names[y < 2], classes=["soft", "medium", "hard"], epochs=1)
    assert pf.predict_proba_samples(X[:2], n_samples=3, random_state=0).shape == (3, 2, 3)


def test_grid_search_over_dropout(case):
    from sklearn.model_selection import GridSearchCV
    from sklearn.pipeline import Pipeline
    from sklearn.preprocessing import StandardScaler

    cls, kind, kw, X, y, _ = case
    clf = cls(random_state=0, **{**kw, "max_epochs": 2})
    pipe = Pipeline([("scale", StandardScaler()), ("clf", clf)]) if kind == "features" else Pipeline(
        [("clf", clf)]
    )
    grid = {"clf__dropout": [0.05, 0.1, 0.2, 0.5]}
    search = GridSearchCV(pipe, grid, cv=2).fit(X, y)
    assert len(search.cv_results_["mean_test_score"]) == 4
    best = search.best_estimator_.named_steps["clf"]
    p = search.best_params_["clf__dropout"]
    assert all(m.p == p for m in best.module_.modules() if isinstance(m, MCDropout))


def test_bad_parameters(case):
    cls, kind, kw, X, y, _ = case
    with pytest.raises(ValueError, match="dropout"):
        cls(dropout=1.5, **kw).fit(X, y)
    with pytest.raises(ValueError, match="at least 2 classes"):
        cls(**kw).fit(X, np.zeros(len(X)))
    with pytest.raises(ValueError, match="labels y"):
        cls(**kw).fit(X, None)
    with pytest.raises(ValueError):
        cls(**kw).fit(X, y[:-1])
    _, _, _, _, _, net = case
    with pytest.raises(ValueError, match="n_samples"):
        net.predict_proba_samples(X, n_samples=0)
    # initialize() alone builds a stand-in; the net is not fitted until it sees data
    with pytest.raises(NotFittedError):
        cls(**kw).initialize().predict_proba(X)
    with pytest.raises(InvalidParameterError, match="class_weight"):
        cls(class_weight="uniform", **kw).fit(X, y)
    with pytest.raises(InvalidParameterError, match="lr"):
        cls(lr=-1.0, **kw).fit(X, y)
    # skorch's own parameters too, before any training
    with pytest.raises(InvalidParameterError, match="The 'device' parameter of .* Got 'gpu' instead"):
        cls(device="gpu", **kw).fit(X, y)
    with pytest.raises(InvalidParameterError, match="The 'callbacks' parameter of .* Got 'all' instead"):
        cls(callbacks="all", **kw).fit(X, y)
    with pytest.raises(InvalidParameterError, match="The 'train_split' parameter of .* Got 0.2 instead"):
        cls(train_split=0.2, **kw).fit(X, y)


def test_device_auto_is_kept_as_parameter(case):
    cls, kind, kw, X, y, _ = case
    net = cls(device="auto", random_state=0, **kw)
    assert net.get_params()["device"] == "auto"
    net.fit(X, y)
    expected = "cuda" if torch.cuda.is_available() else "cpu"
    assert next(net.module_.parameters()).device.type == expected
    assert clone(net).get_params()["device"] == "auto"
    restored = pickle.loads(pickle.dumps(net))
    assert restored.get_params()["device"] == "auto"
    np.testing.assert_allclose(restored.predict_proba(X), net.predict_proba(X))


def test_warm_start_fit_continues(case):
    cls, kind, kw, X, y, _ = case
    net = cls(warm_start=True, random_state=0, **kw).fit(X, y)
    module = net.module_
    net.fit(X, y)
    assert net.module_ is module
    assert len(net.history) == 2 * kw["max_epochs"]
    with pytest.raises(ValueError):
        net.fit(X[:, :2] if kind == "frames" else X[:, :4], y)


@pytest.mark.parametrize("name", list(CASES))
def test_not_fitted_error_before_fit(name):
    cls, kind, kw = CASES[name]
    X, _ = _data(kind, n=4)
    net = cls(**kw)
    for method in (net.predict, net.predict_proba, lambda X: net.predict_proba_samples(X, n_samples=2)):
        with pytest.raises(NotFittedError, match="not fitted"):
            method(X)


def test_predict_proba_samples_parameters_are_validated(case):
    cls, kind, kw, X, y, net = case
    with pytest.raises(InvalidParameterError, match="n_samples"):
        net.predict_proba_samples(X, n_samples=0)
    with pytest.raises(InvalidParameterError, match="batch_size"):
        net.predict_proba_samples(X, n_samples=2, batch_size=0.5)


def test_train_split_fits_and_scores_the_validation_fold(case):
    # skorch's valid_acc callback predicts on a skorch Subset of the encoded labels
    from sklearn.model_selection import KFold
    from skorch.dataset import ValidSplit

    cls, kind, kw, X, y, _ = case
    names = np.array(["soft", "medium", "hard"])[y]
    net = cls(random_state=0, **dict(kw, max_epochs=2, train_split=ValidSplit(5))).fit(X, names)
    assert len(net.history_) == 2
    assert {"valid_loss", "valid_acc"} <= set(net.history_[-1])
    _, valid = next(KFold(5).split(X))  # ValidSplit(5)'s validation fold
    acc = np.mean(net.predict(X[valid]) == names[valid])
    assert net.history_[-1, "valid_acc"] == pytest.approx(acc)
    assert set(net.predict(X)) <= {"soft", "medium", "hard"}


def test_unsorted_classes_give_sorted_classes_and_the_same_model(case):
    cls, kind, kw, X, y, _ = case
    names = np.array(["soft", "medium", "hard"])[y]
    weights = {"soft": 3.0, "medium": 0.5}
    fitted = [cls(classes=c, class_weight=weights, random_state=0, **kw).fit(X, names)
              for c in (["soft", "medium", "hard"], ["hard", "medium", "soft"])]
    first = [cls(class_weight=weights, random_state=0, **kw).partial_fit(X[y < 2], names[y < 2], classes=c,
                                                                        epochs=1)
             for c in (["soft", "medium", "hard"], ["hard", "medium", "soft"])]
    for a, b in (fitted, first):
        np.testing.assert_array_equal(a.classes_, ["hard", "medium", "soft"])
        np.testing.assert_array_equal(a.class_weight_, [1.0, 0.5, 3.0])
        np.testing.assert_array_equal(a.class_weight_, b.class_weight_)
        np.testing.assert_array_equal(a.predict_proba(X), b.predict_proba(X))
        np.testing.assert_array_equal(a.predict(X), b.predict(X))
    assert fitted[0].classes == ["soft", "medium", "hard"]  # the parameter is kept as given


def test_unsorted_classes_are_accepted_by_active_learner():
    from sklearn_hardness.active import ActiveLearner

    X, y = _data("features", n=30)
    names = np.array(["soft", "medium", "hard"])[y]
    net = OFNNClassifier(max_epochs=1, classes=["soft", "medium", "hard"], random_state=0)
    learner = ActiveLearner(net, initial_epochs=1).fit(X, names)
    np.testing.assert_array_equal(learner.classes_, ["hard", "medium", "soft"])


def test_balanced_class_weight_with_declared_classes_absent_from_y():
    from sklearn.utils.class_weight import compute_class_weight

    X, y = _data("features", n=20)  # labels 0, 1, 2 (7, 7, 6 of them)
    # every class present: scikit-learn's weights, exactly
    full = OFNNClassifier(max_epochs=1, class_weight="balanced", random_state=0).fit(X, y)
    np.testing.assert_array_equal(
        full.class_weight_, compute_class_weight("balanced", classes=np.unique(y), y=y).astype(np.float32)
    )
    declared = OFNNClassifier(max_epochs=1, class_weight="balanced", classes=[0, 1, 2], random_state=0)
    np.testing.assert_array_equal(declared.fit(X, y).class_weight_, full.class_weight_)
    # a declared class missing from y gets weight 1; the others are balanced over the present ones
    keep = y != 1
    n0, n2 = np.sum(y[keep] == 0), np.sum(y[keep] == 2)
    expected = np.array([keep.sum() / (2 * n0), 1.0, keep.sum() / (2 * n2)], dtype=np.float32)
    net = OFNNClassifier(max_epochs=1, class_weight="balanced", classes=[0, 1, 2, 3], random_state=0)
    np.testing.assert_array_equal(net.fit(X[keep], y[keep]).class_weight_, np.r_[expected, 1.0].astype(np.float32))
    pf = OFNNClassifier(max_epochs=1, class_weight="balanced", random_state=0)
    pf.partial_fit(X[keep], y[keep], classes=[0, 1, 2], epochs=1)
    np.testing.assert_array_equal(pf.class_weight_, expected)
    assert pf.predict_proba(X).shape == (len(X), 3)
