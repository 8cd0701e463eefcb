#!/usr/bin/env bash
# Benchmark: terrain-render on the Creases paper's scene size - a 120 x 120 grid at 50 m
# (28,322 PN patches) cut from the Logan DEM, its drainage at 10 m, 1280 x 720, 99 frames
# along a straight flight path. Prints the paper's Tables 3 and 4 (GL timer queries and
# wall clock around glFinish) for the full renderer (shaded surface, creases,
# silhouettes) and for a plain shaded frame (TFT only), and the ratio of a full frame to
# a plain one (mean over frames 4-99, wall clock). Needs a built tree (scripts/build.sh).
# Usage: bench/render_creases.sh [FRAMES]   (TERRAIN_BIN=folder: another build's binaries;
#        RENDER_OPTIONS="...": more options for the full frame, e.g. "--formulated off")
set -euo pipefail
cd "$(dirname "$0")/.."
frames="${1:-99}"
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
bin="${TERRAIN_BIN:-build/bin}"  # TERRAIN_BIN=folder times other binaries (an older build)

$bin/dem2mesh data/logan_utm12n_100m.tif "$tmp/scene.ply" --center 450000 4640000 --size 6000 6000 \
  --spacing 50 -q > "$tmp/mesh.txt"
grep -E '^(grid|faces):' "$tmp/mesh.txt"
$bin/build-drainage "$tmp/scene.ply" "$tmp/scene.dv" --spacing 10 -q | grep -E '^(grid|points):'
$bin/terrain-render path --from 446500 4636500 3400 --to 451500 4641500 3100 --frames "$frames" --view-alt 18 \
  -o "$tmp/path.csv" > /dev/null

echo "== full frame (layers shaded,creases,silhouettes), 1280x720"
$bin/terrain-render batch "$tmp/scene.ply" "$tmp/scene.dv" "$tmp/path.csv" -o "$tmp/full" \
  --layers shaded,creases,silhouettes -q ${RENDER_OPTIONS:-}
cp "$tmp/full/timings.csv" "$tmp/full.csv"
echo "== plain shaded frame (layers shaded: TFT + LAY only)"
$bin/terrain-render batch "$tmp/scene.ply" "$tmp/path.csv" -o "$tmp/plain" --layers shaded -q | grep -E 'Table 3|frames 4-N|TFT' | head -8

# Ratios over frames 4-N: a full frame (TFT+AFT+DM+SIL+LAY) over its own TFT (same run,
# same frames), and over the TFT of the plain run (a separate run: on a shared machine the
# two runs' TFT can differ by tens of percent, so both are printed).
awk -F, 'FNR == 1 {next}
  FNR > 4 && FILENAME ~ /full/ {full += $7 + $8 + $9 + $10 + $11; nf++; tft += $7; gfull += $2 + $3 + $4 + $5 + $6; gtft += $2}
  FNR > 4 && FILENAME ~ /plain/ {plain += $7; np++; gplain += $2}
  END {
    printf "full frame (wall) %.1f ms, its TFT %.1f ms; plain shaded frame TFT (wall) %.1f ms\n", full / nf, tft / nf, plain / np
    printf "ratio full frame / its TFT: wall %.2f, GL timers %.2f (paper: 11; target <= 3)\n", full / tft, gfull / gtft
    printf "ratio full frame / plain run TFT: wall %.2f, GL timers %.2f\n", (full / nf) / (plain / np), (gfull / nf) / (gplain / np)
  }' "$tmp/full.csv" "$tmp/plain/timings.csv"
