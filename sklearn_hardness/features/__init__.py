"""Feature transformers for selected press frames (n, k, H, W, C).

- :class:`OpticalFlowFeatures`: displacements of Shi-Tomasi corners tracked
  with pyramidal Lucas-Kanade (OpenCV), the input of the paper's OFNN.
- :class:`DINOv2Features`: frozen DINOv2 embeddings of every frame,
  concatenated, the input of the paper's DINOv2NN (needs the optional
  ``transformers`` dependency: ``pip install sklearn-hardness[dinov2]``).
"""

from ._contact_profile import ContactProfileFeatures
from ._dinov2 import DINOv2Features
from ._optical_flow import OpticalFlowFeatures

__all__ = ["ContactProfileFeatures", "DINOv2Features", "OpticalFlowFeatures"]
