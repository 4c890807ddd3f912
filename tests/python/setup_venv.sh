#!/usr/bin/env bash
# Create .venv (git-ignored) with fmpy, pytest, numpy and matplotlib.
# Idempotent: pip runs only when the venv is new or requirements.txt changed since the last install.
set -euo pipefail
cd "$(dirname "$0")/../.."
venv=.venv
req=tests/python/requirements.txt
stamp="$venv/.viscosph-requirements"

if [ ! -x "$venv/bin/python" ]; then
    if ! python3 -m venv "$venv"; then
        # Debian/Ubuntu ship venv support separately.
        echo "python3 -m venv failed; installing python3-venv" >&2
        rm -rf "$venv"
        apt-get update
        apt-get install -y python3-venv
        python3 -m venv "$venv"
    fi
fi
if ! cmp -s "$req" "$stamp"; then
    "$venv/bin/python" -m pip install --quiet -r "$req"
    cp "$req" "$stamp"
fi
