import numpy as np
import pytest
from sklearn.base import clone

from sklearn_hardness.active import ActiveLearner
from sklearn_hardness.models import make_convlstm_pipeline, make_ofnn_pipeline
from sklearn_hardness.models._pipelines import FrameScaler

from ._exp_data import tiny_presses


def test_frame_scaler():
    X = np.random.default_rng(0).normal(scale=0.03, size=(6, 3, 4, 5, 1)).astype(np.float32)
    s = FrameScaler().fit(X)
    assert s.scale_ == pytest.approx(X.std())
    assert np.std(s.transform(X)) == pytest.approx(1.0, rel=1e-4)
    assert FrameScaler().fit(np.zeros_like(X)).scale_ == 1.0
    with pytest.raises(ValueError):
        s.transform(X[:, :, :, :, 0])


@pytest.mark.slow
def test_pipelines_from_raw_videos_with_active_learner():
    data = tiny_presses()
    y = np.asarray(data.target)
    idx = np.concatenate([np.flatnonzero(y == c)[:2] for c in range(5)])
    test = np.flatnonzero(y == 0)[2:4]
    for pipe in (make_convlstm_pipeline(frame_size=(8, 10), max_epochs=2, random_state=0),
                 make_ofnn_pipeline(frame_size=(16, 20), max_epochs=3, random_state=0)):
        learner = ActiveLearner(clone(pipe), "variance", initial_epochs=2, epochs_per_query=1,
                                n_samples=3, random_state=0)
        learner.fit(data.videos[idx], y[idx])
        q, scores = learner.query(data.videos[test])
        assert scores.shape == (5,) and 0 <= q[0] < 5
        learner.teach(data.videos[np.flatnonzero(y == q[0])[4:6]], np.full(2, q[0]))
        assert learner.predict(data.videos[test]).shape == (2,)
        assert learner.estimator_.named_steps["clf"].get_params()["dropout"] == 0.2
