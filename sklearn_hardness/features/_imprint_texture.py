"""The texture of the imprint a press leaves in the gel: :class:`ImprintTextureFeatures`.

The hardness of everyday objects goes with their material (fabric, foam,
fruit skin, rubber, metal, plastic), and the material shows in the texture
of the imprint it leaves in the gel. The transformer reads that texture, at
moments of the loading phase, with standard descriptors from scikit-image
and OpenCV: local binary patterns, grey-level co-occurrence statistics,
Gabor filter-bank energies, the power spectrum and the colour of the
shading. Every descriptor is scale-free: it does not change when the
change to the pre-contact frames is multiplied by a gain (a harder press,
a brighter sensor).
:func:`~sklearn_hardness.models.make_imprint_texture_pipeline` puts a classifier after it.
"""

from __future__ import annotations

import functools
import numbers

import cv2
import numpy as np
from sklearn.base import BaseEstimator, TransformerMixin
from sklearn.utils.validation import check_is_fitted

from ..utils._optional import import_optional
from ..utils._param_validation import HasMethods, Interval, StrOptions, fit_context
from ..utils._per_press import PerPressTransformerMixin, map_presses, transform_presses
from ..utils._tags import videos_tags
from ..utils._validation import check_roi, check_video_sequence
from ._contact_geometry import _block_mean, _checked_roi, _chroma_gradients
from ._feature_names import check_feature_names
from ._loading_moments import _frame_medians, _norm, loading_moments

__all__ = ["ImprintTextureFeatures"]

#: The descriptors, in output order when ``descriptors="all"``.
DESCRIPTORS = ("lbp", "glcm", "gabor", "spectrum", "colour")

_LEVELS = 32  # grey levels of the quantised change (LBP, co-occurrence)
_LBP_POINTS = ((8, 1), (16, 2))  # (P, R): neighbours and radius in pixels
_GLCM_PROPS = ("contrast", "dissimilarity", "homogeneity", "energy", "correlation")
_GLCM_DISTANCES = (1, 2, 4, 8)
_ANGLES = tuple(k * np.pi / 4 for k in range(4))
_WAVELENGTHS = (4, 8, 16, 32)  # Gabor wavelengths, pixels
_BAND_EDGES = np.geomspace(0.01, 0.5, 11)  # cycles per pixel: ten log-spaced bands
_HUE_BINS = 8
_MIN_CONTACT = 50  # pixels: a smaller contact mask is taken as no contact (the whole frame is read)
_MASK_SIGMA = 2.0  # pixels: the magnitude is smoothed before thresholding, so the mask is not speckled
_CURVE_SIDE = 80  # the moments are found at ContactGeometryFeatures' default resolution
_TINY = 1e-12


def _skimage():
    """scikit-image's ``feature`` module: an optional dependency (``pip install "sklearn-hardness[texture]"``)."""
    return import_optional("skimage.feature", "texture", "ImprintTextureFeatures")


def _descriptor_names(descriptor):
    """The column names of one descriptor at one moment (without the moment's prefix)."""
    if descriptor == "lbp":
        return [f"lbp{p}_{k}" for p, _ in _LBP_POINTS for k in range(p + 2)]
    if descriptor == "glcm":
        return [f"glcm_{prop}_d{d}" for prop in _GLCM_PROPS for d in _GLCM_DISTANCES]
    if descriptor == "gabor":
        return [f"gabor_share_w{w}" for w in _WAVELENGTHS] + [f"gabor_anisotropy_w{w}" for w in _WAVELENGTHS]
    if descriptor == "spectrum":
        return [f"spectrum_{k}" for k in range(len(_BAND_EDGES) - 1)]
    return (["colour_chroma", "colour_red", "colour_green", "colour_blue"]
            + [f"colour_hue_{k}" for k in range(_HUE_BINS)])


def _moment_name(q):
    """1.0 -> "peak", 0.5 -> "half", another fraction q -> "q" and its percentage ("q25")."""
    return {1.0: "peak", 0.5: "half"}.get(float(q), f"q{int(round(100 * q))}")


def _check_moments(moments):
    """``moments`` as a tuple of floats in (0, 1] with distinct names, or a ValueError that says what is wrong."""
    values = tuple(moments)
    if (not values or not all(isinstance(q, numbers.Real) and not isinstance(q, bool) and 0 < q <= 1
                              for q in values)
            or len({_moment_name(q) for q in values}) < len(values)):
        raise ValueError("moments must be a non-empty sequence of distinct fractions of the rise in (0, 1] "
                         f"(distinct to the percent: 0.25 and 0.251 are both 'q25'), got {moments!r}.")
    return tuple(float(q) for q in values)


def _quantise(mag):
    """The magnitude as ``_LEVELS`` integer levels (uint8) up to its 99th percentile (a gain does not change them)."""
    top = float(np.percentile(mag, 99))
    if top <= 0:
        return np.zeros(mag.shape, np.uint8)
    return np.clip(np.rint(mag * ((_LEVELS - 1) / top)), 0, _LEVELS - 1).astype(np.uint8)


def _lbp(levels, region):
    """Uniform LBP histograms at (8, 1) and (16, 2) of the quantised magnitude, in ``region``, each summing to 1."""
    if not levels.any():  # no change: every pattern as likely
        return np.concatenate([np.full(p + 2, 1.0 / (p + 2)) for p, _ in _LBP_POINTS])
    out = []
    for p, r in _LBP_POINTS:
        codes = _skimage().local_binary_pattern(levels, p, r, method="uniform")[region].astype(np.intp)
        out.append(np.bincount(codes, minlength=p + 2)[: p + 2] / codes.size)
    return np.concatenate(out)


def _glcm(levels):
    """Co-occurrence contrast, dissimilarity, homogeneity, energy and correlation at four distances, mean of four
    angles."""
    feature = _skimage()
    matrix = feature.graycomatrix(levels, _GLCM_DISTANCES, _ANGLES, levels=_LEVELS, symmetric=True, normed=True)
    return np.concatenate([feature.graycoprops(matrix, prop).mean(axis=1) for prop in _GLCM_PROPS])


@functools.cache
def _gabor_bank():
    """Zero-mean, unit-energy even Gabor kernels, one list of four orientations per wavelength."""
    bank = []
    for wavelength in _WAVELENGTHS:
        sigma = 0.56 * wavelength  # a bandwidth of one octave
        size = 2 * int(np.ceil(3 * sigma)) + 1
        kernels = []
        for theta in _ANGLES:
            k = cv2.getGaborKernel((size, size), sigma, theta, wavelength, 1.0, 0.0, ktype=cv2.CV_32F)
            k -= k.mean()  # a uniform change gives no response
            kernels.append(k / np.linalg.norm(k))  # white noise gives every wavelength the same response
        bank.append(kernels)
    return bank


def _gabor_response(d, kernel):
    """The Gabor response of a change (h, w, C), its norm over the channels at each pixel."""
    out = cv2.filter2D(d, cv2.CV_32F, kernel, borderType=cv2.BORDER_REFLECT)
    return np.abs(out) if out.ndim == 2 else _norm(out)


def _gabor(d, region):
    """Log share of each wavelength in the Gabor energy, and log ratio of its strongest to weakest orientation."""
    d = np.ascontiguousarray(d, np.float32)
    resp = np.array([[float(_gabor_response(d, k)[region].mean()) for k in kernels] for kernels in _gabor_bank()])
    tiny = _TINY * max(float(resp.sum()), _TINY)
    energy = resp.mean(axis=1) + tiny
    share = np.log(energy / energy.sum())
    anisotropy = np.log((resp.max(axis=1) + tiny) / (resp.min(axis=1) + tiny))
    return np.concatenate([share, anisotropy])


@functools.lru_cache(maxsize=8)
def _bands(h, w):
    """Hann window of an (h, w) image, FFT size, and the band of each rfft2 bin (-1 outside the bands)."""
    window = np.outer(np.hanning(h), np.hanning(w)).astype(np.float32)
    size = cv2.getOptimalDFTSize(max(256, 2 * max(h, w)))  # zero-padded so that the lowest band holds bins
    radius = np.hypot(np.fft.fftfreq(size)[:, None], np.fft.rfftfreq(size)[None, :])
    band = np.digitize(radius, _BAND_EDGES) - 1
    band[(band < 0) | (band >= len(_BAND_EDGES) - 1)] = -1
    return window, size, band


def _spectrum(d):
    """Power of the change (all channels) in ten log-spaced radial frequency bands, as log shares of their total."""
    window, size, band = _bands(*d.shape[:2])
    windowed = d * window[..., None]
    # less each channel's mean: its leak through the window is not texture
    windowed -= window[..., None] * (windowed.sum(axis=(0, 1)) / window.sum())
    power = np.sum(np.abs(np.fft.rfft2(windowed, s=(size, size), axes=(0, 1))) ** 2, axis=-1)
    inside = band >= 0
    total = np.bincount(band[inside], weights=power[inside], minlength=len(_BAND_EDGES) - 1)
    tiny = _TINY * max(float(total.sum()), _TINY)
    return np.log((total + tiny) / (total + tiny).sum())


def _colour(d, mag, region):
    """Chromatic share of the change's energy, each channel's share, and the hue histogram of the chromatic change."""
    total = float(np.sum(mag[region] ** 2))
    if d.shape[-1] != 3 or total <= 0:  # grey videos (or no change): no colour to read
        return np.concatenate([[0.0], np.full(3, 1.0 / 3), np.full(_HUE_BINS, 1.0 / _HUE_BINS)])
    u, v = _chroma_gradients(d[region])
    chroma = np.hypot(u, v)
    channels = [float(np.sum(d[..., c][region] ** 2)) / total for c in range(3)]
    hist, _ = np.histogram(np.arctan2(v, u), bins=_HUE_BINS, range=(-np.pi, np.pi), weights=chroma)
    hist = hist / hist.sum() if hist.sum() > 0 else np.full(_HUE_BINS, 1.0 / _HUE_BINS)
    return np.concatenate([[float(np.sum(chroma ** 2)) / total], channels, hist])


def _contact(mag, noise_factor):
    """Pixels whose smoothed change stands ``noise_factor`` robust deviations above the frame's median.

    Where fewer than ``_MIN_CONTACT`` pixels do, the whole frame; the frame's
    border (the LBP's widest radius) is left out either way.
    """
    smooth = cv2.GaussianBlur(mag, (0, 0), _MASK_SIGMA)
    centre = float(np.median(smooth))
    spread = 1.4826 * float(np.median(np.abs(smooth - centre)))
    mask = smooth > centre + noise_factor * spread
    border = max(r for _, r in _LBP_POINTS)
    inner = np.zeros_like(mask)
    inner[border:-border, border:-border] = True
    if inner.sum() < _MIN_CONTACT:  # a frame too small to leave its border out
        inner[:] = True
    return mask & inner if np.sum(mask & inner) >= _MIN_CONTACT else inner


def _describe(d, descriptors, noise_factor):
    """The descriptors of one change image (h, w, C), concatenated in ``descriptors`` order."""
    mag = _norm(d)
    region = _contact(mag, noise_factor)
    levels = _quantise(mag)
    parts = {"lbp": lambda: _lbp(levels, region), "glcm": lambda: _glcm(levels), "gabor": lambda: _gabor(d, region),
             "spectrum": lambda: _spectrum(d), "colour": lambda: _colour(d, mag, region)}
    return np.concatenate([parts[name]() for name in descriptors])


def _press_row(video, moments, descriptors, max_side, noise_factor, roi, name):
    """The row of one press: the descriptors of its change at each moment, in ``moments`` order."""
    video = _checked_roi(video, roi, name)
    coarse = _block_mean(video, min(max_side, _CURVE_SIDE), name)
    found = loading_moments(coarse, moments)
    if found is None:  # fewer than three frames, or nothing changes: the descriptors of no change
        zero = np.zeros((16, 16, video.shape[-1]), np.float32)
        return np.concatenate([_describe(zero, descriptors, noise_factor)] * len(moments))
    # only the reference (pre-contact) frames and the moments are read at full resolution
    wanted = sorted(set(range(found.n_pre)) | set(found.frames))
    side = max(video.shape[1:3])
    same = max(1, side // max_side) == max(1, side // min(max_side, _CURVE_SIDE))  # the coarse frames serve
    fine = coarse[wanted] if same else _block_mean(video, max_side, name, wanted)
    at = {f: k for k, f in enumerate(wanted)}
    ref = fine[: found.n_pre].mean(axis=0)
    d = fine[[at[f] for f in found.frames]] - ref
    d -= _frame_medians(d)  # uniform illumination drift
    return np.concatenate([_describe(change, descriptors, noise_factor) for change in d])


def _feature_names(moments, descriptors):
    return [f"{_moment_name(q)}_{name}" for q in moments for d in descriptors for name in _descriptor_names(d)]


class ImprintTextureFeatures(PerPressTransformerMixin, TransformerMixin, BaseEstimator):
    """The texture of the imprint a press leaves in the gel, at moments of its loading phase.

    Each video is compared with the mean of its pre-contact frames at the
    moments ContactGeometryFeatures reads (the first frames at which the
    mean change reaches given fractions of its rise from the pre-contact
    level to its peak, found on frames averaged to at most 80 pixels). At
    each moment the change (the frame, block-averaged to about ``max_side``
    pixels on its long side, less the reference, less its per-channel
    median: uniform illumination drift) is described by:

    - ``"lbp"``: histograms of uniform local binary patterns
      (``skimage.feature.local_binary_pattern``) at 8 neighbours on a
      radius of 1 pixel and 16 on a radius of 2 (10 + 18 bins, each summing
      to 1) of the change's magnitude (its norm over the channels)
      quantised to 32 levels up to its 99th percentile, in the contact;
    - ``"glcm"``: grey-level co-occurrence (``skimage.feature.graycomatrix``,
      ``graycoprops``) of the same quantised magnitude, over the frame:
      contrast, dissimilarity, homogeneity, energy and correlation at
      distances 1, 2, 4 and 8 pixels, averaged over four angles (20 values);
    - ``"gabor"``: zero-mean, unit-energy even Gabor kernels
      (:func:`cv2.getGaborKernel`) at wavelengths 4, 8, 16 and 32 pixels and
      four orientations on the change (the norm of the channels'
      responses): the log share of each wavelength in their mean responses
      in the contact, and the log ratio of its strongest to its weakest
      orientation (anisotropy: a weave, a ridge) (8 values);
    - ``"spectrum"``: the power spectrum of the change (summed over the
      channels, each less its mean, Hann window) in ten log-spaced radial
      bands from 0.01 to 0.5 cycles per pixel (edges
      ``np.geomspace(0.01, 0.5, 11)``), as log shares of their total power;
    - ``"colour"``: the chromatic share of the change's energy in the
      contact (GelSight's three lights shade slopes in different colours),
      each channel's share, and an 8-bin histogram of the chromatic
      change's hue weighted by its magnitude (12 values).

    The contact is where the change's magnitude, smoothed by a Gaussian of
    2 pixels, stands more than ``noise_factor`` robust deviations (1.4826
    times the median absolute deviation) above the frame's median; where
    fewer than 50 pixels do, the whole frame is read. Every descriptor is
    scale-free: multiplying the change by a gain (a harder press, a
    brighter sensor) leaves the row as it is. The texture is read from all
    three channels, not from a grey (luminance) change: under GelSight's
    three coloured lights the luminance change is a derivative in one
    direction, blind to slopes across it.

    Parameters
    ----------
    descriptors : "all" or sequence of str, default="all"
        Which of ``"lbp"``, ``"glcm"``, ``"gabor"``, ``"spectrum"`` and
        ``"colour"`` to output, in this order (``"all"``: every one, in that
        order).
    moments : sequence of float in (0, 1], default=(0.5, 1.0)
        The moments, as fractions of the rise (1 is the peak), in output
        order; named ``"peak"`` (1.0), ``"half"`` (0.5) and ``"q"`` and
        the percentage otherwise (0.25: ``"q25"``).
    max_side : int, default=160
        Frames are block-averaged to about this many pixels on their long
        side (a 240x320 frame to 120x160: a fine weave needs resolution).
    noise_factor : float, default=3.0
        Robust deviations above the frame's median that make a pixel part
        of the contact.
    roi : tuple (top, bottom, left, right) or None, default=None
        Read only this region of each frame, given as fractions of its
        height and width, before averaging.
    n_jobs : int or None, default=None
        Videos processed in parallel (joblib threads).
    memory : None, str or object with the joblib.Memory interface, default=None
        Cache each press's row here (a folder, or a :class:`joblib.Memory`),
        keyed by the parameters that change it and the press (a video of a
        lazy sequence by its file or seed, without decoding it; a video in
        memory by a hash of its frames), so that the folds of a
        cross-validation, a grid search or a later run that meet the press
        again read it. Validated as
        :func:`sklearn.utils.validation.check_memory` validates a
        :class:`~sklearn.pipeline.Pipeline`'s ``memory``; None: no cache.
        An entry is the row, ``8 n_features_out_`` bytes (a few kB).

    Attributes
    ----------
    descriptors_ : tuple of str
        The output descriptors, in order.
    moments_ : tuple of float
        The moments, in order.
    n_features_out_ : int
        The number of output features (78 per moment with every descriptor:
        156 by default).

    See Also
    --------
    ContactGeometryFeatures : The contact's depth, edges and shape at the same moments.
    sklearn_hardness.models.make_imprint_texture_pipeline : These features and a classifier.

    Notes
    -----
    Videos of fewer than three frames, or in which nothing changes, give the
    row of no change: uniform histograms and spectrum, a co-occurrence of
    one level (contrast and dissimilarity 0, homogeneity, energy and
    correlation 1), equal Gabor shares without anisotropy, and no colour.
    Grey videos have no colour either: a chromatic share of 0, a third of
    the energy per channel and a uniform hue histogram.

    Ojala, Pietikainen and Maenpaa, "Multiresolution gray-scale and rotation
    invariant texture classification with local binary patterns", IEEE
    TPAMI 24(7), 2002. Haralick, Shanmugam and Dinstein, "Textural features
    for image classification", IEEE TSMC 3(6), 1973.

    Examples
    --------
    >>> import numpy as np
    >>> from sklearn_hardness.features import ImprintTextureFeatures
    >>> yy, xx = np.mgrid[0:48, 0:64]
    >>> video = np.full((20, 48, 64, 3), 120, np.uint8)
    >>> for t in range(8, 20):  # a ribbed object sinks in, shaded by lights from three sides
    ...     ribs = (t - 7) * np.cos(2 * np.pi * xx / 8) * np.exp(-((yy - 24) ** 2 + (xx - 32) ** 2) / 200.0)
    ...     gy, gx = np.gradient(ribs)
    ...     video[t] = np.clip(120 + 20 * np.stack([gx, gy, -gx - gy], axis=-1), 0, 255).astype(np.uint8)
    >>> ImprintTextureFeatures().fit_transform([video]).shape
    (1, 156)
    >>> est = ImprintTextureFeatures(descriptors=["spectrum"], moments=[1.0]).fit([video])
    >>> names = est.get_feature_names_out()
    >>> names[:2]
    array(['peak_spectrum_0', 'peak_spectrum_1'], dtype=object)
    >>> str(names[np.argmax(est.transform([video])[0])])  # period 8 px: 0.125 cycles/px, in band 6 (0.105-0.155)
    'peak_spectrum_6'
    """

    _parameter_constraints: dict = {
        "descriptors": [StrOptions({"all"}), list, tuple],
        "moments": [list, tuple],
        "max_side": [Interval(numbers.Integral, 8, None, closed="left")],
        "noise_factor": [Interval(numbers.Real, 0, None, closed="neither")],
        "roi": [None, tuple, list],
        "n_jobs": [numbers.Integral, None],
        "memory": [None, str, HasMethods(["cache"])],
    }

    def __init__(self, descriptors="all", moments=(0.5, 1.0), max_side=160, noise_factor=3.0, roi=None,
                 n_jobs=None, memory=None):
        self.descriptors = descriptors
        self.moments = moments
        self.max_side = max_side
        self.noise_factor = noise_factor
        self.roi = roi
        self.n_jobs = n_jobs
        self.memory = memory

    @fit_context(prefer_skip_nested_validation=True)
    def fit(self, X, y=None):
        """Check the parameters and the input (stateless otherwise).

        Parameters
        ----------
        X : sequence of array-like of shape (T, H, W, 3)
            Press videos.
        y : ignored

        Returns
        -------
        self : ImprintTextureFeatures
        """
        _skimage()  # the local binary patterns and co-occurrence need it: say so before any press is read
        self.descriptors_ = check_feature_names(self.descriptors, DESCRIPTORS, param="descriptors")
        self.moments_ = _check_moments(self.moments)
        check_roi(self.roi)
        check_video_sequence(X)
        self.n_features_out_ = len(_feature_names(self.moments_, self.descriptors_))
        return self

    def transform(self, X):
        """Compute the features of each video.

        Parameters
        ----------
        X : sequence of array-like of shape (T, H, W, 3)
            Press videos (lengths may differ; videos of fewer than three
            frames, or without any change, give the row of no change).

        Returns
        -------
        features : ndarray of shape (n_videos, n_features_out_), float64
        """
        check_is_fitted(self)
        X = check_video_sequence(X)
        return transform_presses(self, X)[0].astype(np.float64, copy=False)

    def _transform_presses(self, X):
        params = dict(moments=self.moments_, descriptors=self.descriptors_, max_side=self.max_side,
                      noise_factor=self.noise_factor, roi=check_roi(self.roi))
        return map_presses(_press_row, X, params, n_jobs=self.n_jobs), {}

    def get_feature_names_out(self, input_features=None):
        """Names of the features: the moment's name, then the descriptor's column (``"peak_lbp8_3"``).

        Parameters
        ----------
        input_features : ignored

        Returns
        -------
        names : ndarray of str
        """
        check_is_fitted(self)
        return np.array(_feature_names(self.moments_, self.descriptors_), dtype=object)

    def __sklearn_tags__(self):
        return videos_tags(super().__sklearn_tags__())
