"""The contact's geometry over a press, read from GelSight shading: :class:`ContactGeometryFeatures`.

A hand press carries no force, so hardness has to be read from how the
contact itself changes while the press loads: a hard object keeps its shape
and edges while it sinks into the gel, a soft one flattens and spreads. The
transformer reads, from the change of each frame to the pre-contact frames,
the gel's approximate surface gradients (GelSight's three coloured lights:
the chromatic part of the change) and an approximate depth (their
Frankot-Chellappa integration), and summarises, at four moments of the
loading phase, the contact's depth, area, edge sharpness, spread and
texture, and how they grow against each other.
:func:`~sklearn_hardness.models.make_contact_geometry_pipeline` puts a classifier after it.
"""

from __future__ import annotations

import numbers

import cv2
import numpy as np
from sklearn.base import BaseEstimator, TransformerMixin
from sklearn.utils.validation import check_is_fitted

from ..utils._frames import as_float255, check_float_range
from ..utils._param_validation import HasMethods, Interval, fit_context
from ..utils._per_press import PerPressTransformerMixin, map_presses, transform_presses
from ..utils._tags import videos_tags
from ..utils._validation import check_roi, check_video, check_video_sequence, roi_slices
from ._feature_names import check_feature_names, feature_columns
from ._loading_moments import _frame_medians, _norm, loading_moments

__all__ = ["ContactGeometryFeatures"]

#: Loading moments, as fractions of the rise of the contact's change from its pre-contact level to its peak.
MOMENTS = (0.25, 0.5, 0.75, 1.0)

#: Every feature, in output order when ``features="all"``.
FEATURE_NAMES = (
    # at the peak
    "log_depth",
    "log_slope",
    "log_contrast",
    "contact_area",
    "half_depth_area",
    "edge_sharpness",
    "shoulder_ratio",
    "log_spread",
    "eccentricity",
    "texture_ratio",
    "gradient_share",
    # growth over the loading phase (25%, 50%, 75% and 100% of the rise)
    "area_depth_slope",
    "spread_depth_slope",
    "sharpness_depth_slope",
    "texture_depth_slope",
    "early_area_share",
    "early_depth_share",
)

#: The features that do not grow with how hard the press is made: shapes, ratios and growth slopes.
SCALE_FREE = ("half_depth_area", "edge_sharpness", "shoulder_ratio", "eccentricity", "texture_ratio",
              "gradient_share", "area_depth_slope", "spread_depth_slope", "sharpness_depth_slope",
              "texture_depth_slope", "early_area_share", "early_depth_share")

_EPS = 1e-6
_LOG_FLOOR = 1e-3


def _small_rgb(video, max_side, roi, name):
    """Frames block-averaged to about ``max_side`` pixels on the long side, float32 in 0..255, (T, h, w, C).

    Averaging (not striding) keeps all pixels: at the 4x4 blocks of a
    240x320 GelSight Mini frame it divides the codec's pixel noise by about
    four, where the contact signal is a few grey levels.
    """
    return _block_mean(_checked_roi(video, roi, name), max_side, name)


def _checked_roi(video, roi, name):
    """The video checked (float values in [0, 1] over all of it) and cropped to ``roi``."""
    video = check_video(video, min_frames=1, name=name)
    check_float_range(video, name)  # the whole video, before the crop and the averaging
    rows, cols = roi_slices(video.shape[1:3], roi, name)
    return video[:, rows, cols]


def _block_mean(video, max_side, name, frames=None):
    """The frames (all, or those indexed by ``frames``) averaged in blocks to about ``max_side`` pixels, float32."""
    t, h, w, c = video.shape
    frames = range(t) if frames is None else frames
    f = max(1, max(h, w) // max_side)
    hs, ws = max(1, h // f), max(1, w // f)
    out = np.empty((len(frames), hs, ws, c), np.float32)
    for k, i in enumerate(frames):
        frame = as_float255(video[i, : hs * f, : ws * f], name)
        if f > 1:  # an integer factor: OpenCV's area interpolation is the mean of each f x f block
            frame = cv2.resize(frame, (ws, hs), interpolation=cv2.INTER_AREA).reshape(hs, ws, c)
        out[k] = frame
    return out


def _chroma_gradients(d):
    """The chromatic part of a change (h, w, 3) as two orthonormal components (u, v) in grey levels.

    Each of GelSight's three coloured lights shades a slope facing it, so
    the change that differs between channels follows the surface gradient,
    in a frame of the lights' directions; the change common to all
    channels (brightness) does not tell the gradient's direction.
    """
    u = (d[..., 0] - d[..., 1]) / np.sqrt(2.0)
    v = (d[..., 0] + d[..., 1] - 2.0 * d[..., 2]) / np.sqrt(6.0)
    return u, v


def _light_frame(u, v):
    """Rotation (cos, sin) and reflection that make (u, v) most nearly curl-free, as image-axis gradients.

    The curl of ``R(theta) @ (u, v)`` is ``cos * a + sin * b`` with ``a``,
    ``b`` fixed images, so the angle that minimises its energy is the
    eigenvector of a 2x2 matrix; both reflections are tried. The sign (the
    angle up to pi) is left to the caller.
    """
    best = None
    for flip in (1.0, -1.0):
        vv = flip * v
        uy, ux = np.gradient(u)
        vy, vx = np.gradient(vv)
        a, b = (uy - vx).ravel(), (-vy - ux).ravel()
        m = np.array([[a @ a, a @ b], [a @ b, b @ b]])
        vals, vecs = np.linalg.eigh(m)
        rel = vals[0] / max(vals.sum(), _EPS)
        if best is None or rel < best[0]:
            best = (rel, float(vecs[0, 0]), float(vecs[1, 0]), flip)
    return best[1:]


def _integrate(gx, gy):
    """Frankot-Chellappa: the surface whose gradients are nearest (gx, gy), zero-padded to twice the size."""
    h, w = gx.shape
    ph, pw = 2 * h, 2 * w
    wy = 2 * np.pi * np.fft.fftfreq(ph)[:, None]
    wx = 2 * np.pi * np.fft.fftfreq(pw)[None, :]
    gxf = np.fft.fft2(gx, s=(ph, pw))
    gyf = np.fft.fft2(gy, s=(ph, pw))
    denom = wx ** 2 + wy ** 2
    denom[0, 0] = 1.0
    zf = (-1j * wx * gxf - 1j * wy * gyf) / denom
    zf[0, 0] = 0.0
    return np.real(np.fft.ifft2(zf))[:h, :w]


def _shape(z, slope, texture_map, mag, noise, noise_factor):
    """Depth, area, sharpness, spread, eccentricity and texture of one moment's depth map and change."""
    h, w = z.shape
    base = float(np.median(z))
    z = z - base
    depth = max(float(np.percentile(z, 99.5)), _EPS)
    half = z > 0.5 * depth
    half_area = float(half.mean())
    contact = mag > noise_factor * noise
    area = float(contact.mean())
    # the steepest slopes against the mean slope of a cone of this depth over the half-depth disc
    radius = np.sqrt(max(half_area, 1.0 / (h * w)) * h * w / np.pi)
    sharp = float(np.percentile(slope, 99.5)) * radius / depth
    # shoulder: how much wider the contact is at a quarter of its depth than at three quarters
    shoulder = float(np.log((np.mean(z > 0.25 * depth) + 1.0 / (h * w)) / (np.mean(z > 0.75 * depth) + 1.0 / (h * w))))
    weight = np.maximum(z, 0.0)
    total = float(weight.sum())
    if total > 0:
        yy, xx = np.mgrid[0:h, 0:w]
        cy, cx = float((weight * yy).sum()) / total, float((weight * xx).sum()) / total
        syy = float((weight * (yy - cy) ** 2).sum()) / total
        sxx = float((weight * (xx - cx) ** 2).sum()) / total
        sxy = float((weight * (yy - cy) * (xx - cx)).sum()) / total
        ev = np.linalg.eigvalsh(np.array([[syy, sxy], [sxy, sxx]]))
        spread = float(np.log((syy + sxx) / (h * w) + 1e-4))
        ecc = float(1.0 - np.sqrt(max(ev[0], 0.0) / max(ev[1], _EPS)))
    else:
        spread, ecc = float(np.log(1e-4)), 0.0
    # texture: fine (high-frequency) energy of the change in the contact over its coarse energy
    where = contact if contact.any() else np.ones_like(contact)
    texture = float(np.log((np.mean(texture_map[where]) + _EPS) / (np.mean(mag[where] ** 2) + _EPS)))
    return dict(depth=depth, area=area, half_area=half_area, sharp=sharp, shoulder=shoulder, spread=spread,
                ecc=ecc, texture=texture)


def _loglog_slope(x, y):
    """Least-squares slope of log y on log x (0 where x does not vary)."""
    lx, ly = np.log(np.maximum(x, _LOG_FLOOR)), np.log(np.maximum(y, _LOG_FLOOR))
    if np.ptp(lx) < 1e-6:
        return 0.0
    return float(np.polyfit(lx, ly, 1)[0])


def _geometry(small, noise_factor, sigma):
    """The features of one press from its block-averaged frames (T, h, w, C), in FEATURE_NAMES order."""
    t, h, w, c = small.shape
    found = loading_moments(small, MOMENTS)
    if found is None:
        row = np.zeros(len(FEATURE_NAMES))
        row[FEATURE_NAMES.index("log_depth")] = np.log(_LOG_FLOOR)
        row[FEATURE_NAMES.index("log_slope")] = np.log(_LOG_FLOOR)
        row[FEATURE_NAMES.index("log_contrast")] = np.log(_LOG_FLOOR)
        row[FEATURE_NAMES.index("log_spread")] = np.log(1e-4)
        return row
    n_pre, i_peak, frames = found
    # the reference: the mean of the pre-contact frames (quieter than the first frame alone)
    ref = small[:n_pre].mean(axis=0)
    # only the pre-contact frames (for the noise) and the moments are read further
    pre = list(range(1, n_pre)) if n_pre >= 3 else []
    wanted = sorted(set(pre) | set(frames))
    d = small[wanted] - ref
    d -= _frame_medians(d)
    blurred = np.stack([cv2.GaussianBlur(f, (0, 0), sigma) for f in d]) if sigma > 0 else d
    if blurred.ndim == 3:
        blurred = blurred[..., None]
    mag = _norm(blurred)  # (len(wanted), h, w)
    at = {f: k for k, f in enumerate(wanted)}
    # pixel noise: the spread of the change over the pre-contact frames (or the frame's median at the peak)
    if pre:
        mp = mag[[at[f] for f in pre]]
        noise = float(np.median(mp.std(axis=0))) + float(np.median(mp))
    else:
        noise = float(np.median(mag[at[i_peak]]))
    noise = max(noise, 0.05)
    # gradients: the chromatic change in the lights' frame, rotated (once, at the peak) to the image axes
    if c == 3:
        u, v = _chroma_gradients(blurred[at[i_peak]])
        cos, sin, flip = _light_frame(u, v)
    moments = []
    for f in frames:
        b = blurred[at[f]]
        m = mag[at[f]]
        if c == 3:
            u, v = _chroma_gradients(b)
            v = flip * v
            gx, gy = cos * u - sin * v, sin * u + cos * v
            slope = np.hypot(gx, gy)
        else:  # grey frames: the shading change itself stands in for the depth
            gy, gx = np.gradient(b[..., 0])
            slope = m
        z = _integrate(gx, gy) if c == 3 else b[..., 0].astype(np.float64)
        moments.append((z, slope, b, m, f))
    # the sign of depth: the dominant extremum at the peak is the indentation
    z_peak = moments[-1][0] - np.median(moments[-1][0])
    sign = 1.0 if np.percentile(z_peak, 99.5) >= -np.percentile(z_peak, 0.5) else -1.0
    shapes = []
    for z, slope, b, m, f in moments:
        raw = d[at[f]]
        fine = raw - (b if raw.shape == b.shape else b[..., 0])
        texture_map = np.sum(fine ** 2, axis=-1) if fine.ndim == 3 else fine ** 2
        s = _shape(sign * z, slope, texture_map, m, noise, noise_factor)
        s["slope"] = float(np.percentile(slope, 99.5))
        s["contrast"] = float(np.percentile(m, 99.5))
        s["chroma"] = float(np.sum(slope ** 2) / max(np.sum(m ** 2), _EPS)) if c == 3 else 0.0
        shapes.append(s)
    peak = shapes[-1]
    depths = np.array([s["depth"] for s in shapes])
    series = {k: np.array([s[k] for s in shapes]) for k in ("area", "spread", "sharp", "texture")}
    return np.array([
        np.log(max(peak["depth"], _LOG_FLOOR)),
        np.log(max(peak["slope"], _LOG_FLOOR)),
        np.log(max(peak["contrast"], _LOG_FLOOR)),
        peak["area"],
        peak["half_area"],
        peak["sharp"],
        peak["shoulder"],
        peak["spread"],
        peak["ecc"],
        peak["texture"],
        peak["chroma"],
        _loglog_slope(depths, series["area"] + 1.0 / (h * w)),
        _loglog_slope(depths, np.exp(series["spread"])),
        _loglog_slope(depths, series["sharp"]),
        _loglog_slope(depths, np.exp(series["texture"])),
        float(series["area"][1] / max(series["area"][-1], _EPS)) if series["area"][-1] > 0 else 0.0,
        float(depths[1] / max(depths[-1], _EPS)),
    ])


def _press_row(video, max_side, noise_factor, sigma, roi, name):
    return _geometry(_small_rgb(video, max_side, roi, name), noise_factor, sigma)


class ContactGeometryFeatures(PerPressTransformerMixin, TransformerMixin, BaseEstimator):
    """The contact's geometry over a press's loading phase, from GelSight shading.

    Each video is block-averaged to about ``max_side`` pixels on its long
    side and compared with the mean of its pre-contact frames (found as
    :class:`ContactProfileFeatures` finds them), less each frame's median
    change (uniform illumination drift), and smoothed by a Gaussian of
    ``sigma`` pixels. Where the frames are in colour, the part of the change
    that differs between the channels (GelSight's three coloured lights
    shade the slopes facing them) is taken as the gel's surface gradient,
    rotated to the image axes by the angle (and reflection) that makes it
    most nearly curl-free at the peak, and integrated by Frankot-Chellappa
    (FFT) into an approximate depth map, in grey-level pixels. Grey videos
    have no gradients: the shading change stands in for the depth.

    The loading moments are the first frames at which the mean change
    (after a running median over five frames) reaches 25%, 50%, 75% and
    100% of its rise from the pre-contact level to its peak. At the peak:

    - ``log_depth``: log of the depth map's 99.5th percentile above its
      median; ``log_slope``: log of the steepest gradient (99.5th
      percentile); ``log_contrast``: log of the largest change (99.5th
      percentile of its norm over channels; where ``ContactProfileFeatures``
      averages the change over the frame, this is its local strength).
    - ``contact_area``: share of pixels whose change exceeds
      ``noise_factor`` times the pixel noise (the change's spread over the
      pre-contact frames); ``half_depth_area``: share deeper than half the
      depth.
    - ``edge_sharpness``: the steepest gradient over the depth per radius
      of the half-depth disc (1 for a cone; a rigid, flat-ended object that
      keeps its edges gives more); ``shoulder_ratio``: log of the area
      deeper than a quarter of the depth over the area deeper than three
      quarters (a steep-sided contact keeps them close).
    - ``log_spread``: log second moment of the depth about its centroid, as
      a share of the frame; ``eccentricity``: 1 - minor/major axis of that
      moment (0 for a round contact).
    - ``texture_ratio``: log of the fine (removed by the smoothing) energy
      of the change over its energy, in the contact; ``gradient_share``:
      the chromatic (gradient) share of the change's energy.

    And over the four moments, how they grow against each other (log-log
    least-squares slopes against the depth): ``area_depth_slope`` (how the
    contact area grows as it sinks in: a soft object spreads),
    ``spread_depth_slope``, ``sharpness_depth_slope``,
    ``texture_depth_slope``; and ``early_area_share``,
    ``early_depth_share``: area and depth halfway up the rise over those at
    the peak.

    Parameters
    ----------
    features : "all", "scale_free" or sequence of str, default="all"
        Which features to output, in this order (names as in
        :meth:`get_feature_names_out`); every feature is computed either
        way. ``"scale_free"``: the twelve that do not grow with how hard
        the press is made (shapes, ratios and growth slopes), the input of
        :func:`~sklearn_hardness.models.make_contact_geometry_pipeline`.
    max_side : int, default=80
        Frames are block-averaged to about this many pixels on their long
        side (a 240x320 frame to 60x80).
    noise_factor : float, default=4.0
        A pixel is in contact (``contact_area``) where its smoothed change
        exceeds this many times the pixel noise.
    sigma : float, default=1.0
        Standard deviation (pixels, after averaging) of the Gaussian that
        smooths the change before the gradients are read; 0 does not smooth.
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
        An entry is the row, every feature whichever ``features`` are output (under 1 kB).

    Attributes
    ----------
    features_ : tuple of str
        The output features, in order.
    n_features_out_ : int
        Their number (17 for ``features="all"``).

    See Also
    --------
    ContactProfileFeatures : The loading phase's timing, strength and area.
    sklearn_hardness.models.make_contact_geometry_pipeline : These features and a classifier.

    Notes
    -----
    The depth comes from the gradient up to a scale that depends on the
    sensor's lights and gel (it is not calibrated), so the features that
    compare presses across sensors are the scale-free ones (shapes, ratios
    and growth slopes: ``SCALE_FREE`` in this module). Frankot and
    Chellappa, "A method for enforcing integrability in shape from shading
    algorithms", IEEE TPAMI 10(4), 1988.

    Examples
    --------
    >>> import numpy as np
    >>> from sklearn_hardness.features import ContactGeometryFeatures
    >>> yy, xx = np.mgrid[0:32, 0:32]
    >>> video = np.full((20, 32, 32, 3), 120, np.uint8)
    >>> for t in range(8, 20):  # a dome that sinks in, shaded by lights from three sides
    ...     bump = (t - 7) * np.exp(-((yy - 16) ** 2 + (xx - 16) ** 2) / 40.0)
    ...     gy, gx = np.gradient(bump)
    ...     video[t] = np.clip(120 + 20 * np.stack([gx, gy, -gx - gy], axis=-1), 0, 255).astype(np.uint8)
    >>> ContactGeometryFeatures().fit_transform([video]).shape
    (1, 17)
    >>> ContactGeometryFeatures(features=["log_depth", "edge_sharpness"]).fit([video]).get_feature_names_out()
    array(['log_depth', 'edge_sharpness'], dtype=object)
    """

    _parameter_constraints: dict = {
        "features": [str, list, tuple],
        "max_side": [Interval(numbers.Integral, 8, None, closed="left")],
        "noise_factor": [Interval(numbers.Real, 0, None, closed="neither")],
        "sigma": [Interval(numbers.Real, 0, None, closed="left")],
        "roi": [None, tuple, list],
        "n_jobs": [numbers.Integral, None],
        "memory": [None, str, HasMethods(["cache"])],
    }

    _per_press_ignored = ("memory", "n_jobs", "features")  # every feature is computed and cached

    def __init__(self, features="all", max_side=80, noise_factor=4.0, sigma=1.0, roi=None, n_jobs=None, memory=None):
        self.features = features
        self.max_side = max_side
        self.noise_factor = noise_factor
        self.sigma = sigma
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
        self : ContactGeometryFeatures
        """
        if isinstance(self.features, str) and self.features not in ("all", "scale_free"):
            raise ValueError(
                f"features must be 'all', 'scale_free' or a sequence of feature names, got {self.features!r}.")
        check_roi(self.roi)
        check_video_sequence(X)
        self.features_ = check_feature_names(SCALE_FREE if self.features == "scale_free" else self.features,
                                             FEATURE_NAMES)
        self.n_features_out_ = len(self.features_)
        return self

    def transform(self, X):
        """Compute the features of each video.

        Parameters
        ----------
        X : sequence of array-like of shape (T, H, W, 3)
            Press videos (lengths may differ; videos of fewer than three
            frames, or without any change, give a defined row).

        Returns
        -------
        features : ndarray of shape (n_videos, n_features_out_), float64
        """
        check_is_fitted(self)
        X = check_video_sequence(X)
        rows = transform_presses(self, X)[0]
        return rows[:, feature_columns(self.features_, FEATURE_NAMES)]

    def _transform_presses(self, X):
        params = dict(max_side=self.max_side, noise_factor=self.noise_factor, sigma=self.sigma,
                      roi=check_roi(self.roi))
        return map_presses(_press_row, X, params, n_jobs=self.n_jobs), {}

    def get_feature_names_out(self, input_features=None):
        """Names of the features.

        Parameters
        ----------
        input_features : ignored

        Returns
        -------
        names : ndarray of str
        """
        check_is_fitted(self)
        return np.array(self.features_, dtype=object)

    def __sklearn_tags__(self):
        return videos_tags(super().__sklearn_tags__())
