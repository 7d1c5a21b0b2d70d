"""Reading and writing tactile press videos.

Videos are ``(T, H, W, 3)`` ``uint8`` RGB arrays. Files are decoded with
OpenCV; a folder of numbered images is read as one video.
"""

from ._record import record_video
from ._video import read_video, write_video

__all__ = ["read_video", "write_video", "record_video"]
