"""Press-video datasets: real recordings (a manifest, the public PhysiCLeAR set) and the simulator.

- :func:`load_press_videos`, :func:`load_physiclear`: real recordings.
- :func:`make_presses`, :class:`SimulatedSensor`: the physics-based simulator.
- :func:`force_and_position`: each press's force and position per frame, where
  a dataset has them (the input of ``loading_compliance``).
"""

from ._force_position import force_and_position
from ._manifest import load_press_videos
from ._physiclear import load_physiclear
from ._sensor import SimulatedSensor
from ._simulator import make_presses

__all__ = ["load_press_videos", "load_physiclear", "make_presses", "SimulatedSensor", "force_and_position"]
