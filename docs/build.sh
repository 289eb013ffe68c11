#!/usr/bin/env bash
# Build the documentation site into docs/_build/html, warnings as errors.
#   bash docs/build.sh               the full site: the gallery's examples are executed
#   bash docs/build.sh --no-gallery  without running the examples (tests/test_docs.py runs them)
# Needs the docs extra: python -m pip install ".[docs]" (and ".[all]" for the gallery).
set -euo pipefail
cd "$(dirname "$0")/.."
export MPLBACKEND=Agg
args=(-W --keep-going -j auto)
if [ "${1:-}" = "--no-gallery" ]; then
    args+=(-D plot_gallery=0)
fi
start=$(date +%s)
python -m sphinx "${args[@]}" docs docs/_build/html
python -m doctest -o ELLIPSIS docs/guide/*.rst  # the user guide's examples (docstrings: pytest)
echo "built docs/_build/html/index.html in $(( $(date +%s) - start )) s"
