"""Utilities shared across sklearn-hardness (input validation, random state helpers)."""

from ._validation import check_video, check_video_sequence, check_frames_array

__all__ = ["check_video", "check_video_sequence", "check_frames_array"]
