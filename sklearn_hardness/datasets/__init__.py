"""Press-video datasets: the physics-based simulator and loaders of recordings."""

from ._simulator import make_presses

__all__ = ["make_presses"]
