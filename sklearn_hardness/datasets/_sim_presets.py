"""Presets and parameter validation of the press simulator.

A preset is a plain dict of physical parameters. :func:`resolve_params`
merges keyword overrides into a copy of a preset and checks every value
against :data:`PARAM_SPECS` (type and physically sensible range), so that a
typo or an impossible value fails early with a message naming the parameter.

The Shore 00 to Young's modulus conversion used by the ``shore9`` preset is
:func:`shore00_to_modulus`; :func:`modulus_to_compliance` turns a modulus into
the secant compliance (mm/N at 1 N) that the mechanics model uses.
"""

from __future__ import annotations

import numbers

import numpy as np

__all__ = [
    "PRESETS",
    "PARAM_SPECS",
    "EVERYDAY_SPECS",
    "preset_specs",
    "resolve_params",
    "shore00_to_modulus",
    "modulus_to_compliance",
]

#: Reference force (N) at which compliances are quoted: c = delta(F_REF) / F_REF.
F_REF = 1.0

# ASTM D2240 type 00 durometer: hemispherical indenter of radius 1.191 mm
# (3/32 in ball), 2.54 mm travel between readings 100 and 0, and a spring force
# rising linearly from 0.203 N at reading 0 to 1.111 N at reading 100.
_SHORE00_TIP_RADIUS_MM = 1.191
_SHORE00_TRAVEL_MM = 2.54
_SHORE00_F0_N = 0.203
_SHORE00_F100_N = 1.111


def shore00_to_modulus(shore, poisson=0.5):
    """Young's modulus (MPa) of an elastomer from its Shore 00 hardness.

    The durometer is modelled as in Gent's derivation for Shore A and in
    Mix & Giacomin's analysis of all ASTM D2240 scales: the spring force at
    reading ``S`` balances the Hertz force of the hemispherical indenter
    pushed ``d = 2.54 (1 - S/100)`` mm into an elastic half-space,

    .. math::

        F(S) = 0.203 + 0.00908\\,S \\;[\\mathrm{N}], \\qquad
        F = \\frac{4}{3} \\frac{E}{1 - \\nu^2} \\sqrt{R_i}\\, d^{3/2}
        \\;\\Rightarrow\\;
        E = \\frac{3 (1 - \\nu^2) F(S)}{4 \\sqrt{R_i}\\, d^{3/2}},

    with ``R_i = 1.191`` mm. For Shore 00 8 ... 95 this gives 0.04 ... 12 MPa,
    in line with published Shore 00 / modulus tables for silicone rubbers
    (Hertz overestimates at readings above ~90, where ``d`` is small).

    Parameters
    ----------
    shore : float or array-like
        Shore 00 hardness, in (0, 100).
    poisson : float, default=0.5
        Poisson's ratio (0.5: incompressible rubber).

    Returns
    -------
    modulus : ndarray
        Young's modulus in MPa.

    References
    ----------
    A. N. Gent, "On the relation between indentation hardness and Young's
    modulus", Trans. Inst. Rubber Ind. 34 (1958) 46-57.
    A. W. Mix and A. J. Giacomin, "Standardized polymer durometry",
    J. Test. Eval. 39(4) (2011) 696-705.
    ASTM D2240, "Standard test method for rubber property - durometer hardness".
    """
    s = np.asarray(shore, dtype=float)
    if np.any(~np.isfinite(s)) or np.any((s <= 0) | (s >= 100)):
        raise ValueError(f"Shore 00 hardness must lie in (0, 100), got {shore!r}.")
    force = _SHORE00_F0_N + (_SHORE00_F100_N - _SHORE00_F0_N) * s / 100.0
    depth = _SHORE00_TRAVEL_MM * (1.0 - s / 100.0)
    return 3.0 * (1.0 - poisson**2) * force / (4.0 * np.sqrt(_SHORE00_TIP_RADIUS_MM) * depth**1.5)


def modulus_to_compliance(modulus, dome_radius, poisson=0.5, f_ref=F_REF):
    """Secant compliance (mm/N at ``f_ref``) of a flat elastic block pressed by a dome.

    Hertz contact of a rigid sphere of radius ``R`` (the domed gel) on a
    half-space: ``delta = (9 F^2 / (16 R E*^2))^(1/3)`` with
    ``E* = E / (1 - nu^2)``; the compliance is ``delta(f_ref) / f_ref``.

    Parameters
    ----------
    modulus : float or array-like
        Young's modulus in MPa (N/mm^2).
    dome_radius : float
        Radius of curvature of the gel dome in mm.
    poisson : float, default=0.5
    f_ref : float, default=1.0
        Force (N) at which the secant compliance is quoted.

    Returns
    -------
    compliance : ndarray
        In mm/N.
    """
    e_star = np.asarray(modulus, dtype=float) / (1.0 - poisson**2)
    delta = (9.0 * f_ref**2 / (16.0 * dome_radius * e_star**2)) ** (1.0 / 3.0)
    return delta / f_ref


# --------------------------------------------------------------------------
# Parameter specifications: name -> (kind, low, high, description).
# kind: "float", "int", "bool", "range" (pair lo <= hi inside [low, high]),
# "int_range", "array" (1-d array of floats inside [low, high]).
PARAM_SPECS = {
    # objects
    "hardness": ("array", 1e-3, 1e3, "hardness of each reference object, in the preset's unit"),
    "object_spread": ("float", 0.0, 0.5, "relative s.d. of each cast's true compliance around its nominal value"),
    "press_spread": ("float", 0.0, 0.5, "relative s.d. of the object compliance from press to press"),
    # sensor (gel)
    "gel_compliance": ("float", 0.01, 5.0, "secant compliance of the gel pad at 1 N, mm/N"),
    "sensor_spread": ("float", 0.0, 0.5, "relative s.d. of gel compliance and dome radius between sensors"),
    "n_sensors": ("int", 1, 64, "number of sensors the presses are spread over"),
    "dome_radius": ("float", 1.0, 1000.0, "radius of curvature of the gel dome, mm"),
    "hertz_exponent": ("float", 0.3, 1.0, "m in delta = c F_ref^(1-m) F^m (2/3: Hertz, 1: linear spring)"),
    "field_of_view": ("float", 2.0, 200.0, "width of the imaged gel area, mm"),
    # press motion
    "force_range": ("range", 0.01, 100.0, "target force F_push ~ U[lo, hi], N"),
    "speed_range": ("range", 0.1, 1000.0, "approach speed v_push ~ U[lo, hi], mm/s"),
    "speed_unevenness": ("float", 0.0, 0.9, "relative amplitude of smooth speed fluctuations (0: robot)"),
    "drive_compliance": ("float", 0.0, 50.0, "compliance of the robot's impedance controller (or the arm), mm/N"),
    "force_lag_range": ("range", 0.0, 2.0, "time constant of the lagged force estimate ~ U[lo, hi], s"),
    "deceleration": ("float", 1.0, 1e6, "deceleration after the stop is triggered, mm/s^2"),
    "hold_range": ("range", 0.0, 5.0, "dwell at the deepest point ~ U[lo, hi], s"),
    "retreat_speed_ratio": ("range", 0.05, 20.0, "retreat speed / approach speed ~ U[lo, hi]"),
    "fps": ("float", 1.0, 1000.0, "camera frame rate, frames/s"),
    "frames_before_range": ("int_range", 1, 1000, "frames recorded before contact ~ U{lo..hi}"),
    "frames_after_range": ("int_range", 1, 1000, "frames recorded after release ~ U{lo..hi}"),
    "timestamp_jitter": ("float", 0.0, 0.01, "s.d. of camera timestamp jitter, s"),
    "force_noise": ("float", 0.0, 5.0, "s.d. of the recorded force, N"),
    "contact_offset": ("float", 0.0, 10.0, "s.d. of the contact point's offset from the image centre, mm"),
    # optics
    "light_elevation": ("float", 5.0, 85.0, "angle of the three lights from the gel normal, degrees"),
    "shading_ambient": ("float", 0.0, 10.0, "ambient term of the shading ratio"),
    "vignetting": ("float", 0.0, 0.9, "relative darkening in the image corners"),
    "marker_spacing": ("float", 0.2, 20.0, "pitch of the marker grid, mm"),
    "marker_radius": ("float", 0.02, 5.0, "marker radius, mm"),
    "marker_darkness": ("float", 0.0, 1.0, "fraction of light a marker absorbs"),
    "lateral_gain_object": ("float", 0.0, 2.0, "marker spread at the contact edge per mm of object indentation"),
    "lateral_gain_gel": ("float", 0.0, 2.0, "marker spread at the contact edge per mm of gel indentation"),
    "noise_std": ("float", 0.0, 50.0, "s.d. of camera noise, intensity levels"),
    "drift_amplitude": ("float", 0.0, 0.2, "relative amplitude of the slow illumination drift"),
}

#: Extra parameters of the ``everyday`` preset (objects of many shapes in three hardness ranks).
EVERYDAY_SPECS = {
    "n_objects": ("int", 3, 10000, "number of objects, split over the ranks by class_ratio"),
    "class_ratio": ("array", 1e-3, 1e3, "relative number of soft, moderate and hard objects"),
    "soft_compliance_range": ("range", 1e-3, 100.0, "object compliance of soft objects ~ logU[lo, hi], mm/N"),
    "moderate_compliance_range": ("range", 1e-3, 100.0, "object compliance of moderate objects ~ logU[lo, hi], mm/N"),
    "hard_compliance_range": ("range", 1e-4, 100.0, "object compliance of hard objects ~ logU[lo, hi], mm/N"),
    "texture_amplitude": ("array", 0.0, 2.0, "relative texture depth of soft, moderate and hard objects"),
    "kinds_by_rank": ("bool", None, None, "True: each rank has its own kinds of object (foams soft, pen tips hard, "
                      "...); "
                      "False: every rank draws from all kinds, so shape and texture say nothing about hardness"),
    "conformity": ("float", 0.0, 100.0, "a compliant object's imprint is smoothed over conformity x its share of the "
                   "deformation x the contact size (0: every object pressed in with its rigid shape)"),
    "gel_spread": ("float", 0.0, 10.0, "s.d. of the gel's own spreading of every imprint, mm: an elastomer layer "
                   "smooths "
                   "features narrower than its thickness (0: the surface follows the object's shape)"),
    "object_rounding": ("float", 0.0, 10.0, "a compliant object rounds its edges, ridges and texture against the gel: "
                        "its imprint is smoothed over object_rounding x its own indentation, mm (0: rigid shapes)"),
    "hand_fraction": ("float", 0.0, 1.0, "fraction of presses made by hand (uneven speed), the rest by a robot"),
    "hand_speed_range": ("range", 0.1, 1000.0, "approach speed of hand presses ~ U[lo, hi], mm/s"),
    "video_length": ("int", 8, 10000, "frames of a full recording"),
    "short_length": ("int", 8, 10000, "frames of a short recording"),
    "short_fraction": ("float", 0.0, 1.0, "fraction of short recordings (contact at frame 8-15)"),
    "truncated_fraction": ("float", 0.0, 1.0, "fraction of truncated recordings of 3-7 frames"),
    "gel_foundation_modulus": ("float", 1e-3, 1e4, "pressure per mm of gel depth (thin-layer gel), N/mm^3"),
    "ambient_leak": ("float", 0.0, 50.0, "s.d. of the slow pre-contact change (light through the gel), grey levels"),
    "ambient_rise_frames": ("range", 0.1, 1000.0, "time constant of the pre-contact change ~ U[lo, hi], frames"),
    "light_spread": ("float", 10.0, 120.0, "azimuth between neighbouring lights, degrees (120: evenly around the gel)"),
}

_COMMON = {
    "object_spread": 0.02,
    "press_spread": 0.03,
    "sensor_spread": 0.05,
    "n_sensors": 1,
    "dome_radius": 15.0,
    "hertz_exponent": 2.0 / 3.0,
    "timestamp_jitter": 0.0005,
    "contact_offset": 0.4,
    "light_elevation": 65.0,
    "shading_ambient": 0.3,
    "vignetting": 0.3,
    "marker_radius": 0.32,
    "marker_darkness": 0.75,
    "lateral_gain_object": 0.15,
    "lateral_gain_gel": 0.05,
    "noise_std": 1.5,
    "drift_amplitude": 0.003,
}

#: Presets: the paper's two datasets (Sec. III-A).
PRESETS = {
    "silicone5": dict(
        _COMMON,
        description=(
            "Five flat silicone objects (Alpa Sil EH with silicone oil) of compliance 1.13, 1.02, "
            "0.79, 0.68 and 0.44 mm/N, pressed at their centre by a GelSight Mini on a Franka "
            "Panda arm: approach at v_push ~ U[20, 50] mm/s, retreat when the (lagged) force "
            "estimate reaches F_push ~ U[1, 5] N; 25 fps."
        ),
        hardness=np.array([1.13, 1.02, 0.79, 0.68, 0.44]),
        hardness_unit="mm/N",
        n_per_class=91,
        gel_compliance=0.30,
        field_of_view=18.6,  # GelSight Mini: 18.6 x 14.3 mm
        force_range=(1.0, 5.0),
        speed_range=(20.0, 50.0),
        speed_unevenness=0.0,
        drive_compliance=1.0,  # Cartesian impedance of ~1000 N/m
        force_lag_range=(0.01, 0.03),
        deceleration=2500.0,
        hold_range=(0.0, 0.08),
        retreat_speed_ratio=(1.0, 1.0),
        fps=25.0,
        frames_before_range=(8, 16),
        frames_after_range=(4, 10),
        force_noise=0.05,
        marker_spacing=1.6,
    ),
    "shore9": dict(
        _COMMON,
        description=(
            "Yuan et al. (2017) flat silicone samples of Shore 00 hardness 8, 17, 27, 46, 62, 73, "
            "81, 87 and 95 pressed onto a GelSight by hand: slow, uneven speed, a human's slow "
            "reaction when the felt force is reached, a short hold; 30 fps; several sensors."
        ),
        hardness=np.array([8.0, 17.0, 27.0, 46.0, 62.0, 73.0, 81.0, 87.0, 95.0]),
        hardness_unit="Shore 00",
        n_per_class=40,
        n_sensors=2,
        gel_compliance=0.30,
        field_of_view=18.6,
        force_range=(1.0, 6.0),
        speed_range=(8.0, 20.0),
        speed_unevenness=0.35,
        drive_compliance=1.0,
        force_lag_range=(0.05, 0.12),
        deceleration=400.0,
        hold_range=(0.1, 0.4),
        retreat_speed_ratio=(0.7, 1.5),
        fps=30.0,
        frames_before_range=(6, 14),
        frames_after_range=(4, 10),
        force_noise=0.1,
        marker_spacing=1.4,
    ),
}

PRESETS["everyday"] = dict(
    _COMMON,
    description=(
        "Everyday objects pressed onto a marker-less GelSight Mini (240x320, 25 fps), in three "
        "hardness ranks with imbalanced counts (soft : moderate : hard ~ 1 : 3 : 3). Every rank draws "
        "from the same kinds of object (domes of many radii, edges, ridges, small sharp contacts, "
        "broad textured contacts: foams, erasers, fruit, marbles, ruler edges, bottle caps, pen tips, "
        "...), so an imprint's shape says nothing about its hardness; a compliant object's imprint "
        "rounds as it conforms, and the gel smooths every imprint over 0.4 mm. A few presses per "
        "object by hand or robot at varied speed and force; mostly 126-frame videos with contact "
        "from frame 24-36 held ~2 s, some of 50 frames, a few truncated to 3-7 frames. Calibrated "
        "against real GelSight Mini recordings: per-rank contact strength, its spread and the "
        "ranking of the pipelines (see docs/simulator.md)."
    ),
    hardness=np.array([3.0, 2.0, 1.0]),
    hardness_unit="rank",
    n_per_class=4,
    dome_radius=60.0,
    gel_compliance=0.08,
    field_of_view=18.6,
    force_range=(1.0, 6.0),
    speed_range=(5.0, 20.0),
    hand_speed_range=(4.0, 16.0),
    speed_unevenness=0.35,
    drive_compliance=0.3,
    force_lag_range=(0.03, 0.12),
    deceleration=300.0,
    hold_range=(1.6, 2.4),
    retreat_speed_ratio=(0.8, 2.0),
    fps=25.0,
    frames_before_range=(24, 36),
    force_noise=0.1,
    contact_offset=1.5,
    marker_spacing=1.6,
    noise_std=0.5,
    n_objects=42,
    class_ratio=np.array([1.0, 3.0, 3.0]),
    soft_compliance_range=(0.7, 2.8),
    moderate_compliance_range=(0.2, 1.0),
    hard_compliance_range=(0.002, 0.03),
    texture_amplitude=np.array([0.5, 0.15, 0.05]),
    hand_fraction=0.6,
    video_length=126,
    short_length=50,
    short_fraction=0.15,
    truncated_fraction=0.04,
    gel_foundation_modulus=0.4,
    ambient_leak=0.5,
    ambient_rise_frames=(5.0, 9.0),
    light_spread=60.0,
    light_elevation=80.0,
    kinds_by_rank=False,
    conformity=0.1,
    gel_spread=0.4,
    object_rounding=0.0,
)

_NON_PHYSICAL = ("description", "hardness_unit", "n_per_class")


def preset_specs(preset):
    """The parameter specifications that apply to ``preset``."""
    if preset == "everyday":
        unused = ("hardness", "object_spread", "frames_after_range", "drift_amplitude")
        specs = {k: v for k, v in PARAM_SPECS.items() if k not in unused}
        specs.update(EVERYDAY_SPECS)
        return specs
    return PARAM_SPECS


def _check_scalar(name, value, kind, low, high):
    if kind == "bool":
        if not isinstance(value, (bool, np.bool_)):
            raise TypeError(f"{name} must be a bool, got {value!r}.")
        return bool(value)
    integral = kind in ("int", "int_range")
    if isinstance(value, (bool, np.bool_)) or not isinstance(value, numbers.Real):
        raise TypeError(f"{name} must be a {'an integer' if integral else 'a number'}, got {value!r}.")
    if integral and not float(value).is_integer():
        raise TypeError(f"{name} must be an integer, got {value!r}.")
    value = int(value) if integral else float(value)
    if not np.isfinite(value) or not (low <= value <= high):
        raise ValueError(f"{name}={value!r} is out of range: it must lie in [{low}, {high}].")
    return value


def _check_param(name, value, specs=PARAM_SPECS):
    kind, low, high, desc = specs[name]
    if kind in ("float", "int", "bool"):
        return _check_scalar(name, value, kind, low, high)
    if kind in ("range", "int_range"):
        if isinstance(value, numbers.Real):
            value = (value, value)
        try:
            lo, hi = value
        except (TypeError, ValueError):
            raise TypeError(f"{name} must be a pair (low, high) ({desc}), got {value!r}.") from None
        sub = "int" if kind == "int_range" else "float"
        lo = _check_scalar(f"{name}[0]", lo, sub, low, high)
        hi = _check_scalar(f"{name}[1]", hi, sub, low, high)
        if lo > hi:
            raise ValueError(f"{name}=({lo}, {hi}): the low end exceeds the high end.")
        return (lo, hi)
    # array
    arr = np.asarray(value, dtype=float).ravel() if not isinstance(value, str) else None
    if arr is None or arr.size == 0:
        raise TypeError(f"{name} must be a non-empty sequence of numbers, got {value!r}.")
    if not np.all(np.isfinite(arr)) or np.any((arr < low) | (arr > high)):
        raise ValueError(f"{name}={value!r} is out of range: values must lie in [{low}, {high}].")
    return arr


def resolve_params(preset, overrides):
    """Merge ``overrides`` into a copy of ``preset`` and validate everything.

    Parameters
    ----------
    preset : str
        Name of a preset in :data:`PRESETS`.
    overrides : dict
        Physical parameters to replace (keys of :data:`PARAM_SPECS`).

    Returns
    -------
    params : dict
        The validated parameters.

    Raises
    ------
    ValueError
        Unknown preset, or a value out of range.
    TypeError
        Unknown parameter name, or a value of the wrong type.
    """
    if not isinstance(preset, str) or preset not in PRESETS:
        raise ValueError(f"Unknown preset {preset!r}; choose one of {sorted(PRESETS)}.")
    specs = preset_specs(preset)
    unknown = sorted(set(overrides) - set(specs))
    if unknown:
        raise TypeError(
            f"Unknown simulator parameter(s) {unknown} for preset {preset!r}; valid overrides are: "
            f"{', '.join(sorted(specs))}."
        )
    params = dict(PRESETS[preset])
    params.update(overrides)
    out = {k: params[k] for k in _NON_PHYSICAL}
    for name in specs:
        out[name] = _check_param(name, params[name], specs)
    if preset == "everyday":
        out["hardness"] = params["hardness"].copy()
        for name in ("class_ratio", "texture_amplitude"):
            if out[name].shape != (3,):
                raise ValueError(f"{name} must hold 3 values (soft, moderate, hard), got {out[name].tolist()}.")
        if out["short_fraction"] + out["truncated_fraction"] > 1:
            raise ValueError("short_fraction + truncated_fraction must not exceed 1.")
        return out
    if preset == "shore9" and np.any(out["hardness"] >= 100):
        raise ValueError(f"Shore 00 hardness must lie in (0, 100), got {out['hardness']}.")
    # Classes are ordered by increasing hardness value (as a manifest's numeric labels sort).
    out["hardness"] = np.sort(out["hardness"])
    if len(np.unique(out["hardness"])) != len(out["hardness"]):
        raise ValueError(f"hardness values must be distinct (one per object), got {out['hardness']}.")
    if out["marker_radius"] * 2 >= out["marker_spacing"]:
        raise ValueError(
            f"marker_radius={out['marker_radius']} is too large for marker_spacing="
            f"{out['marker_spacing']}: markers would overlap."
        )
    return out
