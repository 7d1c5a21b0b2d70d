import numpy as np
from sklearn.base import clone
from sklearn.model_selection import GridSearchCV

from sklearn_hardness.models import MCDropoutPipeline, make_convlstm_pipeline

from ._exp_data import tiny_presses


def test_pipeline_forwards_predict_proba_samples():
    data = tiny_presses()
    pipe = make_convlstm_pipeline(frame_size=(8, 10), max_epochs=2, random_state=0)
    assert isinstance(pipe, MCDropoutPipeline) and isinstance(clone(pipe), MCDropoutPipeline)
    pipe.fit(data.videos[:20], data.target[:20])
    samples = pipe.predict_proba_samples(data.videos[20:24], n_samples=6, random_state=1)
    assert samples.shape == (6, 4, 5)
    np.testing.assert_allclose(samples.sum(-1), 1, atol=1e-5)
    # the same as running the steps by hand
    Xt = pipe[:-1].transform(data.videos[20:24])
    np.testing.assert_array_equal(samples, pipe[-1].predict_proba_samples(Xt, n_samples=6, random_state=1))


def test_no_forwarding_without_a_sampler():
    from sklearn.linear_model import LogisticRegression
    from sklearn.preprocessing import StandardScaler

    pipe = MCDropoutPipeline([("s", StandardScaler()), ("clf", LogisticRegression())])
    assert not hasattr(pipe, "predict_proba_samples")


def test_grid_search_over_dropout_on_videos():
    data = tiny_presses()
    pipe = make_convlstm_pipeline(frame_size=(8, 10), max_epochs=2, random_state=0)
    search = GridSearchCV(pipe, {"clf__dropout": [0.0, 0.3]}, cv=2).fit(data.videos, data.target)
    assert search.best_params_["clf__dropout"] in (0.0, 0.3)
    assert search.best_estimator_.predict_proba_samples(data.videos[:2], n_samples=3).shape == (3, 2, 5)
