#!/usr/bin/env bash
# The fuzzing campaign of the README's "Reliability" section: every cargo-fuzz target of fuzz/
# (score kernels, relation, report reader) for a set time, then the Python campaign over every
# public function (scripts/fuzz_python.py).
#
#   scripts/fuzz.sh [SECONDS_PER_TARGET] [PYTHON_CALLS_PER_FUNCTION]
#
# Needs nightly Rust and cargo-fuzz (`rustup toolchain install nightly`, `cargo install
# cargo-fuzz`) for the Rust part, and geofeas installed in the Python environment for the other.
# Corpora and any crash reproducers are left in fuzz/corpus/ and fuzz/artifacts/.
set -euo pipefail
cd "$(dirname "$0")/.."
SECS=${1:-60}
CALLS=${2:-100000}
export CARGO_TARGET_DIR=${CARGO_TARGET_DIR:-$PWD/target}/fuzz
for target in scores relation reports; do
    echo "== cargo fuzz run $target (${SECS} s)"
    (cd fuzz && cargo +nightly fuzz run "$target" -- -max_total_time="$SECS" -rss_limit_mb=2048 \
        -print_final_stats=1 2>&1 | grep -E "^(stat::number_of_executed_units|stat::peak_rss|Done|==|SUMMARY)" || true)
    if ls fuzz/artifacts/"$target"/crash-* >/dev/null 2>&1; then
        echo "crash reproducers in fuzz/artifacts/$target" >&2
        exit 1
    fi
done
echo "== python campaign (${CALLS} calls per function)"
"${PYTHON:-python3}" scripts/fuzz_python.py --calls "$CALLS"
