#!/usr/bin/env bash
# Runs every test of the project: the Rust tests, then the Python package (built with pip)
# and its tests. Needs the Rust toolchain, Python 3.11 and pip.
set -euo pipefail
cd "$(dirname "$0")/.."
cargo test --no-fail-fast

# Python package: build and install it (pip install . builds the Rust core with maturin), then
# run its tests. A fresh venv keeps the machine's interpreter clean.
PY="${PYTHON:-python3}"
VENV="${PHOTONMAP_TEST_VENV:-$PWD/.venv-test}"
"$PY" -m venv "$VENV"
"$VENV/bin/python" -m pip install --quiet --upgrade pip
CARGO_TARGET_DIR="${CARGO_TARGET_DIR:-$PWD/target}" "$VENV/bin/python" -m pip install --quiet . pytest
(cd tests/python && "$VENV/bin/python" -m pytest -q -p no:cacheprovider .)
