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
# - for the FMI 3.0 FMU's aarch64-linux binary: gcc-aarch64-linux-gnu and libc6-dev-arm64-cross
#   (the test importer for aarch64 and its sysroot), qemu-user (runs it), and, because rustup
#   cannot download the aarch64 standard library from here, Debian's rustc-web and its arm64
#   standard library, unpacked (not installed: dpkg-deb -x) into ~/.cache/viscosph/rust-aarch64
#   with a `rustc` wrapper there, which fmu-build finds (about 140 MB of packages, once);
# - mdbook, pinned, into cargo's bin directory (`cargo install` builds in a directory of its own,
#   not in target/): the test command builds the user manual (docs/book) with it.
set -uo pipefail
cd "$(dirname "$0")/.."

as_root() { if [ "$(id -u)" -eq 0 ]; then "$@"; else sudo "$@"; fi; }

missing=()
for pkg in libclang-dev mingw-w64 wine wine64 libtbb12 libglu1-mesa libxcursor1 libxinerama1 libxft2 \
           gcc-aarch64-linux-gnu libc6-dev-arm64-cross qemu-user; do
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

# Debian's rustc-web (a newer rustc than rustup's here, so it gets its own target directory,
# target/cross-aarch64) with the amd64 and arm64 standard libraries and the LLVM it links.
AARCH64_RUST="${XDG_CACHE_HOME:-$HOME/.cache}/viscosph/rust-aarch64"
if ! "$AARCH64_RUST/rustc" --version >/dev/null 2>&1; then
    echo "== unpacking Debian's rustc-web with the arm64 standard library into $AARCH64_RUST"
    (
        set -e
        if ! dpkg --print-foreign-architectures | grep -qx arm64; then
            as_root dpkg --add-architecture arm64
            as_root apt-get update -q
        fi
        version=$(apt-cache policy rustc-web | awk '/Candidate:/ {print $2}')
        std=$(apt-cache depends "libstd-rust-web-dev=$version" | awk '/Depends: libstd-rust-web-[0-9]/ {print $2; exit}')
        llvm=$(apt-cache depends "$std" | awk '/Depends: libllvm[0-9]/ {print $2; exit}')
        debs=$(mktemp -d)
        cd "$debs"
        apt-get download -q "rustc-web=$version" "libstd-rust-web-dev=$version" "$std=$version" \
            "libstd-rust-web-dev:arm64=$version" "$std:arm64=$version" "$llvm"
        rm -rf "$AARCH64_RUST"
        mkdir -p "$AARCH64_RUST/root"
        for deb in ./*.deb; do dpkg-deb -x "$deb" "$AARCH64_RUST/root"; done
        cd - >/dev/null
        rm -rf "$debs"
        printf '#!/bin/sh\nLD_LIBRARY_PATH="%s" exec "%s" "$@"\n' \
            "$AARCH64_RUST/root/usr/lib/x86_64-linux-gnu" "$AARCH64_RUST/root/usr/bin/rustc" \
            >"$AARCH64_RUST/rustc"
        chmod +x "$AARCH64_RUST/rustc"
        "$AARCH64_RUST/rustc" --version
    ) || echo "== note: could not unpack Debian's rustc-web for aarch64; the FMI 3.0 FMU will have no aarch64-linux binary"
fi

MDBOOK_VERSION=0.5.4
MDBOOK="${CARGO_HOME:-$HOME/.cargo}/bin/mdbook"
if ! "$MDBOOK" --version 2>/dev/null | grep -qx "mdbook v$MDBOOK_VERSION"; then
    echo "== installing mdbook $MDBOOK_VERSION"
    cargo install mdbook --locked --version "$MDBOOK_VERSION" || exit 1
fi

bash tests/python/setup_venv.sh || exit 1
exit 0
