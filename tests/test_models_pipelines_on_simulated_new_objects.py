"""On new objects of the simulated ``everyday`` preset the ready-made pipelines beat the one-number baseline.

Object-disjoint 5-fold CV on the default ``everyday`` preset, as
``sklearn-hardness evaluate everyday`` runs it, but with each pipeline's
stateless front (frame selection, optical flow) computed once instead of per
fold, and seeded nets. The default inputs must beat the one-number baseline
by 0.10 balanced accuracy, and so must the contact-profile pipeline with its
MC-dropout head (the input that beat the baseline on real recordings). The OFNN's magnitude quantiles must beat the
paper's flattened tracks (same net, same class weights), the effect they exist
for. The ConvLSTM's intensity channels are not asserted against the paper's
frames: on the calibrated preset (issue 20) the two differ by less than the
spread of one seed's training across float paths (0.868 against 0.808 on one
2-core machine, 0.814 against 0.8125 on CI's), and on real recordings of
unseen objects neither beat the one-number baseline.
"""

import warnings

import numpy as np
import pytest
from sklearn.base import clone
from sklearn.metrics import balanced_accuracy_score
from sklearn.model_selection import StratifiedGroupKFold
from sklearn.pipeline import make_pipeline

from sklearn_hardness.datasets import make_presses
from sklearn_hardness.features import ContactProfileFeatures, OpticalFlowFeatures, PeakContactChange
from sklearn_hardness.models import (
    ConvLSTMClassifier,
    OFNNClassifier,
    make_contact_profile_pipeline,
    make_convlstm_pipeline,
    make_ofnn_pipeline,
    make_peak_change_baseline,
)
from sklearn_hardness.models._intensity_channels import IntensityChannels
from sklearn_hardness.models._pipelines import FrameScaler

from ._presets import EVERYDAY_BEFORE


def _cv(estimator, X, y, groups):
    folds = StratifiedGroupKFold(n_splits=5, shuffle=True, random_state=0).split(np.zeros(len(y)), y, groups)
    scores = []
    for train, test in folds:
        est = clone(estimator).fit(X[train], y[train])
        scores.append(balanced_accuracy_score(y[test], est.predict(X[test])))
    return float(np.mean(scores))


@pytest.fixture(scope="module")
def everyday():
    data = make_presses("everyday", random_state=0, **EVERYDAY_BEFORE)  # the preset before issue 20 moved it
    # the per-press steps map each press by itself: each chunk's videos are rendered once for all four
    steps = {"frames": make_convlstm_pipeline().named_steps["frames"].set_params(n_jobs=2),
             "raw": make_ofnn_pipeline().named_steps["frames"].set_params(n_jobs=2),
             "peak": PeakContactChange(), "profile": ContactProfileFeatures(n_jobs=2)}
    rows = {name: [] for name in steps}
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")  # the soft presses' "no contact" warnings
        for chunk in np.array_split(np.arange(len(data.target)), len(data.target) // 8):
            videos = [data.videos[i] for i in chunk]
            for name, step in steps.items():
                rows[name].append(clone(step).fit_transform(videos))
        frames, raw, peak, profile = (np.concatenate(rows[name]) for name in steps)
        flow = {out: OpticalFlowFeatures(output=out, n_jobs=2).fit_transform(raw)
                for out in ("tracks", "magnitude_quantiles")}
    return data, np.asarray(data.target), np.asarray(data.object_id), frames, flow, peak, profile


@pytest.mark.slow
def test_pipelines_beat_the_one_number_on_new_objects_of_the_simulated_everyday_preset(everyday):
    data, y, groups, frames, flow, peak, profile = everyday
    baseline = _cv(make_peak_change_baseline()[1:], peak, y, groups)  # scaler + balanced logistic regression
    assert 0.35 < baseline < 0.55

    net = dict(class_weight="balanced", random_state=0)
    # 25 epochs: 0.80 against the one number's 0.43 (100 epochs: 0.87 in four times the training)
    convlstm = _cv(make_pipeline(FrameScaler(), IntensityChannels(), ConvLSTMClassifier(max_epochs=25, **net)),
                   frames, y, groups)
    ofnn = _cv(OFNNClassifier(**net), flow["magnitude_quantiles"], y, groups)
    ofnn_paper = _cv(OFNNClassifier(**net), flow["tracks"], y, groups)
    contact_profile_nn = _cv(make_contact_profile_pipeline(head="nn", random_state=0)[1:], profile, y, groups)
    scores = dict(baseline=baseline, convlstm=convlstm, ofnn=ofnn, ofnn_paper=ofnn_paper,
                  contact_profile_nn=contact_profile_nn)
    assert contact_profile_nn >= baseline + 0.10, scores
    assert convlstm >= baseline + 0.10, scores
    assert ofnn >= baseline + 0.10, scores
    assert ofnn > ofnn_paper + 0.05, scores
