"""PressOracle: unseen presses of a reference object, without replacement."""

import numpy as np
import pytest

from sklearn_hardness.active import PressOracle
from sklearn_hardness.utils._param_validation import InvalidParameterError


def _pool(n_per_class=(4, 3, 5)):
    y = np.concatenate([np.full(n, c) for c, n in enumerate(n_per_class)])
    X = np.arange(len(y) * 2, dtype=float).reshape(len(y), 2)  # row i encodes i
    return X, y


def test_draws_without_replacement_until_exhausted():
    X, y = _pool()
    oracle = PressOracle(X, y, random_state=0)
    got = []
    for _ in range(3):
        Xc, yc = oracle.press(2, 1)
        assert yc.tolist() == [2]
        got.append(int(Xc[0, 0] // 2))
    Xc, yc = oracle.press(2, 2)
    got += (Xc[:, 0] // 2).astype(int).tolist()
    assert sorted(got) == np.flatnonzero(y == 2).tolist()  # each press exactly once
    assert oracle.n_remaining(2) == 0
    assert oracle.drawn_ == got


def test_exhausted_raises_naming_class_and_remaining():
    X, y = _pool()
    oracle = PressOracle(X, y, random_state=0)
    oracle.press(1, 2)
    with pytest.raises(ValueError, match="reference object 1 has only 1 unseen presses left.*2 asked"):
        oracle.press(1, 2)
    assert oracle.n_remaining(1) == 1  # nothing drawn by the failed call
    with pytest.raises(ValueError, match="reference object 1"):
        oracle.press([0, 1], 2)  # all-or-nothing over several objects
    assert oracle.n_remaining() == {0: 4, 1: 1, 2: 5}


def test_truncate_and_recycle():
    X, y = _pool()
    trunc = PressOracle(X, y, random_state=0, on_exhausted="truncate")
    with pytest.warns(UserWarning, match="only 3 unseen remain"):
        Xc, yc = trunc.press(1, 5)
    assert len(yc) == 3
    with pytest.warns(UserWarning, match="only 0 unseen"):
        Xc, yc = trunc.press(1, 1)
    assert len(yc) == 0 and Xc.shape == (0, 2)

    rec = PressOracle(X, y, random_state=0, on_exhausted="recycle")
    first, _ = rec.press(1, 2)
    with pytest.warns(UserWarning, match="reusing"):
        Xc, yc = rec.press(1, 5)
    rows = (np.concatenate([first, Xc])[:, 0] // 2).astype(int)
    assert len(rows) == 7 and set(rows) == {4, 5, 6}
    assert len(set(rows[:3])) == 3  # unseen presses come first


def test_initial_set_and_several_labels():
    X, y = _pool()
    oracle = PressOracle(X, y, random_state=1)
    X0, y0 = oracle.initial(2)
    assert y0.tolist() == [0, 0, 1, 1, 2, 2]
    np.testing.assert_array_equal(y[(X0[:, 0] // 2).astype(int)], y0)
    X1, y1 = oracle.press(np.array([2, 0]), 1)
    assert y1.tolist() == [2, 0]
    assert oracle.n_remaining() == {0: 1, 1: 1, 2: 2}


def test_seeded_and_order_differs_between_seeds():
    X, y = _pool((30, 30))
    a = PressOracle(X, y, random_state=3).press(0, 10)[0]
    b = PressOracle(X, y, random_state=3).press(0, 10)[0]
    c = PressOracle(X, y, random_state=4).press(0, 10)[0]
    np.testing.assert_array_equal(a, b)
    assert not np.array_equal(a, c)


def test_list_pool_and_string_labels():
    videos = [np.full((3, 4, 4, 3), i, dtype=np.uint8) for i in range(6)]
    labels = np.array(["soft", "hard"] * 3)
    oracle = PressOracle(videos, labels, random_state=0)
    Xs, ys = oracle.press("hard", 2)
    assert isinstance(Xs, list) and len(Xs) == 2
    assert all(labels[int(v[0, 0, 0, 0])] == "hard" for v in Xs)
    assert ys.tolist() == ["hard", "hard"]
    X0, y0 = oracle.press(np.str_("soft"))
    assert y0.tolist() == ["soft"]


@pytest.mark.parametrize(
    "kwargs, err, match",
    [
        (dict(on_exhausted="wrap"), InvalidParameterError, "'on_exhausted' parameter of PressOracle"),
        (dict(random_state="seed"), InvalidParameterError, "'random_state' parameter of PressOracle"),
        (dict(X_pool=None), InvalidParameterError, "'X_pool' parameter of PressOracle"),
        (dict(y_pool="abc"), InvalidParameterError, "'y_pool' parameter of PressOracle"),
        (dict(y_pool=np.zeros((3, 1))), ValueError, "y_pool must be 1-D"),
        (dict(y_pool=np.zeros(5)), ValueError, "has 6 presses but y_pool has 5"),
    ],
)
def test_bad_construction(kwargs, err, match):
    X, y = _pool((3, 3))
    args = dict(X_pool=X, y_pool=y)
    args.update(kwargs)
    with pytest.raises(err, match=match):
        PressOracle(**args)


def test_bad_press():
    X, y = _pool()
    oracle = PressOracle(X, y)
    with pytest.raises(ValueError, match=r"unknown reference object 7; the pool has \[0, 1, 2\]"):
        oracle.press(7)
    for n in (0, -2, 1.5, None):
        with pytest.raises(InvalidParameterError, match="'n_presses' parameter"):
            oracle.press(0, n)
    with pytest.raises(InvalidParameterError, match="'n_per_class' parameter"):
        oracle.initial(0)
    assert oracle.drawn_ == []  # nothing drawn by the failed calls
    with pytest.raises(ValueError, match="repeated"):
        oracle.press([0, 0])
    with pytest.raises(ValueError, match="empty"):
        PressOracle(X[:0], y[:0])


def test_lazy_video_pool_stays_lazy():
    from sklearn_hardness.utils._lazy import LazyVideoSequence

    loaded = []

    def loader(k):
        loaded.append(k)
        return np.full((3, 4, 4, 3), k, np.uint8)

    videos = LazyVideoSequence(loader, range(8))
    oracle = PressOracle(videos, np.arange(8) % 2, random_state=0)
    Xs, ys = oracle.press(1, 3)
    assert isinstance(Xs, LazyVideoSequence) and loaded == []
    assert all(int(v[0, 0, 0, 0]) % 2 == 1 for v in Xs) and ys.tolist() == [1, 1, 1]
