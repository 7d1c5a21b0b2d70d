"""Feature transformers for press videos, selected frames and a robot's force.

- :class:`OpticalFlowFeatures`: displacements of Shi-Tomasi corners tracked
  with pyramidal Lucas-Kanade (OpenCV), the input of the paper's OFNN.
- :class:`DINOv2Features`: frozen DINOv2 embeddings of every frame,
  concatenated, the input of the paper's DINOv2NN (needs the optional
  ``transformers`` dependency: ``pip install sklearn-hardness[dinov2]``).
- :class:`ContactGeometryFeatures`: the contact's depth, edges, shape and
  texture over the loading phase, read from the gel's shading (``features="scale_free"``:
  those that do not grow with how hard the press is made).
- :class:`ImprintTextureFeatures`: the texture of the imprint (local binary
  patterns, co-occurrence, Gabor energies, power spectrum, colour) at moments
  of the loading phase.
- :class:`ContactProfileFeatures`: shape- and texture-normalised features of
  a whole press video's loading phase.
- :class:`PeakContactChange`: the one number of a press, its peak change to
  the first frame (the input of the one-number baseline).
- :class:`LoadingCompliance`: the compliance of gel and object from the
  robot's force and position per frame, where they are recorded;
  :class:`ConventionWarning` where most presses break its input's conventions.
"""

from ._contact_geometry import ContactGeometryFeatures
from ._contact_profile import ContactProfileFeatures
from ._dinov2 import DINOv2Features
from ._imprint_texture import ImprintTextureFeatures
from ._loading_compliance import ConventionWarning, LoadingCompliance
from ._optical_flow import OpticalFlowFeatures
from ._peak_contact_change import PeakContactChange

__all__ = [
    "ContactGeometryFeatures",
    "ContactProfileFeatures",
    "DINOv2Features",
    "ImprintTextureFeatures",
    "LoadingCompliance",
    "ConventionWarning",
    "OpticalFlowFeatures",
    "PeakContactChange",
]
