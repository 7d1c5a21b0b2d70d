"""Study: what the contact-profile features read of a press, against what the press holds.

On the ``everyday`` preset, per seed (object-disjoint 5-fold
``StratifiedGroupKFold`` with ``random_state=seed``: the folds of
``sklearn-hardness evaluate everyday --seed SEED``), the balanced accuracy of
a balanced logistic regression on

- the one number (:class:`~sklearn_hardness.features.PeakContactChange`:
  the ``peak_change`` baseline of ``evaluate``);
- the first ten :class:`~sklearn_hardness.features.ContactProfileFeatures`
  (the features before issue 20's loading time and contact spread), all of
  them (the ``contact_profile`` pipeline of ``evaluate``) and the three that
  read the ideal reader's quantities below (``features=THREE``: peak change,
  loading time between frames, contact spread);
- the simulator's own truth of what the gel is given, read without noise or
  codec (an ideal reader of the video): the rendered gel depth and contact
  area at the peak of the gel's indentation and the loading time (s, from
  first contact to that peak);
- what a robot's proprioception adds: the peak force and the total approach
  (sensor displacement into the object) at the peak.

The last two rows are what a press *holds*, not what a pipeline reaches:
the first is what three quantities an ideal reader of the gel would measure
give with the same head (in the simulator's physics; a reader of their whole
course might get more), the second what force and displacement tell.
A second table gives the same per object: each fold's test objects, each
classed by the mean of its presses' probabilities from the same fits (the
rule of ``evaluate``'s ``per object`` block), so that it says what several
presses of a new object tell. Beside them, how well each video feature
measures its ideal counterpart (Spearman correlation over the presses with
contact).

``--heads`` adds a third table: the twelve features with other heads on the
same folds (standardised features; balanced class weights throughout): the
logistic regression of ``make_contact_profile_pipeline(head="logistic")`` at
its default ``C=1`` and at ``C`` 0.1 and 10; the MC-dropout MLP of
``head="nn"`` (:class:`~sklearn_hardness.models.ContactProfileNNClassifier`
with its defaults, ``random_state=seed``); and two non-linear heads of
scikit-learn, a random forest and gradient boosting. Whether a head more
flexible than a linear one finds more in the features.

``--net-inputs`` adds a fourth table: what the inputs of the paper's nets, as
``evaluate`` builds them, tell of new objects with the same logistic
regression, alone and beside the twelve features (issue 20 asks whether
contact-profile features should feed the nets): the OFNN pipeline's flow
magnitude quantiles (``make_ofnn_pipeline()`` without its net) and the
ConvLSTM pipeline's intensity statistics (``make_convlstm_pipeline(
intensity_channels=True)`` without its net: each selected frame's log mean,
spread and maximum change, the values of its :class:`IntensityChannels`
channels; its :class:`FrameScaler` fitted on each fold's training presses).

    python studies/scripts/contact_profile_features.py [--seeds 0 1 2 3 4] [--n-jobs 2]
        [--variant NAME] [--param NAME=VALUE ...] [--heads] [--net-inputs] [--out FILE] [--smoke]

Prints a markdown table (one column per seed and the mean), the correlations,
time and peak memory; ``--out`` writes the same text with a provenance line. The ideal rows use the renderer's
private profile function (``sklearn_hardness.datasets._sim_everyday``): they follow it.
"""

import argparse
import time
import warnings

import _harness  # noqa: F401 - puts the repository root on sys.path
import numpy as np
from _sim_variants import VARIANTS, variant_params
from joblib import Parallel, delayed
from scipy.stats import spearmanr
from sim_vs_real_stats import parse_param, press_objects
from sklearn.linear_model import LogisticRegression
from sklearn.metrics import balanced_accuracy_score
from sklearn.model_selection import StratifiedGroupKFold
from sklearn.pipeline import make_pipeline
from sklearn.preprocessing import StandardScaler

from harness.memory import peak_rss_mb, reset_peak
from harness.provenance import report
from harness.smoke import add_smoke_argument, parse_args, tiny_presses
from sklearn_hardness.features import ContactProfileFeatures
from sklearn_hardness.models import make_named_pipeline

ROWS = ("one number (peak change)", "contact profile, first 10 features", "contact profile, 12 features",
        "contact profile, 3 features: peak change, loading time, spread",
        "ideal reader of the gel: depth, area, loading time", "force and approach (robot)")

#: The video's readings of the ideal reader's three quantities (``features=`` of ContactProfileFeatures):
#: the features of the named model ``contact_profile_3``.
THREE = tuple(make_named_pipeline("contact_profile_3").get_params()["features__features"])
#: ContactProfileFeatures' columns, in output order (it learns nothing in fit: a blank video gives them).
FEATURE_NAMES = tuple(ContactProfileFeatures().fit([np.zeros((3, 8, 8, 3), np.uint8)]).get_feature_names_out())


def video_features(videos, i):
    """The one number and the contact-profile features of video ``i`` (rendered in the worker)."""
    from sklearn_hardness.features import ContactProfileFeatures, PeakContactChange

    video = videos[i]
    return np.concatenate([PeakContactChange().fit_transform([video])[0],
                           ContactProfileFeatures().fit_transform([video])[0]])


def ideal_features(data):
    """Per press: log rendered depth and contact area at the gel's peak, log loading time, log force, log approach.

    NaN for presses whose gel is never indented (truncated videos).
    """
    # private: the simulator's own contact profile and texture (the ideal reader's quantities)
    from sklearn_hardness.datasets._sim_everyday import _profile, _texture

    p = data.params
    h, w = 120, 160  # the renderer's half-resolution grid of a 240x320 frame
    mm = p["field_of_view"] / w
    x, y = np.meshgrid((np.arange(w) - (w - 1) / 2) * mm, (np.arange(h) - (h - 1) / 2) * mm)
    rows = []
    for obj, mech in zip(press_objects(data), data.mechanics):
        gel, approach, force, t = (mech[k] for k in ("gel_indentation", "approach", "force_true", "time"))
        on = np.flatnonzero(gel > 1e-5)
        if not len(on):
            rows.append([np.nan] * 5)
            continue
        k = int(np.argmax(gel))
        prof, _ = _profile(obj, x, y, approach[k], p["dome_radius"], _texture(obj, x, y))
        area = max(np.count_nonzero(prof > 0.5), 1) * mm * mm
        depth = min(gel[k], force[k] / (p["gel_foundation_modulus"] * area))  # as the renderer caps it
        rows.append([np.log(depth), np.log(area), np.log(t[k] - t[on[0]] + 1e-3), np.log(force.max()),
                     np.log(approach[k])])
    return np.asarray(rows)


def _fitted(X, y, folds, model):
    """Per fold: its test presses and ``model`` (default: a balanced logistic regression) fitted on standardised X."""
    model = make_pipeline(StandardScaler(), model if model is not None else LogisticRegression(
        max_iter=2000, class_weight="balanced"))
    for tr, te in folds:
        yield te, model.fit(X[tr], y[tr])


def scores(X, y, folds, model=None):
    """Balanced accuracy per fold of ``model`` (default: a balanced logistic regression) on standardised ``X``."""
    return [balanced_accuracy_score(y[te], fitted.predict(X[te])) for te, fitted in _fitted(X, y, folds, model)]


def object_predictions(fitted, X, y, groups, n_classes):
    """Each object's label and class: the class of the mean of its presses' probabilities (evaluate's rule)."""
    proba = np.zeros((len(X), n_classes))
    proba[:, np.asarray(fitted.classes_, dtype=int)] = fitted.predict_proba(X)  # a class a fold lacks: 0
    _, first, index = np.unique(groups, return_index=True, return_inverse=True)
    total = np.zeros((len(first), proba.shape[1]))
    np.add.at(total, index, proba)
    return y[first], np.argmax(total, axis=1)  # an object's presses share its label


def press_and_object_scores(X, y, groups, folds):
    """Balanced accuracy per fold of the logistic regression over the test presses, and over the test objects.

    An object's class is that of the mean of its presses' probabilities, the rule of ``evaluate``'s
    ``per object`` block.
    """
    press, objects = [], []
    for te, fitted in _fitted(X, y, folds, None):
        pred = fitted.predict(X[te])
        press.append(balanced_accuracy_score(y[te], pred))
        object_y, object_pred = object_predictions(fitted, X[te], y[te], groups[te], int(y.max()) + 1)
        objects.append(balanced_accuracy_score(object_y, object_pred))
    return press, objects


def heads(seed, n_trees=300, n_rounds=200):
    """``--heads``: name -> unfitted head (standardised input; balanced class weights).

    ``n_trees``, ``n_rounds``: of the random forest and the gradient boosting (fewer in ``--smoke``).
    """
    from sklearn.ensemble import HistGradientBoostingClassifier, RandomForestClassifier

    from sklearn_hardness.models import ContactProfileNNClassifier

    def logistic(C):
        return LogisticRegression(C=C, max_iter=2000, class_weight="balanced")

    return {'logistic, C=1 (head="logistic")': logistic(1.0),
            "logistic, C=0.1": logistic(0.1),
            "logistic, C=10": logistic(10.0),
            'MC-dropout MLP (head="nn")': ContactProfileNNClassifier(class_weight="balanced", random_state=seed),
            f"random forest ({n_trees} trees, leaves >= 5)": RandomForestClassifier(
                n_trees, min_samples_leaf=5, class_weight="balanced", random_state=seed),
            f"gradient boosting (depth 3, {n_rounds} rounds)": HistGradientBoostingClassifier(
                max_depth=3, learning_rate=0.05, max_iter=n_rounds, class_weight="balanced", random_state=seed)}


NET_INPUT_ROWS = ("flow magnitude quantiles (the OFNN pipeline's input)",
                  "intensity statistics (the ConvLSTM pipeline's intensity channels)",
                  "12 features + flow magnitude quantiles", "12 features + intensity statistics")


def net_inputs(videos, n_jobs):
    """The OFNN pipeline's flow quantiles and the ConvLSTM pipeline's selected frames (before its scaler)."""
    from sklearn_hardness.models import make_convlstm_pipeline, make_ofnn_pipeline

    ofnn = make_ofnn_pipeline().set_params(frames__n_jobs=n_jobs)
    frames = make_convlstm_pipeline(intensity_channels=True).set_params(frames__n_jobs=n_jobs).named_steps["frames"]
    return ofnn[:-1].fit_transform(videos), frames.fit_transform(videos)


def intensity_statistics(train_frames, frames):
    """Per selected frame, the values of the ConvLSTM pipeline's intensity channels, its scaler fitted on
    ``train_frames``."""
    from sklearn_hardness.models import make_convlstm_pipeline

    steps = make_convlstm_pipeline(intensity_channels=True).named_steps  # its FrameScaler and IntensityChannels
    scaler = steps["scale"].fit(train_frames)
    channels = steps["intensity"].fit_transform(scaler.transform(frames))
    return channels[:, :, 0, 0, frames.shape[-1]:].reshape(len(frames), -1)  # constant maps: one pixel holds them


def net_input_scores(cp, flow, frames, y, folds):
    """Mean balanced accuracy of the logistic regression on each row of ``NET_INPUT_ROWS``."""
    intensity = [(intensity_statistics(frames[tr], frames[tr]), intensity_statistics(frames[tr], frames[te]))
                 for tr, te in folds]
    model = make_pipeline(StandardScaler(), LogisticRegression(max_iter=3000, class_weight="balanced"))

    def score(train_test):
        return float(np.mean([balanced_accuracy_score(y[te], model.fit(a, y[tr]).predict(b))
                              for (tr, te), (a, b) in zip(folds, train_test)]))

    return {NET_INPUT_ROWS[0]: score([(flow[tr], flow[te]) for tr, te in folds]),
            NET_INPUT_ROWS[1]: score(intensity),
            NET_INPUT_ROWS[2]: score([(np.hstack([cp[tr], flow[tr]]), np.hstack([cp[te], flow[te]]))
                                      for tr, te in folds]),
            NET_INPUT_ROWS[3]: score([(np.hstack([cp[tr], a]), np.hstack([cp[te], b]))
                                      for (tr, te), (a, b) in zip(folds, intensity)])}


def run_seed(seed, overrides, n_jobs, with_heads=False, with_net_inputs=False, head_sizes=()):
    from sklearn_hardness.datasets import make_presses

    data = make_presses("everyday", return_mechanics=True, random_state=seed, **overrides)
    y, groups = np.asarray(data.target), np.asarray(data.object_id)
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", UserWarning)
        V = np.vstack(Parallel(n_jobs=n_jobs)(delayed(video_features)(data.videos, i) for i in range(len(y))))
    ideal = ideal_features(data)
    folds = list(StratifiedGroupKFold(n_splits=5, shuffle=True, random_state=np.random.RandomState(seed)).split(
        np.zeros(len(y)), y, groups))
    contact = np.isfinite(ideal).all(axis=1)
    # presses without contact: the ideal rows are scored on the presses with contact of each test fold
    ideal_folds = [(tr[contact[tr]], te[contact[te]]) for tr, te in folds]
    both = {
        ROWS[0]: press_and_object_scores(V[:, :1], y, groups, folds),
        ROWS[1]: press_and_object_scores(V[:, 1:11], y, groups, folds),
        ROWS[2]: press_and_object_scores(V[:, 1:], y, groups, folds),
        ROWS[3]: press_and_object_scores(V[:, 1 + np.array([FEATURE_NAMES.index(n) for n in THREE])], y, groups, folds),
        ROWS[4]: press_and_object_scores(np.nan_to_num(ideal[:, :3]), y, groups, ideal_folds),
        ROWS[5]: press_and_object_scores(np.nan_to_num(ideal[:, 3:]), y, groups, ideal_folds),
    }
    out = {name: press for name, (press, _) in both.items()}
    per_object = {name: float(np.mean(objects)) for name, (_, objects) in both.items()}
    head_scores = {}
    if with_heads:
        head_scores = {name: float(np.mean(scores(V[:, 1:], y, folds, model)))
                       for name, model in heads(seed, *head_sizes).items()}
    net_scores = {}
    if with_net_inputs:
        with warnings.catch_warnings():
            warnings.simplefilter("ignore", UserWarning)
            flow, frames = net_inputs(data.videos, n_jobs)
        net_scores = net_input_scores(V[:, 1:], flow, frames, y, folds)
    c = contact
    corr = {"gel depth ~ log_peak_change": spearmanr(ideal[c, 0], V[c, 1])[0],
            "contact area ~ area_at_peak": spearmanr(ideal[c, 1], V[c, 6])[0],
            "contact area ~ log_contact_spread": spearmanr(ideal[c, 1], V[c, 12])[0],
            "loading time ~ rise_frames": spearmanr(ideal[c, 2], V[c, 3])[0],
            "loading time ~ log_loading_time": spearmanr(ideal[c, 2], V[c, 11])[0]}
    return ({k: float(np.mean(v)) for k, v in out.items()}, corr, int(contact.sum()), len(y), head_scores,
            net_scores, per_object)


def mean_table(first, seeds, names, per_seed):
    """Markdown rows: one per name, a column per seed (``per_seed[i][name]``) and their mean."""
    lines = [f"| {first} | " + " | ".join(f"seed {s}" for s in seeds) + " | mean |", "|---" * (len(seeds) + 2) + "|"]
    for name in names:
        vals = [scores_of[name] for scores_of in per_seed]
        lines.append(f"| {name} | " + " | ".join(f"{v:.2f}" for v in vals) + f" | {np.mean(vals):.3f} |")
    return lines


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--seeds", type=int, nargs="+", default=[0, 1, 2, 3, 4])
    ap.add_argument("--n-jobs", type=int, default=2)
    ap.add_argument("--variant", choices=sorted(VARIANTS), default=None)
    ap.add_argument("--param", type=parse_param, action="append", default=[])
    ap.add_argument("--heads", action="store_true", help="also score the twelve features with other heads")
    ap.add_argument("--net-inputs", action="store_true",
                    help="also score the paper's nets' inputs, alone and beside the twelve features")
    ap.add_argument("--out", default=None, help="write the text here, with a provenance line")
    add_smoke_argument(ap)
    args = parse_args(ap, argv, seeds=[0], n_jobs=1)
    overrides = dict(tiny_presses("everyday", args.smoke), **variant_params(args.variant, args.param))
    reset_peak()
    t0 = time.perf_counter()
    head_sizes = (10, 10) if args.smoke else ()  # --smoke: 10 trees, 10 boosting rounds
    results = [run_seed(s, overrides, args.n_jobs, args.heads, args.net_inputs, head_sizes) for s in args.seeds]
    seconds = time.perf_counter() - t0
    lines = [f"everyday preset{f' (variant {args.variant})' if args.variant else ''}"
             f"{f', overrides {overrides}' if overrides else ''}: balanced accuracy, object-disjoint 5 folds, "
             "balanced logistic regression (chance 0.33)", ""]
    lines += mean_table("input", args.seeds, ROWS, [r[0] for r in results])
    lines += ["", "The same per object: each test object classed by the mean of its presses' probabilities "
              "(evaluate's per-object rule; same folds and fits)", ""]
    lines += mean_table("input", args.seeds, ROWS, [r[6] for r in results])
    lines += ["", "How well each video feature measures its ideal counterpart (Spearman, presses with contact)", "",
              "| feature ~ ideal | " + " | ".join(f"seed {s}" for s in args.seeds) + " |",
              "|---" * (len(args.seeds) + 1) + "|"]
    for name in results[0][1]:
        lines.append(f"| {name} | " + " | ".join(f"{r[1][name]:.2f}" for r in results) + " |")
    if args.heads:
        lines += ["", "The twelve features with other heads (same folds, standardised features, balanced class "
                  "weights)", ""]
        lines += mean_table("head", args.seeds, list(results[0][4]), [r[4] for r in results])
    if args.net_inputs:
        lines += ["", "The paper's nets' inputs with the same logistic regression, alone and beside the twelve "
                  "features (same folds)", ""]
        lines += mean_table("input", args.seeds, NET_INPUT_ROWS, [r[5] for r in results])
    lines += ["", "presses with contact (ideal rows): " + ", ".join(f"{r[2]} of {r[3]}" for r in results),
              "", f"{seconds:.1f} s, peak memory {peak_rss_mb():.0f} MB"]
    text = "\n".join(lines)
    report(text, args.out)


if __name__ == "__main__":
    main()
