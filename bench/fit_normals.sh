#!/usr/bin/env bash
# Fitted normals (dem2mesh --fit-normals): the PN surface's error against the source DEM
# before and after, the fit's time, and what it does to the drainage. For each case: the
# mesh with and without --fit-normals, build-drainage on each (PN surface sampled at 10 m),
# and build-drainage --raster on the source DEM itself. Printed: the fit's RMSE and max
# |error| (dem2mesh's own report, at every source sample under the mesh), its time, the
# basin counts, and the channel agreement: the share of the mesh run's channel cells
# (accumulation >= A cells, default 100) with a channel cell of the raster run within one
# cell (and the converse share).
# Cases: the Mount St. Helens crater (10 m DEM) at 50 m; Logan (its 100 m DEM resampled to
# 10 m with gdalwarp -r cubic, as issue 12's tests do) at 100 m.
# Usage: bench/fit_normals.sh [A]   (needs scripts/build.sh)
set -euo pipefail
cd "$(dirname "$0")/.."
acc=${1:-100}
bin=build/bin
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
gdalwarp -q -r cubic -tr 10 10 data/logan_utm12n_100m.tif "$tmp/logan10.tif"

# Share of channel cells of raster $1 with a channel cell of raster $2 within one cell (by
# coordinates; both 10 m grids on the same lattice).
agree() {
  gdal_translate -q -of XYZ "$1" "$tmp/a.xyz"
  gdal_translate -q -of XYZ "$2" "$tmp/b.xyz"
  awk -v a="$acc" 'FNR == NR { if ($3 >= a) ch[sprintf("%d,%d", $1 / 10, $2 / 10)] = 1; next }
    $3 >= a { n++; c = int($1 / 10); r = int($2 / 10); hit = 0
      for (dc = -1; dc <= 1; dc++) for (dr = -1; dr <= 1; dr++) if ((c + dc) "," (r + dr) in ch) hit = 1
      k += hit }
    END { printf "%.3f (%d cells)", k / n, n }' "$tmp/b.xyz" "$tmp/a.xyz"
}

run_case() {
  local name=$1 dem=$2 spacing=$3
  echo "== $name: mesh at $spacing m from $(gdalinfo "$dem" | grep 'Size is') at 10 m"
  mkdir -p "$tmp/$name"/{plain,fit,raster}
  $bin/dem2mesh "$dem" "$tmp/$name/plain.ply" --spacing "$spacing" -q > /dev/null
  /usr/bin/time -f "fit: %e s wall, %M KiB peak" $bin/dem2mesh "$dem" "$tmp/$name/fit.ply" --spacing "$spacing" \
    --fit-normals -q 2>&1 | grep -E "^fit_|^fit:" | tr '\n' ' '
  echo
  for m in plain fit; do
    basins=$($bin/build-drainage "$tmp/$name/$m.ply" "$tmp/$name/$m.dv" --spacing 10 --rasters "$tmp/$name/$m" -q |
      awk '/^basins:/ { print $2 }')
    echo "$m normals: basins $basins"
  done
  basins=$($bin/build-drainage --raster "$dem" "$tmp/$name/raster.dv" --rasters "$tmp/$name/raster" -q |
    awk '/^basins:/ { print $2 }')
  echo "source DEM (--raster): basins $basins"
  for m in plain fit; do
    echo "$m normals: channels (accumulation >= $acc) near a --raster channel: $(agree "$tmp/$name/$m/accumulation.tif" \
      "$tmp/$name/raster/accumulation.tif"); --raster channels near one of the mesh: $(agree \
      "$tmp/$name/raster/accumulation.tif" "$tmp/$name/$m/accumulation.tif")"
  done
}

run_case msh data/msh_2007_utm10n_10m.tif 50
run_case logan "$tmp/logan10.tif" 100
