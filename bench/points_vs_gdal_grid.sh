#!/usr/bin/env bash
# Benchmark: scattered points -> 10 m grid, dem2mesh (CGAL Delaunay; linear, natural (C1) and C0 natural
# neighbour) beside gdal_grid -a linear (qhull Delaunay) on the same points and grid, in
# the same run. N random points (fixed seed) over a 10 x 10 km square of a smooth analytic
# terrain (EPSG:32610), as XYZ text. Prints wall time and peak memory of each
# (/usr/bin/time), and dem2mesh's own step times.
# Usage: bench/points_vs_gdal_grid.sh [N ...]   (default 1000000; needs scripts/build.sh)
set -euo pipefail
cd "$(dirname "$0")/.."
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
bin=build/bin
for n in "${@:-1000000}"; do
  awk -v n="$n" 'BEGIN { srand(12345); for (i = 0; i < n; i++) {
      x = 560000 + 10000 * rand(); y = 5110000 + 10000 * rand();
      z = 1000 + 200 * sin((x - 560000) / 1500) * cos((y - 5110000) / 2100) + 0.01 * (x - 560000);
      printf "%.3f %.3f %.3f\n", x, y, z } }' > "$tmp/pts.xyz"
  { echo x,y,z; tr ' ' , < "$tmp/pts.xyz"; } > "$tmp/pts.csv"  # the same points for gdal_grid (GDAL 3.6: no -oo)
  cat > "$tmp/pts.vrt" <<VRT
<OGRVRTDataSource><OGRVRTLayer name="pts"><SrcDataSource>$tmp/pts.csv</SrcDataSource>
<GeometryType>wkbPoint25D</GeometryType><GeometryField encoding="PointFromColumns" x="x" y="y" z="z"/>
</OGRVRTLayer></OGRVRTDataSource>
VRT
  echo "== $n points, 10 m grid over 560000..570000 x 5110000..5120000"
  for method in linear natural natural-c0; do
    /usr/bin/time -f "dem2mesh $method: %e s wall, %M KiB peak" $bin/dem2mesh "$tmp/pts.xyz" "$tmp/o.ply" --spacing 10 \
      --src-crs EPSG:32610 --interpolation "$method" --bbox 560005 5110005 569995 5119995 --fill-nodata \
      -v 2>&1 | grep -E "Delaunay|points \(|peak" || true
  done
  /usr/bin/time -f "gdal_grid -a linear: %e s wall, %M KiB peak" gdal_grid -q -a linear -a_srs EPSG:32610 \
    -txe 560000 570000 -tye 5120000 5110000 -outsize 1000 1000 -ot Float32 \
    -l pts "$tmp/pts.vrt" "$tmp/gdal.tif" 2>&1 | tail -1 || true
done
