"""Honest scikit-learn tags for estimators whose input is not a 2-D table.

Three kinds of input run through this library: raw press videos (a sequence
of (T, H, W, C) arrays, lengths may differ), selected frames (one
(n, k, H, W, C) array) and a robot's force and position per frame (a
sequence of (T, 2) arrays, lengths may differ). None is 2-D, so
``input_tags.two_d_array`` is False: scikit-learn's common checks that feed
2-D data then do not run, and :mod:`sklearn_hardness.utils.estimator_checks`
runs their video equivalents instead.
"""

from __future__ import annotations

__all__ = ["force_position_tags", "frames_tags", "videos_tags"]


def _not_a_table(tags):
    tags.input_tags.two_d_array = False
    tags.input_tags.three_d_array = False
    tags.input_tags.allow_nan = False
    return tags


def frames_tags(tags):
    """Tags of an estimator taking selected frames ``(n, k, H, W, C)``.

    A transformer's output is float32 whatever the input dtype.
    """
    tags = _not_a_table(tags)
    if tags.transformer_tags is not None:
        tags.transformer_tags.preserves_dtype = ["float32"]
    return tags


def videos_tags(tags):
    """Tags of an estimator taking a sequence of press videos ``(T, H, W, C)``.

    It learns what it needs from the videos in ``fit`` (``requires_fit``).
    """
    tags = _not_a_table(tags)
    tags.requires_fit = True
    return tags


def force_position_tags(tags):
    """Tags of an estimator taking per-frame force and position of each press ``(T, 2)``.

    Like :func:`videos_tags`: a sequence whose items' lengths differ, not a
    table.
    """
    tags = _not_a_table(tags)
    tags.requires_fit = True
    return tags
