"""Small synthetic press videos for tests of the data layer (not the simulator)."""

import numpy as np


def synthetic_press(
    n_frames=30,
    size=(48, 64),
    contact_start=10,
    peak=20,
    amplitude=60.0,
    noise=1.5,
    drift=0.0,
    gain_drift=0.0,
    radius=12,
    seed=0,
    dtype=np.uint8,
):
    """A GelSight-like press: vignetted coloured background, a bright blob growing
    from ``contact_start`` to full size at ``peak`` and then held, sensor noise,
    additive (``drift`` levels per frame) and multiplicative (``gain_drift`` per
    frame) illumination drift. Returns (T, H, W, 3) ``dtype``."""
    rng = np.random.default_rng(seed)
    h, w = size
    yy, xx = np.mgrid[:h, :w].astype(np.float32)
    vignette = np.exp(-(((yy - h / 2) / h) ** 2 + ((xx - w / 2) / w) ** 2) * 2.0)
    background = (60 + 90 * vignette)[..., None] * np.array([1.0, 0.85, 0.7], np.float32)
    background += np.stack([xx / w * 20, yy / h * 20, np.zeros_like(xx)], axis=-1)
    frames = np.repeat(background[None], n_frames, axis=0).astype(np.float32)
    t = np.arange(n_frames, dtype=np.float32)
    frames *= (1.0 + gain_drift * t)[:, None, None, None]
    frames += (drift * t)[:, None, None, None]
    cy, cx = h / 2 + rng.uniform(-2, 2), w / 2 + rng.uniform(-2, 2)
    r2 = (yy - cy) ** 2 + (xx - cx) ** 2
    for i in range(contact_start, n_frames):
        frac = 1.0 if peak <= contact_start else min(1.0, (i - contact_start + 1) / (peak - contact_start + 1))
        r = radius * np.sqrt(frac)
        blob = np.clip(1.0 - r2 / max(r, 0.5) ** 2, 0, None)
        frames[i] += amplitude * frac * blob[..., None] * np.array([1.0, 0.6, 0.3], np.float32)
    frames += rng.normal(0.0, noise, frames.shape).astype(np.float32)
    frames = np.clip(frames, 0, 255)
    if dtype == np.uint8:
        return np.rint(frames).astype(np.uint8)
    return (frames / 255.0).astype(dtype)


def no_contact(n_frames=20, size=(48, 64), seed=0):
    return synthetic_press(n_frames=n_frames, size=size, contact_start=n_frames + 1, peak=n_frames + 2, seed=seed)


def growing_disc_press(rise, radius, rng, n=60, start=15, level=40):
    """A 32x32 press: a disc growing to ``radius`` over ``rise`` frames from ``start``, then held, on noise."""
    video = np.full((n, 32, 32, 3), 100.0)
    yy, xx = np.mgrid[:32, :32]
    for t in range(start, n):
        r = radius * min(1.0, (t - start + 1) / rise)
        video[t][(yy - 16) ** 2 + (xx - 16) ** 2 <= r * r] += level
    video += rng.normal(0, 1.0, video.shape)
    return np.clip(video, 0, 255).astype(np.uint8)


#: Where the gel lies in the frames of :func:`framed_press`: rows 8-40 of 48, columns 16-48 of 64
#: (``roi`` fractions: top, bottom, left, right).
FRAMED_GEL = (8 / 48, 40 / 48, 0.25, 0.75)


def framed_press(press, rng):
    """``press`` (T, 32, 32, 3) on the gel of a 48x64 frame whose rest brightens at a random time and speed.

    Like a GelSight Wedge grasp, whose frame shows the housing and the other
    finger: a change that has nothing to do with the object.
    """
    n = len(press)
    frame = np.full((n, 48, 64, 3), 90.0) + rng.normal(0, 1.0, (n, 48, 64, 3))
    start, rise = int(rng.integers(5, 40)), int(rng.integers(1, 40))
    for t in range(start, n):
        frame[t] += 60 * min(1.0, (t - start + 1) / rise)
    frame = np.clip(frame, 0, 255).astype(np.uint8)
    frame[:, 8:40, 16:48] = press
    return frame


def hertz_press(c, f_peak, *, n_before=5, n_load=20, n_hold=6, offset=3.0, c_drive=0.0, noise=0.0, rng=None):
    """A press of a Hertz object: position = offset + c F^(2/3) + c_drive F, force 0 before contact.

    The force rises linearly to ``f_peak`` over ``n_load`` frames, holds, then falls back;
    ``noise`` is the s.d. of the recorded force (N).
    """
    load = np.linspace(0.0, f_peak, n_load + 1)[1:]
    force = np.concatenate([np.zeros(n_before), load, np.full(n_hold, f_peak), load[::-1][1:]])
    position = offset + c * force ** (2 / 3) + c_drive * force
    position[:n_before] = offset - np.linspace(2.0, 0.1, n_before)  # still approaching: no force
    if noise:
        force = force + (rng or np.random.default_rng(0)).normal(0.0, noise, len(force))
    return np.column_stack([force, position])
