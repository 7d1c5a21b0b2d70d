"""Shrinking a documented example's source for a test run (fewer presses, epochs, MC passes)."""


def smaller(code, replacements, where):
    """``code`` with each ``old -> new`` of ``replacements`` made; each ``old`` must be in it.

    ``where`` names the example and the test that holds the replacements, for the error when an
    example no longer contains a text the test shrinks.
    """
    for old, new in replacements.items():
        assert old in code, f"{where} no longer contains {old!r}: update the test's replacements"
        code = code.replace(old, new)
    return code
