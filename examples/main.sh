#!/usr/bin/env bash
# The README's main job: build target/fmu/ViscoSPH.fmu and run the default drop impact (Fang
# 2006's Oldroyd-B drop) through it with fmpy, writing results/fmu_drop.csv and
# results/fmu_drop.png. Extra arguments go to examples/fmu_drop.py, e.g.
#   bash examples/main.sh --set plate_inclination=30 --set rheology=giesekus
# Enumerations take their names (rheology=oldroyd_b) or numbers. A numerical breakdown still
# writes the CSV and the PNG (breakdown marked on it) and makes this script exit non-zero.
# Idempotent: a second run rebuilds nothing and reinstalls nothing.
set -euo pipefail
cd "$(dirname "$0")/.."

# The venv first: it holds PyPI's cargo-zigbuild and ziglang, with which fmu-build links the
# portable linux64 binary.
bash tests/python/setup_venv.sh
# The same build as the test command's (target/, same features), so after
# `bash tests/run_all.sh` this compiles nothing.
cargo run --release -p fmu-build
.venv/bin/python examples/fmu_drop.py "$@"
