"""class_uncertainty: the paper's Eq. 1 and 2, BALD, validation, extreme inputs."""

import numpy as np
import pytest

from sklearn_hardness.active import class_uncertainty, variance_decomposition
from sklearn_hardness.utils._param_validation import InvalidParameterError

KINDS = ["entropy", "variance", "bald"]


def _reference(p, kind):
    """Straight transcription of the formulas with explicit loops."""
    n, l, m = p.shape
    out = np.zeros(m)
    for i in range(m):
        if kind == "entropy":
            s = 0.0
            for j in range(n):
                for k in range(l):
                    v = p[j, k, i]
                    s += 0.0 if v == 0 else v * np.log(v)
            out[i] = -s / (n * l)
        elif kind == "variance":
            mu = sum(p[j, k, i] for j in range(n) for k in range(l)) / (n * l)
            out[i] = sum((p[j, k, i] - mu) ** 2 for j in range(n) for k in range(l)) / (n * l)
        else:
            tot = 0.0
            for k in range(l):
                pbar = sum(p[j, k, i] for j in range(n)) / n
                h = 0.0 if pbar == 0 else -pbar * np.log(pbar)
                e = sum(0.0 if p[j, k, i] == 0 else p[j, k, i] * np.log(p[j, k, i]) for j in range(n)) / n
                tot += h + e
            out[i] = tot / l
    return out


def _dirichlet(rng, shape, alpha):
    n, l, m = shape
    return rng.dirichlet(np.full(m, alpha), size=(n, l))


@pytest.mark.parametrize("kind", KINDS)
@pytest.mark.parametrize("alpha", [0.05, 1.0, 20.0])
def test_matches_loop_reference(kind, alpha):
    rng = np.random.default_rng(1)
    p = _dirichlet(rng, (7, 5, 4), alpha)
    np.testing.assert_allclose(class_uncertainty(p, kind), _reference(p, kind), rtol=1e-10, atol=1e-14)


def test_known_values():
    # two passes, one test input, two classes
    p = np.array([[[0.9, 0.1]], [[0.5, 0.5]]])
    np.testing.assert_allclose(class_uncertainty(p, "variance"), [0.04, 0.04])
    h = -np.array([0.9 * np.log(0.9) + 0.5 * np.log(0.5), 0.1 * np.log(0.1) + 0.5 * np.log(0.5)]) / 2
    np.testing.assert_allclose(class_uncertainty(p, "entropy"), h)
    # BALD class 0: -0.7 log 0.7 + (0.9 log 0.9 + 0.5 log 0.5) / 2
    b0 = -0.7 * np.log(0.7) + (0.9 * np.log(0.9) + 0.5 * np.log(0.5)) / 2
    b1 = -0.3 * np.log(0.3) + (0.1 * np.log(0.1) + 0.5 * np.log(0.5)) / 2
    np.testing.assert_allclose(class_uncertainty(p, "bald"), [b0, b1])


def test_variance_pools_over_passes_and_test_inputs():
    # every pass agrees (no MC spread) but the two test inputs disagree:
    # the paper's pooled variance is > 0, BALD and the per-input variance are 0.
    p = np.tile(np.array([[[1.0, 0.0], [0.0, 1.0]]]), (5, 1, 1))
    np.testing.assert_allclose(class_uncertainty(p, "variance"), [0.25, 0.25])
    np.testing.assert_allclose(class_uncertainty(p, "bald"), [0.0, 0.0])
    np.testing.assert_allclose(p.var(axis=0).mean(axis=0), [0.0, 0.0])


def test_law_of_total_variance_documented_in_docstring():
    rng = np.random.default_rng(3)
    p = _dirichlet(rng, (20, 6, 3), 0.5)
    pooled = class_uncertainty(p, "variance")
    within = p.var(axis=0).mean(axis=0)
    between = p.mean(axis=0).var(axis=0)
    np.testing.assert_allclose(pooled, within + between)


def test_bald_sums_to_usual_bald_score():
    rng = np.random.default_rng(4)
    p = _dirichlet(rng, (30, 8, 5), 0.3)
    pbar = p.mean(axis=0)
    h_mean = -(pbar * np.log(pbar)).sum(axis=1)
    mean_h = -(p * np.log(p)).sum(axis=2).mean(axis=0)
    np.testing.assert_allclose(class_uncertainty(p, "bald").sum(), (h_mean - mean_h).mean())


@pytest.mark.parametrize("kind", KINDS)
def test_one_hot_is_certain_and_finite(kind):
    p = np.zeros((10, 4, 3))
    p[:, :, 1] = 1.0
    s = class_uncertainty(p, kind)
    assert np.all(np.isfinite(s))
    np.testing.assert_array_equal(s, 0.0)


def test_uniform():
    m = 4
    p = np.full((6, 3, m), 1.0 / m)
    np.testing.assert_allclose(class_uncertainty(p, "entropy"), np.log(m) / m)
    np.testing.assert_allclose(class_uncertainty(p, "variance"), 0.0, atol=1e-18)
    np.testing.assert_allclose(class_uncertainty(p, "bald"), 0.0, atol=1e-15)


def test_single_pass_and_single_test_input():
    rng = np.random.default_rng(0)
    one_pass = _dirichlet(rng, (1, 5, 3), 1.0)
    assert np.all(class_uncertainty(one_pass, "bald") == 0.0)
    np.testing.assert_allclose(class_uncertainty(one_pass, "variance"), one_pass[0].var(axis=0))
    one_input = _dirichlet(rng, (9, 1, 3), 1.0)
    np.testing.assert_allclose(class_uncertainty(one_input, "variance"), one_input[:, 0].var(axis=0))
    one_both = _dirichlet(rng, (1, 1, 3), 1.0)
    for kind in KINDS:
        assert np.all(np.isfinite(class_uncertainty(one_both, kind)))


@pytest.mark.parametrize("dtype", [np.float16, np.float32])
@pytest.mark.parametrize("kind", KINDS)
def test_low_precision_input_agrees_with_float64(dtype, kind):
    rng = np.random.default_rng(5)
    p64 = _dirichlet(rng, (25, 6, 5), 0.7)
    low = p64.astype(dtype)
    s = class_uncertainty(low, kind)
    assert s.dtype == np.float64
    # computed in float64 from the rounded inputs
    np.testing.assert_allclose(s, _reference(low.astype(np.float64), kind), rtol=1e-9, atol=1e-12)
    tol = 5e-3 if dtype == np.float16 else 1e-5
    np.testing.assert_allclose(s, class_uncertainty(p64, kind), atol=tol)


def test_torch_tensor_input():
    import torch

    p = torch.softmax(torch.randn(4, 3, 5), dim=-1)
    np.testing.assert_allclose(class_uncertainty(p, "entropy"), class_uncertainty(p.numpy(), "entropy"))


def test_permutation_equivariance():
    rng = np.random.default_rng(6)
    p = _dirichlet(rng, (10, 4, 5), 0.5)
    perm = rng.permutation(5)
    for kind in KINDS:
        base = class_uncertainty(p, kind)
        np.testing.assert_allclose(class_uncertainty(p[:, :, perm], kind), base[perm])
        np.testing.assert_allclose(class_uncertainty(p[::-1, ::-1], kind), base, atol=1e-15)


# ---------------------------------------------------------------- bad input
@pytest.mark.parametrize(
    "p, match",
    [
        (np.full((3, 2), 0.5), "3-D"),
        (np.full((2, 3, 2, 1), 0.5), "3-D"),
        (np.zeros((0, 3, 2)), "at least one MC pass"),
        (np.zeros((3, 0, 2)), "at least one MC pass"),
        (np.ones((3, 2, 1)), "at least 2 classes"),
        (np.array([[[0.5, np.nan]]]), "NaN"),
        (np.array([[[1.5, -0.5]]]), r"\[0, 1\]"),
        (np.array([[[0.5, 0.4]], [[0.5, 0.5]]]), "sum to 1"),
        (np.array([[[2.0, 1.0]]]), "logits"),
    ],
)
def test_bad_input(p, match):
    with pytest.raises(ValueError, match=match):
        class_uncertainty(p, "entropy")


def test_bad_kind_and_type():
    p = np.full((2, 2, 2), 0.5)
    with pytest.raises(InvalidParameterError, match="'kind' parameter of class_uncertainty"):
        class_uncertainty(p, "margin")
    with pytest.raises(InvalidParameterError, match="'atol' parameter of class_uncertainty"):
        class_uncertainty(p, "entropy", atol=-1.0)
    with pytest.raises(InvalidParameterError, match="'proba_samples' parameter of variance_decomposition"):
        variance_decomposition("p")
    with pytest.raises(TypeError, match="real numbers"):
        class_uncertainty(np.array([[["a", "b"]]]), "entropy")
    with pytest.raises(TypeError):
        class_uncertainty(None)


def test_rounding_tolerance_and_atol():
    p = np.array([[[1.0 + 5e-6, -5e-6]]])  # float32 softmax-like rounding
    s = class_uncertainty(p, "entropy")
    assert np.all(np.isfinite(s)) and np.all(s >= 0)
    with pytest.raises(ValueError, match="sum to 1"):
        class_uncertainty(np.array([[[0.5, 0.49]]]), "entropy")
    class_uncertainty(np.array([[[0.5, 0.49]]]), "entropy", atol=0.02)


def test_variance_decomposition_sums_to_eq2_and_separates_sources():
    rng = np.random.default_rng(0)
    logits = rng.normal(size=(30, 5, 4))
    p = np.exp(logits) / np.exp(logits).sum(-1, keepdims=True)
    d = variance_decomposition(p)
    np.testing.assert_allclose(d["mc"] + d["between"], class_uncertainty(p, "variance"), atol=1e-12)
    np.testing.assert_allclose(d["total"], class_uncertainty(p, "variance"), atol=1e-12)
    # identical passes: all of the variance is between presses
    same = np.repeat(p[:1], 30, axis=0)
    d = variance_decomposition(same)
    np.testing.assert_allclose(d["mc"], 0, atol=1e-15)
    np.testing.assert_allclose(d["mc_share"], 0, atol=1e-12)
    # identical presses: all of it is MC
    one = np.repeat(p[:, :1], 5, axis=1)
    d = variance_decomposition(one)
    np.testing.assert_allclose(d["between"], 0, atol=1e-15)
    np.testing.assert_allclose(d["mc_share"], 1, atol=1e-12)


def test_entropy_of_certain_predictions_is_plus_zero_and_other_values_unchanged():
    from scipy.special import xlogy

    p = np.zeros((5, 3, 4))
    p[:, :, 2] = 1.0
    s = class_uncertainty(p, "entropy")
    np.testing.assert_array_equal(s, 0.0)
    assert not np.any(np.signbit(s))  # 0.0, not -0.0
    # every other value is bit for bit the plain formula
    rng = np.random.default_rng(0)
    q = _dirichlet(rng, (7, 5, 4), 0.3)
    q[0, 0] = [0.0, 1.0, 0.0, 0.0]
    np.testing.assert_array_equal(class_uncertainty(q, "entropy"), -xlogy(q, q).mean(axis=(0, 1)))
