"""ImprintTextureFeatures: the texture of the imprint a press leaves in the gel, at moments of its loading phase."""

import numpy as np
import pytest

from sklearn_hardness.features import (
    ContactGeometryFeatures,
    ImprintTextureFeatures,
    _contact_geometry,
    _imprint_texture,
)
from sklearn_hardness.features._loading_moments import loading_moments
from sklearn_hardness.model_selection._per_press import split_per_press
from sklearn_hardness.models import make_imprint_texture_pipeline, make_named_pipeline

H, W = 96, 128
N, START, TOP = 24, 6, 16  # frames; the press starts sinking in at START and is deepest from TOP on
_LIGHTS = [k * 2 * np.pi / 3 for k in range(3)]
_YY, _XX = np.mgrid[0:H, 0:W].astype(np.float64)
_DISC = 0.5 * (1.0 - np.tanh((np.hypot(_YY - H / 2, _XX - W / 2) - 30.0) / 3.0))  # the contact: 30 px radius


def dome():
    """A smooth round object (8 times deeper than the textures, for a shading as strong as theirs)."""
    return 8.0 * np.exp(-((_YY - H / 2) ** 2 + (_XX - W / 2) ** 2) / (2 * 18.0 ** 2))


def stripes(period=8.0):
    return _DISC * 0.5 * (1.0 + np.cos(2 * np.pi * _XX / period))


def dots(period=8.0):
    return _DISC * 0.25 * (1.0 + np.cos(2 * np.pi * _XX / period)) * (1.0 + np.cos(2 * np.pi * _YY / period))


def press(surface, gain=1.0, noise=0.4, seed=0, grey=False):
    """Float frames in [0, 1]: ``surface`` pressed in over frames, shaded by three coloured lights, with noise.

    The change to the background (the shading of the surface's slopes and
    the pixel noise) is multiplied by ``gain``: a harder press, a brighter
    sensor.
    """
    rng = np.random.default_rng(seed)
    depth = 2.0 * np.clip((np.arange(N) - START) / (TOP - START), 0.0, 1.0)
    gy, gx = np.gradient(surface)
    if grey:  # the same in every channel: brighter where the surface is steeper
        shading = 12.0 * np.hypot(gx, gy)[..., None] * np.ones(3)
    else:  # each channel brightens where the surface slopes towards its light
        shading = 12.0 * np.stack([np.cos(a) * gx + np.sin(a) * gy for a in _LIGHTS], axis=-1)
    change = depth[:, None, None, None] * shading + rng.normal(0.0, noise, (N, H, W, 3))
    return (110.0 + gain * change) / 255.0


def _row(video, **params):
    est = ImprintTextureFeatures(**params).fit([video])
    return dict(zip(est.get_feature_names_out(), est.transform([video])[0]))


def test_names_count_and_subsets():
    videos = [press(dome()), press(stripes())]
    est = ImprintTextureFeatures().fit(videos)
    Xt = est.transform(videos)
    names = list(est.get_feature_names_out())
    assert Xt.shape == (2, 156) == (2, est.n_features_out_) and Xt.dtype == np.float64 and np.isfinite(Xt).all()
    assert len(set(names)) == len(names) and names[0] == "half_lbp8_0" and names[78] == "peak_lbp8_0"
    assert {"peak_lbp16_17", "half_glcm_contrast_d2", "peak_gabor_anisotropy_w32", "peak_spectrum_9",
            "half_colour_chroma", "peak_colour_hue_7"} <= set(names)
    # a choice of descriptors and moments gives those columns of the full row, in the order asked
    sub = ImprintTextureFeatures(descriptors=["spectrum", "gabor"], moments=[1.0, 0.5]).fit(videos)
    sub_names = list(sub.get_feature_names_out())
    assert sub_names[:2] == ["peak_spectrum_0", "peak_spectrum_1"] and sub_names[10] == "peak_gabor_share_w4"
    assert len(sub_names) == 2 * (10 + 8) and sub_names[18] == "half_spectrum_0"
    np.testing.assert_array_equal(sub.transform(videos), Xt[:, [names.index(n) for n in sub_names]])
    assert ImprintTextureFeatures(moments=(0.25, 0.9)).fit(videos).get_feature_names_out()[[0, 78]].tolist() == [
        "q25_lbp8_0", "q90_lbp8_0"]


def test_spectrum_peaks_in_the_band_of_the_grating():
    edges = np.geomspace(0.01, 0.5, 11)
    for period in (5.0, 8.0, 12.0, 20.0):
        row = _row(press(stripes(period)), descriptors=["spectrum"], moments=[1.0])
        shares = np.array([row[f"peak_spectrum_{k}"] for k in range(10)])
        assert np.argmax(shares) == np.searchsorted(edges, 1.0 / period) - 1, period
        np.testing.assert_allclose(np.exp(shares).sum(), 1.0, rtol=1e-6)


def test_gabor_reads_the_wavelength_and_the_anisotropy_of_a_weave():
    lines, lattice = _row(press(stripes(8.0))), _row(press(dots(8.0)))
    for row in (lines, lattice):  # most of the energy at the 8-pixel wavelength
        shares = [row[f"peak_gabor_share_w{w}"] for w in (4, 8, 16, 32)]
        assert np.argmax(shares) == 1 and np.exp(shares).sum() == pytest.approx(1.0)
    # stripes respond to one orientation only; a square lattice of dots to two of the four
    assert lines["peak_gabor_anisotropy_w8"] > lattice["peak_gabor_anisotropy_w8"] + 1.0
    assert lattice["peak_gabor_anisotropy_w8"] > 0.0


def test_lbp_histograms_sum_to_one_and_texture_differs_from_a_smooth_dome():
    smooth, ribbed = _row(press(dome())), _row(press(stripes(8.0)))
    for row in (smooth, ribbed):
        for moment in ("half", "peak"):
            assert sum(row[f"{moment}_lbp8_{k}"] for k in range(10)) == pytest.approx(1.0)
            assert sum(row[f"{moment}_lbp16_{k}"] for k in range(18)) == pytest.approx(1.0)
            assert all(row[f"{moment}_lbp8_{k}"] >= 0 for k in range(10))
    # neighbours half a period apart differ on the ribs; on a smooth dome they differ less
    assert ribbed["peak_glcm_contrast_d4"] > 3 * smooth["peak_glcm_contrast_d4"]


def test_colour_reads_the_lights_shading():
    shaded, grey = _row(press(dome()), descriptors=["colour"]), _row(press(dome(), grey=True), descriptors=["colour"])
    # three lights 120 degrees apart: the shading sums to nothing over the channels, so it is all chromatic
    assert shaded["peak_colour_chroma"] > 0.9 and grey["peak_colour_chroma"] < 0.05
    for row in (shaded, grey):
        assert sum(row[f"peak_colour_{c}"] for c in ("red", "green", "blue")) == pytest.approx(1.0)
        assert sum(row[f"peak_colour_hue_{k}"] for k in range(8)) == pytest.approx(1.0)
    # a dome's slopes face every way: every hue bin holds some of the chromatic change
    assert min(shaded[f"peak_colour_hue_{k}"] for k in range(8)) > 0.03


def test_the_row_does_not_change_with_the_gain_of_the_change():
    """A press twice as strong (the shading and the noise of the change both doubled) gives the same row."""
    est = ImprintTextureFeatures().fit([press(dome())])
    for surface in (dome(), stripes(), dots()):
        weak, strong = est.transform([press(surface, gain=0.7), press(surface, gain=1.4)])
        np.testing.assert_allclose(strong, weak, atol=0.01, rtol=0.01)
    # while the texture itself moves the row by much more
    assert np.abs(est.transform([press(stripes())]) - est.transform([press(dots())])).max() > 1.0


def test_presses_without_change_give_the_row_of_no_change():
    still = np.full((12, H, W, 3), 100, np.uint8)
    rows = ImprintTextureFeatures().fit([still]).transform([still, press(dome())[:2], press(dome())[:1]])
    assert np.isfinite(rows).all()
    np.testing.assert_array_equal(rows[1], rows[0])
    np.testing.assert_array_equal(rows[2], rows[0])
    row = dict(zip(ImprintTextureFeatures().fit([still]).get_feature_names_out(), rows[0]))
    assert row["peak_lbp8_0"] == pytest.approx(0.1) and row["peak_spectrum_3"] == pytest.approx(np.log(0.1))
    assert row["peak_glcm_contrast_d1"] == 0.0 and row["peak_glcm_energy_d8"] == pytest.approx(1.0)
    assert row["peak_gabor_anisotropy_w8"] == 0.0 and row["peak_colour_chroma"] == 0.0
    assert row["peak_colour_hue_0"] == pytest.approx(1 / 8)


def test_grey_uint8_and_large_videos():
    video = np.clip(np.rint(press(stripes()) * 255), 0, 255).astype(np.uint8)
    grey = video.mean(axis=-1).astype(np.uint8)  # (T, H, W)
    assert np.isfinite(ImprintTextureFeatures().fit_transform([video, grey])).all()
    # a frame twice as large is block-averaged back to the same one
    big = np.repeat(np.repeat(video, 2, axis=1), 2, axis=2)
    np.testing.assert_allclose(ImprintTextureFeatures(max_side=128).fit_transform([big]),
                               ImprintTextureFeatures(max_side=128).fit_transform([video]), rtol=1e-4, atol=1e-5)


def test_roi_reads_only_the_region():
    video = press(stripes())
    noisy = video.copy()
    noisy[:, :, 112:] = np.random.default_rng(0).random(noisy[:, :, 112:].shape)
    roi = (0.0, 1.0, 0.0, 0.875)  # leaves the noisy strip out
    np.testing.assert_allclose(ImprintTextureFeatures(roi=roi).fit_transform([noisy]),
                               ImprintTextureFeatures().fit_transform([video[:, :, :112]]), rtol=1e-6, atol=1e-9)


def test_both_transformers_read_the_same_moments(monkeypatch):
    """The texture is read at the frames where ContactGeometryFeatures reads the contact's shape."""
    found = []

    def spy(small, fractions):
        moments = loading_moments(small, fractions)
        found.append(dict(zip(fractions, moments.frames)))
        return moments

    monkeypatch.setattr(_contact_geometry, "loading_moments", spy)
    monkeypatch.setattr(_imprint_texture, "loading_moments", spy)
    video = press(dots(), seed=3)
    ContactGeometryFeatures().fit_transform([video])
    ImprintTextureFeatures(moments=(0.5, 0.75, 1.0)).fit_transform([video])
    geometry, texture = found
    assert texture == {q: geometry[q] for q in (0.5, 0.75, 1.0)}
    # the depth grows linearly from START to TOP: halfway up is halfway through, the peak at TOP or after
    assert abs(texture[0.5] - (START + TOP) / 2) <= 1 and texture[1.0] >= TOP - 1


def test_loading_moments_of_a_linear_rise():
    video = np.zeros((40, 8, 8, 3), np.float32)
    video[10:, :4] = np.minimum(np.arange(30) + 1, 20)[:, None, None, None]  # rises over frames 10 .. 29, then held
    moments = loading_moments(video, (0.25, 0.5, 1.0))
    assert moments.n_pre == 10 and moments.i_peak == 29
    assert moments.frames == [14, 19, 29]
    assert loading_moments(video[:2], (0.5,)) is None and loading_moments(video[:10], (0.5,)) is None


@pytest.mark.parametrize("params, match", [
    ({"descriptors": ["lbp", "wavelets"]}, "descriptors must be 'all' or .*wavelets"),
    ({"descriptors": ["lbp", "lbp"]}, "more than once"),
    ({"descriptors": []}, "got none"),
    ({"descriptors": "some"}, "descriptors"),
    ({"moments": (0.5, 0.0)}, r"moments must be .* in \(0, 1\]"),
    ({"moments": (1.5,)}, "moments must be"),
    ({"moments": ()}, "moments must be"),
    ({"moments": (0.25, 0.251)}, "q25"),
    ({"moments": 0.5}, "moments"),
    ({"max_side": 4}, "max_side"),
    ({"noise_factor": 0.0}, "noise_factor"),
    ({"roi": (0.5, 0.2, 0.0, 1.0)}, "roi must be"),
])
def test_bad_parameters_are_named(params, match):
    with pytest.raises(ValueError, match=match):
        ImprintTextureFeatures(**params).fit([press(dome())])


def test_bad_input_is_named():
    est = ImprintTextureFeatures().fit([press(dome())])
    with pytest.raises(ValueError, match="video 1"):
        est.transform([press(dome()), np.full((4, 8, 8, 3), 2.0)])  # floats must lie in [0, 1]
    with pytest.raises(Exception, match="not fitted"):
        ImprintTextureFeatures().transform([press(dome())])


def test_pipeline_by_name_and_its_posterior_samples():
    videos = [press(stripes(8.0), seed=s) for s in range(4)] + [press(dots(8.0), seed=s) for s in range(4)]
    y = np.array([0] * 4 + [1] * 4)
    pipe = make_imprint_texture_pipeline(descriptors=["gabor"], moments=[1.0]).fit(videos, y)
    assert (pipe.predict(videos) == y).all()
    assert pipe.predict_proba_samples(videos[:3], n_samples=4, random_state=0).shape == (4, 3, 2)
    named = make_named_pipeline("imprint_texture", roi=(0.1, 0.9, 0.1, 0.9))
    assert named.named_steps["features"].roi == (0.1, 0.9, 0.1, 0.9) and named.named_steps["clf"].C == 0.1
    prefix, rest = split_per_press(named)  # evaluate computes the features once per press for all folds
    assert [n for n, _ in prefix.steps] == ["features"] and [n for n, _ in rest.steps] == ["scale", "clf"]
    with pytest.raises(ValueError, match="head"):
        make_imprint_texture_pipeline(head="svm")
