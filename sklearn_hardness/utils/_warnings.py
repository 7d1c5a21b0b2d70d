"""Warnings that point at the user's line: :func:`external_stacklevel`."""

import os
import sys

import sklearn

#: Folders whose frames a warning skips: this package and scikit-learn's wrappers
#: (``set_output``, ``Pipeline``) that sit between a user's call and our code.
_INTERNAL = (
    os.path.dirname(os.path.dirname(os.path.abspath(__file__))) + os.sep,
    os.path.dirname(os.path.abspath(sklearn.__file__)) + os.sep,
)


def external_stacklevel():
    """The ``stacklevel`` that makes ``warnings.warn`` report the first caller outside the library.

    Call it in the function that calls ``warnings.warn``:
    ``warnings.warn(msg, Category, stacklevel=external_stacklevel())``. Frames
    of this package and of scikit-learn (whose ``fit`` and ``transform``
    wrappers add a different number of frames per method) are skipped, so the
    warning names the user's line whether it came through ``fit``,
    ``fit_transform`` or a pipeline (what Python 3.12's
    ``skip_file_prefixes`` does, on Python 3.11 too).

    Returns
    -------
    stacklevel : int
    """
    frame = sys._getframe(1)  # the function that calls warnings.warn: stacklevel 1
    level = 1
    while frame is not None and os.path.abspath(frame.f_code.co_filename).startswith(_INTERNAL):
        frame = frame.f_back
        level += 1
    return level
