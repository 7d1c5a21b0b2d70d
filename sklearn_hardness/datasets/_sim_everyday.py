"""Everyday objects for the press simulator: shapes, textures, long hand-held videos, codecs.

The ``everyday`` preset of :func:`~sklearn_hardness.datasets.make_presses`
stands in for GelSight Mini recordings of household objects (see
``docs/simulator.md``): many objects in three hardness ranks, each with a
shape and a surface texture, a few presses per object, long videos in which
contact starts late, a marker-less gel by default, and optional real lossy
compression.

Mechanics are those of the flat presets (``_sim_mechanics.simulate_press``:
gel and object as Hertz-like springs in series, a drive that stops on a
lagged force estimate); only the contact *geometry* changes with the shape.
With total approach ``delta`` and gel indentation ``delta_g`` (the gel's
share), the gel surface is ``h(x, y) = delta_g P(x, y)`` with a normalised
profile ``P`` whose size grows with ``delta``:

``dome`` / ``point``
    ``P = f(r / a)``, ``a = sqrt(R delta)``, ``1/R = 1/R_gel + 1/R_obj``;
    ``f`` is the Hertz profile (``1 - rho^2/2`` inside the contact).
``edge``
    ``P = f(|d| / b) w(s)``: ``d`` the distance to the edge line, ``b =
    sqrt(R_edge delta)``, ``w`` a smooth window along the edge.
``ridge``
    parallel edges of pitch ``p`` under a dome window of radius
    ``sqrt(R_obj delta)``.
``broad`` (foam, fabric, pillows)
    a conforming soft body: ``P = w(r / a) (1 - tau + tau T(x, y))`` with a
    large ``a = sqrt(R_obj delta)`` and the object's texture ``T`` (foam
    cells or a fabric weave), so the contact is weak and spread out.

Every shape's profile is multiplied by ``1 + tau_s (T - 1/2)`` (surface
texture, small for hard objects). Shading is the three-light normal shading
of ``_sim_optics``; markers, if any, move by ``-lambda * s * grad P``.

Pre-contact artefacts of real recordings are modelled as a zero-mean,
spatially smooth "ambient leak" field (light through the gel, the
approaching hand's shadow) rising as ``A (1 - exp(-t / tau_a))`` from the
first frame, plus temporal camera noise; a real codec (``codec="mp4v"``)
adds blockiness and key-frame periodicity.
"""

from __future__ import annotations

import os
import tempfile

import cv2
import numpy as np

from ..io import read_video, write_video
from ._sim_mechanics import simulate_press

__all__ = [
    "EVERYDAY_RANKS",
    "OBJECT_KINDS",
    "sample_objects",
    "sample_press",
    "render_everyday_press",
    "apply_codec",
    "check_codec",
]

#: Class names, in the order a manifest's labels sort (alphabetical), and their rank (1 soft .. 3 hard).
EVERYDAY_RANKS = (("hard", 3.0), ("moderate", 2.0), ("soft", 1.0))

#: Object kinds per rank: (name, shape, radius range mm, edge/ridge parameter range mm, texture).
OBJECT_KINDS = {
    "hard": [
        ("marble", "dome", (4.0, 12.0), None, "smooth"),
        ("mug", "dome", (25.0, 60.0), None, "smooth"),
        ("phone", "dome", (150.0, 400.0), None, "smooth"),
        ("ruler edge", "edge", (0.15, 0.8), None, "smooth"),
        ("box corner", "edge", (0.3, 1.5), None, "grain"),
        ("bottle cap", "ridge", (10.0, 20.0), (0.8, 1.6), "smooth"),
        ("screw", "ridge", (2.0, 5.0), (0.5, 1.2), "smooth"),
        ("pen tip", "point", (0.3, 1.2), None, "smooth"),
        ("wood block", "dome", (80.0, 300.0), None, "grain"),
    ],
    "moderate": [
        ("rubber ball", "dome", (15.0, 40.0), None, "grain"),
        ("eraser", "edge", (0.8, 2.5), None, "grain"),
        ("fruit", "dome", (25.0, 50.0), None, "grain"),
        ("shoe sole", "ridge", (40.0, 120.0), (1.5, 3.5), "grain"),
        ("cable", "edge", (1.5, 4.0), None, "smooth"),
        ("silicone pad", "dome", (100.0, 300.0), None, "smooth"),
        ("cork", "dome", (30.0, 120.0), None, "foam"),
    ],
    "soft": [
        ("foam", "broad", (60.0, 250.0), None, "foam"),
        ("sponge", "broad", (40.0, 150.0), None, "foam"),
        ("pillow", "broad", (100.0, 400.0), None, "weave"),
        ("fabric", "broad", (80.0, 300.0), None, "weave"),
        ("cotton ball", "dome", (8.0, 20.0), None, "foam"),
        ("feather duster", "broad", (30.0, 80.0), None, "foam"),
    ],
}

_TEXTURE_SCALE = {"smooth": (1.0, 2.0), "grain": (0.4, 1.0), "foam": (0.3, 0.9), "weave": (0.5, 1.2)}
_EDGE_ROUND = 1e-3


def sample_objects(rng, n_objects, class_ratio, params):
    """Draw ``n_objects`` objects: rank, kind, shape, size, compliance and texture.

    Objects are split over the three ranks in proportion to ``class_ratio``
    (soft : moderate : hard), at least one per rank.
    """
    ratio = np.asarray(class_ratio, dtype=float)
    counts = np.maximum(np.round(n_objects * ratio / ratio.sum()).astype(int), 1)
    while counts.sum() > n_objects:
        counts[np.argmax(counts)] -= 1
    while counts.sum() < n_objects:
        counts[np.argmin(counts / ratio)] += 1
    ranks = {"soft": counts[0], "moderate": counts[1], "hard": counts[2]}
    objects = []
    for cls, (name, _) in enumerate(EVERYDAY_RANKS):
        rank = ("soft", "moderate", "hard").index(name)
        lo, hi = params[f"{name}_compliance_range"]
        kinds = [(kind, rank) for kind in OBJECT_KINDS[name]]
        if not params.get("kinds_by_rank", True):
            # every kind in every rank, in an order of its own per rank (True, the default, draws as before);
            # a kind keeps the texture depth of the rank it is listed under (a foam's cells are deep anywhere)
            pool = [(kind, ("soft", "moderate", "hard").index(r)) for r in ("hard", "moderate", "soft")
                    for kind in OBJECT_KINDS[r]]
            kinds = [pool[i] for i in rng.permutation(len(pool))]
        for j in range(ranks[name]):
            (kind, shape, r_range, p_range, texture), home = kinds[j % len(kinds)]
            tex_lo, tex_hi = _TEXTURE_SCALE[texture]
            objects.append(dict(
                target=cls,
                kind=kind,
                shape=shape,
                radius=float(np.exp(rng.uniform(np.log(r_range[0]), np.log(r_range[1])))),
                pitch=float(rng.uniform(*p_range)) if p_range else 0.0,
                compliance=float(np.exp(rng.uniform(np.log(lo), np.log(hi)))),
                texture=texture,
                texture_wavelength=float(rng.uniform(tex_lo, tex_hi)),
                texture_amplitude=float(params["texture_amplitude"][home] * rng.uniform(0.6, 1.4)),
                angle=float(rng.uniform(0, np.pi)),
                texture_seed=int(rng.integers(2**31 - 1)),
            ))
    return objects


def sample_press(rng, obj, *, c_gel, params):
    """Draw one press of ``obj`` and simulate its mechanics, cropped to the video length.

    Returns the per-frame mechanics (see ``simulate_press``) and a dict of the
    press's sampled parameters.
    """
    fps = params["fps"]
    u = rng.uniform()
    if u < params["truncated_fraction"]:
        n_frames = int(rng.integers(3, 8))
        n_before = int(rng.integers(*params["frames_before_range"]) + 1)
    elif u < params["truncated_fraction"] + params["short_fraction"]:
        n_frames = params["short_length"]
        n_before = int(rng.integers(8, 16))
    else:
        n_frames = params["video_length"]
        lo, hi = params["frames_before_range"]
        n_before = int(rng.integers(lo, hi + 1))
    hand = bool(rng.uniform() < params["hand_fraction"])
    c_obj = obj["compliance"] * np.exp(params["press_spread"] * rng.standard_normal())
    f_push = rng.uniform(*params["force_range"])
    v_push = rng.uniform(*(params["hand_speed_range"] if hand else params["speed_range"]))
    lag = rng.uniform(*params["force_lag_range"])
    hold = rng.uniform(*params["hold_range"])
    ret = rng.uniform(*params["retreat_speed_ratio"])
    offset = rng.normal(0.0, params["contact_offset"], 2)
    frames, summary = simulate_press(
        rng, c_gel=c_gel, c_obj=c_obj, dome_radius=params["dome_radius"], m=params["hertz_exponent"],
        c_drive=params["drive_compliance"], f_push=f_push, v_push=v_push,
        unevenness=params["speed_unevenness"] if hand else 0.0, force_lag=lag,
        deceleration=params["deceleration"], hold=hold, retreat_ratio=ret, fps=fps,
        n_before=n_before, n_after=max(n_frames, 1), timestamp_jitter=params["timestamp_jitter"],
        force_noise=params["force_noise"], lateral_gain_object=params["lateral_gain_object"],
        lateral_gain_gel=params["lateral_gain_gel"],
    )
    total = len(frames["time"])
    if total < n_frames:  # long holds end the press after the video would; pad with released frames
        pad = n_frames - total
        for k, v in frames.items():
            fill = v[-1] + np.arange(1, pad + 1) / fps if k == "time" else np.zeros(pad) + (
                frames["force"][-1] - frames["force_true"][-1] if k == "force" else 0.0)
            frames[k] = np.concatenate([v, fill])
    frames = {k: v[:n_frames].copy() for k, v in frames.items()}
    row = dict(F_push=f_push, v_push=v_push, force_lag=lag, hold=hold, retreat_speed=ret * v_push,
               compliance_object=c_obj, compliance_gel=c_gel, dome_radius=params["dome_radius"],
               offset_x=offset[0], offset_y=offset[1], n_before=n_before, n_after=n_frames - n_before,
               hand=float(hand), n_frames=n_frames, **summary)
    return frames, row


def _hertz_height(rho):
    """Hertz surface height for contact radius 1: ``1 - rho^2/2`` inside, the half-space tail outside."""
    rho = np.asarray(rho, dtype=np.float32)
    r_out = np.maximum(rho, 1.0)
    tail = ((2.0 - r_out**2) * np.arcsin(1.0 / r_out) + np.sqrt(r_out**2 - 1.0)) / np.pi
    taper = np.clip((4.0 - rho) / 2.0, 0.0, 1.0)  # thin gel on a rigid backing: the tail ends
    return np.where(rho <= 1.0, 1.0 - 0.5 * rho**2, tail * taper * taper * (3 - 2 * taper))


def _texture(obj, x, y):
    """Object texture in [0, 1] at positions (mm) on the object's surface."""
    rng = np.random.default_rng(obj["texture_seed"])
    lam = obj["texture_wavelength"]
    if obj["texture"] == "weave":
        c, s = np.cos(obj["angle"]), np.sin(obj["angle"])
        u, v = c * x + s * y, -s * x + c * y
        k = 2 * np.pi / lam
        t = 0.5 + 0.25 * (np.sin(k * u) * np.abs(np.sin(0.5 * k * v)) + np.sin(k * v) * np.abs(np.sin(0.5 * k * u)))
        return t.astype(np.float32)
    n = 10
    theta = rng.uniform(0, 2 * np.pi, n)
    k = 2 * np.pi / (lam * rng.uniform(0.7, 1.4, n))
    phase = rng.uniform(0, 2 * np.pi, n)
    t = np.zeros(np.broadcast(x, y).shape, np.float32)
    for i in range(n):
        t += np.cos(k[i] * (np.cos(theta[i]) * x + np.sin(theta[i]) * y) + phase[i]).astype(np.float32)
    t = t / np.sqrt(2.0 * n)  # unit s.d.
    if obj["texture"] == "foam":  # cells: sharp walls, flat pores
        t = np.abs(t)
    return np.clip(0.5 + 0.35 * t, 0.0, 1.0).astype(np.float32)


def _profile(obj, x, y, approach, gel_radius, texture):
    """Normalised gel profile P(x, y) (peak ~1) and its length scale (mm) at total approach ``approach``.

    ``texture`` is the object's texture on the same grid (:func:`_texture`).
    """
    shape = obj["shape"]
    r_eff = 1.0 / (1.0 / gel_radius + 1.0 / obj["radius"])
    c, s = np.cos(obj["angle"]), np.sin(obj["angle"])
    if shape in ("dome", "point"):
        a = np.sqrt(r_eff * approach)
        prof = _hertz_height(np.sqrt(x * x + y * y) / a)
    elif shape == "edge":
        a = np.sqrt(obj["radius"] * approach)
        d = -s * x + c * y
        along = c * x + s * y
        prof = _hertz_height(np.abs(d) / a) * np.clip(1.2 - np.abs(along) / 12.0, 0.0, 1.0)
    elif shape == "ridge":
        b = np.sqrt(min(obj["pitch"] * 0.3, r_eff) * approach)
        a = np.sqrt(r_eff * approach)
        d = -s * x + c * y
        p = obj["pitch"]
        d = np.abs(np.mod(d + p / 2, p) - p / 2)
        prof = _hertz_height(d / max(b, 1e-3)) * _hertz_height(np.sqrt(x * x + y * y) / (a + p))
    else:  # broad soft body conforming to the gel
        a = np.sqrt(r_eff * approach)
        prof = np.clip(1.6 - np.sqrt(x * x + y * y) / a, 0.0, 1.0)
        prof = prof * prof * (3 - 2 * prof)
        tau = min(obj["texture_amplitude"], 1.0)
        return prof * (1.0 - tau + tau * texture), a
    tau = obj["texture_amplitude"]
    return prof * (1.0 + tau * (texture - 0.5)), a


def _conform(prof, kappa, object_share, scale_px):
    """A compliant object's imprint: ``prof`` smoothed over ``kappa * object_share * scale``.

    A soft body flattens its own edges, points and texture against the gel rather than
    pressing them into it: the gel sees the same load (the same displaced volume, as the
    smoothing keeps the profile's integral) spread over a length that grows with the
    object's share of the deformation (``delta_obj / delta``; near 0 for a rigid object).
    """
    return _smooth(prof, kappa * object_share * scale_px)


def _smooth(prof, sigma_px):
    """``prof`` smoothed by a Gaussian of s.d. ``sigma_px`` pixels, its integral kept (none below 0.3 px)."""
    sigma = float(sigma_px)
    if sigma < 0.3:
        return prof
    return cv2.GaussianBlur(np.ascontiguousarray(prof, dtype=np.float32), (0, 0), sigma,
                            borderType=cv2.BORDER_CONSTANT)


def _ambient_field(rng, h2, w2):
    """Smooth zero-mean field of unit s.d. (light leaking through the gel, the approaching hand's shadow)."""
    f = rng.standard_normal((max(h2 // 8, 2), max(w2 // 8, 2))).astype(np.float32)
    f = cv2.resize(f, (w2, h2), interpolation=cv2.INTER_CUBIC)
    f = cv2.GaussianBlur(f, (0, 0), max(w2 / 24.0, 1.0))
    f -= f.mean()
    return f / max(float(f.std()), 1e-6)


def render_everyday_press(sensor, obj, mech, center_mm, rng, params):
    """Render one press of an everyday object as a ``(T, H, W, 3)`` ``uint8`` video."""
    h, w = sensor.image_size
    h2, w2 = (h + 1) // 2, (w + 1) // 2
    mm_per_px2 = 2.0 / sensor.px_per_mm
    n_frames = len(mech["time"])
    xs = (np.arange(w2, dtype=np.float32) - (w2 - 1) / 2) * mm_per_px2 - center_mm[0]
    ys = (np.arange(h2, dtype=np.float32) - (h2 - 1) / 2) * mm_per_px2 - center_mm[1]
    x, y = np.meshgrid(xs, ys)
    texture = _texture(obj, x, y)  # fixed to the object: computed once per press
    leak = _ambient_field(rng, h2, w2) * np.float32(params["ambient_leak"])
    leak = cv2.resize(leak, (w, h), interpolation=cv2.INTER_LINEAR)[..., None]
    tau_a = rng.uniform(*params["ambient_rise_frames"])
    # Camera noise: random crops of the sensor's noise bank (no 100 MB of normals per video).
    bank = sensor.noise
    noise_idx = rng.integers(0, bank.shape[0], n_frames)
    noise_off = rng.integers(0, bank.shape[1] - h + 1, (n_frames, 2))
    elev_l, elev_z = sensor.l_xy, sensor.l_z
    denom = np.float32(sensor.ambient + elev_z)
    lights = [(np.float32(elev_l * np.cos(p)), np.float32(elev_l * np.sin(p))) for p in sensor.azimuth]
    lat = (params["lateral_gain_object"] * mech["object_indentation"]
           + params["lateral_gain_gel"] * mech["gel_indentation"])
    video = np.empty((n_frames, h, w, 3), np.uint8)
    buf = np.empty((h, w, 3), np.float32)
    for t in range(n_frames):
        rise = np.float32(1.0 - np.exp(-t / tau_a)) if t > 0 else np.float32(0.0)
        np.add(sensor.bg, leak * rise, out=buf)
        depth = float(mech["gel_indentation"][t])
        approach = float(mech["approach"][t])
        if depth > 1e-5 and approach > 1e-5:
            prof, scale = _profile(obj, x, y, approach, params["dome_radius"], texture)
            # Thin gel on a rigid backing: its local depth follows the mean contact pressure F / A.
            area = max(float(np.count_nonzero(prof > 0.5)), 1.0) * mm_per_px2**2
            depth = min(depth, float(mech["force_true"][t]) / (params["gel_foundation_modulus"] * area))
            kappa = params.get("conformity", 0.0)
            if kappa > 0:  # the same load (gel volume) spread by a compliant object
                prof = _conform(prof, kappa, mech["object_indentation"][t] / approach, scale / mm_per_px2)
            # the gel layer's own spreading (the same for every object) and a compliant object's rounding of
            # its edges, ridges and texture, over a length that grows with its own indentation (mm)
            spread = np.hypot(params.get("gel_spread", 0.0),
                              params.get("object_rounding", 0.0) * float(mech["object_indentation"][t]))
            if spread > 0:
                prof = _smooth(prof, spread / mm_per_px2)
            gy, gx = np.gradient(prof.astype(np.float32), mm_per_px2)
            hx, hy = gx * np.float32(depth), gy * np.float32(depth)
            inv = 1.0 / np.sqrt(1.0 + hx * hx + hy * hy)
            shade = np.empty((h2, w2, 3), np.float32)
            for c, (lx, ly) in enumerate(lights):
                shade[..., c] = (np.maximum(-hx * lx - hy * ly + elev_z, 0.0) * inv + sensor.ambient) / denom
            shade = cv2.resize(shade, (w, h), interpolation=cv2.INTER_LINEAR)
            if sensor.markers:
                k = np.float32(-lat[t] * scale * sensor.px_per_mm)
                disp = np.stack([gx * k, gy * k], axis=-1).astype(np.float32)
                disp = cv2.resize(disp, (w, h), interpolation=cv2.INTER_LINEAR)
                disp[..., 0] += sensor.xx
                disp[..., 1] += sensor.yy
                warped = cv2.remap(sensor.marker_mask, disp, None, cv2.INTER_LINEAR,
                                   borderMode=cv2.BORDER_REPLICATE)
                np.multiply(sensor.bg_plain * warped[..., None], shade, out=shade)
                np.add(shade, leak * rise, out=buf)
            else:
                np.multiply(buf, shade, out=buf)
        oy, ox = noise_off[t]
        buf += bank[noise_idx[t], oy:oy + h, ox:ox + w]
        np.clip(buf, 0, 255, out=buf)
        np.rint(buf, out=buf)
        video[t] = buf
    return video


_CODEC_EXT = {"mp4v": ".mp4", "avc1": ".mp4", "mjpg": ".avi"}


def check_codec(codec):
    """Validate ``codec`` and check that this OpenCV build can write it; return it lower-cased or None."""
    if codec is None:
        return None
    if not isinstance(codec, str) or codec.lower() not in _CODEC_EXT:
        raise ValueError(f"codec must be None or one of {sorted(_CODEC_EXT)}, got {codec!r}.")
    codec = codec.lower()
    with tempfile.TemporaryDirectory() as tmp:
        path = os.path.join(tmp, "probe" + _CODEC_EXT[codec])
        writer = cv2.VideoWriter(path, cv2.VideoWriter_fourcc(*codec.upper() if codec == "mjpg" else codec),
                                 25.0, (32, 32))
        ok = writer.isOpened()
        writer.release()
    if not ok:
        raise ValueError(
            f"codec {codec!r} cannot be written by this OpenCV build ({cv2.__version__}); "
            "use codec='mp4v' (MPEG-4 Part 2, available in every FFmpeg build) or None."
        )
    return codec


def apply_codec(video, codec, fps):
    """Pass ``video`` through a real lossy codec (write a temporary file, read it back)."""
    fourcc = codec.upper() if codec == "mjpg" else codec
    with tempfile.TemporaryDirectory() as tmp:
        path = os.path.join(tmp, "press" + _CODEC_EXT[codec])
        write_video(path, video, fps=fps, fourcc=fourcc)
        out = read_video(path)
    if len(out) != len(video):  # a decoder may drop a trailing frame; keep the timeline
        raise RuntimeError(f"codec {codec!r} returned {len(out)} of {len(video)} frames.")
    return out
