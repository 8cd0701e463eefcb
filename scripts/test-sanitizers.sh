#!/usr/bin/env bash
# Builds the whole project with clang under AddressSanitizer + UndefinedBehaviorSanitizer
# into build-asan/ and runs every test through ctest (CI runs it after scripts/test.sh).
# Leaks inside the system's libraries (Mesa's llvmpipe, LLVM, GDAL's drivers) are
# suppressed in scripts/lsan.supp; leaks in our code are errors.
set -euo pipefail
cd "$(dirname "$0")/.."
scripts/install-deps.sh
CC=clang CXX=clang++ cmake -S . -B build-asan -G Ninja -DCMAKE_BUILD_TYPE=RelWithDebInfo \
  -DTERRAIN_SANITIZE=address,undefined >/dev/null
cmake --build build-asan --parallel "${TERRAIN_BUILD_JOBS:-$(nproc)}"
export ASAN_OPTIONS=detect_leaks=1:abort_on_error=0:strict_string_checks=1:detect_stack_use_after_return=1
export UBSAN_OPTIONS=print_stacktrace=1:halt_on_error=1
export LSAN_OPTIONS=suppressions=$PWD/scripts/lsan.supp:print_suppressions=0
cd build-asan
ctest --output-on-failure --parallel "$(nproc)" "$@"
