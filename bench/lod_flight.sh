#!/usr/bin/env bash
# Issue 52's Logan 10 m flight (docs/performance.md, "The Logan 10 m flight"): the paper's
# 99-frame path (bench/gpu_flight.sh's and bench/render_creases.sh's: from 446500 4636500
# 3400 to 451500 4641500 3100, 18 degrees down, 1280 x 720) flown over the whole Logan
# mesh at 10 m (14.3 M vertices, its pyramid beside it) with its .dv (--breach 10), drawn
# by terrain-render batch with the default levels of detail and layers. Prints the device
# (the GL renderer), the batch's timing tables (Tables 3 and 4 of the paper: GL timers and
# the wall clock) and the process's wall time and peak memory. On a GPU machine, run it
# where the project builds (scripts/install-deps.sh); the files are made here in WORKDIR
# (about 1.5 GB; bench/lod_baseline.sh's, when it made them there).
# Usage: bench/lod_flight.sh WORKDIR [FRAMES (99)]
set -euo pipefail
root="$(cd "$(dirname "$0")/.." && pwd)"
bin="${TERRAIN_BIN:-$root/build/bin}"
work="${1:?usage: bench/lod_flight.sh WORKDIR [FRAMES]}"
frames="${2:-99}"
mkdir -p "$work"
[ -f "$work/logan_10.ply" ] || "$bin/dem2mesh" "$root/data/logan_utm12n_100m.tif" "$work/logan_10.ply" --spacing 10 \
  --pyramid -q > /dev/null
[ -f "$work/logan_10.dv" ] || "$bin/build-drainage" "$work/logan_10.ply" "$work/logan_10.dv" --breach 10 -q > /dev/null
"$bin/terrain-render" path --from 446500 4636500 3400 --to 451500 4641500 3100 --frames "$frames" --view-alt 18 \
  -o "$work/flight10.csv" > /dev/null
rm -rf "$work/flight10"
mkdir -p "$work/flight10"
/usr/bin/time -f "%e %M" -o "$work/flight10_time.txt" "$bin/terrain-render" batch "$work/logan_10.ply" \
  "$work/logan_10.dv" "$work/flight10.csv" -o "$work/flight10" --size 1280x720 > "$work/flight10_out.txt"
sed -n '/^renderer:/,$p' "$work/flight10_out.txt"
read -r wall kb < "$work/flight10_time.txt"
echo "process: $wall s, peak $((kb / 1024)) MB, $frames frames"
