"""A press's compliance from the robot's force and position over its loading phase: :class:`LoadingCompliance`."""

from __future__ import annotations

import numbers
import warnings

import numpy as np
from sklearn.base import BaseEstimator, TransformerMixin
from sklearn.utils.validation import check_is_fitted

from ..utils._param_validation import HasMethods, Interval, StrOptions, fit_context
from ..utils._per_press import PerPressTransformerMixin, transform_presses
from ..utils._tags import force_position_tags
from ..utils._validation import check_force_position
from ..utils._warnings import external_stacklevel
from ._feature_names import check_feature_names, feature_columns

__all__ = ["LoadingCompliance"]

#: Every feature, in output order when ``features="all"``.
FEATURE_NAMES = ("hertz_compliance", "linear_compliance", "travel", "peak_force")

#: Exponent of the Hertz law ``delta = c F^(2/3)`` (``F`` grows as ``delta^(3/2)``).
_HERTZ = 2.0 / 3.0


def _loading_figures(press, onset, min_frames, drive_compliance):
    """The four figures of one (T, 2) press; NaN where its loading phase is too short to fit."""
    force = press[:, 0]
    position = press[:, 1] - drive_compliance * force  # where the sensor is
    peak = int(np.argmax(force))
    f_peak = float(force[peak])
    if f_peak <= 0.0:
        return np.array([np.nan, np.nan, np.nan, f_peak])
    start = int(np.argmax(force > onset * f_peak))  # <= peak: the peak itself exceeds the onset
    f, z = np.clip(force[start:peak + 1], 0.0, None), position[start:peak + 1]
    travel = float(z[-1] - z[0])
    if peak - start + 1 < min_frames or np.ptp(f) == 0.0:
        return np.array([np.nan, np.nan, travel, f_peak])
    hertz = float(np.polyfit(f ** _HERTZ, z, 1)[0])
    linear = float(np.polyfit(f, z, 1)[0])
    return np.array([hertz, linear, travel, f_peak])


class ConventionWarning(UserWarning):
    """Most presses break a convention of :class:`LoadingCompliance`'s input.

    Force is positive and position in millimetres, growing as the sensor
    moves inwards; where more than half of the presses break one of these,
    :class:`LoadingCompliance` warns, listing them.

    Examples
    --------
    >>> import warnings
    >>> import numpy as np
    >>> from sklearn_hardness.features import ConventionWarning, LoadingCompliance
    >>> force = np.linspace(0.0, 4.0, 20)
    >>> width = 10.0 - 0.3 * force ** (2 / 3)   # a gripper's width: falls as the force rises
    >>> with warnings.catch_warnings(record=True) as caught:
    ...     warnings.simplefilter("always")
    ...     _ = LoadingCompliance().fit_transform([np.column_stack([force, width])])
    >>> [w.category.__name__ for w in caught]
    ['ConventionWarning']
    """


def _listed(indices):
    return ", ".join(map(str, indices[:10])) + (", ..." if len(indices) > 10 else "")


def _force_negative(press):
    """Whether a press's force is mostly below zero (a compressive force recorded with the wrong sign)."""
    return bool(-press[:, 0].min() > 3 * max(press[:, 0].max(), 0.0))


def _convention_messages(force_negative, hertz):
    """What most presses break of the input's conventions (force positive, position in mm growing inwards).

    Each check counts presses, and speaks where more than half of them break
    it: one rigid object can fit a compliance of zero or below, or a press
    without contact be noise around zero, but a whole recording with a
    flipped sign or another unit is an input to fix.
    """
    n = len(hertz)
    half, messages = n / 2, []
    negative = np.flatnonzero(force_negative)
    if len(negative) > half:
        messages.append(f"{len(negative)} of {n} presses (X[{_listed(negative)}]) have their force mostly below "
                        "zero: a compressive force must be positive (negate it).")
    falling = np.flatnonzero(hertz <= 0.0)
    if len(falling) > half:
        messages.append(f"on {len(falling)} of {n} presses (X[{_listed(falling)}]) the position falls as the force "
                        "rises: the position must grow as the sensor moves into the object (a gripper's closing, "
                        "not its width; negate a position that falls).")
    tiny = np.flatnonzero((hertz > 0.0) & (hertz < 1e-3))
    if len(tiny) > half:
        messages.append(f"{len(tiny)} of {n} presses (X[{_listed(tiny)}]) move under a micrometre per N^(2/3): "
                        "is the position in metres? It must be in mm.")
    return messages


class LoadingCompliance(PerPressTransformerMixin, TransformerMixin, BaseEstimator):
    """How far the sensor moves into the object per unit force while it loads.

    For a robot (or gripper) that records its force and position at each
    frame, the most direct measure of hardness: a soft object lets the
    sensor travel further for the same force. Per press, the loading phase
    runs from the first frame whose force exceeds ``onset`` times the peak
    force to the peak. Over it:

    - ``hertz_compliance``: the least-squares slope of the position against
      ``F^(2/3)``, in mm per N^(2/3). In Hertz contact a dome indents as
      ``delta = c F^(2/3)``, so this is the compliance ``c`` quoted at 1 N
      (the unit of the simulator's compliances) of gel and object in series,
      with any give between the recorded position and the sensor that
      ``drive_compliance`` does not take off. Unlike the slope against
      ``F``, it does not grow stiffer with the force a robot pushes to, so a
      model trained at a few newtons carries over to grasps at tens of
      newtons.
    - ``linear_compliance``: the slope of the position against ``F``, mm/N.
    - ``travel``: the position's advance over the loading phase, mm.
    - ``peak_force``: the peak force, N.

    A press whose loading phase has fewer than ``min_loading_frames`` frames
    (a video cut short) or no positive force gets NaN for the figures it
    cannot fit, with a warning that names it; put an imputer after this
    step (:func:`~sklearn_hardness.models.make_loading_compliance_pipeline`
    does). Where most presses break the input's conventions (a force mostly
    below zero, a position that falls as the force rises, or one that moves
    under a micrometre per N^(2/3), as a position in metres would), a
    warning says what to fix.

    Parameters
    ----------
    features : "all" or sequence of str, default="all"
        Which figures to output, in this order; ``"all"`` is
        ``hertz_compliance, linear_compliance, travel, peak_force``.
    onset : float in (0, 1), default=0.1
        The loading phase starts where the force first exceeds this share of
        its peak (below it, force noise dominates).
    min_loading_frames : int, default=3
        Fewest frames of loading to fit a slope.
    drive_compliance : float, default=0.0
        The give between the recorded position and the sensor, mm/N:
        ``drive_compliance * force`` is taken off the position first. 0 for a
        measured position (joint encoders, a gripper's width); for an
        impedance controller's *commanded* position, its compliance (one over
        its stiffness: 1.0 mm/N at 1000 N/m). Left in, the drive's give grows
        linearly with force and the Hertz compliance no longer carries across
        forces.
    memory : None, str or object with the joblib.Memory interface, default=None
        Cache each press's figures here (a folder, or a
        :class:`joblib.Memory`), keyed by the parameters that change them and
        a hash of the press's force and position. Validated as
        :func:`sklearn.utils.validation.check_memory` validates a
        :class:`~sklearn.pipeline.Pipeline`'s ``memory``. An entry is under
        1 kB.

    Attributes
    ----------
    features_ : tuple of str
        The output figures, in order.
    n_features_out_ : int
        Their number.

    See Also
    --------
    sklearn_hardness.models.make_loading_compliance_pipeline : This step, a
        log, an imputer, a scaler and a logistic regression.
    sklearn_hardness.features.ContactProfileFeatures : What the video alone
        tells of the loading phase.

    Notes
    -----
    Each press is an array of shape ``(T, 2)``: the force (N) and the position
    (mm) per frame, the position growing as the sensor moves into the object
    (for a robot arm, its measured advance along the press axis; for a
    parallel gripper, the closing: its width at the start minus its width).
    Any offset is allowed. Build it with ``np.column_stack([force,
    position])``. :func:`~sklearn_hardness.datasets.make_presses` gives both
    for simulated presses (``force`` and ``position``, the sensor's measured
    position).

    Examples
    --------
    >>> import numpy as np
    >>> from sklearn_hardness.features import LoadingCompliance
    >>> force = np.linspace(0.0, 4.0, 20)
    >>> soft = np.column_stack([force, 2.0 * force ** (2 / 3)])  # c = 2 mm/N^(2/3)
    >>> hard = np.column_stack([force, 0.5 * force ** (2 / 3)])
    >>> LoadingCompliance(features=["hertz_compliance"]).fit_transform([soft, hard]).round(3)
    array([[2. ],
           [0.5]])
    """

    _parameter_constraints: dict = {
        "features": [StrOptions({"all"}), list, tuple],
        "onset": [Interval(numbers.Real, 0, 1, closed="neither")],
        "min_loading_frames": [Interval(numbers.Integral, 2, None, closed="left")],
        "drive_compliance": [Interval(numbers.Real, 0, None, closed="left")],
        "memory": [None, str, HasMethods(["cache"])],
    }

    _per_press_input = "force_position"
    _per_press_ignored = ("memory", "features")  # every figure is computed and cached

    def __init__(self, features="all", onset=0.1, min_loading_frames=3, drive_compliance=0.0, memory=None):
        self.features = features
        self.onset = onset
        self.min_loading_frames = min_loading_frames
        self.drive_compliance = drive_compliance
        self.memory = memory

    @fit_context(prefer_skip_nested_validation=True)
    def fit(self, X, y=None):
        """Check the parameters and the input (stateless otherwise).

        Parameters
        ----------
        X : sequence of array-like of shape (T, 2)
            Per press, the force (N) and position (mm) of each frame.
        y : ignored

        Returns
        -------
        self : LoadingCompliance
        """
        self.features_ = check_feature_names(self.features, FEATURE_NAMES)
        check_force_position(X)
        self.n_features_out_ = len(self.features_)
        return self

    def transform(self, X):
        """Compute the figures of each press.

        Parameters
        ----------
        X : sequence of array-like of shape (T, 2)
            Per press, the force (N) and position (mm) of each frame.

        Returns
        -------
        figures : ndarray of shape (n_presses, n_features_out_), float64
            NaN where a press's loading phase is too short (with a warning).
        """
        return self._transform_and_info(X)[0]

    def _transform_and_info(self, X):
        check_is_fitted(self)
        presses = check_force_position(X)
        rows, info = transform_presses(self, presses)
        out = rows[:, feature_columns(self.features_, FEATURE_NAMES)]
        for message in _convention_messages(info["force_negative"], rows[:, 0]):
            warnings.warn(message, ConventionWarning, stacklevel=external_stacklevel())
        bad = np.flatnonzero(np.isnan(out).any(axis=1))
        if len(bad):
            warnings.warn(
                f"{len(bad)} of {len(presses)} presses (X[{_listed(bad)}]) have no positive force or fewer than "
                f"{self.min_loading_frames} frames from {self.onset:g} of their peak force to the peak; "
                "their figures are NaN.", UserWarning, stacklevel=external_stacklevel())
        return out, info

    def _transform_presses(self, X):
        rows = np.vstack([_loading_figures(p, self.onset, self.min_loading_frames, self.drive_compliance)
                          for p in X])
        return rows, {"force_negative": np.array([_force_negative(p) for p in X], dtype=bool),
                      "hertz_compliance": rows[:, 0]}

    def _press_note(self, info, users):
        """On how many presses a loading phase was found, and what most presses break of the conventions."""
        hertz = np.asarray(info["hertz_compliance"], dtype=float)
        n, missing = len(hertz), int(np.isnan(hertz).sum())
        text = f"loading phase ({', '.join(users)}): found on {n - missing} of {n} presses"
        if missing:
            text += (f"; none on {missing} (no positive force, or fewer than {self.min_loading_frames} frames from "
                     f"{self.onset:g} of the peak force to the peak): their figures are NaN, for an imputer in the "
                     "pipeline to fill")
        return "; ".join([text, *_convention_messages(info["force_negative"], hertz)])

    def get_feature_names_out(self, input_features=None):
        """Names of the output figures.

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
        return force_position_tags(super().__sklearn_tags__())
