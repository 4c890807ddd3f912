#!/usr/bin/env bash
# The README's "all tests" command: Rust unit and integration tests (the FMU through the `fmi`
# crate included), then the fmpy tests of the built FMU. Every stage runs even if an earlier
# one failed; the exit status is nonzero if any failed.
set -uo pipefail
cd "$(dirname "$0")/.."

as_root() { if [ "$(id -u)" -eq 0 ]; then "$@"; else sudo "$@"; fi; }

# The `fmi` crate's fmi-sys runs bindgen, which needs libclang.
# (grep without -q reads all of ldconfig's output, so pipefail sees no SIGPIPE.)
if ! ldconfig -p | grep libclang >/dev/null; then
    echo "== installing libclang-dev (needed by bindgen in fmi-sys)"
    as_root apt-get update && as_root apt-get install -y libclang-dev || exit 1
fi

failed=()
stage() {
    local name=$1
    shift
    echo "== $name"
    local t0=$SECONDS
    if "$@"; then
        echo "== $name: ok ($((SECONDS - t0)) s)"
    else
        echo "== $name: FAILED ($((SECONDS - t0)) s)"
        failed+=("$name")
    fi
}

stage "cargo test" cargo test --release --workspace --no-fail-fast
stage "build the FMU" cargo run --release -p fmu-build --target-dir target/fmu-build
stage "python venv" bash tests/python/setup_venv.sh
stage "fmpy tests" .venv/bin/python -m pytest tests/python

if [ ${#failed[@]} -gt 0 ]; then
    echo "FAILED: ${failed[*]}"
    exit 1
fi
echo "all tests passed"
