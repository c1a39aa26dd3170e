#!/usr/bin/env bash
# Long local fuzzing run: each cargo-fuzz target (libFuzzer) for FUZZ_SECONDS (default 3600)
# seconds, or FUZZ_RUNS executions when that is set, then the USD importer's hypothesis test with
# FUZZ_PY_EXAMPLES (default 20000) fresh examples. Crashes land in fuzz/artifacts/<target>/;
# replay one with `RUSTC_BOOTSTRAP=1 cargo fuzz run <target> <file>`, then turn it into a test
# in tests/fuzz_regressions.rs.
#
#   ./scripts/fuzz.sh                         # both targets, one hour each
#   FUZZ_SECONDS=600 FUZZ_JOBS=4 ./scripts/fuzz.sh ir_builder
#   FUZZ_SANITIZER=none FUZZ_RUNS=1000000 ./scripts/fuzz.sh scene_json
#
# FUZZ_TIMEOUT (default 10) is libFuzzer's per-input limit in wall seconds; raise it for a run
# at low priority on a busy machine, where a starved input can take ten times its CPU time.
# FUZZ_SANITIZER (default address) is passed to `cargo fuzz run -s`: `none` builds without
# AddressSanitizer, several times faster. The core is safe Rust, so the sanitizer mostly
# guards the dependencies; panics and the finite-pixel checks are caught either way.
#
# cargo-fuzz needs nightly flags; RUSTC_BOOTSTRAP=1 lets the stable toolchain accept them.
set -euo pipefail
cd "$(dirname "$0")/.."
SECS="${FUZZ_SECONDS:-3600}"
# A run count alone runs until it is reached (max_total_time=0: no time limit).
[ -z "${FUZZ_RUNS:-}" ] || [ -n "${FUZZ_SECONDS:-}" ] || SECS=0
JOBS="${FUZZ_JOBS:-1}"
SANITIZER="${FUZZ_SANITIZER:-address}"
TIMEOUT="${FUZZ_TIMEOUT:-10}"
RUNS=()
[ -z "${FUZZ_RUNS:-}" ] || RUNS=(-runs="$FUZZ_RUNS")
TARGET_DIR="${CARGO_TARGET_DIR:-$PWD/target-fuzz}"
PAR=()
[ "$JOBS" -le 1 ] || PAR=(-jobs="$JOBS" -workers="$JOBS")
TARGETS=("$@")
[ ${#TARGETS[@]} -gt 0 ] || TARGETS=(scene_json ir_builder)
command -v cargo-fuzz > /dev/null || cargo install cargo-fuzz

for t in "${TARGETS[@]}"; do
    mkdir -p "fuzz/corpus/$t"
    RUSTC_BOOTSTRAP=1 cargo fuzz run -O -s "$SANITIZER" --target-dir "$TARGET_DIR" "$t" -- \
        -max_total_time="$SECS" -timeout="$TIMEOUT" -rss_limit_mb=3072 -max_len=8192 -len_control=0 \
        -print_final_stats=1 ${RUNS[@]+"${RUNS[@]}"} ${PAR[@]+"${PAR[@]}"}
done

# The USD importer: the test venv of scripts/test.sh (with hypothesis), if there is one.
PY="${PHOTONMAP_TEST_VENV:-$PWD/.venv-test}/bin/python"
if [ -x "$PY" ]; then
    (cd tests/python && PHOTONMAP_FUZZ_EXAMPLES="${FUZZ_PY_EXAMPLES:-20000}" \
        "$PY" -m pytest -q -p no:cacheprovider test_fuzz_usd.py)
fi
