#!/usr/bin/env bash
# The project's full test command (the README's second quick-start command; .ci/run calls it).
# Installs what the tests need into the active Python environment, lints and tests the Rust crates
# (the core and the trackers; the bindings crate is tested by pytest), builds the wheel, installs
# it, then runs pytest against it.
#
# One cargo profile (`ci`: optimised, no LTO) for `cargo test` and the wheel, with the same
# interpreter for pyo3, so neither build invalidates the other and a rerun recompiles nothing
# that did not change: the wheel build compiles only the bindings crate (geofeas-python) and
# links the core and tracking libraries `cargo test` built. Fat-LTO builds are for `pip install .`
# and `cargo bench` only.
set -euo pipefail
cd "$(dirname "$0")/.."
PY=${PYTHON:-python3}
export PYO3_PYTHON="$("$PY" -c 'import sys; print(sys.executable)')"
export CARGO_PROFILE=ci

echo "== install the test tools"
"$PY" -m pip install --quiet --disable-pip-version-check "maturin>=1.7,<2"

echo "== cargo fmt --check"
cargo fmt --all -- --check
echo "== cargo clippy"
cargo clippy --workspace --all-targets --all-features -- -D warnings
echo "== cargo test"
# the bindings crate has no Rust tests (pytest tests it); it is listed so that features resolve as
# in the wheel build, which then reuses the core and tracking libraries built here
cargo test -p geofeas -p geofeas-tracking -p geofeas-python --all-features --profile "$CARGO_PROFILE"

echo "== build and install the wheel with the test extras"
rm -rf dist
"$PY" -m maturin build --profile "$CARGO_PROFILE" --out dist
wheel=$(ls dist/geofeas-*.whl)
"$PY" -m pip install --quiet --disable-pip-version-check "${wheel}[test]"
"$PY" -m pip install --quiet --disable-pip-version-check --force-reinstall --no-deps "$wheel"

echo "== typed stubs match the runtime"
(cd /tmp && "$PY" -m mypy.stubtest geofeas._core --ignore-missing-stub)

echo "== ruff"
"$PY" -m ruff check python tests benches scripts

echo "== pytest"
# run from a directory without the source tree so the installed wheel is what is tested;
# pytest exits 5 when it collects nothing, which fails this script.
"$PY" -m pytest "$PWD/tests" -q -p no:cacheprovider
