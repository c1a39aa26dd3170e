#!/usr/bin/env bash
# Runs every test of the project. Needs only the Rust toolchain.
set -euo pipefail
cd "$(dirname "$0")/.."
cargo test --no-fail-fast
