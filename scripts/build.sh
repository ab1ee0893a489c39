#!/usr/bin/env bash
# Configures and builds furnace in Release into ./build (2 parallel jobs: the
# CGAL translation unit alone takes ~1.3 GiB and 30 CPU-s).
set -euo pipefail
cd "$(dirname "$0")/.."
cmake -S . -B build -G Ninja -DCMAKE_BUILD_TYPE=Release
cmake --build build -j "${FURNACE_JOBS:-2}"
