#!/usr/bin/env bash
# Quick start, step 1: install the Debian packages, build furnace (Release)
# with its tests, and run the default verification (`furnace verify`), which
# prints the verdict table and exits non-zero on any failure.
set -euo pipefail
cd "$(dirname "$0")/.."
./scripts/setup.sh
./scripts/build.sh
./build/bin/furnace verify
