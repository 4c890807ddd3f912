#!/usr/bin/env bash
# The README's "all tests" command. Stages:
#   1. tool chains and the Python venv (tests/install_toolchains.sh; installs only what is missing)
#   2. the FMU: `cargo run --release -p fmu-build` in target/ (host library, shared with the
#      tests and the main job) plus the portable linux64 and win64 binaries in target/cross
#   3. `cargo test --release --workspace`; the FMU tests use the FMU of stage 2 (VISCOSPH_FMU)
#   4. the validation gallery's short mode (`validation/run.sh --short`: every validation/<case>
#      at low resolution, about a minute, with the release binary stage 3 built; fails when a
#      case breaks a threshold of its README)
#   5. pytest tests/python: fmpy, libcosim, ecos, fmutool, the platforms (glibc, wine), Dask
#   6. the user manual (`mdbook build docs/book`) and the API documentation (`cargo doc`), both
#      without a warning
# Every stage runs even if an earlier one failed; the exit status is nonzero if any failed.
# `bash examples/main.sh` afterwards compiles nothing: it runs the same fmu-build.
set -uo pipefail
cd "$(dirname "$0")/.."

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

stage "tool chains" bash tests/install_toolchains.sh
stage "build the FMU" cargo run --release -p fmu-build
stage "cargo test" env VISCOSPH_FMU="$PWD/target/fmu/ViscoSPH.fmu" \
    cargo test --release --workspace --no-fail-fast
stage "validation (short)" bash validation/run.sh --short
stage "pytest" .venv/bin/python -m pytest tests/python

# Output that names a warning fails the stage: mdbook reports a missing include or a broken
# SUMMARY entry as WARN/ERROR lines and still exits 0; cargo's own warnings (not rustdoc's,
# which -D warnings turns into errors) are lines starting with "warning".
clean_build() {
    local log
    log=$(mktemp)
    "$@" >"$log" 2>&1
    local status=$?
    cat "$log"
    if [ $status -ne 0 ] || grep -qE '(^|\s)(WARN|ERROR)\b|^warning' "$log"; then
        rm -f "$log"
        return 1
    fi
    rm -f "$log"
}
stage "user manual" clean_build "${CARGO_HOME:-$HOME/.cargo}/bin/mdbook" build docs/book
stage "API docs" clean_build env RUSTDOCFLAGS="-D warnings" cargo doc --workspace --no-deps

if [ ${#failed[@]} -gt 0 ]; then
    echo "FAILED: ${failed[*]}"
    exit 1
fi
echo "all tests passed"
