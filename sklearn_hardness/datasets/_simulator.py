"""Physics-based simulator of GelSight press videos: :func:`make_presses`.

Real recordings of the paper cannot be downloaded here, so this simulator is
the library's built-in dataset. It models, per press (see ``docs/simulator.md``
for the full derivation and sources):

Mechanics (``_sim_mechanics``)
    Gel (compliance ``c_g``, a few tenths of a mm/N, varying between sensors)
    and object (``c_o``) are nonlinear springs in series carrying the same
    force ``F``: ``delta_i = c_i F_r^(1-m) F^m`` with the Hertz exponent
    ``m = 2/3`` and ``F_r = 1`` N. The gel is a dome of radius ``R``: the
    contact radius follows the *total* approach, ``a = sqrt(R (delta_g + delta_o))``,
    while the gel is indented only by its share ``delta_g = c_g / (c_g + c_o) delta``.
    Gel depth and image intensity therefore grow with force for every object;
    the hardness is in the relation ``a^2 / delta_g = R (c_g + c_o) / c_g`` and
    in how contact size and depth evolve together during the press.

Motion
    A drive of compliance ``c_d`` (the robot's impedance controller, or a
    hand) advances at ``v_push`` (uneven for hands), stops when a first-order
    lagged force estimate reaches ``F_push`` (so the true force overshoots),
    decelerates, holds briefly and retreats. Frames before contact and after
    release are recorded, with per-frame timestamps and (noisy) force.

Optics (``_sim_optics``)
    A GelSight-like background (colour gradient from three coloured side
    lights, vignetting, faint coating pattern); the gel surface follows the
    Hertz profile and is shaded by its normals under the three lights; dark
    markers move with the gel's lateral displacement; camera noise, slow
    illumination drift, small offsets of the contact point.

Presets (``_sim_presets``)
    ``silicone5``: the paper's robot dataset; ``shore9``: Yuan et al.'s flat
    Shore 00 samples pressed by hand.

Videos are rendered lazily on access from stored parameters and per-press
seeds, so the whole ``silicone5`` set costs little memory, and the same seed
gives identical frames whatever the access order.
"""

from __future__ import annotations

import numbers

import numpy as np
from sklearn.utils import Bunch, check_random_state

from ._sim_everyday import EVERYDAY_RANKS, check_codec, sample_objects, sample_press
from ._sim_mechanics import simulate_press
from ._sim_presets import (
    EVERYDAY_SPECS,
    PARAM_SPECS,
    PRESETS,
    modulus_to_compliance,
    resolve_params,
    shore00_to_modulus,
)
from ._sim_videos import SimulatedPressVideos, _CodecSimulation, _EverydaySimulation, _Simulation

__all__ = ["make_presses", "SimulatedPressVideos", "object_compliance"]


def object_compliance(preset, hardness, dome_radius):
    """Nominal compliance (mm/N at 1 N) of each object of a preset.

    ``silicone5`` quotes compliance directly; ``shore9`` converts Shore 00 to
    Young's modulus (:func:`shore00_to_modulus`) and the modulus to the
    compliance of a flat block under the gel dome (:func:`modulus_to_compliance`).
    """
    hardness = np.asarray(hardness, dtype=float)
    if PRESETS[preset]["hardness_unit"] == "mm/N":
        return hardness.copy()
    return modulus_to_compliance(shore00_to_modulus(hardness), dome_radius)


def _check_image_size(image_size):
    try:
        h, w = image_size
    except (TypeError, ValueError):
        raise TypeError(f"image_size must be a pair (height, width), got {image_size!r}.") from None
    out = []
    for name, v in (("height", h), ("width", w)):
        if isinstance(v, (bool, np.bool_)) or not isinstance(v, (numbers.Integral, np.integer)):
            raise TypeError(f"image_size {name} must be an integer, got {v!r}.")
        if not 16 <= int(v) <= 4096:
            raise ValueError(f"image_size {name}={v} is out of range: it must lie in [16, 4096].")
        out.append(int(v))
    return tuple(out)


def _seed_sequence(random_state):
    if isinstance(random_state, np.random.Generator):
        entropy = int(random_state.integers(0, 2**63 - 1))
    else:
        entropy = int(check_random_state(random_state).randint(0, 2**31 - 1))
    return np.random.SeedSequence(entropy)


def _seed_int(ss):
    return int(ss.generate_state(2, dtype=np.uint64)[0] >> np.uint64(1))


def _descr(preset, params, n, image_size):
    lines = [
        f"Simulated GelSight press videos, preset '{preset}'",
        "=" * 60,
        "",
        params["description"],
        "",
        f"Presses: {n} ({params.get('n_objects', len(params['hardness']))} objects); "
        f"frames {image_size[0]}x{image_size[1]} RGB "
        f"uint8 at {params['fps']:g} fps.",
        f"Hardness ({params['hardness_unit']}): {', '.join(f'{h:g}' for h in params['hardness'])}.",
        "",
        "Physics: gel and object are Hertz-like springs in series (delta = c F^(2/3)); the contact "
        "radius follows the total approach (a = sqrt(R delta)), the gel is indented by its share only; "
        "the drive stops on a lagged force estimate (overshoot); shading from the gel's normals under "
        "three coloured lights; markers follow the lateral displacement; noise, drift, offsets. "
        "See docs/simulator.md.",
        "",
        "Parameters:",
    ]
    for k in sorted(params):
        if k not in ("description",):
            v = params[k]
            v = np.round(v, 4).tolist() if isinstance(v, np.ndarray) else v
            lines.append(f"  {k} = {v}")
    return "\n".join(lines)


def make_presses(preset="silicone5", n_per_class=None, *, markers=None, image_size=(240, 320),
                 shuffle=True, return_mechanics=False, codec="auto", random_state=None, **physics):
    """Simulate GelSight press videos of objects of known hardness.

    A physics-based stand-in for the paper's datasets (Sec. III-A): gel and
    object as Hertz-like springs in series under a domed gel, a drive that
    stops on a lagged force estimate, and GelSight-like optics (three-light
    shading, markers, noise, drift). See the module docstring and
    ``docs/simulator.md`` for the equations.

    Parameters
    ----------
    preset : {"silicone5", "shore9", "everyday"}, default="silicone5"
        ``"silicone5"``: five silicone objects of compliance 1.13, 1.02,
        0.79, 0.68 and 0.44 mm/N pressed by a robot with a GelSight Mini at
        25 fps, ``F_push ~ U[1, 5]`` N, ``v_push ~ U[20, 50]`` mm/s, 91 presses
        per object. ``"shore9"``: Yuan et al.'s flat samples of Shore 00 8,
        17, 27, 46, 62, 73, 81, 87, 95 pressed by hand (slow, uneven), 30 fps,
        40 presses per object. ``"everyday"``: 42 household objects of many
        shapes and textures (domes, edges, ridges, pen tips, foams, fabrics)
        in three hardness ranks ``hard``, ``moderate``, ``soft`` (objects
        ~ 3 : 3 : 1), 4 presses per object by hand or robot, marker-less
        GelSight Mini videos of mostly 126 frames with contact from frame
        24-36, passed through the ``mp4v`` codec; calibrated against real
        recordings (``docs/simulator.md``). Classes are the ranks, and
        ``object_id`` says which object each press is of: evaluate it with
        folds grouped by object.
    n_per_class : int or None, default=None
        Presses per object; ``None`` uses the preset's number.
    markers : bool or None, default=None
        Whether the gel carries dark markers; ``None``: the preset's default
        (markers for ``silicone5`` and ``shore9``, none for ``everyday``).
    image_size : (int, int), default=(240, 320)
        Frame height and width in pixels (GelSight Mini streams 240x320).
        The field of view stays the same; smaller images are coarser.
    shuffle : bool, default=True
        Shuffle the presses; otherwise they are grouped by object.
    return_mechanics : bool, default=False
        Also return ``mechanics``: per press, a dict of per-frame arrays
        ``time``, ``force_true``, ``position`` (the drive's commanded
        position), ``sensor_position`` (the sensor's: the dataset's
        ``position``), ``approach``, ``gel_indentation``,
        ``object_indentation``, ``contact_radius`` (all in s, N, mm) and
        ``lateral_shift`` (marker spread at the contact edge, mm).
    codec : {"auto", "mp4v", "avc1", "mjpg"} or None, default="auto"
        Pass every video through this real lossy codec (OpenCV writes a
        temporary file and reads it back), so compression noise is real.
        ``"avc1"`` (H.264) only where the local OpenCV build can write it
        (otherwise a ``ValueError`` says so). ``"auto"``: ``"mp4v"`` for
        ``everyday``, None (uncompressed) for the other presets.
    random_state : int, RandomState instance, Generator or None, default=None
        Seed of everything random. The same seed gives identical videos,
        forces and parameters, whatever order the videos are read in.
    **physics
        Overrides of the preset's physical parameters, e.g.
        ``gel_compliance=0.4``, ``force_range=(2, 4)``, ``noise_std=0``,
        ``hardness=[1.0, 0.5]`` (objects in the preset's unit). Every name,
        its meaning and its allowed range:

{physics}

    Returns
    -------
    data : :class:`~sklearn.utils.Bunch`
        videos : sequence of length n_samples
            Lazy sequence (rendered when indexed) of ``(T_i, H, W, 3)`` ``uint8`` videos (``T_i``
            differs between presses).
        target : ndarray of shape (n_samples,), int
            Object (class) index. Classes are ordered by increasing
            hardness *value*: for ``silicone5`` (compliance) class 0 is the
            hardest object (0.44 mm/N), for ``shore9`` the softest (Shore 00 8).
        target_names : ndarray of str
            The hardness values as strings (``"0.44"``, ``"8"``), so that a
            manifest written by ``sklearn-hardness simulate`` loads back to
            the same class indices.
        hardness : ndarray of shape (n_classes,)
            Nominal hardness of each class, in ``hardness_unit``.
        hardness_unit : str
            ``"mm/N"`` (compliance: larger is softer) or ``"Shore 00"``.
        force, timestamps : list of ndarray of shape (T_i,)
            Recorded force (N, with sensor noise) and frame times (s).
        position : list of ndarray of shape (T_i,)
            Where the sensor is along the press axis (mm, growing as it
            moves into the object, 0 at first contact, negative before: the
            gap): what a robot's joint encoders record beside the force.
            It is the drive's commanded position less the drive's give
            (``drive_compliance`` times the force). With ``force``, the input
            of :class:`~sklearn_hardness.features.LoadingCompliance`
            (``np.column_stack([force, position])`` per press). For the
            presses a preset makes by hand it is the hand's, which only
            motion capture would record.
        object_id : ndarray of str
            Which physical object was pressed (``everyday``: e.g.
            ``"everyday-07-eraser"``).
        objects : list of dict, only for ``everyday``
            Each object's rank, kind, shape, radius, compliance and texture.
        press_params : dict of ndarray of shape (n_samples,)
            Sampled press parameters: ``F_push``, ``v_push``, ``force_lag``,
            ``hold``, ``retreat_speed``, ``compliance_object`` (this press),
            ``compliance_gel``, ``dome_radius``, ``sensor``, ``offset_x``,
            ``offset_y`` (mm), ``n_before``, ``n_after``, ``force_peak``
            (true peak force), ``t_contact``, ``t_trigger``, ``t_release`` (s).
        fps : float
            Frame rate of the simulated camera.
        params : dict
            All physical parameters used.
        mechanics : list of dict, only if ``return_mechanics=True``
            Per-frame mechanical quantities of each press (force, approach,
            gel indentation, contact radius).
        DESCR : str
            A description of the dataset.

    Raises
    ------
    ValueError
        Unknown preset, out-of-range parameter or ``image_size``.
    TypeError
        Unknown parameter name or wrongly typed value.

    Examples
    --------
    >>> from sklearn_hardness.datasets import make_presses
    >>> data = make_presses("silicone5", n_per_class=2, image_size=(48, 64), random_state=0)
    >>> len(data.videos), data.target_names.tolist()[:2], data.hardness_unit
    (10, ['0.44', '0.68'], 'mm/N')
    >>> video = data.videos[0]
    >>> video.shape[1:], video.dtype, len(data.force[0]) == len(video)
    ((48, 64, 3), dtype('uint8'), True)
    """
    params = resolve_params(preset, physics)
    image_size = _check_image_size(image_size)
    if markers is None:
        markers = preset != "everyday"
    if not isinstance(markers, (bool, np.bool_)):
        raise TypeError(f"markers must be a bool or None, got {markers!r}.")
    if isinstance(codec, str) and codec == "auto":
        codec = "mp4v" if preset == "everyday" else None
    codec = check_codec(codec)
    if n_per_class is None:
        n_per_class = params["n_per_class"]
    if isinstance(n_per_class, (bool, np.bool_)) or not isinstance(n_per_class, (numbers.Integral, np.integer)):
        raise TypeError(f"n_per_class must be a positive integer or None, got {n_per_class!r}.")
    if not 1 <= n_per_class <= 100_000:
        raise ValueError(f"n_per_class={n_per_class} is out of range: it must lie in [1, 100000].")
    n_per_class = int(n_per_class)

    ss = _seed_sequence(random_state)
    if preset == "everyday":
        return _make_everyday(params, n_per_class, bool(markers), image_size, shuffle,
                              return_mechanics, codec, ss)
    return _make_flat(preset, params, n_per_class, bool(markers), image_size, shuffle, return_mechanics,
                      codec, ss)



def _physics_doc():
    """The ``**physics`` keys of :func:`make_presses`, one entry each, from the presets' specifications."""

    def entry(name, spec):
        kind, low, high, meaning = spec
        allowed = "bool" if kind == "bool" else f"{kind.replace('_', ' ')}, {low:g} to {high:g}"
        return f"        ``{name}``\n            {meaning} ({allowed})."

    everyday = [entry(name, spec) for name, spec in EVERYDAY_SPECS.items()]
    return "\n".join([entry(name, spec) for name, spec in PARAM_SPECS.items()]
                     + ["", "        ``everyday`` preset only:", ""] + everyday)


if make_presses.__doc__:  # None under python -OO
    make_presses.__doc__ = make_presses.__doc__.replace("{physics}", _physics_doc())

def _make_flat(preset, params, n_per_class, markers, image_size, shuffle, return_mechanics, codec, ss):
    """``make_presses`` for the flat presets (one object per class): sensors, casts, presses, renderer."""
    hardness = params["hardness"]
    n_classes = len(hardness)
    n = n_classes * n_per_class
    ss_sensor, ss_object, ss_press, ss_order = ss.spawn(4)

    # Sensors: gel compliance and dome radius vary a little between sensors.
    n_sensors = params["n_sensors"]
    sensor_rng = np.random.default_rng(ss_sensor)
    spread = params["sensor_spread"]
    gel_c = params["gel_compliance"] * np.exp(spread * sensor_rng.standard_normal(n_sensors))
    dome_r = params["dome_radius"] * np.exp(spread * sensor_rng.standard_normal(n_sensors))
    sensor_seeds = [_seed_int(s) for s in ss_sensor.spawn(n_sensors)]

    # Objects: each cast's true compliance differs a little from its nominal value.
    nominal = object_compliance(preset, hardness, params["dome_radius"])
    obj_rng = np.random.default_rng(ss_object)
    cast = nominal * np.exp(params["object_spread"] * obj_rng.standard_normal(n_classes))

    target = np.repeat(np.arange(n_classes), n_per_class)
    if shuffle:
        target = target[np.random.default_rng(ss_order).permutation(n)]

    keys = ["F_push", "v_push", "force_lag", "hold", "retreat_speed", "compliance_object",
            "compliance_gel", "dome_radius", "sensor", "offset_x", "offset_y", "n_before",
            "n_after", "force_peak", "t_contact", "t_trigger", "t_release"]
    pp = {k: np.empty(n) for k in keys}
    mechanics, centers, render_seeds = [], [], []
    for i, (cls, press_ss) in enumerate(zip(target, ss_press.spawn(n))):
        mech_ss, render_ss = press_ss.spawn(2)
        frames, offset, row = _sample_press(np.random.default_rng(mech_ss), params, cast[cls], gel_c,
                                            dome_r)
        mechanics.append(frames)
        centers.append(offset)
        render_seeds.append(_seed_int(render_ss))
        for k in keys:
            pp[k][i] = row[k]
    for k in ("sensor", "n_before", "n_after"):
        pp[k] = pp[k].astype(int)

    sim = _Simulation(params, image_size, bool(markers), sensor_seeds, pp["sensor"], mechanics,
                      centers, render_seeds)
    if codec is not None:
        sim = _CodecSimulation(sim, codec)
    unit = params["hardness_unit"]
    names = np.array([f"{h:g}" for h in hardness])
    data = Bunch(
        videos=SimulatedPressVideos(sim.render, list(range(n))),
        target=target,
        target_names=names,
        hardness=hardness.copy(),
        hardness_unit=unit,
        force=[m["force"].copy() for m in mechanics],
        timestamps=[m["time"].copy() for m in mechanics],
        position=[m["sensor_position"].copy() for m in mechanics],
        object_id=np.array([f"{preset}-object{c}" for c in target]),
        press_params=pp,
        fps=params["fps"],
        params=dict(params),
        DESCR=_descr(preset, params, n, image_size),
    )
    if return_mechanics:
        data.mechanics = [{k: v.copy() for k, v in m.items() if k != "force"} for m in mechanics]
    return data


def _sample_press(rng, params, cast_compliance, gel_c, dome_r):
    """One robot or hand press of an object cast: its mechanics, contact offset and parameters."""
    n_sensors = len(gel_c)
    s = int(rng.integers(n_sensors))
    c_obj = cast_compliance * np.exp(params["press_spread"] * rng.standard_normal())
    f_push = rng.uniform(*params["force_range"])
    v_push = rng.uniform(*params["speed_range"])
    lag = rng.uniform(*params["force_lag_range"])
    hold = rng.uniform(*params["hold_range"])
    ret = rng.uniform(*params["retreat_speed_ratio"])
    n_before = int(rng.integers(params["frames_before_range"][0], params["frames_before_range"][1] + 1))
    n_after = int(rng.integers(params["frames_after_range"][0], params["frames_after_range"][1] + 1))
    offset = rng.normal(0.0, params["contact_offset"], 2) if params["contact_offset"] > 0 else np.zeros(2)
    frames, summary = simulate_press(
        rng, c_gel=gel_c[s], c_obj=c_obj, dome_radius=dome_r[s], m=params["hertz_exponent"],
        c_drive=params["drive_compliance"], f_push=f_push, v_push=v_push,
        unevenness=params["speed_unevenness"], force_lag=lag, deceleration=params["deceleration"],
        hold=hold, retreat_ratio=ret, fps=params["fps"], n_before=n_before, n_after=n_after,
        timestamp_jitter=params["timestamp_jitter"], force_noise=params["force_noise"],
        lateral_gain_object=params["lateral_gain_object"],
        lateral_gain_gel=params["lateral_gain_gel"],
    )
    row = dict(F_push=f_push, v_push=v_push, force_lag=lag, hold=hold, retreat_speed=ret * v_push,
               compliance_object=c_obj, compliance_gel=gel_c[s], dome_radius=dome_r[s], sensor=s,
               offset_x=offset[0], offset_y=offset[1], n_before=n_before, n_after=n_after, **summary)
    return frames, (float(offset[0]), float(offset[1])), row


def _make_everyday(params, n_per_class, markers, image_size, shuffle, return_mechanics, codec, ss):
    """``make_presses("everyday")``: objects of many shapes, a few presses each."""
    ss_sensor, ss_object, ss_press, ss_order = ss.spawn(4)
    n_sensors = params["n_sensors"]
    sensor_rng = np.random.default_rng(ss_sensor)
    gel_c = params["gel_compliance"] * np.exp(params["sensor_spread"] * sensor_rng.standard_normal(n_sensors))
    sensor_seeds = [_seed_int(s) for s in ss_sensor.spawn(n_sensors)]
    objects = sample_objects(np.random.default_rng(ss_object), params["n_objects"],
                             params["class_ratio"], params)
    object_idx = np.repeat(np.arange(len(objects)), n_per_class)
    n = len(object_idx)
    if shuffle:
        object_idx = object_idx[np.random.default_rng(ss_order).permutation(n)]
    target = np.array([objects[k]["target"] for k in object_idx], dtype=int)

    keys = ["F_push", "v_push", "force_lag", "hold", "retreat_speed", "compliance_object",
            "compliance_gel", "dome_radius", "sensor", "offset_x", "offset_y", "n_before",
            "n_after", "force_peak", "t_contact", "t_trigger", "t_release", "hand", "n_frames"]
    pp = {k: np.empty(n) for k in keys}
    mechanics, centers, render_seeds = [], [], []
    for i, (k, press_ss) in enumerate(zip(object_idx, ss_press.spawn(n))):
        mech_ss, render_ss = press_ss.spawn(2)
        rng = np.random.default_rng(mech_ss)
        s = int(rng.integers(n_sensors))
        frames, row = sample_press(rng, objects[k], c_gel=gel_c[s], params=params)
        mechanics.append(frames)
        centers.append((float(row["offset_x"]), float(row["offset_y"])))
        render_seeds.append(_seed_int(render_ss))
        row["sensor"] = s
        for key in keys:
            pp[key][i] = row[key]
    for key in ("sensor", "n_before", "n_after", "n_frames"):
        pp[key] = pp[key].astype(int)
    pp["hand"] = pp["hand"].astype(bool)

    sim = _EverydaySimulation(params, image_size, markers, sensor_seeds, pp["sensor"], mechanics,
                              centers, render_seeds, objects, object_idx, codec)
    names = np.array([name for name, _ in EVERYDAY_RANKS])
    data = Bunch(
        videos=SimulatedPressVideos(sim.render, list(range(n))),
        target=target,
        target_names=names,
        hardness=params["hardness"].copy(),
        hardness_unit=params["hardness_unit"],
        force=[m["force"].copy() for m in mechanics],
        timestamps=[m["time"].copy() for m in mechanics],
        position=[m["sensor_position"].copy() for m in mechanics],
        object_id=np.array([f"everyday-{k:02d}-{objects[k]['kind'].replace(' ', '-')}" for k in object_idx]),
        objects=[dict(o) for o in objects],
        press_params=pp,
        fps=params["fps"],
        params=dict(params),
        DESCR=_descr("everyday", params, n, image_size),
    )
    if return_mechanics:
        data.mechanics = [{k: v.copy() for k, v in m.items() if k != "force"} for m in mechanics]
    return data
