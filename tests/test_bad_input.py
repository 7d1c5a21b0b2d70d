"""Malformed input to every public entry point: a clear error naming the problem.

Each case is ``(call, exception type, message fragment)``: the call must
raise that type (``InvalidParameterError`` for parameters, which is both a
ValueError and a TypeError) with a message matching the fragment. Cases
that write files also check that nothing partial is left behind.
"""

from __future__ import annotations

import os
import warnings

import numpy as np
import pytest
from sklearn.exceptions import NotFittedError

from sklearn_hardness.active import ActiveLearner, PressOracle, class_uncertainty
from sklearn_hardness.active._strategies import get_strategy
from sklearn_hardness.datasets import load_press_videos, make_presses
from sklearn_hardness.features import OpticalFlowFeatures
from sklearn_hardness.io import read_video, write_video
from sklearn_hardness.metrics import hardness_mae, make_hardness_mae_scorer
from sklearn_hardness.models import ConvLSTMClassifier, OFNNClassifier
from sklearn_hardness.models._pipelines import FrameScaler
from sklearn_hardness.preprocessing import ContactFrameSelector
from sklearn_hardness.utils._lazy import LazyVideoSequence
from sklearn_hardness.utils._param_validation import InvalidParameterError

from ._synthetic import synthetic_press

_U8 = np.zeros((4, 16, 16, 3), np.uint8)
_FRAMES = np.random.default_rng(0).random((4, 3, 16, 20, 1), dtype=np.float32)
_TABLE = np.random.default_rng(0).random((12, 4)).astype(np.float32)
_Y3 = np.arange(12) % 3


def _nan(a, where=(0,)):
    a = np.array(a, dtype=np.float32, copy=True)
    a[where] = np.nan
    return a


def _fitted_of():
    return OpticalFlowFeatures(n_features=4).fit(_FRAMES)


def _net(**kw):
    return OFNNClassifier(hidden_units=8, max_epochs=2, random_state=0, **kw)


@pytest.fixture(scope="module")
def files(tmp_path_factory):
    """A folder with a good video, a corrupt one, a truncated one and manifests."""
    root = tmp_path_factory.mktemp("bad_input")
    write_video(root / "good.avi", synthetic_press(n_frames=6, size=(16, 16)))
    (root / "corrupt.avi").write_bytes(os.urandom(2048))
    good = (root / "good.avi").read_bytes()
    (root / "truncated.avi").write_bytes(good[: 200])
    (root / "empty_dir").mkdir()
    (root / "object.npy").write_bytes(b"")
    np.save(root / "float.npy", np.zeros((3, 8, 8, 3), np.float32))
    np.save(root / "whole.npy", np.zeros((3, 8, 8, 3), np.uint8))
    (root / "truncated.npy").write_bytes((root / "whole.npy").read_bytes()[:150])
    np.save(root / "flat.npy", np.zeros((8, 8), np.uint8))
    mixed = root / "mixed_sizes"
    write_video(mixed, np.zeros((2, 8, 8, 3), np.uint8))
    write_video(root / "other", np.zeros((1, 10, 10, 3), np.uint8))
    os.replace(root / "other" / "frame_00000.png", mixed / "frame_00002.png")

    def manifest(name, text):
        (root / name).write_text(text)
        return root / name

    return {
        "root": root,
        "missing_files": manifest("m_missing.csv", "path,label\ngood.avi,a\nnope1.avi,b\nnope2.avi,b\n"),
        "no_label": manifest("m_nolabel.csv", "path,hardness\ngood.avi,1.0\n"),
        "empty": manifest("m_empty.csv", "path,label\n"),
        "bad_hardness": manifest("m_badh.csv", "path,label,hardness\ngood.avi,a,soft\n"),
        "inf_hardness": manifest("m_infh.csv", "path,label,hardness\ngood.avi,a,inf\n"),
        "conflicting": manifest("m_conf.csv", "path,label,hardness\ngood.avi,a,1.0\ngood.avi,a,2.0\n"),
        "partial_hardness": manifest("m_parth.csv", "path,label,hardness\ngood.avi,a,1.0\ngood.avi,b,\n"),
        "empty_label": manifest("m_emptylabel.csv", "path,label\ngood.avi,\n"),
        "mixed_units": manifest(
            "m_units.csv", "path,label,hardness_unit\ngood.avi,a,mm/N\ngood.avi,b,Shore 00\n"
        ),
        "bad_fps": manifest("m_fps.csv", "path,label,fps\ngood.avi,a,fast\n"),
    }


def _cases(files):
    f = files
    r = f["root"]
    return {
        # ------------------------------------------------------------- read_video
        "read_video missing file": (lambda: read_video(r / "nope.avi"), FileNotFoundError, "not found"),
        "read_video corrupt file": (lambda: read_video(r / "corrupt.avi"), ValueError, "corrupt|zero decodable"),
        "read_video truncated file": (lambda: read_video(r / "truncated.avi"), ValueError, "corrupt|zero decodable"),
        "read_video empty folder": (lambda: read_video(r / "empty_dir"), ValueError, "no image files"),
        "read_video images of two sizes": (lambda: read_video(r / "mixed_sizes"), ValueError, "same size"),
        "read_video empty .npy": (lambda: read_video(r / "object.npy"), ValueError, "as a .npy video"),
        "read_video truncated .npy": (lambda: read_video(r / "truncated.npy"), ValueError, "truncated"),
        "read_video float .npy": (lambda: read_video(r / "float.npy"), TypeError, "must be uint8"),
        "read_video 2-D .npy": (lambda: read_video(r / "flat.npy"), ValueError, r"\(T, H, W, C\)"),
        "read_video max_frames=0": (
            lambda: read_video(r / "good.avi", max_frames=0), InvalidParameterError, "'max_frames' parameter"
        ),
        "read_video path is an int": (lambda: read_video(3), InvalidParameterError, "'path' parameter"),
        # ------------------------------------------------------------ write_video
        "write_video float frames": (
            lambda: write_video(r / "w1.avi", np.zeros((2, 8, 8, 3), np.float32)), TypeError, "must be uint8"
        ),
        "write_video 2-D frames": (
            lambda: write_video(r / "w2.avi", np.zeros((8, 8), np.uint8)), ValueError, r"\(T, H, W, C\)"
        ),
        "write_video no frames": (
            lambda: write_video(r / "w3.avi", np.zeros((0, 8, 8, 3), np.uint8)), ValueError, "0 frame"
        ),
        "write_video 4 channels": (
            lambda: write_video(r / "w4.avi", np.zeros((2, 8, 8, 4), np.uint8)), ValueError, "1 or 3 colour channels"
        ),
        "write_video fps=0": (lambda: write_video(r / "w5.avi", _U8, fps=0), InvalidParameterError, "'fps' parameter"),
        "write_video unknown extension": (
            lambda: write_video(r / "w6.xyz", _U8), ValueError, "Unknown video extension"
        ),
        "write_video 2-letter fourcc": (
            lambda: write_video(r / "w7.avi", _U8, fourcc="ab"), ValueError, "4 characters"
        ),
        "write_video frames is a string": (
            lambda: write_video(r / "w8.avi", "frames"), InvalidParameterError, "'frames' parameter"
        ),
        # ------------------------------------------------------ load_press_videos
        "manifest missing": (lambda: load_press_videos(r / "nope.csv"), FileNotFoundError, "Manifest not found"),
        "manifest names missing files (all listed)": (
            lambda: load_press_videos(f["missing_files"]), FileNotFoundError, "(?s)2 missing file.*nope1.*nope2"
        ),
        "manifest without label column": (
            lambda: load_press_videos(f["no_label"]), ValueError, r"required column\(s\) \['label'\]"
        ),
        "manifest without rows": (lambda: load_press_videos(f["empty"]), ValueError, "lists no videos"),
        "manifest hardness not a number": (
            lambda: load_press_videos(f["bad_hardness"]), ValueError, "'hardness' must be a number, got 'soft'"
        ),
        "manifest hardness infinite": (lambda: load_press_videos(f["inf_hardness"]), ValueError, "not finite"),
        "manifest conflicting hardness": (
            lambda: load_press_videos(f["conflicting"]), ValueError, "a class has one hardness value"
        ),
        "manifest hardness on some rows only": (
            lambda: load_press_videos(f["partial_hardness"]), ValueError, "'hardness' is empty"
        ),
        "manifest empty label": (lambda: load_press_videos(f["empty_label"]), ValueError, "empty 'label'"),
        "manifest mixed hardness units": (
            lambda: load_press_videos(f["mixed_units"]), ValueError, "mixes hardness units"
        ),
        "manifest fps not a number": (lambda: load_press_videos(f["bad_fps"]), ValueError, "'fps' must be a number"),
        "manifest cache_size=-1": (
            lambda: load_press_videos(f["empty"], cache_size=-1), InvalidParameterError, "'cache_size' parameter"
        ),
        "lazy videos loader not callable": (
            lambda: LazyVideoSequence("read_video", ["a.avi"]), TypeError, "loader must be callable"
        ),
        "lazy videos keys is one path": (
            lambda: LazyVideoSequence(read_video, "a.avi"), TypeError, "keys must be a sequence"
        ),
        "lazy videos cache_size=-1": (
            lambda: LazyVideoSequence(read_video, ["a.avi"], cache_size=-1), ValueError, "cache_size must be"
        ),
        "lazy videos index out of range": (
            lambda: LazyVideoSequence(read_video, [r / "good.avi"])[3], IndexError, "out of range"
        ),
        # ----------------------------------------------------------------- metrics
        "hardness_mae unknown label": (
            lambda: hardness_mae([0, 5], [0, 1], [1.0, 2.0]), ValueError, r"labels \[5\] with no hardness"
        ),
        "hardness_mae lengths differ": (
            lambda: hardness_mae([0, 1], [0], [1.0, 2.0]), ValueError, "2 samples but y_pred has 1"
        ),
        "hardness_mae empty": (lambda: hardness_mae([], [], [1.0]), ValueError, "empty"),
        "hardness_mae NaN hardness": (
            lambda: hardness_mae([0], [0], [np.nan]), ValueError, "hardness contains NaN"
        ),
        "hardness_mae 2-D hardness": (
            lambda: hardness_mae([0], [0], [[1.0, 2.0]]), ValueError, "hardness must be 1-D"
        ),
        "hardness_mae duplicate classes": (
            lambda: hardness_mae(["a"], ["a"], [1.0, 2.0], classes=["a", "a"]), ValueError, "duplicate labels"
        ),
        "hardness_mae mapping and classes": (
            lambda: hardness_mae(["a"], ["a"], {"a": 1.0}, classes=["a"]), ValueError, "not both"
        ),
        "hardness_mae sample_weight shape": (
            lambda: hardness_mae([0, 1], [0, 1], [1.0, 2.0], sample_weight=[1.0]), ValueError, "sample_weight has shape"
        ),
        "hardness_mae hardness is a string": (
            lambda: hardness_mae([0], [0], "hard"), InvalidParameterError, "'hardness' parameter"
        ),
        "hardness scorer with empty hardness": (
            lambda: make_hardness_mae_scorer([]), ValueError, "hardness is empty"
        ),
        # ------------------------------------------------------ OpticalFlowFeatures
        "optical flow 4-D X": (lambda: OpticalFlowFeatures().fit(_FRAMES[0]), ValueError, "n_samples, n_frames"),
        "optical flow one frame": (
            lambda: OpticalFlowFeatures().fit(_FRAMES[:, :1]), ValueError, "at least 2 frames"
        ),
        "optical flow NaN": (
            lambda: OpticalFlowFeatures().fit(_nan(_FRAMES, (2,))), ValueError,
            r"NaN or infinite values in sample\(s\) \[2\]",
        ),
        "optical flow strings": (
            lambda: OpticalFlowFeatures().fit(np.array(["a", "b"])), TypeError, "numeric array"
        ),
        "optical flow no samples": (
            lambda: OpticalFlowFeatures().fit(_FRAMES[:0]), ValueError, "contains no samples"
        ),
        "optical flow transform before fit": (
            lambda: OpticalFlowFeatures().transform(_FRAMES), NotFittedError, "not fitted"
        ),
        "optical flow other frame count": (
            lambda: _fitted_of().transform(_FRAMES[:, :2]), ValueError, "2 frames per sample but 3"
        ),
        "optical flow other frame shape": (
            lambda: _fitted_of().transform(_FRAMES[:, :, :8]), ValueError, "seen during fit"
        ),
        "optical flow n_features=0": (
            lambda: OpticalFlowFeatures(n_features=0).fit(_FRAMES), InvalidParameterError, "'n_features' parameter"
        ),
        "optical flow value_range reversed": (
            lambda: OpticalFlowFeatures(value_range=(1, 0)).fit(_FRAMES), InvalidParameterError, "low < high"
        ),
        # ------------------------------------------------------ ContactFrameSelector
        "selector X is a path": (
            lambda: ContactFrameSelector().fit("video.avi"), TypeError, "sequence of videos"
        ),
        "selector no videos": (lambda: ContactFrameSelector().fit([]), ValueError, "no videos"),
        "selector one video, not a list": (
            lambda: ContactFrameSelector().fit(np.zeros((8, 16, 16, 3), np.uint8)), ValueError, "For a single video"
        ),
        "selector NaN frames": (
            lambda: ContactFrameSelector().fit([_nan(np.zeros((8, 16, 16, 3)), (3,))]), ValueError, "NaN or infinite"
        ),
        "selector 4 channels": (
            lambda: ContactFrameSelector().fit([np.zeros((8, 16, 16, 4), np.uint8)]), ValueError,
            "1 or 3 colour channels",
        ),
        "selector transform before fit": (
            lambda: ContactFrameSelector().transform([_U8]), NotFittedError, "not fitted"
        ),
        # ------------------------------------------------------------------- models
        "FrameScaler NaN": (lambda: FrameScaler().fit(_nan(_FRAMES)), ValueError, "NaN or infinite"),
        "FrameScaler 2-D X": (lambda: FrameScaler().fit(_TABLE), ValueError, "n_samples, n_frames"),
        "OFNN frames instead of features": (
            lambda: _net().fit(_FRAMES, [0, 1, 0, 1]), ValueError, "expects a 2-D array of features"
        ),
        "OFNN NaN features": (lambda: _net().fit(_nan(_TABLE), _Y3), ValueError, "Input X contains NaN"),
        "OFNN y of other length": (lambda: _net().fit(_TABLE, _Y3[:5]), ValueError, "inconsistent numbers of samples"),
        "OFNN one class": (lambda: _net().fit(_TABLE, np.zeros(12, int)), ValueError, "at least 2 classes"),
        "OFNN predict_proba before fit": (
            lambda: _net().predict_proba(_TABLE), NotFittedError, "not initialized|not fitted"
        ),
        "ConvLSTM features instead of frames": (
            lambda: ConvLSTMClassifier(max_epochs=1).fit(_TABLE, _Y3), ValueError, "n_samples, n_frames"
        ),
        # ------------------------------------------------------------------- active
        "unknown strategy name": (lambda: get_strategy("uncertainty"), ValueError, "strategy.*'uncertainty'"),
        "strategy neither name nor callable": (
            lambda: get_strategy(3), TypeError, "'strategy' parameter of get_strategy"
        ),
        "class_uncertainty 2-D probabilities": (
            lambda: class_uncertainty(np.full((4, 3), 1 / 3)), ValueError,
            r"must be 3-D with shape \(n_samples, n_X, n_classes\)",
        ),
        "class_uncertainty NaN probabilities": (
            lambda: class_uncertainty(_nan(np.full((2, 4, 3), 1 / 3))), ValueError, "proba_samples contains NaN"
        ),
        "class_uncertainty unknown kind": (
            lambda: class_uncertainty(np.full((2, 4, 3), 1 / 3), kind="margin"), ValueError,
            "'kind' parameter of class_uncertainty",
        ),
        "learner query before fit": (
            lambda: ActiveLearner(_net()).query(_TABLE), NotFittedError, "not fitted yet"
        ),
        "learner class missing from the initial set": (
            lambda: ActiveLearner(_net(), classes=[0, 1, 2], initial_epochs=1).fit(_TABLE[_Y3 < 2], _Y3[_Y3 < 2]),
            ValueError, r"classes \[2\] are missing from the initial training set",
        ),
        "learner reservoir cap below the batch": (
            lambda: ActiveLearner(_net(), initial_epochs=1, epochs_per_query=1, max_reservoir=2)
            .fit(_TABLE, _Y3).teach(_TABLE[:5], _Y3[:5]),
            ValueError, "max_reservoir=2 is smaller than the batch of 5",
        ),
        "learner teach unknown label": (
            lambda: ActiveLearner(_net(), initial_epochs=1, epochs_per_query=1)
            .fit(_TABLE, _Y3).teach(_TABLE[:2], [0, 7]),
            ValueError, r"labels \[7\] that are not among the classes",
        ),
        "oracle unknown label": (lambda: PressOracle(_TABLE, _Y3).press(9), ValueError, "unknown reference object 9"),
        "oracle unknown on_exhausted": (
            lambda: PressOracle(_TABLE, _Y3, on_exhausted="wrap"), ValueError, "on_exhausted"
        ),
        # ----------------------------------------------------------------- datasets
        "simulator unknown preset": (lambda: make_presses("granite"), ValueError, "Unknown preset 'granite'"),
    }


_MANIFEST_FIXTURES = ("missing_files", "no_label", "empty", "bad_hardness", "inf_hardness", "conflicting",
                      "partial_hardness", "empty_label", "mixed_units", "bad_fps")
_CASE_IDS = list(_cases({"root": None, **dict.fromkeys(_MANIFEST_FIXTURES)}))


def test_at_least_fifty_cases():
    assert len(_CASE_IDS) >= 50


@pytest.mark.parametrize("case", _CASE_IDS)
def test_bad_input_raises_clear_error(case, files):
    call, exc, fragment = _cases(files)[case]
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", UserWarning)
        with pytest.raises(exc, match=fragment):
            call()


@pytest.mark.parametrize(
    "name, frames, kwargs",
    [
        ("w_float.avi", np.zeros((2, 8, 8, 3), np.float32), {}),
        ("w_ext.xyz", _U8, {}),
        ("w_fourcc.avi", _U8, {"fourcc": "ab"}),
        ("w_fps.avi", _U8, {"fps": -1}),
        ("w_folder", np.zeros((0, 8, 8, 3), np.uint8), {}),
        ("sub/w_npy.npy", np.zeros((2, 8), np.uint8), {}),
    ],
)
def test_failed_write_leaves_nothing_behind(tmp_path, name, frames, kwargs):
    with pytest.raises((ValueError, TypeError)):
        write_video(tmp_path / name, frames, **kwargs)
    assert list(tmp_path.iterdir()) == []


_RECORD = '{"key": {"strategy": "variance", "seed": 0}, "accuracy": 1.0}\n'


@pytest.mark.parametrize(
    "kwargs, fragment",
    [
        ({"strategies": ["uncertainty"]}, "strategy.*'uncertainty'"),
        ({"dataset": "granite"}, "dataset 'granite' is neither a simulator preset"),
        ({"n_runs": 0}, "'n_runs' parameter of the experiment configuration"),
        ({"model": "svm"}, "unknown model 'svm'"),
    ],
)
def test_failed_experiment_leaves_results_file_intact(tmp_path, kwargs, fragment):
    from sklearn_hardness.experiments import run_active_sampling

    results = tmp_path / "results.jsonl"
    results.write_text(_RECORD)
    with pytest.raises(ValueError, match=fragment):
        run_active_sampling(results_path=results, quick=True, **kwargs)
    assert results.read_text() == _RECORD
    assert sorted(p.name for p in tmp_path.iterdir()) == ["results.jsonl"]


def test_results_file_with_a_bad_middle_line_is_not_rewritten(tmp_path):
    from sklearn_hardness.experiments._results import ResultsStore

    text = _RECORD + "not json\n" + _RECORD.replace('"seed": 0', '"seed": 1')
    results = tmp_path / "results.jsonl"
    results.write_text(text)
    with pytest.raises(ValueError, match="line 2 is not a valid run record"):
        ResultsStore(results)
    assert results.read_text() == text


def test_results_record_with_a_malformed_key_names_the_line(tmp_path):
    from sklearn_hardness.experiments._results import ResultsStore

    results = tmp_path / "results.jsonl"
    text = _RECORD + '{"key": ["variance", 0]}\n'
    results.write_text(text)
    # complete JSON is never a torn write: an error naming the line, and the file left as it was
    with pytest.raises(ValueError, match="line 2 is a record whose 'key' is a list"):
        ResultsStore(results)
    assert results.read_text() == text


def test_parameter_validation_is_the_package_s_own_and_scikit_learn_is_not_capped():
    """Policy: every constraint table and validation decorator of the package comes from its own
    vendored copy of scikit-learn's parameter validation (``sklearn_hardness/utils/_param_validation.py``;
    tests/test_import_boundaries.py checks that nothing imports scikit-learn's private modules), so
    scikit-learn has a floor and no upper bound, and our constraints raise our
    ``InvalidParameterError`` (a ValueError and a TypeError) in scikit-learn's message format."""
    import importlib
    import inspect
    import pathlib
    import pkgutil
    import re

    from packaging.requirements import Requirement  # a dependency of pytest

    import sklearn_hardness
    from sklearn_hardness.utils import _param_validation as pv

    root = pathlib.Path(__file__).resolve().parents[1]
    spec = Requirement(re.search(r'"(scikit-learn[^"]*)"', (root / "pyproject.toml").read_text()).group(1)).specifier
    assert {s.operator for s in spec} == {">="}, f"scikit-learn needs a floor only, got {spec}"
    assert issubclass(pv.InvalidParameterError, ValueError) and issubclass(pv.InvalidParameterError, TypeError)

    # every table of the package is made of constraints our make_constraint takes
    tables = {}
    for info in pkgutil.walk_packages(sklearn_hardness.__path__, "sklearn_hardness."):
        if info.name.endswith(".__main__"):  # __main__ runs the CLI
            continue
        module = importlib.import_module(info.name)
        for name, obj in vars(module).items():
            if getattr(obj, "__module__", None) != module.__name__:
                continue
            if inspect.isclass(obj):
                for attr, table in vars(obj).items():
                    if attr.endswith("_constraints") and isinstance(table, dict):
                        tables[f"{module.__name__}.{name}.{attr}"] = table
            elif callable(obj) and isinstance(getattr(obj, "_skl_parameter_constraints", None), dict):
                tables[f"{module.__name__}.{name}"] = obj._skl_parameter_constraints
    assert len(tables) > 30, sorted(tables)
    for where, table in tables.items():
        for param, constraints in table.items():
            if constraints == "no_validation":
                continue
            for constraint in constraints:
                assert isinstance(pv.make_constraint(constraint), pv._Constraint), (where, param, constraint)

    with pytest.raises(
        pv.InvalidParameterError,
        match=r"^The 'n_features' parameter of OpticalFlowFeatures must be an int in the range \[1, inf\)\. "
              r"Got 0 instead\.$",
    ):
        OpticalFlowFeatures(n_features=0).fit(_FRAMES)


def test_fit_context_validates_skips_and_nests_like_scikit_learn_s():
    """``fit_context`` (our ``sklearn.base._fit_context``) honours the public
    ``skip_parameter_validation`` setting, sets it for nested calls, and validates a
    ``partial_fit`` only until the estimator is fitted."""
    from numbers import Integral

    import sklearn
    from sklearn.base import BaseEstimator

    from sklearn_hardness.utils._param_validation import Interval, fit_context

    class Stub(BaseEstimator):
        _parameter_constraints = {"k": [Interval(Integral, 1, None, closed="left")]}

        def __init__(self, k=1):
            self.k = k

        @fit_context(prefer_skip_nested_validation=True)
        def fit(self, X=None, y=None):
            self.nested_skip_ = sklearn.get_config()["skip_parameter_validation"]
            return self

        @fit_context(prefer_skip_nested_validation=False)
        def partial_fit(self, X=None, y=None):
            self.nested_skip_ = sklearn.get_config()["skip_parameter_validation"]
            return self

    with pytest.raises(InvalidParameterError, match="'k' parameter of Stub"):
        Stub(k=0).fit()
    with pytest.raises(InvalidParameterError, match="'k' parameter of Stub"):
        Stub(k=0).partial_fit()
    assert Stub().fit().nested_skip_ is True
    assert Stub().partial_fit().nested_skip_ is False
    fitted = Stub().partial_fit()
    fitted.set_params(k=0).partial_fit()  # fitted: partial_fit does not validate again
    with sklearn.config_context(skip_parameter_validation=True):
        assert Stub(k=0).fit().nested_skip_ is True
        assert Stub(k=0).partial_fit().nested_skip_ is True
