#!/usr/bin/env bash
# .dv version 1 against version 2 on one DEM: bytes per point, write time (build-drainage -v
# "write" step) and read-back time (terrain-inspect info, best of 3, page cache dropped
# where we may). Usage: bench/dv_format.sh [DEM] (default: Logan resampled to 10 m, cubic).
set -euo pipefail
cd "$(dirname "$0")/.."
BIN=${BIN:-build/bin}
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
dem=${1:-}
if [ -z "$dem" ]; then
  dem=$work/logan10.tif
  gdalwarp -q -r cubic -tr 10 10 data/logan_utm12n_100m.tif "$dem"
fi
drop() { sync; echo 3 > /proc/sys/vm/drop_caches 2>/dev/null || true; }
for v in 1 2; do
  out=$work/v$v.dv
  write=$("$BIN/build-drainage" --raster "$dem" "$out" --dv-version $v -v 2>&1 >/dev/null | sed -n 's/^write .*: \([0-9.]*\) s$/\1/p')
  points=$("$BIN/terrain-inspect" info "$out" | sed -n 's/^grid: \([0-9]*\) x \([0-9]*\).*/\1 \2/p' | awk '{print $1*$2}')
  best=999
  for i in 1 2 3; do
    drop
    t0=$(date +%s.%N)
    "$BIN/terrain-inspect" info "$out" >/dev/null
    t=$(echo "$(date +%s.%N) - $t0" | bc)
    best=$(echo "if ($t < $best) $t else $best" | bc)
  done
  bytes=$(stat -c %s "$out")
  printf 'version %s: %d points, %d bytes (%.2f bytes/point), write %s s, read (terrain-inspect info) %.2f s\n' \
    "$v" "$points" "$bytes" "$(echo "$bytes / $points" | bc -l)" "$write" "$best"
done
