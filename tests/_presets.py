"""The ``everyday`` preset's settings before issue 20 moved it to shared kinds and the gel's spreading.

Tests of properties that the former preset has by design (each rank its own kinds of object, rigid
imprints, softer soft objects; on it the ready-made nets beat the one-number baseline by >= 0.10)
pass these explicitly, so they test what they say and not whatever the defaults are.
"""

EVERYDAY_BEFORE = dict(kinds_by_rank=True, conformity=0.0, gel_spread=0.0, soft_compliance_range=(1.0, 4.0))
