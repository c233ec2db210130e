#!/usr/bin/env bash
# The project's full test command (the README's second quick-start command; .ci/run calls it).
# Lints and tests the Rust core, builds the wheel, installs it, then runs pytest against it.
set -euo pipefail
cd "$(dirname "$0")/.."
PY=${PYTHON:-python3}

echo "== cargo fmt --check"
cargo fmt --all -- --check
echo "== cargo clippy"
cargo clippy --workspace --all-targets --all-features -- -D warnings
echo "== cargo test"
cargo test --workspace --release

echo "== build and install the wheel"
rm -rf dist
"$PY" -m maturin build --release --out dist
"$PY" -m pip install --force-reinstall --no-deps dist/geofeas-*.whl

echo "== typed stubs match the runtime"
(cd /tmp && "$PY" -m mypy.stubtest geofeas._core --ignore-missing-stub)

echo "== ruff"
"$PY" -m ruff check python tests benches scripts

echo "== pytest"
# run from a directory without the source tree so the installed wheel is what is tested;
# pytest exits 5 when it collects nothing, which fails this script.
"$PY" -m pytest "$PWD/tests" -q -p no:cacheprovider
