"""``python -m sklearn_hardness._cli``: the ``sklearn-hardness`` command."""

import sys

from . import main

sys.exit(main())
