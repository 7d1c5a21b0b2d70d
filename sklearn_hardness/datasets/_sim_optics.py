"""Optics of the press simulator: what the GelSight camera sees.

A sensor is a static background (three coloured side lights giving a colour
gradient, vignetting, a faint fixed pattern of the gel coating), a grid of
dark markers, and a camera with Gaussian read noise. A press deforms the gel
radially around the contact centre: the height of the gel surface follows the
Hertz profile scaled to the gel's share of the indentation, and each of the
three lights shades the surface by its normal,

.. math::

    S_c = \\frac{\\kappa + \\max(0, \\mathbf n \\cdot \\mathbf l_c)}{\\kappa + l_{c,z}},
    \\qquad \\mathbf n = \\frac{(-h_x, -h_y, 1)}{\\sqrt{1 + |\\nabla h|^2}},

multiplying channel ``c`` of the background (``kappa``: ambient light). The
markers are painted on the gel and move with its lateral displacement
``u_r(r)``; they are warped by inverse mapping ``M(x) = M_0(x - u(x))``.

Only pixels within ``RHO_MAX`` contact radii of the centre are rendered for a
contact frame; frames without contact are background x drift + noise.
"""

from __future__ import annotations

import cv2
import numpy as np

__all__ = ["SensorOptics", "render_press", "RHO_MAX", "hertz_profiles"]

#: Rendering radius in units of the contact radius (profiles taper to 0 there).
RHO_MAX = 2.5
_RHO_TAPER = 1.5  # start of the cosine taper (thin gel layer: the Hertz tail is cut)
_N_TAB = 2048
_NOISE_BANK = 12
_NOISE_PAD = 16


def hertz_profiles(rho):
    """Radial profiles of the gel surface for contact radius 1.

    Parameters
    ----------
    rho : ndarray
        Distance from the contact centre over the contact radius.

    Returns
    -------
    slope : ndarray
        ``f'(rho)`` with the gel height ``h(r) = delta_g f(r/a)``, so that the
        surface slope is ``dh/dr = (delta_g / a) f'(rho)``. Inside the contact
        ``f = 1 - rho^2 / 2`` (conforming to the dome); outside, the Hertz
        half-space solution ``f = ((2 - rho^2) asin(1/rho) + sqrt(rho^2 - 1)) / pi``,
        whose derivative is ``(2/pi) (sqrt(rho^2 - 1)/rho - rho asin(1/rho))``.
        A cosine taper from 1.5 to 2.5 contact radii stands for the thin gel
        layer on its rigid backing.
    shift : ndarray
        Relative lateral marker displacement: ``rho`` inside (uniform radial
        strain of the stuck region), ``1/rho`` outside, same taper.
    """
    rho = np.asarray(rho, dtype=float)
    out = rho > 1.0
    r_out = np.where(out, rho, 2.0)
    slope_out = (2.0 / np.pi) * (np.sqrt(r_out**2 - 1.0) / r_out - r_out * np.arcsin(1.0 / r_out))
    slope = np.where(out, slope_out, -rho)
    shift = np.where(out, 1.0 / r_out, rho)
    taper = np.clip((RHO_MAX - rho) / (RHO_MAX - _RHO_TAPER), 0.0, 1.0)
    taper = np.where(rho <= _RHO_TAPER, 1.0, 0.5 - 0.5 * np.cos(np.pi * taper))
    return slope * taper, shift * taper


_TAB_RHO = np.linspace(0.0, RHO_MAX, _N_TAB)
_TAB_SLOPE, _TAB_SHIFT = (t.astype(np.float32) for t in hertz_profiles(_TAB_RHO))
_TAB_SCALE = np.float32((_N_TAB - 1) / RHO_MAX)


class SensorOptics:
    """Static appearance of one sensor (background, markers, lights, noise bank).

    Parameters
    ----------
    rng : numpy.random.Generator
    image_size : (int, int)
    params : dict
        Validated simulator parameters.
    markers : bool
    """

    def __init__(self, rng, image_size, params, markers=True):
        h, w = image_size
        self.image_size = (h, w)
        self.px_per_mm = w / params["field_of_view"]
        # Three lights (R, G, B) ``light_spread`` degrees apart around the middle one (120: evenly
        # around the gel, the summed light has no direction), sensor-specific rotation.
        rot = rng.uniform(-10, 10)
        spread = float(params.get("light_spread", 120.0))
        self.azimuth = np.deg2rad(90.0 + np.array([-spread, 0.0, spread]) + rot)
        elev = np.deg2rad(params["light_elevation"])
        self.l_xy = np.float32(np.sin(elev))
        self.l_z = np.float32(np.cos(elev))
        self.ambient = np.float32(params["shading_ambient"])

        yy, xx = np.mgrid[0:h, 0:w].astype(np.float32)
        u = (xx - (w - 1) / 2) / (w / 2)
        v = (yy - (h - 1) / 2) / (w / 2)
        base = np.array([0.62, 0.60, 0.64]) * rng.uniform(0.95, 1.05, 3)
        bg = np.empty((h, w, 3), np.float32)
        for c in range(3):
            # The side of the image near LED c is tinted with its colour.
            grad = 0.16 * (u * np.cos(self.azimuth[c]) + v * np.sin(self.azimuth[c]))
            bg[..., c] = base[c] + grad
        r2 = (u**2 + v**2) / (1.0 + (h / w) ** 2)
        bg *= (1.0 - params["vignetting"] * r2)[..., None]
        # Faint fixed pattern of the reflective coating (low spatial frequency).
        pattern = rng.normal(0.0, 1.0, (h, w)).astype(np.float32)
        sigma = max(w / 40.0, 1.0)
        pattern = cv2.GaussianBlur(pattern, (0, 0), sigma)
        pattern *= 0.015 / max(float(pattern.std()), 1e-6)
        bg *= (1.0 + pattern)[..., None]
        self.bg_plain = np.ascontiguousarray(bg * 255.0, dtype=np.float32)

        self.markers = bool(markers)
        if self.markers:
            self.marker_mask = self._marker_mask(rng, h, w, params)
            self.bg = self.bg_plain * self.marker_mask[..., None]
        else:
            self.marker_mask = None
            self.bg = self.bg_plain
        self.xx = xx
        self.yy = yy
        # Noise bank: random crops of a few padded noise frames give many
        # distinct noise frames without drawing 230k normals per frame.
        self.noise = (
            rng.standard_normal((_NOISE_BANK, h + _NOISE_PAD, w + _NOISE_PAD, 3), dtype=np.float32)
            * np.float32(params["noise_std"])
        )

    def _marker_mask(self, rng, h, w, params):
        ppm = self.px_per_mm
        pitch = params["marker_spacing"] * ppm
        radius = params["marker_radius"] * ppm
        angle = np.deg2rad(rng.uniform(-2, 2))
        off = rng.uniform(0, pitch, 2)
        n = int(np.ceil(max(h, w) / pitch)) + 3
        i, j = np.meshgrid(np.arange(-n, n + 1), np.arange(-n, n + 1), indexing="ij")
        gx = i.ravel() * pitch
        gy = j.ravel() * pitch
        cx = w / 2 + off[0] + gx * np.cos(angle) - gy * np.sin(angle)
        cy = h / 2 + off[1] + gx * np.sin(angle) + gy * np.cos(angle)
        cx = cx + rng.normal(0, 0.04 * pitch, cx.size)
        cy = cy + rng.normal(0, 0.04 * pitch, cy.size)
        keep = (cx > -pitch) & (cx < w + pitch) & (cy > -pitch) & (cy < h + pitch)
        ss = 4  # supersampling for smooth edges
        canvas = np.zeros((h * ss, w * ss), np.uint8)
        rad = max(int(round(radius * ss)), 1)
        for x, y in zip(cx[keep], cy[keep]):
            cv2.circle(canvas, (int(round(x * ss)), int(round(y * ss))), rad, 255, -1, cv2.LINE_8)
        cov = cv2.resize(canvas.astype(np.float32) / 255.0, (w, h), interpolation=cv2.INTER_AREA)
        cov = cv2.GaussianBlur(cov, (0, 0), max(0.3 * radius, 0.4))
        return (1.0 - params["marker_darkness"] * cov).astype(np.float32)


def _drift_gains(rng, time, amplitude):
    """Slow illumination gain (LED warm-up, exposure control), one per frame."""
    if amplitude <= 0:
        return np.ones(len(time), np.float32)
    period = rng.uniform(4.0, 12.0)
    phase = rng.uniform(0, 2 * np.pi)
    trend = rng.uniform(-1, 1) * amplitude / 2.0  # per second
    g = 1.0 + amplitude * np.sin(2 * np.pi * time / period + phase) + trend * time
    return g.astype(np.float32)


def render_press(sensor, mech, center_mm, rng, drift_amplitude):
    """Render the video of one press.

    Parameters
    ----------
    sensor : SensorOptics
    mech : dict of ndarray
        Per-frame mechanics from :func:`simulate_press`.
    center_mm : (float, float)
        Offset of the contact centre from the image centre, mm (x, y).
    rng : numpy.random.Generator
        Source of the per-frame noise and drift.
    drift_amplitude : float

    Returns
    -------
    video : ndarray of shape (T, H, W, 3), uint8
    """
    h, w = sensor.image_size
    ppm = np.float32(sensor.px_per_mm)
    n_frames = len(mech["time"])
    gains = _drift_gains(rng, mech["time"], drift_amplitude)
    noise_idx = rng.integers(0, _NOISE_BANK, n_frames)
    noise_off = rng.integers(0, _NOISE_PAD + 1, (n_frames, 2))

    a_px = (mech["contact_radius"] * ppm).astype(np.float32)
    with np.errstate(divide="ignore", invalid="ignore"):
        k_slope = np.where(a_px > 0, mech["gel_indentation"] / np.maximum(mech["contact_radius"], 1e-12), 0.0)
    k_slope = k_slope.astype(np.float32)
    shift_px = (mech["lateral_shift"] * ppm).astype(np.float32)
    contact = a_px >= 0.5

    cx = (w - 1) / 2 + center_mm[0] * ppm
    cy = (h - 1) / 2 + center_mm[1] * ppm
    video = np.empty((n_frames, h, w, 3), np.uint8)
    buf = np.empty((h, w, 3), np.float32)
    if contact.any():
        # Press bounding box; shading and marker shifts are smooth, so they are
        # computed on a half-resolution grid (block centres) and upsampled.
        half = RHO_MAX * float(a_px.max()) + 2.0
        bx0, bx1 = max(int(cx - half), 0), min(int(np.ceil(cx + half)) + 1, w)
        by0, by1 = max(int(cy - half), 0), min(int(np.ceil(cy + half)) + 1, h)
        if bx1 <= bx0 or by1 <= by0:  # contact entirely outside the image
            contact[:] = False
        else:
            xs = bx0 + 0.5 + 2.0 * np.arange((bx1 - bx0 + 1) // 2, dtype=np.float32)
            ys = by0 + 0.5 + 2.0 * np.arange((by1 - by0 + 1) // 2, dtype=np.float32)
            dx = (xs - np.float32(cx))[None, :]
            dy = (ys - np.float32(cy))[:, None]
            r = np.sqrt(dx * dx + dy * dy)
            rs = np.maximum(r, np.float32(1e-6))
            cos_p, sin_p = dx / rs, dy / rs
            # Per-light directional factor l_xy * cos(psi - phi_c), shape (h2, w2, 3).
            proj = np.stack(
                [sensor.l_xy * (cos_p * np.float32(np.cos(p)) + sin_p * np.float32(np.sin(p)))
                 for p in sensor.azimuth], axis=-1)
            denom = np.float32(sensor.ambient + sensor.l_z)
    for t in range(n_frames):
        np.multiply(sensor.bg, gains[t], out=buf)  # scalar gain: slow illumination drift
        if contact[t]:
            half = RHO_MAX * float(a_px[t]) + 2.0
            j0 = max(int((cx - half - bx0) // 2), 0)
            j1 = min(int((cx + half - bx0) // 2) + 1, len(xs))
            i0 = max(int((cy - half - by0) // 2), 0)
            i1 = min(int((cy + half - by0) // 2) + 1, len(ys))
            x0, x1 = bx0 + 2 * j0, min(bx0 + 2 * j1, w)
            y0, y1 = by0 + 2 * i0, min(by0 + 2 * i1, h)
            if x1 > x0 and y1 > y0:
                loc = (slice(i0, i1), slice(j0, j1))
                idx = r[loc] * (_TAB_SCALE / a_px[t])
                np.minimum(idx, _N_TAB - 1, out=idx)
                idx = idx.astype(np.intp)
                slope = _TAB_SLOPE[idx]
                slope *= k_slope[t]
                inv = 1.0 / np.sqrt(1.0 + slope * slope)
                shade = proj[loc] * -slope[..., None]
                shade += sensor.l_z
                np.maximum(shade, 0.0, out=shade)
                shade *= inv[..., None]
                shade += sensor.ambient
                shade *= gains[t] / denom
                size = (x1 - x0, y1 - y0)
                shade = cv2.resize(shade, size, interpolation=cv2.INTER_LINEAR)
                out = buf[y0:y1, x0:x1]
                np.multiply(sensor.bg_plain[y0:y1, x0:x1], shade, out=out)
                if sensor.markers:
                    shift = _TAB_SHIFT[idx]
                    shift *= -shift_px[t]
                    disp = np.stack([shift * cos_p[loc], shift * sin_p[loc]], axis=-1)
                    disp = cv2.resize(disp, size, interpolation=cv2.INTER_LINEAR)
                    disp[..., 0] += sensor.xx[y0:y1, x0:x1]
                    disp[..., 1] += sensor.yy[y0:y1, x0:x1]
                    warped = cv2.remap(sensor.marker_mask, disp, None, cv2.INTER_LINEAR,
                                       borderMode=cv2.BORDER_REPLICATE)
                    out *= warped[..., None]
        oy, ox = noise_off[t]
        # Add camera noise, round and saturate to uint8 in one pass.
        cv2.add(buf, sensor.noise[noise_idx[t], oy:oy + h, ox:ox + w], dst=video[t], dtype=cv2.CV_8U)
    return video
