"""Press-video datasets: real recordings from a manifest and the built-in simulator."""

from ._manifest import load_press_videos
from ._sensor import SimulatedSensor
from ._simulator import make_presses

__all__ = ["load_press_videos", "make_presses", "SimulatedSensor"]
