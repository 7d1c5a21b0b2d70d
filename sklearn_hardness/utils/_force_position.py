"""Each press's force and position per frame, as ``(T, 2)`` arrays: the input of ``loading_compliance``.

Shared by ``model_selection``, the experiments and the command line, which read them from a dataset's
``force`` and ``position`` (a manifest's ``force_path`` and ``position_path``,
the simulator's presets).
"""

from __future__ import annotations

import numpy as np

__all__ = ["force_position", "presses_lacking_force_position"]


def presses_lacking_force_position(data):
    """Indices of the presses of ``data`` without force or position per frame."""
    force, position = getattr(data, "force", None), getattr(data, "position", None)
    return [i for i in range(len(data.target))
            if force is None or position is None or force[i] is None or position[i] is None]


def _per_frame(series, what, i):
    """One number per frame: shape (T,), or (T, 1) / (1, T) flattened; anything else is an error."""
    arr = np.asarray(series, dtype=float)
    if arr.ndim == 1 or (arr.ndim == 2 and 1 in arr.shape):
        return arr.ravel()
    raise ValueError(f"press {i}: {what} must be one number per frame, shape (T,); got shape {arr.shape}. "
                     "For a multi-axis force/torque sensor, pass the component along the press axis.")


def force_position(data, names):
    """Each press's ``(T, 2)`` force and position, for the pipelines ``names`` that read them."""
    lacking = presses_lacking_force_position(data)
    if lacking:
        shown = ", ".join(map(str, lacking[:10])) + (", ..." if len(lacking) > 10 else "")
        raise ValueError(
            f"pipeline(s) {names} read each press's force and position per frame, and {len(lacking)} of "
            f"{len(data.target)} presses have none (presses {shown}): give a manifest force_path and "
            "position_path columns (position in mm, growing as the sensor moves into the object), or a "
            "dataset Bunch with force and position lists.")
    out = []
    paths = getattr(data, "paths", None)  # a manifest's: name the press by its video too
    for i, (f, z) in enumerate(zip(data.force, data.position)):
        f, z = _per_frame(f, "force", i), _per_frame(z, "position", i)
        if len(f) != len(z):
            video = f" ({paths[i]})" if paths is not None else ""
            raise ValueError(f"press {i}{video} has {len(f)} force values but {len(z)} positions; both are per "
                             "frame.")
        out.append(np.column_stack([f, z]))
    return out
