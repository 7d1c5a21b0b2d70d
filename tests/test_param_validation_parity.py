"""Our copy of scikit-learn's parameter validation behaves like the installed scikit-learn's.

``sklearn_hardness/utils/_param_validation.py`` is a copy of scikit-learn 1.9.1's private
``sklearn/utils/_param_validation.py``, so that the package imports no private scikit-learn code
(tests/test_import_boundaries.py). A copy drifts silently: here, for a broad table of constraint
declarations (every kind the copy takes) and many values, the copy and the installed scikit-learn's
module accept and reject the same values with the same messages — through
``validate_parameter_constraints``, through a ``validate_params``-decorated function and through an
estimator's ``_parameter_constraints`` checked at ``fit`` — describe each constraint alike, and
generate the same valid and invalid values for the common checks.

This is the one file of the repository that imports scikit-learn's private module (tests are not
the package). It never skips: if scikit-learn moves or renames what it compares with, every test
here fails and says what to do. What scikit-learn changed between the oldest release we support
(pyproject.toml's floor) and the one the copy was taken from is listed in ``UPSTREAM_CHANGES``: on
an older scikit-learn exactly those differ, checked as such.
"""

from __future__ import annotations

import importlib
from numbers import Integral, Real

import numpy as np
import pandas as pd
import pytest
import sklearn
from packaging.version import Version  # a dependency of pytest
from scipy.sparse import csr_array, csr_matrix
from sklearn.base import BaseEstimator
from sklearn.model_selection import KFold, LeaveOneOut

from sklearn_hardness.utils import _param_validation as ours

#: The version of scikit-learn the copy was taken from (its module docstring says so too).
VENDORED_FROM = "1.9.1"

#: What this test compares with, in the installed scikit-learn.
UPSTREAM_MODULE = "sklearn.utils._param_validation"
UPSTREAM_NAMES = (
    "HasMethods", "Hidden", "Interval", "InvalidParameterError", "MissingValues", "Options", "RealNotInt",
    "StrOptions", "_Booleans", "generate_invalid_param_val", "generate_valid_param", "make_constraint",
    "validate_parameter_constraints", "validate_params",
)

#: Behaviour scikit-learn changed after its oldest release we support (1.6) and up to the copy's
#: (1.9.1): name -> (release that changed it, what). On an older installed scikit-learn these, and
#: nothing else, differ from the copy.
UPSTREAM_CHANGES = {
    "nan_float": ("1.7", 'make_constraint takes a float NaN (np.nan) like "nan"; before: "Unknown constraint type"'),
    "sparse_message": ("1.9", '"sparse matrix" is described as "a sparse array or matrix"; before: "a sparse matrix"'),
    "sparse_valid": ("1.9", 'generate_valid_param("sparse matrix") gives a csr_array; before: a csr_matrix'),
}


def _load_upstream():
    try:
        module = importlib.import_module(UPSTREAM_MODULE)
        names = {name: getattr(module, name) for name in UPSTREAM_NAMES}
        names["_fit_context"] = importlib.import_module("sklearn.base")._fit_context
    except (ImportError, AttributeError) as exc:
        return None, (
            f"scikit-learn {sklearn.__version__}: {exc}. It moved or renamed its private parameter "
            f"validation ({UPSTREAM_MODULE}, sklearn.base._fit_context), which "
            "sklearn_hardness/utils/_param_validation.py copies from scikit-learn "
            f"{VENDORED_FROM}. The package itself is unaffected (it imports none of it). Find where scikit-learn "
            "keeps it now and point UPSTREAM_MODULE/UPSTREAM_NAMES of this test at it; if its behaviour "
            "changed, either update the copy (its version in the module docstring, VENDORED_FROM, "
            "LICENSES/scikit-learn.txt) or list the change in UPSTREAM_CHANGES with the release that made it."
        )
    return type("Upstream", (), names), None


_UPSTREAM, _MOVED = _load_upstream()


@pytest.fixture
def upstream():
    if _UPSTREAM is None:
        pytest.fail(_MOVED, pytrace=False)
    return _UPSTREAM


def _has(change):
    """Whether the installed scikit-learn has made ``UPSTREAM_CHANGES[change]``."""
    return Version(sklearn.__version__) >= Version(UPSTREAM_CHANGES[change][0])


def test_the_copy_says_which_release_it_comes_from():
    assert f"scikit-learn {VENDORED_FROM}" in ours.__doc__
    assert Version(sklearn.__version__) >= Version("1.6")  # pyproject.toml's floor: UPSTREAM_CHANGES starts there


# ------------------------------------------------------------------------------------------------ the table
def _specs():
    """``id -> builder``: a builder takes a module (ours or scikit-learn's) and returns one parameter's
    list of constraint declarations, built from that module's classes."""
    specs = {}
    for closed in ("left", "right", "both", "neither"):
        specs[f"int[-2,2]{closed}"] = lambda m, c=closed: [m.Interval(Integral, -2, 2, closed=c)]
        specs[f"real[0,1]{closed}"] = lambda m, c=closed: [m.Interval(Real, 0, 1, closed=c)]
        specs[f"realnotint[0,1]{closed}"] = lambda m, c=closed: [m.Interval(m.RealNotInt, 0, 1, closed=c)]
    specs.update({
        "int>=1": lambda m: [m.Interval(Integral, 1, None, closed="left")],
        "int>0": lambda m: [m.Interval(Integral, 0, None, closed="neither")],
        "int<=3": lambda m: [m.Interval(Integral, None, 3, closed="right")],
        "int<3": lambda m: [m.Interval(Integral, None, 3, closed="neither")],
        "int-any": lambda m: [m.Interval(Integral, None, None, closed="neither")],
        "real>=0": lambda m: [m.Interval(Real, 0, None, closed="left")],
        "real>0": lambda m: [m.Interval(Real, 0, None, closed="neither")],
        "real<=0": lambda m: [m.Interval(Real, None, 0, closed="right")],
        "real<0": lambda m: [m.Interval(Real, None, 0, closed="neither")],
        "real-any-closed": lambda m: [m.Interval(Real, None, None, closed="both")],
        "real-any-open": lambda m: [m.Interval(Real, None, None, closed="neither")],
        "real-any-left": lambda m: [m.Interval(Real, None, None, closed="left")],
        "realnotint>=0.5": lambda m: [m.Interval(m.RealNotInt, 0.5, None, closed="left")],
        "int>=1|realnotint(0,1]": lambda m: [m.Interval(Integral, 1, None, closed="left"),
                                            m.Interval(m.RealNotInt, 0, 1, closed="right")],
        "int>=2|None": lambda m: [m.Interval(Integral, 2, None, closed="left"), None],
        "stroptions": lambda m: [m.StrOptions({"a", "b", "c"})],
        "stroptions-deprecated": lambda m: [m.StrOptions({"a", "b", "c"}, deprecated={"c"})],
        "stroptions|hidden": lambda m: [m.StrOptions({"auto"}), m.Hidden(m.StrOptions({"warn"}))],
        "stroptions|dict|None": lambda m: [m.StrOptions({"balanced"}), dict, None],
        "stroptions|real>0": lambda m: [m.StrOptions({"auto", "sqrt"}), m.Interval(Real, 0, None, closed="neither")],
        "options-real": lambda m: [m.Options(Real, {-0.5, 0.5, np.inf})],
        "options-deprecated": lambda m: [m.Options(Real, {-0.5, 0.5}, deprecated={-0.5})],
        "options-type": lambda m: [m.Options(type, {np.float32, np.float64})],
        "int>=1|options{-1}": lambda m: [m.Interval(Integral, 1, None, closed="left"), m.Options(Integral, {-1})],
        "hasmethods-fit": lambda m: [m.HasMethods("fit")],
        "hasmethods-fit-predict|None": lambda m: [m.HasMethods(["fit", "predict"]), None],
        "hasmethods-split": lambda m: [m.HasMethods(["split", "get_n_splits"])],
        "array-like": lambda m: ["array-like"],
        "sparse matrix": lambda m: ["sparse matrix"],
        "array-like|sparse": lambda m: ["array-like", "sparse matrix"],
        "random_state": lambda m: ["random_state"],
        "boolean": lambda m: ["boolean"],
        "boolean|StrOptions": lambda m: ["boolean", m.StrOptions({"auto"})],
        "verbose": lambda m: ["verbose"],
        "cv_object": lambda m: ["cv_object"],
        "nan": lambda m: ["nan"],
        "real|nan": lambda m: [m.Interval(Real, 0, None, closed="left"), "nan"],
        "None": lambda m: [None],
        "callable": lambda m: [callable],
        "callable|None": lambda m: [callable, None],
        "int": lambda m: [int],
        "Integral": lambda m: [Integral],
        "Real": lambda m: [Real],
        "str": lambda m: [str],
        "list|tuple": lambda m: [list, tuple],
        "ndarray": lambda m: [np.ndarray],
        "dict|None": lambda m: [dict, None],
        "type": lambda m: [type],
        "estimator-class": lambda m: [BaseEstimator],
        "missing": lambda m: [m.MissingValues()],
        "missing-numeric": lambda m: [m.MissingValues(numeric_only=True)],
        "hidden-list|dict": lambda m: [m.Hidden(list), dict],
        "hidden-array|None": lambda m: [m.Hidden("array-like"), None],
        "hidden-only": lambda m: [m.Hidden(m.StrOptions({"x"})), m.Interval(Integral, 0, 1, closed="both")],
        "no_validation": lambda m: "no_validation",
    })
    return specs


SPECS = _specs()
NAN_FLOAT_SPECS = {
    "np.nan": lambda m: [np.nan],
    "real|np.nan": lambda m: [m.Interval(Real, 0, 1, closed="both"), np.nan],
}


class _Fit:
    def fit(self, X=None, y=None):
        return self


class _FitPredict(_Fit):
    def predict(self, X):
        return X


def _values():
    """Many values of many kinds; the same objects go to both modules."""
    return [
        -2, -1, 0, 1, 2, 3, 5, 10, 2**32 - 1, 2**32, 2**65, 2**1024, np.int64(3), np.int32(-1), np.uint8(1),
        -1.5, -1e-6, 0.0, 1e-6, 0.5, 1.0, 1.5, 2.0, 10.0, float(2**65), np.float32(0.5), np.float64(2.0),
        np.inf, -np.inf, np.nan, float("nan"), np.float32("nan"),
        True, False, np.bool_(True), np.bool_(False),
        "", "a", "b", "c", "d", "auto", "warn", "sqrt", "balanced", "x", "missing", "nan", "a string", "fit",
        None, pd.NA,
        [1, 2, 3], [], (1, 2), (), {"a": 1}, {}, {1, 2}, range(3), "abc",
        np.array([1, 2, 3]), np.array([[1.0, 2.0], [3.0, 4.0]]), np.array(5), np.array([]),
        csr_matrix([[0, 1], [1, 0]]), csr_array([[0, 1], [1, 0]]), pd.DataFrame({"a": [1, 2]}), pd.Series([1.0]),
        np.random.RandomState(0), np.random.default_rng(0),
        len, lambda x: x, int, float, str, np.float32, np.float64, dict, BaseEstimator, _Fit,
        _Fit(), _FitPredict(), LeaveOneOut(), KFold(3), [([0, 1], [2]), ([2], [0, 1])], iter([1, 2]),
        object(), type("BadType", (), {})(),
    ]


VALUES = _values()


# ------------------------------------------------------------------------------- three ways to validate
def _outcome(call):
    """``None`` when ``call()`` passes, else the error's class name (as ours is named) and message."""
    try:
        call()
    except Exception as exc:  # noqa: BLE001 - the outcome is compared, whatever it is
        return type(exc).__name__, str(exc)
    return None


def _through_validate_parameter_constraints(m, spec, value):
    return _outcome(lambda: m.validate_parameter_constraints({"p": spec}, {"p": value}, caller_name="Caller"))


def _decorated(m, spec):
    @m.validate_params({"p": spec}, prefer_skip_nested_validation=True)
    def f(p):
        return p

    return f


def _estimator(m, spec, fit_context):
    def __init__(self, p=None):
        self.p = p

    def fit(self, X=None, y=None):
        return self

    return type("Estimator", (BaseEstimator,), {
        "_parameter_constraints": {"p": spec}, "__init__": __init__,
        "fit": fit_context(prefer_skip_nested_validation=True)(fit),
    })


def _expected_upstream(outcome):
    """scikit-learn's outcome as the copy (1.9.1) gives it: ``UPSTREAM_CHANGES`` undone on an older release."""
    if outcome is not None and not _has("sparse_message"):
        return outcome[0], outcome[1].replace("a sparse matrix", "a sparse array or matrix")
    return outcome


def _mismatches(spec_id, builder, upstream):
    ours_spec, their_spec = builder(ours), builder(upstream)
    our_f, their_f = _decorated(ours, ours_spec), _decorated(upstream, their_spec)
    Ours = _estimator(ours, ours_spec, ours.fit_context)
    Theirs = _estimator(upstream, their_spec, upstream._fit_context)
    found = []
    for value in VALUES:
        for how, mine, theirs in [
            ("validate_parameter_constraints", lambda: _through_validate_parameter_constraints(ours, ours_spec, value),
             lambda: _through_validate_parameter_constraints(upstream, their_spec, value)),
            ("validate_params", lambda: _outcome(lambda: our_f(value)), lambda: _outcome(lambda: their_f(value))),
            ("estimator fit", lambda: _outcome(lambda: Ours(p=value).fit()),
             lambda: _outcome(lambda: Theirs(p=value).fit())),
        ]:
            a, b = mine(), _expected_upstream(theirs())
            if a != b:
                found.append(f"{spec_id} / {value!r} / {how}:\n    ours:   {a}\n    theirs: {b}")
            if a is not None and a[0] == "InvalidParameterError":
                assert a[1].startswith("The 'p' parameter of "), a  # the message format, whoever raised it
    return found


@pytest.mark.parametrize("spec_id", list(SPECS))
def test_the_copy_accepts_and_rejects_like_scikit_learn(spec_id, upstream):
    found = _mismatches(spec_id, SPECS[spec_id], upstream)
    assert found == [], f"{len(found)} differences from scikit-learn {sklearn.__version__}:\n" + "\n".join(found)


@pytest.mark.parametrize("spec_id", list(NAN_FLOAT_SPECS))
def test_a_float_nan_constraint_is_scikit_learn_s_since_1_7(spec_id, upstream):
    builder = NAN_FLOAT_SPECS[spec_id]
    if _has("nan_float"):
        assert _mismatches(spec_id, builder, upstream) == []
    else:  # the known difference, exactly: scikit-learn < 1.7 does not know the declaration
        with pytest.raises(ValueError, match="Unknown constraint type: nan"):
            upstream.validate_parameter_constraints({"p": builder(upstream)}, {"p": 0.5}, caller_name="C")
        ours.validate_parameter_constraints({"p": builder(ours)}, {"p": np.nan}, caller_name="C")


def test_every_kind_of_declaration_is_in_the_table():
    """The table covers each constraint class the copy's make_constraint can return."""
    made = {type(ours.make_constraint(c)).__name__
            for builder in {**SPECS, **NAN_FLOAT_SPECS}.values() if builder(ours) != "no_validation"
            for c in builder(ours)}
    kinds = {"Interval", "StrOptions", "Options", "HasMethods", "_ArrayLikes", "_SparseMatrices", "_RandomStates",
             "_Booleans", "_VerboseHelper", "_CVObjects", "_NanConstraint", "_NoneConstraint", "_Callables",
             "_InstancesOf", "MissingValues"}
    assert kinds <= made, kinds - made
    returned = {cls.__name__ for cls in vars(ours).values()
                if isinstance(cls, type) and issubclass(cls, ours._Constraint) and cls is not ours._Constraint}
    # the copy's own constraint classes that no declaration names: scikit-learn's helpers of other classes
    # (_PandasNAConstraint inside MissingValues, _IterablesNotString inside "cv_object") and ours
    assert returned - kinds == {"_PandasNAConstraint", "_IterablesNotString", "Pair", "ValueRange"}


# ---------------------------------------------------------------- one constraint at a time
def _single_constraints(builder, m):
    spec = builder(m)
    return [] if spec == "no_validation" else [m.make_constraint(c) for c in spec]


def _described(value):
    """A comparable description of a generated value."""
    if isinstance(value, np.random.RandomState):
        return "RandomState", value.get_state()[1][:4].tolist()
    if hasattr(value, "toarray"):
        return type(value).__name__, value.toarray().tolist()
    if isinstance(value, np.ndarray):
        return "ndarray", value.tolist()
    if callable(value) and not isinstance(value, type) and type(value).__name__ == "function":
        return "function", value(7)
    if type(value).__module__ in (ours.__name__, _UPSTREAM and _UPSTREAM.make_constraint.__module__):
        return type(value).__name__, sorted(m for m in dir(value) if not m.startswith("__"))
    return type(value).__name__, repr(value)


def _generated(generate, constraint):
    try:
        return _described(generate(constraint))
    except Exception as exc:  # noqa: BLE001 - compared, whatever it is (a type that needs arguments: TypeError)
        return type(exc).__name__, str(exc)


@pytest.mark.parametrize("spec_id", list(SPECS))
def test_each_constraint_is_described_satisfied_and_generated_alike(spec_id, upstream):
    pairs = list(zip(_single_constraints(SPECS[spec_id], ours), _single_constraints(SPECS[spec_id], upstream)))
    for mine, theirs in pairs:
        assert type(mine).__name__ == type(theirs).__name__
        assert mine.hidden == theirs.hidden
        expected = str(theirs) if _has("sparse_message") else str(theirs).replace("a sparse matrix",
                                                                                  "a sparse array or matrix")
        assert str(mine) == expected
        for value in VALUES:
            assert mine.is_satisfied_by(value) == theirs.is_satisfied_by(value), (str(mine), value)
        invalid = _generated(ours.generate_invalid_param_val, mine)
        assert invalid == _generated(upstream.generate_invalid_param_val, theirs), str(mine)
        valid = _generated(ours.generate_valid_param, mine)
        expected_valid = _generated(upstream.generate_valid_param, theirs)
        if not _has("sparse_valid") and expected_valid[0] == "csr_matrix":
            expected_valid = ("csr_array", expected_valid[1])
        assert valid == expected_valid, str(mine)


@pytest.mark.parametrize("kwargs", [
    dict(type=Integral, left=1.0, right=2, closed="both"),
    dict(type=Integral, left=1, right=2.0, closed="neither"),
    dict(type=Integral, left=None, right=0, closed="left"),
    dict(type=Integral, left=0, right=None, closed="right"),
    dict(type=Integral, left=1, right=-1, closed="both"),
    dict(type=Real, left=0, right=1, closed="sideways"),
    dict(type=str, left=0, right=1, closed="both"),
])
def test_bad_constraints_are_refused_alike(kwargs, upstream):
    assert _outcome(lambda: ours.Interval(**kwargs)) == _outcome(lambda: upstream.Interval(**kwargs))
    assert _outcome(lambda: ours.Interval(**kwargs)) is not None


@pytest.mark.parametrize("declaration", ["not a valid constraint", 3, [int]])
def test_unknown_declarations_are_refused_alike(declaration, upstream):
    mine = _outcome(lambda: ours.make_constraint(declaration))
    assert mine is not None and mine == _outcome(lambda: upstream.make_constraint(declaration))


def test_deprecated_options_must_be_options_alike(upstream):
    for m in (ours, upstream):
        with pytest.raises(ValueError, match="deprecated options must be a subset"):
            m.StrOptions({"a", "b"}, deprecated={"a", "z"})


def test_the_one_intended_difference_make_constraint_takes_any_constraint_object(upstream):
    """Ours passes any constraint object through (Pair, ValueRange and the like need it); scikit-learn's
    only its public classes."""
    assert isinstance(ours.make_constraint(ours._Booleans()), ours._Booleans)
    with pytest.raises(ValueError, match="Unknown constraint type"):
        upstream.make_constraint(upstream._Booleans())


def test_both_errors_are_value_and_type_errors(upstream):
    for m in (ours, upstream):
        assert issubclass(m.InvalidParameterError, ValueError) and issubclass(m.InvalidParameterError, TypeError)


@pytest.mark.parametrize("outer_prefers_skip", [True, False])
def test_nested_validation_is_skipped_across_the_two_alike(outer_prefers_skip, upstream):
    """Both read and set scikit-learn's own ``skip_parameter_validation``: an inner function of either,
    called with a bad value by an outer one of the other, is validated exactly when the outer one asks."""
    for outer_m, inner_m in ((ours, upstream), (upstream, ours)):
        @inner_m.validate_params({"a": [int]}, prefer_skip_nested_validation=True)
        def inner(a):
            return a

        @outer_m.validate_params({"b": [int]}, prefer_skip_nested_validation=outer_prefers_skip)
        def outer(b):
            return inner(a="bad")

        if outer_prefers_skip:
            assert outer(b=1) == "bad"
        else:
            with pytest.raises(inner_m.InvalidParameterError, match="The 'a' parameter of"):
                outer(b=1)
        with sklearn.config_context(skip_parameter_validation=True):
            assert outer(b="bad") == "bad"
