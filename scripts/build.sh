#!/usr/bin/env bash
# Configures and builds the toolkit into build/ (Release, Ninja). Used by demo.sh and test.sh.
set -euo pipefail
cd "$(dirname "$0")/.."
cmake -S . -B build -G Ninja -DCMAKE_BUILD_TYPE="${CMAKE_BUILD_TYPE:-Release}" >/dev/null
cmake --build build --parallel "${TERRAIN_BUILD_JOBS:-$(nproc)}"
