#!/usr/bin/env bash
# Checks that every C++ source is laid out as .clang-format says (clang-format 14, Debian
# 12); CI runs it first. Fix with: git ls-files '*.cpp' '*.hpp' '*.h' | xargs clang-format -i
set -euo pipefail
cd "$(dirname "$0")/.."
git ls-files -z '*.cpp' '*.hpp' '*.h' | xargs -0 clang-format --dry-run -Werror
echo "check-format: $(git ls-files '*.cpp' '*.hpp' '*.h' | wc -l) files as .clang-format lays them out"
