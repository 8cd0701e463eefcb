#!/usr/bin/env bash
# Issue 52's viewer targets (docs/terrain-view.md): terrain-view's full and cheap frames at
# its default view, offscreen, eight `timings` replay commands; prints each frame kind's
# smallest, median and largest time (the first frames warm up).
# Usage: bench/viewer_timings.sh MESH.ply [DRAINAGE.dv]   (TERRAIN_BIN: another build's bin)
set -euo pipefail
root="$(cd "$(dirname "$0")/.." && pwd)"
bin="${TERRAIN_BIN:-$root/build/bin}"
replay="$(mktemp)"
trap 'rm -f "$replay"' EXIT
for _ in 1 2 3 4 5 6 7 8; do echo timings; done > "$replay"
echo quit >> "$replay"
out=$("$bin/terrain-view" "$@" --replay "$replay" --offscreen 2>&1)
for kind in full cheap; do
  echo "$out" | grep "^$kind frame" | awk '{print $4}' | sort -n |
    awk -v k="$kind" '{v[NR] = $1} END {printf "%s frame: min %.1f ms, median %.1f ms, max %.1f ms (%d frames)\n", k, v[1], (v[int((NR + 1) / 2)] + v[int(NR / 2) + 1]) / 2, v[NR], NR}'
done
