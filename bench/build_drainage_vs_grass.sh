#!/usr/bin/env bash
# Benchmark: build-drainage on the Logan DEM at 10 m (14.4 M points) against GRASS
# r.watershed -s on the same grid, in one run; and the mesh pipeline (Logan mesh sampled
# at 10 m through the PN surface). Prints wall times, peak memory per point, the ratio.
# Needs a built tree (scripts/build.sh) and, for the GRASS figure, the Debian package
# grass-core (installed here when missing and we are root).
set -euo pipefail
cd "$(dirname "$0")/.."
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
bin=build/bin
if ! command -v grass >/dev/null; then
  if [ "$(id -u)" -eq 0 ]; then
    echo "installing grass-core for the comparison ..." >&2
    DEBIAN_FRONTEND=noninteractive apt-get install -y -qq --no-install-recommends grass-core >/dev/null
  fi
fi

measure() {  # prints "wall_s peak_kb"; the command's stdout/stderr go to $tmp/out, $tmp/err
  /usr/bin/time -f "%e %M" -o "$tmp/time" "$@" >"$tmp/out" 2>"$tmp/err"
  cat "$tmp/time"
}

gdalwarp -q -r cubic -tr 10 10 data/logan_utm12n_100m.tif "$tmp/logan10.tif"
read -r rw rkb < <(measure $bin/build-drainage --raster "$tmp/logan10.tif" "$tmp/raster.dv" -v)
points=$(awk '/^points:/ {print $2}' "$tmp/out")
raster_steps=$(grep -E '^  [a-z0-9]+: |^drainage \(|^write ' "$tmp/err" | tr '\n' ';')

$bin/dem2mesh data/logan_utm12n_100m.tif "$tmp/logan.ply" -q >/dev/null
read -r mw mkb < <(measure $bin/build-drainage "$tmp/logan.ply" "$tmp/mesh.dv" --spacing 10 -v)
mpoints=$(awk '/^points:/ {print $2}' "$tmp/out")
mesh_steps=$(grep -E '^sampled |^  [a-z0-9]+: |^drainage \(|^write ' "$tmp/err" | tr '\n' ';')

gw="n/a"
if command -v grass >/dev/null; then
  cat >"$tmp/ws.sh" <<'GRASS'
r.in.gdal --quiet -o input="$1" output=dem
g.region raster=dem
/usr/bin/time -f "%e %M" -o "$2" r.watershed -s --quiet memory=4000 elevation=dem accumulation=acc drainage=dir
GRASS
  grass --tmp-location EPSG:26912 --exec bash "$tmp/ws.sh" "$tmp/logan10.tif" "$tmp/grass_time" >/dev/null 2>&1 \
    && read -r gw gkb <"$tmp/grass_time"
fi

echo "build-drainage vs GRASS r.watershed -s: Logan at 10 m ($points points, $(nproc) cores)"
awk -v w="$rw" -v k="$rkb" -v n="$points" 'BEGIN { printf "  build-drainage --raster (read, steps 2-7, write)  %6.2f s  peak %7.1f MB  %5.1f bytes/point\n", w, k/1024, k*1024/n }'
echo "    steps: $raster_steps"
awk -v w="$mw" -v k="$mkb" -v n="$mpoints" 'BEGIN { printf "  build-drainage MESH (sample at 10 m, steps 2-7) %6.2f s  peak %7.1f MB  %5.1f bytes/point (%d points)\n", w, k/1024, k*1024/n, n }'
echo "    steps: $mesh_steps"
if [ "$gw" != "n/a" ]; then
  awk -v g="$gw" -v k="$gkb" -v w="$rw" 'BEGIN { printf "  GRASS r.watershed -s (memory=4000)               %6.2f s  peak %7.1f MB\n  ratio r.watershed / build-drainage --raster      %6.2f\n", g, k/1024, g / w }'
else
  echo "  GRASS r.watershed -s: not available (install grass-core)"
fi
