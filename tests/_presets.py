"""The ``everyday`` preset's settings before issue 20 moved it to shared kinds and the gel's spreading.

Tests of properties that the former preset has by design (each rank its own kinds of object, rigid
imprints, softer soft objects; on it the ready-made nets beat the one-number baseline by >= 0.10)
pass these explicitly, so they test what they say and not whatever the defaults are. The settings are
defined once, as ``PRESET_BEFORE`` in ``studies/scripts/_sim_variants.py``, which the simulator studies
build their variants on.
"""

import importlib.util
import os

_spec = importlib.util.spec_from_file_location(
    "_sim_variants", os.path.join(os.path.dirname(os.path.dirname(os.path.abspath(__file__))),
                                  "studies", "scripts", "_sim_variants.py"))
_variants = importlib.util.module_from_spec(_spec)
_spec.loader.exec_module(_variants)

EVERYDAY_BEFORE = dict(_variants.PRESET_BEFORE)
