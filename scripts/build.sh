#!/usr/bin/env bash
# Configures and builds the toolkit into build/ (Release, Ninja). Used by demo.sh and test.sh.
set -euo pipefail
cd "$(dirname "$0")/.."
# TERRAIN_WARNINGS_AS_ERRORS=ON (CI sets it): a compiler warning fails the build.
cmake -S . -B build -G Ninja -DCMAKE_BUILD_TYPE="${CMAKE_BUILD_TYPE:-Release}" \
  -DTERRAIN_WARNINGS_AS_ERRORS="${TERRAIN_WARNINGS_AS_ERRORS:-OFF}" >/dev/null
cmake --build build --parallel "${TERRAIN_BUILD_JOBS:-$(nproc)}"
