"""ContactGeometryFeatures: the contact's depth, area, edges and texture over a press, from GelSight shading."""

import numpy as np
import pytest
from sklearn.base import clone

from sklearn_hardness.features import ContactGeometryFeatures
from sklearn_hardness.features._contact_geometry import FEATURE_NAMES, SCALE_FREE
from sklearn_hardness.models import make_contact_geometry_pipeline

H, W = 60, 80


def _render(heights, angle=0.0, gain=20.0, noise=0.5, seed=0):
    """GelSight-like frames of a gel surface over time: three coloured lights 120 degrees apart.

    Each channel brightens where the surface slopes towards its light (linear
    shading), around a grey of 120, with Gaussian pixel noise, as uint8.
    """
    rng = np.random.default_rng(seed)
    frames = []
    for z in heights:
        gy, gx = np.gradient(z)
        chans = [gain * (np.cos(angle + k * 2 * np.pi / 3) * gx + np.sin(angle + k * 2 * np.pi / 3) * gy)
                 for k in range(3)]
        frame = 120.0 + np.stack(chans, axis=-1) + rng.normal(0.0, noise, (H, W, 3))
        frames.append(np.clip(np.rint(frame), 0, 255).astype(np.uint8))
    return np.stack(frames)


def _depths(n=30, start=8, top=20, depth=3.0):
    """Depth of the press over time: none before ``start``, growing linearly to ``depth`` at ``top``, held."""
    t = np.arange(n)
    return depth * np.clip((t - start) / (top - start), 0.0, 1.0)


def _radius():
    yy, xx = np.mgrid[0:H, 0:W]
    return np.hypot(yy - H / 2, xx - W / 2)


def hard_press(depth=3.0, **kwargs):
    """A rigid flat-ended object: the imprint keeps its radius and steep edge while it sinks in."""
    r = _radius()
    shape = 0.5 * (1.0 - np.tanh((r - 9.0) / 1.0))
    return _render([d * shape for d in _depths(depth=depth)], **kwargs)


def soft_press(depth=3.0, **kwargs):
    """A soft object: it flattens, so the imprint is smooth and widens as it sinks in."""
    r = _radius()
    heights = [d * np.exp(-r ** 2 / (2 * (4.0 + 6.0 * d / depth) ** 2)) for d in _depths(depth=depth)]
    return _render(heights, **kwargs)


def _row(video, **params):
    est = ContactGeometryFeatures(**params).fit([video])
    return dict(zip(est.get_feature_names_out(), est.transform([video])[0]))


def test_shape_names_and_subsets():
    videos = [hard_press(), soft_press()]
    est = ContactGeometryFeatures().fit(videos)
    Xt = est.transform(videos)
    assert Xt.shape == (2, len(FEATURE_NAMES)) == (2, est.n_features_out_)
    assert Xt.dtype == np.float64 and np.isfinite(Xt).all()
    assert list(est.get_feature_names_out()) == list(FEATURE_NAMES)
    sub = ContactGeometryFeatures(features=["edge_sharpness", "log_depth"]).fit(videos)
    np.testing.assert_array_equal(sub.transform(videos),
                                  Xt[:, [FEATURE_NAMES.index("edge_sharpness"), FEATURE_NAMES.index("log_depth")]])
    assert set(SCALE_FREE) <= set(FEATURE_NAMES)


def test_a_rigid_press_keeps_its_edges_and_a_soft_one_spreads():
    hard, soft = _row(hard_press()), _row(soft_press())
    # the rigid object's imprint is steep-sided: a sharp edge, quarter- and three-quarter-depth areas close
    assert hard["edge_sharpness"] > 1.5 * soft["edge_sharpness"]
    assert hard["shoulder_ratio"] < soft["shoulder_ratio"]
    # and it does not spread as it sinks in; the soft one does
    assert hard["area_depth_slope"] < soft["area_depth_slope"]
    assert hard["spread_depth_slope"] < soft["spread_depth_slope"]
    assert soft["spread_depth_slope"] > 0.3


def test_depth_grows_with_the_press_and_does_not_depend_on_the_lights_direction():
    shallow, deep = _row(soft_press(depth=1.5)), _row(soft_press(depth=4.0))
    assert deep["log_depth"] > shallow["log_depth"] + 0.5
    # the lights' frame is found from the gradients' integrability: turning the lights changes little
    turned = _row(soft_press(depth=4.0, angle=1.0))
    assert abs(turned["log_depth"] - deep["log_depth"]) < 0.2
    assert abs(turned["half_depth_area"] - deep["half_depth_area"]) < 0.02
    # the scale-free features do not change with the gain of the shading (a brighter sensor)
    bright = _row(soft_press(depth=4.0, gain=40.0))
    for name in ("half_depth_area", "edge_sharpness", "area_depth_slope"):
        assert abs(bright[name] - deep[name]) < 0.15 * max(1.0, abs(deep[name])), name


def test_texture_tells_a_fibrous_contact_from_a_smooth_one():
    rng = np.random.default_rng(1)
    r = _radius()
    fibres = rng.normal(0.0, 1.0, (H, W))
    smooth = soft_press()
    rough = _render([d * np.exp(-r ** 2 / 200.0) * (1.0 + 0.8 * fibres) for d in _depths()])
    assert _row(rough)["texture_ratio"] > _row(smooth)["texture_ratio"] + 0.5


def test_short_constant_grey_and_uint16_videos():
    for video in (hard_press()[:1], hard_press()[:2], np.full((10, H, W, 3), 100, np.uint8)):
        row = ContactGeometryFeatures().fit_transform([video])
        assert row.shape == (1, len(FEATURE_NAMES)) and np.isfinite(row).all()
    grey = hard_press().mean(axis=-1).astype(np.uint8)  # (T, H, W): no gradients, the shading stands in
    assert np.isfinite(ContactGeometryFeatures().fit_transform([grey])).all()
    video = hard_press()
    np.testing.assert_allclose(ContactGeometryFeatures().fit_transform([video.astype(np.uint16) * 257]),
                               ContactGeometryFeatures().fit_transform([video]), rtol=1e-5, atol=1e-6)


def test_large_frames_are_averaged_to_max_side():
    video = hard_press()
    big = np.repeat(np.repeat(video, 4, axis=1), 4, axis=2)  # 240x320, the same press
    np.testing.assert_allclose(ContactGeometryFeatures().fit_transform([big]),
                               ContactGeometryFeatures().fit_transform([video]), rtol=1e-4, atol=1e-5)


def test_roi_reads_only_the_region():
    video = hard_press()
    noisy = video.copy()
    noisy[15:, 60:] = np.random.default_rng(0).integers(0, 255, noisy[15:, 60:].shape, dtype=np.uint8)
    roi = (0.0, 1.0, 0.0, 0.75)  # leaves the noisy strip out
    np.testing.assert_allclose(ContactGeometryFeatures(roi=roi).fit_transform([noisy]),
                               ContactGeometryFeatures().fit_transform([video[:, :, :60]]), rtol=1e-6)


@pytest.mark.parametrize("params, error", [
    ({"features": ["log_depth", "nope"]}, ValueError),
    ({"features": "some"}, ValueError),
    ({"max_side": 4}, ValueError),
    ({"noise_factor": 0.0}, ValueError),
    ({"sigma": -1.0}, ValueError),
    ({"roi": (0.5, 0.2, 0.0, 1.0)}, ValueError),
])
def test_bad_parameters(params, error):
    with pytest.raises(error):
        ContactGeometryFeatures(**params).fit([hard_press()])


def test_bad_input_is_named():
    est = ContactGeometryFeatures().fit([hard_press()])
    with pytest.raises(TypeError):
        est.transform(["press.mov"])
    with pytest.raises(ValueError):
        est.transform([np.zeros((5, 8), np.uint8)])
    with pytest.raises(ValueError, match="video 1"):
        est.transform([hard_press(), np.full((4, 8, 8, 3), 2.0)])  # floats must lie in [0, 1]
    with pytest.raises(Exception):
        ContactGeometryFeatures().transform([hard_press()])  # not fitted


def test_clone_and_params():
    est = ContactGeometryFeatures(features=["log_depth"], sigma=0.5, n_jobs=1)
    params = clone(est).get_params()
    assert params["features"] == ["log_depth"] and params["sigma"] == 0.5 and params["n_jobs"] == 1
    assert est.set_params(max_side=40).max_side == 40
    assert not hasattr(clone(est.fit([hard_press()])), "features_")


def test_pipeline_has_posterior_samples():
    videos = [hard_press(depth=d, seed=s) for s, d in enumerate((2.0, 2.5, 3.0, 3.5))]
    videos += [soft_press(depth=d, seed=s) for s, d in enumerate((2.0, 2.5, 3.0, 3.5))]
    y = np.array([0] * 4 + [1] * 4)
    pipe = make_contact_geometry_pipeline(features=["edge_sharpness", "shoulder_ratio"]).fit(videos, y)
    assert (pipe.predict(videos) == y).all()
    assert pipe.predict_proba_samples(videos[:3], n_samples=4, random_state=0).shape == (4, 3, 2)
    assert make_contact_geometry_pipeline().fit(videos, y).named_steps["scale"].n_features_in_ == len(SCALE_FREE)
    names = ContactGeometryFeatures(features="scale_free").fit(videos).get_feature_names_out()
    assert names.tolist() == list(SCALE_FREE)
    both = make_contact_geometry_pipeline(features="all", with_profile=True).fit(videos, y)
    assert both.named_steps["scale"].n_features_in_ == len(FEATURE_NAMES) + 12
    with pytest.raises(ValueError, match="head"):
        make_contact_geometry_pipeline(head="svm")


def test_simulated_presses_give_finite_rows():
    from sklearn_hardness.datasets import make_presses

    data = make_presses("everyday", n_per_class=1, image_size=(60, 80), random_state=0)
    videos = [data.videos[i] for i in range(6)]
    Xt = ContactGeometryFeatures().fit_transform(videos)
    assert Xt.shape == (6, len(FEATURE_NAMES)) and np.isfinite(Xt).all()
