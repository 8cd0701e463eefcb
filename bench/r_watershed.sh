#!/usr/bin/env bash
# GRASS r.watershed -s (memory=8000) on DEM in a temporary location of EPSG (default 26912,
# Logan's), timed: prints "WALL_S PEAK_KIB" of r.watershed alone, or nothing when GRASS is
# missing (grass-core is installed from Debian first when we are root). The peer of
# build-drainage --raster (bench/build_drainage_vs_grass.sh, bench/peers.sh).
# Usage: bench/r_watershed.sh DEM.tif [EPSG]
set -euo pipefail
dem="$1" epsg="${2:-26912}"
if ! command -v grass > /dev/null && [ "$(id -u)" -eq 0 ]; then
  echo "installing grass-core for the comparison ..." >&2
  DEBIAN_FRONTEND=noninteractive apt-get install -y -qq --no-install-recommends grass-core > /dev/null 2>&1 || true
fi
command -v grass > /dev/null || exit 0
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
cat > "$tmp/ws.sh" << 'GRASS'
r.in.gdal --quiet -o input="$1" output=dem
g.region raster=dem
/usr/bin/time -f "%e %M" -o "$2" r.watershed -s --quiet memory=8000 elevation=dem accumulation=acc drainage=dir
GRASS
grass --tmp-location "EPSG:$epsg" --exec bash "$tmp/ws.sh" "$dem" "$tmp/time" > /dev/null 2>&1 && cat "$tmp/time"
