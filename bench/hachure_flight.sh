#!/usr/bin/env bash
# Issue 51's coherence and cost figures for hachures (docs/terrain-render.md, "Hachures"):
# the paper's scene and 99-frame flight (bench/render_creases.sh's: Logan cropped to 6 km,
# meshed at 50 m, drained at 10 m; 1280 x 720), drawn with
# `--layers mask,hachures,creases,silhouettes --line-stats`. Prints the batch's summary:
# crease flicker, hachure coherence (the share of each frame's hachure ink within 1 px of
# the next frame's, target >= 60 %), and the timing tables; then the hachure cost of one
# frame against its TFT pass (terrain-render frame's "hachures ms" and "TFT ms").
# Usage: bench/hachure_flight.sh [WORKDIR] [FRAMES (99)] [EXTRA BATCH OPTIONS...]
set -euo pipefail
root="$(cd "$(dirname "$0")/.." && pwd)"
bin="${TERRAIN_BIN:-$root/build/bin}"
work="${1:-$(mktemp -d)}"
frames="${2:-99}"
shift 2 || shift $# || true
mkdir -p "$work"
[ -f "$work/scene.ply" ] || "$bin/dem2mesh" "$root/data/logan_utm12n_100m.tif" "$work/scene.ply" --center 450000 4640000 \
  --size 6000 6000 --spacing 50 -q > /dev/null
[ -f "$work/scene.dv" ] || "$bin/build-drainage" "$work/scene.ply" "$work/scene.dv" --spacing 10 -q > /dev/null
"$bin/terrain-render" path --from 446500 4636500 3400 --to 451500 4641500 3100 --frames "$frames" --view-alt 18 \
  -o "$work/flight.csv" > /dev/null
rm -rf "$work/flight"
mkdir -p "$work/flight"
"$bin/terrain-render" batch "$work/scene.ply" "$work/scene.dv" "$work/flight.csv" -o "$work/flight" --size 1280x720 \
  --layers mask,hachures,creases,silhouettes --line-stats -q "$@" | grep -E "flicker|coherence|^(TFT|TOTAL)"
"$bin/terrain-render" frame "$work/scene.ply" "$work/scene.dv" -o "$work/one.png" --size 1280x720 \
  --layers mask,hachures,creases,silhouettes --eye 446500 4636500 3400 --view-az 45 --view-alt 18 "$@" 2>&1 |
  grep -E "^(TFT ms|hachures ms)" || true
