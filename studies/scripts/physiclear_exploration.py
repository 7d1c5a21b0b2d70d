"""Exploration before the plan: what reads the hardness of new objects from real presses?

Usage::

    python studies/scripts/physiclear_exploration.py --data DATA [--cnn] [--out OUT] [--cache DIR] [--smoke]

Every variant tried while looking for a model that reads the imprint (its texture,
its appearance, its geometry) is run here, on the presses of the public set's
train and val objects among the development objects (42 objects, 231 presses): the
split's 7 test objects are left out, so that nothing here is chosen on them.
Folds: :class:`~sklearn.model_selection.StratifiedGroupKFold` grouped by
``family`` (the parts of one object stay on one side), 5 folds x 5 repetitions,
one stream seeded 0 (the CNN: the first 5 folds). Balanced accuracy per press
(mean ± standard deviation over folds), accuracy per press and balanced accuracy
per object (the mean of its presses' probabilities).

The descriptors (texture of the change at the half-rise and peak frames: local
binary patterns, co-occurrence, Gabor energies, radial spectrum, colour; the
imprint's own LBP; timing) are computed here by the exploration's own code, the
one that was run; the library's :class:`~sklearn_hardness.features.ImprintTextureFeatures`
was built from it afterwards. The contact geometry is also read at twice the resolution (160 px on the long side,
``sigma=2``). The CNN (``--cnn``) is a small one trained from
scratch on every frame of the loading phase (60x80, 8 epochs, flips, gain,
shifts and noise), probabilities pooled per press. ``--smoke``: 2 folds once, 10 trees and boosting rounds,
the CNN one epoch on one fold, with the global scale only.
"""

from __future__ import annotations

import argparse
import re
import sys
import time
import warnings

import _harness  # noqa: F401 - puts the repository root on sys.path
import cv2
import numpy as np
from _physiclear import load_development
from joblib import Parallel, delayed
from scipy.optimize import minimize
from scipy.special import expit
from skimage.feature import graycomatrix, graycoprops, local_binary_pattern
from sklearn.base import BaseEstimator, ClassifierMixin, clone
from sklearn.compose import ColumnTransformer
from sklearn.ensemble import HistGradientBoostingClassifier, RandomForestClassifier, VotingClassifier
from sklearn.linear_model import LogisticRegression
from sklearn.metrics import accuracy_score, balanced_accuracy_score
from sklearn.model_selection import StratifiedGroupKFold
from sklearn.pipeline import make_pipeline
from sklearn.preprocessing import StandardScaler

from harness.provenance import report
from harness.smoke import add_smoke_argument, parse_args
from sklearn_hardness.features import ContactGeometryFeatures, ContactProfileFeatures
from sklearn_hardness.features._loading_moments import loading_moments  # the features' own moments

#: The twelve scale-free geometry features (``contact_geometry``'s input).
SCALE_FREE = ("half_depth_area", "edge_sharpness", "shoulder_ratio", "eccentricity", "texture_ratio",
              "gradient_share", "area_depth_slope", "spread_depth_slope", "sharpness_depth_slope",
              "texture_depth_slope", "early_area_share", "early_depth_share")
GEOMETRY_SF = "^geom_(" + "|".join(SCALE_FREE) + ")$"


# --- descriptors of one press -------------------------------------------------------------------------

def _lbp_hist(grey, points, radius, mask=None):
    code = local_binary_pattern(grey, points, radius, method="uniform")
    values = code[mask] if mask is not None and mask.sum() > 50 else code.ravel()
    hist = np.bincount(values.astype(int), minlength=points + 2)[: points + 2].astype(float)
    return hist / max(hist.sum(), 1)


def _glcm(quantised, levels=32):
    m = graycomatrix(quantised, distances=[1, 2, 4, 8], angles=[0, np.pi / 4, np.pi / 2, 3 * np.pi / 4],
                     levels=levels, symmetric=True, normed=True)
    return [v for p in ("contrast", "homogeneity", "energy", "correlation", "dissimilarity")
            for v in graycoprops(m, p).mean(axis=1)]


def _radial_spectrum(grey, n_bands=10):
    h, w = grey.shape
    window = np.outer(np.hanning(h), np.hanning(w))
    power = np.abs(np.fft.fftshift(np.fft.fft2((grey - grey.mean()) * window))) ** 2
    yy, xx = np.mgrid[0:h, 0:w]
    r = np.hypot((yy - h / 2) / h, (xx - w / 2) / w)
    edges = np.geomspace(0.01, 0.5, n_bands + 1)
    bands = np.array([power[(r >= a) & (r < b)].mean() for a, b in zip(edges[:-1], edges[1:])])
    return list(np.log(bands + 1e-9) - np.log(bands.sum() + 1e-9)), float(np.log(bands.sum() + 1e-9))


def _gabor(grey):
    energy, aniso = [], []
    for lam in (4, 8, 16, 32):
        resp = []
        for theta in np.arange(4) * np.pi / 4:
            k = cv2.getGaborKernel((0, 0), sigma=0.56 * lam, theta=theta, lambd=lam, gamma=0.5, psi=0,
                                   ktype=cv2.CV_32F)
            resp.append(np.abs(cv2.filter2D(grey, cv2.CV_32F, k - k.mean())).mean())
        resp = np.array(resp)
        energy.append(resp.mean())
        aniso.append(resp.max() / max(resp.min(), 1e-6))
    energy = np.array(energy)
    return list(np.log(energy / energy.sum() + 1e-9)) + list(np.log(aniso)), float(np.log(energy.sum() + 1e-9))


def _change_descriptors(d, tag):
    """The exploration's descriptors of one change image ``d`` (h, w, 3), names prefixed by ``tag``."""
    d = d - np.median(d.reshape(-1, 3), axis=0)
    mag = np.sqrt((d ** 2).sum(-1))
    grey = d.mean(-1)
    noise = 1.4826 * np.median(np.abs(mag - np.median(mag))) + 1e-3
    mask = cv2.GaussianBlur(mag, (0, 0), 3) > np.median(mag) + 3 * noise
    scale = np.percentile(np.abs(grey), 99) + 1e-6
    grey_q = np.clip((grey / scale + 1) * 16, 0, 31).astype(np.uint8)
    mag_q = np.clip(mag / (np.percentile(mag, 99) + 1e-6) * 31, 0, 31).astype(np.uint8)
    spectrum, power = _radial_spectrum(grey)
    gabor, gabor_total = _gabor(grey.astype(np.float32))
    gradient = np.hypot(cv2.Sobel(grey, cv2.CV_32F, 1, 0), cv2.Sobel(grey, cv2.CV_32F, 0, 1))
    u = (d[..., 0] - d[..., 1]) / np.sqrt(2)
    v = (d[..., 0] + d[..., 1] - 2 * d[..., 2]) / np.sqrt(6)
    hue = np.histogram(np.arctan2(v, u), bins=8, range=(-np.pi, np.pi), weights=np.hypot(u, v))[0]
    chroma = d - d.mean(-1, keepdims=True)
    colour = [float((chroma ** 2).sum() / max((mag ** 2).sum(), 1e-6))]
    colour += list((d.reshape(-1, 3) ** 2).mean(0) / max((mag ** 2).mean(), 1e-6))
    colour += list(hue / max(hue.sum(), 1e-9))
    out = {
        f"{tag}_int_log_mean": np.log(mag.mean() + 1e-3),
        f"{tag}_int_log_p99": np.log(np.percentile(mag, 99) + 1e-3),
        f"{tag}_int_log_ptot": power,
        f"{tag}_int_log_gabtot": gabor_total,
        f"{tag}_int_area": float(mask.mean()),
        f"{tag}_int_p99_over_mean": np.log(np.percentile(mag, 99) / (mag.mean() + 1e-3)),
        f"{tag}_int_grad_ratio": np.log(np.percentile(gradient, 99) / (np.percentile(np.abs(grey), 99) + 1e-3)),
        f"{tag}_int_grad_p50_p99": np.log((np.percentile(gradient, 50) + 1e-3) / (np.percentile(gradient, 99) + 1e-3)),
        f"{tag}_int_kurt": float(((grey - grey.mean()) ** 4).mean() / (grey.var() ** 2 + 1e-9)),
    }
    out.update({f"{tag}_spec_{j}": v for j, v in enumerate(spectrum)})
    out.update({f"{tag}_gabor_{j}": v for j, v in enumerate(gabor)})
    lbp = np.concatenate([_lbp_hist(grey_q, 8, 1, mask), _lbp_hist(grey_q, 16, 2, mask), _lbp_hist(grey_q, 8, 3)])
    out.update({f"{tag}_lbp_{j}": v for j, v in enumerate(lbp)})
    out.update({f"{tag}_glcm_{j}": v for j, v in enumerate(_glcm(mag_q))})
    out.update({f"{tag}_col_{j}": v for j, v in enumerate(colour)})
    return out, mask


def _press_descriptors(video):
    """Descriptors of one press and its frames of the loading phase at 60x80 (for the CNN)."""
    video = np.asarray(video, dtype=np.float32)
    small = np.stack([cv2.resize(f, (80, 60), interpolation=cv2.INTER_AREA) for f in video])
    moments = loading_moments(small, (0.25, 0.5, 1.0))
    if moments is None:
        raise ValueError("a press without change: the exploration assumed every press has one")
    ref = video[:moments.n_pre].mean(axis=0)
    quarter, half, peak = moments.frames
    row, mask = _change_descriptors(video[peak] - ref, "pk")
    row.update(_change_descriptors(video[half] - ref, "mid")[0])
    raw = video[peak].mean(-1)
    raw_q = np.clip((raw - raw.min()) / (np.ptp(raw) + 1e-6) * 31, 0, 31).astype(np.uint8)
    row.update({f"raw_lbp_{j}": v for j, v in enumerate(_lbp_hist(raw_q, 8, 1, mask))})
    row["time_loading"] = float(peak - quarter)
    row["time_t"] = float(len(video))
    row["time_rise_ratio"] = float((half - quarter + 1) / (peak - quarter + 1))
    small = []
    for k in range(quarter, min(len(video), peak + 5)):
        d = video[k] - ref
        d -= np.median(d.reshape(-1, 3), axis=0)
        small.append(cv2.resize(d, (80, 60), interpolation=cv2.INTER_AREA))
    return row, np.stack(small).astype(np.float16)


def _features(data, n_jobs):
    out = Parallel(n_jobs=n_jobs)(delayed(_press_descriptors)(data.videos[i]) for i in range(len(data.target)))
    names = list(out[0][0])
    X = np.array([[row[n] for n in names] for row, _ in out])
    geometry = ContactGeometryFeatures(n_jobs=n_jobs).fit(data.videos[:1])
    fine = ContactGeometryFeatures(max_side=160, sigma=2.0, n_jobs=n_jobs).fit(data.videos[:1])
    profile = ContactProfileFeatures(n_jobs=n_jobs).fit(data.videos[:1])
    names += ["geom_" + n for n in geometry.get_feature_names_out()]
    names += ["geom160_" + n for n in fine.get_feature_names_out()]
    names += ["prof_" + n for n in profile.get_feature_names_out()]
    X = np.hstack([X, geometry.transform(data.videos), fine.transform(data.videos), profile.transform(data.videos)])
    return X, np.array(names), [frames for _, frames in out]


# --- classifiers tried ---------------------------------------------------------------------------------

class OrdinalLogisticRegression(ClassifierMixin, BaseEstimator):
    """Cumulative-link (all-threshold) logistic regression, L2 penalty, balanced weights: the ranks' order."""

    def __init__(self, C=1.0):
        self.C = C

    def fit(self, X, y):
        X, y = np.asarray(X, float), np.asarray(y)
        self.classes_ = np.unique(y)
        k, (n, d) = len(self.classes_), X.shape
        yi = np.searchsorted(self.classes_, y)
        w = (n / (k * np.bincount(yi, minlength=k)))[yi]

        def loss(p):
            beta, cuts = p[:d], np.cumsum(np.concatenate([[p[d]], np.exp(p[d + 1:])]))
            cdf = np.column_stack([np.zeros(n), expit(cuts[None, :] - (X @ beta)[:, None]), np.ones(n)])
            pr = cdf[np.arange(n), yi + 1] - cdf[np.arange(n), yi]
            return -(w * np.log(np.clip(pr, 1e-12, None))).sum() / n + 0.5 / (self.C * n) * beta @ beta

        p0 = np.zeros(d + k - 1)
        p0[d] = -1.0
        x = minimize(loss, p0, method="L-BFGS-B").x
        self.coef_, self.cuts_ = x[:d], np.cumsum(np.concatenate([[x[d]], np.exp(x[d + 1:])]))
        return self

    def predict_proba(self, X):
        s = np.asarray(X, float) @ self.coef_
        cdf = np.column_stack([np.zeros(len(s)), expit(self.cuts_[None, :] - s[:, None]), np.ones(len(s))])
        return np.diff(cdf, axis=1)

    def predict(self, X):
        return self.classes_[self.predict_proba(X).argmax(1)]


def _columns(names, pattern):
    return np.flatnonzero([bool(re.search(pattern, n)) for n in names])


def _logistic(names, pattern, C, class_weight="balanced", head=None):
    head = head or LogisticRegression(C=C, class_weight=class_weight, max_iter=3000)
    return make_pipeline(ColumnTransformer([("scale", StandardScaler(), _columns(names, pattern))]), head)


def _scores(y, objects, folds, proba):
    """Per press balanced accuracy and accuracy, per object balanced accuracy, over ``folds``."""
    ba, acc, oba = [], [], []
    for (_, test), p in zip(folds, proba):
        pred = p.argmax(1)
        ba.append(balanced_accuracy_score(y[test], pred))
        acc.append(accuracy_score(y[test], pred))
        names, index = np.unique(objects[test], return_inverse=True)
        total = np.zeros((len(names), p.shape[1]))
        np.add.at(total, index, p)
        first = [np.flatnonzero(index == j)[0] for j in range(len(names))]
        oba.append(balanced_accuracy_score(y[test][first], total.argmax(1)))
    return np.mean(ba), np.std(ba), np.mean(acc), np.mean(oba)


def _cross_val(estimator, X, y, folds):
    proba = []
    for train, test in folds:
        with warnings.catch_warnings():
            warnings.simplefilter("ignore")
            proba.append(clone(estimator).fit(X[train], y[train]).predict_proba(X[test]))
    return proba


def _variants(names, n_trees=500, n_rounds=200):
    """Every feature-and-head variant tried, in the order they were tried: (label, estimator).

    ``n_trees``, ``n_rounds``: of the random forests and the gradient boosting (fewer in ``--smoke``).
    """
    out = []
    families = {"one number (peak change)": r"^pk_int_log_mean$", "intensity": r"^pk_int_",
                "spectrum": r"^pk_spec_", "Gabor": r"^pk_gabor_", "LBP": r"^pk_lbp_", "co-occurrence": r"^pk_glcm_",
                "colour": r"^pk_col_", "imprint LBP": r"^raw_lbp_", "timing": r"^time_",
                "all peak descriptors": r"^pk_", "all descriptors": r"^(pk|mid|raw|time)_"}
    for label, pattern in families.items():
        for C in (0.01, 0.1, 1.0):
            out.append((f"{label}, logistic C={C}", _logistic(names, pattern, C)))
    votes = [r"pk_int_log_mean$", r"^pk_spec_", r"^pk_lbp_", r"^pk_glcm_", r"^pk_col_", r"^mid_spec_", r"^mid_lbp_",
             r"^mid_glcm_"]
    for cw in ("balanced", None):
        out.append((f"soft vote of 8 descriptor families, class_weight={cw}",
                    VotingClassifier([(f"f{i}", _logistic(names, p, 0.1, cw)) for i, p in enumerate(votes)],
                                     voting="soft")))
    out.append(("one number, unweighted", _logistic(names, r"^pk_int_log_mean$", 1.0, None)))
    for label, pattern in (("peak descriptors", r"^pk_"), ("all descriptors", r"^(pk|mid|raw|time)_")):
        cols = _columns(names, pattern)
        pick = ColumnTransformer([("keep", "passthrough", cols)])
        out.append((f"random forest, {label}", make_pipeline(pick, RandomForestClassifier(
            n_trees, min_samples_leaf=3, class_weight="balanced", random_state=0, n_jobs=1))))
        out.append((f"gradient boosting, {label}", make_pipeline(pick, HistGradientBoostingClassifier(
            max_depth=3, learning_rate=0.05, max_iter=n_rounds, class_weight="balanced", random_state=0))))
    out.append(("geometry scale-free (contact_geometry)", _logistic(names, GEOMETRY_SF, 1.0)))
    out.append(("geometry all 17", _logistic(names, r"^geom_", 1.0)))
    out.append(("contact profile 12", _logistic(names, r"^prof_", 1.0)))
    out.append(("soft vote: geometry scale-free + spectrum + co-occurrence", VotingClassifier(
        [("g", _logistic(names, GEOMETRY_SF, 1.0)), ("s", _logistic(names, r"^pk_spec_", 0.1)),
         ("c", _logistic(names, r"^pk_glcm_", 0.1))], voting="soft")))
    for C in (0.1, 1.0, 10.0):
        for label, pattern in (("geometry scale-free", GEOMETRY_SF),
                               ("geometry scale-free + one number", GEOMETRY_SF + r"|^pk_int_log_mean$"),
                               ("geometry all 17", r"^geom_")):
            out.append((f"{label}, multinomial C={C}", _logistic(names, pattern, C)))
            out.append((f"{label}, ordinal C={C}", _logistic(names, pattern, C,
                                                             head=OrdinalLogisticRegression(C=C))))
    out.append(("geometry scale-free, unweighted", _logistic(names, GEOMETRY_SF, 1.0, None)))
    out.append(("geometry scale-free at 160 px (sigma 2), multinomial C=1.0",
                _logistic(names, GEOMETRY_SF.replace("^geom_", "^geom160_"), 1.0)))
    return out


# --- the CNN -------------------------------------------------------------------------------------------

def _cnn_proba(frames, y, train, test, normalise, seed, epochs=8):
    import torch
    import torch.nn as nn
    import torch.nn.functional as F

    torch.manual_seed(seed)
    rng = np.random.RandomState(seed)

    def prepared(i):
        f = frames[i].astype(np.float32)
        if normalise == "per image":
            f = f / (np.percentile(np.abs(f).reshape(len(f), -1), 99, axis=1)[:, None, None, None] + 0.5)
        else:
            f = f / 4.0
        return torch.from_numpy(np.ascontiguousarray(f.transpose(0, 3, 1, 2)))

    class Net(nn.Module):
        def __init__(self, w=16):
            super().__init__()
            ch = [3, w, 2 * w, 4 * w, 4 * w]
            self.convs = nn.ModuleList(nn.Conv2d(a, b, 3, padding=1) for a, b in zip(ch[:-1], ch[1:]))
            self.norms = nn.ModuleList(nn.BatchNorm2d(b) for b in ch[1:])
            self.drop, self.fc = nn.Dropout(0.3), nn.Linear(ch[-1], 3)

        def forward(self, x):
            for i, (conv, norm) in enumerate(zip(self.convs, self.norms)):
                x = F.relu(norm(conv(x)))
                if i < 3:
                    x = F.max_pool2d(x, 2)
            return self.fc(self.drop(x.mean((2, 3))))

    X_train = torch.cat([prepared(i) for i in train])
    y_train = torch.tensor(np.concatenate([[y[i]] * len(frames[i]) for i in train]))
    weight = torch.tensor(1.0 / np.bincount(y_train.numpy(), minlength=3), dtype=torch.float32)
    net = Net()
    opt = torch.optim.AdamW(net.parameters(), 2e-3, weight_decay=1e-3)
    n, bs = len(X_train), 64
    sched = torch.optim.lr_scheduler.OneCycleLR(opt, 3e-3, total_steps=epochs * ((n + bs - 1) // bs))
    for _ in range(epochs):
        net.train()
        order = torch.randperm(n)
        for b in range(0, n, bs):
            idx = order[b:b + bs]
            xb = X_train[idx]
            if rng.rand() < 0.5:
                xb = xb.flip(3)
            if rng.rand() < 0.5:
                xb = xb.flip(2)
            xb = xb * torch.exp(0.3 * torch.randn(len(xb), 1, 1, 1)) + 0.05 * torch.randn_like(xb)
            xb = torch.roll(xb, (rng.randint(-7, 8), rng.randint(-10, 11)), (2, 3))
            loss = F.cross_entropy(net(xb), y_train[idx], weight=weight / weight.sum() * 3)
            opt.zero_grad()
            loss.backward()
            opt.step()
            sched.step()
    net.eval()
    with torch.no_grad():
        return np.array([F.softmax(net(prepared(i)), 1).mean(0).numpy() for i in test])


def main(argv=None):
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--data", required=True, help="a local copy of the public set (or the development manifest)")
    parser.add_argument("--cnn", action="store_true", help="also the two CNN runs (about 20 min each on 2 cores)")
    parser.add_argument("--n-jobs", type=int, default=2)
    parser.add_argument("--out", help="write the tables here too, under the harness's header")
    add_smoke_argument(parser)
    args = parse_args(parser, argv, n_jobs=1)
    n_splits, n_repeats, cnn_folds, cnn_epochs = (2, 1, 1, 1) if args.smoke else (5, 5, 5, 8)
    t0 = time.perf_counter()
    data = load_development(args.data)
    split = getattr(data, "split", None)
    split = np.asarray(split if split is not None else [""] * len(data.target))
    keep = np.flatnonzero(np.isin(split, ["train", "val"]))
    if keep.size == 0:
        raise SystemExit("the data holds no split (train/val/test): pass the public set's folder, not a manifest.")
    from sklearn.utils import Bunch
    sub = Bunch(videos=[data.videos[i] for i in keep], target=np.asarray(data.target)[keep])
    y, family, objects = sub.target, np.asarray(data.family)[keep], np.asarray(data.object_id)[keep]
    X, names, frames = _features(sub, args.n_jobs)
    rng = np.random.RandomState(0)
    folds = [f for _ in range(n_repeats)
             for f in StratifiedGroupKFold(n_splits, shuffle=True, random_state=rng).split(X, y, family)]
    lines = [f"{len(y)} presses of {len(set(objects))} objects ({len(set(family))} families; split train+val), "
             f"classes {dict(zip(data.target_names, np.bincount(y, minlength=3).tolist()))}; family-grouped "
             "5 x 5 folds, seed 0", "",
             f"{'variant':70s} {'BA per press':>16s} {'accuracy':>9s} {'BA per object':>14s}"]
    for label, estimator in _variants(names, *((10, 10) if args.smoke else ())):
        ba, sd, acc, oba = _scores(y, objects, folds, _cross_val(estimator, X, y, folds))
        lines.append(f"{label:70s} {ba:7.3f} ± {sd:5.3f} {acc:9.3f} {oba:14.3f}")
        print(lines[-1], flush=True)
    if args.cnn:
        lines.append("")
        lines.append("CNN from scratch on the loading-phase frames (first 5 folds; the rows above over those 5 folds:")
        cnn = folds[:cnn_folds]
        for label, estimator in (("one number", _logistic(names, r"^pk_int_log_mean$", 1.0)),
                                 ("geometry scale-free", _logistic(names, GEOMETRY_SF, 1.0))):
            ba, sd, acc, oba = _scores(y, objects, cnn, _cross_val(estimator, X, y, cnn))
            lines.append(f"{label + ' (5 folds)':70s} {ba:7.3f} ± {sd:5.3f} {acc:9.3f} {oba:14.3f}")
        for normalise in ("global",) if args.smoke else ("global", "per image"):
            proba = [_cnn_proba(frames, y, train, test, normalise, k, cnn_epochs)
                     for k, (train, test) in enumerate(cnn)]
            ba, sd, acc, oba = _scores(y, objects, cnn, proba)
            lines.append(f"{'CNN, ' + normalise + ' scale (5 folds)':70s} {ba:7.3f} ± {sd:5.3f} {acc:9.3f} {oba:14.3f}")
            print(lines[-1], flush=True)
    lines.append(f"\n{time.perf_counter() - t0:.0f} s")
    report("\n".join(lines), args.out)


if __name__ == "__main__":
    sys.exit(main())
