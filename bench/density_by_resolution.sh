#!/usr/bin/env bash
# Issue 50, item 3 (docs/terrain-render.md, "Density across mesh resolutions"): the same
# DEM meshed at several spacings (dem2mesh --spacing S), each drained with build-drainage's
# defaults, each drawn at one camera per DEM: the 50 m mesh's automatic view (its eye,
# view, light and exaggeration given to the other meshes' frames). Prints each frame's
# crease ink, strokes and mean stroke (--line-stats) and their change against the 50 m
# mesh. Targets: ink within 15 %, strokes within 25 %.
# Usage: bench/density_by_resolution.sh [WORKDIR] [RENDER OPTIONS...]
# TERRAIN_DENSITY_SPACINGS="logan:100,50,25 msh:50,25" runs fewer meshes (the default
# includes the 10 m ones: Logan 10 m is 14.3 M vertices, about 3 minutes here).
set -euo pipefail
root="$(cd "$(dirname "$0")/.." && pwd)"
bin="${TERRAIN_BIN:-$root/build/bin}"
work="${1:-$(mktemp -d)}"
shift || true
mkdir -p "$work"
declare -A dem=([msh]="$root/data/msh_2007_utm10n_10m.tif" [logan]="$root/data/logan_utm12n_100m.tif")
runs="${TERRAIN_DENSITY_SPACINGS:-logan:100,50,25,10 msh:50,25,10}"
stat() { awk -F': ' -v k="$1" '$1 == k {print $2}'; }
printf '%-6s %8s %9s %7s %8s %9s %7s %9s\n' dem mesh_m ink_px ink_% strokes strokes_% mean_px connected
for run in $runs; do
  name=${run%%:*} spacings=${run#*:}
  for sp in 50 ${spacings//,/ }; do
    m="$work/${name}_$sp.ply" d="$work/${name}_$sp.dv"
    [ -f "$m" ] || "$bin/dem2mesh" "${dem[$name]}" "$m" --spacing "$sp" -q > /dev/null
    [ -f "$d" ] || "$bin/build-drainage" "$m" "$d" -q > /dev/null
  done
  base=$("$bin/terrain-render" frame "$work/${name}_50.ply" "$work/${name}_50.dv" -o "$work/${name}_50.png" --line-stats "$@")
  read -r ex ey ez < <(echo "$base" | awk '/^eye:/ {print $2, $3, $4}')
  read -r az alt fov < <(echo "$base" | awk '/^view:/ {print $3, $5, $7}')
  read -r laz lalt < <(echo "$base" | awk '/^light:/ {print $3, $5}')
  exag=$(echo "$base" | awk '/^exaggeration:/ {print $2}')
  ink0=$(echo "$base" | stat "crease length px") strokes0=$(echo "$base" | stat "crease strokes")
  for sp in ${spacings//,/ }; do
    out=$base
    [ "$sp" = 50 ] || out=$("$bin/terrain-render" frame "$work/${name}_$sp.ply" "$work/${name}_$sp.dv" \
      -o "$work/${name}_$sp.png" --line-stats --eye "$ex" "$ey" "$ez" --view-az "$az" --view-alt "$alt" --fov "$fov" \
      --light-az "$laz" --light-alt "$lalt" --exaggeration "$exag" "$@")
    awk -v n="$name" -v sp="$sp" -v a0="$ink0" -v s0="$strokes0" -v a="$(echo "$out" | stat "crease length px")" \
      -v s="$(echo "$out" | stat "crease strokes")" -v mean="$(echo "$out" | stat "crease mean stroke px")" \
      -v c="$(echo "$out" | stat "crease connected share")" \
      'BEGIN {printf "%-6s %8s %9d %+6.1f%% %8d %+8.1f%% %7.1f %9.3f\n", n, sp, a, 100 * (a - a0) / a0, s, 100 * (s - s0) / s0, mean, c}'
  done
done
