import numpy as np
import pytest
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


@pytest.mark.slow
def test_grid_search_over_dropout_on_videos():
    data = tiny_presses()
    pipe = make_convlstm_pipeline(frame_size=(8, 10), max_epochs=2, random_state=0)
    search = GridSearchCV(pipe, {"clf__dropout": [0.0, 0.3]}, cv=2).fit(data.videos, data.target)
    assert search.best_params_["clf__dropout"] in (0.0, 0.3)
    assert search.best_estimator_.predict_proba_samples(data.videos[:2], n_samples=3).shape == (3, 2, 5)


def test_every_net_factory_reads_only_its_roi():
    """``roi`` of a factory: the frames step sees the gel alone, as if the videos were cropped to it."""
    from sklearn_hardness.models import make_dinov2nn_pipeline, make_ofnn_pipeline

    from ._synthetic import FRAMED_GEL, framed_press, growing_disc_press

    rng = np.random.default_rng(0)
    framed = [framed_press(growing_disc_press(int(rng.integers(2, 30)), 8.0, rng), rng) for _ in range(4)]
    cropped = [v[:, 8:40, 16:48] for v in framed]
    for factory, kwargs in [(make_convlstm_pipeline, {"frame_size": (8, 8)}),
                            (make_ofnn_pipeline, {"frame_size": (16, 16)}),
                            (make_dinov2nn_pipeline, {"frame_size": (14, 14)})]:
        on_gel = factory(roi=FRAMED_GEL, **kwargs).named_steps["frames"]
        assert on_gel.roi == FRAMED_GEL
        np.testing.assert_array_equal(on_gel.fit_transform(framed),
                                      factory(**kwargs).named_steps["frames"].fit_transform(cropped))
        # without it, the housing's change is taken for contact on some of the videos
        whole = factory(**kwargs).named_steps["frames"]
        assert not np.array_equal(whole.select(framed).indices, on_gel.select(framed).indices), factory.__name__
