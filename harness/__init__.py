"""The development harness of sklearn-hardness: what studies, benchmarks and CI share.

It lives beside the package, never inside it (the wheel holds ``sklearn_hardness``
only), and imports the package, never the other way round:

- :mod:`harness.machine`: the machine's one-thread matmul rate (the speed reference
  of every timing), its BLAS kernels and versions (``python -m harness.machine``);
- :mod:`harness.memory`: peak resident memory of this process or of a process tree;
- :mod:`harness.provenance`: the header of a study's output (command, commit, date,
  machine), the notes beside an output and superseded outputs restored from git;
- :mod:`harness.config_hash`: the configuration hash a ``sklearn-hardness reproduce``
  command will key its runs by, before it runs (``python -m harness.config_hash``);
- :mod:`harness.readme_table`: README's quick table, remade by its command
  (``python -m harness.readme_table``).
- :mod:`harness.figures`: every figure README, ``studies/`` and the docs quote, found in
  the output its page names (``python -m harness.figures``).
- :mod:`harness.timed`: a command's printed text with its wall and CPU time and peak
  memory, as an output with its header (``python -m harness.timed OUT -- COMMAND``).

Run it from the repository root (``python -m harness.<module>``). Scripts in
``studies/scripts`` and ``benchmarks`` reach it through their ``_harness.py``; the
tests import it from the repository root, which pytest puts on ``sys.path``.
"""

import os

#: The repository holding the harness.
ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
