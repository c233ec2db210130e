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
# the test extra's requirements (expanded through the extras it names) install in the background
# while cargo compiles; the wheel's own install below then finds them in place. Without tomllib
# (Python 3.10) that install does all the work instead. No byte-compiling of every installed
# module: the tests compile the few they import.
deps_log=$(mktemp)
deps=$("$PY" - <<'PYEOF' || true
try:
    import tomllib
except ImportError:
    raise SystemExit(0)
extras = tomllib.load(open("pyproject.toml", "rb"))["project"]["optional-dependencies"]


def expand(name):
    for req in extras[name]:
        if req.startswith("geofeas["):
            for e in req[len("geofeas[") : -1].split(","):
                yield from expand(e.strip())
        else:
            yield req


print("\n".join(sorted(set(expand("test")))))
PYEOF
)
deps_pid=
if [ -n "$deps" ]; then
    printf '%s\n' "$deps" > "$deps_log.req"
    "$PY" -m pip install --quiet --disable-pip-version-check --no-compile -r "$deps_log.req" > "$deps_log" 2>&1 &
    deps_pid=$!
fi

echo "== cargo fmt --check"
cargo fmt --all -- --check
echo "== cargo clippy"
# in the test profile, so the build scripts and proc-macros it compiles serve `cargo test` too
cargo clippy --workspace --all-targets --all-features --profile "$CARGO_PROFILE" -- -D warnings
echo "== cargo test"
# the bindings crate has no Rust tests (pytest tests it); it is listed so that features resolve as
# in the wheel build, which then reuses the core and tracking libraries built here
cargo test -p geofeas -p geofeas-tracking -p geofeas-python --all-features --profile "$CARGO_PROFILE"

echo "== build and install the wheel with the test extras"
rm -rf dist
"$PY" -m maturin build --profile "$CARGO_PROFILE" --out dist
wheel=$(ls dist/geofeas-*.whl)
if [ -n "$deps_pid" ] && ! wait "$deps_pid"; then
    cat "$deps_log"
    echo "installing the test requirements failed" >&2
    exit 1
fi
"$PY" -m pip install --quiet --disable-pip-version-check "${wheel}[test]"
"$PY" -m pip install --quiet --disable-pip-version-check --force-reinstall --no-deps "$wheel"

echo "== typed stubs match the runtime"
(cd /tmp && "$PY" -m mypy.stubtest geofeas._core --ignore-missing-stub)

echo "== ruff"
"$PY" -m ruff check python tests benches scripts
"$PY" -m ruff format --check python tests benches scripts

echo "== pytest"
# run from a directory without the source tree so the installed wheel is what is tested;
# pytest exits 5 when it collects nothing, which fails this script.
# Two workers (pytest-xdist), a test file per worker at a time: the module-scoped fixtures (the
# demo runs) are computed once, and the demo's file runs beside the rest.
"$PY" -m pytest "$PWD/tests" -q -p no:cacheprovider -n 2 --dist loadfile
