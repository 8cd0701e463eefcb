#!/usr/bin/env bash
# Builds the libFuzzer harnesses (clang, ASan + UBSan) into build-fuzz/ and runs each for
# SECONDS (default 600) on one core each, FUZZ_JOBS (default 2) at a time. The seed corpora in tests/fuzz/corpus/
# are copied into build-fuzz/corpus/ (grown there, never in the repository). Prints the
# executions and crashes of each harness; crash inputs are kept in build-fuzz/crashes/.
#   scripts/fuzz.sh 600            # every harness 10 minutes
#   scripts/fuzz.sh 60 ply dv      # only these
set -euo pipefail
cd "$(dirname "$0")/.."
seconds=${1:-600}
shift || true
harnesses=("$@")
[ ${#harnesses[@]} -gt 0 ] || harnesses=(dv ply frames d8 points pyramid)
scripts/install-deps.sh >/dev/null
CC=clang CXX=clang++ cmake -S . -B build-fuzz -G Ninja -DCMAKE_BUILD_TYPE=RelWithDebInfo -DTERRAIN_FUZZ=ON \
  -DTERRAIN_SANITIZE=address,undefined -DTERRAIN_BUILD_TESTS=OFF >/dev/null
cmake --build build-fuzz --target "${harnesses[@]/#/fuzz_}"
mkdir -p build-fuzz/crashes build-fuzz/logs
run_one() {
  local h=$1
  mkdir -p "build-fuzz/corpus/$h"
  cp -n tests/fuzz/corpus/"$h"/* "build-fuzz/corpus/$h/" 2>/dev/null || true
  ASAN_OPTIONS=detect_leaks=0:allocator_may_return_null=1 \
    build-fuzz/bin/fuzz_"$h" -max_total_time="$seconds" -rss_limit_mb=4096 -malloc_limit_mb=4096 \
    -timeout=30 -print_final_stats=1 -artifact_prefix="build-fuzz/crashes/$h-" "build-fuzz/corpus/$h" \
    >"build-fuzz/logs/$h.log" 2>&1 || true
  local done_line crashes
  done_line=$(grep -m1 "^Done [0-9]* runs in" "build-fuzz/logs/$h.log" || echo "stopped early: see the log")
  crashes=$(ls build-fuzz/crashes | grep -c "^$h-" || true)
  echo "fuzz_$h: $done_line; ${crashes} crash/timeout/oom inputs in build-fuzz/crashes (log build-fuzz/logs/$h.log)"
}
running=0
for h in "${harnesses[@]}"; do
  run_one "$h" &
  running=$((running + 1))
  if [ $running -ge "${FUZZ_JOBS:-2}" ]; then wait -n; running=$((running - 1)); fi
done
wait
