#!/usr/bin/env bash
# Build the HTML docs with warnings as errors, offline: docs/_build/html/index.html.
#   bash docs/build_docs.sh                 # gallery examples executed (the whole site)
#   bash docs/build_docs.sh --no-gallery    # examples rendered but not run (CI: the tests run them)
# Extra arguments go to sphinx-build. Needs: pip install -e ".[docs]".
set -euo pipefail
cd "$(dirname "$0")/.."

PY=${PYTHON:-python3}
gallery=()
if [ "${1:-}" = "--no-gallery" ]; then
    gallery=(-D plot_gallery=0)
    shift
fi
# Generated pages of an earlier build would hide a name that was removed since.
rm -rf docs/generated docs/auto_examples docs/sg_execution_times.rst
# -E: a fresh environment, so every page is read and resolved again: an incremental build would
# not re-check a page whose reference lost its target elsewhere (nitpicky, see docs/conf.py).
$PY -m sphinx -E -W --keep-going -b html ${gallery[@]+"${gallery[@]}"} "$@" docs docs/_build/html
echo "built docs/_build/html/index.html"
