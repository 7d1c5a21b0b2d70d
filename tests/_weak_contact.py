"""Weak contacts in compressed marker-less videos, calibrated to real GelSight Mini presses.

Real presses of soft everyday objects (issue 10) change the mean residual of the
contact curve from ~0.75 to only ~1.6 grey levels; the stream carries H.264 noise
(a jump on frame 1, a slow rise of ~1 level over ~20 frames, dips at key frames).
These videos reproduce that: a marker-less gel background, a contact whose mean
absolute change at full load is ``strength`` grey levels (a broad faint texture,
a small sharp edge or a dome), sensor noise, illumination drift, a slow local
exposure change, and a real lossy round trip through OpenCV's ``mp4v`` codec
(key frame every 12 frames, as ffmpeg's default GOP).
"""

import os
import tempfile

import cv2
import numpy as np

from sklearn_hardness.io import read_video, write_video

KINDS = ("fabric", "edge", "dome")


def _smooth_noise(rng, shape, sigma):
    field = cv2.GaussianBlur(rng.normal(size=shape).astype(np.float32), (0, 0), sigma)
    return field / (field.std() + 1e-9)


def _background(rng, h, w):
    yy, xx = np.mgrid[:h, :w].astype(np.float32)
    vignette = np.exp(-(((yy - h / 2) / h) ** 2 + ((xx - w / 2) / w) ** 2) * 2.0)
    tint = rng.uniform(0.75, 1.0, 3).astype(np.float32)
    bg = (70 + 80 * vignette)[..., None] * tint
    bg += np.stack([xx / w * 25, yy / h * 25, (1 - xx / w) * 15], axis=-1)
    # the gel's own faint surface texture (static, so it cancels against the first frame)
    bg += 2.0 * _smooth_noise(rng, (h, w), 1.5)[..., None]
    return bg


def _contact_map(rng, kind, h, w):
    """Signed change (h, w, 3) of a fully loaded contact, before scaling."""
    yy, xx = np.mgrid[:h, :w].astype(np.float32)
    cy, cx = rng.uniform(0.3, 0.7) * h, rng.uniform(0.3, 0.7) * w
    if kind == "fabric":
        # faint texture over most of the pad (fabric, foam, sponge)
        height = _smooth_noise(rng, (h, w), rng.uniform(1.0, 2.5)) + 0.8
        height *= np.exp(-(((yy - cy) / (0.6 * h)) ** 2 + ((xx - cx) / (0.6 * w)) ** 2))
    elif kind == "edge":
        # a short sharp line: the edge of a hard object
        angle = rng.uniform(0, np.pi)
        dist = np.abs((yy - cy) * np.cos(angle) - (xx - cx) * np.sin(angle))
        along = np.abs((yy - cy) * np.sin(angle) + (xx - cx) * np.cos(angle))
        width = rng.uniform(0.006, 0.015) * w
        height = np.exp(-((dist / width) ** 2)) * (along < rng.uniform(0.1, 0.3) * w)
    else:
        r = rng.uniform(0.08, 0.25) * h
        height = np.clip(1 - ((yy - cy) ** 2 + (xx - cx) ** 2) / r**2, 0, None) ** 1.5
    height = height.astype(np.float32)
    # three-light shading: each channel sees the surface slope along its light's direction
    gy, gx = np.gradient(height)
    shade = np.stack([gx, 0.5 * (gy - gx), -gy], axis=-1) + 0.3 * height[..., None]
    return shade


def _profile(rng, n_frames, rise):
    """Load per frame in [0, 1]: flat, smooth rise over ``rise`` frames, hold, release."""
    scale = n_frames / 126
    start = int(round(rng.uniform(30, 40) * scale))
    rise = max(1, int(round(rise * scale)))
    hold = int(round(rng.uniform(50, 60) * scale))
    t = np.arange(n_frames, dtype=np.float32)
    up = np.clip((t - start + 1) / rise, 0, 1)
    up = up * up * (3 - 2 * up)
    down = np.clip(1 - (t - (start + rise + hold)) / max(3, 5 * scale), 0, 1)
    return up * down, start, min(start + rise - 1, n_frames - 1)


def weak_press(
    kind="fabric",
    *,
    strength=1.0,
    contact=True,
    n_frames=126,
    size=(240, 320),
    noise=0.6,
    rise=None,
    codec=True,
    seed=0,
):
    """One compressed press video and its true contact start and peak.

    Parameters
    ----------
    kind : {"fabric", "edge", "dome"}
        Shape of the contact.
    strength : float
        Mean absolute change (grey levels, over pixels and channels) the
        contact makes at full load, before noise and codec.
    contact : bool
        False gives the same video with no contact at all.
    rise : int or None
        Frames from first contact to full load (at 126 frames); soft presses
        rise slowly, so ``None`` draws 25-50 for fabric and 3-20 otherwise.

    Returns
    -------
    video : ndarray (n_frames, H, W, 3) uint8
    start, peak : int
        First frame of contact and first frame at full load (-1 without contact).
    """
    rng = np.random.default_rng(seed)
    h, w = size
    if rise is None:
        rise = rng.uniform(25, 50) if kind == "fabric" else rng.uniform(3, 20)
    load, start, peak = _profile(rng, n_frames, rise)
    frames = np.repeat(_background(rng, h, w)[None], n_frames, axis=0)
    if contact:
        change = _contact_map(rng, kind, h, w)
        change *= strength / np.abs(change).mean()
        frames += load[:, None, None, None] * change
    else:
        start = peak = -1
    t = np.arange(n_frames, dtype=np.float32)
    # LED drift: offset and gain (removed by the curve's fit) ...
    frames *= (1 + rng.uniform(-1e-3, 1e-3) * t)[:, None, None, None]
    frames += (rng.uniform(-0.05, 0.05) * t)[:, None, None, None]
    # ... and a slow local exposure change that settles over ~20 frames (not removed)
    settle = (1 - np.exp(-t / rng.uniform(5, 12)))[:, None, None, None]
    frames += settle * rng.uniform(0.3, 0.6) * _smooth_noise(rng, (h, w), 0.15 * w)[..., None]
    # the first frame's exposure differs a little: the jump on frame 1
    frames[0] += rng.uniform(-2.0, 2.0, 3)
    frames += rng.normal(0.0, noise, frames.shape).astype(np.float32)
    video = np.clip(np.rint(frames), 0, 255).astype(np.uint8)
    if codec:
        with tempfile.TemporaryDirectory() as tmp:
            path = os.path.join(tmp, "press.mp4")
            write_video(path, video, fps=25)  # mp4v, lossy
            video = read_video(path)
    return video, int(start), int(peak)
