"""Contact mechanics and press motion of the press simulator.

Gel and object are two nonlinear springs in series (same force ``F``):

.. math::

    \\delta_g = c_g F_r^{1-m} F^m, \\qquad \\delta_o = c_o F_r^{1-m} F^m, \\qquad
    \\delta = \\delta_g + \\delta_o,

with compliances ``c`` quoted as secants at ``F_r = 1`` N and ``m = 2/3``
(Hertz: ``F`` grows as ``delta^{3/2}``). The gel is a dome of radius ``R``; as
in Hertz contact, the contact radius follows the *total* approach,
``a = sqrt(R delta)``, while the gel itself is indented only by its share
``delta_g = delta c_g / (c_g + c_o)``.

The drive (robot impedance controller or human arm) is a third spring of
compliance ``c_d`` between the commanded position ``z(t)`` and the sensor,
so ``z = c_d F + delta`` in quasi-static equilibrium. ``z`` advances at the
approach speed (uneven for a hand), the stop is triggered when a first-order
lagged force estimate ``tau dF_hat/dt = F - F_hat`` reaches ``F_push``; the
drive then decelerates at ``a_dec`` (overshoot), holds, and retreats.
"""

from __future__ import annotations

import numpy as np
from scipy.signal import lfilter

from ._sim_presets import F_REF

__all__ = ["simulate_press", "force_from_position"]

_DT = 0.0005  # s, time step of the motion integration


def force_from_position(z, c_total, c_drive, m, f_ref=F_REF):
    """Force (N) for commanded penetration ``z`` (mm): solves ``c_d F + C F^m = z``.

    ``C = c_total f_ref^(1-m)``. Vectorised by inverting the monotone
    relation on a dense grid; ``z <= 0`` gives zero force.
    """
    z = np.asarray(z, dtype=float)
    zmax = max(float(np.max(z, initial=0.0)), 1e-9)
    coef = c_total * f_ref ** (1.0 - m)
    # Upper bound of F: the smaller of the two single-spring solutions.
    f_hi = (zmax / coef) ** (1.0 / m)
    if c_drive > 0:
        f_hi = min(f_hi, zmax / c_drive)
    grid = f_hi * np.linspace(0.0, 1.0, 4097) ** 2
    zgrid = c_drive * grid + coef * grid**m
    return np.interp(np.clip(z, 0.0, None), zgrid, grid)


def _smooth_speed_profile(rng, n, dt, unevenness):
    """Relative speed (mean 1) with smooth random fluctuations (a hand's uneven push)."""
    if unevenness <= 0:
        return np.ones(n)
    t = np.arange(n) * dt
    prof = np.ones(n)
    for _ in range(3):
        freq = rng.uniform(0.5, 3.0)  # Hz: tremor-free voluntary speed changes
        prof += unevenness / np.sqrt(3.0) * np.sqrt(2) * np.sin(2 * np.pi * freq * t + rng.uniform(0, 2 * np.pi))
    return np.clip(prof, 0.2, None)


def simulate_press(rng, *, c_gel, c_obj, dome_radius, m, c_drive, f_push, v_push, unevenness,
                   force_lag, deceleration, hold, retreat_ratio, fps, n_before, n_after,
                   timestamp_jitter, force_noise, lateral_gain_object, lateral_gain_gel):
    """Simulate one press; return per-frame mechanics and scalar summaries.

    Returns
    -------
    frames : dict of ndarray, each of shape (T,)
        ``time`` (s since the first frame, with jitter), ``force`` (recorded,
        noisy, N), ``force_true``, ``approach`` (total, mm), ``gel_indentation``,
        ``object_indentation``, ``contact_radius`` (mm), ``lateral_shift``
        (marker spread at the contact edge, mm), ``position`` (commanded
        penetration ``z``, mm), ``sensor_position`` (where the sensor is,
        ``z - c_drive F``: what a robot's encoders or a gripper's width
        measure, mm; negative before contact, the gap; ``approach`` once in
        contact).
    summary : dict of float
        ``force_peak`` (true peak force), ``t_contact``, ``t_trigger``,
        ``t_release`` (s since the first frame).
    """
    c_tot = c_gel + c_obj
    # --- loading: z(t) = integral of v(t) from the contact instant (t = 0).
    f_push_z = c_drive * f_push + c_tot * F_REF ** (1 - m) * f_push**m  # z at which F = F_push
    t_need = f_push_z / v_push
    horizon = 2.0 * t_need / 0.2 + 12 * force_lag + 0.5  # generous: speed factor >= 0.2
    n = int(np.ceil(horizon / _DT)) + 2
    speed = v_push * _smooth_speed_profile(rng, n, _DT, unevenness)
    z_load = np.concatenate([[0.0], np.cumsum(speed[:-1]) * _DT])
    f_load = force_from_position(z_load, c_tot, c_drive, m)
    alpha = _DT / (force_lag + _DT)
    f_est = lfilter([alpha], [1.0, alpha - 1.0], f_load)
    hit = np.flatnonzero(f_est >= f_push)
    if hit.size == 0:  # pragma: no cover - horizon is generous
        raise RuntimeError("simulated press never reached F_push; horizon too short")
    i_trig = int(hit[0])
    t_trig = i_trig * _DT
    z_trig = z_load[i_trig]
    v_trig = speed[i_trig]
    # --- deceleration, hold, retreat (piecewise analytic).
    t_stop = v_trig / deceleration
    z_max = z_trig + v_trig * t_stop - 0.5 * deceleration * t_stop**2
    v_ret = v_push * retreat_ratio
    t_ret0 = t_trig + t_stop + hold
    t_release = t_ret0 + z_max / v_ret  # z back to 0: contact ends (force 0)

    # --- frame times: contact instant lies between frames n_before-1 and n_before.
    dt_f = 1.0 / fps
    phase = rng.uniform(0.0, dt_f)
    t0 = -(n_before - 1) * dt_f - phase  # time of the first frame (contact at t = 0)
    n_contact = int(np.floor((t_release - (t0 + n_before * dt_f)) / dt_f)) + 1
    n_frames = n_before + max(n_contact, 0) + n_after
    t_frames = t0 + np.arange(n_frames) * dt_f
    if timestamp_jitter > 0:
        t_frames = t_frames + rng.normal(0.0, timestamp_jitter, n_frames)
        t_frames = np.maximum.accumulate(t_frames)

    z = np.empty(n_frames)
    for k, t in enumerate(t_frames):
        if t <= 0:
            z[k] = v_push * t  # in the air (negative: gap to the object)
        elif t <= t_trig:
            z[k] = np.interp(t, np.arange(n) * _DT, z_load)
        elif t <= t_trig + t_stop:
            tau = t - t_trig
            z[k] = z_trig + v_trig * tau - 0.5 * deceleration * tau**2
        elif t <= t_ret0:
            z[k] = z_max
        else:
            z[k] = z_max - v_ret * (t - t_ret0)
    force = force_from_position(z, c_tot, c_drive, m)
    sensor = z - c_drive * force  # where the sensor is: negative before contact (the gap)
    approach = np.clip(sensor, 0.0, None)
    share = c_gel / c_tot
    gel = share * approach
    obj = approach - gel
    radius = np.sqrt(dome_radius * approach)
    lateral = lateral_gain_object * obj + lateral_gain_gel * gel
    recorded = force + (rng.normal(0.0, force_noise, n_frames) if force_noise > 0 else 0.0)
    frames = dict(
        time=t_frames - t_frames[0],
        force=recorded,
        force_true=force,
        position=z,
        sensor_position=sensor,
        approach=approach,
        gel_indentation=gel,
        object_indentation=obj,
        contact_radius=radius,
        lateral_shift=lateral,
    )
    f_peak = float(force_from_position(np.array([z_max]), c_tot, c_drive, m)[0])
    summary = dict(
        force_peak=f_peak,
        t_contact=float(-t_frames[0]),
        t_trigger=float(t_trig - t_frames[0]),
        t_release=float(t_release - t_frames[0]),
    )
    return frames, summary
