"""A lazy, indexable sequence of videos, and the error for videos that cannot be read."""

from __future__ import annotations

from ..utils._lazy import LazyVideoSequence
from ..utils._unreadable import UnreadableVideosError, raise_unreadable  # moved to utils

__all__ = ["LazyVideoSequence", "UnreadableVideosError", "raise_unreadable"]
