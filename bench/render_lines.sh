#!/usr/bin/env bash
# Benchmark: the line methods of terrain-render side by side on the Creases paper's scene
# size (a 120 x 120 grid at 50 m cut from the Logan DEM, 28,322 PN patches) and on the
# Mount St. Helens crater at 10 m: Toward/Away and Adjacency silhouettes (Mower 2014) and
# object-space contour edges (McGuire & Hughes) with cheap and with exact caps, each over
# FRAMES frames of a flight path at 1280 x 720 with a plain shaded frame in the same run.
# Prints, per scene and method, the mean GL-timer ms over frames 4-N of the passes that
# differ (AFT: the away surface or Adjacency's ID pass; SIL; EDGE), the line frame
# (TFT + AFT + SIL + EDGE + LAY) as fps, and its ratio to the plain shaded frame; writes
# the four methods side by side from one viewpoint (out/render_lines_<scene>.png).
# Usage: bench/render_lines.sh [FRAMES]   (needs a built tree: scripts/build.sh)
set -euo pipefail
cd "$(dirname "$0")/.."
frames="${1:-20}"
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
bin=build/bin
mkdir -p out

run_scene() {  # NAME MESH FROM TO
  local name=$1 mesh=$2
  $bin/terrain-render path --from $3 --to $4 --frames "$frames" --view-alt 18 -o "$tmp/$name.csv" > /dev/null
  $bin/terrain-render batch "$mesh" "$tmp/$name.csv" -o "$tmp/${name}_plain" --layers shaded -q > /dev/null
  local method
  for method in silhouettes silhouettes-adjacency edges-cheap edges-exact; do
    case $method in
      edges-*) opts=(--layers mask,edges --edges contour --edge-caps "${method#edges-}") ;;
      *) opts=(--layers "mask,$method") ;;
    esac
    $bin/terrain-render batch "$mesh" "$tmp/$name.csv" -o "$tmp/${name}_$method" "${opts[@]}" -q > /dev/null
    # timings.csv columns: 2 TFT, 3 AFT, 5 SIL, 6 LAY, 14 EDGE (GL timer ms).
    awk -F, -v name="$name" -v method="$method" 'FNR == 1 {next}
      FNR > 4 && FILENAME ~ /_plain/ {plain += $2 + $6; np++}
      FNR > 4 && FILENAME !~ /_plain/ {aft += $3; sil += $5; edge += $14; frame += $2 + $3 + $5 + $6 + $14; nf++}
      END {
        printf "%s %-22s AFT %7.2f ms  SIL %7.2f ms  EDGE %7.2f ms  fps %6.2f  frame / plain shaded frame %.2f\n",
               name, method, aft / nf, sil / nf, edge / nf, 1000 / (frame / nf), (frame / nf) / (plain / np)
      }' "$tmp/${name}_plain/timings.csv" "$tmp/${name}_$method/timings.csv"
  done
  oiiotool "$tmp/${name}_silhouettes/frame_00004.png" "$tmp/${name}_silhouettes-adjacency/frame_00004.png" \
    "$tmp/${name}_edges-cheap/frame_00004.png" "$tmp/${name}_edges-exact/frame_00004.png" \
    --mosaic 2x2 --resize 50% -o "out/render_lines_$name.png" 2>/dev/null || true
}

$bin/dem2mesh data/logan_utm12n_100m.tif "$tmp/logan.ply" --center 450000 4640000 --size 6000 6000 --spacing 50 -q \
  > /dev/null
run_scene logan "$tmp/logan.ply" "446500 4636500 3400" "451500 4641500 3100"
$bin/dem2mesh data/msh_2007_utm10n_10m.tif "$tmp/msh.ply" --center 562500 5116750 --size 2400 2400 --spacing 10 -q \
  > /dev/null
run_scene msh "$tmp/msh.ply" "561300 5114800 3000" "562900 5116200 2800"
