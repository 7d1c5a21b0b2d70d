"""Object-disjoint active sampling: many objects per class, one of them the test object.

And what must not change for class-only data (silicone5, shore9): splits, seeds and
configuration hashes of earlier results files.
"""

import numpy as np
import pytest
from sklearn.utils import Bunch

from sklearn_hardness.active import PressOracle
from sklearn_hardness.datasets import make_presses
from sklearn_hardness.experiments import ExperimentResult, _active, run_active_sampling
from sklearn_hardness.experiments._config import check_config, get_config
from sklearn_hardness.experiments._run import _seeds, _split, _split_objects

from ._exp_data import TINY, tiny_presses


def _with_objects(data, per_object=2):
    """The tiny silicone5 set with each class's presses split into objects of ``per_object`` presses."""
    y = np.asarray(data.target)
    obj = np.empty(len(y), dtype=object)
    for c in np.unique(y):
        idx = np.flatnonzero(y == c)
        obj[idx] = [f"class{c}-obj{i // per_object}" for i in range(len(idx))]
    return Bunch(**{k: v for k, v in data.items() if k != "object_id"}, object_id=obj.astype(str))


def test_no_press_of_the_test_object_is_trained_on_pooled_or_held_out():
    data = _with_objects(tiny_presses(10))
    groups, y = data.object_id, np.asarray(data.target)
    tests = ["class0-obj1", "class4-obj4"]
    res = run_active_sampling(data, model="ofnn", strategies=("variance", "random"), test_objects=tests,
                              seeds=[0, 1], n_jobs=1, verbose=0, **dict(TINY, n_holdout=2, n_iterations=3))
    assert res.config["protocol"] == "object-disjoint"
    assert len(res.records) == 2 * len(tests) * 2
    for r in res.records:
        obj = r["key"]["test_object"]
        assert r["test_object"] == obj and r["key"]["test_class"] == int(y[groups == obj][0])
        own = np.flatnonzero(groups == obj)
        test = np.asarray(r["test_indices"])
        assert test.size and np.all(groups[test] == obj)
        used = np.concatenate([r["initial_indices"]] + [np.asarray(d) for d in r["drawn_indices"]])
        hold = np.asarray(r["holdout_indices"])
        assert not np.intersect1d(own, used).size and not np.intersect1d(own, hold).size
        # held-out presses are of objects never pressed in the run (unseen objects of every class)
        assert not set(groups[hold]) & set(groups[used])
        assert np.bincount(y[hold], minlength=5).tolist() == [2] * 5
        # the recorded objects are those of the presses, and of the queried class
        assert r["initial_objects"] == groups[np.asarray(r["initial_indices"])].tolist()
        for q, d, objs in zip(r["queried"], r["drawn_indices"], r["drawn_objects"]):
            assert objs == groups[np.asarray(d)].tolist() and set(y[np.asarray(d)]) == {q}
    # pairs are (test object, seed): the paired strategies share the test presses and the start
    for obj in tests:
        for seed in (0, 1):
            a, b = [r for r in res.records if r["key"]["test_object"] == obj and r["key"]["seed"] == seed]
            assert a["test_indices"] == b["test_indices"] and a["initial_indices"] == b["initial_indices"]
    rows = res.paired_table(metrics=["accuracy", "holdout_accuracy"])
    assert {r["n_pairs"] for r in rows if r["strategy"] == "variance"} == {len(tests) * 2}
    assert {r["n_pairs"] for r in res.presses_to_reach(n_boot=50)} == {len(tests) * 2}


def test_the_split_never_uses_the_test_object_for_every_object_and_seed():
    data = make_presses("everyday", n_per_class=3, image_size=(24, 32), random_state=0)
    groups, y = data.object_id.astype(str), np.asarray(data.target)
    cfg = dict(n_test=5, n_holdout=2, n_initial=3)
    n = 0
    for obj in np.unique(groups):
        for seed in range(3):
            test, hold, pool = _split_objects(y, groups, cfg, 3, obj, seed)
            own = set(np.flatnonzero(groups == obj))
            assert set(test) <= own and len(test) == 3  # all its presses when it has fewer than n_test
            assert not own & set(hold) and not own & set(pool)
            assert not set(groups[hold]) & set(groups[pool])
            assert np.bincount(y[hold], minlength=3).tolist() == [2, 2, 2]
            n += 1
    assert n == 3 * len(np.unique(groups))


def test_too_few_objects_is_a_clear_error_before_any_run():
    data = _with_objects(tiny_presses(8), per_object=4)  # 2 objects per class
    with pytest.raises(ValueError, match="n_holdout"):
        run_active_sampling(data, model="ofnn", test_objects=["class0-obj0"], seeds=[0], verbose=0,
                            **dict(TINY, n_holdout=2))
    with pytest.raises(ValueError, match="unknown"):
        run_active_sampling(data, model="ofnn", test_objects=["no-such-object"], seeds=[0], verbose=0, **TINY)
    shared = _with_objects(tiny_presses(8), per_object=4)
    shared["object_id"] = np.array([o.split("-")[1] for o in shared["object_id"]])  # "obj0" in every class
    with pytest.raises(ValueError, match="one class"):
        run_active_sampling(shared, model="ofnn", seeds=[0], verbose=0, **TINY)
    with pytest.raises(ValueError, match="object ids"):
        run_active_sampling(tiny_presses(8), model="ofnn", test_objects=["x"], seeds=[0], verbose=0, **TINY)


def test_oracle_presses_the_least_pressed_reference_object_ties_at_random():
    y = np.repeat([0, 1], 6)
    groups = np.array(["a", "a", "a", "b", "b", "c", "d", "d", "d", "d", "e", "e"])
    chosen = set()
    for seed in range(20):
        oracle = PressOracle(np.arange(12), y, groups=groups, random_state=seed)
        first, X1, y1 = oracle.press_object(0, 2)
        assert first in ("a", "b", "c") and set(groups[X1]) == {first} and y1.tolist() == [0] * len(X1)
        assert len(X1) == min(2, int(np.sum(groups == first)))
        chosen.add(first)
        second = oracle.press_object(0, 1)[0]
        assert second != first and oracle.n_pressed_[second] == 1  # an unpressed object comes next
        third = oracle.press_object(0, 1)[0]
        assert oracle.n_pressed_[third] == 1 and third not in (first, second) or third == first and len(X1) < 2
        # press(): n presses of the class, object after object by the same rule, none twice
        X, yy = oracle.press(1, 6)
        assert sorted(X.tolist()) == list(range(6, 12)) and set(yy) == {1}
        assert oracle.drawn_objects_[-6:] == groups[X].tolist()
    assert chosen == {"a", "b", "c"}  # ties are broken at random, by the seed


def test_oracle_recycles_objects_of_a_class_once_all_are_pressed_out():
    y = np.zeros(5, int)
    groups = np.array(["a", "a", "b", "b", "b"])
    oracle = PressOracle(np.arange(5), y, groups=groups, random_state=0, on_exhausted="recycle")
    oracle.press(0, 5)
    with pytest.warns(UserWarning, match="reusing"):
        X, _ = oracle.press(0, 3)
    assert set(X) <= set(range(5)) and oracle.n_remaining(0) == 2
    with pytest.raises(ValueError, match="one class"):
        PressOracle(np.arange(3), [0, 0, 1], groups=["a", "a", "a"])
    with pytest.raises(ValueError, match="no unseen presses"):
        strict = PressOracle(np.arange(5), y, groups=groups, random_state=0)
        strict.press(0, 5)
        strict.press_object(0)


def test_recycling_hands_out_every_unseen_press_before_a_reused_one():
    # the first 4 presses leave 2 unseen (which object's depends on the seed's ties); asked for 4 more,
    # the class has those 2 unseen: they come first, before any press is reused
    y = np.zeros(6, int)
    groups = np.array(["a", "a", "b", "b", "b", "b"])
    for seed in range(10):
        oracle = PressOracle(np.arange(6), y, groups=groups, random_state=seed, on_exhausted="recycle")
        first = oracle.press(0, 4)[0].tolist()
        with pytest.warns(UserWarning, match="reusing"):
            second = oracle.press(0, 4)[0].tolist()
        unseen = sorted(set(range(6)) - set(first))
        assert sorted(second[:len(unseen)]) == unseen, (seed, first, second)
        assert len(second) == 4 and oracle.n_pressed_["a"] + oracle.n_pressed_["b"] == 8


def test_class_only_oracle_is_unchanged():
    """The draws of the class-level oracle on main f885357 (silicone5 quick, test class 0, seed 0)."""
    y = make_presses("silicone5", image_size=(96, 128), random_state=0).target
    cfg = check_config(dict(get_config("silicone5", quick=True, n_holdout=5), model="convlstm"))
    s = _seeds(0, 0, 5)
    test, hold, pool = _split(y, cfg, 5, 0, s[0])
    oracle = PressOracle(pool, y[pool], random_state=s[1])
    assert oracle.initial(5)[0].tolist() == [433, 223, 359, 386, 380, 155, 284, 28, 128, 405, 393, 35, 152, 47,
                                             57, 15, 251, 211, 385, 188, 252, 435, 222, 79, 263]
    assert oracle.press(2, 5)[0].tolist() == [237, 331, 236, 41, 203]
    obj, X, _ = oracle.press_object(3, 2)  # without groups the object is the class
    assert obj == 3 and len(X) == 2


# values computed on main f885357 (machine-independent: SeedSequence and PCG64 integers, SHA-256)
_MAIN_SPLITS = {
    (0, 0): ([117, 132, 202, 304, 358], [94, 119, 215, 347, 363, 36, 136, 229, 423, 454]),
    (0, 1): ([117, 132, 161, 362, 398], [26, 94, 119, 146, 417, 114, 150, 151, 258, 405]),
    (3, 0): ([116, 185, 227, 283, 340], [90, 120, 174, 238, 362, 9, 29, 329, 423, 427]),
    (3, 1): ([18, 56, 73, 99, 256], [119, 162, 272, 287, 304, 51, 141, 151, 153, 449]),
}


def test_silicone5_results_resume_unchanged(monkeypatch):
    """Class-only data: the same config hash, seeds and splits as on main, and no test_object in the keys."""
    data = make_presses("silicone5", image_size=(96, 128), random_state=0)
    y = np.asarray(data.target)
    seen = {}

    def fake_inputs(dataset, cfg, model, **kwargs):
        from sklearn_hardness.experiments._data import _dataset_spec

        return Bunch(X=np.zeros((len(y), 1), np.float32), y=y, target_names=data.target_names,
                     hardness=data.hardness, hardness_unit=data.hardness_unit, n_classes=5, model=model,
                     data_id=list(_dataset_spec(dataset, cfg)), object_id=data.object_id)

    def fake_run(func, groups, common, store, **kwargs):
        seen["groups"], seen["common"] = groups, common
        return store

    monkeypatch.setattr(_active, "prepare_inputs", fake_inputs)
    monkeypatch.setattr(_active, "run_tasks", fake_run)
    for extra, expected in (({}, "24045a7c028c"), ({"n_holdout": 5}, "ee3555b26197")):
        res = run_active_sampling("silicone5", quick=True, seeds=[0, 1], verbose=0, **extra)
        assert res.config["config_hash"] == expected and res.config["protocol"] == "class"
        assert "groups" not in seen["common"]
        assert all("test_object" not in g and all("test_object" not in k for k in g["keys"])
                   for g in seen["groups"])
        assert [(g["test_class"], g["seed"]) for g in seen["groups"]] == [(c, s) for c in range(5) for s in (0, 1)]
    cfg = res.config
    for (tc, seed), (test, hold) in _MAIN_SPLITS.items():
        t, h, _ = _split(y, cfg, 5, tc, _seeds(seed, tc, 5)[0])
        assert t.tolist() == test and h.tolist()[:10] == hold


def test_tables_pair_runs_by_test_object():
    """Two test objects of one class with the same seed are two pairs, not one."""
    recs = [{"key": {"strategy": s, "test_class": 0, "test_object": o, "seed": 0}, "converged": True,
             "accuracy": [0.0, a], "initial_indices": [0] * 2, "drawn_indices": [[0] * 2]}
            for o, (ar, av) in (("a", (0.0, 1.0)), ("b", (0.5, 1.0)), ("c", (0.5, 0.5)))
            for s, a in (("random", ar), ("variance", av))]
    row = [r for r in ExperimentResult(recs).paired_table(metrics=["accuracy"]) if r["strategy"] == "variance"][0]
    assert row["n_pairs"] == 3 and row["diff"] == pytest.approx(0.5)


def test_object_runs_resume_without_recomputing(tmp_path, monkeypatch):
    data = _with_objects(tiny_presses(8), per_object=4)
    kwargs = dict(model="ofnn", strategies=("variance", "random"), test_objects=["class1-obj0"], seeds=[0],
                  n_jobs=1, verbose=0, results_path=tmp_path / "runs.jsonl", **TINY)
    first = run_active_sampling(data, **kwargs)

    def fail(*args, **kw):
        raise AssertionError("a finished (test object, seed) pair was run again")

    monkeypatch.setattr(_active, "_active_pair", fail)
    again = run_active_sampling(data, **kwargs)
    assert [r["key"] for r in again.records] == [r["key"] for r in first.records]
    assert all(r["key"]["test_object"] == "class1-obj0" for r in again.records)


def _with_families(data):
    """Objects of ``_with_objects`` paired into families: objN and objN+1 (N even) are parts of one whole."""
    obj = np.asarray(data.object_id)
    family = np.array([o.rsplit("obj", 1)[0] + f"fam{int(o.rsplit('obj', 1)[1]) // 2}" for o in obj])
    return Bunch(**data, family=family)


def test_family_siblings_of_the_test_object_are_never_trained_on_pooled_or_held_out():
    data = _with_families(_with_objects(tiny_presses(12)))
    groups, family = data.object_id, data.family
    tests = ["class0-obj1", "class3-obj2"]
    res = run_active_sampling(data, model="ofnn", strategies=("variance", "random"), test_objects=tests,
                              seeds=[0, 1], n_jobs=1, verbose=0, **dict(TINY, n_holdout=2, n_iterations=3))
    assert res.config["protocol"] == "family-disjoint"
    for r in res.records:
        siblings = np.flatnonzero(family == family[groups == r["test_object"]][0])
        used = np.concatenate([r["initial_indices"]] + [np.asarray(d) for d in r["drawn_indices"]]
                              + [np.asarray(r["holdout_indices"])])
        assert siblings.size == 4 and not np.intersect1d(siblings, used).size
    # the effect: without families, a sibling of the test object is in the pool the runs draw from
    y = np.asarray(data.target)
    cfg = dict(n_test=2, n_holdout=2, n_initial=2)
    for obj in tests:
        sibling = (family == family[groups == obj][0]) & (groups != obj)
        _, hold, pool = _split_objects(y, groups, cfg, 5, obj, 0)
        assert np.isin(np.flatnonzero(sibling), np.concatenate([pool, hold])).any()
        _, hold, pool = _split_objects(y, groups, cfg, 5, obj, 0, family)
        assert not np.isin(np.flatnonzero(sibling), np.concatenate([pool, hold])).any()


def test_families_of_one_object_each_keep_the_object_disjoint_protocol_and_hash():
    data = _with_objects(tiny_presses(10))
    same = Bunch(**data, family=data.object_id)
    cfg = check_config(get_config("silicone5", **TINY))
    inputs = Bunch(object_id=np.asarray(data.object_id), family=np.asarray(same.family))
    assert _active._family(inputs) is None
    y = np.asarray(data.target)
    assert _active._results_hash(cfg, "d", inputs.object_id, y) == _active._results_hash(cfg, "d", inputs.object_id,
                                                                                          y, None)
