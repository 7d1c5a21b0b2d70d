"""Press-video datasets: real recordings (a manifest, the public PhysiCLeAR set) and the simulator."""

from ._manifest import load_press_videos
from ._physiclear import load_physiclear
from ._sensor import SimulatedSensor
from ._simulator import make_presses

__all__ = ["load_press_videos", "load_physiclear", "make_presses", "SimulatedSensor"]
