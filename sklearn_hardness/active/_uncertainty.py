"""Per-class uncertainty scores from Monte-Carlo-dropout predictions.

The paper (Sec. II-C, Eq. 1 and 2) scores every *class* (reference object),
not every sample: the classifier is queried ``n`` times with dropout on, on
``l`` presses of the test object, and the scores are pooled over the passes
and the presses. This module computes those scores, plus a class-wise share
of the BALD mutual information (our addition).
"""

from __future__ import annotations

from numbers import Real

import numpy as np
from scipy.special import xlogy

from ..utils._param_validation import Interval, StrOptions, validate_params

__all__ = ["class_uncertainty", "variance_decomposition", "UNCERTAINTY_KINDS"]

#: The kinds of per-class uncertainty :func:`class_uncertainty` computes.
UNCERTAINTY_KINDS = ("entropy", "variance", "bald")

# Default tolerance on "is a probability" and "rows sum to one", per input dtype:
# float16 has a 2**-11 relative precision, so a float16 softmax over a few
# classes is off by up to ~1e-3 per row.
_DEFAULT_ATOL = {np.dtype(np.float16): 1e-2}
_FALLBACK_ATOL = 1e-4


def check_proba_samples(proba_samples, *, atol=None, name="proba_samples"):
    """Validate MC-dropout probabilities and return them as float64.

    Parameters
    ----------
    proba_samples : array-like of shape (n_samples, n_X, n_classes)
        Class probabilities of ``n_samples`` stochastic forward passes on
        ``n_X`` inputs.
    atol : float or None
        Tolerance for values outside ``[0, 1]`` and for rows not summing to
        one. ``None`` picks ``1e-2`` for float16 input and ``1e-4`` otherwise.
    name : str
        How the array is called in error messages.

    Returns
    -------
    proba : ndarray of shape (n_samples, n_X, n_classes), float64
        The probabilities clipped to ``[0, 1]`` (values within ``atol``
        outside it are rounding errors), not renormalised.
    """
    if isinstance(proba_samples, (str, bytes)) or proba_samples is None:
        raise TypeError(
            f"{name} must be an array of shape (n_samples, n_X, n_classes), "
            f"got {type(proba_samples).__name__}."
        )
    if hasattr(proba_samples, "detach"):  # torch tensor, possibly on a GPU
        proba_samples = proba_samples.detach().cpu().numpy()
    arr = np.asarray(proba_samples)
    if arr.dtype == object or not (
        np.issubdtype(arr.dtype, np.floating)
        or np.issubdtype(arr.dtype, np.integer)
        or arr.dtype == bool
    ):
        raise TypeError(
            f"{name} must hold real numbers (float16, float32 or float64 "
            f"probabilities), got dtype {arr.dtype}."
        )
    if arr.ndim != 3:
        raise ValueError(
            f"{name} must be 3-D with shape (n_samples, n_X, n_classes) "
            f"(MC passes, test inputs, classes), got shape {arr.shape}. "
            "Use predict_proba_samples(X, n_samples=...) to make it."
        )
    n_samples, n_x, n_classes = arr.shape
    if n_samples < 1 or n_x < 1:
        raise ValueError(
            f"{name} needs at least one MC pass and one test input, got shape "
            f"{arr.shape} (n_samples={n_samples}, n_X={n_x})."
        )
    if n_classes < 2:
        raise ValueError(
            f"{name} needs at least 2 classes, got n_classes={n_classes} "
            f"(shape {arr.shape})."
        )
    if atol is None:
        atol = _DEFAULT_ATOL.get(arr.dtype, _FALLBACK_ATOL)
    proba = arr.astype(np.float64)  # always a copy: we clip in place below
    if not np.all(np.isfinite(proba)):
        raise ValueError(f"{name} contains NaN or infinite values.")
    lo, hi = proba.min(), proba.max()
    if lo < -atol or hi > 1 + atol:
        raise ValueError(
            f"{name} must hold probabilities in [0, 1], got values in "
            f"[{lo:.6g}, {hi:.6g}]. Pass probabilities (softmax output), not logits."
        )
    row_sums = proba.sum(axis=2)
    worst = np.abs(row_sums - 1.0).max()
    if worst > atol:
        j, k = np.unravel_index(np.abs(row_sums - 1.0).argmax(), row_sums.shape)
        raise ValueError(
            f"{name} rows must sum to 1 over the class axis (last axis) within "
            f"atol={atol:g}; pass {j}, input {k} sums to {row_sums[j, k]:.6g}."
        )
    np.clip(proba, 0.0, 1.0, out=proba)
    return proba


@validate_params(
    {
        "proba_samples": ["array-like"],
        "kind": [StrOptions(set(UNCERTAINTY_KINDS))],
        "atol": [Interval(Real, 0, None, closed="left"), None],
    },
    prefer_skip_nested_validation=True,
)
def class_uncertainty(proba_samples, kind="entropy", *, atol=None):
    r"""Per-class uncertainty of Monte-Carlo-dropout predictions.

    Scores each class (reference object) from ``n`` stochastic forward passes
    (dropout on) over ``l`` test inputs, pooling passes and inputs as in the
    paper (Sec. II-C). With :math:`p_{ijk}` the probability of class
    :math:`i` in pass :math:`j` for test input :math:`k`:

    ``"entropy"`` (Eq. 1)
        :math:`H_i = -\frac{1}{nl}\sum_{j,k} p_{ijk}\log p_{ijk}`,
        with :math:`0 \log 0 = 0` (:func:`scipy.special.xlogy`). Natural log;
        each score lies in :math:`[0, 1/e]`.

    ``"variance"`` (Eq. 2)
        :math:`\mathrm{Var}_i = \frac{1}{nl}\sum_{j,k}(p_{ijk}-\mu_i)^2` with
        :math:`\mu_i = \frac{1}{nl}\sum_{j,k} p_{ijk}`. As in the paper, the
        variance is pooled over passes *and* test inputs, so by the law of
        total variance it equals the mean over inputs of the across-pass
        variance (the model's MC-dropout spread) plus the across-input
        variance of the per-input mean probability (how differently the test
        presses are classified). The purely epistemic alternative,
        :math:`\frac{1}{l}\sum_k \mathrm{Var}_j(p_{ijk})`, is the first term
        alone; compute it with ``proba_samples.var(axis=0).mean(axis=0)``.
        Each score lies in :math:`[0, 1/4]`.

    ``"bald"`` (our addition)
        The class-wise share of the BALD score (the mutual information
        between the prediction and the model parameters, Houlsby et al.
        2011), averaged over test inputs. With
        :math:`\bar p_{ik} = \frac{1}{n}\sum_j p_{ijk}`,

        .. math::

            B_i = \frac{1}{l}\sum_k \Big[-\bar p_{ik}\log\bar p_{ik}
                  + \frac{1}{n}\sum_j p_{ijk}\log p_{ijk}\Big].

        Summed over classes, :math:`\sum_i B_i` is the usual BALD score
        :math:`\mathbb{H}[\bar p_{\cdot k}] - \frac{1}{n}\sum_j
        \mathbb{H}[p_{\cdot jk}]` averaged over inputs. Each term is
        non-negative by Jensen's inequality (:math:`x\log x` is convex),
        so :math:`B_i \in [0, 1/e]`; rounding noise below zero is clipped
        to 0. It is zero with a single MC pass or when all passes agree,
        so unlike the pooled variance it ignores disagreement *between*
        test inputs.

    Parameters
    ----------
    proba_samples : array-like of shape (n_samples, n_X, n_classes)
        Class probabilities of ``n_samples`` MC-dropout passes on ``n_X``
        test inputs, e.g. the output of
        ``clf.predict_proba_samples(X_test, n_samples=50)``. float16,
        float32 and float64 (and torch tensors) are accepted; the scores
        are computed in float64.
    kind : {"entropy", "variance", "bald"}, default="entropy"
        Which score to compute.
    atol : float, default=None
        Tolerance for probabilities outside ``[0, 1]`` and rows not summing
        to one. ``None`` uses ``1e-2`` for float16 input and ``1e-4``
        otherwise. Values within the tolerance outside ``[0, 1]`` are
        clipped; rows are not renormalised.

    Returns
    -------
    scores : ndarray of shape (n_classes,), float64
        One score per class; higher means more uncertain.

    Raises
    ------
    ValueError
        If ``kind`` is unknown, ``atol`` negative or ``proba_samples`` not
        array-like (an ``InvalidParameterError``, with scikit-learn's message
        format, which is also a TypeError).
    ValueError
        If the array is not 3-D, has fewer than two classes, contains
        NaN/inf, values outside ``[0, 1]`` or rows that do not sum to one.
    TypeError
        If the array is not numeric.

    See Also
    --------
    entropy_sampling, variance_sampling, bald_sampling :
        Strategies that pick the classes with the highest scores.
    variance_decomposition : Eq. 2 split into its MC and between-press parts.

    Examples
    --------
    >>> import numpy as np
    >>> from sklearn_hardness.active import class_uncertainty
    >>> p = np.array([[[0.9, 0.1]], [[0.5, 0.5]]])  # 2 passes, 1 input, 2 classes
    >>> class_uncertainty(p, "variance")
    array([0.04, 0.04])
    >>> class_uncertainty(p, "entropy").round(4)
    array([0.2207, 0.2884])
    """
    p = check_proba_samples(proba_samples, atol=atol)
    if kind == "entropy":
        return -xlogy(p, p).mean(axis=(0, 1)) + 0.0  # + 0.0: 0, not -0.0, when certain
    if kind == "variance":
        # two-pass variance about the pooled class mean mu_i (Eq. 2)
        mu = p.mean(axis=(0, 1))
        return ((p - mu) ** 2).mean(axis=(0, 1))
    # kind == "bald"
    p_bar = p.mean(axis=0)  # (n_X, n_classes)
    term = -xlogy(p_bar, p_bar) + xlogy(p, p).mean(axis=0)
    return np.maximum(term.mean(axis=0), 0.0)


@validate_params(
    {
        "proba_samples": ["array-like"],
        "atol": [Interval(Real, 0, None, closed="left"), None],
    },
    prefer_skip_nested_validation=True,
)
def variance_decomposition(proba_samples, *, atol=None):
    r"""Split the paper's pooled variance (Eq. 2) into its MC and between-press parts.

    With :math:`p_{ijk}` the probability of class :math:`i` in MC pass
    :math:`j` for test press :math:`k`, :math:`m_{ik} = \frac{1}{n}\sum_j
    p_{ijk}` the press's mean over passes and :math:`\mu_i` the pooled mean,
    the law of total variance splits Eq. 2 exactly:

    .. math::

        \mathrm{Var}_i
        = \underbrace{\frac{1}{l}\sum_k \frac{1}{n}\sum_j (p_{ijk} - m_{ik})^2}_{\text{MC part}}
        + \underbrace{\frac{1}{l}\sum_k (m_{ik} - \mu_i)^2}_{\text{between-press part}}.

    The MC part is the model's own (epistemic) spread under dropout; the
    between-press part is how differently the test presses are classified,
    which stays when dropout is off. A query driven by the second part is
    not driven by the model's uncertainty.

    Parameters
    ----------
    proba_samples : array-like of shape (n_samples, n_X, n_classes)
        Class probabilities of ``n_samples`` MC-dropout passes on ``n_X``
        test presses, e.g. ``clf.predict_proba_samples(X_test)``.
    atol : float, default=None
        Tolerance on probabilities, as in :func:`class_uncertainty`.

    Returns
    -------
    decomposition : dict of ndarray of shape (n_classes,)
        ``"total"`` (Eq. 2, equal to ``class_uncertainty(p, "variance")``),
        ``"mc"`` and ``"between"`` (the two parts, summing to ``"total"``)
        and ``"mc_share"`` (``mc / total``, 0 where ``total`` is 0).

    See Also
    --------
    class_uncertainty : the pooled scores themselves.

    Examples
    --------
    >>> import numpy as np
    >>> from sklearn_hardness.active import variance_decomposition
    >>> p = np.array([[[0.9, 0.1], [0.5, 0.5]],
    ...               [[0.7, 0.3], [0.5, 0.5]]])  # 2 passes, 2 presses, 2 classes
    >>> d = variance_decomposition(p)
    >>> d["mc"], d["between"], d["total"]
    (array([0.005, 0.005]), array([0.0225, 0.0225]), array([0.0275, 0.0275]))
    """
    p = check_proba_samples(proba_samples, atol=atol)
    m = p.mean(axis=0)  # (n_X, n_classes): per-press mean over passes
    mc = ((p - m) ** 2).mean(axis=(0, 1))
    between = ((m - m.mean(axis=0)) ** 2).mean(axis=0)
    total = mc + between
    with np.errstate(invalid="ignore", divide="ignore"):
        share = np.where(total > 0, mc / np.where(total > 0, total, 1.0), 0.0)
    return {"total": total, "mc": mc, "between": between, "mc_share": share}
