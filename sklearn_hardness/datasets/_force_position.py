"""Each press's force and position per frame, as ``(T, 2)`` arrays: the input of ``loading_compliance``."""

from __future__ import annotations

import numpy as np

from ..utils._param_validation import StrOptions, validate_params

__all__ = ["force_and_position"]


def _lacking(data):
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


@validate_params({"data": "no_validation", "missing": [StrOptions({"raise", "none"})]},
                 prefer_skip_nested_validation=True)
def force_and_position(data, *, missing="raise"):
    """Each press's force and sensor position per frame, as one ``(T, 2)`` array a press.

    The input of :class:`~sklearn_hardness.features.LoadingCompliance` (the
    pipeline ``"loading_compliance"``; ``force_position`` of
    :func:`~sklearn_hardness.model_selection.evaluate_pipelines`), from a
    dataset's ``force`` and ``position`` (a manifest's ``force_path`` and
    ``position_path`` columns, the simulator's presets).

    Parameters
    ----------
    data : Bunch
        A dataset with ``target`` and, per press, ``force`` (N) and
        ``position`` (mm, growing as the sensor moves into the object), one
        number per frame each; where it has ``paths`` (a manifest's), an
        error names the press by its video too.
    missing : {"raise", "none"}, default="raise"
        Where some press has no force or position: raise an error naming
        them and what to give, or return None.

    Returns
    -------
    force_position : list of ndarray of shape (T, 2), or None
        Force and position per frame, press by press.

    Raises
    ------
    ValueError
        Presses without force or position (with ``missing="raise"``), a
        series that is not one number per frame, or force and position of
        different lengths.

    Examples
    --------
    >>> from sklearn_hardness.datasets import force_and_position, make_presses
    >>> data = make_presses("everyday", n_per_class=1, n_objects=3, class_ratio=[1, 1, 1],
    ...                     image_size=(16, 20), codec=None, random_state=0)
    >>> rows = force_and_position(data)
    >>> len(rows) == len(data.target), rows[0].shape[1]
    (True, 2)
    """
    lacking = _lacking(data)
    if lacking and missing == "none":
        return None
    if lacking:
        shown = ", ".join(map(str, lacking[:10])) + (", ..." if len(lacking) > 10 else "")
        raise ValueError(
            f"{len(lacking)} of {len(data.target)} presses have no force and position per frame (presses "
            f"{shown}), which loading_compliance reads: give a manifest force_path and position_path columns "
            "(position in mm, growing as the sensor moves into the object), or a dataset Bunch with force and "
            "position lists.")
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
