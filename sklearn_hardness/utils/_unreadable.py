"""The error for videos that cannot be read, raised by ``datasets``, ``model_selection``,
``experiments`` and the command line once for every such video of a dataset."""

from __future__ import annotations

from ._lazy import LazyVideoSequence

__all__ = ["UnreadableVideosError", "raise_unreadable"]


class UnreadableVideosError(ValueError):
    """Some videos of a dataset cannot be read; the message lists every one of them."""


def raise_unreadable(videos, cause=None):
    """Raise one :class:`UnreadableVideosError` listing every video of ``videos`` that cannot be read.

    For the places where a pass over every press failed: the pass stops at
    the first video it cannot read, and a user mending a manifest wants them
    all at once. Returns (raising nothing) where every video reads, so the
    caller re-raises its own error. Only a :class:`LazyVideoSequence` is read
    (videos in memory have nothing left to fail on), each in full: a file can
    open and fail later. ``cause`` is chained to the error raised.
    """
    if not isinstance(videos, LazyVideoSequence):
        return
    found = []
    for i in range(len(videos)):
        try:
            videos[i]
        except (ValueError, TypeError, OSError) as exc:  # what read_video raises on a file it cannot read
            found.append(f"video {i}: {exc}")
    if found:
        raise UnreadableVideosError(
            f"{len(found)} of {len(videos)} videos cannot be read:\n  " + "\n  ".join(found)
            + "\nRemove their rows from the manifest, or replace the files with ones that "
            "sklearn_hardness.io.read_video reads."
        ) from cause
