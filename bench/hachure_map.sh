#!/usr/bin/env bash
# Issue 51's plan-view cost (docs/terrain-render.md, "Plan-view maps"): a 1024 x 1024 DEM
# (data/logan_utm12n_100m.tif resampled to 25 m, cubic, its north-west 1024 x 1024 cells:
# 25.6 km a side) to a hachure map, end to end:
# dem2mesh, then terrain-inspect export --to gpkg and --to svg at the DEM's own spacing
# (a pixel a cell). Target: under 10 s. Prints each step's wall time, the hachure count and
# the files' sizes.
# Usage: bench/hachure_map.sh [WORKDIR]
set -euo pipefail
root="$(cd "$(dirname "$0")/.." && pwd)"
bin="${TERRAIN_BIN:-$root/build/bin}"
work="${1:-$(mktemp -d)}"
mkdir -p "$work"
gdalwarp -q -overwrite -tr 25 25 -r cubic "$root/data/logan_utm12n_100m.tif" "$work/dem25.tif"
gdal_translate -q -srcwin 0 0 1024 1024 "$work/dem25.tif" "$work/dem1024.tif"
t() { local t0=$(date +%s.%N); "$@" > "$work/last.txt"; awk -v a="$t0" -v b="$(date +%s.%N)" 'BEGIN{printf "%.2f s", b-a}'; }
rm -f "$work/m.ply" "$work/h.gpkg" "$work/h.svg"
echo "dem2mesh: $(t "$bin/dem2mesh" "$work/dem1024.tif" "$work/m.ply" -q)"
echo "export gpkg: $(t "$bin/terrain-inspect" export "$work/m.ply" --to gpkg --scale 25 -o "$work/h.gpkg")" \
  "($(grep -E '^(map|hachures):' "$work/last.txt" | tr '\n' ' '))"
echo "export svg: $(t "$bin/terrain-inspect" export "$work/m.ply" --to svg --scale 25 -o "$work/h.svg")"
echo "sizes: gpkg $(du -k "$work/h.gpkg" | cut -f1) kB, svg $(du -k "$work/h.svg" | cut -f1) kB"
