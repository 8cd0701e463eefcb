#!/usr/bin/env bash
# Benchmark: build-drainage on the Logan DEM resampled to RES metres (default: 10 and 5, i.e.
# 14.4 M and 57.6 M points; cubic) against GRASS r.watershed -s on the same grid, untiled
# and tiled (--tile-size TILE, default 2048); and at 10 m the mesh pipeline (the Logan mesh
# sampled at 10 m through the PN surface). Prints wall times, peak memory, bytes per point,
# the ratios. Needs a built tree (scripts/build.sh) and, for the GRASS figures, the Debian
# package grass-core (bench/r_watershed.sh installs it when missing and we are root).
# Usage: bench/build_drainage_vs_grass.sh [RES ...]     e.g. bench/build_drainage_vs_grass.sh 10
set -euo pipefail
cd "$(dirname "$0")/.."
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
bin=build/bin
TILE=${TILE:-2048}
resolutions=("$@")
[ ${#resolutions[@]} -gt 0 ] || resolutions=(10 5)

measure() {  # prints "wall_s peak_kb"; the command's stdout/stderr go to $tmp/out, $tmp/err
  /usr/bin/time -f "%e %M" -o "$tmp/time" "$@" >"$tmp/out" 2>"$tmp/err"
  cat "$tmp/time"
}
row() {  # label wall kb points
  awk -v l="$1" -v w="$2" -v k="$3" -v n="$4" 'BEGIN { printf "  %-46s %7.2f s  peak %8.1f MB  %5.1f bytes/point\n", l, w, k/1024, k*1024/n }'
}

echo "build-drainage vs GRASS r.watershed -s on Logan ($(nproc) cores)"
first_wall=""
for res in "${resolutions[@]}"; do
  dem=$tmp/logan$res.tif
  gdalwarp -q -r cubic -tr "$res" "$res" data/logan_utm12n_100m.tif "$dem"
  read -r rw rkb < <(measure $bin/build-drainage --raster "$dem" "$tmp/raster.dv" -v)
  points=$(awk '/^points:/ {print $2}' "$tmp/out")
  steps=$(grep -E '^  [a-z0-9]+: |^drainage \(|^write ' "$tmp/err" | tr '\n' ';')
  read -r tw tkb < <(measure $bin/build-drainage --raster "$dem" "$tmp/tiled.dv" --tile-size "$TILE" -q)
  echo "Logan at $res m: $points points"
  row "build-drainage --raster (read, steps 2-7, write)" "$rw" "$rkb" "$points"
  echo "    steps: $steps"
  row "build-drainage --raster --tile-size $TILE" "$tw" "$tkb" "$points"
  if [ -z "$first_wall" ]; then
    first_wall=$rw first_points=$points
  else
    awk -v a="$rw" -v b="$first_wall" -v n="$points" -v m="$first_points" \
      'BEGIN { printf "  time ratio to the first size: %.2f for %.2f x the points\n", a / b, n / m }'
  fi
  gw=""
  read -r gw gkb < <(bench/r_watershed.sh "$dem") || true
  if [ -n "$gw" ]; then
    row "GRASS r.watershed -s (memory=8000)" "$gw" "$gkb" "$points"
    awk -v g="$gw" -v w="$rw" 'BEGIN { printf "  ratio r.watershed / build-drainage --raster: %.2f\n", g / w }'
  fi
  rm -f "$dem" "$tmp/raster.dv" "$tmp/tiled.dv"
done

if [[ " ${resolutions[*]} " == *" 10 "* ]]; then
  $bin/dem2mesh data/logan_utm12n_100m.tif "$tmp/logan.ply" -q >/dev/null
  read -r mw mkb < <(measure $bin/build-drainage "$tmp/logan.ply" "$tmp/mesh.dv" --spacing 10 -v)
  mpoints=$(awk '/^points:/ {print $2}' "$tmp/out")
  row "build-drainage MESH (sample at 10 m, steps 2-7)" "$mw" "$mkb" "$mpoints"
  echo "    steps: $(grep -E '^sampled |^  [a-z0-9]+: |^drainage \(|^write ' "$tmp/err" | tr '\n' ';')"
fi
