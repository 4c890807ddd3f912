#!/usr/bin/env bash
# Everything the test command needs beyond Rust itself, installed only when missing (a second
# run installs nothing):
# - Debian packages: libclang-dev (bindgen in the `fmi` crate's fmi-sys), mingw-w64 (linker of
#   the win64 DLL and of the Windows test importer), wine (runs that importer), libtbb12
#   (ecospy's native library), libglu1-mesa libxcursor1 libxinerama1 libxft2 (libraries the PyPI
#   gmsh wheel links against, for tests/python/test_cylinder_reference.py);
# - the Rust standard library for x86_64-pc-windows-gnu (rustup; offline it may be impossible:
#   then the FMU is built without win64 and fmu-build says so);
# - the Python venv .venv (tests/python/setup_venv.sh), which also holds PyPI's cargo-zigbuild
#   and ziglang: fmu-build links the glibc-2.17 linux64 binary with them.
# - mdbook, pinned, into cargo's bin directory (`cargo install` builds in a directory of its own,
#   not in target/): the test command builds the user manual (docs/book) with it.
set -uo pipefail
cd "$(dirname "$0")/.."

as_root() { if [ "$(id -u)" -eq 0 ]; then "$@"; else sudo "$@"; fi; }

missing=()
for pkg in libclang-dev mingw-w64 wine wine64 libtbb12 libglu1-mesa libxcursor1 libxinerama1 libxft2; do
    dpkg -s "$pkg" >/dev/null 2>&1 || missing+=("$pkg")
done
if [ ${#missing[@]} -gt 0 ]; then
    echo "== installing ${missing[*]}"
    as_root apt-get update -q && DEBIAN_FRONTEND=noninteractive as_root apt-get install -y -q "${missing[@]}" || exit 1
fi

if ! rustc --print target-list >/dev/null 2>&1 || \
   [ ! -d "$(rustc --print sysroot)/lib/rustlib/x86_64-pc-windows-gnu" ]; then
    rustup target add x86_64-pc-windows-gnu || \
        echo "== note: could not install Rust's x86_64-pc-windows-gnu standard library; the FMU will have no win64 binary"
fi

MDBOOK_VERSION=0.5.4
MDBOOK="${CARGO_HOME:-$HOME/.cargo}/bin/mdbook"
if ! "$MDBOOK" --version 2>/dev/null | grep -qx "mdbook v$MDBOOK_VERSION"; then
    echo "== installing mdbook $MDBOOK_VERSION"
    cargo install mdbook --locked --version "$MDBOOK_VERSION" || exit 1
fi

bash tests/python/setup_venv.sh || exit 1
exit 0
