#!/usr/bin/env bash
# Benchmark: dem2mesh on the Logan DEM resampled from 100 m to 10 m (~14 M vertices)
# against gdalwarp performing the same bilinear resampling onto the same grid, in one
# run. Prints both wall times, their ratio, dem2mesh's peak memory and bytes per vertex.
# Usage: bench/dem2mesh_vs_gdalwarp.sh [SPACING]   (needs a built tree: scripts/build.sh;
# DEM2MESH=path times another dem2mesh binary, e.g. an older build)
# Outputs go to a folder under $TMPDIR (default /tmp): TMPDIR=/dev/shm leaves the disk out.
set -euo pipefail
cd "$(dirname "$0")/.."
spacing="${1:-10}"
dem=data/logan_utm12n_100m.tif
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
[ -x /usr/bin/time ] || { echo "needs /usr/bin/time (Debian package 'time')" >&2; exit 1; }

measure() {  # prints "wall_s peak_kb"
  sync  # the previous step's (or run's) writeback does not land on this one's clock
  /usr/bin/time -f "%e %M" -o "$tmp/time" "$@" >"$tmp/stdout" 2>/dev/null
  cat "$tmp/time"
}

read -r d_wall d_kb < <(measure "${DEM2MESH:-build/bin/dem2mesh}" "$dem" "$tmp/mesh.ply" --spacing "$spacing" -q)
vertices=$(awk '/^vertices:/ {print $2}' "$tmp/stdout")
read -r xmin ymin xmax ymax < <(awk '/^extent:/ {print $2, $3, $4, $5}' "$tmp/stdout")
read -r g_wall g_kb < <(measure gdalwarp -q -overwrite -r bilinear -tr "$spacing" "$spacing" \
  -te "$xmin" "$ymin" "$xmax" "$ymax" "$dem" "$tmp/warp.tif")
read -r gm_wall gm_kb < <(measure gdalwarp -q -overwrite -r bilinear -tr "$spacing" "$spacing" \
  -te "$xmin" "$ymin" "$xmax" "$ymax" -multi -wo NUM_THREADS=ALL_CPUS "$dem" "$tmp/warp_mt.tif")

ply_mb=$(du -m "$tmp/mesh.ply" | cut -f1)
tif_mb=$(du -m "$tmp/warp.tif" | cut -f1)
echo "dem2mesh vs gdalwarp: $dem at ${spacing} m, $vertices vertices, $(nproc) cores"
awk -v dw="$d_wall" -v dk="$d_kb" -v n="$vertices" -v gw="$g_wall" -v gk="$g_kb" -v mw="$gm_wall" \
    -v mk="$gm_kb" -v pm="$ply_mb" -v tm="$tif_mb" 'BEGIN {
  printf "  dem2mesh                  %6.2f s  peak %7.1f MB  %5.1f bytes/vertex  output %s MB (PLY)\n", dw, dk/1024, dk*1024/n, pm
  printf "  gdalwarp                  %6.2f s  peak %7.1f MB  output %s MB (GeoTIFF)\n", gw, gk/1024, tm
  printf "  gdalwarp -multi (all)     %6.2f s  peak %7.1f MB\n", mw, mk/1024
  printf "  ratio dem2mesh / gdalwarp %6.2f\n", dw/gw
}'
# Floor: copying a file of the PLY's size into the page cache.
read -r cp_wall _ < <(measure cp "$tmp/mesh.ply" "$tmp/copy.ply")
echo "  (cp of the PLY alone: $cp_wall s)"
